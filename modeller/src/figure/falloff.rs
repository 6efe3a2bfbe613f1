//! Wyvill's sixth-degree density falloff ("soft objects"), the density of one metacircle or
//! metaball (P0 eq. (8), after Wyvill, McPheeters and Wyvill 1986).
//!
//! With `ρ = r / R` (distance to the centre over the effective radius):
//!
//! ```text
//! f(ρ) = 1 − 22/9 ρ² + 17/9 ρ⁴ − 4/9 ρ⁶   for ρ ≤ 1,      f(ρ) = 0   for ρ > 1
//! ```
//!
//! so `f(0) = 1`, `f(1) = 0`, `f'(1) = 0` (the density joins zero tangentially) and
//! `f(1/2) = 1/2`: a lone metacircle of centre density 1 has the circle of radius `R/2` as its
//! iso-curve at the threshold 0.5, as P0 says. The polynomial is even, so it is evaluated
//! in `s = ρ² = r² / R²` without a square root: `f = 1 + s (−22/9 + s (17/9 − 4/9 s))`.

use crate::curve::Point;

/// The default threshold `T` of the iso-curve `Σ q_i f_i = T` (P0 eq. (9)).
pub const DEFAULT_THRESHOLD: f64 = 0.5;

const A2: f64 = -22.0 / 9.0;
const A4: f64 = 17.0 / 9.0;
const A6: f64 = -4.0 / 9.0;

/// `f` at `s = r² / R²`: `1 − 22/9 s + 17/9 s² − 4/9 s³` for `s < 1`, else 0.
#[inline]
#[must_use]
pub fn density(s: f64) -> f64 {
    if s < 1.0 {
        1.0 + s * (A2 + s * (A4 + s * A6))
    } else {
        0.0
    }
}

/// `df/ds` at `s = r² / R²`: `−22/9 + 34/9 s − 12/9 s²` for `s < 1`, else 0 (continuous at
/// `s = 1`, where it is 0).
#[inline]
#[must_use]
pub fn density_ds(s: f64) -> f64 {
    if s < 1.0 {
        A2 + s * (2.0 * A4 + s * 3.0 * A6)
    } else {
        0.0
    }
}

/// `f` and `df/ds` together.
#[inline]
#[must_use]
pub fn density_and_ds(s: f64) -> (f64, f64) {
    if s < 1.0 {
        (
            1.0 + s * (A2 + s * (A4 + s * A6)),
            A2 + s * (2.0 * A4 + s * 3.0 * A6),
        )
    } else {
        (0.0, 0.0)
    }
}

/// Distance from `x` to the level set `F = t` of a density field, by Newton steps along the
/// gradient (`X ← X − (F − t) ∇F / |∇F|²`, each step at most `size / 20`); `None` when the
/// iteration does not settle on the level set (no density gradient near `x`). `field` gives
/// `(F, ∇F)`; the same iteration serves the 2D figures and the 3D shapes.
pub fn distance_to_level<P: Point>(
    field: impl Fn(P) -> (f64, P),
    t: f64,
    x: P,
    size: f64,
) -> Option<f64> {
    let max_step = (size / 20.0).max(1e-12);
    let mut q = x;
    for _ in 0..60 {
        let (f, g) = field(q);
        let g2 = g.length_squared();
        if g2 <= 1e-300 {
            return None;
        }
        let step = g * ((f - t) / g2);
        let len = step.length();
        q = q - if len > max_step {
            step * (max_step / len)
        } else {
            step
        };
        if len <= 1e-10 * size.max(1e-300) {
            return Some((q - x).length());
        }
    }
    let (f, g) = field(q);
    ((f - t).abs() <= 1e-9 * g.length().max(1e-300) * size).then(|| (q - x).length())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_polynomial_in_rho() {
        for k in 0..=100 {
            let rho = k as f64 / 100.0;
            let direct = -4.0 / 9.0 * rho.powi(6) + 17.0 / 9.0 * rho.powi(4)
                - 22.0 / 9.0 * rho.powi(2)
                + 1.0;
            assert!((density(rho * rho) - direct).abs() < 1e-14, "rho {rho}");
        }
    }

    #[test]
    fn boundary_values() {
        assert_eq!(density(0.0), 1.0);
        assert!(density(1.0).abs() < 1e-15);
        assert!(density_ds(1.0).abs() < 1e-15);
        assert_eq!(density(1.5), 0.0);
        // A lone metacircle's iso-curve at T = 0.5 is the circle of radius R/2.
        assert!((density(0.25) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn derivative_matches_finite_differences() {
        for k in 1..100 {
            let s = k as f64 / 100.0;
            let h = 1e-6;
            let fd = (density(s + h) - density(s - h)) / (2.0 * h);
            assert!((density_ds(s) - fd).abs() < 1e-8, "s {s}");
            assert_eq!(density_and_ds(s), (density(s), density_ds(s)));
        }
    }

    #[test]
    fn decreasing_on_the_support() {
        for k in 0..100 {
            let s = k as f64 / 100.0;
            assert!(density(s + 0.01) < density(s));
        }
    }
}
