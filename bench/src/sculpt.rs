//! `nendo bench sculpt`: the cost of one push — samples, flows, Bernstein inverse and (per
//! column) regulation — on grids of growing size with the same finger, so that the ratio
//! 40 × 40 / 10 × 10 shows whether the cost follows the touched area (target ≤ 1.5) rather
//! than the patch count.
//!
//! Set-up: planes of 10 × 10, 20 × 20 and 40 × 40 unit patches pushed at `(0.5, 0.5, 0)` along
//! −z, and spheres of radius 3 with 8 × 4 and 32 × 16 patches pushed at latitude 30°, longitude
//! 20° along the inward normal; finger radius 1.25 side, depth 0.5 side. Pushes alternate
//! with pulls of the same depth so the surface stays bounded over the repetitions. Times are
//! medians over batches of the mean time per operation, in **CPU time of the measuring
//! thread** on Linux (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)`), so that other processes on a
//! shared machine do not inflate them; elsewhere in wall time ([`super::Stopwatch`]). The last
//! column is the exact regulation projecting group by group, for comparison with the default
//! coupled projection ([`nendo::surface::Sculptor::with_group_by_group_exact`]).
//!
//! **Refinement** ([`refinement_report`], issue 13): the time of uniform refinement ×2 of the
//! 40 × 40 plane and a 40 × 40 sphere (radius 3) — every patch split into 2 × 2, ratios
//! carried over, the grid rebuilt with its box pyramid — with the counts before and after,
//! the cost of the same push (exact regulation) on the refined grids next to the unrefined
//! ones, and the time of the finger's refinement rule ([`nendo::surface::refine::for_finger`])
//! and of applying it for the paper's push (r_f 1.25) on the 10 × 10 plane.

use glam::DVec3;
use std::hint::black_box;

use super::{Stopwatch, Table, cpu_median_ns, format_ns, median};
use nendo::surface::refine;
use nendo::surface::{Grid, Op, Primitive, PrimitiveParams, Regulation, Sculptor};

/// One benchmark case: a grid and the push applied to it.
#[derive(Debug, Clone)]
pub struct SculptCase {
    /// Row label.
    pub name: String,
    /// The starting grid.
    pub grid: Grid,
    /// The push (its pull twin is the same with the depth negated).
    pub push: Op,
}

/// The cases of the suite (see the module docs).
///
/// # Panics
/// Never for these fixed parameters (the primitives are valid).
#[must_use]
pub fn cases() -> Vec<SculptCase> {
    let mut out = Vec::new();
    for m in [10, 20, 40] {
        let grid = Primitive::Plane
            .build(&PrimitiveParams {
                patches: Some((m, m)),
                ..PrimitiveParams::default()
            })
            .unwrap_or_else(|e| panic!("plane {m}: {e}"));
        let push = Op::Push {
            at: DVec3::new(0.5, 0.5, 0.0),
            dir: -DVec3::Z,
            depth: 0.5,
            radius: 1.25,
        };
        out.push(SculptCase {
            name: format!("plane {m} x {m}"),
            grid,
            push,
        });
    }
    let (lat, lon) = (30f64.to_radians(), 20f64.to_radians());
    let at = DVec3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin()) * 3.0;
    for (m, n) in [(8, 4), (32, 16)] {
        let grid = Primitive::Sphere
            .build(&PrimitiveParams {
                patches: Some((m, n)),
                radius: Some(3.0),
                ..PrimitiveParams::default()
            })
            .unwrap_or_else(|e| panic!("sphere {m}: {e}"));
        let push = Op::Push {
            at,
            dir: -at,
            depth: 0.5,
            radius: 1.25,
        };
        out.push(SculptCase {
            name: format!("sphere {m} x {n}"),
            grid,
            push,
        });
    }
    out
}

