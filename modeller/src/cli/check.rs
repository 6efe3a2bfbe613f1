//! `nendo check MODEL.json`: reads a model and prints its continuity report as JSON (docs/design.md §14):
//! patches, shared edges, the G0 gap (between the file's copies of shared points and between
//! the patches' evaluations along shared edges), the G1 angle (max and mean) along shared
//! edges, and every pole with the spread of its tangent plane. With `--against OTHER.json` (a
//! model with the same topology and patch counts) it adds the deviation between the two
//! surfaces on 40 × 40 samples per patch at the same parameters (docs/design.md §14).
//!
//! `g2`: the curvature mismatch across every seam and at every pole from the patches' exact
//! derivatives ([`crate::surface::curvature`]): the largest relative `|(R₁ − R₂)/(R₁ + R₂)|` and
//! absolute `|1/R₁ − 1/R₂|` mismatch of the normal curvature across the seam, their mean, the
//! [`G2_WORST`] worst seams, and per pole the residual of its meridian curvatures against one
//! quadratic form with the fitted principal curvatures.
//!
//! Memory is bounded: the deviation streams its samples (memory for the two models only), the
//! edge samples are streamed too, and the one list the report holds — the directions out of a
//! pole, `patches_u × samples` of them, 24 bytes each — is refused over
//! [`MAX_POLE_DIRECTIONS`] (about 100 MB).

use clap::Args as ClapArgs;
use serde_json::json;
use std::path::PathBuf;
use std::process::ExitCode;

use crate::model::Model;
use crate::surface::PoleEnd;
use crate::surface::continuity::{MIN_SAMPLES_PER_EDGE, report};
use crate::surface::curvature::g2_report;
use crate::surface::deviation::{DeviationStats, distance_iter};

/// Arguments of `nendo check`.
#[derive(Debug, ClapArgs)]
pub struct CheckArgs {
    /// The model file.
    pub model: PathBuf,
    /// Points per shared edge (33 to 100 000).
    #[arg(long, default_value_t = MIN_SAMPLES_PER_EDGE)]
    pub samples: usize,
    /// Also report the deviation from this model (same topology and patch counts).
    #[arg(long)]
    pub against: Option<PathBuf>,
}

/// Most points per shared edge `--samples` accepts.
const MAX_SAMPLES_PER_EDGE: usize = 100_000;

/// Most directions out of a pole (`patches_u × --samples` on a grid with a pole) the report
/// holds at once: 24 bytes each, about 100 MB.
pub const MAX_POLE_DIRECTIONS: usize = 1 << 22;

/// Seams listed as the worst in the G2 report.
pub const G2_WORST: usize = 5;

/// Sample points per seam for the G2 report (the edge's ends left out).
const G2_SAMPLES: usize = 17;

/// Samples per patch side for `--against`.
const DEVIATION_SAMPLES: usize = 40;

/// Runs `nendo check`.
pub fn run(args: CheckArgs) -> ExitCode {
    if args.samples > MAX_SAMPLES_PER_EDGE {
        eprintln!("nendo check: --samples must be at most {MAX_SAMPLES_PER_EDGE}");
        return ExitCode::from(2);
    }
    let loaded = match Model::read(&args.model) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("nendo check: {}", e.in_file(&args.model));
            return ExitCode::from(1);
        }
    };
    let g = &loaded.model.surface;
    let directions = g.patches_u().saturating_mul(args.samples);
    if !g.poles().is_empty() && directions > MAX_POLE_DIRECTIONS {
        eprintln!(
            "nendo check: {} patches around a pole × --samples {} = {directions} pole directions, more than the {MAX_POLE_DIRECTIONS} held at once (about 100 MB); lower --samples",
            g.patches_u(),
            args.samples
        );
        return ExitCode::from(2);
    }
    let deviation = match &args.against {
        None => None,
        Some(path) => {
            let other = match Model::read(path) {
                Ok(l) => l.model.surface,
                Err(e) => {
                    eprintln!("nendo check: {}", e.in_file(path));
                    return ExitCode::from(1);
                }
            };
            // Streamed: the 40 × 40 samples per patch are compared one at a time, so memory
            // stays at the two models whatever their size.
            let d = distance_iter(g, &other, DEVIATION_SAMPLES);
            match (d, g.topology() == other.topology()) {
                (Ok(d), true) => {
                    let mut moved = 0usize;
                    let s =
                        DeviationStats::of(d.inspect(|&x| moved += usize::from(x > 1e-9)), 0.15);
                    Some(json!({
                        "against": path.display().to_string(),
                        "samples": s.count,
                        "samples_apart": moved,
                        "mean": s.mean,
                        "max": s.max,
                        "share_within_0.15": s.share_within,
                    }))
                }
                _ => {
                    eprintln!(
                        "nendo check: {} has another topology or other patch counts; no deviation to measure",
                        path.display()
                    );
                    return ExitCode::from(1);
                }
            }
        }
    };
    let r = report(g, args.samples);
    let poles: Vec<_> = r
        .poles
        .iter()
        .map(|p| {
            json!({
                "end": if p.end == PoleEnd::Start { "v=0" } else { "v=N" },
                "position": [p.position.x, p.position.y, p.position.z],
                "normal": p.normal.map(|n| json!([n.x, n.y, n.z])),
                "spread_deg": p.spread_deg,
            })
        })
        .collect();
    let g2 = g2_report(g, G2_SAMPLES);
    let g2 = json!({
        "samples_per_seam": G2_SAMPLES - 2,
        "seams": g2.seams.len(),
        "relative_max": g2.max_relative,
        "relative_mean": g2.mean_relative,
        "absolute_max": g2.max_absolute,
        "worst": g2.worst(G2_WORST).iter().map(|s| json!({
            "line": format!("{} line {}", s.direction, s.line),
            "patch_along": s.along,
            "relative": s.relative,
            "absolute": s.absolute,
        })).collect::<Vec<_>>(),
        "poles": g2.poles.iter().map(|p| json!({
            "end": if p.end == PoleEnd::Start { "v=0" } else { "v=N" },
            "relative": p.relative,
            "absolute": p.absolute,
            "principal_curvatures": [p.principal.0, p.principal.1],
        })).collect::<Vec<_>>(),
    });
    let out = json!({
        "topology": g.topology().name(),
        "patches_u": g.patches_u(),
        "patches_v": g.patches_v(),
        "patches": r.patches,
        "curves": loaded.model.curves.len(),
        "regulation": loaded.model.regulation.name(),
        "shared_edges": r.shared_edges,
        "samples_per_edge": r.samples_per_edge,
        "g0_gap": r.g0_gap.max(loaded.seam_gap),
        "g0_gap_file": loaded.seam_gap,
        "g0_gap_eval": r.g0_gap,
        "g1_max_deg": r.g1_max_deg,
        "g1_mean_deg": r.g1_mean_deg,
        "undefined_normals": r.undefined_normals,
        "poles": poles,
        "g2": g2,
    });
    let out = match (out, deviation) {
        (serde_json::Value::Object(mut o), Some(d)) => {
            o.insert("deviation".into(), d);
            serde_json::Value::Object(o)
        }
        (out, _) => out,
    };
    super::output::exit_after("nendo check", super::output::println(out))
}
