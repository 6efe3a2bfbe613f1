//! The group-by-group projection ([`Projection`]): each group alone, its neighbours held, onto
//! the bilinear lattice with its reference spacing ratios, nearest in the surface metric over
//! its four patches.
//!
//! It is the coupled projection's least squares with the metric made block-diagonal (the
//! former default, kept as the fallback and for comparison): each group alone, its neighbours held, over its four patches (for its
//! nodes `M[(i,j),(k,l)] = m_ik m_jl` with `i, k ∈ {0, 1}`: `1/7`, `1/14`, `3/35`), a fixed
//! 9 × 9 map per spacing and boundary shape. It stays 1.17 × farther from the ideal dent than
//! the coupled solve ([`super::Coupled`]) and is used only for a set whose factorisation would
//! cost more than the coupled solve's limit (hundreds of groups across: a palm on a finely refined grid,
//! [`crate::surface::regulate_all`] on a large grid) or fail.

use glam::DVec3;

use crate::surface::regulate::GroupPoints;

/// Gram matrix entries `∫₀¹ B_i³ B_k³` for `i, k ∈ {0, 1}` (the vertex row and the next).
const GRAM: [[f64; 2]; 2] = [[1.0 / 7.0, 1.0 / 14.0], [1.0 / 14.0, 3.0 / 35.0]];

/// The linear map of a group's nine points to their regulated positions: `P'_i = Σ_j Π_ij P_j`
/// over the slots `3(s + 1) + (t + 1)` (zero rows and columns for missing slots). It depends
/// only on the spacing ratios and on which slots exist, so it can be computed once and reused.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    m: [[f64; 9]; 9],
    present: [bool; 9],
}

impl Projection {
    /// The projection for a group with these reference ratios `(ρ_u, ρ_v)` and these slots
    /// (`present[3(s + 1) + (t + 1)]`); `None` when fewer than two patches meet or the
    /// system is singular.
    #[must_use]
    pub fn new(ratios: (f64, f64), present: [bool; 9]) -> Option<Self> {
        let su = [-1.0, 0.0, ratios.0];
        let tv = [-1.0, 0.0, ratios.1];
        let phi = |k: usize| {
            let (s, t) = (k / 3, k % 3);
            [1.0, su[s], tv[t], su[s] * tv[t]]
        };
        // Normal equations A θ = K P for θ = (P_O, a, b, c), K[·][β] = Σ_α w_αβ φ_α.
        let mut a = [[0.0f64; 4]; 4];
        let mut kmat = [[0.0f64; 9]; 4];
        let mut patches = 0;
        for (qs, qt) in [(0usize, 0usize), (2, 0), (0, 2), (2, 2)] {
            // The patch in this quadrant: the slots next to the vertex and their Bernstein
            // indices (0 at the vertex, 1 next to it) along u and v.
            let nodes = [
                (4usize, 0usize, 0usize),
                (3 * qs + 1, 1, 0),
                (3 + qt, 0, 1),
                (3 * qs + qt, 1, 1),
            ];
            if nodes.iter().any(|&(k, _, _)| !present[k]) {
                continue;
            }
            patches += 1;
            for &(k1, i1, j1) in &nodes {
                let f1 = phi(k1);
                for &(k2, i2, j2) in &nodes {
                    let w = GRAM[i1][i2] * GRAM[j1][j2];
                    let f2 = phi(k2);
                    for i in 0..4 {
                        for j in 0..4 {
                            a[i][j] += w * f1[i] * f2[j];
                        }
                        kmat[i][k2] += w * f1[i];
                    }
                }
            }
        }
        if patches < 2 {
            return None;
        }
        let l = cholesky4(a)?;
        let mut m = [[0.0f64; 9]; 9];
        for beta in 0..9 {
            if !present[beta] {
                continue;
            }
            let theta = cholesky_solve(
                &l,
                [kmat[0][beta], kmat[1][beta], kmat[2][beta], kmat[3][beta]],
            );
            for (alpha, row) in m.iter_mut().enumerate() {
                if present[alpha] {
                    let f = phi(alpha);
                    row[beta] =
                        f[0] * theta[0] + f[1] * theta[1] + f[2] * theta[2] + f[3] * theta[3];
                }
            }
        }
        Some(Self { m, present })
    }

    /// Which slots the projection was built for.
    #[must_use]
    pub fn present(&self) -> [bool; 9] {
        self.present
    }

    /// Applies the projection to a group's points.
    pub fn apply(&self, p: &mut GroupPoints) {
        let x: [DVec3; 9] = std::array::from_fn(|k| p[k / 3][k % 3].unwrap_or_default());
        for alpha in 0..9 {
            if self.present[alpha] {
                let row = &self.m[alpha];
                let mut sum = DVec3::ZERO;
                for beta in 0..9 {
                    sum += x[beta] * row[beta];
                }
                p[alpha / 3][alpha % 3] = Some(sum);
            }
        }
    }
}

/// Which slots of a group exist.
#[must_use]
pub fn present(p: &GroupPoints) -> [bool; 9] {
    std::array::from_fn(|k| p[k / 3][k % 3].is_some())
}

/// Regulates one non-degenerate group: the member of the bilinear family with the reference
/// spacing ratios `(ρ_u, ρ_v)` nearest to the group in the surface metric (see the module
/// docs). `false` when there is nothing to fit (fewer than two patches) or the system is
/// singular.
pub fn regulate_group(p: &mut GroupPoints, ratios: (f64, f64)) -> bool {
    match Projection::new(ratios, present(p)) {
        Some(proj) => {
            proj.apply(p);
            true
        }
        None => false,
    }
}

/// The Cholesky factor `L` (`A = L Lᵀ`) of a symmetric 4 × 4 matrix; `None` when it is not
/// (numerically) positive definite.
fn cholesky4(a: [[f64; 4]; 4]) -> Option<[[f64; 4]; 4]> {
    let scale = (0..4).fold(0.0f64, |m, i| m.max(a[i][i]));
    let mut l = [[0.0f64; 4]; 4];
    for i in 0..4 {
        for j in 0..=i {
            let mut sum = a[i][j];
            for k in 0..j {
                sum -= l[i][k] * l[j][k];
            }
            if i == j {
                if sum.is_nan() || sum <= 1e-13 * scale {
                    return None;
                }
                l[i][i] = sum.sqrt();
            } else {
                l[i][j] = sum / l[j][j];
            }
        }
    }
    Some(l)
}

/// Solves `L Lᵀ x = b`.
fn cholesky_solve(l: &[[f64; 4]; 4], b: [f64; 4]) -> [f64; 4] {
    let mut y = [0.0; 4];
    for i in 0..4 {
        let mut sum = b[i];
        for k in 0..i {
            sum -= y[k] * l[i][k];
        }
        y[i] = sum / l[i][i];
    }
    let mut x = [0.0; 4];
    for i in (0..4).rev() {
        let mut sum = y[i];
        for k in i + 1..4 {
            sum -= x[k] * l[k][i];
        }
        x[i] = sum / l[i][i];
    }
    x
}
