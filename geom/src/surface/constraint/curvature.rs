//! Curvature continuity (G2) across seams and at poles, from the patches' exact derivatives.
//!
//! ## Normal curvature across a seam
//! At a point of a shared edge with unit tangent `T`, each side has its unit normal `N` (the
//! second side's turned to agree with the first's) and the direction across the seam in its
//! tangent plane, `d = N × T`. The normal curvature of a side in direction `d` is Euler's
//! quotient of the fundamental forms,
//!
//! ```text
//! κ(d) = II(d) / I(d) = (a² L + 2ab M + b² N') / (a² E + 2ab F + b² G),
//! ```
//!
//! with `d = a S_u + b S_v` (solved from `[E F; F G] (a, b)ᵀ = (d·S_u, d·S_v)ᵀ`),
//! `E = S_u·S_u`, `F = S_u·S_v`, `G = S_v·S_v`, `L = S_uu·N`, `M = S_uv·N`, `N' = S_vv·N`, and
//! the second derivatives from the Bernstein basis: `B₀'' = 6(1 − t)`, `B₁'' = 6t − 12(1 − t)`,
//! `B₂'' = 6(1 − t) − 12t`, `B₃'' = 6t`. A G1 surface is G2 across the seam where the two sides'
//! `κ(d)` agree (their tangent-direction curvatures agree already, both being the curvature
//! of the shared boundary curve's normal component).
//!
//! ## The measures (as Rhino's EdgeContinuity reports them)
//! - **absolute**: `|κ₁ − κ₂| = |1/R₁ − 1/R₂|` (1 / model units);
//! - **relative**: `|κ₁ − κ₂| / (|κ₁| + |κ₂|)`, which is `|(R₁ − R₂) / (R₁ + R₂)|` for curvatures
//!   of one sign and 1 for opposite signs (bounded in `[0, 1]`); 0 where both sides are flat
//!   (`|κ₁| + |κ₂|` below `1e-9` / the model's size).
//!
//! Each seam (all patch edges of one grid line between two patches) reports its worst sample.
//! Sample points where a side has no tangent plane (a pole end) are skipped.
//!
//! ## At a pole
//! All the patches around a pole meet at one point, so there is no seam to compare across:
//! instead the meridian curvatures there, `κ_i = S_vv·N / |S_v|²` in the directions
//! `d_i = ±S_v / |S_v|` out of the pole (k parameters on each patch), must be the values of one
//! quadratic form (Euler's theorem: a surface that is C2 at the point has
//! `κ(d) = dᵀ K d`). `K` (three numbers in an orthonormal basis of the pole's tangent plane) is
//! fitted by least squares; the pole's absolute mismatch is the largest residual
//! `|κ_i − d_iᵀ K d_i|` and its relative one that over the largest `|κ_i|` (0 on a flat pole).

use glam::DVec3;

use crate::surface::grid::Grid;
use crate::surface::group::PoleEnd;
use crate::surface::patch::{Patch, cubic_basis, cubic_basis_derivative};
use crate::surface::plane_fit::plane_normal;

/// Second derivatives of the cubic Bernstein basis at `t`.
#[must_use]
pub fn cubic_basis_second(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [6.0 * s, 6.0 * t - 12.0 * s, 6.0 * s - 12.0 * t, 6.0 * t]
}

/// `S_u, S_v, S_uu, S_uv, S_vv` of a patch at `(u, v)`.
#[must_use]
pub fn second_frame(p: &Patch, u: f64, v: f64) -> [DVec3; 5] {
    let (bu, du, ddu) = (
        cubic_basis(u),
        cubic_basis_derivative(u),
        cubic_basis_second(u),
    );
    let (bv, dv, ddv) = (
        cubic_basis(v),
        cubic_basis_derivative(v),
        cubic_basis_second(v),
    );
    let mut out = [DVec3::ZERO; 5];
    for i in 0..4 {
        for j in 0..4 {
            let x = p.point(i, j);
            out[0] += x * (du[i] * bv[j]);
            out[1] += x * (bu[i] * dv[j]);
            out[2] += x * (ddu[i] * bv[j]);
            out[3] += x * (du[i] * dv[j]);
            out[4] += x * (bu[i] * ddv[j]);
        }
    }
    out
}

