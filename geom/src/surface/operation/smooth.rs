//! The **thin-plate energy** a smoothing stroke lowers: the measure by which the engine
//! accepts a smoothing dab ([`crate::surface::fairing`] moves the surface, the regulation
//! restores G1 and may give a little back; a dab that did not lower the energy of the patches
//! it touched is taken again at half the strength, up to [`HALVINGS`] times, or not at all).
//!
//! The energy of a grid is the sum over its patches of
//!
//! ```text
//! E_p = ∫₀¹∫₀¹ |S_uu|² + 2|S_uv|² + |S_vv|²  du dv  =  Σ_ab H_ab (P_a · P_b),
//! H_(ij)(kl) = A″_ik M_jl + 2 A′_ik A′_jl + M_ik A″_jl,
//! ```
//!
//! with `M_ik = ∫ B_i B_k`, `A′_ik = ∫ B_i′ B_k′`, `A″_ik = ∫ B_i″ B_k″` over `[0, 1]` (cubic
//! Bernstein polynomials; computed exactly by 4-point Gauss–Legendre quadrature), a quadratic
//! form in the control points. It is parametric: it measures the control net's bending in
//! `(u, v)`, not the surface's curvature.

// Per-coordinate and per-slot loops index several small fixed arrays at once; the index
// form follows the formulas.
#![allow(clippy::needless_range_loop)]

use glam::DVec3;

use crate::surface::grid::Grid;
use crate::surface::patch::PatchPoints;

/// How many times a dab's strength is halved when the regulated result does not lower the
/// energy.
pub const HALVINGS: usize = 8;

/// `∫ f g` of polynomials of degree ≤ 7 on `[0, 1]`: Gauss–Legendre nodes and weights.
const GAUSS: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
];

fn basis(t: f64) -> [[f64; 4]; 3] {
    let s = 1.0 - t;
    [
        [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t],
        [
            -3.0 * s * s,
            3.0 * s * s - 6.0 * t * s,
            6.0 * t * s - 3.0 * t * t,
            3.0 * t * t,
        ],
        [6.0 * s, 18.0 * t - 12.0, 6.0 - 18.0 * t, 6.0 * t],
    ]
}

/// `[M, A′, A″]`: the Gram matrices of the cubic Bernstein basis and its derivatives.
fn gram() -> [[[f64; 4]; 4]; 3] {
    let mut g = [[[0.0; 4]; 4]; 3];
    for (x, w) in GAUSS {
        let t = 0.5 * (x + 1.0);
        let b = basis(t);
        for d in 0..3 {
            for i in 0..4 {
                for k in 0..4 {
                    g[d][i][k] += 0.5 * w * b[d][i] * b[d][k];
                }
            }
        }
    }
    g
}

/// The 16 × 16 thin-plate matrix `H` of one patch (indexed like `P[4i + j]`).
#[must_use]
pub fn thin_plate_matrix() -> [[f64; 16]; 16] {
    let [m, a1, a2] = gram();
    let mut h = [[0.0; 16]; 16];
    for i in 0..4 {
        for j in 0..4 {
            for k in 0..4 {
                for l in 0..4 {
                    h[4 * i + j][4 * k + l] =
                        a2[i][k] * m[j][l] + 2.0 * a1[i][k] * a1[j][l] + m[i][k] * a2[j][l];
                }
            }
        }
    }
    h
}

/// The thin-plate energy of one patch (see the module docs).
#[must_use]
pub fn patch_energy(h: &[[f64; 16]; 16], p: &PatchPoints) -> f64 {
    let mut e = 0.0;
    for a in 0..16 {
        let mut y = DVec3::ZERO;
        for b in 0..16 {
            y += p[b] * h[a][b];
        }
        e += p[a].dot(y);
    }
    e
}

/// The thin-plate energy of the listed patches.
#[must_use]
pub fn energy_of(grid: &Grid, patches: &[usize]) -> f64 {
    let h = thin_plate_matrix();
    patches
        .iter()
        .map(|&p| patch_energy(&h, &grid.patch_at(p)))
        .sum()
}

/// The thin-plate energy of the whole grid.
#[must_use]
pub fn thin_plate_energy(grid: &Grid) -> f64 {
    let all: Vec<usize> = (0..grid.patch_count()).collect();
    energy_of(grid, &all)
}

/// What the last smoothing stroke did to the energy of the patches it touched.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EnergyDrop {
    /// Thin-plate energy of the touched patches before the stroke.
    pub before: f64,
    /// After it (regulated).
    pub after: f64,
    /// How many times the step was halved.
    pub halvings: usize,
}

impl EnergyDrop {
    /// `(before − after) / before` (0 when there was no energy).
    #[must_use]
    pub fn relative(&self) -> f64 {
        if self.before > 0.0 {
            (self.before - self.after) / self.before
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::patch::Patch;

    fn wavy() -> PatchPoints {
        let mut p = [DVec3::ZERO; 16];
        for i in 0..4 {
            for j in 0..4 {
                let (x, y) = (i as f64 / 3.0, j as f64 / 3.0);
                p[4 * i + j] = DVec3::new(
                    x + 0.1 * y * y,
                    y + 0.2 * x * y,
                    0.3 * (x * 3.0).sin() * y + 0.1 * ((i * j) % 3) as f64,
                );
            }
        }
        p
    }

    #[test]
    fn the_energy_is_the_integral_of_the_second_derivatives() {
        // Independent reference: second derivatives by central differences of S, midpoint
        // rule on a fine grid.
        let p = wavy();
        let patch = Patch::new(p);
        let (n, h) = (200, 1e-4);
        let mut sum = 0.0;
        for a in 0..n {
            for b in 0..n {
                let (u, v) = ((a as f64 + 0.5) / n as f64, (b as f64 + 0.5) / n as f64);
                let s = |du: f64, dv: f64| patch.eval(u + du, v + dv);
                let suu = (s(h, 0.0) - 2.0 * s(0.0, 0.0) + s(-h, 0.0)) / (h * h);
                let svv = (s(0.0, h) - 2.0 * s(0.0, 0.0) + s(0.0, -h)) / (h * h);
                let suv = (s(h, h) - s(h, -h) - s(-h, h) + s(-h, -h)) / (4.0 * h * h);
                sum += suu.length_squared() + 2.0 * suv.length_squared() + svv.length_squared();
            }
        }
        let want = sum / (n * n) as f64;
        let got = patch_energy(&thin_plate_matrix(), &p);
        assert!((got - want).abs() < 1e-3 * want, "{got} vs {want}");
    }

    #[test]
    fn a_plane_patch_has_no_energy() {
        let mut p = [DVec3::ZERO; 16];
        for i in 0..4 {
            for j in 0..4 {
                p[4 * i + j] = DVec3::new(i as f64, j as f64, 0.5 * i as f64 - 0.2 * j as f64);
            }
        }
        assert!(patch_energy(&thin_plate_matrix(), &p).abs() < 1e-12);
    }
}
