//! Gaussian, mean and principal curvatures of a patch from its exact derivatives: the CPU
//! reference of the window's curvature map (`modeller/shaders/analysis.wgsl` evaluates the
//! same formulas per pixel in single precision).
//!
//! ## The shape operator
//! With the first derivatives `S_u, S_v`, the second derivatives `S_uu, S_uv, S_vv` (from the
//! Bernstein basis, see [`super::curvature::second_frame`]) and the unit normal
//! `N = (S_u × S_v) / |S_u × S_v|`, the fundamental forms are
//!
//! ```text
//! I  = [E F; F G],   E = S_u·S_u,  F = S_u·S_v,  G = S_v·S_v,
//! II = [L M; M N'],  L = S_uu·N,   M = S_uv·N,   N' = S_vv·N,
//! ```
//!
//! and the curvatures are the invariants of the shape operator `I⁻¹ II`:
//!
//! ```text
//! K = (L N' − M²) / (E G − F²)                    (Gaussian),
//! H = (E N' − 2 F M + G L) / (2 (E G − F²))       (mean),
//! κ₁,₂ = H ± √(H² − K)                            (principal, κ₁ ≥ κ₂).
//! ```
//!
//! `√(H² − K)` cancels catastrophically near an umbilic (every point of a sphere), so it is
//! evaluated as `√(((a − c)/2)² + b²)` from II's matrix `[a b; b c]` in the orthonormal
//! tangent basis `t₁ = S_u/|S_u|`, `t₂ = N × t₁` (a tangent vector `t` has coordinates
//! `I⁻¹ (t·S_u, t·S_v)` on `S_u, S_v`).
//!
//! Signs follow `N`: a surface curving away from its normal has negative curvature, so the
//! sphere primitive (outward normals) reads `H = κ₁ = κ₂ = −1/R`, `K = 1/R²`. `K` does not
//! depend on the orientation. The window shows *convexity* `−H` (and `−κ` for the principal
//! curvature of largest magnitude), positive on a ball seen from outside.
//!
//! ## Where there is no tangent plane
//! At a pole (a collapsed patch edge) `E G − F² = 0` and the formulas have no value; the
//! curvature there is the limit from inside the patch. [`patch_curvature`] returns `None`
//! when `E G − F²` is below `1e-20 · E G` (so callers step inside, as the shader does with its
//! interpolated parameters, which never land exactly on the pole edge).

use glam::DVec3;

use super::curvature::second_frame;
use crate::surface::patch::Patch;

/// The curvatures at a point of a surface (see the module docs for the signs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceCurvature {
    /// Gaussian curvature `K = κ₁ κ₂`.
    pub gaussian: f64,
    /// Mean curvature `H = (κ₁ + κ₂) / 2`, signed by the normal `S_u × S_v`.
    pub mean: f64,
    /// Larger principal curvature `κ₁`.
    pub k1: f64,
    /// Smaller principal curvature `κ₂`.
    pub k2: f64,
    /// The unit normal `N` the signs refer to.
    pub normal: DVec3,
}

impl SurfaceCurvature {
    /// The principal curvature of largest magnitude (signed).
    #[must_use]
    pub fn max_abs_principal(&self) -> f64 {
        if self.k1.abs() >= self.k2.abs() {
            self.k1
        } else {
            self.k2
        }
    }
}

/// The curvatures from `[S_u, S_v, S_uu, S_uv, S_vv]` (any regular parametrisation, not only
/// a patch's); `None` where the first fundamental form is singular or not finite.
#[must_use]
pub fn curvature_from_derivatives(d: &[DVec3; 5]) -> Option<SurfaceCurvature> {
    let [su, sv, suu, suv, svv] = *d;
    let (e, f, g) = (su.dot(su), su.dot(sv), sv.dot(sv));
    let det = e * g - f * f;
    if !det.is_finite() || det <= 1e-20 * (e * g).max(f64::MIN_POSITIVE) {
        return None;
    }
    let normal = su.cross(sv).try_normalize()?;
    let (l, m, n) = (suu.dot(normal), suv.dot(normal), svv.dot(normal));
    let gaussian = (l * n - m * m) / det;
    let mean = (e * n - 2.0 * f * m + g * l) / (2.0 * det);
    // √(H² − K) cancels at an umbilic (a sphere): take it from II in an orthonormal tangent
    // basis instead, where it is √(((a − c)/2)² + b²) without cancellation.
    let t1 = su / e.sqrt();
    let t2 = normal.cross(t1);
    let coefficients = |t: DVec3| {
        let (x, y) = (t.dot(su), t.dot(sv));
        ((g * x - f * y) / det, (e * y - f * x) / det)
    };
    let second = |(a1, b1): (f64, f64), (a2, b2): (f64, f64)| {
        a1 * a2 * l + (a1 * b2 + a2 * b1) * m + b1 * b2 * n
    };
    let (c1, c2) = (coefficients(t1), coefficients(t2));
    let (a, b, c) = (second(c1, c1), second(c1, c2), second(c2, c2));
    let spread = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    Some(SurfaceCurvature {
        gaussian,
        mean,
        k1: mean + spread,
        k2: mean - spread,
        normal,
    })
}

