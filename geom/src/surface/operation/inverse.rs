//! The Bernstein inverse mapping (P2 §2.2, eq. (1)–(2); docs/design.md §11).
//!
//! A patch is sampled at the 16 parameters `(u_a, v_b)`, `u_a, v_b ∈ {0, 1/3, 2/3, 1}`:
//! `R = B P`, with the 16 × 16 Bernstein matrix `B = B₄ ⊗ B₄` (Kronecker product of the 4 × 4
//! matrix `B₄[a][i] = B_i³(u_a)`). Every sample moves by its flow vector `F_ab` towards the
//! ideal shape, and the control points follow as `P' = P + B⁻¹ F`, so that the new patch passes
//! exactly through the moved samples. By the Kronecker structure `B⁻¹ = B₄⁻¹ ⊗ B₄⁻¹`, so with
//! the 16 points arranged as a 4 × 4 array the update is `ΔP = B₄⁻¹ F B₄⁻ᵀ` — two products with
//! a constant 4 × 4 matrix, no 16 × 16 solve:
//!
//! ```text
//!          ⎡   1     0     0     0  ⎤
//! B₄⁻¹  =  ⎢ −5/6    3   −3/2   1/3 ⎥
//!          ⎢  1/3  −3/2    3  −5/6  ⎥
//!          ⎣   0     0     0     1  ⎦
//! ```
//!
//! Rows 0 and 3 of `B₄⁻¹` are unit rows: a boundary control point's update depends only on the
//! samples of that boundary, and a corner's only on the corner sample. Two patches sharing an
//! edge therefore compute bit-identical updates for it (both code paths below copy the
//! boundary values rather than multiply them by 0 and 1).

use glam::DVec3;

use crate::surface::patch::PatchPoints;

/// The sample parameters `{0, 1/3, 2/3, 1}` along each direction.
pub const SAMPLE_PARAMS: [f64; 4] = [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0];

/// `B₄[a][i] = B_i³(u_a)` at [`SAMPLE_PARAMS`].
pub const SAMPLE_MATRIX: [[f64; 4]; 4] = [
    [1.0, 0.0, 0.0, 0.0],
    [8.0 / 27.0, 12.0 / 27.0, 6.0 / 27.0, 1.0 / 27.0],
    [1.0 / 27.0, 6.0 / 27.0, 12.0 / 27.0, 8.0 / 27.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// `B₄⁻¹`, exactly (see the module docs).
pub const INVERSE_MATRIX: [[f64; 4]; 4] = [
    [1.0, 0.0, 0.0, 0.0],
    [-5.0 / 6.0, 3.0, -1.5, 1.0 / 3.0],
    [1.0 / 3.0, -1.5, 3.0, -5.0 / 6.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// `Σ_k m[k] x[k]` for an interior row of a 4 × 4 matrix (whose entries sum to one), exact
/// when the four points are equal (at a pole).
#[inline]
fn row(m: &[f64; 4], x: [DVec3; 4]) -> DVec3 {
    if x[0] == x[1] && x[1] == x[2] && x[2] == x[3] {
        return x[0];
    }
    x[0] * m[0] + x[1] * m[1] + x[2] * m[2] + x[3] * m[3]
}

/// Applies `M` on the left of a 4-vector of points, copying rows 0 and 3 (unit rows).
#[inline]
fn apply4(m: &[[f64; 4]; 4], x: [DVec3; 4]) -> [DVec3; 4] {
    [x[0], row(&m[1], x), row(&m[2], x), x[3]]
}

/// `M X Mᵀ` on a 4 × 4 array of points stored as `x[4*i + j]`, for a matrix with unit first
/// and last rows.
#[inline]
fn sandwich(m: &[[f64; 4]; 4], x: &[DVec3; 16]) -> [DVec3; 16] {
    // Along j (the second index) for every i, then along i for every j.
    let mut t = [DVec3::ZERO; 16];
    for i in 0..4 {
        let r = apply4(m, [x[4 * i], x[4 * i + 1], x[4 * i + 2], x[4 * i + 3]]);
        t[4 * i..4 * i + 4].copy_from_slice(&r);
    }
    let mut out = [DVec3::ZERO; 16];
    for j in 0..4 {
        let c = apply4(m, [t[j], t[4 + j], t[8 + j], t[12 + j]]);
        for i in 0..4 {
            out[4 * i + j] = c[i];
        }
    }
    out
}

/// The 16 samples `R[4a + b] = S(u_a, v_b)` of a patch: `R = B₄ P B₄ᵀ`.
#[must_use]
pub fn samples(points: &PatchPoints) -> [DVec3; 16] {
    sandwich(&SAMPLE_MATRIX, points)
}

/// The control-point update `ΔP = B₄⁻¹ F B₄⁻ᵀ` that moves sample `R[4a + b]` by
/// `flows[4a + b]` (the result is indexed like the control points, `ΔP[4i + j]`).
#[must_use]
pub fn control_update(flows: &[DVec3; 16]) -> [DVec3; 16] {
    sandwich(&INVERSE_MATRIX, flows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::bernstein::cubic_matrix;
    use crate::surface::patch::Patch;

    #[test]
    fn matrices_match_the_basis_and_invert_each_other() {
        let b = cubic_matrix(SAMPLE_PARAMS);
        for a in 0..4 {
            for i in 0..4 {
                assert!((b[a][i] - SAMPLE_MATRIX[a][i]).abs() < 1e-15);
                let mut id = 0.0;
                for k in 0..4 {
                    id += INVERSE_MATRIX[a][k] * SAMPLE_MATRIX[k][i];
                }
                assert!((id - f64::from(u8::from(a == i))).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn samples_are_patch_evaluations() {
        let mut p = [DVec3::ZERO; 16];
        for (k, x) in p.iter_mut().enumerate() {
            *x = DVec3::new(k as f64 * 0.37, (k * k) as f64 * 0.1, (k as f64).sin());
        }
        let r = samples(&p);
        let patch = Patch::new(p);
        for a in 0..4 {
            for b in 0..4 {
                let want = patch.eval(SAMPLE_PARAMS[a], SAMPLE_PARAMS[b]);
                assert!((r[4 * a + b] - want).length() < 1e-13);
            }
        }
    }

    /// The Kronecker form against a general 16 × 16 solve, by brute force.
    #[test]
    fn update_equals_the_general_16_by_16_solve() {
        // B (16 × 16) with B[(a,b),(i,j)] = B₄[a][i] B₄[b][j].
        let mut big = [[0.0f64; 16]; 16];
        for a in 0..4 {
            for b in 0..4 {
                for i in 0..4 {
                    for j in 0..4 {
                        big[4 * a + b][4 * i + j] = SAMPLE_MATRIX[a][i] * SAMPLE_MATRIX[b][j];
                    }
                }
            }
        }
        let mut f = [DVec3::ZERO; 16];
        for (k, x) in f.iter_mut().enumerate() {
            *x = DVec3::new((k as f64 * 1.3).cos(), k as f64 * 0.05, -(k as f64).sqrt());
        }
        let dp = control_update(&f);
        // B ΔP must reproduce F.
        for r in 0..16 {
            let mut s = DVec3::ZERO;
            for c in 0..16 {
                s += dp[c] * big[r][c];
            }
            assert!((s - f[r]).length() < 1e-13, "{r}: {s} vs {}", f[r]);
        }
    }
}
