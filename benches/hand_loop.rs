#![forbid(unsafe_code)]
//! Device sample -> regulated surface, per frame (criterion): the gestures of `nendo bench
//! input` fed to the hand loop on a 1 600-patch sphere (40 x 40, radius 3). One iteration
//! replays a whole gesture on a fresh copy of the sphere; the per-frame figures are in the
//! `nendo bench input` table.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use nendo::hand::{Hand, HandOptions, HandSession};
use nendo::surface::{Primitive, PrimitiveParams, Regulation};

fn hand_loop(c: &mut Criterion) {
    let grid = Primitive::Sphere
        .build(&PrimitiveParams {
            patches: Some((40, 40)),
            radius: Some(3.0),
            ..PrimitiveParams::default()
        })
        .expect("a 40 x 40 sphere");
    let mut group = c.benchmark_group("hand_loop");
    group.sample_size(10);
    for (name, trace) in nendo_bench::input::gestures().expect("the fixed gestures") {
        let hand = Hand::new(trace.header.hand, trace.header.world_from_tracker).expect("a hand");
        group.throughput(Throughput::Elements(trace.frames.len() as u64));
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut s = HandSession::new(
                    grid.clone(),
                    Regulation::default(),
                    hand,
                    HandOptions::default(),
                )
                .expect("valid options");
                for f in &trace.frames {
                    std::hint::black_box(s.feed(f));
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, hand_loop);
criterion_main!(benches);
