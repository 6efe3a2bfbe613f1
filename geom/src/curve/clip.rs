//! Bezier clipping of scalar Bernstein functions (Nishita, Sederberg & Kakimoto 1990; P0
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
    (
        if lo < 0.0 { 0.0 } else { lo },
        if hi > 1.0 { 1.0 } else { hi },
    )
}

/// The part `[lo, hi]` of `[0,1]` over which the convex hull of the points
/// `(k/m, σ (c_k − level))` has a point with `y ≤ 0` (`σ = ±1`); `None` when every value is
/// positive.
///
/// That is where the hull's *lower* boundary is `≤ 0`. The lower boundary is built by Andrew's
/// monotone chain (the points are already sorted by `x`), then scanned from each end for its
/// first crossing of `y = 0`: `O(m)`.
///
/// # Panics
/// If `c` has more than 64 coefficients.
#[inline]
#[must_use]
pub fn hull_range(c: &[f64], level: f64, sign: f64) -> Option<(f64, f64)> {
    let m = c.len() - 1;
    // The lower hull's vertices (x, y), built left to right.
    let mut hx = [0.0f64; 64];
    let mut hy = [0.0f64; 64];
    let mut h = 0usize;
    let mut any = false;
    let mut x = 0.0f64;
    for &ck in c {
        let y = sign * (ck - level);
        any |= y <= 0.0;
        // Pop while the last two hull points and (x, y) do not turn counter-clockwise.
        while h >= 2 {
            let cross = (hx[h - 1] - hx[h - 2]) * (y - hy[h - 2])
                - (hy[h - 1] - hy[h - 2]) * (x - hx[h - 2]);
            if cross > 0.0 {
                break;
            }
            h -= 1;
        }
        hx[h] = x;
        hy[h] = y;
        h += 1;
        x += 1.0;
    }
    if !any {
        return None;
    }
    if m == 0 {
        return Some((0.0, 1.0));
    }
    let lo = if hy[0] <= 0.0 {
        0.0
    } else {
        let mut i = 0;
        while hy[i + 1] > 0.0 {
            i += 1;
        }
        hx[i] + (hx[i + 1] - hx[i]) * hy[i] / (hy[i] - hy[i + 1])
    };
    let hi = if hy[h - 1] <= 0.0 {
        m as f64
    } else {
        let mut i = h - 2;
        while hy[i] > 0.0 {
            i -= 1;
        }
        hx[i] + (hx[i + 1] - hx[i]) * hy[i] / (hy[i] - hy[i + 1])
    };
    let inv_m = 1.0 / m as f64;
    let (lo, hi) = (lo * inv_m, hi * inv_m);
    Some((
        if lo < 0.0 { 0.0 } else { lo },
        if hi > 1.0 { 1.0 } else { hi },
    ))
}

/// `1/k` for `k < 64` (`RECIPROCAL[0]` unused).
static RECIPROCAL: [f64; 64] = {
    let mut r = [0.0; 64];
    let mut k = 1;
    while k < 64 {
        r[k] = 1.0 / k as f64;
        k += 1;
    }
    r
};

/// A cheaper enclosure of [`hull_below`]: the part of `[0,1]` outside of which
/// `f = Σ c_k B_k^m` certainly stays above `level`, from the two supporting lines of the
/// control polygon's hull through its end points. Every control point lies on or above the line
/// from `(0, c_0)` with the least slope `min_k m (c_k − c_0)/k`, hence so does the hull and the
/// graph of `f`; `f` cannot reach `level` before that line does (and likewise from the right
/// end). Where the hull's first edge reaches the level this is the exact hull clip; otherwise
/// it is a little wider. `O(m)`, no allocation. `None` when every coefficient is above `level`.
#[inline(always)]
#[must_use]
pub fn end_lines_below(c: &[f64], level: f64) -> Option<(f64, f64)> {
    let m = c.len() - 1;
    let (c0, cm) = (c[0] - level, c[m] - level);
    let mut any = c0 <= 0.0 || cm <= 0.0;
    // Least slopes from each end, in units of the coefficient index.
    let mut left = f64::INFINITY;
    let mut right = f64::INFINITY;
    #[allow(clippy::needless_range_loop)] // index loop: unrolls for a constant length
    for k in 1..m {
        let v = c[k] - level;
        any |= v <= 0.0;
        let from_left = (v - c0) * RECIPROCAL[k];
        let from_right = (v - cm) * RECIPROCAL[m - k];
        if from_left < left {
            left = from_left;
        }
        if from_right < right {
            right = from_right;
        }
    }
    if !any {
        return None;
    }
    if m == 0 {
        return Some((0.0, 1.0));
    }
    let end_slope = (cm - c0) / m as f64;
    if end_slope < left {
        left = end_slope;
    }
    if -end_slope < right {
        right = -end_slope;
    }
    let lo = if c0 <= 0.0 {
        0.0
    } else {
        -c0 / left / m as f64
    };
    let hi = if cm <= 0.0 {
        1.0
    } else {
        1.0 + cm / right / m as f64
    };
    Some((
        if lo < 0.0 { 0.0 } else { lo },
        if hi > 1.0 { 1.0 } else { hi },
    ))
}

