//! `nendo sculpt`: builds a primitive (or reads a model), replays operations on it and writes
//! the model.
//!
//! ```text
//! nendo sculpt --primitive sphere --patches 8x4 --radius 3 --ops strokes.jsonl --out pot.json
//! nendo sculpt --model pot.json --ops more.jsonl --regulation none --out pot2.json
//! ```
//!
//! Operations are JSON lines (see [`crate::model::ops`]); every line is validated before any is
//! applied, and a bad line is reported with its number while nothing is written. `--ops -`
//! reads them from standard input. The file is read line by line: a line of more than 1 MB or
//! a file of more than 64 MB ([`ops::MAX_OP_LINE_BYTES`], [`ops::MAX_OPS_FILE_BYTES`]) is
//! refused as soon as the limit is passed (an endless input such as `/dev/zero` at once).
//!
//! `--auto-refine`: before each operation the grid is refined where its finger reaches
//! ([`crate::surface::refine::for_finger`]): every patch column (row) holding a patch whose box
//! may come within `r_f` of the finger, and whose control polygon is longer than `3 r_f / 4`
//! that way, is split uniformly into `⌈length / (r_f/2)⌉` pieces (the opposite column too
//! around a closed direction), repeated until the reached patches are at most `3 r_f / 4`
//! across. The surface does not change; the operation then acts on the finer patches. A
//! refinement that would pass the grid limit stops there, says so on standard error, and the
//! operation is still applied.
//!
//! `--mirror x|y|z` applies every operation together with its mirror image across the plane
//! `x = 0` (`y = 0`, `z = 0`) as one operation, keeping a symmetric model exactly symmetric;
//! a model that is not symmetric about the plane is refused. Mirrors combine (`--mirror x,y`
//! or the option repeated: every image under the group they generate), and so do `--radial N`
//! and `--lathe` ([`super::symmetry_args`]).
//!
//! The run holds the writer lock of `--out` ([`nendo_file::lock`], `.NAME.nendo-lock` beside
//! it) from reading `--model` to writing `--out`: concurrent runs on one file (`--model m --out
//! m`) take turns, and one that waits more than a minute fails with nothing written.

use super::arg_error::{parse_primitive, parse_regulation};
use super::primitive_args::ShapeArgs;
use clap::Args as ClapArgs;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use crate::model::{Model, ops};
use crate::surface::MAX_PATCHES;
use crate::surface::{Plane, Primitive, Regulation, Sculptor, refine};

/// Arguments of `nendo sculpt`.
#[derive(Debug, ClapArgs)]
pub struct SculptArgs {
    /// Start from a primitive: plane, cylinder, hemisphere, sphere, torus or tube.
    #[arg(long, value_parser = clap::builder::ValueParser::new(parse_primitive), conflicts_with = "model")]
    pub primitive: Option<Primitive>,
    /// The primitive's shape.
    #[command(flatten)]
    pub shape: ShapeArgs,
    /// Start from this model file instead of a primitive.
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Operations to apply, one JSON object per line (`-`: standard input).
    #[arg(long)]
    pub ops: Option<PathBuf>,
    /// Regulation after each operation: none (the Bernstein inverse alone), c1 (the paper's
    /// baseline), g1 (the paper's method), exact (our own, also called `default`) or g2 (exact,
    /// and curvature-continuous across every seam). Without the option: the model's, else
    /// exact.
    #[arg(long, value_parser = clap::builder::ValueParser::new(parse_regulation))]
    pub regulation: Option<Regulation>,
    /// Before each operation, split the patches its finger reaches that are more than 3/4 of
    /// the finger radius across into pieces of at most half of it (the surface does not
    /// change). Not with `--mirror`.
    #[arg(long, conflicts_with_all = ["mirror", "radial", "lathe"])]
    pub auto_refine: bool,
    /// Apply every operation together with its mirror image across the plane x = 0, y = 0 or
    /// z = 0 (as one operation; `x,y` or the option repeated: every combination). The model
    /// must be symmetric about the planes.
    #[arg(long, value_delimiter = ',', value_parser = clap::builder::ValueParser::new(parse_plane))]
    pub mirror: Vec<Plane>,
    /// `--radial N`, `--lathe`.
    #[command(flatten)]
    pub turns: super::symmetry_args::TurnArgs,
    /// Where to write the model (atomically).
    #[arg(long)]
    pub out: PathBuf,
}

/// Longest wait for another writer of `--out` (see [`nendo_file::lock`]).
const WRITER_WAIT: std::time::Duration = std::time::Duration::from_secs(60);

/// Parses `--mirror`.
///
/// # Errors
/// The name is not x, y or z.
pub fn parse_plane(s: &str) -> Result<Plane, crate::surface::UnknownName> {
    s.parse()
}

