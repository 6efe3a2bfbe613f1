//! `nendo bench curves`: the curve edits of issue 7 on cubic and degree-9 curves — grab (closest
//! point plus the move), split, refinement — the accuracy of refinement on its similar-copy
//! property, and the 3D warp of a 1 600-patch control net by 3 curves (the interactive target is
//! ≤ 2 ms per drag frame).
//!
//! Set-up (fixed seeds): space curves with control points along a wavy line plus noise in
//! `[−1,1]³`; planar curves likewise for refinement. Grab: the closest point to a query within
//! 0.3 of the curve, then the grabbed point moved by a random vector (largest-weight and
//! least-change methods). Refinement: the start kept and the end moved by a random rotation
//! (−π..π) and scale (0.5..2) about it — curvature mode on one segment; variation mode with the
//! end tangents turned too; the paper's two-segment C2 cubic — whose exact answer is the similar
//! copy, so the error column is the largest control-point distance to that copy. Warp: a 40 × 40
//! plane of unit patches (14 641 control points), three cubics laid on it along `y = −10, 0, 10`,
//! the middle one lifted into an arch; the net is bound once at the start of the drag and every
//! frame replaces the dragged curve and carries the net. Times are medians over batches of the
//! mean time per operation, in CPU time of the measuring thread where Linux reports it (so that
//! other processes on a shared machine do not inflate them), elsewhere in wall time
//! ([`super::Stopwatch`]).

use super::rng::Seeded;
use super::{Table, cpu_median_ns, format_ns};
use glam::{DMat2, DVec2, DVec3};
use nendo::curve::edit::{Grab, GrabMethod, GrabOptions, split};
use nendo::curve::refine::{Constraint, Similarity, refine, refine_piecewise};
use nendo::curve::warp::{CurveWarp, WarpParams};
use nendo::curve::{BSpline, Bezier, Curve, Point};
use nendo::surface::{Primitive, PrimitiveParams};
use std::hint::black_box;

/// A curve with bend: control points along a wavy line, plus noise.
pub fn wavy<P: Point>(rng: &mut Seeded, degree: usize) -> Bezier<P> {
    let amp = rng.range(0.3, 1.0);
    let pts = (0..=degree)
        .map(|i| {
            let t = i as f64 / degree as f64;
            let mut c = vec![2.0 * t - 1.0, amp * (3.0 * t).sin()];
            if P::DIM == 3 {
                c.push(0.5 * amp * (2.0 * t).cos());
            }
            P::from_coords(&c).unwrap_or(P::ZERO) + rng.point::<P>(0.3)
        })
        .collect();
    Bezier::new(pts)
}

/// A grab case: the curve and the hand's start and end.
#[derive(Debug, Clone)]
pub struct GrabCase {
    /// The curve grabbed.
    pub curve: Curve<DVec3>,
    /// Where the hand takes hold (within 0.3 of the curve).
    pub from: DVec3,
    /// Where the hand lets go.
    pub to: DVec3,
}

/// `count` grab cases on Bezier curves of `degree`.
#[must_use]
pub fn grab_cases(count: usize, degree: usize, seed: u64) -> Vec<GrabCase> {
    let mut rng = Seeded::new(seed);
    (0..count)
        .map(|_| {
            let curve: Curve<DVec3> = wavy(&mut rng, degree).into();
            let from = curve.eval(rng.range(0.0, 1.0)) + rng.point::<DVec3>(0.17);
            let to = from + rng.point::<DVec3>(0.5);
            GrabCase { curve, from, to }
        })
        .collect()
}

/// One grab: the closest point, then the move. `None` when nothing lies within 1.
#[must_use]
pub fn grab_once(case: &GrabCase, method: GrabMethod) -> Option<Curve<DVec3>> {
    let options = GrabOptions {
        method,
        keep_ends: false,
    };
    let g = Grab::at_point(&case.curve, case.from, 1.0, options).ok()??;
    g.moved_by(case.to - case.from).ok()
}

