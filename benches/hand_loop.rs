#![forbid(unsafe_code)]
//! Device sample -> regulated surface, per frame (criterion): the gestures of `nendo bench
//! input` fed to the hand loop on a 1 600-patch sphere (40 x 40, radius 3). One iteration
//! replays a whole gesture on a fresh copy of the sphere; the per-frame figures are in the
//! `nendo bench input` table. Then the shipped pot (`devices/traces/tube-pot.trace`, 3 232
//! frames on the 128-patch tube) with the index alone, its scene's finger, and with every
//! finger, the glove's default: the curled fingers never enter the clay, so the two take about
//! the same time (issue 25: every finger took 58 s for the index's 0.3 before the contact
//! rule; `tests/it/hand_side.rs` checks the work counters).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use nendo::hand::{Digit, FingerModel, Fingers, Hand, HandOptions, HandSession};
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

    let pot = nendo_devices::Trace::read(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/devices/traces/tube-pot.trace"
    )))
    .expect("the shipped pot trace");
    let tube = Primitive::Tube
        .build(&PrimitiveParams::default())
        .expect("the paper's tube");
    let hand = Hand::new(pot.header.hand, pot.header.world_from_tracker).expect("a hand");
    let mut group = c.benchmark_group("tube_pot");
    group.sample_size(10);
    group.throughput(Throughput::Elements(pot.frames.len() as u64));
    for (name, finger) in [
        ("index", FingerModel::digit(Digit::Index)),
        ("every_finger", FingerModel::Hand(Fingers::ALL)),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| {
                let options = HandOptions {
                    finger,
                    ..HandOptions::default()
                };
                let mut s = HandSession::new(tube.clone(), Regulation::default(), hand, options)
                    .expect("valid options");
                for f in &pot.frames {
                    std::hint::black_box(s.feed(f));
                }
            })
        });
    }
    group.finish();
}

criterion_group!(benches, hand_loop);
criterion_main!(benches);
