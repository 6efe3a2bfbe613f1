//! Regulation of a pole: the first ring onto a fitted tangent plane through the pole.
//!
//! At a pole the first ring must lie in one plane through the pole (then every derivative out
//! of the pole lies in it, and the normal's limit is the same from every side), and each ring
//! triple crossing a meridian keeps its line's ratio. With the plane's normal `n` fixed the
//! conditions are linear again, so `n` is chosen first, as the one that makes the total
//! least-squares displacement smallest: with `d_a = R_a − O` the ring points relative to the
//! pole and `e_k` the defect `ρ_k R₋ − (1 + ρ_k) R₀ + R₊` of meridian `k`'s triple,
//! `cost(n) = Σ (n·d_a)² + Σ (|e_k|² − (n·e_k)²) / |c_k|²` (`c_k = (ρ_k, −1−ρ_k, 1)`), whose
//! minimiser is the eigenvector of the smallest eigenvalue of
//! `Σ d_a d_aᵀ − Σ e_k e_kᵀ / |c_k|²`. Then the ring is projected onto the plane and each
//! triple onto its ratio constraint (this projection is in the plain control-point metric).
//! The pole itself stays (it is the sample on the finger's axis when the pole is pushed, and
//! every patch around it shares it).

use glam::DVec3;

use crate::surface::plane_fit::symmetric_eigen;
use crate::surface::regulate::PolePoints;

/// Regulates a pole: the first ring onto the least-squares tangent plane through the pole,
/// and every meridian's ring triple onto its ratio (`ratios[k]` for meridian `k`).
pub fn regulate_pole(p: &mut PolePoints, ratios: &[f64]) -> bool {
    let len = p.ring.len();
    if len < 6 || !len.is_multiple_of(3) || ratios.len() != len / 3 {
        return false;
    }
    let o = p.pole;
    let at = |a: isize| (a.rem_euclid(len as isize)) as usize;
    let defect = |ring: &[DVec3], k: usize| {
        let a = 3 * k as isize;
        let rho = ratios[k];
        ring[at(a - 1)] * rho - ring[at(a)] * (1.0 + rho) + ring[at(a + 1)]
    };
    let coeff_sq = |rho: f64| rho * rho + (1.0 + rho) * (1.0 + rho) + 1.0;
    // The tangent-plane normal minimising the total displacement.
    let mut s = [[0.0f64; 3]; 3];
    for &x in &p.ring {
        let d = x - o;
        add_outer(&mut s, d, 1.0);
    }
    for k in 0..len / 3 {
        add_outer(&mut s, defect(&p.ring, k), -1.0 / coeff_sq(ratios[k]));
    }
    let n = symmetric_eigen(s).1[0];
    // Onto the plane, then each triple onto its constraint (within the plane).
    for x in &mut p.ring {
        *x -= n * n.dot(*x - o);
    }
    for k in 0..len / 3 {
        let e = defect(&p.ring, k);
        let rho = ratios[k];
        let c = [rho, -(1.0 + rho), 1.0];
        let q = e / coeff_sq(rho);
        let a = 3 * k as isize;
        for (i, ci) in c.iter().enumerate() {
            p.ring[at(a - 1 + i as isize)] -= q * *ci;
        }
    }
    true
}

fn add_outer(m: &mut [[f64; 3]; 3], v: DVec3, w: f64) {
    let a = v.to_array();
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] += w * a[i] * a[j];
        }
    }
}
