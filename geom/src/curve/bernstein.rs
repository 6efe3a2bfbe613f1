//! Bernstein polynomials and the algorithms on Bernstein coefficient arrays that every other part
//! of nendo builds on (docs/design.md §3).
//!
//! A Bernstein form of degree `n` is `f(t) = Σ_{i=0..n} c_i B_i^n(t)` with
//! `B_i^n(t) = C(n,i) t^i (1-t)^(n-i)`. The coefficients `c_i` may be scalars (a Bezier *function*)
//! or points (a Bezier *curve*): every routine here is generic over [`Coeff`].
//!
//! All functions take the coefficients as a slice whose length is `degree + 1`; an empty slice is
//! a caller error and is reported by `debug_assert!` (public types validate before calling).

use super::point::Coeff;

/// Largest `n` for which [`binomial`] is tabulated exactly (C(60,30) < 2^63).
pub const MAX_BINOMIAL: usize = 60;

const fn pascal() -> [[u64; MAX_BINOMIAL + 1]; MAX_BINOMIAL + 1] {
    let mut t = [[0u64; MAX_BINOMIAL + 1]; MAX_BINOMIAL + 1];
    let mut n = 0;
    while n <= MAX_BINOMIAL {
        t[n][0] = 1;
        let mut k = 1;
        while k <= n {
            t[n][k] = t[n - 1][k - 1] + if k < n { t[n - 1][k] } else { 0 };
            k += 1;
        }
        n += 1;
    }
    t
}

const fn pascal_f64() -> [[f64; MAX_BINOMIAL + 1]; MAX_BINOMIAL + 1] {
    let t = pascal();
    let mut f = [[0.0; MAX_BINOMIAL + 1]; MAX_BINOMIAL + 1];
    let mut n = 0;
    while n <= MAX_BINOMIAL {
        let mut k = 0;
        while k <= n {
            f[n][k] = t[n][k] as f64;
            k += 1;
        }
        n += 1;
    }
    f
}

static PASCAL: [[f64; MAX_BINOMIAL + 1]; MAX_BINOMIAL + 1] = pascal_f64();

/// The binomial coefficient `C(n, k)` as `f64`; zero when `k > n`.
///
/// Exact for `n ≤ MAX_BINOMIAL`; beyond that it is computed by the multiplicative formula.
///
/// ```
/// use nendo_geom::curve::bernstein::binomial;
/// assert_eq!(binomial(6, 3), 20.0);
/// assert_eq!(binomial(3, 4), 0.0);
/// ```
#[inline]
#[must_use]
pub fn binomial(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    if n <= MAX_BINOMIAL {
        return PASCAL[n][k];
    }
    let k = k.min(n - k);
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

/// Row `n` of Pascal's triangle, `C(n, 0..=n)` (zeros beyond), for loops that need many
/// binomials of one degree.
///
/// # Panics
/// If `n > MAX_BINOMIAL`.
#[inline]
#[must_use]
pub fn binomial_row(n: usize) -> &'static [f64; MAX_BINOMIAL + 1] {
    &PASCAL[n]
}

/// The Bernstein basis polynomial `B_i^n(t) = C(n,i) t^i (1-t)^(n-i)`.
///
/// ```
/// use nendo_geom::curve::bernstein::basis;
/// assert!((basis(3, 1, 0.5) - 0.375).abs() < 1e-15);
/// ```
#[inline]
#[must_use]
pub fn basis(n: usize, i: usize, t: f64) -> f64 {
    if i > n {
        return 0.0;
    }
    binomial(n, i) * powi(t, i) * powi(1.0 - t, n - i)
}

#[inline]
fn powi(x: f64, k: usize) -> f64 {
    let mut r = 1.0;
    for _ in 0..k {
        r *= x;
    }
    r
}

/// All `n + 1` basis values `B_0^n(t) .. B_n^n(t)` written into `out[..=n]`, by the triangular
/// recurrence `B_i^n = (1-t) B_i^{n-1} + t B_{i-1}^{n-1}` (stable for every `t` in `[0,1]`).
///
/// # Panics
/// If `out.len() < n + 1`.
pub fn basis_all(n: usize, t: f64, out: &mut [f64]) {
    let s = 1.0 - t;
    out[0] = 1.0;
    for j in 1..=n {
        let mut saved = 0.0;
        for o in out.iter_mut().take(j) {
            let tmp = *o;
            *o = saved + s * tmp;
            saved = t * tmp;
        }
        out[j] = saved;
    }
}

