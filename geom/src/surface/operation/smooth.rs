//! Smoothing: a damped descent step on the **thin-plate energy** of the control points within
//! the brush's reach.
//!
//! The energy of a grid is the sum over its patches of
//!
//! ```text
//! E_p = ∫₀¹∫₀¹ |S_uu|² + 2|S_uv|² + |S_vv|²  du dv  =  Σ_ab H_ab (P_a · P_b),
//! H_(ij)(kl) = A″_ik M_jl + 2 A′_ik A′_jl + M_ik A″_jl,
//! ```
//!
//! with `M_ik = ∫ B_i B_k`, `A′_ik = ∫ B_i′ B_k′`, `A″_ik = ∫ B_i″ B_k″` over `[0, 1]` (cubic
//! Bernstein polynomials; computed exactly by 4-point Gauss–Legendre quadrature). It is a
//! quadratic form in the control points, its gradient `g_n = 2 Σ_p Σ_{a=n} (H X_p)_a` summed over
//! the patches holding node `n`.
//!
//! A stroke `{"op":"smooth","at":A,"radius":r,"strength":s}` moves each control point `n`
//! within `r` of `A` by
//!
//! ```text
//! d_n = − (s/2) · f_n · g_n / D_n,     f_n = 1 − |P_n − A|²/r²,   D_n = Σ_p Σ_{a=n} Σ_b |H_ab|
//! ```
//!
//! `diag(D) − H` is diagonally dominant with a non-negative diagonal, so `H ≤ diag(D)`, and
//! with `F = diag(f) ≤ I`: `E(X + d) ≤ E − (s/2)(1 − s/2) gᵀ F D⁻¹ g` — the step lowers the
//! energy for every `0 < s ≤ 1` and moves nothing as `s → 0`. The regulation then restores G1
//! (it may give a little back): the operation measures the energy of the touched patches
//! before and after the whole stroke, and when it did not drop it halves the step (up to
//! [`HALVINGS`] times) or, failing that, leaves the grid as it was.
//!
//! The energy is parametric (it measures the control net's bending in `(u, v)`, not the
//! surface's curvature): like every smoothing brush it also shrinks what it flattens.

// Per-coordinate and per-slot loops index several small fixed arrays at once; the index
// form follows the formulas.
#![allow(clippy::needless_range_loop)]

use glam::DVec3;

use crate::surface::grid::Grid;
use crate::surface::marks::Marks;
use crate::surface::patch::PatchPoints;

/// How many times a stroke's step is halved when the regulated result does not lower the
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

/// One damped thin-plate step over the control points within `radius` of the centres (the
/// stroke's point and, with a mirror, its mirror image): every node `x` moves by
/// `−½ · step · f(x) · g / d`, with `g = ∂E/∂x` the thin-plate gradient summed over the
/// patches holding it, `d = Σ |H_a|₁` the bound of its rows (so `step ≤ 1` cannot overshoot
/// along any one node), and `f(x) = max(0, 1 − |x − c|²/r²)` the falloff from the nearest
/// centre. Keeps its scratch between steps.
#[derive(Debug, Clone, Default)]
pub(crate) struct ThinPlateStep {
    nodes: Marks,
    /// Per node: thin-plate gradient and its bound.
    grad: Vec<(DVec3, f64)>,
    /// The patches within reach of the last step.
    pub(crate) candidates: Vec<usize>,
}

impl ThinPlateStep {
    /// The per-patch control-point updates of one step, into `updates` (patches whose
    /// update is all zero are left out).
    // The slot loops index the patch's points, ids and the matrix rows together.
    #[allow(clippy::needless_range_loop)]
    pub(crate) fn updates(
        &mut self,
        grid: &Grid,
        h: &[[f64; 16]; 16],
        centres: &[DVec3],
        radius: f64,
        step: f64,
        updates: &mut Vec<(usize, [DVec3; 16])>,
    ) {
        self.candidates.clear();
        grid.hierarchy().query(
            &|b| {
                centres.iter().any(|c| {
                    let d = (b.min - *c).max(*c - b.max).max(DVec3::ZERO);
                    d.length() <= radius
                })
            },
            &mut self.candidates,
        );
        self.candidates.sort_unstable();
        let len = grid.nodes().len();
        if self.grad.len() != len {
            self.grad = vec![(DVec3::ZERO, 0.0); len];
        }
        self.nodes.start(len);
        let m = grid.patches_u();
        let row_abs: [f64; 16] = std::array::from_fn(|a| h[a].iter().map(|x| x.abs()).sum());
        // Gradient and bound per node over every patch holding it (all are candidates: a
        // node within reach lies in the box of every patch holding it).
        for &p in &self.candidates {
            let ids = grid.patch_node_ids(p % m, p / m);
            let x = grid.patch_at(p);
            for a in 0..16 {
                let mut y = DVec3::ZERO;
                for b in 0..16 {
                    y += x[b] * h[a][b];
                }
                let id = ids[a];
                if self.nodes.mark(id) {
                    self.grad[id] = (DVec3::ZERO, 0.0);
                }
                self.grad[id].0 += 2.0 * y;
                self.grad[id].1 += row_abs[a];
            }
        }
        let r2 = radius * radius;
        let nodes = grid.nodes();
        let delta_of = |id: usize, grad: &[(DVec3, f64)]| {
            let f = centres
                .iter()
                .map(|c| 1.0 - (nodes[id] - *c).length_squared() / r2)
                .fold(0.0f64, f64::max);
            let (g, d) = grad[id];
            if f > 0.0 && d > 0.0 {
                g * (-0.5 * step * f / d)
            } else {
                DVec3::ZERO
            }
        };
        updates.clear();
        for &p in &self.candidates {
            let ids = grid.patch_node_ids(p % m, p / m);
            let delta: [DVec3; 16] = std::array::from_fn(|a| delta_of(ids[a], &self.grad));
            if delta.iter().any(|d| *d != DVec3::ZERO) {
                updates.push((p, delta));
            }
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
