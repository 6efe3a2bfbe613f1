#![forbid(unsafe_code)]
//! Closest point on curves: Bezier clipping against kurbo 0.13's `CubicBez::nearest`, a
//! 1001-sample search and Newton from 8 seeds, on the same random cases in one run.
//!
//! `cargo bench --bench closest` first prints the comparison table of
//! `nendo_bench::closest::report` with kurbo added as a baseline (the library itself does not
//! depend on kurbo), then runs the criterion groups on the same case sets (same seeds and
//! counts). Both sides get their inputs ready before timing: kurbo its `CubicBez` and `Point`,
//! clipping its `Bezier` and query. With `--profile-time` (e.g. under callgrind) the table is
//! skipped.

use criterion::{BenchmarkId, Criterion, criterion_group};
use glam::{DVec2, DVec3};
use kurbo::{CubicBez, ParamCurveNearest, Point as KPoint};
use nendo::curve::{Bezier, CurveSet, closest_bezier, ray_closest_bezier, sphere_intervals_bezier};
use nendo_bench::closest::{
    Baseline, Batch, ClosestCase, Prepared, SEEDS, Spread, case_count, cases, pick_setup,
    probe_setup, report,
};
use std::hint::black_box;

fn to_kurbo(c: &Bezier<DVec2>) -> CubicBez {
    let p = c.points();
    let k = |v: DVec2| KPoint::new(v.x, v.y);
    CubicBez::new(k(p[0]), k(p[1]), k(p[2]), k(p[3]))
}

fn kurbo_inputs(set: &[ClosestCase<DVec2>]) -> Vec<(CubicBez, KPoint)> {
    set.iter()
        .map(|c| (to_kurbo(&c.curve), KPoint::new(c.q.x, c.q.y)))
        .collect()
}

#[inline(always)]
fn kurbo_query((c, q): &(CubicBez, KPoint)) -> (f64, f64) {
    let n = c.nearest(*q, 1e-9);
    (n.t, n.distance_sq.sqrt())
}

struct Kurbo;

impl Baseline for Kurbo {
    fn name(&self) -> &str {
        "kurbo 0.13 CubicBez::nearest (accuracy 1e-9)"
    }
    fn prepare<'a>(&'a self, cases: &[ClosestCase<DVec2>]) -> Box<dyn Batch + 'a> {
        Box::new(Prepared::new(kurbo_inputs(cases), kurbo_query))
    }
}

fn benches(c: &mut Criterion) {
    let count = case_count(1.0);
    let mut g = c.benchmark_group("closest");
    g.throughput(criterion::Throughput::Elements(count as u64));
    for (name, spread, seed) in [
        ("spread", Spread::Around, SEEDS[0]),
        ("close", Spread::Close, SEEDS[1]),
    ] {
        let set = cases::<DVec2>(count, 3, spread, seed);
        let kset = kurbo_inputs(&set);
        g.bench_function(BenchmarkId::new("clipping 2D cubic", name), |b| {
            b.iter(|| {
                for c in &set {
                    black_box(closest_bezier(
                        black_box(&c.curve),
                        black_box(c.q),
                        f64::INFINITY,
                    ));
                }
            })
        });
        g.bench_function(BenchmarkId::new("kurbo 2D cubic", name), |b| {
            b.iter(|| {
                for x in &kset {
                    black_box(kurbo_query(black_box(x)));
                }
            })
        });
    }
    let set3 = cases::<DVec3>(count, 3, Spread::Around, SEEDS[2]);
    g.bench_function("clipping 3D cubic", |b| {
        b.iter(|| {
            for c in &set3 {
                black_box(closest_bezier(
                    black_box(&c.curve),
                    black_box(c.q),
                    f64::INFINITY,
                ));
            }
        })
    });
    let (radii, dirs) = probe_setup(&set3);
    g.bench_function("probe sphere 3D cubic", |b| {
        b.iter(|| {
            for (c, &r) in set3.iter().zip(&radii) {
                black_box(sphere_intervals_bezier(
                    black_box(&c.curve),
                    black_box(c.q),
                    r,
                ));
            }
        })
    });
    g.bench_function("ray 3D cubic", |b| {
        b.iter(|| {
            for (c, &d) in set3.iter().zip(&dirs) {
                black_box(ray_closest_bezier(black_box(&c.curve), black_box(c.q), d));
            }
        })
    });
    let set9 = cases::<DVec2>(count, 9, Spread::Around, SEEDS[3]);
    g.bench_function("clipping 2D degree 9", |b| {
        b.iter(|| {
            for c in &set9 {
                black_box(closest_bezier(
                    black_box(&c.curve),
                    black_box(c.q),
                    f64::INFINITY,
                ));
            }
        })
    });
    let (curves, qs) = pick_setup(count);
    let cs = CurveSet::new(&curves);
    g.bench_function("pick among 1000 2D cubics", |b| {
        b.iter(|| {
            for &q in &qs {
                black_box(cs.pick(black_box(q), f64::INFINITY));
            }
        })
    });
    g.finish();
}

