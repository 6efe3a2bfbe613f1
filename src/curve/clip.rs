//! Bezier clipping of scalar Bernstein functions (Nishita, Sederberg & Kakimoto 1990; seed 000
//! §2.2–2.3): the graph of `f(t) = Σ c_k B_k^m(t)` lies in the convex hull of its control points
//! `(k/m, c_k)`, so the part of `[0,1]` where that hull meets `y ≤ 0` (or `y = 0`) bounds where
//! `f` can be non-positive (or vanish). Every clip is a handful of linear interpolations.
//!
//! Also here: root finding for Bernstein functions by clipping, Descartes' rule of signs and a
//! bracketed Newton finish, used by the probe-sphere and ray queries.
//!
//! Limits: a root of even multiplicity (the function touches zero without changing sign) cannot
//! be bracketed by sign. Where rounding leaves coefficients of both signs around it, it is
//! located by clipping alone down to [`ROOT_WIDTH`] and reported once; where rounding makes them
//! one-signed, it is not reported. Callers that need tangencies test the critical points (the
//! roots of the derivative), as the probe-sphere query does.

use super::bernstein;

/// Interval width (in the function's own parameter) at which clipping stops and reports the
/// interval's midpoint; reached only near roots of even multiplicity.
pub const ROOT_WIDTH: f64 = 1e-12;

/// Every clipped interval is widened by this much (in the clipped function's own `[0,1]`) on
/// each side, so that rounding in the hull computation can never clip a root away when it lies
/// at the very edge of the hull (e.g. where clipping has converged onto it).
pub const CLIP_MARGIN: f64 = 1e-10;

/// `[lo, hi]` widened by [`CLIP_MARGIN`] on each side, within `[0,1]`.
#[inline]
#[must_use]
pub fn widen(lo: f64, hi: f64) -> (f64, f64) {
    let lo = lo - CLIP_MARGIN;
    let hi = hi + CLIP_MARGIN;
    (if lo < 0.0 { 0.0 } else { lo }, if hi > 1.0 { 1.0 } else { hi })
}

/// The part `[lo, hi]` of `[0,1]` over which the convex hull of the control points
/// `(k/m, c_k)` has a point with `y ≤ 0`; `None` when every `c_k > 0`.
///
/// The left end is `0` if `c_0 ≤ 0`, otherwise the leftmost point where a hull edge from a
/// positive control point to a non-positive one crosses `y = 0`; the right end likewise.
#[must_use]
pub fn hull_nonpositive(c: &[f64]) -> Option<(f64, f64)> {
    let m = c.len() - 1;
    let first = c.iter().position(|&v| v <= 0.0)?;
    let last = m - c.iter().rev().position(|&v| v <= 0.0).unwrap_or(0);
    if m == 0 {
        return Some((0.0, 1.0));
    }
    let inv_m = 1.0 / m as f64;
    let lo = if first == 0 {
        0.0
    } else {
        let mut lo = first as f64 * inv_m;
        for i in 0..first {
            // c_i > 0 here.
            for (j, &cj) in c.iter().enumerate().skip(first) {
                if cj <= 0.0 {
                    let x = (i as f64 + (j - i) as f64 * c[i] / (c[i] - cj)) * inv_m;
                    if x < lo {
                        lo = x;
                    }
                }
            }
        }
        lo
    };
    let hi = if last == m {
        1.0
    } else {
        let mut hi = last as f64 * inv_m;
        for i in last + 1..=m {
            for (j, &cj) in c.iter().enumerate().take(last + 1) {
                if cj <= 0.0 {
                    let x = (i as f64 - (i - j) as f64 * c[i] / (c[i] - cj)) * inv_m;
                    if x > hi {
                        hi = x;
                    }
                }
            }
        }
        hi
    };
    Some((lo.max(0.0), hi.min(1.0)))
}

/// Like [`hull_nonpositive`] for `c_k − level`, without allocating.
#[must_use]
pub fn hull_below(c: &[f64], level: f64) -> Option<(f64, f64)> {
    let mut buf = [0.0; 64];
    let n = c.len().min(64);
    for (b, &v) in buf.iter_mut().zip(c) {
        *b = v - level;
    }
    hull_nonpositive(&buf[..n])
}

/// The part of `[0,1]` where the convex hull of `(k/m, c_k)` meets `y = 0`: the intersection of
/// the ranges where it meets `y ≤ 0` and `y ≥ 0` (for a convex set, a vertical line that meets
/// both half-planes meets the line between them).
#[must_use]
pub fn hull_zero(c: &[f64]) -> Option<(f64, f64)> {
    let (a, b) = hull_nonpositive(c)?;
    let mut neg = [0.0; 64];
    let n = c.len().min(64);
    for (b, &v) in neg.iter_mut().zip(c) {
        *b = -v;
    }
    let (c2, d2) = hull_nonpositive(&neg[..n])?;
    let lo = if a > c2 { a } else { c2 };
    let hi = if b < d2 { b } else { d2 };
    (lo <= hi).then_some((lo, hi))
}

