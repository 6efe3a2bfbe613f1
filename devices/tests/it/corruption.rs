//! Corrupted streams with fixed seeds: bit flips, dropped and inserted bytes, garbage bursts and
//! truncated records. Every decoder must recover, count what it threw away, and never panic.

use crate::support::{ALL, Proto, accounted, canonical, decode, random_record};
use rand::{Rng, RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[derive(Debug, Default)]
struct Outcome {
    records: usize,
    corrupted: usize,
    intact_recovered: usize,
    intact: usize,
    fakes: usize,
    rejected: u64,
    skipped: u64,
}

/// Builds a stream of `n` records with about one in eight corrupted or preceded by garbage, and
/// decodes it pushed in random pieces.
fn corrupt_and_decode(p: Proto, seed: u64, n: usize) -> Outcome {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut stream = Vec::new();
    let mut intact = Vec::new();
    let mut all_canonical = Vec::new();
    let mut corrupted = 0;
    for _ in 0..n {
        let mut rec = random_record(p, &mut rng);
        let clean = canonical(p, &rec);
        all_canonical.push(clean.clone());
        let mut touched = true;
        match rng.gen_range(0..48) {
            0..=3 => {
                let i = rng.gen_range(0..rec.len());
                rec[i] ^= 1 << rng.gen_range(0..8);
            }
            4 => {
                rec.remove(rng.gen_range(0..rec.len()));
            }
            5 => {
                let at = rng.gen_range(0..=rec.len());
                rec.insert(at, rng.r#gen());
            }
            6 => {
                rec.truncate(rng.gen_range(1..rec.len()));
            }
            7 => {
                let mut burst = vec![0u8; rng.gen_range(1..64)];
                rng.fill_bytes(&mut burst);
                stream.extend_from_slice(&burst);
                touched = false; // the record itself is whole
            }
            _ => touched = false,
        }
        if touched {
            corrupted += 1;
        } else {
            intact.push(clean);
        }
        stream.extend_from_slice(&rec);
    }
    let chunks: Vec<usize> = (0..97).map(|_| rng.gen_range(1..80)).collect();
    let d = decode(p, &stream, &chunks);
    assert!(accounted(&d), "{p:?}: {d:?}");
    // Intact records found in order (a greedy subsequence match).
    let mut pos = 0;
    let mut intact_recovered = 0;
    for want in &intact {
        // Look a little ahead only, so one miss cannot swallow the rest of the match.
        let window = &d.records[pos..(pos + 8).min(d.records.len())];
        if let Some(k) = window.iter().position(|got| got == want) {
            pos += k + 1;
            intact_recovered += 1;
        }
    }
    let fakes = d
        .records
        .iter()
        .filter(|r| !all_canonical.contains(r))
        .count();
    Outcome {
        records: n,
        corrupted,
        intact_recovered,
        intact: intact.len(),
        fakes,
        rejected: d.stats.rejected,
        skipped: d.stats.skipped_bytes,
    }
}

#[test]
fn every_decoder_recovers_from_corruption() {
    let mut report = String::new();
    for (i, p) in ALL.into_iter().enumerate() {
        let o = corrupt_and_decode(p, 0x5EED_0000 + i as u64, 4000);
        report.push_str(&format!(
            "{p:?}: {} records, {} corrupted, {}/{} intact recovered, {} fake, {} rejected, {} bytes skipped\n",
            o.records, o.corrupted, o.intact_recovered, o.intact, o.fakes, o.rejected, o.skipped
        ));
        assert!(o.corrupted > 300, "{p:?}: the test must corrupt plenty");
        assert!(o.skipped > 0);
        // Resynchronisation within one record: a corruption costs at most the record after it
        // (when a false header inside the damage happens to pass every check).
        let lost = o.intact - o.intact_recovered;
        assert!(
            lost * 50 <= o.corrupted,
            "{p:?}: lost {lost} intact records for {} corruptions",
            o.corrupted
        );
        // Fakes: records that decode but were never sent. Only the Data Glove 5 has a checksum;
        // in every other format a flipped data bit yields another valid value, undetectable by
        // design (the value range checks still keep such values physical).
        if p == Proto::Glove5 {
            assert!(o.fakes * 10 <= o.corrupted, "{p:?}: {} fakes", o.fakes);
        }
    }
    println!("{report}");
}

#[test]
fn truncated_and_empty_inputs_leave_nothing_behind_but_pending_bytes() {
    for p in ALL {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let rec = random_record(p, &mut rng);
        for cut in 0..rec.len() {
            let d = decode(p, &rec[..cut], &[1]);
            assert!(d.records.is_empty(), "{p:?} cut at {cut}");
            assert!(accounted(&d));
        }
        // The whole record after a truncated copy of itself: the truncated copy is dropped and
        // the whole record decodes.
        let mut stream = rec[..rec.len() / 2].to_vec();
        stream.extend_from_slice(&rec);
        let d = decode(p, &stream, &[3]);
        assert_eq!(d.records.last(), Some(&canonical(p, &rec)), "{p:?}");
    }
}

#[test]
fn pure_garbage_never_panics_and_is_all_accounted_for() {
    let mut rng = ChaCha8Rng::seed_from_u64(0xBAD);
    for p in ALL {
        let mut garbage = vec![0u8; 200_000];
        rng.fill_bytes(&mut garbage);
        let d = decode(p, &garbage, &[1, 13, 255, 4096]);
        assert!(accounted(&d));
        assert!(d.stats.skipped_bytes > 150_000, "{p:?}: {:?}", d.stats);
    }
}