/// The same operation with its depth negated.
#[must_use]
pub fn reversed(op: &Op) -> Op {
    match op.clone() {
        Op::Brushed { op, brush } => Op::Brushed {
            op: Box::new(reversed(&op)),
            brush,
        },
        Op::Push {
            at,
            dir,
            depth,
            radius,
        } => Op::Push {
            at,
            dir,
            depth: -depth,
            radius,
        },
        Op::Drag {
            path,
            dir,
            depth,
            radius,
        } => Op::Drag {
            path,
            dir,
            depth: -depth,
            radius,
        },
        Op::PushNormal { at, depth, radius } => Op::PushNormal {
            at,
            depth: -depth,
            radius,
        },
        Op::Groove {
            path,
            dirs,
            depth,
            radius,
        } => Op::Groove {
            path,
            dirs,
            depth: -depth,
            radius,
        },
        // The way back from a move is the opposite move; smoothing has no depth.
        Op::Move { at, to, radius } => Op::Move {
            at: to,
            to: at,
            radius,
        },
        other @ Op::Smooth { .. } => other,
        // Inflate and crease reversed press the other way; flatten and pinch have no depth.
        Op::Sculpt(mut b) => {
            b.depth = -b.depth;
            Op::Sculpt(b)
        }
    }
}

/// Median nanoseconds per operation of alternating push / pull on a copy of the case's grid,
/// and the number of patches one push changes.
#[must_use]
pub fn time_push(
    case: &SculptCase,
    regulation: Regulation,
    calls_per_batch: usize,
) -> (f64, usize, usize) {
    time_push_with(case, regulation, calls_per_batch, Sculptor::new())
}

/// [`time_push`] with a given sculptor (e.g. [`Sculptor::with_group_by_group_exact`]).
#[must_use]
pub fn time_push_with(
    case: &SculptCase,
    regulation: Regulation,
    calls_per_batch: usize,
    mut sculptor: Sculptor,
) -> (f64, usize, usize) {
    let mut grid = case.grid.clone();
    let pull = reversed(&case.push);
    let (touched, examined) = match sculptor.apply(&mut grid.clone(), &case.push, regulation) {
        Ok(t) => (t.patches.len(), t.examined),
        Err(_) => (0, 0),
    };
    let ops = [case.push.clone(), pull];
    let fingers: Vec<_> = ops.iter().filter_map(|o| o.finger().ok()).collect();
    if fingers.len() != 2 {
        return (f64::NAN, touched, examined);
    }
    let ns = if thread_cpu_ns().is_some() {
        for k in 0..calls_per_batch {
            let _ = black_box(sculptor.apply_finger(&mut grid, &fingers[k % 2], regulation));
        }
        let mut per_call = Vec::with_capacity(21);
        for _ in 0..21 {
            let t0 = thread_cpu_ns().unwrap_or(0);
            for k in 0..calls_per_batch {
                let _ = black_box(sculptor.apply_finger(&mut grid, &fingers[k % 2], regulation));
            }
            let t1 = thread_cpu_ns().unwrap_or(0);
            per_call.push(t1.saturating_sub(t0) as f64 / calls_per_batch.max(1) as f64);
        }
        median(&mut per_call)
    } else {
        let watch = Stopwatch {
            batches: 21,
            calls_per_batch,
        };
        watch.median_ns(|k| {
            let _ = black_box(sculptor.apply_finger(&mut grid, &fingers[k % 2], regulation));
        })
    };
    (ns, touched, examined)
}

/// CPU time consumed by the calling thread so far (ns), on Linux; `None` when the clock
/// cannot be read.
#[cfg(target_os = "linux")]
#[must_use]
pub fn thread_cpu_ns() -> Option<u64> {
    use nix::sys::time::TimeValLike;
    use nix::time::{ClockId, clock_gettime};
    let ts = clock_gettime(ClockId::CLOCK_THREAD_CPUTIME_ID).ok()?;
    u64::try_from(ts.num_nanoseconds()).ok()
}

/// CPU time of the calling thread: not available on this platform (wall time is used).
#[cfg(not(target_os = "linux"))]
#[must_use]
pub fn thread_cpu_ns() -> Option<u64> {
    None
}

