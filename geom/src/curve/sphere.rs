//! The parts of a curve inside a probe circle or sphere (P4 §3(1); docs/design.md §4).
//!
//! `e(t,R) = |C(t) − Q|² − R² = Σ_{k=0..2n} d_k B_k^{2n}(t)`, with
//! `d_k = Σ_{i+j=k} C(n,i) C(n,j)/C(2n,k) (p_i·p_j) − R²`, `p_i = P_i − Q`. For a cubic
//! `d = [p0·p0, p0·p1, 0.4 p0·p2 + 0.6 p1·p1, 0.1 p0·p3 + 0.9 p1·p2, 0.4 p1·p3 + 0.6 p2·p2,
//! p2·p3, p3·p3] − R²`. **P4's eq. (6) is misprinted** (it swaps the 0.1/0.9 and 0.4/0.6
//! weights and puts p1·p1 where p1·p2 belongs); the general product formula above is what is
//! computed, and a regression test pins the cubic coefficients.
//!
//! The curve is inside where `e ≤ 0`. If every `d_k > 0` the curve misses the sphere (the hull
//! test); if every `d_k ≤ 0` it lies wholly inside; otherwise the roots of `e` are found by
//! clipping ([`clip::roots`]) and the pieces between them are classified by the sign of `e` at
//! their midpoints. A tangency (the curve touches the sphere from outside: a local minimum of
//! `e` equal to zero up to rounding) is found among the roots of `e'` — which are simple where
//! `e`'s root is double — and reported as the single-point interval `[t, t]`.

use super::bernstein;
use super::bezier::{Bezier, MAX_DEGREE};
use super::clip;
use super::closest::{distance_squared_coeffs, magnitude, rescale_for};
use super::point::Point;

/// Coefficients `d_k` of `e(t,R)` for the curve and sphere (length `2n + 1`).
#[must_use]
pub fn sphere_function<P: Point>(curve: &Bezier<P>, centre: P, radius: f64) -> Vec<f64> {
    let pts = curve.points();
    let p: Vec<P> = pts.iter().map(|&c| c - centre).collect();
    let mut d = vec![0.0; 2 * (pts.len() - 1) + 1];
    distance_squared_coeffs(&p, &mut d);
    let r2 = radius * radius;
    for v in &mut d {
        *v -= r2;
    }
    d
}

