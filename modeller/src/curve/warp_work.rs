//! The cap on the work of one curve warp: carrying `n` points by a warp of `k` curve pairs
//! costs `k × n` Beier–Neely weight evaluations ([`crate::curve::warp`]: every point is
//! projected onto every original curve), so the work grows as the product, without a bound
//! from either factor alone. Every warp nendo runs on input it is given — the `warp` request
//! of `nendo curve --batch`, `nendo figure warp`, each warp of `nendo morph` and of the
//! sections of `nendo figure shape` — is checked by [`check_warp_work`] before any point is
//! carried, and one over [`MAX_WARP_WORK`] is refused with its size and an estimate of its time.

/// Most `pairs × points` weight evaluations one warp may ask for: 10 000 000, a few seconds
/// on one core (1 000 pairs × 100 000 points took 24 s).
pub const MAX_WARP_WORK: u64 = 10_000_000;

/// Measured time per pair and point (1 000 pairs × 100 000 points took 24 s), for the estimate
/// a refused warp is given.
pub const WARP_SECONDS_PER_UNIT: f64 = 24.0 / 1e8;

/// A warp over [`MAX_WARP_WORK`], refused before any work.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error(
    "warp of {pairs} pairs x {points} points = {work} weight evaluations, about {seconds:.0} s of work: at most {MAX_WARP_WORK} per warp"
)]
pub struct WarpTooLarge {
    /// Curve pairs.
    pub pairs: u64,
    /// Points carried.
    pub points: u64,
    /// Their product (saturating).
    pub work: u64,
    /// The estimated time in seconds.
    pub seconds: f64,
}

/// Checks the work `pairs × points` of a warp against [`MAX_WARP_WORK`].
///
/// # Errors
/// [`WarpTooLarge`] when it is over the cap.
pub fn check_warp_work(pairs: u64, points: u64) -> Result<(), WarpTooLarge> {
    let work = pairs.saturating_mul(points);
    if work > MAX_WARP_WORK {
        return Err(WarpTooLarge {
            pairs,
            points,
            work,
            seconds: work as f64 * WARP_SECONDS_PER_UNIT,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cap_is_on_the_product_and_saturates() {
        assert!(check_warp_work(1000, 10_000).is_ok());
        assert!(check_warp_work(1, MAX_WARP_WORK).is_ok());
        let e = check_warp_work(1000, 10_001).expect_err("over");
        assert_eq!(e.work, 10_001_000);
        assert!(e.to_string().contains("10001000 weight evaluations"), "{e}");
        let e = check_warp_work(u64::MAX, 2).expect_err("saturated");
        assert_eq!(e.work, u64::MAX);
    }
}