/// The suite's table; `scale` scales the repetitions.
#[must_use]
pub fn report(scale: f64) -> String {
    let calls = ((400.0 * scale).round() as usize).max(2) & !1;
    let methods = Regulation::ALL;
    let mut header = vec![
        "case".to_string(),
        "patches".into(),
        "examined".into(),
        "moved".into(),
    ];
    for r in methods {
        header.push(format!("{r} (µs)"));
    }
    header.push("exact group by group (µs)".into());
    let header_refs: Vec<&str> = header.iter().map(String::as_str).collect();
    let mut t = Table::new(&header_refs);
    let mut medians: Vec<Vec<f64>> = Vec::new();
    for case in cases() {
        let mut row = vec![case.name.clone(), case.grid.patch_count().to_string()];
        let mut times = Vec::new();
        let (mut touched, mut examined) = (0, 0);
        for r in methods {
            let (ns, tp, ex) = time_push(&case, r, calls);
            if r == Regulation::None {
                (touched, examined) = (tp, ex);
            }
            times.push(ns);
        }
        let (ns, _, _) = time_push_with(
            &case,
            Regulation::Exact,
            calls,
            Sculptor::with_group_by_group_exact(),
        );
        times.push(ns);
        row.push(examined.to_string());
        row.push(touched.to_string());
        row.extend(times.iter().map(|ns| format!("{:.2}", ns / 1e3)));
        t.row(row);
        medians.push(times);
    }
    let mut ratio = vec![
        "ratio 40x40 / 10x10".to_string(),
        String::new(),
        String::new(),
        String::new(),
    ];
    ratio.extend((0..=methods.len()).map(|k| format!("{:.2}", medians[2][k] / medians[0][k])));
    t.row(ratio);
    let mut ratio = vec![
        "ratio sphere 32x16 / 8x4".to_string(),
        String::new(),
        String::new(),
        String::new(),
    ];
    ratio.extend((0..=methods.len()).map(|k| format!("{:.2}", medians[4][k] / medians[3][k])));
    t.row(ratio);
    let clock = if thread_cpu_ns().is_some() {
        "thread CPU time"
    } else {
        "wall time"
    };
    format!(
        "One push (and its pull twin), finger r_f = 1.25 side, depth 0.5 side; median {clock} per \
         operation, by regulation method.\nexamined: patches sampled after the box test; moved: \
         patches the finger moved.\nTargets: plane 10x10 without regulation <= 10 µs, with \
         regulation <= 20 µs; ratio 40x40 / 10x10 <= 1.5.\n{}\n{}{}",
        t.render(),
        refinement_report(scale),
        smooth_drop()
    )
}