/// Evaluates `Σ c_i B_i^n(t)` by de Casteljau's algorithm (repeated linear interpolation), the
/// numerically stable evaluation of a Bernstein form.
///
/// ```
/// use nendo_geom::curve::bernstein::eval;
/// // B-form of t² on degree 2 is [0, 0, 1].
/// assert!((eval(&[0.0, 0.0, 1.0], 0.3) - 0.09).abs() < 1e-15);
/// ```
#[must_use]
pub fn eval<T: Coeff>(c: &[T], t: f64) -> T {
    debug_assert!(!c.is_empty());
    macro_rules! fixed {
        ($($n:literal)*) => {
            match c.len() {
                $($n => {
                    let mut buf: [T; $n] = c.try_into().unwrap_or([T::ZERO; $n]);
                    casteljau_in_place(&mut buf, t)
                })*
                _ => casteljau_in_place(&mut c.to_vec(), t),
            }
        };
    }
    fixed!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21)
}

#[inline]
fn casteljau_in_place<T: Coeff>(buf: &mut [T], t: f64) -> T {
    let n = buf.len();
    for r in 1..n {
        for i in 0..n - r {
            buf[i] = buf[i].lerp_to(buf[i + 1], t);
        }
    }
    buf[0]
}

/// Evaluates a *scalar* Bernstein form in `O(n)` by a Horner-like scheme in `t/(1-t)`
/// (`Σ c_i C(n,i) t^i (1-t)^(n-i)`), switching to `(1-t)/t` for `t > 1/2` so the ratio never
/// exceeds one. Faster than [`eval`] and accurate on `[0,1]` for the low degrees of the hot
/// loops; [`eval`] remains the reference.
#[inline(always)]
#[must_use]
pub fn eval_scalar_fast(c: &[f64], t: f64) -> f64 {
    let n = c.len() - 1;
    if n == 0 {
        return c[0];
    }
    if n > MAX_BINOMIAL {
        return eval(c, t);
    }
    let row = &PASCAL[n];
    if t <= 0.5 {
        let s = 1.0 - t;
        let r = t / s;
        // Horner on Σ c_i C(n,i) r^i, from the top.
        let mut acc = c[n];
        for i in (0..n).rev() {
            acc = acc * r + c[i] * row[i];
        }
        acc * powi(s, n)
    } else {
        let r = (1.0 - t) / t;
        let mut acc = c[0];
        for i in 1..=n {
            acc = acc * r + c[i] * row[i];
        }
        acc * powi(t, n)
    }
}

/// Splits a Bernstein form at `t`: `left` receives the coefficients of the piece on `[0,t]` and
/// `right` those on `[t,1]`, each reparameterised to `[0,1]` (de Casteljau subdivision).
///
/// # Panics
/// If `left` or `right` is shorter than `c`.
#[inline]
pub fn subdivide_into<T: Coeff>(c: &[T], t: f64, left: &mut [T], right: &mut [T]) {
    let n = c.len();
    right[..n].copy_from_slice(c);
    left[0] = c[0];
    for (r, l) in left.iter_mut().enumerate().take(n).skip(1) {
        for i in 0..n - r {
            right[i] = right[i].lerp_to(right[i + 1], t);
        }
        *l = right[0];
    }
}

/// [`subdivide_into`] for scalar coefficient arrays of a fixed length `F`: the same de
/// Casteljau passes, written with constant loop bounds so that they unroll (the hot loop of
/// the closest-point query).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // index loops: they unroll for the constant length
pub(crate) fn subdivide_fixed<const F: usize>(
    c: &[f64; F],
    t: f64,
    left: &mut [f64; F],
    right: &mut [f64; F],
) {
    *right = *c;
    left[0] = c[0];
    for r in 1..F {
        for i in 0..F - r {
            right[i] += (right[i + 1] - right[i]) * t;
        }
        left[r] = right[0];
    }
}

/// [`restrict_in_place`] for scalar coefficient arrays of a fixed length `F` (constant loop
/// bounds, as [`subdivide_fixed`]).
#[inline(always)]
pub(crate) fn restrict_fixed<const F: usize>(c: &mut [f64; F], a: f64, b: f64) {
    debug_assert!(a <= b);
    if a > 0.0 {
        for r in 1..F {
            for i in 0..F - r {
                c[i] += (c[i + 1] - c[i]) * a;
            }
        }
    }
    if b < 1.0 {
        let span = 1.0 - a;
        let t = if span > 0.0 { (b - a) / span } else { 0.0 };
        for r in 1..F {
            for i in (r..F).rev() {
                c[i] = c[i - 1] + (c[i] - c[i - 1]) * t;
            }
        }
    }
}

/// Splits a Bernstein form at `t` into the forms on `[0,t]` and `[t,1]`.
#[must_use]
pub fn subdivide<T: Coeff>(c: &[T], t: f64) -> (Vec<T>, Vec<T>) {
    let mut l = vec![T::ZERO; c.len()];
    let mut r = vec![T::ZERO; c.len()];
    subdivide_into(c, t, &mut l, &mut r);
    (l, r)
}

