//! Editing curves with the mouse (SPEC §3; seeds 000 §3 and 004 §3(2)): grab anywhere, split,
//! tangent edit at a joint.
//!
//! - **Grab.** The point `C(u)` found by the closest-point query is moved by `ΔP` by moving
//!   the control point `k` with the largest basis weight `w = B_k(u)` (`k = round(u·n)` for a
//!   Bezier curve, as in seed 000) by `ΔP_k = ΔP / w`: since the other control points stay,
//!   `C(u)` moves by `w · ΔP_k = ΔP` exactly — the grabbed point follows the mouse. For a
//!   B-spline the weight is the B-spline basis function `N_k(u)`.
//! - **Split** at `u`: de Casteljau for a Bezier curve, knot insertion for a B-spline; both
//!   halves share the split point.
//! - **Tangent edit** at a joint `Q` (the last point of one curve equal to the first of the
//!   next): moving the neighbour `Q_L` of `Q` on one side moves the neighbour on the other side
//!   to `Q_R = Q + |Q_R − Q| · unit(Q − Q_L)`: the three stay collinear, the far side keeping
//!   its length, so the joint stays G1.

use glam::{DVec2, DVec3};

use crate::curve::{BSpline, Bezier, Curve, CurveError, Point, bernstein};

/// The control point a grab at parameter `u` moves, and its basis weight there.
#[must_use]
pub fn grab_handle<P: Point>(curve: &Curve<P>, u: f64) -> (usize, f64) {
    let weights = basis_weights(curve, u);
    weights
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((0, 1.0))
}

/// Every control point's basis weight at `u` (they sum to 1).
#[must_use]
pub fn basis_weights<P: Point>(curve: &Curve<P>, u: f64) -> Vec<f64> {
    match curve {
        Curve::Bezier(b) => {
            let n = b.degree();
            (0..=n)
                .map(|k| bernstein::basis(n, k, u.clamp(0.0, 1.0)))
                .collect()
        }
        Curve::BSpline(s) => {
            // N_k(u) is the curve whose control points are the unit vectors e_k, evaluated at u.
            let count = s.points().len();
            (0..count)
                .map(|k| {
                    let unit: Vec<DVec2> = (0..count)
                        .map(|i| if i == k { DVec2::X } else { DVec2::ZERO })
                        .collect();
                    BSpline::try_new(s.degree(), s.knots().to_vec(), unit)
                        .map_or(0.0, |e| e.eval(u).x)
                })
                .collect()
        }
    }
}

/// The curve with control point `k` replaced by `p`.
///
/// # Errors
/// [`CurveError`] when `k` is out of range or `p` not finite.
pub fn with_point<P: Point>(curve: &Curve<P>, k: usize, p: P) -> Result<Curve<P>, CurveError> {
    match curve {
        Curve::Bezier(b) => {
            let mut b = b.clone();
            b.set_point(k, p)?;
            Ok(Curve::Bezier(b))
        }
        Curve::BSpline(s) => {
            let mut points = s.points().to_vec();
            let len = points.len();
            *points
                .get_mut(k)
                .ok_or(CurveError::Index { index: k, len })? = p;
            Ok(Curve::BSpline(BSpline::try_new(
                s.degree(),
                s.knots().to_vec(),
                points,
            )?))
        }
    }
}

/// A grab in progress: the curve as it was when grabbed, and where.
#[derive(Debug, Clone, PartialEq)]
pub struct Grab<P> {
    /// The curve when the grab started.
    pub original: Curve<P>,
    /// The grabbed parameter.
    pub u: f64,
    /// The grabbed point `C(u)` at the start.
    pub start: P,
    /// The control point moved, and its weight at `u`.
    pub handle: (usize, f64),
}

impl<P: Point> Grab<P> {
    /// Grabs `curve` at `u`.
    #[must_use]
    pub fn new(curve: &Curve<P>, u: f64) -> Self {
        Self {
            original: curve.clone(),
            u,
            start: curve.eval(u),
            handle: grab_handle(curve, u),
        }
    }

    /// The curve with the grabbed point moved to `target`: `P_k += (target − C(u)) / B_k(u)`.
    ///
    /// # Errors
    /// [`CurveError`] if the result is not finite.
    pub fn moved_to(&self, target: P) -> Result<Curve<P>, CurveError> {
        let (k, w) = self.handle;
        let delta = (target - self.start) * (1.0 / w.max(1e-9));
        with_point(&self.original, k, self.original.points()[k] + delta)
    }
}

/// Splits a curve at `u` (strictly inside its domain) into two sharing the split point.
///
/// # Errors
/// [`CurveError::OutOfDomain`] at or beyond the ends.
pub fn split<P: Point>(curve: &Curve<P>, u: f64) -> Result<(Curve<P>, Curve<P>), CurveError> {
    let (a, b) = curve.domain();
    if !(u > a && u < b) {
        return Err(CurveError::OutOfDomain {
            t: u,
            range: format!("the open domain ({a}, {b})"),
        });
    }
    match curve {
        Curve::Bezier(c) => {
            let (l, r) = c.split(u);
            Ok((Curve::Bezier(l), Curve::Bezier(r)))
        }
        Curve::BSpline(s) => {
            let (l, r) = s.split(u)?;
            Ok((Curve::BSpline(l), Curve::BSpline(r)))
        }
    }
}

/// A joint between two curves: the last control point of `left` equals the first of `right`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Joint {
    /// The curve ending at the joint.
    pub left: usize,
    /// The curve starting at the joint.
    pub right: usize,
}

