//! Best-fit planes through a point: the eigenvector of the smallest eigenvalue of a symmetric
//! 3 × 3 matrix, by [`nalgebra::SymmetricEigen`] (Householder tridiagonalisation and implicit
//! QR; robust for repeated eigenvalues, deterministic).

use glam::DVec3;
use nalgebra::{Matrix3, SymmetricEigen};

/// Most implicit QR iterations [`symmetric_eigen`] allows; a finite 3 × 3 matrix converges in a
/// handful.
const MAX_ITERATIONS: usize = 1000;

/// Eigenvalues and unit eigenvectors of a symmetric 3 × 3 matrix, sorted by increasing
/// eigenvalue. Only the upper triangle of `a` is read.
///
/// A matrix with a NaN or infinite entry has no decomposition: its eigenvalues are NaN and its
/// eigenvectors the coordinate axes.
#[must_use]
pub fn symmetric_eigen(a: [[f64; 3]; 3]) -> ([f64; 3], [DVec3; 3]) {
    let m = Matrix3::from_fn(|i, j| if i <= j { a[i][j] } else { a[j][i] });
    let fallback = ([f64::NAN; 3], [DVec3::X, DVec3::Y, DVec3::Z]);
    if !m.iter().all(|v| v.is_finite()) {
        return fallback;
    }
    let Some(eigen) = SymmetricEigen::try_new(m, f64::EPSILON, MAX_ITERATIONS) else {
        return fallback;
    };
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
    let values = order.map(|i| eigen.eigenvalues[i]);
    let vectors = order.map(|i| {
        let c = eigen.eigenvectors.column(i);
        DVec3::new(c[0], c[1], c[2]).normalize_or(DVec3::Z)
    });
    (values, vectors)
}

/// The unit normal `n` minimising `Σ (n·d_k)²` over the given vectors: the normal of the
/// best-fit plane through the origin. `None` without a non-zero vector.
#[must_use]
pub fn plane_normal(vectors: impl IntoIterator<Item = DVec3>) -> Option<DVec3> {
    let mut a = [[0.0; 3]; 3];
    let mut any = false;
    for d in vectors {
        any |= d != DVec3::ZERO;
        for i in 0..3 {
            for j in i..3 {
                a[i][j] += d[i] * d[j];
            }
        }
    }
    if !any {
        return None;
    }
    Some(symmetric_eigen(a).1[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_decomposition_reconstructs_the_matrix() {
        let a = [[4.0, 1.0, -2.0], [1.0, 3.0, 0.5], [-2.0, 0.5, 1.0]];
        let (l, v) = symmetric_eigen(a);
        assert!(l[0] <= l[1] && l[1] <= l[2]);
        for k in 0..3 {
            let x = v[k];
            let ax = DVec3::new(
                a[0][0] * x.x + a[0][1] * x.y + a[0][2] * x.z,
                a[1][0] * x.x + a[1][1] * x.y + a[1][2] * x.z,
                a[2][0] * x.x + a[2][1] * x.y + a[2][2] * x.z,
            );
            assert!((ax - x * l[k]).length() < 1e-13);
        }
        assert!((v[0].dot(v[1])).abs() < 1e-14);
    }

    #[test]
    fn repeated_eigenvalues_and_non_finite_matrices() {
        // diag(2, 1, 1): a repeated eigenvalue still gives an orthonormal basis.
        let (l, v) = symmetric_eigen([[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        assert_eq!(l, [1.0, 1.0, 2.0]);
        assert!(v[2].cross(DVec3::X).length() < 1e-15);
        assert!(v[0].dot(v[1]).abs() < 1e-15 && v[0].dot(DVec3::X).abs() < 1e-15);
        // The lower triangle is not read.
        let upper = symmetric_eigen([[4.0, 1.0, -2.0], [99.0, 3.0, 0.5], [7.0, -3.0, 1.0]]);
        let full = symmetric_eigen([[4.0, 1.0, -2.0], [1.0, 3.0, 0.5], [-2.0, 0.5, 1.0]]);
        assert_eq!(upper, full);
        let (l, v) = symmetric_eigen([[f64::NAN, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        assert!(l.iter().all(|x| x.is_nan()));
        assert_eq!(v, [DVec3::X, DVec3::Y, DVec3::Z]);
    }

    #[test]
    fn plane_normal_of_coplanar_vectors_is_exact() {
        let n = DVec3::new(0.3, -0.5, 0.8).normalize();
        let t1 = n.any_orthonormal_vector();
        let t2 = n.cross(t1);
        let vs: Vec<DVec3> = (0..12)
            .map(|k| t1 * (k as f64).cos() * 2.0 + t2 * (k as f64).sin())
            .collect();
        let got = plane_normal(vs).unwrap();
        assert!(got.cross(n).length() < 1e-14);
    }
}