/// The part of `[0,1]` where the convex hull of `(k/m, c_k)` has a point with `y ≤ 0`.
#[inline]
#[must_use]
pub fn hull_nonpositive(c: &[f64]) -> Option<(f64, f64)> {
    hull_range(c, 0.0, 1.0)
}

/// The part of `[0,1]` where the convex hull of `(k/m, c_k)` has a point with `y ≤ level`.
#[inline]
#[must_use]
pub fn hull_below(c: &[f64], level: f64) -> Option<(f64, f64)> {
    hull_range(c, level, 1.0)
}

/// The part of `[0,1]` where the convex hull of `(k/m, c_k)` meets `y = 0`: the intersection of
/// the ranges where it meets `y ≤ 0` and `y ≥ 0` (for a convex set, a vertical line that meets
/// both half-planes meets the line between them).
#[inline]
#[must_use]
pub fn hull_zero(c: &[f64]) -> Option<(f64, f64)> {
    let (a, b) = hull_range(c, 0.0, 1.0)?;
    let (c2, d2) = hull_range(c, 0.0, -1.0)?;
    let lo = if a > c2 { a } else { c2 };
    let hi = if b < d2 { b } else { d2 };
    (lo <= hi).then_some((lo, hi))
}

/// Newton iterations stop when a step is below this (in the function's own `[0,1]`).
pub const NEWTON_STEP: f64 = 1e-14;

/// A Newton step (inside the bracket) below this ends the iteration: the error left after it
/// is of the order of its square times the root's curvature ratio.
pub const NEWTON_QUADRATIC: f64 = 1e-9;

/// The root of `f = Σ c_k B_k^m` in `[lo, hi] ⊆ [0,1]`, where `f` is known to have exactly one
/// root, of odd multiplicity, that changes sign from the sign of `c_0` (one sign change in the
/// coefficients; `[lo, hi]` from a clip, or `[0,1]`): Newton's method from `start`, safeguarded
/// by the bracket, which every evaluation tightens, falling back to bisection whenever a step
/// would leave it. Returns the root and the number of iterations.
///
/// `f` and `f'` are evaluated together by Horner's scheme (in the power basis up to degree
/// 8, in the Bernstein basis scaled by `t/(1−t)` above).
#[must_use]
#[inline(always)]
pub fn bracketed_root(c: &[f64], mut lo: f64, mut hi: f64, start: f64) -> (f64, u32) {
    let m = c.len() - 1;
    // Low degrees: evaluate in the power basis, converted once (the conversion amplifies
    // rounding by at most about 2^m, harmless for m ≤ POWER_MAX; Newton only needs the sign and
    // a slope). Higher degrees keep the Bernstein form.
    let mut power = [0.0; POWER_MAX + 1];
    let use_power = m <= POWER_MAX;
    if use_power {
        // Index loops with the degree's bounds, so that they unroll once `m` is a constant.
        let scale = bernstein::binomial_row(m);
        for k in 0..=m {
            let mut acc = 0.0;
            for i in 0..=k {
                acc += c[i] * SIGNED_BINOMIAL[k][i];
            }
            power[k] = acc * scale[k];
        }
    }
    let neg_before_root = c[0] < 0.0;
    let mut s = if start > lo && start < hi {
        start
    } else {
        0.5 * (lo + hi)
    };
    let mut iters = 0;
    while iters < 100 {
        iters += 1;
        let (v, dv) = if use_power {
            let mut v = power[m];
            let mut d = 0.0;
            for k in (0..m).rev() {
                d = d * s + v;
                v = v * s + power[k];
            }
            (v, d)
        } else {
            value_and_slope(c, s)
        };
        if v == 0.0 {
            return (s, iters);
        }
        if (v < 0.0) == neg_before_root {
            lo = s;
        } else {
            hi = s;
        }
        let step = v / dv;
        let next = s - step;
        if next > lo && next < hi {
            s = next;
            // Newton converges quadratically: after a step below NEWTON_QUADRATIC the error
            // is of the order of its square, far below rounding.
            if step.abs() <= NEWTON_QUADRATIC {
                return (s, iters);
            }
        } else if step.abs() <= NEWTON_STEP {
            return (s, iters); // within rounding of the root, on the bracket's edge
        } else {
            s = 0.5 * (lo + hi);
        }
        if hi - lo <= NEWTON_STEP {
            break;
        }
    }
    (s, iters)
}