/// The curvatures of a patch at `(u, v)` from its exact derivatives; `None` where it has no
/// tangent plane (a pole).
#[must_use]
pub fn patch_curvature(p: &Patch, u: f64, v: f64) -> Option<SurfaceCurvature> {
    curvature_from_derivatives(&second_frame(p, u, v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::primitive::{Primitive, PrimitiveParams};

    /// The round sphere `S(θ, φ) = R (cos θ cos φ, sin θ cos φ, sin φ)` and its exact
    /// derivatives: the formulas read `H = −1/R` (outward normal), `K = 1/R²` to rounding,
    /// everywhere including next to the poles.
    #[test]
    fn a_round_sphere_reads_one_over_r_everywhere() {
        for radius in [0.01, 1.0, 3.0, 250.0] {
            for i in 0..=40 {
                // φ from −π/2 to π/2, the poles themselves replaced by points 1e-6 away.
                let phi = (-0.5 + f64::from(i) / 40.0) * std::f64::consts::PI;
                let phi = phi.clamp(
                    -std::f64::consts::FRAC_PI_2 + 1e-6,
                    std::f64::consts::FRAC_PI_2 - 1e-6,
                );
                for j in 0..16 {
                    let theta = f64::from(j) * std::f64::consts::TAU / 16.0;
                    let (st, ct, sp, cp) = (theta.sin(), theta.cos(), phi.sin(), phi.cos());
                    let r = radius;
                    let d = [
                        DVec3::new(-st * cp, ct * cp, 0.0) * r,
                        DVec3::new(-ct * sp, -st * sp, cp) * r,
                        DVec3::new(-ct * cp, -st * cp, 0.0) * r,
                        DVec3::new(st * sp, -ct * sp, 0.0) * r,
                        DVec3::new(-ct * cp, -st * cp, -sp) * r,
                    ];
                    let c = curvature_from_derivatives(&d)
                        .unwrap_or_else(|| panic!("no tangent plane at θ {theta}, φ {phi}"));
                    let scale = 1.0 / r;
                    assert!((c.mean + scale).abs() <= 1e-9 * scale, "{c:?} R {r}");
                    assert!((c.k1 + scale).abs() <= 1e-9 * scale, "{c:?} R {r}");
                    assert!((c.k2 + scale).abs() <= 1e-9 * scale, "{c:?} R {r}");
                    assert!(
                        (c.gaussian - scale * scale).abs() <= 1e-9 * scale * scale,
                        "{c:?}"
                    );
                    assert!((c.max_abs_principal() + scale).abs() <= 1e-9 * scale);
                }
            }
        }
        let flat = [DVec3::X, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, DVec3::ZERO];
        assert_eq!(curvature_from_derivatives(&flat), None);
    }

    /// A patch that is exactly the paraboloid `z = (x² + y²) / (2R)` over `[0, 1]²`
    /// (control heights from the blossom of `x²`): its curvatures against the closed form
    /// `K = 1 / (R² w⁴)`, `H = −(2 + |∇z|²) / (2 R w³)` with `w = √(1 + |∇z|²)`, and
    /// `1/R` at the apex.
    #[test]
    fn a_paraboloid_patch_matches_its_closed_form() {
        let r = 2.5;
        let blossom = [0.0, 0.0, 1.0 / 3.0, 1.0];
        let mut points = [DVec3::ZERO; 16];
        for i in 0..4 {
            for j in 0..4 {
                let (x, y) = (i as f64 / 3.0, j as f64 / 3.0);
                points[4 * i + j] = DVec3::new(x, y, (blossom[i] + blossom[j]) / (2.0 * r));
            }
        }
        let p = Patch::new(points);
        for i in 0..=10 {
            for j in 0..=10 {
                let (u, v) = (f64::from(i) / 10.0, f64::from(j) / 10.0);
                let c = patch_curvature(&p, u, v).unwrap_or_else(|| panic!("({u}, {v})"));
                let g2 = (u * u + v * v) / (r * r);
                let w = (1.0 + g2).sqrt();
                let k = 1.0 / (r * r * w.powi(4));
                // Upward normal (S_u × S_v = +z side), the paraboloid bends towards it.
                let h = (2.0 + g2) / (2.0 * r * w.powi(3));
                assert!((c.gaussian - k).abs() < 1e-12, "{c:?} vs K {k}");
                assert!((c.mean - h).abs() < 1e-12, "{c:?} vs H {h}");
            }
        }
        let apex = patch_curvature(&p, 0.0, 0.0).unwrap_or_else(|| unreachable!());
        assert!((apex.k1 - 1.0 / r).abs() < 1e-12 && (apex.k2 - 1.0 / r).abs() < 1e-12);
    }

    /// The sphere primitive's patches approximate a sphere by cubics: sampled away from the
    /// pole edges (the limit is taken from inside), the curvature is `1/R` to the
    /// approximation's error, which this measures and bounds.
    #[test]
    fn the_sphere_primitive_reads_one_over_r_to_its_approximation() {
        let radius = 3.0;
        let g = Primitive::Sphere
            .build(&PrimitiveParams {
                radius: Some(radius),
                ..PrimitiveParams::default()
            })
            .unwrap_or_else(|e| panic!("{e}"));
        let mut worst = 0.0f64;
        for p in 0..g.patch_count() {
            let patch = Patch::new(g.patch_at(p));
            for i in 0..=8 {
                for j in 0..=8 {
                    let (u, v) = (
                        f64::from(i) / 8.0,
                        (f64::from(j) / 8.0).clamp(1e-4, 1.0 - 1e-4),
                    );
                    let c = patch_curvature(&patch, u, v)
                        .unwrap_or_else(|| panic!("patch {p} ({u}, {v})"));
                    worst = worst.max((c.mean.abs() * radius - 1.0).abs());
                }
            }
        }
        assert!(worst < 0.05, "worst relative mean-curvature error {worst}");
    }
}
