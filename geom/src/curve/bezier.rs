//! Bezier curves of any degree up to [`Bezier::MAX_DEGREE`] in 2D and 3D.
//!
//! `C(t) = Σ_{i=0..n} P_i B_i^n(t)`, `t ∈ [0,1]` (docs/design.md §3).

use super::bernstein;
use super::error::CurveError;
use super::point::Point;

/// Largest supported curve degree (see [`Bezier::MAX_DEGREE`]).
pub const MAX_DEGREE: usize = 20;

/// A Bezier curve: its control points `P_0 .. P_n` (degree `n = points − 1`).
///
/// ```
/// use glam::DVec2;
/// use nendo_geom::curve::Bezier;
/// let c = Bezier::try_new(vec![DVec2::ZERO, DVec2::new(1.0, 2.0), DVec2::new(2.0, 0.0)])?;
/// assert_eq!(c.degree(), 2);
/// assert_eq!(c.eval(0.5), DVec2::new(1.0, 1.0));
/// # Ok::<(), nendo_geom::curve::CurveError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Bezier<P> {
    points: Vec<P>,
}

impl<P: Point> Bezier<P> {
    /// Largest supported degree. The queries keep their working arrays on the stack, sized for
    /// products of two curves of this degree.
    pub const MAX_DEGREE: usize = MAX_DEGREE;

    /// A curve from its control points; errors on an empty list, a degree above
    /// [`Self::MAX_DEGREE`] or a non-finite coordinate. One point is a valid (degree-0) curve.
    pub fn try_new(points: Vec<P>) -> Result<Self, CurveError> {
        if points.is_empty() {
            return Err(CurveError::Empty);
        }
        if points.len() > Self::MAX_DEGREE + 1 {
            return Err(CurveError::DegreeTooHigh {
                degree: points.len() - 1,
                max: Self::MAX_DEGREE,
            });
        }
        if let Some(i) = points.iter().position(|p| !p.is_finite_coeff()) {
            return Err(CurveError::NotFinite {
                what: format!("control point {i}"),
            });
        }
        if let Some(i) = points.iter().position(|&p| too_large(p)) {
            return Err(CurveError::TooLarge {
                what: format!("control point {i}"),
            });
        }
        Ok(Self { points })
    }

    /// A curve from control points derived from a valid curve (a blossom, a subdivision):
    /// finite by construction, and within rounding of the source's magnitude, so not
    /// checked again (a check could only fail by an ulp at [`MAX_COORDINATE`] and would then
    /// have to panic).
    pub(crate) fn from_derived(points: Vec<P>) -> Self {
        debug_assert!(!points.is_empty() && points.len() <= Self::MAX_DEGREE + 1);
        Self { points }
    }

    /// A curve from its control points.
    ///
    /// # Panics
    /// Where [`Self::try_new`] would return an error.
    #[must_use]
    pub fn new(points: Vec<P>) -> Self {
        match Self::try_new(points) {
            Ok(c) => c,
            Err(e) => panic!("invalid Bezier curve: {e}"),
        }
    }

    /// The control points.
    #[inline]
    #[must_use]
    pub fn points(&self) -> &[P] {
        &self.points
    }

    /// The degree `n`.
    #[inline]
    #[must_use]
    pub fn degree(&self) -> usize {
        self.points.len() - 1
    }

    /// `C(t)` by de Casteljau's algorithm.
    #[inline]
    #[must_use]
    pub fn eval(&self, t: f64) -> P {
        bernstein::eval(&self.points, t)
    }

    /// The `k`-th derivative `C^(k)(t)`.
    #[must_use]
    pub fn eval_derivative(&self, t: f64, k: usize) -> P {
        if k > self.degree() {
            return P::ZERO;
        }
        bernstein::eval(&bernstein::derivative_k(&self.points, k), t)
    }

    /// The hodograph `C'(t) = n Σ (P_{i+1} − P_i) B_i^{n−1}(t)` as a curve of degree `n − 1`
    /// (the zero point for a degree-0 curve).
    #[must_use]
    pub fn hodograph(&self) -> Self {
        Self {
            points: bernstein::derivative(&self.points),
        }
    }

    /// Splits at `t ∈ [0,1]` into the curves on `[0,t]` and `[t,1]` (de Casteljau subdivision).
    #[must_use]
    pub fn split(&self, t: f64) -> (Self, Self) {
        let (l, r) = bernstein::subdivide(&self.points, t);
        (Self { points: l }, Self { points: r })
    }

    /// The piece on `[a,b]` (`0 ≤ a ≤ b ≤ 1`), reparameterised to `[0,1]`.
    #[must_use]
    pub fn restrict(&self, a: f64, b: f64) -> Self {
        Self {
            points: bernstein::restrict(&self.points, a, b),
        }
    }

    /// The same curve one degree higher (fails only above [`Self::MAX_DEGREE`]).
    pub fn elevate(&self) -> Result<Self, CurveError> {
        Self::try_new(bernstein::elevate(&self.points))
    }

    /// The same curve traversed backwards: `C_rev(t) = C(1 − t)`.
    #[must_use]
    pub fn reversed(&self) -> Self {
        let mut p = self.points.clone();
        p.reverse();
        Self { points: p }
    }

    /// Axis-aligned bounds of the control points (which contain the curve).
    #[must_use]
    pub fn control_bounds(&self) -> (P, P) {
        let mut lo = self.points[0];
        let mut hi = self.points[0];
        for &p in &self.points[1..] {
            lo = lo.min_by_coord(p);
            hi = hi.max_by_coord(p);
        }
        (lo, hi)
    }

    /// Replaces control point `k` (used by editing); errors when `k > degree` or `p` is not
    /// finite.
    pub fn set_point(&mut self, k: usize, p: P) -> Result<(), CurveError> {
        if k >= self.points.len() {
            return Err(CurveError::Index {
                index: k,
                len: self.points.len(),
            });
        }
        if !p.is_finite_coeff() {
            return Err(CurveError::NotFinite {
                what: format!("control point {k}"),
            });
        }
        self.points[k] = p;
        Ok(())
    }
}

/// Largest coordinate magnitude a curve accepts: half the largest double, so that the
/// difference of two coordinates (the step of de Casteljau's and de Boor's algorithms) never
/// overflows.
pub const MAX_COORDINATE: f64 = f64::MAX / 2.0;

/// Whether a point has a coordinate beyond [`MAX_COORDINATE`].
pub(crate) fn too_large<P: Point>(p: P) -> bool {
    (0..P::DIM).any(|i| p.coord(i).abs() > MAX_COORDINATE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn rejects_bad_input() {
        assert_eq!(Bezier::<DVec3>::try_new(vec![]), Err(CurveError::Empty));
        assert!(matches!(
            Bezier::try_new(vec![DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 0.0)]),
            Err(CurveError::NotFinite { .. })
        ));
        assert!(matches!(
            Bezier::try_new(vec![DVec3::ZERO; 22]),
            Err(CurveError::DegreeTooHigh { degree: 21, .. })
        ));
    }

    #[test]
    fn elevation_keeps_shape() {
        let c = Bezier::new(vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(1.0, 1.0, 2.0),
            DVec3::Y,
        ]);
        let e = c.elevate().expect("degree 4 is supported");
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            assert!((c.eval(t) - e.eval(t)).length() < 1e-14);
        }
    }
}
