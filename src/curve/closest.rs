//! The closest point on a curve to a query point within a radius, by Bezier clipping
//! (seed 000 §2.3, seed 004 §3(1); SPEC §2), and picking the nearest of many curves (seed 000 §3).
//!
//! With `p_i = P_i − Q` (the curve translated so that `Q` is the origin):
//!
//! * `f(u) = |C(u) − Q|² = Σ_{k=0..2n} f_k B_k^{2n}(u)`,
//!   `f_k = Σ_{i+j=k} C(n,i) C(n,j) / C(2n,k) · p_i·p_j` (the product of Bernstein forms);
//! * `g(u) = C'(u)·(C(u) − Q) = ½ f'(u) = n Σ_{k=0..2n−1} (f_{k+1} − f_k) B_k^{2n−1}(u)`, whose
//!   roots hold every interior minimum of the distance.
//!
//! The algorithm follows the paper's steps, with `f` and `g` built once and restricted rather
//! than rebuilt from a subdivided curve (restricting `f` restricts `g` — its coefficients are
//! `f`'s differences):
//!
//! 1. `d_min = min(|p_0|, |p_n|, R_max)`; the end points are the first candidates.
//! 2. Clip the curve by the band `|(C(u) − Q)·L| ≤ d_min` perpendicular to the chord
//!    `L = (P_n − P_0)/|P_n − P_0|` (the convex hull of the degree-`n` function `p_i·L`).
//! 3. On each interval: its end values `f(a)`, `f(b)` are candidates (they are `f`'s first and
//!    last coefficients there); discard it when `min_k f_k ≥ d_min²` (no point of the curve in
//!    the interval is closer — the circle test of seed 004), or when `g`'s coefficients have
//!    no sign change (the distance is monotone; its minimum is an end already counted).
//! 4. By Descartes' rule of signs, one sign change means exactly one root of `g`: a minimum if
//!    `g` goes from negative to positive (found by bracketed Newton), a maximum otherwise
//!    (discarded).
//! 5. Otherwise clip: keep the part of the interval where `g`'s hull meets zero and `f`'s hull
//!    dips below `d_min²`; if that removes less than 20 % of the interval, split it in two.
//! 6. Every better value found shrinks `d_min` for the intervals still to come.
//!
//! The result's point and distance are evaluated on the curve itself (de Casteljau), so the
//! distance is accurate to rounding even where `f` suffers cancellation (a query on the curve).

use super::bernstein;
use super::bezier::{Bezier, MAX_DEGREE};
use super::clip;
use super::point::Point;

/// Working size for `f` (degree `2n ≤ 2 · MAX_DEGREE`).
const F_CAP: usize = 2 * MAX_DEGREE + 1;

/// Width (in the curve's parameter) below which an interval that still holds several sign
/// changes of `g` is taken as converged: reached only at multiple roots of `g`.
const U_WIDTH: f64 = 1e-12;

/// Safety cap on intervals processed per query (never reached on finite input).
const MAX_STEPS: u32 = 10_000;

/// The closest point found on a curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Nearest<P> {
    /// Parameter of the closest point (for a B-spline, in the B-spline's own parameter).
    pub u: f64,
    /// The closest point `C(u)`.
    pub point: P,
    /// Its distance to the query.
    pub distance: f64,
}

/// Work done by one query, for the benchmark's histograms.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ClipStats {
    /// Clipping iterations: intervals examined, counting each clip and each split.
    pub clips: u32,
    /// Newton iterations spent finishing single roots.
    pub newton: u32,
    /// Splits (a clip removed less than 20 %).
    pub splits: u32,
}

impl ClipStats {
    /// Adds another query's counts.
    pub fn add(&mut self, o: ClipStats) {
        self.clips += o.clips;
        self.newton += o.newton;
        self.splits += o.splits;
    }
}

/// `f_k` of `|C(u) − Q|²` for the translated control points `p` (SPEC §2, the product formula
/// with `p_i·p_j`), written into `out[..2n+1]`.
pub(crate) fn distance_squared_coeffs<P: Point>(p: &[P], out: &mut [f64]) {
    let n = p.len() - 1;
    let m = 2 * n;
    for o in out.iter_mut().take(m + 1) {
        *o = 0.0;
    }
    for i in 0..=n {
        let wi = bernstein::binomial(n, i);
        out[2 * i] += wi * wi * p[i].dot(p[i]);
        for j in i + 1..=n {
            out[i + j] += 2.0 * wi * bernstein::binomial(n, j) * p[i].dot(p[j]);
        }
    }
    for (k, o) in out.iter_mut().enumerate().take(m + 1) {
        *o /= bernstein::binomial(m, k);
    }
}

