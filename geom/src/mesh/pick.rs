//! Ray picking on the exact surface.
//!
//! A ray `o + t d` first meets the tessellation (patches culled by the bounding box of their
//! control points, which holds the patch; then Möller–Trumbore on the patch's triangles); the
//! nearest hit is then refined on the exact patch by Newton's method on
//! `F(u, v, t) = S(u, v) − (o + t d) = 0`, whose Jacobian columns are `S_u`, `S_v`, `−d`. The
//! mesh hit is within the tessellation tolerance, so Newton starts close and converges in a
//! few steps; if it leaves the patch or fails to converge, the mesh hit is returned as it is.

use glam::DVec3;

use super::tessellate::{PatchPoints, eval_patch, patch_normal};
use super::trimesh::TriMesh;

/// A ray `origin + t · direction`, `t ≥ 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: DVec3,
    /// Its direction (need not be unit; `t` is measured in multiples of it).
    pub direction: DVec3,
}

impl Ray {
    /// The point at parameter `t`.
    #[must_use]
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + self.direction * t
    }
}

/// Where a ray meets the surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceHit {
    /// Index of the patch.
    pub patch: usize,
    /// Patch parameter along `u`.
    pub u: f64,
    /// Patch parameter along `v`.
    pub v: f64,
    /// The point `S(u, v)`.
    pub point: DVec3,
    /// The unit normal `S_u × S_v` there.
    pub normal: DVec3,
    /// Ray parameter of the point.
    pub t: f64,
}

/// The nearest point where `ray` meets the patches, `mesh` being their tessellation (with its
/// blocks, as [`super::tessellate()`] returns it).
#[must_use]
pub fn pick(patches: &[PatchPoints], mesh: &TriMesh, ray: &Ray) -> Option<SurfaceHit> {
    let mut best: Option<(f64, usize, f64, f64)> = None;
    for block in &mesh.blocks {
        let Some(p) = patches.get(block.patch as usize) else {
            continue;
        };
        let (lo, hi) = hull_box(p);
        let Some(t_box) = ray_box(ray, lo, hi) else {
            continue;
        };
        if best.is_some_and(|(t, ..)| t_box > t) {
            continue;
        }
        let first = block.first_index as usize;
        let tris = &mesh.indices[first..first + block.index_count() as usize];
        for tri in tris.chunks_exact(3) {
            let q = [tri[0], tri[1], tri[2]].map(|i| mesh.positions[i as usize].as_dvec3());
            let Some((t, b1, b2)) = ray_triangle(ray, q) else {
                continue;
            };
            if best.is_none_or(|(bt, ..)| t < bt) {
                let uv = [tri[0], tri[1], tri[2]].map(|i| block.uv_of(i));
                let b0 = 1.0 - b1 - b2;
                let u = b0 * uv[0].0 + b1 * uv[1].0 + b2 * uv[2].0;
                let v = b0 * uv[0].1 + b1 * uv[1].1 + b2 * uv[2].1;
                best = Some((t, block.patch as usize, u, v));
            }
        }
    }
    let (t, patch, u, v) = best?;
    let p = &patches[patch];
    let (u, v, t) = refine(p, ray, u, v, t).unwrap_or((u, v, t));
    Some(SurfaceHit {
        patch,
        u,
        v,
        point: eval_patch(p, u, v).0,
        normal: patch_normal(p, u, v),
        t,
    })
}

/// Newton's method on `S(u, v) − ray(t) = 0` from a nearby start; `None` when it does not
/// converge inside the patch.
fn refine(
    p: &PatchPoints,
    ray: &Ray,
    mut u: f64,
    mut v: f64,
    mut t: f64,
) -> Option<(f64, f64, f64)> {
    for _ in 0..12 {
        let (s, su, sv) = eval_patch(p, u, v);
        let f = s - ray.at(t);
        let d = -ray.direction;
        // Solve [su sv d] x = -f by Cramer's rule.
        let det = su.dot(sv.cross(d));
        if det.abs() < 1e-300 {
            return None;
        }
        let du = -f.dot(sv.cross(d)) / det;
        let dv = -su.dot(f.cross(d)) / det;
        let dt = -su.dot(sv.cross(f)) / det;
        u += du;
        v += dv;
        t += dt;
        if !(-1e-9..=1.0 + 1e-9).contains(&u) || !(-1e-9..=1.0 + 1e-9).contains(&v) || t < 0.0 {
            return None;
        }
        if du.abs().max(dv.abs()) < 1e-13 {
            return Some((u.clamp(0.0, 1.0), v.clamp(0.0, 1.0), t));
        }
    }
    None
}

