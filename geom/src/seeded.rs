//! The tests' one seeded generator: a ChaCha8 stream from a `u64` seed (`rand_chacha`), the
//! same numbers on every platform and in every run.

use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{RngCore, SeedableRng};

/// Uniform numbers in `[0, 1)` (53 random bits each) from `seed`.
pub(crate) fn unit(seed: u64) -> impl FnMut() -> f64 {
    let mut g = ChaCha8Rng::seed_from_u64(seed);
    move || (g.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}
