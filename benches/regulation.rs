#![forbid(unsafe_code)]
//! Regulation: push + regulation on the 10 × 10 and 40 × 40 planes and the 8 × 4 sphere for
//! every method, and the whole-grid regulation of a sculpted sphere.
//!
//! `cargo bench --bench regulation` first prints the tables of `nendo bench regulation` (the
//! paper's experiment; random strokes at a tenth of the full 10 000), then runs the criterion
//! groups.

use criterion::{BenchmarkId, Criterion, criterion_group};
use nendo::surface::{Primitive, PrimitiveParams, Regulation, Sculptor, regulate_all};
use nendo_bench::regulation::Strokes;
use nendo_bench::sculpt::{cases, reversed};
use std::hint::black_box;

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("push+regulation");
    for case in cases()
        .into_iter()
        .filter(|c| c.name != "plane 20 x 20" && c.name != "sphere 32 x 16")
    {
        for regulation in Regulation::ALL {
            let mut grid = case.grid.clone();
            let mut sculptor = Sculptor::new();
            let fingers = [
                case.push.finger().unwrap(),
                reversed(&case.push).finger().unwrap(),
            ];
            let mut k = 0usize;
            g.bench_function(BenchmarkId::new(regulation.name(), &case.name), |b| {
                b.iter(|| {
                    k += 1;
                    let _ =
                        black_box(sculptor.apply_finger(&mut grid, &fingers[k % 2], regulation));
                })
            });
        }
    }
    g.finish();
    let mut g = c.benchmark_group("regulate all");
    let mut sculpted = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .unwrap();
    let mut strokes = Strokes::new(5);
    let mut sculptor = Sculptor::new();
    for _ in 0..200 {
        let op = strokes.next_op(&sculpted);
        let _ = sculptor.apply(&mut sculpted, &op, Regulation::None);
    }
    for regulation in [
        Regulation::C1,
        Regulation::G1,
        Regulation::Exact,
        Regulation::G2,
    ] {
        g.bench_function(BenchmarkId::new(regulation.name(), "sphere 8 x 4"), |b| {
            b.iter(|| {
                let mut grid = sculpted.clone();
                black_box(regulate_all(&mut grid, regulation).ok());
            })
        });
    }
    g.finish();
}

criterion_group!(group, benches);

fn main() {
    print!("{}", nendo_bench::regulation::report_text(0.1));
    group();
    Criterion::default().configure_from_args().final_summary();
}
