//! Best-fit planes through a point: the eigenvector of the smallest eigenvalue of a symmetric
//! 3 × 3 matrix, by cyclic Jacobi rotations (robust for repeated eigenvalues, deterministic).
//!
//! Kept by hand on purpose: `nalgebra::SymmetricEigen` was tried in its place and the exact pole
//! regulation (`regulate::exact`), which takes its tangent plane from here, then refused a pull
//! of 10 sides at a sphere's pole as folded (67.9°) that this solver regulates to G1 exactly
//! (the verification tests, `surface::verify`). Until that difference is understood, this solver stays.

use glam::DVec3;

/// Eigenvalues and unit eigenvectors of a symmetric 3 × 3 matrix, sorted by increasing
/// eigenvalue. Only the upper triangle of `a` is read.
#[must_use]
#[allow(clippy::needless_range_loop)] // index form follows the textbook rotation
pub fn symmetric_eigen(a: [[f64; 3]; 3]) -> ([f64; 3], [DVec3; 3]) {
    let mut m = a;
    for i in 0..3 {
        for j in 0..i {
            m[i][j] = m[j][i];
        }
    }
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let scale: f64 = m.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    for _sweep in 0..64 {
        let off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
        if off <= (1e-36 * scale * scale).max(f64::MIN_POSITIVE) {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if m[p][q] == 0.0 {
                continue;
            }
            let theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A ← Jᵀ A J with the rotation J in the (p, q) plane.
            for k in 0..3 {
                let (akp, akq) = (m[k][p], m[k][q]);
                m[k][p] = c * akp - s * akq;
                m[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (m[p][k], m[q][k]);
                m[p][k] = c * apk - s * aqk;
                m[q][k] = s * apk + c * aqk;
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| m[i][i].total_cmp(&m[j][j]));
    let values = order.map(|i| m[i][i]);
    let vectors = order.map(|i| DVec3::new(v[0][i], v[1][i], v[2][i]).normalize_or(DVec3::Z));
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