/// The sorted, maximal parameter intervals `[a, b] ⊆ [0,1]` where the Bezier curve lies inside
/// (or on) the sphere of the given centre and radius. Empty for a non-finite centre or a
/// negative or non-finite radius.
///
/// ```
/// use glam::DVec2;
/// use nendo_geom::curve::{sphere_intervals_bezier, Bezier};
/// let line = Bezier::new(vec![DVec2::new(-2.0, 0.0), DVec2::new(2.0, 0.0)]);
/// let iv = sphere_intervals_bezier(&line, DVec2::ZERO, 1.0);
/// assert_eq!(iv.len(), 1);
/// assert!((iv[0].0 - 0.25).abs() < 1e-12 && (iv[0].1 - 0.75).abs() < 1e-12);
/// ```
#[must_use]
pub fn sphere_intervals_bezier<P: Point>(
    curve: &Bezier<P>,
    centre: P,
    radius: f64,
) -> Vec<(f64, f64)> {
    if !centre.is_finite_coeff() || !radius.is_finite() || radius < 0.0 {
        return Vec::new();
    }
    // Extreme magnitudes: the same intervals on a copy scaled by a power of two (exact).
    let s = rescale_for(magnitude(curve.points(), centre).max(radius));
    if s != 1.0 {
        return match Bezier::try_new(curve.points().iter().map(|&c| c * s).collect()) {
            Ok(scaled) => sphere_intervals_bezier(&scaled, centre * s, radius * s),
            Err(_) => Vec::new(),
        };
    }
    let n = curve.degree();
    let mut p = [P::ZERO; MAX_DEGREE + 1];
    for (pi, &c) in p.iter_mut().zip(curve.points()) {
        *pi = c - centre;
    }
    let mut e = [0.0; 2 * MAX_DEGREE + 1];
    distance_squared_coeffs(&p[..=n], &mut e);
    let e = &mut e[..=2 * n];
    let r2 = radius * radius;
    for v in e.iter_mut() {
        *v -= r2;
    }
    if e.iter().all(|&v| v > 0.0) {
        return Vec::new();
    }
    if e.iter().all(|&v| v <= 0.0) {
        return vec![(0.0, 1.0)];
    }
    let mut roots = Vec::new();
    clip::roots(e, &mut roots);
    let mut breaks = Vec::with_capacity(roots.len() + 2);
    breaks.push(0.0);
    breaks.extend(roots.iter().copied().filter(|&r| r > 0.0 && r < 1.0));
    breaks.push(1.0);
    let mut out: Vec<(f64, f64)> = Vec::new();
    for w in breaks.windows(2) {
        let (a, b) = (w[0], w[1]);
        let inside = bernstein::eval(e, 0.5 * (a + b)) <= 0.0;
        if inside {
            match out.last_mut() {
                Some(last) if last.1 == a => last.1 = b,
                _ => out.push((a, b)),
            }
        }
    }
    // Tangencies: local minima of e that vanish up to rounding, outside every interval found.
    let scale = e.iter().fold(r2, |m, &v| m.max((v + r2).abs()));
    let tolerance = 64.0 * f64::EPSILON * scale;
    let de = bernstein::derivative(e);
    let mut crit = Vec::new();
    clip::roots(&de, &mut crit);
    for &t in crit.iter().chain(&roots) {
        let known = out.iter().any(|&(a, b)| t >= a - 1e-9 && t <= b + 1e-9);
        if !known && bernstein::eval(e, t).abs() <= tolerance {
            out.push((t, t));
        }
    }
    out.sort_by(|x, y| x.0.total_cmp(&y.0));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    /// Regression for P4's eq. (6): the right cubic coefficients are the product formula's.
    #[test]
    fn cubic_coefficients_are_not_the_misprinted_ones() {
        let pts = [
            DVec2::new(0.3, -1.0),
            DVec2::new(1.0, 2.0),
            DVec2::new(2.5, -0.5),
            DVec2::new(3.0, 1.5),
        ];
        let c = Bezier::new(pts.to_vec());
        let d = sphere_function(&c, DVec2::ZERO, 0.0);
        let p = pts;
        let right = [
            p[0].dot(p[0]),
            p[0].dot(p[1]),
            0.4 * p[0].dot(p[2]) + 0.6 * p[1].dot(p[1]),
            0.1 * p[0].dot(p[3]) + 0.9 * p[1].dot(p[2]),
            0.4 * p[1].dot(p[3]) + 0.6 * p[2].dot(p[2]),
            p[2].dot(p[3]),
            p[3].dot(p[3]),
        ];
        let misprinted = [
            p[0].dot(p[0]),
            p[0].dot(p[1]),
            0.1 * p[0].dot(p[2]) + 0.9 * p[1].dot(p[1]),
            0.4 * p[0].dot(p[3]) + 0.6 * p[1].dot(p[1]),
            0.1 * p[1].dot(p[3]) + 0.9 * p[2].dot(p[2]),
            p[2].dot(p[3]),
            p[3].dot(p[3]),
        ];
        for k in 0..7 {
            assert!((d[k] - right[k]).abs() < 1e-12, "d_{k}");
        }
        assert!((0..7).any(|k| (d[k] - misprinted[k]).abs() > 1e-3));
        // And the right form reproduces |C(t)|² exactly.
        for i in 0..=10 {
            let t = i as f64 / 10.0;
            assert!((bernstein::eval(&d, t) - c.eval(t).length_squared()).abs() < 1e-12);
        }
    }

    #[test]
    fn tangential_sphere_gives_a_point_interval() {
        let line = Bezier::new(vec![DVec2::new(-1.0, 1.0), DVec2::new(1.0, 1.0)]);
        let iv = sphere_intervals_bezier(&line, DVec2::ZERO, 1.0);
        assert_eq!(iv.len(), 1, "{iv:?}");
        assert!((iv[0].0 - 0.5).abs() < 1e-6 && iv[0].0 == iv[0].1);
    }
}