/// A refinement case whose exact answer is a similar copy.
#[derive(Debug, Clone)]
pub struct RefineCase {
    /// The curve as segments (one for a single Bezier curve).
    pub segments: Vec<Bezier<DVec2>>,
    /// The constraints.
    pub constraints: Vec<Constraint>,
    /// The similar copy the constraints admit.
    pub copy: Vec<Bezier<DVec2>>,
    /// The mode.
    pub mode: Similarity,
}

/// `count` refinement cases: single Bezier curves of `degree` (`segments == 1`) or the
/// Bezier segments of a clamped cubic B-spline (`segments > 1`, C2 joins).
#[must_use]
pub fn refine_cases(
    count: usize,
    degree: usize,
    segments: usize,
    mode: Similarity,
    seed: u64,
) -> Vec<RefineCase> {
    let mut rng = Seeded::new(seed);
    (0..count)
        .map(|_| {
            let segs: Vec<Bezier<DVec2>> = if segments == 1 {
                vec![wavy(&mut rng, degree)]
            } else {
                let pts: Vec<DVec2> = wavy::<DVec2>(&mut rng, segments + 2).points().to_vec();
                BSpline::clamped_uniform(3, pts)
                    .map(|s| {
                        s.to_bezier_segments()
                            .into_iter()
                            .map(|s| s.bezier)
                            .collect()
                    })
                    .unwrap_or_else(|_| vec![wavy(&mut rng, 3)])
            };
            let start = segs[0].points()[0];
            let last = &segs[segs.len() - 1];
            let end = last.points()[last.degree()];
            let m = DMat2::from_angle(rng.range(-3.1, 3.1)) * rng.range(0.5, 2.0);
            let sim = |p: DVec2| start + m * (p - start);
            let n = segs.len() as f64;
            let mut constraints = vec![
                Constraint::Point {
                    u: 0.0,
                    point: start,
                },
                Constraint::Point {
                    u: n,
                    point: sim(end),
                },
            ];
            if mode == Similarity::Variation {
                constraints.push(Constraint::Tangent {
                    u: 0.0,
                    direction: m * segs[0].eval_derivative(0.0, 1),
                });
                constraints.push(Constraint::Tangent {
                    u: n,
                    direction: m * last.eval_derivative(1.0, 1),
                });
            }
            let copy = segs
                .iter()
                .map(|s| Bezier::new(s.points().iter().map(|&p| sim(p)).collect()))
                .collect();
            RefineCase {
                segments: segs,
                constraints,
                copy,
                mode,
            }
        })
        .collect()
}

/// Refines one case; `None` if the library refused it.
#[must_use]
pub fn refine_once(case: &RefineCase) -> Option<Vec<Bezier<DVec2>>> {
    if case.segments.len() == 1 {
        let c: Curve<DVec2> = case.segments[0].clone().into();
        match refine(&c, case.mode, &case.constraints).ok()?.curve {
            Curve::Bezier(b) => Some(vec![b]),
            Curve::BSpline(_) => None,
        }
    } else {
        refine_piecewise(&case.segments, case.mode, &case.constraints)
            .ok()
            .map(|r| r.curve)
    }
}

/// The warp set-up: a 40 × 40 plane's control net, three curves on it, the middle one's
/// dragged state.
#[derive(Debug, Clone)]
pub struct WarpCase {
    /// The control net (14 641 points).
    pub nodes: Vec<DVec3>,
    /// The three curves as laid on the plane.
    pub originals: Vec<Curve<DVec3>>,
    /// The middle curve lifted into an arch.
    pub dragged: Curve<DVec3>,
}