criterion_group!(closest_benches, benches);

/// `NENDO_CLOSEST_PROFILE=<set>` (spread, close, 3d, nonic, kurbo-spread, kurbo-close, pick,
/// sphere, ray): answers that set's 500 cases 10 times through [`Batch::run`] and exits, for
/// instruction counts under `valgrind --tool=callgrind` (inclusive cost of `run` / 5 000).
fn profile(set: &str) {
    let n = 500;
    let s2 = || cases::<DVec2>(n, 3, Spread::Around, SEEDS[0]);
    let c2 = || cases::<DVec2>(n, 3, Spread::Close, SEEDS[1]);
    let s3 = || cases::<DVec3>(n, 3, Spread::Around, SEEDS[2]);
    let batch: Box<dyn Batch> = match set {
        "spread" => nendo_bench::closest::clipping_batch(&s2()),
        "close" => nendo_bench::closest::clipping_batch(&c2()),
        "3d" => nendo_bench::closest::clipping_batch(&s3()),
        "nonic" => {
            nendo_bench::closest::clipping_batch(&cases::<DVec2>(n, 9, Spread::Around, SEEDS[3]))
        }
        "kurbo-spread" => Box::new(Prepared::new(kurbo_inputs(&s2()), kurbo_query)),
        "kurbo-close" => Box::new(Prepared::new(kurbo_inputs(&c2()), kurbo_query)),
        "pick" => {
            let (curves, qs) = pick_setup(n);
            let cs = CurveSet::new(&curves);
            Box::new(Prepared::new(qs, move |&q: &DVec2| {
                cs.pick(q, f64::INFINITY)
                    .map_or((0.0, 0.0), |p| (p.nearest.u, p.nearest.distance))
            }))
        }
        "sphere" => {
            let set = s3();
            let (radii, _) = probe_setup(&set);
            let inputs: Vec<(Bezier<DVec3>, DVec3, f64)> = set
                .iter()
                .zip(&radii)
                .map(|(c, &r)| (c.curve.clone(), c.q, r))
                .collect();
            Box::new(Prepared::new(
                inputs,
                |(c, q, r): &(Bezier<DVec3>, DVec3, f64)| {
                    (sphere_intervals_bezier(c, *q, *r).len() as f64, 0.0)
                },
            ))
        }
        "ray" => {
            let set = s3();
            let (_, dirs) = probe_setup(&set);
            let inputs: Vec<(Bezier<DVec3>, DVec3, DVec3)> = set
                .iter()
                .zip(&dirs)
                .map(|(c, &d)| (c.curve.clone(), c.q, d))
                .collect();
            Box::new(Prepared::new(
                inputs,
                |(c, o, d): &(Bezier<DVec3>, DVec3, DVec3)| {
                    ray_closest_bezier(c, *o, *d).map_or((0.0, 0.0), |r| (r.u, r.distance))
                },
            ))
        }
        _ => {
            eprintln!("unknown NENDO_CLOSEST_PROFILE set {set}");
            return;
        }
    };
    for _ in 0..10 {
        black_box(batch.run());
    }
}

fn main() {
    if let Ok(set) = std::env::var("NENDO_CLOSEST_PROFILE") {
        profile(&set);
        return;
    }
    let quick = std::env::args().any(|a| a == "--test" || a == "--list" || a == "--profile-time");
    if !quick {
        print!("{}", report(1.0, &[&Kurbo]));
    }
    closest_benches();
    criterion::Criterion::default()
        .configure_from_args()
        .final_summary();
}