/// Highest degree that [`bracketed_root`] evaluates in the power basis.
const POWER_MAX: usize = 8;

/// `(−1)^{k−i} C(k,i)` for `i ≤ k ≤ POWER_MAX`: the Bernstein-to-power conversion
/// `a_k = C(m,k) Σ_{i≤k} (−1)^{k−i} C(k,i) c_i` as a table of exact integers (no parity
/// branches in the hot loop; the sums round exactly as with the binomials and signs applied
/// term by term).
static SIGNED_BINOMIAL: [[f64; POWER_MAX + 1]; POWER_MAX + 1] = {
    let mut t = [[0.0; POWER_MAX + 1]; POWER_MAX + 1];
    let mut c = [[0i64; POWER_MAX + 1]; POWER_MAX + 1];
    let mut k = 0;
    while k <= POWER_MAX {
        c[k][0] = 1;
        let mut i = 1;
        while i <= k {
            c[k][i] = c[k - 1][i - 1] + if i < k { c[k - 1][i] } else { 0 };
            i += 1;
        }
        let mut i = 0;
        while i <= k {
            t[k][i] = if (k - i) % 2 == 0 {
                c[k][i] as f64
            } else {
                -(c[k][i] as f64)
            };
            i += 1;
        }
        k += 1;
    }
    t
};

/// `f(t) = Σ c_k C(m,k) t^k (1−t)^(m−k)` and
/// `f'(t) = m Σ (c_{k+1} − c_k) C(m−1,k) t^k (1−t)^(m−1−k)`, by Horner's scheme in `t/(1−t)`
/// (or `(1−t)/t` past one half, so that the ratio stays at most one).
#[inline(always)]
pub(crate) fn value_and_slope(c: &[f64], t: f64) -> (f64, f64) {
    let m = c.len() - 1;
    if m == 0 {
        return (c[0], 0.0);
    }
    if m > bernstein::MAX_BINOMIAL {
        let d = bernstein::derivative(c);
        return (bernstein::eval(c, t), bernstein::eval(&d, t));
    }
    let bm = bernstein::binomial_row(m);
    let bd = bernstein::binomial_row(m - 1);
    let s = 1.0 - t;
    let (v, d, pm1, last) = if t <= 0.5 {
        let r = t / s;
        let mut v = c[m];
        let mut d = c[m] - c[m - 1];
        for k in (0..m - 1).rev() {
            v = v * r + c[k + 1] * bm[k + 1];
            d = d * r + (c[k + 1] - c[k]) * bd[k];
        }
        v = v * r + c[0];
        (v, d, s.powi(m as i32 - 1), s)
    } else {
        let r = s / t;
        let mut v = c[0];
        let mut d = c[1] - c[0];
        for k in 1..m {
            v = v * r + c[k] * bm[k];
            d = d * r + (c[k + 1] - c[k]) * bd[k];
        }
        v = v * r + c[m];
        (v, d, t.powi(m as i32 - 1), t)
    };
    (v * pm1 * last, d * pm1 * m as f64)
}

/// [`bracketed_root`] on all of `[0,1]`, for a function with exactly one sign change in its
/// coefficients, started where the control polygon crosses zero (between the two coefficients
/// that change sign): a good first guess that improves as intervals shrink.
#[must_use]
#[inline(always)]
pub fn clipped_root(c: &[f64]) -> (f64, u32) {
    let m = c.len() - 1;
    let mut start = 0.5;
    for k in 0..m {
        let (a, b) = (c[k], c[k + 1]);
        if (a <= 0.0 && b > 0.0) || (a >= 0.0 && b < 0.0) {
            start = (k as f64 + a / (a - b)) / m as f64;
            break;
        }
    }
    bracketed_root(c, 0.0, 1.0, start)
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
                let (s, _) = clipped_root(wk);
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