/// The warp set-up of the module docs.
///
/// # Panics
/// Never for these fixed parameters (the plane is valid).
#[must_use]
pub fn warp_case() -> WarpCase {
    let grid = Primitive::Plane
        .build(&PrimitiveParams {
            patches: Some((40, 40)),
            ..PrimitiveParams::default()
        })
        .unwrap_or_else(|e| panic!("plane 40 x 40: {e}"));
    let row = |y: f64, wave: f64| -> Curve<DVec3> {
        Bezier::new(vec![
            DVec3::new(-15.0, y, 0.0),
            DVec3::new(-5.0, y + wave, 0.0),
            DVec3::new(5.0, y - wave, 0.0),
            DVec3::new(15.0, y, 0.0),
        ])
        .into()
    };
    let originals = vec![row(-10.0, 1.0), row(0.0, 2.0), row(10.0, -1.0)];
    let dragged = Bezier::new(vec![
        DVec3::new(-15.0, 0.0, 0.0),
        DVec3::new(-5.0, 2.0, 4.0),
        DVec3::new(5.0, -2.0, 4.0),
        DVec3::new(15.0, 0.0, 0.0),
    ])
    .into();
    WarpCase {
        nodes: grid.nodes().to_vec(),
        originals,
        dragged,
    }
}