/// The normal curvature of a patch at `(u, v)` in the tangent direction `d`, with the unit
/// normal `n` (see the module docs); `None` where the first fundamental form is singular.
#[must_use]
pub fn normal_curvature(p: &Patch, u: f64, v: f64, n: DVec3, d: DVec3) -> Option<f64> {
    let [su, sv, suu, suv, svv] = second_frame(p, u, v);
    let (e, f, g) = (su.dot(su), su.dot(sv), sv.dot(sv));
    let det = e * g - f * f;
    if det.is_nan() || det <= 1e-20 * (e * g).max(f64::MIN_POSITIVE) {
        return None;
    }
    let (x, y) = (d.dot(su), d.dot(sv));
    let a = (g * x - f * y) / det;
    let b = (e * y - f * x) / det;
    let first = a * a * e + 2.0 * a * b * f + b * b * g;
    let second = a * a * suu.dot(n) + 2.0 * a * b * suv.dot(n) + b * b * svv.dot(n);
    (first > 0.0).then(|| second / first)
}

/// The G2 mismatch of one seam: a grid line between two patches.
#[derive(Debug, Clone, PartialEq)]
pub struct SeamG2 {
    /// `"u"` for a u grid line (constant `u`), `"v"` for a v grid line.
    pub direction: &'static str,
    /// The grid line's index.
    pub line: usize,
    /// The patch on the line's other side along it (`iv` for a u line, `iu` for a v line).
    pub along: usize,
    /// Largest relative mismatch on the seam.
    pub relative: f64,
    /// Largest absolute mismatch `|κ₁ − κ₂|` on the seam.
    pub absolute: f64,
}

/// The G2 mismatch at a pole.
#[derive(Debug, Clone, PartialEq)]
pub struct PoleG2 {
    /// Which pole.
    pub end: PoleEnd,
    /// Largest relative residual of the meridian curvatures against one quadratic form.
    pub relative: f64,
    /// Largest absolute residual.
    pub absolute: f64,
    /// The fitted form's principal curvatures (smaller first).
    pub principal: (f64, f64),
}

/// The G2 report of a grid.
#[derive(Debug, Clone, PartialEq)]
pub struct G2Report {
    /// Every seam (shared patch edge), in the order u lines then v lines.
    pub seams: Vec<SeamG2>,
    /// Every pole.
    pub poles: Vec<PoleG2>,
    /// Largest relative mismatch over the seams.
    pub max_relative: f64,
    /// Largest absolute mismatch over the seams.
    pub max_absolute: f64,
    /// Mean of the seams' largest relative mismatches.
    pub mean_relative: f64,
}

impl G2Report {
    /// The `count` seams of largest relative mismatch, worst first.
    #[must_use]
    pub fn worst(&self, count: usize) -> Vec<&SeamG2> {
        let mut all: Vec<&SeamG2> = self.seams.iter().collect();
        all.sort_by(|a, b| b.relative.total_cmp(&a.relative));
        all.truncate(count);
        all
    }
}

/// Relative and absolute mismatch of two curvatures; `flat` is the floor below which both
/// count as flat (relative 0).
fn mismatch(k1: f64, k2: f64, flat: f64) -> (f64, f64) {
    let abs = (k1 - k2).abs();
    let sum = k1.abs() + k2.abs();
    (if sum > flat { abs / sum } else { 0.0 }, abs)
}