/// In place: keeps the piece on `[t,1]`, reparameterised to `[0,1]`.
#[inline]
pub fn keep_right_in_place<T: Coeff>(c: &mut [T], t: f64) {
    let n = c.len();
    for r in 1..n {
        for i in 0..n - r {
            c[i] = c[i].lerp_to(c[i + 1], t);
        }
    }
}

/// In place: keeps the piece on `[0,t]`, reparameterised to `[0,1]`.
#[inline]
pub fn keep_left_in_place<T: Coeff>(c: &mut [T], t: f64) {
    let n = c.len();
    for r in 1..n {
        for i in (r..n).rev() {
            c[i] = c[i - 1].lerp_to(c[i], t);
        }
    }
}

/// In place: restricts the form to `[a,b] ⊆ [0,1]` and reparameterises it to `[0,1]`
/// (two subdivisions: keep `[a,1]`, then keep the first `(b-a)/(1-a)` of it).
pub fn restrict_in_place<T: Coeff>(c: &mut [T], a: f64, b: f64) {
    debug_assert!(a <= b);
    if a > 0.0 {
        keep_right_in_place(c, a);
    }
    if b < 1.0 {
        let span = 1.0 - a;
        let t = if span > 0.0 { (b - a) / span } else { 0.0 };
        keep_left_in_place(c, t);
    }
}

/// The form restricted to `[a,b]`, reparameterised to `[0,1]`.
#[must_use]
pub fn restrict<T: Coeff>(c: &[T], a: f64, b: f64) -> Vec<T> {
    let mut v = c.to_vec();
    restrict_in_place(&mut v, a, b);
    v
}

/// Derivative (the hodograph of a curve): `d/dt Σ c_i B_i^n = n Σ (c_{i+1} - c_i) B_i^{n-1}`.
/// The derivative of a degree-0 form is the degree-0 zero form.
#[must_use]
pub fn derivative<T: Coeff>(c: &[T]) -> Vec<T> {
    let n = c.len() - 1;
    if n == 0 {
        return vec![T::ZERO];
    }
    (0..n).map(|i| (c[i + 1] - c[i]) * n as f64).collect()
}

/// The `k`-th derivative, by `k` applications of [`derivative`].
#[must_use]
pub fn derivative_k<T: Coeff>(c: &[T], k: usize) -> Vec<T> {
    let mut d = c.to_vec();
    for _ in 0..k {
        d = derivative(&d);
    }
    d
}

/// Degree elevation by one: `c'_i = i/(n+1) c_{i-1} + (1 - i/(n+1)) c_i`, the same polynomial.
#[must_use]
pub fn elevate<T: Coeff>(c: &[T]) -> Vec<T> {
    let n = c.len() - 1;
    let m = (n + 1) as f64;
    let mut out = Vec::with_capacity(n + 2);
    out.push(c[0]);
    for i in 1..=n {
        let a = i as f64 / m;
        out.push(c[i - 1] * a + c[i] * (1.0 - a));
    }
    out.push(c[n]);
    out
}

/// Product of two Bernstein forms under a bilinear pairing `pair` (multiplication for scalars,
/// the dot product for vectors):
/// `f·g = Σ_k h_k B_k^{m+n}`, `h_k = Σ_{i+j=k} C(m,i) C(n,j) / C(m+n,k) · pair(a_i, b_j)`.
///
/// ```
/// use nendo_geom::curve::bernstein::{product, eval};
/// let f = [1.0, 2.0, 0.5];
/// let g = [3.0, -1.0];
/// let h = product(&f, &g, |x, y| x * y);
/// let t = 0.37;
/// assert!((eval(&h, t) - eval(&f, t) * eval(&g, t)).abs() < 1e-14);
/// ```
#[must_use]
pub fn product<A: Copy, B: Copy>(a: &[A], b: &[B], pair: impl Fn(A, B) -> f64) -> Vec<f64> {
    let m = a.len() - 1;
    let n = b.len() - 1;
    let mut h = vec![0.0; m + n + 1];
    for (i, &ai) in a.iter().enumerate() {
        let wi = binomial(m, i);
        for (j, &bj) in b.iter().enumerate() {
            h[i + j] += wi * binomial(n, j) * pair(ai, bj);
        }
    }
    for (k, hk) in h.iter_mut().enumerate() {
        *hk /= binomial(m + n, k);
    }
    h
}

