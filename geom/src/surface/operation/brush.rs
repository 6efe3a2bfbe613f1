//! Brushes: the falloff profile a pressing finger moves the clay by, and its strength.
//!
//! Every pressing operation (push, pull, draw a line) moves a surface sample at distance `r`
//! from its finger ([`super::shape_fn`]) by `w(t) · M`, `t = r²/r_f²`, `M = s · depth · d̂`,
//! `s` the brush **strength** (a fraction of the depth, `0 < s ≤ 1`) and `w` the brush's
//! **falloff**, zero for `t ≥ 1`:
//!
//! ```text
//! finger  w(t) = 1 − t                         the paper's paraboloid (P2 §5), C0 at the rim
//! soft    w(t) = (1 − t)³                      a C2 polynomial bump: w, w′, w″ vanish at r = r_f
//! flat    w = 1                  for ρ ≤ ½,    ρ = r / r_f = √t,
//!         w = 1 − S(2ρ − 1)      for ½ < ρ < 1,  S(x) = x³ (10 − 15x + 6x²)
//! ```
//!
//! The flat brush is a plateau of full depth over half the radius with a C2 rim (`S` is the
//! quintic smoothstep: `S(0) = 0`, `S(1) = 1`, `S′ = S″ = 0` at both ends). The finger brush
//! of strength 1 is exactly the operation without a brush (bit for bit).

use super::shape_fn::Op;
use crate::surface::error::SurfaceError;

impl Op {
    /// The same operation pressing `s` times as deep (push, pull, drag; others unchanged).
    pub(crate) fn scaled(&self, s: f64) -> Op {
        let mut op = self.clone();
        if let Op::Push { depth, .. }
        | Op::PushNormal { depth, .. }
        | Op::Drag { depth, .. }
        | Op::Groove { depth, .. } = &mut op
        {
            *depth *= s;
        }
        op
    }
}

/// The profile of a brush (see the module docs for the formulas).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum Falloff {
    /// `w = 1 − r²/r_f²`: the paper's finger (the default).
    #[default]
    Finger,
    /// `w = (1 − r²/r_f²)³`: a soft C2 bump.
    Soft,
    /// Full depth to half the radius, a C2 smoothstep rim beyond.
    Flat,
}

impl Falloff {
    /// Every falloff, in panel order.
    pub const ALL: [Falloff; 3] = [Falloff::Finger, Falloff::Soft, Falloff::Flat];

    /// The weight `w(t)` at `t = r²/r_f²` (zero for `t ≥ 1`, one at `t = 0`).
    #[inline]
    #[must_use]
    pub fn weight(self, t: f64) -> f64 {
        if t.is_nan() || t >= 1.0 {
            return 0.0;
        }
        match self {
            Falloff::Finger => 1.0 - t,
            Falloff::Soft => {
                let u = 1.0 - t;
                u * u * u
            }
            Falloff::Flat => {
                let rho = t.max(0.0).sqrt();
                if rho <= 0.5 {
                    1.0
                } else {
                    let x = 2.0 * rho - 1.0;
                    1.0 - x * x * x * (10.0 - 15.0 * x + 6.0 * x * x)
                }
            }
        }
    }

    /// The name in operation files and the settings file.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Falloff::Finger => "finger",
            Falloff::Soft => "soft",
            Falloff::Flat => "flat",
        }
    }

    /// The falloff called `name` (see [`Falloff::name`]).
    #[must_use]
    pub fn from_name(name: &str) -> Option<Falloff> {
        Falloff::ALL.into_iter().find(|f| f.name() == name)
    }
}

/// A brush: a falloff and a strength, the fraction of the depth it presses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Brush {
    /// The profile.
    pub falloff: Falloff,
    /// The fraction of the depth pressed, `0 < strength ≤ 1`.
    pub strength: f64,
}

impl Default for Brush {
    fn default() -> Self {
        Brush {
            falloff: Falloff::Finger,
            strength: 1.0,
        }
    }
}

impl Brush {
    /// Checks `0 < strength ≤ 1`.
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] for a strength out of range or not finite.
    pub fn validate(&self) -> Result<(), SurfaceError> {
        if self.strength.is_finite() && self.strength > 0.0 && self.strength <= 1.0 {
            Ok(())
        } else {
            Err(SurfaceError::BadOp(
                "brush strength must be a number with 0 < strength <= 1".to_string(),
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_falloff_is_one_at_the_centre_and_zero_at_the_rim() {
        for f in Falloff::ALL {
            assert_eq!(f.weight(0.0), 1.0, "{f:?}");
            assert_eq!(f.weight(1.0), 0.0, "{f:?}");
            assert_eq!(f.weight(1.5), 0.0, "{f:?}");
            assert_eq!(f.weight(f64::NAN), 0.0, "{f:?}");
            assert_eq!(Falloff::from_name(f.name()), Some(f));
            // Non-increasing in t.
            let mut last = 1.0;
            for k in 0..=1000 {
                let w = f.weight(k as f64 / 1000.0);
                assert!(w <= last + 1e-15, "{f:?} at {k}");
                last = w;
            }
        }
    }

    #[test]
    fn soft_and_flat_are_smooth_at_their_joins() {
        // Slopes in ρ near the rim (and the flat's plateau edge) vanish.
        let slope = |f: Falloff, rho: f64| {
            let h = 1e-6;
            (f.weight((rho + h) * (rho + h)) - f.weight((rho - h) * (rho - h))) / (2.0 * h)
        };
        // Both vanish quadratically: 1e-4 from a join the slope is about 60 · (2e-4)² = 2.4e-6
        // for the flat rim's quintic and 6 · (2e-4)² = 2.4e-7 for the soft one.
        assert!(slope(Falloff::Soft, 1.0 - 1e-4).abs() < 1e-5);
        assert!(slope(Falloff::Flat, 1.0 - 1e-4).abs() < 1e-5);
        assert!(slope(Falloff::Flat, 0.5 + 1e-4).abs() < 1e-5);
        assert!(slope(Falloff::Finger, 1.0 - 1e-4) < -1.9);
        assert_eq!(Falloff::Flat.weight(0.2), 1.0);
        assert!((Falloff::Flat.weight(0.5625) - 0.5).abs() < 1e-12);
    }
}