/// The largest relative and absolute mismatch of the normal curvatures across the edge
/// between patches `a` and `bp` (`bp` after `a` across a u line when `across_u`, else across a
/// v line), at `k − 2` points inside the edge; `flat` as in [`g2_report`].
#[must_use]
pub(crate) fn seam_mismatch(
    a: &Patch,
    bp: &Patch,
    across_u: bool,
    k: usize,
    flat: f64,
) -> (f64, f64) {
    let k = k.max(3);
    let (mut rel, mut abs) = (0.0f64, 0.0f64);
    for i in 1..k - 1 {
        let t = i as f64 / (k - 1) as f64;
        let ((ua, va), (ub, vb)) = if across_u {
            ((1.0, t), (0.0, t))
        } else {
            ((t, 1.0), (t, 0.0))
        };
        let (Some(na), Some(nb)) = (a.normal(ua, va), bp.normal(ub, vb)) else {
            continue;
        };
        let nb = if nb.dot(na) < 0.0 { -nb } else { nb };
        let fa = a.frame(ua, va);
        let tangent = if across_u { fa.dv } else { fa.du };
        let Some(tangent) = tangent.try_normalize() else {
            continue;
        };
        let (da, db) = (na.cross(tangent), nb.cross(tangent));
        let (Some(ka), Some(kb)) = (
            normal_curvature(a, ua, va, na, da),
            normal_curvature(bp, ub, vb, nb, db),
        ) else {
            continue;
        };
        let (r, x) = mismatch(ka, kb, flat);
        rel = rel.max(r);
        abs = abs.max(x);
    }
    (rel, abs)
}

/// Measures the G2 mismatch of `grid` with `k` points per shared edge (at least 3; the end
/// points of each edge are left out, where a pole or a corner may leave a side without a
/// tangent plane).
#[must_use]
pub fn g2_report(grid: &Grid, k: usize) -> G2Report {
    let k = k.max(3);
    let (m, n) = (grid.patches_u(), grid.patches_v());
    let b = grid.bounds();
    let size = (b.max - b.min).length().max(f64::MIN_POSITIVE);
    let flat = 1e-9 / size;
    let patches: Vec<Patch> = (0..grid.patch_count())
        .map(|p| Patch::new(grid.patch_at(p)))
        .collect();
    let mut seams = Vec::new();
    let seam = |a: &Patch, bp: &Patch, across_u: bool| seam_mismatch(a, bp, across_u, k, flat);
    for line in 0..grid.vertices_u() {
        if !grid.u_line_shared(line) {
            continue;
        }
        for iv in 0..n {
            let (left, right) = ((line + m - 1) % m, line % m);
            let (relative, absolute) =
                seam(&patches[iv * m + left], &patches[iv * m + right], true);
            seams.push(SeamG2 {
                direction: "u",
                line,
                along: iv,
                relative,
                absolute,
            });
        }
    }
    for line in 0..grid.vertices_v() {
        if !grid.v_line_shared(line) {
            continue;
        }
        for iu in 0..m {
            let (below, above) = ((line + n - 1) % n, line % n);
            let (relative, absolute) =
                seam(&patches[below * m + iu], &patches[above * m + iu], false);
            seams.push(SeamG2 {
                direction: "v",
                line,
                along: iu,
                relative,
                absolute,
            });
        }
    }
    let max_relative = seams.iter().map(|s| s.relative).fold(0.0, f64::max);
    let max_absolute = seams.iter().map(|s| s.absolute).fold(0.0, f64::max);
    let mean_relative = if seams.is_empty() {
        0.0
    } else {
        seams.iter().map(|s| s.relative).sum::<f64>() / seams.len() as f64
    };
    let poles = grid
        .poles()
        .iter()
        .filter_map(|p| pole_g2(grid, &patches, p.end, k, flat))
        .collect();
    G2Report {
        seams,
        poles,
        max_relative,
        max_absolute,
        mean_relative,
    }
}

