#![forbid(unsafe_code)]
//! Decode throughput per device protocol (criterion). The same streams and decoders as the
//! table of `nendo_devices::decode_throughput` (behind `nendo bench input`).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use nendo_devices::throughput::{BenchProtocol, decode_stream, sample_stream};

fn decode(c: &mut Criterion) {
    let mut group = c.benchmark_group("input_decode");
    for protocol in BenchProtocol::ALL {
        let records = 5_000;
        let bytes = sample_stream(protocol, records);
        group.throughput(Throughput::Bytes(bytes.len() as u64));
        group.bench_function(protocol.name(), |b| {
            b.iter(|| {
                let n = decode_stream(protocol, std::hint::black_box(&bytes), 64);
                assert_eq!(n, records);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, decode);
criterion_main!(benches);