/// The root of `f = Σ c_k B_k^m` in `[0,1]` when `c_0` and `c_m` have strictly opposite signs
/// and `f` is known to have exactly one root there (one sign change in the coefficients):
/// Newton's method safeguarded by the bracket, falling back to bisection whenever a step leaves
/// the bracket. Returns the root and the number of iterations.
#[must_use]
pub fn bracketed_root(c: &[f64]) -> (f64, u32) {
    let m = c.len() - 1;
    let c0 = c[0];
    let cm = c[m];
    debug_assert!(c0 * cm < 0.0);
    let mut d = [0.0; 64];
    for k in 0..m.min(64) {
        d[k] = c[k + 1] - c[k];
    }
    let d = &d[..m.min(64)];
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let neg_at_lo = c0 < 0.0;
    let mut s = c0 / (c0 - cm);
    let mut iters = 0;
    while iters < 200 {
        iters += 1;
        let v = bernstein::eval_scalar_fast(c, s);
        if v == 0.0 {
            return (s, iters);
        }
        if (v < 0.0) == neg_at_lo {
            lo = s;
        } else {
            hi = s;
        }
        let dv = bernstein::eval_scalar_fast(d, s) * m as f64;
        let mut next = s - v / dv;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        let step = (next - s).abs();
        s = next;
        if step <= 4.0 * f64::EPSILON * s.abs().max(f64::MIN_POSITIVE) || hi - lo <= 2.0 * f64::EPSILON {
            break;
        }
    }
    (s, iters)
}

/// All roots of `f = Σ c_k B_k^m` in `[0,1]` where `f` changes sign (and exact zeros at the
/// ends and at split points), sorted, each reported once; roots of even multiplicity only as
/// the module documentation says.
/// A function that vanishes identically has no isolated roots and yields none.
pub fn roots(c: &[f64], out: &mut Vec<f64>) {
    out.clear();
    let m = c.len() - 1;
    if c.iter().all(|&v| v == 0.0) {
        return;
    }
    if c[0] == 0.0 {
        out.push(0.0);
    }
    if c[m] == 0.0 && m > 0 {
        out.push(1.0);
    }
    let mut stack: Vec<(f64, f64)> = vec![(0.0, 1.0)];
    let mut w = [0.0; 64];
    let n = c.len().min(64);
    let mut budget = 100_000u32;
    while let Some((mut a, mut b)) = stack.pop() {
        w[..n].copy_from_slice(&c[..n]);
        bernstein::restrict_in_place(&mut w[..n], a, b);
        loop {
            budget = budget.saturating_sub(1);
            if budget == 0 {
                break;
            }
            let wk = &w[..n];
            // An exact zero at an interior end (a split point, or where clipping converged onto
            // the root) is a root.
            if wk[0] == 0.0 && a > 0.0 {
                out.push(a);
            }
            if wk[n - 1] == 0.0 && b < 1.0 {
                out.push(b);
            }
            let v = bernstein::sign_changes(wk);
            if v == 0 {
                break;
            }
            let (w0, wm) = (wk[0], wk[n - 1]);
            if v == 1 && w0 != 0.0 && wm != 0.0 {
                let (s, _) = bracketed_root(wk);
                out.push(a + s * (b - a));
                break;
            }
            let Some((lo, hi)) = hull_zero(wk) else { break };
            let (lo, hi) = widen(lo, hi);
            if (hi - lo) * (b - a) < ROOT_WIDTH {
                out.push(a + 0.5 * (lo + hi) * (b - a));
                break;
            }
            let span = b - a;
            if hi - lo > 0.8 {
                let mid = 0.5 * (lo + hi);
                stack.push((a + mid * span, a + hi * span));
                bernstein::restrict_in_place(&mut w[..n], lo, mid);
                b = a + mid * span;
                a += lo * span;
            } else {
                bernstein::restrict_in_place(&mut w[..n], lo, hi);
                b = a + hi * span;
                a += lo * span;
            }
        }
    }
    out.sort_by(f64::total_cmp);
    out.dedup_by(|x, y| (*x - *y).abs() <= 4.0 * ROOT_WIDTH);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn from_roots(rs: &[f64]) -> Vec<f64> {
        // Π (t − r) in Bernstein form, by products of linear factors [−r, 1 − r].
        let mut c = vec![1.0];
        for &r in rs {
            c = bernstein::product(&c, &[-r, 1.0 - r], |x, y| x * y);
        }
        c
    }

    #[test]
    fn finds_simple_roots() {
        let rs = [0.1, 0.35, 0.36, 0.8];
        let c = from_roots(&rs);
        let mut out = Vec::new();
        roots(&c, &mut out);
        assert_eq!(out.len(), 4, "{out:?}");
        for (a, b) in out.iter().zip(&rs) {
            assert!((a - b).abs() < 1e-12);
        }
    }

    #[test]
    fn double_root_never_hides_a_simple_one() {
        let c = from_roots(&[0.4, 0.4, 0.9]);
        let mut out = Vec::new();
        roots(&c, &mut out);
        assert!(!out.is_empty() && out.len() <= 2, "{out:?}");
        assert!((out[out.len() - 1] - 0.9).abs() < 1e-12);
        if out.len() == 2 {
            assert!((out[0] - 0.4).abs() < 1e-6);
        }
    }

    #[test]
    fn roots_at_the_ends() {
        let c = from_roots(&[0.0, 1.0, 0.5]);
        let mut out = Vec::new();
        roots(&c, &mut out);
        assert_eq!(out, vec![0.0, 0.5, 1.0]);
    }

    #[test]
    fn hull_ranges() {
        assert_eq!(hull_nonpositive(&[1.0, 2.0]), None);
        let (lo, hi) = hull_zero(&[1.0, -1.0]).expect("crosses");
        assert!((lo - 0.5).abs() < 1e-15 && (hi - 0.5).abs() < 1e-15);
        let (lo, hi) = hull_nonpositive(&[1.0, -1.0, 1.0]).expect("dips");
        assert!((lo - 0.25).abs() < 1e-15 && (hi - 0.75).abs() < 1e-15);
    }
}
