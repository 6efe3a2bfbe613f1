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
//!    patch by Newton's method on `S(u, v) = O + t·d̂`;
//! 3. the triangles lie up to the tessellation's error (10⁻² side) off the patches, so a
//!    segment that starts or ends that close to the surface may cross the triangles where the
//!    surface has no crossing, or miss them where it has one. The triangles are therefore
//!    searched from a slack (0.05 side) before the segment to one past it, every hit refined
//!    onto the exact patch, and a crossing behind the origin passed over; a hit that did not
//!    refine onto the line (the pick then returns the tessellation's point) is redone
//!    exactly: Newton with `t` free over every candidate
//!    patch, from the pick's parameters and a 3 × 3 grid of starts on each; the smallest
//!    solution with `0 ≤ t ≤ t_max` is the crossing, and none is none. So the probe decides
//!    on the exact surface whether a segment crosses it, however close to the surface the
//!    segment ends (the hand loop's rule 3 asks exactly that of a fingertip's path resting on
//!    the clay).
//!
//! The hand loop uses the probe on short segments: the tip's path between two frames, the
//! segments of a part's body, the normal line through a tip in the clay (rule 3 of
//! [`super::hand_loop`]); the mouse's view ray is searched along its axis.

use glam::DVec3;

use crate::mesh::{PatchPoints, Ray, Tessellation, eval_patch, patch_normal, pick, tessellate};
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
    /// The part's body, from the back of the hand to the tip: for a finger the hand's sensor
    /// (on the back of the hand), the finger's knuckle, its two inner joints and its tip; for
    /// the palm the sensor (repeated) and the centre of the palm's face. A part presses only
    /// where its tip entered the clay while this body was out of it (rule 3 of
    /// [`super::hand_loop`]): the side of the clay the tip came from is the hand's.
    pub body: [DVec3; 5],
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
        // The tessellation is searched from `SLACK` before the origin to `SLACK` past the end
        // (step 3 of the module docs): a segment ending, or starting, within the
        // tessellation's error of the surface crosses the triangles there or not at all.
        let start = origin - SLACK * dir;
        let span = t_max + 2.0 * SLACK;
        self.candidates.clear();
        grid.patches_where(
            |b| b.inflated(pad).clip_line(start, dir, 0.0, span).is_some(),
            &mut self.candidates,
        );
        if self.candidates.is_empty() {
            return None;
        }
        self.patches.clear();
        self.patches
            .extend(self.candidates.iter().map(|&p| grid.patch_at(p)));
        let mesh = tessellate(&self.patches, &CONTACT_TESSELLATION);
        // The nearest triangle hit from `start + from·d̂` on; a crossing found behind the
        // origin, or a triangle with no crossing of the patch near it, sends the search on
        // past it.
        let mut from = 0.0;
        for _ in 0..PASSES {
            let hit = pick(
                &self.patches,
                &mesh,
                &Ray {
                    origin: start + from * dir,
                    direction: dir,
                },
            )?;
            if !hit.point.is_finite() {
                return None;
            }
            let along = from + hit.t;
            if along > span {
                return None;
            }
            let scale = 1.0 + hit.point.abs().max_element() + origin.abs().max_element();
            let off_line = (start + along * dir - hit.point).length();
            let exact = if off_line <= ON_LINE * scale {
                Some((along - SLACK, hit.patch, (hit.u, hit.v)))
            } else {
                // The triangle's hit did not refine onto the line: the line meets the surface
                // within the tessellation's error of it, or not at all.
                self.exact_crossing(origin, dir, t_max, hit.patch, (hit.u, hit.v), scale)
            };
            let Some((t, patch, uv)) = exact.filter(|e| e.0 >= 0.0) else {
                // Behind the origin, or no crossing there: on to the next triangle.
                from = along + 1e-9 * (1.0 + span);
                continue;
            };
            if t > t_max {
                return None;
            }
            let p = &self.patches[patch];
            let point = eval_patch(p, uv.0, uv.1).0;
            return Some(AxisHit {
                t,
                point,
                patch: self.candidates[patch],
                uv,
                normal: patch_normal(p, uv.0, uv.1),
            });
        }
        None
    }

    /// Newton's method on `S(u, v) = O + t·d̂` over every candidate patch, from the
    /// tessellation's hit `(patch, uv)` and a 3 × 3 grid of starts on each patch, `t` free:
    /// the smallest `t ≥ 0` at which the line meets the exact surface, or `None` when every
    /// solution found lies behind the origin (or none is found).
    fn exact_crossing(
        &self,
        origin: DVec3,
        dir: DVec3,
        t_max: f64,
        patch: usize,
        uv: (f64, f64),
        scale: f64,
    ) -> Option<(f64, usize, (f64, f64))> {
        let mut best: Option<(f64, usize, (f64, f64))> = None;
        let mut consider = |k: usize, start: (f64, f64)| {
            if let Some((t, u, v)) = newton(&self.patches[k], origin, dir, start, scale)
                && t >= 0.0
                && t <= t_max
                && best.is_none_or(|(b, ..)| t < b)
            {
                best = Some((t, k, (u, v)));
            }
        };
        consider(patch, uv);
        for k in 0..self.patches.len() {
            for i in 0..3 {
                for j in 0..3 {
                    consider(k, (0.1 + 0.4 * f64::from(i), 0.1 + 0.4 * f64::from(j)));
                }
            }
        }
        best
    }
}

