//! The coordinate spaces curves live in: glam's `DVec2` and `DVec3`, behind one small trait so
//! that the Bernstein and Bezier code is written once for both.

use glam::{DVec2, DVec3};
use std::fmt::Debug;
use std::ops::{Add, Mul, Neg, Sub};

/// A value that Bernstein forms can be built from: closed under addition, subtraction and
/// scaling by `f64`. Implemented for `f64` (Bezier *functions*) and for [`Point`]s (Bezier *curves*).
pub trait Coeff:
    Copy + Debug + PartialEq + Add<Output = Self> + Sub<Output = Self> + Mul<f64, Output = Self>
{
    /// The additive identity.
    const ZERO: Self;

    /// `self + (other - self) * t`, the step of de Casteljau's algorithm.
    #[inline]
    #[must_use]
    fn lerp_to(self, other: Self, t: f64) -> Self {
        self + (other - self) * t
    }

    /// True when every component is finite (no NaN, no infinity).
    fn is_finite_coeff(self) -> bool;
}

impl Coeff for f64 {
    const ZERO: Self = 0.0;
    #[inline]
    fn is_finite_coeff(self) -> bool {
        self.is_finite()
    }
}

/// A point (or vector) of a Euclidean space of dimension [`Point::DIM`].
pub trait Point: Coeff + Neg<Output = Self> + Send + Sync + 'static {
    /// Number of coordinates (2 or 3).
    const DIM: usize;

    /// Euclidean inner product.
    fn dot(self, other: Self) -> f64;

    /// Coordinate `i` (`i < DIM`).
    fn coord(self, i: usize) -> f64;

    /// Builds a point from exactly `DIM` coordinates; `None` for any other length.
    fn from_coords(c: &[f64]) -> Option<Self>;

    /// Component-wise minimum.
    #[must_use]
    fn min_by_coord(self, other: Self) -> Self;

    /// Component-wise maximum.
    #[must_use]
    fn max_by_coord(self, other: Self) -> Self;

    /// Squared distance from `self` to the axis-aligned box `[lo, hi]` (zero inside it): a
    /// lower bound for the squared distance to anything the box contains.
    fn box_distance_squared(self, lo: Self, hi: Self) -> f64;

    /// Squared length.
    #[inline]
    fn length_squared(self) -> f64 {
        self.dot(self)
    }

    /// Length.
    #[inline]
    fn length(self) -> f64 {
        self.dot(self).sqrt()
    }

    /// The coordinates as a vector (for serialisation).
    fn to_vec(self) -> Vec<f64> {
        (0..Self::DIM).map(|i| self.coord(i)).collect()
    }
}

impl Coeff for DVec2 {
    const ZERO: Self = DVec2::ZERO;
    #[inline]
    fn is_finite_coeff(self) -> bool {
        self.is_finite()
    }
}

impl Point for DVec2 {
    const DIM: usize = 2;
    #[inline]
    fn box_distance_squared(self, lo: Self, hi: Self) -> f64 {
        let d = (lo - self).max(self - hi).max(DVec2::ZERO);
        d.dot(d)
    }
    #[inline]
    fn dot(self, other: Self) -> f64 {
        DVec2::dot(self, other)
    }
    #[inline]
    fn coord(self, i: usize) -> f64 {
        self[i]
    }
    fn from_coords(c: &[f64]) -> Option<Self> {
        match c {
            [x, y] => Some(DVec2::new(*x, *y)),
            _ => None,
        }
    }
    #[inline]
    fn min_by_coord(self, other: Self) -> Self {
        DVec2::new(
            if other.x < self.x { other.x } else { self.x },
            if other.y < self.y { other.y } else { self.y },
        )
    }
    #[inline]
    fn max_by_coord(self, other: Self) -> Self {
        DVec2::new(
            if other.x > self.x { other.x } else { self.x },
            if other.y > self.y { other.y } else { self.y },
        )
    }
}

impl Coeff for DVec3 {
    const ZERO: Self = DVec3::ZERO;
    #[inline]
    fn is_finite_coeff(self) -> bool {
        self.is_finite()
    }
}

impl Point for DVec3 {
    const DIM: usize = 3;
    #[inline]
    fn box_distance_squared(self, lo: Self, hi: Self) -> f64 {
        let d = (lo - self).max(self - hi).max(DVec3::ZERO);
        d.dot(d)
    }
    #[inline]
    fn dot(self, other: Self) -> f64 {
        DVec3::dot(self, other)
    }
    #[inline]
    fn coord(self, i: usize) -> f64 {
        self[i]
    }
    fn from_coords(c: &[f64]) -> Option<Self> {
        match c {
            [x, y, z] => Some(DVec3::new(*x, *y, *z)),
            _ => None,
        }
    }
    #[inline]
    fn min_by_coord(self, other: Self) -> Self {
        DVec3::new(
            if other.x < self.x { other.x } else { self.x },
            if other.y < self.y { other.y } else { self.y },
            if other.z < self.z { other.z } else { self.z },
        )
    }
    #[inline]
    fn max_by_coord(self, other: Self) -> Self {
        DVec3::new(
            if other.x > self.x { other.x } else { self.x },
            if other.y > self.y { other.y } else { self.y },
            if other.z > self.z { other.z } else { self.z },
        )
    }
}
