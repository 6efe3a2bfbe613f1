//! One grid direction of the `g2` regulation: the projection of a line of control points onto
//! the piecewise cubics that are curvature-continuous at every seam inside a window.
//!
//! Along one lattice row, a seam at node `p` joins two Bezier segments whose widths have the
//! fixed ratio `ρ` (the grid line's reference spacing ratio, what `exact` keeps). With
//! `b₋₂ … b₂` the five nodes around it, the conditions are
//!
//! ```text
//! G1:  ρ b₋₁ − (1 + ρ) b₀ + b₁ = 0
//! G2:  (b₂ − 2b₁ + b₀) = ρ² (b₀ − 2b₋₁ + b₋₂) + α (b₀ − b₋₁)
//! ```
//!
//! (with `D₁ = 3(b₁ − b₀)` and `D₂ = 6(b₂ − 2b₁ + b₀)`: `D₂⁺ = ρ² D₂⁻ + 2α D₁⁻`, the two sides
//! C2 after the quadratic reparametrisation `s ↦ ρ s + α s²` — Farin's β-constraints; with
//! `α = 0` the row is the Bezier form of one C2 cubic spline whose knot spacing is the
//! patches' widths). `α` is one number per grid line, the same for every row crossing it
//! (see [`super`]).
//!
//! The window's nodes are free or fixed; the constraints are those whose stencil holds a free
//! node. Among the rows satisfying them, with the fixed nodes where they are, the projection
//! returns the one nearest the target in `Σ_s ∫₀¹ |Δc_s|²` over the window's segments (per
//! segment `δᵀ m δ`, `m_ik = ∫ B_i³ B_k³`, the metric of `exact`). With `C = [C_f C_x]` split
//! by free and fixed nodes, `N` a basis of `ker C_f`, `M` the metric on the free nodes:
//!
//! ```text
//! x_f = G t_f + H x_x,   G = N (Nᵀ M N)⁻¹ Nᵀ M,   H = −(I − G) C_f⁺ C_x
//! ```
//!
//! (the minimum-norm particular solution `−C_f⁺ C_x x_x`, then the metric projection of what
//! is left onto `ker C_f`). Both matrices are built once per window and applied to every row.

use glam::DVec3;
use nalgebra::{DMatrix, SVD};

/// The Bernstein Gram matrix of one segment, `m_ik = C(3,i) C(3,k) / (7 C(6,i+k))`.
const GRAM: [[f64; 4]; 4] = [
    [1.0 / 7.0, 1.0 / 14.0, 1.0 / 35.0, 1.0 / 140.0],
    [1.0 / 14.0, 3.0 / 35.0, 9.0 / 140.0, 1.0 / 35.0],
    [1.0 / 35.0, 9.0 / 140.0, 3.0 / 35.0, 1.0 / 14.0],
    [1.0 / 140.0, 1.0 / 35.0, 1.0 / 14.0, 1.0 / 7.0],
];

/// A seam inside the window: its node's position, the line's ratio `ρ` and `α`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Seam {
    pub position: usize,
    pub rho: f64,
    pub alpha: f64,
}

/// The G1 and G2 stencils on `b₋₂ … b₂` of a seam (see the module docs).
#[must_use]
pub(super) fn stencils(rho: f64, alpha: f64) -> [[f64; 5]; 2] {
    let r2 = rho * rho;
    [
        [0.0, rho, -(1.0 + rho), 1.0, 0.0],
        [-r2, 2.0 * r2 + alpha, 1.0 - r2 - alpha, -2.0, 1.0],
    ]
}

/// The window of one direction, as the projection needs it.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Window {
    /// Nodes in the window.
    pub len: usize,
    /// Whether the window is a whole closed loop (positions taken modulo `len`).
    pub cyclic: bool,
    /// Per position: free (may move) or fixed.
    pub free: Vec<bool>,
    /// The segments `[3s', 3s' + 3]` (by their first position) the metric sums over.
    pub segments: Vec<usize>,
    /// The seams whose conditions apply.
    pub seams: Vec<Seam>,
}

/// Why a window's projection could not be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum LineFailure {
    /// The metric restricted to the admissible rows is not positive definite.
    Singular,
}

/// The projection of one direction (see the module docs).
#[derive(Debug, Clone)]
pub(super) struct LineProjection {
    /// Free positions, in order.
    pub free: Vec<usize>,
    /// Fixed positions, in order.
    pub fixed: Vec<usize>,
    g: DMatrix<f64>,
    h: DMatrix<f64>,
}

