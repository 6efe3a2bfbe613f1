//! The suites' one seeded generator: [`Seeded`], a ChaCha8 stream from a `u64` seed
//! (`rand_chacha`), the same numbers on every platform and in every run, so a suite measures
//! the same cases each time.

use nendo::curve::Point;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{RngCore, SeedableRng};

/// Uniform numbers, indices and points from a seed (see the module docs).
#[derive(Debug, Clone)]
pub struct Seeded(ChaCha8Rng);

impl Seeded {
    /// A generator from a seed.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        Self(ChaCha8Rng::seed_from_u64(seed))
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// Uniform in `[0, 1)`, with 53 random bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in `0..n` (`0` when `n` is `0`).
    pub fn index(&mut self, n: usize) -> usize {
        (self.unit() * n as f64) as usize % n.max(1)
    }

    /// A point with coordinates uniform in `[−s, s)`.
    pub fn point<P: Point>(&mut self, s: f64) -> P {
        let c: Vec<f64> = (0..P::DIM).map(|_| self.range(-s, s)).collect();
        P::from_coords(&c).unwrap_or(P::ZERO)
    }
}