/// The refinement table (see the module docs); `scale` scales the repetitions.
#[must_use]
pub fn refinement_report(scale: f64) -> String {
    let reps = ((5.0 * scale).round() as usize).max(1);
    let calls = ((400.0 * scale).round() as usize).max(2) & !1;
    let mut t = Table::new(&[
        "case",
        "patches",
        "refined x2",
        "refine x2",
        "push exact",
        "push exact on x2",
    ]);
    let plane = cases().swap_remove(2);
    let (lat, lon) = (30f64.to_radians(), 20f64.to_radians());
    let at = DVec3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin()) * 3.0;
    let sphere = Primitive::Sphere
        .build(&PrimitiveParams {
            patches: Some((40, 40)),
            radius: Some(3.0),
            ..PrimitiveParams::default()
        })
        .map(|grid| SculptCase {
            name: "sphere 40 x 40".into(),
            grid,
            push: Op::Push {
                at,
                dir: -at,
                depth: 0.5,
                radius: 1.25,
            },
        });
    for case in std::iter::once(Ok(plane)).chain(std::iter::once(sphere)) {
        let case = match case {
            Ok(c) => c,
            Err(e) => return format!("sphere 40 x 40: {e}"),
        };
        let refined = match refine::uniform(&case.grid, 2) {
            Ok(g) => g,
            Err(e) => return format!("{}: {e}", case.name),
        };
        let ns = cpu_median_ns(reps, 3, |_| {
            let _ = black_box(refine::uniform(black_box(&case.grid), 2));
        });
        let (coarse, _, _) = time_push(&case, Regulation::Exact, calls);
        let fine_case = SculptCase {
            name: case.name.clone(),
            grid: refined.clone(),
            push: case.push.clone(),
        };
        let (fine, _, _) = time_push(&fine_case, Regulation::Exact, calls);
        t.row(vec![
            case.name.clone(),
            case.grid.patch_count().to_string(),
            format!(
                "{} x {} = {}",
                refined.patches_u(),
                refined.patches_v(),
                refined.patch_count()
            ),
            format_ns(ns),
            format_ns(coarse),
            format_ns(fine),
        ]);
    }
    // The finger's rule for the paper's push on the 10 × 10 plane.
    let paper = cases().swap_remove(0);
    let rule = refine::for_finger(&paper.grid, &paper.push);
    let finger = match &rule {
        Ok(f) => {
            let (m, n) = f.refinement.counts();
            let find = cpu_median_ns(reps, 5, |_| {
                let _ = black_box(refine::for_finger(black_box(&paper.grid), &paper.push));
            });
            let apply = cpu_median_ns(reps, 5, |_| {
                let _ = black_box(f.refinement.apply(black_box(&paper.grid)));
            });
            format!(
                "finger rule, paper push (r_f 1.25, patches <= {:.3} side) on plane 10 x 10: -> {m} x {n}; finding it {}, applying it {}",
                f.target,
                format_ns(find),
                format_ns(apply)
            )
        }
        Err(e) => format!("finger rule: {e}"),
    };
    let clock = if thread_cpu_ns().is_some() {
        "thread CPU time"
    } else {
        "wall time"
    };
    format!(
        "Refinement (issue 13): uniform x2 (every patch into 2 x 2, the same surface), median {clock}; the push (r_f 1.25, depth 0.5, exact regulation) before and after.\n{}{finger}\n",
        t.render()
    )
}

/// One line: by how much a smoothing stroke lowers the thin-plate energy of the patches it
/// touches (median over 10 strokes, strength 1, radius 1.25, exact regulation) on a 32 × 16
/// sphere of radius 3 dented by 6 pushes of depth 0.5 around the stroke centre.
#[must_use]
pub fn smooth_drop() -> String {
    let Ok(mut grid) = Primitive::Sphere.build(&PrimitiveParams {
        patches: Some((32, 16)),
        radius: Some(3.0),
        ..PrimitiveParams::default()
    }) else {
        return "smooth: the sphere could not be built\n".to_string();
    };
    let mut sculptor = Sculptor::new();
    let dir = |lat: f64, lon: f64| {
        let (lat, lon) = (lat.to_radians(), lon.to_radians());
        DVec3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin())
    };
    for k in 0..6 {
        let at = dir(30.0 + 8.0 * (k % 2) as f64, 20.0 + 6.0 * k as f64) * 3.0;
        let _ = sculptor.apply(
            &mut grid,
            &Op::Push {
                at,
                dir: -at,
                depth: 0.5,
                radius: 0.8,
            },
            Regulation::Exact,
        );
    }
    let mut drops = Vec::new();
    for _ in 0..10 {
        let op = Op::Smooth {
            at: dir(34.0, 35.0) * 3.0,
            radius: 1.25,
            strength: 1.0,
        };
        if sculptor.apply(&mut grid, &op, Regulation::Exact).is_ok()
            && let Some(e) = sculptor.last_energy()
        {
            drops.push(100.0 * e.relative());
        }
    }
    format!(
        "smooth (r = 1.25, strength 1, exact): thin-plate energy of the touched patches lowered by \
         {:.2} % per stroke (median of {} strokes on a dented 32x16 sphere)\n",
        median(&mut drops),
        drops.len()
    )
}