impl LineProjection {
    /// Builds the projection of `w`.
    pub(super) fn new(w: &Window) -> Result<Self, LineFailure> {
        let free: Vec<usize> = (0..w.len).filter(|&i| w.free[i]).collect();
        let fixed: Vec<usize> = (0..w.len).filter(|&i| !w.free[i]).collect();
        let mut col_of = vec![(false, 0usize); w.len];
        for (c, &i) in free.iter().enumerate() {
            col_of[i] = (true, c);
        }
        for (c, &i) in fixed.iter().enumerate() {
            col_of[i] = (false, c);
        }
        let (nf, nx) = (free.len(), fixed.len());
        // Constraint rows with at least one free node.
        let mut cf_rows: Vec<Vec<f64>> = Vec::new();
        let mut cx_rows: Vec<Vec<f64>> = Vec::new();
        for seam in &w.seams {
            for st in stencils(seam.rho, seam.alpha) {
                let mut rf = vec![0.0; nf];
                let mut rx = vec![0.0; nx];
                let mut any = false;
                for (k, &c) in st.iter().enumerate() {
                    if c == 0.0 {
                        continue;
                    }
                    let p = seam.position as isize + k as isize - 2;
                    let p = if w.cyclic {
                        p.rem_euclid(w.len as isize) as usize
                    } else if p < 0 || p >= w.len as isize {
                        continue;
                    } else {
                        p as usize
                    };
                    let (is_free, c_idx) = col_of[p];
                    if is_free {
                        rf[c_idx] += c;
                        any = true;
                    } else {
                        rx[c_idx] += c;
                    }
                }
                if any {
                    cf_rows.push(rf);
                    cx_rows.push(rx);
                }
            }
        }
        // The metric on the free nodes.
        let mut m = DMatrix::<f64>::zeros(nf, nf);
        for &s in &w.segments {
            for i in 0..4 {
                for k in 0..4 {
                    let (pi, pk) = ((s + i) % w.len, (s + k) % w.len);
                    if let ((true, ci), (true, ck)) = (col_of[pi], col_of[pk]) {
                        m[(ci, ck)] += GRAM[i][k];
                    }
                }
            }
        }
        let rows = cf_rows.len();
        let (null, pinv) = if rows == 0 {
            (
                DMatrix::<f64>::identity(nf, nf),
                DMatrix::<f64>::zeros(nf, 0),
            )
        } else {
            // Padded to at least square, so that the thin SVD gives the whole null space.
            let height = rows.max(nf);
            let mut cf = DMatrix::<f64>::zeros(height, nf);
            for (r, row) in cf_rows.iter().enumerate() {
                for (c, &x) in row.iter().enumerate() {
                    cf[(r, c)] = x;
                }
            }
            let svd = SVD::new(cf, true, true);
            let (Some(u), Some(vt)) = (svd.u.as_ref(), svd.v_t.as_ref()) else {
                return Err(LineFailure::Singular);
            };
            let largest = svd.singular_values.max();
            let tol = 1e-10 * largest.max(f64::MIN_POSITIVE);
            let kept: Vec<usize> = (0..svd.singular_values.len())
                .filter(|&i| svd.singular_values[i] > tol)
                .collect();
            let nulls: Vec<usize> = (0..vt.nrows())
                .filter(|&i| svd.singular_values[i] <= tol)
                .collect();
            let mut null = DMatrix::<f64>::zeros(nf, nulls.len());
            for (c, &i) in nulls.iter().enumerate() {
                for r in 0..nf {
                    null[(r, c)] = vt[(i, r)];
                }
            }
            // C_f⁺ over the real rows: Σ v_i u_iᵀ / σ_i.
            let mut pinv = DMatrix::<f64>::zeros(nf, rows);
            for &i in &kept {
                let s = svd.singular_values[i];
                for r in 0..nf {
                    for c in 0..rows {
                        pinv[(r, c)] += vt[(i, r)] * u[(c, i)] / s;
                    }
                }
            }
            (null, pinv)
        };
        let mn = &m * &null;
        let gram = null.transpose() * &mn;
        let g = if null.ncols() == 0 {
            DMatrix::<f64>::zeros(nf, nf)
        } else {
            let Some(ch) = gram.cholesky() else {
                return Err(LineFailure::Singular);
            };
            &null * ch.solve(&mn.transpose())
        };
        let mut cx = DMatrix::<f64>::zeros(rows, nx);
        for (r, row) in cx_rows.iter().enumerate() {
            for (c, &x) in row.iter().enumerate() {
                cx[(r, c)] = x;
            }
        }
        let rest = DMatrix::<f64>::identity(nf, nf) - &g;
        let h = if rows == 0 {
            DMatrix::<f64>::zeros(nf, nx)
        } else {
            -(rest * (pinv * cx))
        };
        if g.iter().chain(h.iter()).any(|x| !x.is_finite()) {
            return Err(LineFailure::Singular);
        }
        Ok(Self { free, fixed, g, h })
    }

