//! Cholesky factorisation of a symmetric positive definite matrix in skyline (envelope)
//! storage, and the solve with its factor: the linear algebra of the coupled projection, whose
//! groups are ordered so that the envelope is about one grid row of groups wide.

use glam::DVec3;

/// In-place Cholesky factorisation `A = L Lᵀ` of a symmetric matrix in skyline storage (row
/// `r`: columns `first[r] ..= r` at `data[start[r]..]`); the envelope holds the factor (no fill
/// outside it). `false` when a pivot is not positive (relative to the diagonal's scale).
pub(super) fn skyline_cholesky(first: &[usize], start: &[usize], data: &mut [f64]) -> bool {
    let rows = first.len();
    let scale = (0..rows).fold(0.0f64, |m, r| m.max(data[start[r] + r - first[r]]));
    for r in 0..rows {
        let (fr, sr) = (first[r], start[r]);
        for c in fr..=r {
            let (fc, sc) = (first[c], start[c]);
            let lo = fr.max(fc);
            let mut sum = data[sr + c - fr];
            for k in lo..c {
                sum -= data[sr + k - fr] * data[sc + k - fc];
            }
            if c == r {
                if sum.is_nan() || sum <= 1e-13 * scale {
                    return false;
                }
                data[sr + c - fr] = sum.sqrt();
            } else {
                data[sr + c - fr] = sum / data[sc + c - fc];
            }
        }
    }
    true
}

/// Solves `L Lᵀ x = b` in place for a skyline factor of [`skyline_cholesky`] (three
/// right-hand sides at once, one per coordinate).
pub(super) fn skyline_solve(first: &[usize], start: &[usize], l: &[f64], b: &mut [DVec3]) {
    let rows = first.len();
    for r in 0..rows {
        let (fr, sr) = (first[r], start[r]);
        // Row r of the factor: columns fr..r, then the diagonal.
        let (row, diag) = l[sr..=sr + r - fr].split_at(r - fr);
        let (done, rest) = b.split_at_mut(r);
        let mut sum = rest[0];
        for (x, &w) in done[fr..].iter().zip(row) {
            sum -= *x * w;
        }
        rest[0] = sum / diag[0];
    }
    for r in (0..rows).rev() {
        let (fr, sr) = (first[r], start[r]);
        let (row, diag) = l[sr..=sr + r - fr].split_at(r - fr);
        let (todo, rest) = b.split_at_mut(r);
        let x = rest[0] / diag[0];
        rest[0] = x;
        for (y, &w) in todo[fr..].iter_mut().zip(row) {
            *y -= x * w;
        }
    }
}