/// The pole's meridian curvatures against one quadratic form (see the module docs).
fn pole_g2(grid: &Grid, patches: &[Patch], end: PoleEnd, k: usize, flat: f64) -> Option<PoleG2> {
    let (m, n) = (grid.patches_u(), grid.patches_v());
    let (iv, v, sign) = if end == PoleEnd::Start {
        (0, 0.0, 1.0)
    } else {
        (n - 1, 1.0, -1.0)
    };
    // Directions out of the pole and the meridian curvatures along them.
    let mut samples: Vec<(DVec3, DVec3, DVec3)> = Vec::with_capacity(m * k);
    for iu in 0..m {
        let p = &patches[iv * m + iu];
        for i in 0..k {
            let u = i as f64 / (k - 1) as f64;
            let [_, sv, _, _, svv] = second_frame(p, u, v);
            samples.push((
                sv * sign,
                svv,
                p.normal(u, if v == 0.0 { 0.05 } else { 0.95 })?,
            ));
        }
    }
    let mut normal = plane_normal(samples.iter().filter_map(|s| s.0.try_normalize()))?;
    let orient: DVec3 = samples.iter().map(|s| s.2).sum();
    if normal.dot(orient) < 0.0 {
        normal = -normal;
    }
    let e1 = normal.any_orthonormal_vector();
    let e2 = normal.cross(e1);
    let mut rows = Vec::with_capacity(samples.len());
    for (sv, svv, _) in &samples {
        let len2 = sv.length_squared();
        if len2 <= 0.0 {
            continue;
        }
        let d = *sv / len2.sqrt();
        let kappa = svv.dot(normal) / len2;
        let (x, y) = (d.dot(e1), d.dot(e2));
        rows.push(([x * x, 2.0 * x * y, y * y], kappa));
    }
    // Least squares for (a, b, c): the 3 × 3 normal equations by Cramer's rule.
    let mut ata = [[0.0; 3]; 3];
    let mut atb = [0.0; 3];
    for (r, kappa) in &rows {
        for i in 0..3 {
            for j in 0..3 {
                ata[i][j] += r[i] * r[j];
            }
            atb[i] += r[i] * kappa;
        }
    }
    let det3 = |a: [[f64; 3]; 3]| {
        a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
            - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
            + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
    };
    let det = det3(ata);
    if det.abs() < 1e-30 {
        return None;
    }
    let mut x = [0.0; 3];
    for (c, slot) in x.iter_mut().enumerate() {
        let mut a = ata;
        for r in 0..3 {
            a[r][c] = atb[r];
        }
        *slot = det3(a) / det;
    }
    let (mut abs, mut largest) = (0.0f64, 0.0f64);
    for (r, kappa) in &rows {
        let fit = r[0] * x[0] + r[1] * x[1] + r[2] * x[2];
        abs = abs.max((kappa - fit).abs());
        largest = largest.max(kappa.abs());
    }
    // Principal curvatures: eigenvalues of [[a, b], [b, c]].
    let (a, b, c) = (x[0], x[1], x[2]);
    let mean = 0.5 * (a + c);
    let radius = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    Some(PoleG2 {
        end,
        relative: if largest > flat { abs / largest } else { 0.0 },
        absolute: abs,
        principal: (mean - radius, mean + radius),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::primitive::{Primitive, PrimitiveParams};

    fn plane(m: usize, n: usize) -> Grid {
        Primitive::Plane
            .build(&PrimitiveParams {
                patches: Some((m, n)),
                ..PrimitiveParams::default()
            })
            .unwrap_or_else(|e| panic!("{e}"))
    }

    /// `z = x² + y²` on a plane grid of unit squares, exactly (control values from the
    /// blossom `f(x₁, x₂, x₃) = (x₁x₂ + x₁x₃ + x₂x₃) / 3` of `x²`).
    fn paraboloid(m: usize, n: usize) -> Grid {
        let mut g = plane(m, n);
        let (la, lb) = g.lattice_size();
        let value = |t0: f64, r: usize| {
            let t1 = t0 + 1.0;
            match r {
                0 => t0 * t0,
                1 => (t0 * t0 + 2.0 * t0 * t1) / 3.0,
                _ => (2.0 * t0 * t1 + t1 * t1) / 3.0,
            }
        };
        let mut changes = Vec::new();
        for a in 0..la {
            for b in 0..lb {
                let id = g
                    .node_id(a as isize, b as isize)
                    .unwrap_or_else(|| unreachable!());
                let x0 = g.nodes()[g.node_id(3 * (a / 3) as isize, b as isize).unwrap_or(id)].x;
                let y0 = g.nodes()[g.node_id(a as isize, 3 * (b / 3) as isize).unwrap_or(id)].y;
                let mut p = g.nodes()[id];
                p.z = value(x0, a % 3) + value(y0, b % 3);
                changes.push((id, p));
            }
        }
        g.set_nodes(&changes).unwrap_or_else(|e| panic!("{e}"));
        g
    }

    #[test]
    fn second_derivatives_match_differences() {
        let g = paraboloid(2, 2);
        let p = Patch::new(g.patch_at(3));
        let (u, v, h) = (0.3, 0.6, 1e-5);
        let [su, sv, suu, suv, svv] = second_frame(&p, u, v);
        let f = |u: f64, v: f64| p.eval(u, v);
        assert!((su - (f(u + h, v) - f(u - h, v)) / (2.0 * h)).length() < 1e-8);
        assert!((sv - (f(u, v + h) - f(u, v - h)) / (2.0 * h)).length() < 1e-8);
        let h = 1e-4;
        assert!((suu - (f(u + h, v) - 2.0 * f(u, v) + f(u - h, v)) / (h * h)).length() < 1e-5);
        assert!((svv - (f(u, v + h) - 2.0 * f(u, v) + f(u, v - h)) / (h * h)).length() < 1e-5);
        let cross =
            (f(u + h, v + h) - f(u + h, v - h) - f(u - h, v + h) + f(u - h, v - h)) / (4.0 * h * h);
        assert!((suv - cross).length() < 1e-5);
    }

    #[test]
    fn a_polynomial_surface_is_g2_and_a_flat_one_reads_zero() {
        let r = g2_report(&paraboloid(3, 3), 9);
        assert_eq!(r.seams.len(), 2 * 2 * 3);
        assert!(r.max_relative < 1e-9 && r.max_absolute < 1e-9, "{r:?}");
        let r = g2_report(&plane(3, 3), 9);
        assert_eq!((r.max_relative, r.max_absolute), (0.0, 0.0));
    }

    #[test]
    fn a_curvature_jump_is_found_on_its_seams() {
        let mut g = paraboloid(4, 2);
        // Column a = 5 (patch 1's third control column): its second derivatives at both its
        // sides change, G1 stays (the rows across the lines are untouched).
        let (_, lb) = g.lattice_size();
        let changes: Vec<(usize, DVec3)> = (0..lb)
            .map(|b| {
                let id = g.node_id(5, b as isize).unwrap_or_else(|| unreachable!());
                (id, g.nodes()[id] + DVec3::Z * 0.2)
            })
            .collect();
        g.set_nodes(&changes).unwrap_or_else(|e| panic!("{e}"));
        let r = g2_report(&g, 9);
        let worst = r.worst(4);
        assert!(worst[0].relative > 0.05, "{worst:?}");
        for s in &worst[..4] {
            assert!(s.direction == "u" && (s.line == 1 || s.line == 2), "{s:?}");
        }
        for s in r.seams.iter().filter(|s| s.direction == "u" && s.line == 3) {
            assert!(s.relative < 1e-9, "{s:?}");
        }
    }

    #[test]
    fn the_sphere_primitive_is_near_g2_with_curvature_near_one_over_r() {
        let g = Primitive::Sphere
            .build(&PrimitiveParams::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let r = g2_report(&g, 9);
        assert!(r.max_relative < 0.1, "{}", r.max_relative);
        assert_eq!(r.poles.len(), 2);
        for p in &r.poles {
            // Outward normals: a sphere curves away, κ ≈ −1/R on both principal directions.
            assert!(p.principal.0 < 0.0 && p.principal.1 < 0.0, "{p:?}");
        }
    }
}
