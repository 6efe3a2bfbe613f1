//! The isometries of a symmetry group: turns about the z axis followed by coordinate
//! reflections.
//!
//! An [`Isometry`] is `g = S · R_θ` with `R_θ` the turn by `θ = 2π k / N` about the z axis,
//!
//! ```text
//! R_θ (x, y, z) = (x cos θ − y sin θ,  x sin θ + y cos θ,  z),
//! ```
//!
//! and `S` a diagonal matrix of signs (the mirrors across `x = 0`, `y = 0`, `z = 0` it
//! combines). Every rotational primitive turns about the z axis, so the groups the sculpting
//! keeps — any set of the three mirrors, `N`-fold radial symmetry about z, and both — are made
//! of these. Conjugating a turn by a reflection of one of x, y reverses it
//! (`S R_θ S = R_−θ`), so the inverse is `g⁻¹ = R_−θ S = S R_{∓θ}`, and the set
//! `{S R_θ}` is closed under products.
//!
//! The signs are applied exactly (a negation); a turn by a multiple of a quarter is exact too
//! (`(x, y) ↦ (−y, x)`); other turns round (≈ 10⁻¹⁶ relative), which is why a group with
//! such turns keeps the model invariant to 10⁻¹² rather than bit for bit.

use glam::{DMat3, DVec3};

use crate::surface::bounds::Aabb;

/// `S · R_θ`: a turn by `θ = 2π turn / of` about the z axis, then the coordinate signs
/// `flip` (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Isometry {
    turn: u32,
    of: u32,
    flip: [bool; 3],
}

impl Isometry {
    /// The identity.
    pub const IDENTITY: Isometry = Isometry {
        turn: 0,
        of: 1,
        flip: [false; 3],
    };

    /// The turn by `2π turn / of` about the z axis followed by negating the coordinates
    /// marked in `flip` (`of` of 0 is taken as 1).
    #[must_use]
    pub fn new(turn: u32, of: u32, flip: [bool; 3]) -> Self {
        let of = of.max(1);
        Self {
            turn: turn % of,
            of,
            flip,
        }
    }

    /// The mirror negating coordinate `axis` (0, 1, 2).
    #[must_use]
    pub fn reflection(axis: usize) -> Self {
        let mut flip = [false; 3];
        flip[axis.min(2)] = true;
        Self::new(0, 1, flip)
    }

    /// True for the identity.
    #[must_use]
    pub fn is_identity(&self) -> bool {
        self.turn == 0 && self.flip == [false; 3]
    }

    /// True when the isometry turns (not only reflects).
    #[must_use]
    pub fn turns(&self) -> bool {
        self.turn != 0
    }

    /// The coordinates negated after the turn.
    #[must_use]
    pub fn flips(&self) -> [bool; 3] {
        self.flip
    }

    /// `(turn, of)`: the turn is by `2π turn / of`.
    #[must_use]
    pub fn turn(&self) -> (u32, u32) {
        (self.turn, self.of)
    }

    /// True when the isometry reverses the sense of turning about z (exactly one of x, y
    /// negated).
    #[must_use]
    pub fn reverses_turning(&self) -> bool {
        self.flip[0] != self.flip[1]
    }

    fn rotate(&self, v: DVec3) -> DVec3 {
        if self.turn == 0 {
            return v;
        }
        let (turn, of) = (u64::from(self.turn), u64::from(self.of));
        if (4 * turn).is_multiple_of(of) {
            return match (4 * turn / of) % 4 {
                1 => DVec3::new(-v.y, v.x, v.z),
                2 => DVec3::new(-v.x, -v.y, v.z),
                3 => DVec3::new(v.y, -v.x, v.z),
                _ => v,
            };
        }
        let (s, c) = (std::f64::consts::TAU * turn as f64 / of as f64).sin_cos();
        DVec3::new(v.x * c - v.y * s, v.x * s + v.y * c, v.z)
    }

    /// `g v`.
    #[inline]
    #[must_use]
    pub fn apply(&self, v: DVec3) -> DVec3 {
        let mut a = self.rotate(v).to_array();
        for (x, f) in a.iter_mut().zip(self.flip) {
            if f {
                *x = -*x;
            }
        }
        DVec3::from_array(a)
    }

    /// A box holding the image of `b` (exact for reflections and quarter turns; the box of
    /// the turned corners otherwise).
    #[must_use]
    pub fn apply_box(&self, b: &Aabb) -> Aabb {
        let (lo, hi) = (b.min, b.max);
        let mut min = DVec3::splat(f64::INFINITY);
        let mut max = DVec3::splat(f64::NEG_INFINITY);
        for k in 0..8 {
            let c = DVec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            let g = self.apply(c);
            min = min.min(g);
            max = max.max(g);
        }
        Aabb { min, max }
    }

    /// `g⁻¹` (see the module docs).
    #[must_use]
    pub fn inverse(&self) -> Isometry {
        let back = if self.reverses_turning() {
            self.turn
        } else {
            (self.of - self.turn) % self.of
        };
        Isometry::new(back, self.of, self.flip)
    }

    /// `g h` (apply `h`, then `g`), with both turns over a common denominator.
    #[must_use]
    pub fn then_after(&self, h: &Isometry) -> Isometry {
        // S_g R_a S_h R_b = S_g S_h R_{±a + b}.
        let of = lcm(self.of, h.of);
        let a = u64::from(self.turn) * u64::from(of / self.of);
        let b = u64::from(h.turn) * u64::from(of / h.of);
        let of64 = u64::from(of);
        let a = if h.reverses_turning() {
            (of64 - a % of64) % of64
        } else {
            a
        };
        let turn = ((a + b) % of64) as u32;
        let flip = std::array::from_fn(|k| self.flip[k] != h.flip[k]);
        Isometry::new(turn, of, flip)
    }

    /// The matrix of `g`.
    #[must_use]
    pub fn matrix(&self) -> DMat3 {
        DMat3::from_cols(
            self.apply(DVec3::X),
            self.apply(DVec3::Y),
            self.apply(DVec3::Z),
        )
    }
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 { a.max(1) } else { gcd(b, a % b) }
}

fn lcm(a: u32, b: u32) -> u32 {
    a / gcd(a, b) * b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_and_inverses_act_as_the_matrices_do() {
        let v = DVec3::new(0.3, -1.7, 0.9);
        let gs = [
            Isometry::new(1, 8, [false; 3]),
            Isometry::new(3, 8, [true, false, false]),
            Isometry::new(2, 6, [false, true, true]),
            Isometry::new(1, 4, [true, true, false]),
            Isometry::reflection(2),
        ];
        for g in &gs {
            let back = g.inverse().apply(g.apply(v));
            assert!((back - v).length() < 1e-14, "{g:?}");
            for h in &gs {
                let gh = g.then_after(h);
                let want = g.apply(h.apply(v));
                assert!((gh.apply(v) - want).length() < 1e-14, "{g:?} {h:?}");
                assert!((gh.matrix() * v - want).length() < 1e-14);
            }
        }
        assert!(g_quarter_is_exact());
    }

    fn g_quarter_is_exact() -> bool {
        let v = DVec3::new(0.1, 0.7, -0.3);
        Isometry::new(2, 8, [false; 3]).apply(v) == DVec3::new(-0.7, 0.1, -0.3)
    }
}