/// How many triangle hits the probe passes over (crossings behind the origin, triangles with no
/// crossing of the patch near them) before it gives up.
const PASSES: usize = 8;

/// How far off the line (relative to the coordinates' size) a hit may be and still be on it.
const ON_LINE: f64 = 1e-9;

/// How far before and past a segment the tessellation is searched (side): several times the
/// contact tessellation's tolerance ([`CONTACT_TESSELLATION`], 10⁻²), its triangles' largest
/// distance from the patches.
const SLACK: f64 = 0.05;

/// Newton's method on `S(u, v) − (O + t·d̂) = 0` from `start`, `t` free, `(u, v)` kept in the
/// patch (a step leaving it by more than a hair fails): `(t, u, v)` when it converges onto
/// the line.
fn newton(
    p: &PatchPoints,
    origin: DVec3,
    dir: DVec3,
    start: (f64, f64),
    scale: f64,
) -> Option<(f64, f64, f64)> {
    let (mut u, mut v) = start;
    let s0 = eval_patch(p, u, v).0;
    let mut t = (s0 - origin).dot(dir);
    for _ in 0..20 {
        let (s, su, sv) = eval_patch(p, u, v);
        let f = s - (origin + t * dir);
        let d = -dir;
        let det = su.dot(sv.cross(d));
        if det.is_nan() || det.abs() <= 1e-300 {
            return None;
        }
        let du = -f.dot(sv.cross(d)) / det;
        let dv = -su.dot(f.cross(d)) / det;
        let dt = -su.dot(sv.cross(f)) / det;
        u += du;
        v += dv;
        t += dt;
        if !(-1e-9..=1.0 + 1e-9).contains(&u) || !(-1e-9..=1.0 + 1e-9).contains(&v) {
            return None;
        }
        if du.abs().max(dv.abs()) < 1e-13 {
            let (u, v) = (u.clamp(0.0, 1.0), v.clamp(0.0, 1.0));
            let s = eval_patch(p, u, v).0;
            return ((origin + t * dir - s).length() <= ON_LINE * scale).then_some((t, u, v));
        }
    }
    None
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

    /// Segments ending (or starting) within 10⁻⁷ to 10⁻³ side of a surface point, well inside
    /// the tessellation's 10⁻² error, on the curved primitives: the probe says they cross the
    /// surface exactly when they pass the point, and where (the point evaluated on the patch
    /// is the reference).
    #[test]
    fn a_segment_crosses_the_surface_exactly_when_it_passes_it_however_close_it_ends() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2501);
        let mut probe = Probe::new();
        for primitive in [Primitive::Sphere, Primitive::Tube, Primitive::Torus] {
            let grid = primitive.build(&PrimitiveParams::default()).unwrap();
            for case in 0..200 {
                let patch = rng.gen_range(0..grid.patch_count());
                let (u, v) = (rng.gen_range(0.05..0.95), rng.gen_range(0.05..0.95));
                let points = grid.patch_at(patch);
                let at = eval_patch(&points, u, v).0;
                let n = patch_normal(&points, u, v);
                let d = loop {
                    let d = DVec3::new(
                        rng.gen_range(-1.0..1.0),
                        rng.gen_range(-1.0..1.0),
                        rng.gen_range(-1.0..1.0),
                    );
                    if let Some(d) = d.try_normalize()
                        && d.dot(n).abs() > 0.3
                    {
                        break d;
                    }
                };
                let before = rng.gen_range(0.001..0.1);
                let past = 10f64.powf(rng.gen_range(-7.0..-3.0));
                let label = format!("{primitive} case {case}");
                // Ending just past the point, and just short of it.
                let hit = probe.first_crossing(&grid, at - before * d, d, before + past);
                let hit = hit.unwrap_or_else(|| panic!("{label}: missed ({past} past)"));
                assert!(
                    (hit.t - before).abs() < 1e-9,
                    "{label}: {} vs {before}",
                    hit.t
                );
                assert!((hit.point - at).length() < 1e-9, "{label}");
                assert!(
                    probe
                        .first_crossing(&grid, at - before * d, d, before - past)
                        .is_none(),
                    "{label}: crossed {past} short of the surface"
                );
                // Starting just short of the point, and just past it.
                let hit = probe.first_crossing(&grid, at - past * d, d, before);
                assert!(
                    hit.is_some_and(|h| (h.t - past).abs() < 1e-9),
                    "{label}: {hit:?} from {past} before"
                );
                assert!(
                    probe
                        .first_crossing(&grid, at + past * d, d, before)
                        .is_none(),
                    "{label}: crossed from {past} past the surface"
                );
            }
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
            body: [
                DVec3::Z * 3.0,
                DVec3::Z * 2.0,
                DVec3::Z * 2.0,
                DVec3::Z,
                DVec3::ZERO,
            ],
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