/// Number of sign changes in a coefficient sequence, zeros skipped. By Descartes' rule of signs
/// for Bernstein forms this bounds the number of roots in the open interval `(0,1)`, with the
/// same parity; zero changes means no root there, one change means exactly one simple root.
#[inline]
#[must_use]
pub fn sign_changes(c: &[f64]) -> usize {
    // Without zeros (or NaN) the count is that of adjacent pairs of opposite signs, branch-free;
    // otherwise the zeros are skipped one by one below.
    let Some(&last) = c.last() else {
        return 0;
    };
    let mut irregular = last == 0.0 || last.is_nan();
    let mut flips = 0;
    for k in 1..c.len() {
        irregular |= c[k - 1] == 0.0 || c[k - 1].is_nan();
        flips += usize::from((c[k - 1] < 0.0) != (c[k] < 0.0));
    }
    if !irregular {
        return flips;
    }
    let mut count = 0;
    let mut last = 0.0f64;
    for &x in c {
        if x != 0.0 {
            if (last < 0.0 && x > 0.0) || (last > 0.0 && x < 0.0) {
                count += 1;
            }
            last = x;
        }
    }
    count
}

/// Converts a Bernstein form to the power basis `Σ a_k t^k`:
/// `a_k = C(n,k) Σ_{i=0..k} (-1)^{k-i} C(k,i) c_i`.
#[must_use]
pub fn to_power<T: Coeff>(c: &[T]) -> Vec<T> {
    let n = c.len() - 1;
    (0..=n)
        .map(|k| {
            let mut s = T::ZERO;
            for (i, &ci) in c.iter().enumerate().take(k + 1) {
                let sign = if (k - i) % 2 == 0 { 1.0 } else { -1.0 };
                s = s + ci * (sign * binomial(k, i));
            }
            s * binomial(n, k)
        })
        .collect()
}

/// Converts power-basis coefficients `Σ a_k t^k` to the Bernstein form of the same degree:
/// `c_i = Σ_{k=0..i} C(i,k)/C(n,k) a_k`.
#[must_use]
pub fn from_power<T: Coeff>(a: &[T]) -> Vec<T> {
    let n = a.len() - 1;
    (0..=n)
        .map(|i| {
            let mut s = T::ZERO;
            for (k, &ak) in a.iter().enumerate().take(i + 1) {
                s = s + ak * (binomial(i, k) / binomial(n, k));
            }
            s
        })
        .collect()
}

/// The 4×4 cubic Bernstein matrix at the parameters `ts`: `B[a][i] = B_i^3(ts[a])`.
#[must_use]
pub fn cubic_matrix(ts: [f64; 4]) -> [[f64; 4]; 4] {
    let mut m = [[0.0; 4]; 4];
    for (a, &t) in ts.iter().enumerate() {
        basis_all(3, t, &mut m[a]);
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binomials_match_pascal_and_formula() {
        assert_eq!(binomial(0, 0), 1.0);
        assert_eq!(binomial(9, 4), 126.0);
        assert_eq!(binomial(18, 9), 48620.0);
        let big = binomial(70, 3);
        assert!((big - 54740.0).abs() < 1e-9);
    }

    #[test]
    fn basis_partition_of_unity() {
        let mut out = [0.0; 10];
        for n in 0..10 {
            for &t in &[0.0, 0.1, 0.5, 0.77, 1.0] {
                basis_all(n, t, &mut out);
                let s: f64 = out[..=n].iter().sum();
                assert!((s - 1.0).abs() < 1e-14);
                for (i, &o) in out.iter().enumerate().take(n + 1) {
                    assert!((o - basis(n, i, t)).abs() < 1e-14);
                }
            }
        }
    }

    #[test]
    fn fast_scalar_eval_matches_casteljau() {
        let c = [0.3, -1.2, 4.0, 2.5, -0.7, 0.1, 1.0];
        for k in 0..=20 {
            let t = k as f64 / 20.0;
            assert!((eval_scalar_fast(&c, t) - eval(&c, t)).abs() < 1e-13);
        }
    }

    #[test]
    fn power_basis_round_trip() {
        let c = [1.0, -2.0, 0.5, 3.0, 0.25];
        let a = to_power(&c);
        let back = from_power(&a);
        for (x, y) in c.iter().zip(&back) {
            assert!((x - y).abs() < 1e-12);
        }
        let t = 0.3f64;
        let p: f64 = a
            .iter()
            .enumerate()
            .map(|(k, ak)| ak * t.powi(k as i32))
            .sum();
        assert!((p - eval(&c, t)).abs() < 1e-13);
    }

    #[test]
    fn restrict_matches_evaluation() {
        let c = [0.0, 3.0, -2.0, 1.0, 5.0];
        let (a, b) = (0.2, 0.65);
        let r = restrict(&c, a, b);
        for k in 0..=10 {
            let s = k as f64 / 10.0;
            assert!((eval(&r, s) - eval(&c, a + s * (b - a))).abs() < 1e-13);
        }
    }

    #[test]
    fn sign_change_count_skips_zeros() {
        assert_eq!(sign_changes(&[1.0, 0.0, -1.0, 0.0, 2.0]), 2);
        assert_eq!(sign_changes(&[0.0, 0.0]), 0);
        assert_eq!(sign_changes(&[-1.0, -2.0]), 0);
    }
}