/// Runs the suite and returns the report. `scale` multiplies the case counts (1.0: 1 000 grab
/// and split cases, 200 refinement cases per row).
#[must_use]
pub fn report(scale: f64) -> String {
    let count = ((1000.0 * scale) as usize).max(20);
    let refine_count = ((200.0 * scale) as usize).max(10);
    let mut table = Table::new(&["operation", "curve", "median / op", "accuracy"]);

    for degree in [3, 9] {
        let cases = grab_cases(count, degree, 70 + degree as u64);
        for (method, name) in [
            (GrabMethod::LargestWeight, "largest weight"),
            (GrabMethod::LeastChange, "least change"),
        ] {
            let mut worst: f64 = 0.0;
            for c in &cases {
                if let (Some(moved), Some(n)) = (grab_once(c, method), c.curve.closest(c.from, 1.0))
                {
                    let want = c.curve.eval(n.u) + (c.to - c.from);
                    worst = worst.max((moved.eval(n.u) - want).length());
                }
            }
            let ns = cpu_median_ns(15, cases.len(), |k| {
                black_box(grab_once(&cases[k % cases.len()], method));
            });
            table.row(vec![
                format!("grab ({name}), closest point included"),
                format!("3D Bezier degree {degree}"),
                format_ns(ns),
                format!("max |C'(u) − C(u) − ΔP| = {worst:.1e}"),
            ]);
        }
        let ns = cpu_median_ns(15, cases.len(), |k| {
            let c = &cases[k % cases.len()];
            black_box(split(&c.curve, 0.37).ok());
        });
        table.row(vec![
            "split at u = 0.37".into(),
            format!("3D Bezier degree {degree}"),
            format_ns(ns),
            String::new(),
        ]);
    }
    {
        let mut rng = Seeded::new(77);
        let splines: Vec<Curve<DVec3>> = (0..count.min(200))
            .filter_map(|_| {
                BSpline::clamped_uniform(3, wavy::<DVec3>(&mut rng, 7).points().to_vec())
                    .ok()
                    .map(Curve::BSpline)
            })
            .collect();
        let ns = cpu_median_ns(15, splines.len(), |k| {
            black_box(split(&splines[k % splines.len()], 0.37).ok());
        });
        table.row(vec![
            "split at u = 0.37".into(),
            "3D cubic B-spline, 8 points".into(),
            format_ns(ns),
            String::new(),
        ]);
    }

    let refine_rows = [
        (3, 1, Similarity::Curvature, "2D Bezier cubic"),
        (9, 1, Similarity::Curvature, "2D Bezier degree 9"),
        (3, 1, Similarity::Variation, "2D Bezier cubic"),
        (9, 1, Similarity::Variation, "2D Bezier degree 9"),
        (3, 2, Similarity::Variation, "2D 2-segment C2 cubic"),
    ];
    for (i, (degree, segments, mode, label)) in refine_rows.into_iter().enumerate() {
        let cases = refine_cases(refine_count, degree, segments, mode, 90 + i as u64);
        let mut worst: f64 = 0.0;
        let mut refused = 0;
        for c in &cases {
            match refine_once(c) {
                Some(r) => {
                    for (a, b) in r.iter().zip(&c.copy) {
                        for (p, q) in a.points().iter().zip(b.points()) {
                            worst = worst.max((*p - *q).length());
                        }
                    }
                }
                None => refused += 1,
            }
        }
        let ns = cpu_median_ns(11, cases.len(), |k| {
            black_box(refine_once(&cases[k % cases.len()]));
        });
        let refused = if refused > 0 {
            format!(", {refused} refused")
        } else {
            String::new()
        };
        table.row(vec![
            format!("refine ({mode:?}), end moved by a similarity"),
            label.into(),
            format_ns(ns),
            format!("max distance to the similar copy {worst:.1e}{refused}"),
        ]);
    }

    let case = warp_case();
    let params = WarpParams::default();
    let mut warp = match CurveWarp::still(&case.originals, params) {
        Ok(w) => w,
        Err(e) => return format!("warp set-up failed: {e}\n"),
    };
    let bind_ns = cpu_median_ns(5, 1, |_| {
        black_box(warp.bind(&case.nodes));
    });
    let bound = warp.bind(&case.nodes);
    let mut out = case.nodes.clone();
    // Two dragged states, alternated so that no frame repeats the last.
    let lower = match &case.dragged {
        Curve::Bezier(b) => Curve::Bezier(Bezier::new(
            b.points()
                .iter()
                .map(|p| *p * DVec3::new(1.0, 1.0, 0.9))
                .collect(),
        )),
        other => other.clone(),
    };
    let frames = [case.dragged.clone(), lower];
    let apply_ns = cpu_median_ns(21, 4, |k| {
        let _ = warp.set_deformed(1, frames[k % 2].clone());
        black_box(bound.apply_into(&warp, &mut out).ok());
    });
    let _ = warp.set_deformed(1, case.dragged.clone());
    let _ = bound.apply_into(&warp, &mut out);
    let lifted = out.iter().filter(|p| p.z > 1e-9).count();
    // Every curve dragged at once (each lifted by 0.5 more than the last frame's).
    let lift = |c: &Curve<DVec3>, dz: f64| -> Curve<DVec3> {
        match c {
            Curve::Bezier(b) => Curve::Bezier(Bezier::new(
                b.points().iter().map(|p| *p + DVec3::Z * dz).collect(),
            )),
            other => other.clone(),
        }
    };
    let all_ns = cpu_median_ns(21, 4, |k| {
        for (i, c) in case.originals.iter().enumerate() {
            let _ = warp.set_deformed(i, lift(c, 0.5 + (k % 2) as f64 * 0.1));
        }
        black_box(bound.apply_into(&warp, &mut out).ok());
    });
    let direct_ns = cpu_median_ns(3, 1, |_| {
        black_box(warp.warp_points(&case.nodes));
    });
    table.row(vec![
        "warp: bind the net to the curves (once per drag)".into(),
        format!("{} control points, 3 curves", case.nodes.len()),
        format_ns(bind_ns),
        String::new(),
    ]);
    table.row(vec![
        "warp: one drag frame (set curve + carry the net)".into(),
        format!("{} control points, 3 curves", case.nodes.len()),
        format_ns(apply_ns),
        format!("{lifted} points lifted; target ≤ 2 ms"),
    ]);
    table.row(vec![
        "warp: one drag frame, all 3 curves moved".into(),
        format!("{} control points, 3 curves", case.nodes.len()),
        format_ns(all_ns),
        String::new(),
    ]);
    table.row(vec![
        "warp: every point from scratch (no binding)".into(),
        format!("{} control points, 3 curves", case.nodes.len()),
        format_ns(direct_ns),
        String::new(),
    ]);
    let mut text = String::from("nendo bench curves (issue 7)\n\n");
    text.push_str(&table.render());
    text
}
