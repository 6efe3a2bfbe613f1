//! Where the virtual finger meets the surface.
//!
//! The fingertip is a capsule of radius `r_f` around the finger's axis: the segment that ends
//! at the fingertip point `E` and runs back along the finger (direction `−d̂`) for the loop's
//! reach `ℓ` ([`super::HandLoop::reach`]). Toward the tip that is the finger of the push shape
//! function (P2 §5.1; [`crate::surface::shape_fn`]): the samples within `r_f` of it are
//! the ones a push moves, by `(1 − r²/r_f²)·M`, so the capsule drawn is the reach of the
//! operation. The shape function's finger runs back without end; here it stops `ℓ` behind
//! the tip (see [`super::press`]), so that a finger inside a pot does not press the opposite
//! wall.
//!
//! Contact is decided on the capsule's axis. A [`Probe`] finds the first point where the
//! segment `O + t·d̂`, `t ∈ [0, t_max]`, meets the surface:
//!
//! 1. the patches whose control-point boxes the segment passes (the grid's box pyramid, so the
//!    cost follows the few patches near the finger, not the patch count; a Bezier patch lies
//!    in the box of its control points);
//! 2. those patches tessellated coarsely together (watertight across their shared edges) and
//!    picked by [`crate::mesh::pick`], which refines the nearest triangle hit on the exact
//!    patch by Newton's method on `S(u, v) = O + t·d̂`.
//!
//! The session then reads the penetration `p = (E − S)·d̂` off the hit `S`.

use glam::DVec3;

use crate::mesh::{PatchPoints, Ray, Tessellation, pick, tessellate};
use crate::surface::Grid;

/// The fingertip capsule: radius `radius` around the segment from `tip − length·axis` to
/// `tip`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fingertip {
    /// The fingertip point `E`: the end of the capsule's axis.
    pub tip: DVec3,
    /// The unit direction `d̂` the finger points in.
    pub axis: DVec3,
    /// The joint where the distal segment starts (the finger's own last joint, for drawing).
    pub base: DVec3,
    /// The capsule radius `r_f`, which is also the shape function's finger radius.
    pub radius: f64,
    /// How far back from the tip the capsule's axis runs (`ℓ`).
    pub length: f64,
    /// How far behind the tip, along the axis, the part's own body reaches: for a finger
    /// `max_k (E − p_k)·d̂` over its knuckle and two inner joints `p_k` (its length when
    /// straight, less when curled), for the palm the capsule's length. The axis crossing the
    /// surface farther back than this is only the straight capsule running on past a curled
    /// finger's joints, and does not press (rule 3 of [`super::session`]).
    pub body: f64,
}

impl Fingertip {
    /// Squared distance from `x` to the capsule's axis. Toward the tip it is the `r²` of the
    /// push shape function; `x` is inside the capsule when it is below `r_f²`.
    #[must_use]
    pub fn distance_sq(&self, x: DVec3) -> f64 {
        let w = x - self.tip;
        let behind = (-w.dot(self.axis)).clamp(0.0, self.length);
        (w + behind * self.axis).length_squared()
    }

    /// Whether `x` is inside the capsule.
    #[must_use]
    pub fn contains(&self, x: DVec3) -> bool {
        self.distance_sq(x) < self.radius * self.radius
    }
}

/// Where a line met the surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisHit {
    /// Parameter along the line (`origin + t·direction`, unit direction: a distance).
    pub t: f64,
    /// The surface point.
    pub point: DVec3,
    /// The patch (`iv * M + iu`).
    pub patch: usize,
    /// The patch parameters of the point.
    pub uv: (f64, f64),
    /// The unit normal `S_u × S_v` there.
    pub normal: DVec3,
}

/// The tessellation used to find contact candidates: coarse, since the hit is refined on the
/// exact patch; at least 4 segments per patch edge so that Newton starts close.
pub const CONTACT_TESSELLATION: Tessellation = Tessellation {
    tolerance: 1e-2,
    min_segments: 4,
    max_segments: 16,
};

/// Finds where lines meet a grid; keeps its buffers between queries.
#[derive(Debug, Clone, Default)]
pub struct Probe {
    candidates: Vec<usize>,
    patches: Vec<PatchPoints>,
}

