//! Whether a mirrored Move would fold the clay at the mirror plane, so that the window can
//! say so while the Move is held (issue 27: a Move grabbed near `x = 0` with symmetry on tore
//! into a lens with a crease, without a word).
//!
//! With the plane `x_k = 0` (`k` its axis), the grabbed point `a` taken to `b` and its mirror
//! image `a'` to `b'` in the same operation, and the finger radius `r_f`: the two moves
//! share clay only when the finger's ball reaches the plane, `|a_k| < r_f`. Then the move
//! folds when
//!
//! - it carries the point across the plane, `a_k · b_k < 0` (the point and its image swap
//!   sides: the sheet between them must pass through itself); or
//! - it carries the point towards the plane, `|b_k| < |a_k| − ε`: the two sides are pushed
//!   into each other at the plane, where the surface must stay symmetric, and crease; or
//! - the point lies on the plane, `|a_k| ≤ ε`, and the move takes it off the plane,
//!   `|b_k| > ε`: a point on the plane is its own image and can only move within it.
//!
//! `ε = r_f / 20`, so that grabbing on the plane and pulling straight out (a nose) or moving
//! a little sideways by hand is not called a fold. Moves away from the plane are not: they
//! stretch the clay between the two sides.

use glam::DVec3;

use crate::surface::Plane;

/// True when moving `at` to `to` with finger radius `radius`, together with its mirror image
/// across `plane`, folds the clay at the plane (the rule of the module docs).
#[must_use]
pub fn mirrored_move_folds(at: DVec3, to: DVec3, radius: f64, plane: Plane) -> bool {
    let k = plane.axis();
    let (a, b) = (at[k], to[k]);
    let eps = radius / 20.0;
    if a.is_nan() || a.abs() >= radius {
        return false;
    }
    if a.abs() <= eps {
        return b.abs() > eps;
    }
    a * b < 0.0 || b.abs() < a.abs() - eps
}

/// The warning shown by the cursor.
pub const FOLD_WARNING: &str = "the mirrored halves would fold at the plane: grab farther from it, or on it and move within it";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folds_only_where_the_two_sides_meet() {
        let r = 1.0;
        let p = |x: f64, z: f64| DVec3::new(x, 0.5, z);
        // Far from the plane: never.
        assert!(!mirrored_move_folds(p(2.0, 0.0), p(-3.0, 1.0), r, Plane::X));
        // Near it, pulled straight out, or away from the plane: no fold.
        assert!(!mirrored_move_folds(p(0.5, 0.0), p(0.5, 1.0), r, Plane::X));
        assert!(!mirrored_move_folds(p(0.5, 0.0), p(0.8, 1.0), r, Plane::X));
        // On the plane, a nose pulled out within it: no fold; pushed sideways: a fold.
        assert!(!mirrored_move_folds(p(0.0, 0.0), p(0.02, 1.5), r, Plane::X));
        assert!(mirrored_move_folds(p(0.0, 0.0), p(0.4, 1.0), r, Plane::X));
        // Near it, towards it or across it: a fold.
        assert!(mirrored_move_folds(p(0.5, 0.0), p(0.2, 0.3), r, Plane::X));
        assert!(mirrored_move_folds(p(-0.5, 0.0), p(0.3, 0.0), r, Plane::X));
        // The plane's own axis counts, not x.
        assert!(!mirrored_move_folds(p(0.5, 0.0), p(0.2, 0.3), r, Plane::Y));
        assert!(mirrored_move_folds(
            DVec3::new(3.0, 0.3, 0.0),
            DVec3::new(3.0, -0.3, 0.0),
            r,
            Plane::Y
        ));
    }
}
