//! Closest point on curves: Bezier clipping against kurbo 0.13's `CubicBez::nearest`, a
//! 1001-sample search and Newton from 8 seeds, on the same random cases in one run.
//!
//! `cargo bench --bench closest` first prints the comparison table of
//! `nendo::bench::closest::report` with kurbo added as a baseline (the library itself does not
//! depend on kurbo), then runs the criterion groups.

use criterion::{BenchmarkId, Criterion, criterion_group};
use glam::DVec2;
use kurbo::{CubicBez, ParamCurveNearest, Point as KPoint};
use nendo::bench::closest::{Baseline, Spread, cases, report};
use nendo::curve::{Bezier, Curve, CurveSet, closest_bezier};
use std::hint::black_box;

fn to_kurbo(c: &Bezier<DVec2>) -> CubicBez {
    let p = c.points();
    let k = |v: DVec2| KPoint::new(v.x, v.y);
    CubicBez::new(k(p[0]), k(p[1]), k(p[2]), k(p[3]))
}

fn kurbo_distance(c: &Bezier<DVec2>, q: DVec2) -> f64 {
    to_kurbo(c)
        .nearest(KPoint::new(q.x, q.y), 1e-9)
        .distance_sq
        .sqrt()
}

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("closest");
    for (name, spread) in [("spread", Spread::Around), ("close", Spread::Close)] {
        let set = cases::<DVec2>(256, 3, spread, 11);
        let kset: Vec<(CubicBez, KPoint)> = set
            .iter()
            .map(|c| (to_kurbo(&c.curve), KPoint::new(c.q.x, c.q.y)))
            .collect();
        g.bench_function(BenchmarkId::new("clipping 2D cubic", name), |b| {
            b.iter(|| {
                for c in &set {
                    black_box(closest_bezier(&c.curve, c.q, f64::INFINITY));
                }
            })
        });
        g.bench_function(BenchmarkId::new("kurbo 2D cubic", name), |b| {
            b.iter(|| {
                for (c, q) in &kset {
                    black_box(c.nearest(*q, 1e-9));
                }
            })
        });
    }
    let set3 = cases::<glam::DVec3>(256, 3, Spread::Around, 12);
    g.bench_function("clipping 3D cubic", |b| {
        b.iter(|| {
            for c in &set3 {
                black_box(closest_bezier(&c.curve, c.q, f64::INFINITY));
            }
        })
    });
    let set9 = cases::<DVec2>(256, 9, Spread::Around, 13);
    g.bench_function("clipping 2D degree 9", |b| {
        b.iter(|| {
            for c in &set9 {
                black_box(closest_bezier(&c.curve, c.q, f64::INFINITY));
            }
        })
    });
    let curves: Vec<Curve<DVec2>> = cases::<DVec2>(1000, 3, Spread::Around, 14)
        .into_iter()
        .enumerate()
        .map(|(i, c)| {
            let shift = DVec2::new((i % 32) as f64 * 1.25, (i / 32) as f64 * 1.25);
            Curve::Bezier(Bezier::new(
                c.curve.points().iter().map(|&p| p + shift).collect(),
            ))
        })
        .collect();
    let cs = CurveSet::new(&curves);
    let qs: Vec<DVec2> = set9
        .iter()
        .map(|c| c.q * 10.0 + DVec2::splat(20.0))
        .collect();
    g.bench_function("pick among 1000 2D cubics", |b| {
        b.iter(|| {
            for &q in &qs {
                black_box(cs.pick(q, f64::INFINITY));
            }
        })
    });
    g.finish();
}

criterion_group!(closest_benches, benches);

fn main() {
    let quick = std::env::args().any(|a| a == "--test" || a == "--list");
    if !quick {
        let kurbo = Baseline {
            name: "kurbo 0.13 CubicBez::nearest (accuracy 1e-9)",
            distance: &kurbo_distance,
        };
        print!("{}", report(1.0, &[kurbo]));
    }
    closest_benches();
    criterion::Criterion::default()
        .configure_from_args()
        .final_summary();
}