/// Runs `nendo sculpt`.
pub fn run(args: SculptArgs) -> ExitCode {
    match sculpt(&args) {
        Ok(summary) => {
            eprintln!("nendo sculpt: {summary}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("nendo sculpt: {e:#}");
            ExitCode::from(1)
        }
    }
}

fn sculpt(args: &SculptArgs) -> anyhow::Result<String> {
    // `--out` may replace the `--model` read (a model either way), not the operations file.
    super::paths::check(
        &[("--out", Some(&args.out))],
        &[("operations file", args.ops.as_deref())],
    )?;
    let shape_args = args.shape.given();
    // Held from the read of `--model` to the write of `--out`: two runs on one file take
    // turns, so neither update is lost (the later one fails clearly after the wait).
    let _writer = nendo_file::WriterLock::acquire(&args.out, WRITER_WAIT)?;
    let mut model = match (&args.model, args.primitive) {
        (Some(path), _) => {
            if shape_args {
                return Err(ShapeArgs::not_for_a_model());
            }
            Model::read(path)
                .map_err(|e| anyhow::anyhow!(e.in_file(path)))?
                .model
        }
        (None, Some(p)) => {
            args.shape.check_applies(p)?;
            let params = args.shape.params();
            Model::new(p.build(&params).map_err(|e| anyhow::anyhow!("{p}: {e}"))?)
        }
        (None, None) => anyhow::bail!("give --primitive or --model"),
    };
    if let Some(r) = args.regulation {
        model.regulation = r;
    }
    // Streamed line by line: at most one line of 1 MB and a file of 64 MB are read
    // (`ops::read_ops`), so `/dev/zero` or an endless pipe is refused at once.
    let ops: Vec<(crate::surface::Op, String, usize)> = match &args.ops {
        None => Vec::new(),
        Some(path) => {
            let name = path.display().to_string();
            let read = if path.as_os_str() == "-" {
                ops::read_ops(std::io::stdin().lock())
            } else {
                let file = std::fs::File::open(path)
                    .map_err(|e| anyhow::anyhow!("{name}: {e}; nothing written"))?;
                ops::read_ops(std::io::BufReader::with_capacity(1 << 16, file))
            };
            read.map_err(|e| anyhow::anyhow!("{name}: {e}; nothing written"))?
                .into_iter()
                .map(|(op, l)| (op, name.clone(), l))
                .collect()
        }
    };
    let spec = args.turns.spec(&args.mirror);
    let symmetry = super::symmetry_args::symmetry_for(&mut model.surface, &spec, model.regulation)?;
    let start = Instant::now();
    let mut sculptor = Sculptor::new();
    let mut updates = 0usize;
    let mut refined = 0usize;
    for (i, (op, name, line)) in ops.iter().enumerate() {
        if args.auto_refine {
            let refuse = |e: &dyn std::fmt::Display| {
                anyhow::anyhow!(
                    "{name} line {line} (operation {}): {e}; nothing written",
                    i + 1
                )
            };
            let f = refine::for_finger(&model.surface, op).map_err(|e| refuse(&e))?;
            if !f.refinement.is_empty() {
                model.surface = f.refinement.apply(&model.surface).map_err(|e| refuse(&e))?;
                refined += 1;
            }
            if f.limited {
                eprintln!(
                    "nendo sculpt: {name} line {line}: refinement for the finger (patches of at most {} side) stopped at the grid limit of {MAX_PATCHES} patches ({} x {}); the operation is applied on these patches",
                    crate::num::Compact(f.target),
                    model.surface.patches_u(),
                    model.surface.patches_v()
                );
            }
        }
        // A refused operation (invalid, a result not finite or beyond the coordinate limit,
        // a seam the regulation could not keep G1) stops the run before anything is written.
        let applied = match &symmetry {
            Some(s) => sculptor.apply_mirrored(&mut model.surface, op, model.regulation, s),
            None => sculptor.apply(&mut model.surface, op, model.regulation),
        };
        let t = applied.map_err(|e| {
            anyhow::anyhow!(
                "{name} line {line} (operation {}): {e}; nothing written",
                i + 1
            )
        })?;
        updates += t.patches.len();
    }
    let elapsed = start.elapsed();
    model
        .write(&args.out)
        .map_err(|e| anyhow::anyhow!("{}", e.in_file(&args.out)))?;
    let refinement = if args.auto_refine {
        format!(
            ", {refined} refined for the finger, {} x {} patches",
            model.surface.patches_u(),
            model.surface.patches_v()
        )
    } else {
        String::new()
    };
    Ok(format!(
        "{} operations ({} patch updates, regulation {}{refinement}) in {:.3} ms -> {}",
        ops.len(),
        updates,
        model.regulation,
        elapsed.as_secs_f64() * 1e3,
        args.out.display()
    ))
}

#[cfg(test)]
mod tests {
    use crate::cli::arg_error::parse_counts;

    #[test]
    fn counts_parse() {
        assert_eq!(parse_counts("8x4").ok(), Some((8, 4)));
        assert_eq!(parse_counts("10X10").ok(), Some((10, 10)));
        assert!(parse_counts("8").is_err());
        assert!(parse_counts("ax4").is_err());
    }
}
