//! The window's side of curve editing: finding joints among the model's curves and making new
//! curves. The edits themselves — grab anywhere, split, tangent edit (docs/design.md §5; seeds 000 §3 and
//! 004 §3(2)) — are [`crate::curve::edit`]'s; this module only adapts them to a list of curves.

use glam::DVec3;

use crate::curve::edit::{self, Follow, JointSide};
use crate::curve::{Bezier, Curve, CurveError};

/// A joint between two curves of a list: the last control point of `left` equals the first of
/// `right` (as a split leaves them).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CurveJoint {
    /// Index of the curve ending at the joint.
    pub left: usize,
    /// Index of the curve starting at the joint.
    pub right: usize,
}

/// Every joint among `curves`.
#[must_use]
pub fn joints(curves: &[Curve<DVec3>]) -> Vec<CurveJoint> {
    let mut out = Vec::new();
    for (left, a) in curves.iter().enumerate() {
        for (right, b) in curves.iter().enumerate() {
            if left != right && edit::joint(a, b).is_ok() {
                out.push(CurveJoint { left, right });
            }
        }
    }
    out
}

/// `(Q_L, Q, Q_R)` of a joint of `curves`.
#[must_use]
pub fn joint_points(curves: &[Curve<DVec3>], joint: CurveJoint) -> Option<(DVec3, DVec3, DVec3)> {
    edit::joint(curves.get(joint.left)?, curves.get(joint.right)?).ok()
}

/// Tangent edit of a joint of `curves`: the neighbour on the left side (`left_side`) or the
/// right moves to `target`, the other follows on the line through `Q`, keeping its length.
/// Returns the edited `(left, right)`.
///
/// # Errors
/// As [`edit::tangent_edit`]; [`CurveError::Index`] for a joint outside `curves`.
pub fn tangent_edit(
    curves: &[Curve<DVec3>],
    joint: CurveJoint,
    left_side: bool,
    target: DVec3,
) -> Result<(Curve<DVec3>, Curve<DVec3>), CurveError> {
    let missing = || CurveError::Index {
        index: joint.left.max(joint.right),
        len: curves.len(),
    };
    let left = curves.get(joint.left).ok_or_else(missing)?;
    let right = curves.get(joint.right).ok_or_else(missing)?;
    let side = if left_side {
        JointSide::Left
    } else {
        JointSide::Right
    };
    edit::tangent_edit(left, right, side, target, Follow::KeepLength)
}

/// A straight cubic Bezier from `a` to `b` (a new curve to bend).
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

    #[test]
    fn a_split_makes_a_joint_whose_tangent_edit_stays_collinear() {
        let c: Curve<DVec3> = Bezier::new(vec![
            DVec3::ZERO,
            DVec3::new(1.0, 2.0, 0.0),
            DVec3::new(3.0, -1.0, 1.0),
            DVec3::new(4.0, 0.0, 0.0),
        ])
        .into();
        let (l, r) = edit::split(&c, 0.5).expect("inside");
        let curves = vec![straight_cubic(DVec3::ZERO, DVec3::ONE), l, r];
        assert_eq!(joints(&curves), vec![CurveJoint { left: 1, right: 2 }]);
        let joint = joints(&curves)[0];
        let (_, q, qr) = joint_points(&curves, joint).expect("joint");
        let (l2, r2) =
            tangent_edit(&curves, joint, true, q + DVec3::new(-0.5, 0.9, 0.3)).expect("edit");
        let (ql2, q2, qr2) = edit::joint(&l2, &r2).expect("still a joint");
        assert_eq!(q2, q);
        assert!(((qr2 - q2).length() - (qr - q).length()).abs() < 1e-12);
        assert!(
            (q2 - ql2)
                .normalize()
                .cross((qr2 - q2).normalize())
                .length()
                < 1e-12
        );
    }
}
