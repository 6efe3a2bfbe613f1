#![forbid(unsafe_code)]
//! Curve edits and curve-driven warping (issue 7): grab, split and refine on cubic and degree-9
//! curves, and one drag frame of the 1 600-patch control net carried by 3 curves.
//!
//! `cargo bench --bench curves` first prints the table of `nendo bench curves` (with the
//! accuracy figures), then runs the criterion groups on the same cases.

use criterion::{BenchmarkId, Criterion, criterion_group};
use nendo::curve::edit::{GrabMethod, split};
use nendo::curve::refine::Similarity;
use nendo::curve::warp::{CurveWarp, WarpParams};
use nendo_bench::curves::{grab_cases, grab_once, refine_cases, refine_once, warp_case};
use std::hint::black_box;

fn edits(c: &mut Criterion) {
    let mut g = c.benchmark_group("curve edit");
    for degree in [3, 9] {
        let cases = grab_cases(256, degree, 70 + degree as u64);
        let mut k = 0usize;
        g.bench_function(BenchmarkId::new("grab largest weight", degree), |b| {
            b.iter(|| {
                k += 1;
                black_box(grab_once(
                    &cases[k % cases.len()],
                    GrabMethod::LargestWeight,
                ))
            })
        });
        g.bench_function(BenchmarkId::new("grab least change", degree), |b| {
            b.iter(|| {
                k += 1;
                black_box(grab_once(&cases[k % cases.len()], GrabMethod::LeastChange))
            })
        });
        g.bench_function(BenchmarkId::new("split", degree), |b| {
            b.iter(|| {
                k += 1;
                black_box(split(&cases[k % cases.len()].curve, 0.37).ok())
            })
        });
        for mode in [Similarity::Curvature, Similarity::Variation] {
            let cases = refine_cases(64, degree, 1, mode, 90 + degree as u64);
            g.bench_function(BenchmarkId::new(format!("refine {mode:?}"), degree), |b| {
                b.iter(|| {
                    k += 1;
                    black_box(refine_once(&cases[k % cases.len()]))
                })
            });
        }
    }
    g.finish();
}

fn warping(c: &mut Criterion) {
    let case = warp_case();
    let Ok(mut warp) = CurveWarp::still(&case.originals, WarpParams::default()) else {
        eprintln!("warp set-up failed");
        return;
    };
    let bound = warp.bind(&case.nodes);
    let mut out = case.nodes.clone();
    let mut g = c.benchmark_group("curve warp");
    g.sample_size(30);
    g.bench_function("drag frame, 14641 control points, 3 curves", |b| {
        b.iter(|| {
            let _ = warp.set_deformed(1, case.dragged.clone());
            black_box(bound.apply_into(&warp, &mut out).ok())
        })
    });
    g.finish();
}

criterion_group!(group, edits, warping);

fn main() {
    print!("{}", nendo_bench::curves::report(0.5));
    group();
    Criterion::default().configure_from_args().final_summary();
}
