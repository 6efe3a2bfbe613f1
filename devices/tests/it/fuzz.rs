//! Property-based fuzzing of every decoder and of the trace reader (proptest, fixed seeds so
//! CI runs the same inputs every time). Case counts are stated per suite; the totals are in
//! `devices/README.md`.

use crate::support::{ALL, accounted, canonical, decode, random_record};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Cases per property; every case runs all ten decoder configurations, so each decoder sees
/// `CASES` inputs per property.
const CASES: u32 = 1000;

fn config(seed: u64) -> Config {
    Config {
        cases: CASES,
        rng_seed: RngSeed::Fixed(seed),
        failure_persistence: None,
        ..Config::default()
    }
}

/// Byte soup biased toward each protocol's header bytes, so that candidate records are common.
fn soup() -> impl Strategy<Value = Vec<u8>> {
    let byte = prop_oneof![
        6 => any::<u8>(),
        1 => prop::sample::select(vec![b'S', b'G', 0u8, 0x80, b'<', b'D', b'I', b'0', b'1', b' ', b'\r', b'\n', b'.', b'-']),
    ];
    prop::collection::vec(byte, 0..1500)
}

proptest! {
    #![proptest_config(config(0xF022_0001))]

    /// Arbitrary bytes in arbitrary pieces: no panic, every byte accounted for, and the result
    /// independent of how the stream was cut.
    #[test]
    fn arbitrary_bytes_never_panic_and_cutting_does_not_matter(
        bytes in soup(),
        chunks in prop::collection::vec(1usize..70, 1..20),
    ) {
        for p in ALL {
            let whole = decode(p, &bytes, &[]);
            let cut = decode(p, &bytes, &chunks);
            prop_assert!(accounted(&whole));
            prop_assert!(accounted(&cut));
            prop_assert_eq!(whole, cut);
        }
    }
}

proptest! {
    #![proptest_config(config(0xF022_0002))]

    /// A clean stream with garbage inserted at one point: every record before it decodes
    /// exactly, and every record from the second one after it on decodes exactly (the first may
    /// be swallowed by a false header inside the garbage).
    #[test]
    fn garbage_at_one_point_costs_at_most_one_record(
        seed in any::<u64>(),
        n in 2usize..25,
        at in 0usize..25,
        garbage in soup(),
    ) {
        for p in ALL {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let records: Vec<Vec<u8>> = (0..n).map(|_| random_record(p, &mut rng)).collect();
        let at = at.min(n);
        let mut stream = Vec::new();
        for (i, r) in records.iter().enumerate() {
            if i == at {
                stream.extend_from_slice(&garbage);
            }
            stream.extend_from_slice(r);
        }
        if at == n {
            stream.extend_from_slice(&garbage);
        }
        let want: Vec<String> = records.iter().map(|r| canonical(p, r)).collect();
        let got = decode(p, &stream, &[17]);
        prop_assert!(accounted(&got));
        prop_assert_eq!(&got.records[..at.min(got.records.len())], &want[..at]);
        let tail = &want[(at + 1).min(n)..];
        prop_assert!(got.records.ends_with(tail), "{:?}: tail lost", p);
        }
    }

    /// One mutation (bit flip, dropped byte, inserted byte, truncation) inside record `k`:
    /// records before it decode exactly, records from `k + 2` on decode exactly.
    #[test]
    fn one_damaged_record_costs_at_most_two(
        seed in any::<u64>(),
        n in 3usize..20,
        k in 0usize..20,
        kind in 0u8..4,
        where_ in any::<prop::sample::Index>(),
        byte in any::<u8>(),
    ) {
        for p in ALL {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let records: Vec<Vec<u8>> = (0..n).map(|_| random_record(p, &mut rng)).collect();
        let k = k % n;
        let mut damaged = records[k].clone();
        let i = where_.index(damaged.len());
        match kind {
            0 => damaged[i] ^= 1 << (byte % 8),
            1 => { damaged.remove(i); }
            2 => damaged.insert(i, byte),
            _ => damaged.truncate(i.max(1)),
        }
        let mut stream = Vec::new();
        for (j, r) in records.iter().enumerate() {
            stream.extend_from_slice(if j == k { &damaged } else { r });
        }
        let want: Vec<String> = records.iter().map(|r| canonical(p, r)).collect();
        let got = decode(p, &stream, &[5, 40]);
        prop_assert!(accounted(&got));
        prop_assert_eq!(&got.records[..k.min(got.records.len())], &want[..k]);
        prop_assert!(got.records.ends_with(&want[(k + 2).min(n)..]), "{:?}: tail lost", p);
        }
    }
}

proptest! {
    #![proptest_config(config(0xF022_0003))]

    /// The trace reader on arbitrary text: an error with a line number or a trace, never a
    /// panic.
    #[test]
    fn trace_reader_never_panics(lines in prop::collection::vec(
        prop_oneof![
            Just("nendo-hand-trace 1".to_string()),
            Just("nendo-hand-trace 2".to_string()),
            Just("scene {\"primitive\":{\"name\":\"plane\"}}".to_string()),
            Just("scene none".to_string()),
            Just("frames".to_string()),
            Just("joints index_mcp index_pip".to_string()),
            Just("end 1".to_string()),
            Just("0 ok* none 0 P 0.000000 0.000000 0.000000 1.000000 0.000000 0.000000 0.000000 J -".to_string()),
            "[ -~]{0,80}",
        ],
        0..12,
    )) {
        let text = lines.join("\n");
        let strict = nendo_devices::Trace::parse(&text);
        // The recovering reader: a whole trace reads the same, with no notice.
        let recovered = nendo_devices::Trace::parse_recovering(&text);
        match &recovered {
            Ok(r) if r.interrupted.is_none() => prop_assert_eq!(strict.as_ref().ok(), Some(&r.trace)),
            Ok(r) => {
                prop_assert!(strict.is_err());
                prop_assert_eq!(r.interrupted.as_ref().map(|i| i.frames), Some(r.trace.frames.len()));
            }
            Err(nendo_devices::DeviceError::TraceSyntax { line, .. }) => {
                prop_assert!(strict.is_err());
                prop_assert!(*line >= 1 && *line <= lines.len().max(1) + 1);
            }
            Err(e) => prop_assert!(false, "unexpected error kind: {e}"),
        }
        match strict {
            Ok(t) => prop_assert_eq!(nendo_devices::Trace::parse(&t.to_text()).ok(), Some(t)),
            Err(nendo_devices::DeviceError::TraceSyntax { line, .. }) => prop_assert!(line >= 1 && line <= lines.len().max(1) + 1),
            Err(e) => prop_assert!(false, "unexpected error kind: {e}"),
        }
    }
}