/// Every joint among `curves` (exact equality of end points, as a split leaves them), where
/// both sides have a neighbour point to edit.
#[must_use]
pub fn joints(curves: &[Curve<DVec3>]) -> Vec<Joint> {
    let mut out = Vec::new();
    for (left, a) in curves.iter().enumerate() {
        for (right, b) in curves.iter().enumerate() {
            let (pa, pb) = (a.points(), b.points());
            if left != right && pa.len() >= 2 && pb.len() >= 2 && pa[pa.len() - 1] == pb[0] {
                out.push(Joint { left, right });
            }
        }
    }
    out
}

/// The two neighbours of a joint, `(Q_L, Q, Q_R)`.
#[must_use]
pub fn joint_points(curves: &[Curve<DVec3>], joint: Joint) -> Option<(DVec3, DVec3, DVec3)> {
    let l = curves.get(joint.left)?.points();
    let r = curves.get(joint.right)?.points();
    (l.len() >= 2 && r.len() >= 2).then(|| (l[l.len() - 2], l[l.len() - 1], r[1]))
}

/// Moves one neighbour of a joint to `target` (`left_side`: the left curve's `Q_L`) and the
/// other onto the line through `Q`, keeping its distance (see the module docs). Returns the
/// two edited curves `(left, right)`.
///
/// # Errors
/// [`CurveError`] for a non-finite result or a joint whose curves are missing.
pub fn tangent_edit(
    curves: &[Curve<DVec3>],
    joint: Joint,
    left_side: bool,
    target: DVec3,
) -> Result<(Curve<DVec3>, Curve<DVec3>), CurveError> {
    let missing = CurveError::Index {
        index: joint.left.max(joint.right),
        len: curves.len(),
    };
    let (ql, q, qr) = joint_points(curves, joint).ok_or(missing)?;
    let (left, right) = (&curves[joint.left], &curves[joint.right]);
    let l_k = left.points().len() - 2;
    let (new_l, new_r) = if left_side {
        let dir = (q - target)
            .try_normalize()
            .unwrap_or((qr - q).normalize_or_zero());
        (target, q + dir * (qr - q).length())
    } else {
        let dir = (q - target)
            .try_normalize()
            .unwrap_or((ql - q).normalize_or_zero());
        (q + dir * (ql - q).length(), target)
    };
    Ok((with_point(left, l_k, new_l)?, with_point(right, 1, new_r)?))
}

/// A straight cubic Bezier from `a` to `b` (a new curve to edit).
#[must_use]
pub fn straight_cubic(a: DVec3, b: DVec3) -> Curve<DVec3> {
    Curve::Bezier(Bezier::new(vec![
        a,
        a.lerp(b, 1.0 / 3.0),
        a.lerp(b, 2.0 / 3.0),
        b,
    ]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_bezier() -> Curve<DVec3> {
        Curve::Bezier(Bezier::new(vec![
            DVec3::ZERO,
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(3.0, -1.0, 1.0),
            DVec3::new(4.0, 0.0, 0.0),
        ]))
    }

    fn sample_bspline() -> Curve<DVec3> {
        let points = (0..6)
            .map(|i| DVec3::new(i as f64, (i as f64 * 1.3).sin(), 0.2 * i as f64))
            .collect();
        Curve::BSpline(BSpline::clamped_uniform(3, points).expect("valid B-spline"))
    }

    #[test]
    fn the_grabbed_point_follows_the_target_exactly() {
        for curve in [sample_bezier(), sample_bspline()] {
            let (a, b) = curve.domain();
            for s in [0.0, 0.13, 0.5, 0.77, 1.0] {
                let u = a + s * (b - a);
                let grab = Grab::new(&curve, u);
                let target = grab.start + DVec3::new(0.3, -0.7, 1.1);
                let moved = grab.moved_to(target).expect("finite");
                assert!((moved.eval(u) - target).length() < 1e-12, "u = {u}");
            }
        }
    }

    #[test]
    fn basis_weights_sum_to_one() {
        for curve in [sample_bezier(), sample_bspline()] {
            let (a, b) = curve.domain();
            for s in [0.0, 0.3, 0.61, 1.0] {
                let w: f64 = basis_weights(&curve, a + s * (b - a)).iter().sum();
                assert!((w - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn split_halves_meet_and_trace_the_curve() {
        for curve in [sample_bezier(), sample_bspline()] {
            let (a, b) = curve.domain();
            let u = a + 0.4 * (b - a);
            let (l, r) = split(&curve, u).expect("inside");
            assert_eq!(l.points().last(), r.points().first());
            assert!((l.eval(l.domain().1) - curve.eval(u)).length() < 1e-12);
            assert!(split(&curve, a).is_err());
        }
    }

    #[test]
    fn tangent_edit_keeps_the_joint_collinear() {
        let (l, r) = split(&sample_bezier(), 0.5).expect("inside");
        let curves = vec![l, r];
        let joint = joints(&curves)[0];
        assert_eq!(joint, Joint { left: 0, right: 1 });
        let (_, q, qr) = joint_points(&curves, joint).expect("joint");
        let (l2, r2) =
            tangent_edit(&curves, joint, true, q + DVec3::new(-0.5, 0.9, 0.3)).expect("edit");
        let edited = vec![l2, r2];
        let (ql2, q2, qr2) = joint_points(&edited, joint).expect("joint");
        assert_eq!(q2, q);
        assert!((qr2 - q2).length() - (qr - q).length() < 1e-12);
        assert!(
            (q2 - ql2)
                .normalize()
                .cross((qr2 - q2).normalize())
                .length()
                < 1e-12
        );
    }
}