/// Bounding box of a patch's control points (which holds the patch).
fn hull_box(p: &PatchPoints) -> (DVec3, DVec3) {
    p.iter()
        .fold((p[0], p[0]), |(lo, hi), q| (lo.min(*q), hi.max(*q)))
}

/// Entry parameter of a ray into a box (0 when it starts inside); `None` if it misses.
fn ray_box(ray: &Ray, lo: DVec3, hi: DVec3) -> Option<f64> {
    let pad = (hi - lo).max_element() * 1e-9 + 1e-12;
    let (lo, hi) = (lo - DVec3::splat(pad), hi + DVec3::splat(pad));
    let mut t0 = 0.0f64;
    let mut t1 = f64::INFINITY;
    for k in 0..3 {
        let (o, d) = (ray.origin[k], ray.direction[k]);
        if d == 0.0 {
            if o < lo[k] || o > hi[k] {
                return None;
            }
            continue;
        }
        let (a, b) = ((lo[k] - o) / d, (hi[k] - o) / d);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    (t0 <= t1).then_some(t0)
}

/// Möller–Trumbore: `(t, b1, b2)` with the hit `= (1 − b1 − b2) q0 + b1 q1 + b2 q2`.
fn ray_triangle(ray: &Ray, q: [DVec3; 3]) -> Option<(f64, f64, f64)> {
    let e1 = q[1] - q[0];
    let e2 = q[2] - q[0];
    let h = ray.direction.cross(e2);
    let det = e1.dot(h);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = ray.origin - q[0];
    let b1 = s.dot(h) / det;
    let qv = s.cross(e1);
    let b2 = ray.direction.dot(qv) / det;
    let eps = 1e-9;
    if b1 < -eps || b2 < -eps || b1 + b2 > 1.0 + eps {
        return None;
    }
    let t = e2.dot(qv) / det;
    (t >= 0.0).then_some((t, b1.max(0.0), b2.max(0.0)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Tessellation, tessellate};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn picks_the_exact_surface_of_a_curved_patch() {
        let mut rng = ChaCha8Rng::seed_from_u64(61);
        let p: PatchPoints = std::array::from_fn(|k| {
            let (i, j) = ((k / 4) as f64, (k % 4) as f64);
            DVec3::new(i, j, rng.gen_range(-0.8..0.8))
        });
        let mesh = tessellate(&[p], &Tessellation::DISPLAY);
        for _ in 0..50 {
            // Aim from above at a known surface point.
            let (u, v) = (rng.gen_range(0.05..0.95), rng.gen_range(0.05..0.95));
            let target = eval_patch(&p, u, v).0;
            let origin =
                target + DVec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), 10.0);
            let ray = Ray {
                origin,
                direction: target - origin,
            };
            let hit = pick(&[p], &mesh, &ray).expect("the ray aims at the patch");
            // The patch may fold over the target; the hit must lie on both the surface and the ray.
            let on_surface = eval_patch(&p, hit.u, hit.v).0;
            let off_ray = (hit.point - ray.at(hit.t)).length();
            assert!((on_surface - hit.point).length() < 1e-12);
            assert!(off_ray < 1e-9, "{off_ray}");
            assert!(hit.t <= 1.0 + 1e-9);
        }
        let miss = Ray {
            origin: DVec3::new(-5.0, -5.0, 5.0),
            direction: DVec3::Z,
        };
        assert!(pick(&[p], &mesh, &miss).is_none());
    }
}