impl Probe {
    /// A probe with empty buffers.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The first point of the segment `origin + t·direction`, `0 ≤ t ≤ t_max`, on the surface
    /// (see the module docs); `direction` need not be unit (it is normalised, and `t` is a
    /// distance). `None` when the segment misses or a value is not finite.
    pub fn first_crossing(
        &mut self,
        grid: &Grid,
        origin: DVec3,
        direction: DVec3,
        t_max: f64,
    ) -> Option<AxisHit> {
        let dir = direction.try_normalize()?;
        if !(origin.is_finite() && t_max.is_finite() && t_max >= 0.0) {
            return None;
        }
        // Pad the boxes by a hair so that a segment along a flat patch's plane still finds it.
        let pad = 1e-9 * grid.bounds().half_extents().max_element().max(1.0);
        self.candidates.clear();
        grid.patches_where(
            |b| b.inflated(pad).clip_line(origin, dir, 0.0, t_max).is_some(),
            &mut self.candidates,
        );
        if self.candidates.is_empty() {
            return None;
        }
        self.patches.clear();
        self.patches
            .extend(self.candidates.iter().map(|&p| grid.patch_at(p)));
        let mesh = tessellate(&self.patches, &CONTACT_TESSELLATION);
        let hit = pick(
            &self.patches,
            &mesh,
            &Ray {
                origin,
                direction: dir,
            },
        )?;
        (hit.t <= t_max && hit.point.is_finite()).then(|| AxisHit {
            t: hit.t,
            point: hit.point,
            patch: self.candidates[hit.patch],
            uv: (hit.u, hit.v),
            normal: hit.normal,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Primitive, PrimitiveParams};

    #[test]
    fn a_line_meets_the_sphere_where_algebra_says() {
        let grid = Primitive::Sphere
            .build(&PrimitiveParams::default())
            .unwrap();
        let mut probe = Probe::new();
        // Straight down onto the north pole from 5 above it.
        let hit = probe
            .first_crossing(&grid, DVec3::new(0.0, 0.0, 8.0), -DVec3::Z, 10.0)
            .unwrap();
        assert!((hit.t - 5.0).abs() < 1e-9, "{hit:?}");
        assert!((hit.point - DVec3::new(0.0, 0.0, 3.0)).length() < 1e-9);
        assert!(hit.normal.dot(DVec3::Z) > 0.999);
        // Too short a segment misses.
        assert!(
            probe
                .first_crossing(&grid, DVec3::new(0.0, 0.0, 8.0), -DVec3::Z, 4.9)
                .is_none()
        );
        // From inside, outward: the first crossing is the wall, at the sphere's radius (within
        // the primitive's arc error, 4.2e-6 of the radius at 45° arcs).
        for k in 0..12 {
            let phi = 0.37 + k as f64 * 0.5;
            let d = DVec3::new(phi.cos(), phi.sin(), 0.3 * (k as f64 - 6.0) / 6.0);
            let hit = probe.first_crossing(&grid, DVec3::ZERO, d, 10.0).unwrap();
            assert!((hit.t - 3.0).abs() < 3.0 * 1e-5, "{k}: {}", hit.t);
            assert!((hit.point.length() - 3.0).abs() < 3.0 * 1e-5);
        }
    }

    #[test]
    fn capsule_distance_is_the_shape_functions_near_the_tip() {
        let f = Fingertip {
            tip: DVec3::ZERO,
            axis: -DVec3::Z,
            base: DVec3::Z,
            radius: 1.0,
            length: 2.0,
            body: 2.0,
        };
        assert_eq!(f.distance_sq(DVec3::new(0.5, 0.0, 1.5)), 0.25);
        assert_eq!(f.distance_sq(DVec3::new(0.0, 0.0, -2.0)), 4.0);
        assert_eq!(f.distance_sq(DVec3::new(0.0, 0.0, 3.0)), 1.0);
        assert!(f.contains(DVec3::new(0.9, 0.0, 0.5)) && !f.contains(DVec3::new(0.0, 1.0, 0.0)));
        let push = crate::surface::Op::Push {
            at: DVec3::Z,
            dir: -DVec3::Z,
            depth: 1.0,
            radius: 1.0,
        };
        let finger = push.finger().unwrap();
        for x in [
            DVec3::new(0.3, 0.2, 0.5),
            DVec3::new(-0.7, 0.1, 1.9),
            DVec3::new(0.1, 0.0, -0.4),
        ] {
            assert!(
                (finger.distance_sq(x) - f.distance_sq(x)).abs() < 1e-15,
                "{x}"
            );
        }
    }
}
