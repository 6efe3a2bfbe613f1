#![forbid(unsafe_code)]
//! One push (alternating with its pull twin) on planes and spheres of growing size, with the
//! same finger: the cost should follow the touched area, not the patch count.
//!
//! `cargo bench --bench sculpt` first prints the table of `nendo bench sculpt` (all regulation
//! methods, with the 40 × 40 / 10 × 10 ratio), then runs the criterion group.

use criterion::{BenchmarkId, Criterion, criterion_group};
use nendo::surface::{Regulation, Sculptor};
use nendo_bench::sculpt::{cases, reversed};
use std::hint::black_box;

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("push");
    for case in cases() {
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
}

criterion_group!(group, benches);

fn main() {
    print!("{}", nendo_bench::sculpt::report(0.5));
    group();
    Criterion::default().configure_from_args().final_summary();
}