    /// The projected row: `row` holds the target on the free positions and the fixed values
    /// on the fixed ones; the free positions are overwritten.
    pub(super) fn apply(&self, row: &mut [DVec3], scratch: &mut Vec<DVec3>) {
        scratch.clear();
        for (i, _) in self.free.iter().enumerate() {
            let mut x = DVec3::ZERO;
            for (j, &pj) in self.free.iter().enumerate() {
                x += row[pj] * self.g[(i, j)];
            }
            for (k, &pk) in self.fixed.iter().enumerate() {
                x += row[pk] * self.h[(i, k)];
            }
            scratch.push(x);
        }
        for (&p, &x) in self.free.iter().zip(scratch.iter()) {
            row[p] = x;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The residual of every seam's conditions on `row`.
    fn residual(w: &Window, row: &[DVec3]) -> f64 {
        let mut worst = 0.0f64;
        for s in &w.seams {
            for st in stencils(s.rho, s.alpha) {
                let mut r = DVec3::ZERO;
                for (k, &c) in st.iter().enumerate() {
                    let p = (s.position + w.len + k - 2) % w.len;
                    r += row[p] * c;
                }
                worst = worst.max(r.length());
            }
        }
        worst
    }

    fn random_row(rng: &mut ChaCha8Rng, len: usize) -> Vec<DVec3> {
        (0..len)
            .map(|_| DVec3::new(rng.r#gen(), rng.r#gen(), rng.r#gen()) * 2.0 - DVec3::ONE)
            .collect()
    }

    #[test]
    fn a_closed_loop_projects_onto_its_conditions_and_keeps_what_meets_them() {
        let mut rng = ChaCha8Rng::seed_from_u64(29);
        let segs = 6;
        let len = 3 * segs;
        let w = Window {
            len,
            cyclic: true,
            free: vec![true; len],
            segments: (0..segs).map(|s| 3 * s).collect(),
            seams: (0..segs)
                .map(|k| Seam {
                    position: 3 * k,
                    rho: 1.0 + 0.1 * k as f64,
                    alpha: 0.0,
                })
                .collect(),
        };
        // Ratios around a loop must multiply to 1 for a C2 loop to exist with them; with
        // arbitrary ratios the projection still satisfies the conditions (a smaller space).
        let p = LineProjection::new(&w).unwrap();
        let mut row = random_row(&mut rng, len);
        let mut scratch = Vec::new();
        p.apply(&mut row, &mut scratch);
        assert!(residual(&w, &row) < 1e-12, "{}", residual(&w, &row));
        // A projection: applying it again changes nothing.
        let again = {
            let mut r = row.clone();
            p.apply(&mut r, &mut scratch);
            r
        };
        for (a, b) in row.iter().zip(&again) {
            assert!((*a - *b).length() < 1e-12);
        }
    }

    #[test]
    fn an_open_window_keeps_its_fixed_nodes_and_meets_the_seams_at_its_ends() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        // Segments 0..8, window nodes 0..=24; nodes 0..=4 and 20..=24 fixed.
        let len = 25;
        let free: Vec<bool> = (0..len).map(|i| (5..20).contains(&i)).collect();
        let seams: Vec<Seam> = (1..8)
            .map(|k| Seam {
                position: 3 * k,
                rho: 1.0,
                alpha: 0.0,
            })
            .collect();
        let w = Window {
            len,
            cyclic: false,
            free,
            segments: (0..8).map(|s| 3 * s).collect(),
            seams,
        };
        // A C2 row to start from: a cubic in the global parameter, uniform knots, in Bezier
        // form (node 3s + i is the blossom at s (3 − i times) and s + 1 (i times)).
        let base: Vec<DVec3> = (0..len)
            .map(|a| {
                let (s, i) = ((a / 3) as f64, a % 3);
                let x: Vec<f64> = (0..3)
                    .map(|k| if k < 3 - i { s } else { s + 1.0 })
                    .collect();
                let b1 = (x[0] + x[1] + x[2]) / 3.0;
                let b2 = (x[0] * x[1] + x[0] * x[2] + x[1] * x[2]) / 3.0;
                let b3 = x[0] * x[1] * x[2];
                DVec3::new(b1, 0.1 * b2, 0.01 * b3)
            })
            .collect();
        assert!(residual(&w, &base) < 1e-12);
        let p = LineProjection::new(&w).unwrap();
        let mut row = base.clone();
        for x in &mut row[5..20] {
            *x += DVec3::new(rng.r#gen(), rng.r#gen(), rng.r#gen()) * 0.3;
        }
        let mut scratch = Vec::new();
        p.apply(&mut row, &mut scratch);
        assert!(residual(&w, &row) < 1e-12, "{}", residual(&w, &row));
        for i in (0..5).chain(20..25) {
            assert_eq!(row[i], base[i]);
        }
    }
}
