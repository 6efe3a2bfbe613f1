//! The closest pair between a ray and a curve (P4 §3(3); docs/design.md §4): screen picking of 3D
//! curves with the mouse.
//!
//! With the ray `O + s D` (`s ≥ 0`), `D̂ = D/|D|` and `p(t) = C(t) − O`:
//!
//! * `σ(t) = p(t)·D̂ = Σ (p_i·D̂) B_i^n(t)`, the position of the foot of the perpendicular along
//!   the ray's line;
//! * `h(t) = |p(t)|² − σ(t)²`, a Bernstein function of degree `2n` (product formula for both
//!   terms): the squared distance from `C(t)` to the line;
//! * the squared distance to the *ray* is `h(t)` where `σ(t) ≥ 0` and `|p(t)|²` (to the origin
//!   `O`) where `σ(t) < 0`.
//!
//! The roots of `σ` cut `[0,1]` into pieces of constant sign; on each the relevant function is
//! minimised by the clipping minimiser of [`super::closest`].

use super::bernstein;
use super::bezier::{Bezier, MAX_DEGREE};
use super::clip;
use super::closest::{ClipStats, distance_squared_coeffs, magnitude, minimize_below, rescale_for};
use super::point::Point;

/// The closest pair between a ray and a curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayNearest<P> {
    /// Curve parameter of the closest point (the B-spline's own parameter for B-splines).
    pub u: f64,
    /// The closest point on the curve.
    pub point: P,
    /// Ray parameter `s ≥ 0` of the closest point on the ray, `O + s·dir` (in units of the
    /// given `dir`, not normalised).
    pub ray_t: f64,
    /// The distance between the two points.
    pub distance: f64,
}

/// The closest pair between the ray `origin + s·dir` (`s ≥ 0`) and a Bezier curve. `None` when
/// `dir` is zero or any input is not finite.
///
/// ```
/// use glam::DVec3;
/// use nendo_geom::curve::{ray_closest_bezier, Bezier};
/// // An arch over the ray's path: its apex C(1/2) = (0, 1, 1) passes 1 from the ray.
/// let c = Bezier::new(vec![DVec3::new(-1.0, 1.0, 0.0), DVec3::new(0.0, 1.0, 2.0), DVec3::new(1.0, 1.0, 0.0)]);
/// let r = ray_closest_bezier(&c, DVec3::new(0.0, 0.0, 5.0), DVec3::new(0.0, 0.0, -1.0)).expect("valid ray");
/// assert!((r.u - 0.5).abs() < 1e-9 && (r.distance - 1.0).abs() < 1e-12 && (r.ray_t - 4.0).abs() < 1e-12);
/// ```
pub fn ray_closest_bezier<P: Point>(curve: &Bezier<P>, origin: P, dir: P) -> Option<RayNearest<P>> {
    ray_closest_bezier_with_stats(curve, origin, dir, &mut ClipStats::default())
}

/// [`ray_closest_bezier`], counting the clipping work.
pub fn ray_closest_bezier_with_stats<P: Point>(
    curve: &Bezier<P>,
    origin: P,
    dir: P,
    stats: &mut ClipStats,
) -> Option<RayNearest<P>> {
    if !origin.is_finite_coeff() || !dir.is_finite_coeff() {
        return None;
    }
    // Extreme magnitudes: search on a copy scaled by a power of two (exact), map back.
    let sp = rescale_for(magnitude(curve.points(), origin));
    if sp != 1.0 {
        let scaled = Bezier::try_new(curve.points().iter().map(|&c| c * sp).collect()).ok()?;
        let r = ray_closest_bezier_with_stats(&scaled, origin * sp, dir, stats)?;
        return Some(RayNearest {
            u: r.u,
            point: r.point * (1.0 / sp),
            ray_t: r.ray_t / sp,
            distance: r.distance / sp,
        });
    }
    // The direction alone may be tiny or huge: normalise it through a power-of-two copy.
    let ds = rescale_for(magnitude(&[dir], P::ZERO));
    let dir_n = dir * ds;
    let dlen = dir_n.length();
    if dlen.is_nan() || dlen <= 0.0 {
        return None;
    }
    let dh = dir_n * (1.0 / dlen);
    let n = curve.degree();
    let mut p = [P::ZERO; MAX_DEGREE + 1];
    for (pi, &c) in p.iter_mut().zip(curve.points()) {
        *pi = c - origin;
    }
    let p = &p[..=n];
    let sigma: Vec<f64> = p.iter().map(|&pi| pi.dot(dh)).collect();
    let mut f = [0.0; 2 * MAX_DEGREE + 1];
    distance_squared_coeffs(p, &mut f);
    let f = &f[..=2 * n];
    let s2 = bernstein::product(&sigma, &sigma, |a, b| a * b);
    let h: Vec<f64> = f.iter().zip(&s2).map(|(a, b)| a - b).collect();

    let mut roots = Vec::new();
    clip::roots(&sigma, &mut roots);
    let mut breaks = vec![0.0];
    breaks.extend(roots.iter().copied().filter(|&r| r > 0.0 && r < 1.0));
    breaks.push(1.0);
    let mut best: Option<(f64, f64)> = None;
    for w in breaks.windows(2) {
        let (a, b) = (w[0], w[1]);
        let ahead = bernstein::eval(&sigma, 0.5 * (a + b)) >= 0.0;
        let func: &[f64] = if ahead { &h } else { f };
        let bound = best.map_or(f64::INFINITY, |(_, v)| v);
        if let Some((u, v)) = minimize_below(func, a, b, bound, stats) {
            best = Some((u, v));
        }
    }
    let (u, _) = best?;
    let point = curve.eval(u);
    let s = (point - origin).dot(dh).max(0.0);
    let on_ray = origin + dh * s;
    Some(RayNearest {
        u,
        point,
        ray_t: s * ds / dlen,
        distance: (point - on_ray).length(),
    })
}
