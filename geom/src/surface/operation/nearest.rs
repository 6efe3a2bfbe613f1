//! The surface point nearest a point in space: `argmin_{p, u, v} |S_p(u, v) − q|`.
//!
//! 1. An upper bound `B` on the distance: the nearest patch corner (the corners `P[0]`,
//!    `P[3]`, `P[12]`, `P[15]` of every patch lie on the surface).
//! 2. Every patch whose control-point box (which holds the patch) is within `B` of `q` is a
//!    candidate (box pyramid), and is sampled on a 9 × 9 parameter grid; the best samples seed
//!    the refinement.
//! 3. Gauss–Newton on `f(u, v) = ½|S(u, v) − q|²` (`[S_u·S_u S_u·S_v; S_u·S_v S_v·S_v] Δ =
//!    [S_u·(q − S); S_v·(q − S)]`, damped, clamped to `[0, 1]²`), keeping a step only when it
//!    lowers `f`.
//!
//! Limits: a local method seeded from samples — on a patch folded tighter than the sample
//! spacing (1/8 of the patch) the global minimum may be missed by a near-equal local one; the
//! distance found is never larger than the best sample's.

use glam::DVec3;

use crate::surface::bounds::Aabb;
use crate::surface::grid::Grid;
use crate::surface::patch::Patch;

/// A point of a grid's surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// Patch index `iv * M + iu`.
    pub patch: usize,
    /// Parameter along `u` in the patch, `[0, 1]`.
    pub u: f64,
    /// Parameter along `v` in the patch, `[0, 1]`.
    pub v: f64,
    /// `S(u, v)`.
    pub point: DVec3,
}

/// Samples per direction of the seeding grid.
const SEEDS: usize = 9;
/// Seeds refined by Gauss–Newton.
const REFINED: usize = 4;

/// Distance from `q` to the box (0 inside).
fn box_distance(b: &Aabb, q: DVec3) -> f64 {
    let d = (b.min - q).max(q - b.max).max(DVec3::ZERO);
    d.length()
}

/// The surface point nearest `q` (see the module docs); `None` for a non-finite `q`.
#[must_use]
pub fn nearest(grid: &Grid, q: DVec3) -> Option<SurfacePoint> {
    if !q.is_finite() {
        return None;
    }
    let mut bound = f64::INFINITY;
    for p in 0..grid.patch_count() {
        let pts = grid.patch_at(p);
        for c in [0, 3, 12, 15] {
            bound = bound.min((pts[c] - q).length());
        }
    }
    let bound = bound * (1.0 + 1e-12) + 1e-300;
    let mut candidates = Vec::new();
    grid.patches_where(|b| box_distance(b, q) <= bound, &mut candidates);
    candidates.sort_unstable();
    // The best seeds over all candidates: (squared distance, patch, u, v).
    let mut seeds: Vec<(f64, usize, f64, f64)> = Vec::new();
    for &p in &candidates {
        let patch = Patch::new(grid.patch_at(p));
        for i in 0..SEEDS {
            for j in 0..SEEDS {
                let (u, v) = (i as f64 / (SEEDS - 1) as f64, j as f64 / (SEEDS - 1) as f64);
                let d = (patch.eval(u, v) - q).length_squared();
                if seeds.len() < REFINED || d < seeds[REFINED - 1].0 {
                    seeds.push((d, p, u, v));
                    seeds.sort_by(|a, b| a.0.total_cmp(&b.0));
                    seeds.truncate(REFINED);
                }
            }
        }
    }
    let mut best: Option<SurfacePoint> = None;
    let mut best_d = f64::INFINITY;
    for &(_, p, u, v) in &seeds {
        let patch = Patch::new(grid.patch_at(p));
        let (u, v, point) = refine(&patch, q, u, v);
        let d = (point - q).length_squared();
        if d < best_d {
            best_d = d;
            best = Some(SurfacePoint {
                patch: p,
                u,
                v,
                point,
            });
        }
    }
    best
}

/// Gauss–Newton from `(u, v)` (see the module docs).
fn refine(patch: &Patch, q: DVec3, mut u: f64, mut v: f64) -> (f64, f64, DVec3) {
    let mut point = patch.eval(u, v);
    let mut f = (point - q).length_squared();
    for _ in 0..40 {
        let fr = patch.frame(u, v);
        let r = q - fr.point;
        let (a, b, c) = (fr.du.dot(fr.du), fr.du.dot(fr.dv), fr.dv.dot(fr.dv));
        let (gu, gv) = (fr.du.dot(r), fr.dv.dot(r));
        let mut lambda = 1e-12 * (a + c).max(1e-300);
        let mut moved = false;
        for _ in 0..30 {
            let (a2, c2) = (a + lambda, c + lambda);
            let det = a2 * c2 - b * b;
            if det.is_finite() && det > 0.0 {
                let du = (gu * c2 - gv * b) / det;
                let dv = (gv * a2 - gu * b) / det;
                let (nu, nv) = ((u + du).clamp(0.0, 1.0), (v + dv).clamp(0.0, 1.0));
                let np = patch.eval(nu, nv);
                let nf = (np - q).length_squared();
                if nf < f {
                    moved = (nu - u).abs() + (nv - v).abs() > 1e-15;
                    (u, v, point, f) = (nu, nv, np, nf);
                    break;
                }
            }
            lambda = lambda * 10.0 + 1e-12 * (a + c).max(1e-300);
        }
        if !moved {
            break;
        }
    }
    (u, v, point)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Primitive, PrimitiveParams};

    #[test]
    fn nearest_on_a_sphere_is_the_radial_point() {
        let grid = Primitive::Sphere
            .build(&PrimitiveParams {
                patches: Some((16, 8)),
                ..PrimitiveParams::default()
            })
            .unwrap();
        let mut u = crate::seeded::unit(17u64);
        let mut r = move || u() - 0.5;
        for _ in 0..40 {
            let q = DVec3::new(r(), r(), r()) * 8.0;
            let got = nearest(&grid, q).unwrap();
            // Brute force: dense samples of every patch.
            let mut best = f64::INFINITY;
            for p in 0..grid.patch_count() {
                let patch = Patch::new(grid.patch_at(p));
                for i in 0..=40 {
                    for j in 0..=40 {
                        let s = patch.eval(i as f64 / 40.0, j as f64 / 40.0);
                        best = best.min((s - q).length());
                    }
                }
            }
            let d = (got.point - q).length();
            assert!(d <= best + 1e-12, "{q}: {d} vs {best}");
            // Neighbouring samples are at most 2π·3/16/40 ≈ 0.03 apart (a patch spans 1/16 of
            // the equator of the radius-3 sphere, sampled 40 times), so the nearest sample is
            // within 0.03 of the nearest point: sampling can only be that much worse.
            assert!(best - d <= 0.03, "{q}: {d} vs {best}");
        }
    }
}