/// Global minimum of the Bernstein function `f` (coefficients on `[0,1]`) over `[a0, b0]`,
/// among values below `bound` (strictly): returns `(u, f(u))`, or `None` when `f ≥ bound` on
/// the whole interval. Steps 3–6 of the module documentation; `f`'s end values at `a0`, `b0`
/// are candidates.
pub(crate) fn minimize_below(f: &[f64], a0: f64, b0: f64, bound: f64, stats: &mut ClipStats) -> Option<(f64, f64)> {
    let len = f.len();
    let m = len - 1;
    let mut best_f = bound;
    let mut best_u = f64::NAN;
    let mut w = [0.0; F_CAP];
    let mut g = [0.0; F_CAP];
    let mut stack = [(0.0f64, 0.0f64); 48];
    let mut top = 0usize;
    let mut steps = 0u32;
    let (mut a, mut b) = (a0, b0);
    w[..len].copy_from_slice(f);
    bernstein::restrict_in_place(&mut w[..len], a, b);
    loop {
        'interval: loop {
            steps += 1;
            stats.clips += 1;
            if steps > MAX_STEPS {
                break 'interval;
            }
            let wk = &w[..len];
            if wk[0] < best_f {
                best_f = wk[0];
                best_u = a;
            }
            if wk[m] < best_f {
                best_f = wk[m];
                best_u = b;
            }
            let mut low = wk[0];
            for &v in &wk[1..] {
                if v < low {
                    low = v;
                }
            }
            if !(low < best_f) || m == 0 {
                break 'interval;
            }
            for k in 0..m {
                g[k] = wk[k + 1] - wk[k];
            }
            let gk = &g[..m];
            let changes = bernstein::sign_changes(gk);
            if changes == 0 {
                break 'interval;
            }
            if changes == 1 {
                let first = gk.iter().copied().find(|&v| v != 0.0).unwrap_or(0.0);
                if first > 0.0 {
                    break 'interval; // a maximum inside; both ends already counted
                }
                if gk[0] != 0.0 && gk[m - 1] != 0.0 {
                    let (s, it) = clip::bracketed_root(gk);
                    stats.newton += it;
                    let v = bernstein::eval_scalar_fast(wk, s);
                    if v < best_f {
                        best_f = v;
                        best_u = a + s * (b - a);
                    }
                    break 'interval;
                }
            }
            let Some((l1, h1)) = clip::hull_zero(gk) else { break 'interval };
            let Some((l2, h2)) = clip::hull_below(wk, best_f) else { break 'interval };
            let lo = if l1 > l2 { l1 } else { l2 };
            let hi = if h1 < h2 { h1 } else { h2 };
            if lo > hi {
                break 'interval;
            }
            let (lo, hi) = clip::widen(lo, hi);
            let span = b - a;
            if (hi - lo) * span < U_WIDTH {
                let s = 0.5 * (lo + hi);
                let v = bernstein::eval_scalar_fast(wk, s);
                if v < best_f {
                    best_f = v;
                    best_u = a + s * span;
                }
                break 'interval;
            }
            if hi - lo > 0.8 {
                stats.splits += 1;
                let mid = 0.5 * (lo + hi);
                if top < stack.len() {
                    stack[top] = (a + mid * span, a + hi * span);
                    top += 1;
                    bernstein::restrict_in_place(&mut w[..len], lo, mid);
                    b = a + mid * span;
                    a += lo * span;
                    continue 'interval;
                }
            }
            bernstein::restrict_in_place(&mut w[..len], lo, hi);
            b = a + hi * span;
            a += lo * span;
        }
        if top == 0 {
            break;
        }
        top -= 1;
        (a, b) = stack[top];
        w[..len].copy_from_slice(f);
        bernstein::restrict_in_place(&mut w[..len], a, b);
    }
    best_u.is_finite().then_some((best_u, best_f))
}

/// The part of `[0,1]` where the curve `p` (translated control points) lies inside the band
/// `|p(u)·L| ≤ d` perpendicular to its chord; `[0,1]` when the chord is degenerate.
fn chord_band<P: Point>(p: &[P], d: f64) -> Option<(f64, f64)> {
    let n = p.len() - 1;
    let chord = p[n] - p[0];
    let len2 = chord.dot(chord);
    if !(len2 > 0.0) || n == 0 {
        return Some((0.0, 1.0));
    }
    let l = chord * (1.0 / len2.sqrt());
    let mut s = [0.0; MAX_DEGREE + 1];
    for (si, &pi) in s.iter_mut().zip(p) {
        *si = pi.dot(l);
    }
    let s = &s[..=n];
    let (a1, b1) = clip::hull_below(s, d)?;
    let mut neg = [0.0; MAX_DEGREE + 1];
    for (ni, &si) in neg.iter_mut().zip(s) {
        *ni = -si;
    }
    let (a2, b2) = clip::hull_below(&neg[..=n], d)?;
    let lo = if a1 > a2 { a1 } else { a2 };
    let hi = if b1 < b2 { b1 } else { b2 };
    (lo <= hi).then_some((lo, hi))
}

/// The closest point of a Bezier curve to `q` no farther than `r_max` (pass `f64::INFINITY`
/// for no limit), with the work counted into `stats`. `None` when nothing lies within `r_max`
/// or when the query is not finite. Ties (two equally close points) resolve to the smaller `u`
/// found first, deterministically.
pub fn closest_bezier_with_stats<P: Point>(
    curve: &Bezier<P>,
    q: P,
    r_max: f64,
    stats: &mut ClipStats,
) -> Option<Nearest<P>> {
    if !q.is_finite_coeff() || r_max.is_nan() || r_max < 0.0 {
        return None;
    }
    let pts = curve.points();
    let n = pts.len() - 1;
    let mut p = [P::ZERO; MAX_DEGREE + 1];
    for (pi, &c) in p.iter_mut().zip(pts) {
        *pi = c - q;
    }
    let p = &p[..=n];
    let d0 = p[0].length();
    let dn = p[n].length();
    // Step 1: the end points are candidates; d_min bounds the search.
    let mut d_min = r_max;
    let mut best: Option<f64> = None;
    if d0 <= d_min {
        d_min = d0;
        best = Some(0.0);
    }
    if dn < d_min {
        d_min = dn;
        best = Some(1.0);
    }
    let mut result_u = best;
    if n > 0 && d_min > 0.0 {
        // Step 2: the band perpendicular to the chord.
        if let Some((lo, hi)) = chord_band(p, d_min) {
            let mut f = [0.0; F_CAP];
            distance_squared_coeffs(p, &mut f);
            let bound = if d_min.is_finite() { d_min * d_min } else { f64::INFINITY };
            if let Some((u, _)) = minimize_below(&f[..=2 * n], lo, hi, bound, stats) {
                result_u = Some(u);
            }
        }
    }
    let u = result_u?;
    let point = curve.eval(u);
    let distance = (point - q).length();
    (distance <= r_max).then_some(Nearest { u, point, distance })
}

/// The closest point of a Bezier curve to `q` within `r_max` (`f64::INFINITY` for no limit).
///
/// ```
/// use glam::DVec2;
/// use nendo::curve::{closest_bezier, Bezier};
/// let c = Bezier::new(vec![DVec2::new(0.0, 0.0), DVec2::new(1.0, 2.0), DVec2::new(2.0, 0.0)]);
/// let n = closest_bezier(&c, DVec2::new(1.0, 3.0), f64::INFINITY).expect("unbounded search");
/// assert!((n.u - 0.5).abs() < 1e-12 && (n.distance - 2.0).abs() < 1e-12);
/// assert!(closest_bezier(&c, DVec2::new(1.0, 3.0), 1.5).is_none());
/// ```
pub fn closest_bezier<P: Point>(curve: &Bezier<P>, q: P, r_max: f64) -> Option<Nearest<P>> {
    closest_bezier_with_stats(curve, q, r_max, &mut ClipStats::default())
}

/// Squared distance from `q` to the axis-aligned box `[lo, hi]`: a lower bound for the
/// squared distance to anything inside the box (the control points' box holds the curve).
#[inline]
pub(crate) fn box_distance_squared<P: Point>(lo: P, hi: P, q: P) -> f64 {
    let mut s = 0.0;
    for i in 0..P::DIM {
        let (l, h, x) = (lo.coord(i), hi.coord(i), q.coord(i));
        let d = if x < l {
            l - x
        } else if x > h {
            x - h
        } else {
            0.0
        };
        s += d * d;
    }
    s
}
