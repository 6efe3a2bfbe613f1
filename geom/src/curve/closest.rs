//! The closest point on a curve to a query point within a radius, by Bezier clipping
//! (P0 §2.3, P4 §3(1); docs/design.md §4), and picking the nearest of many curves (P0 §3).
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
//!    the interval is closer — the circle test of P4), or when `g`'s coefficients have
//!    no sign change (the distance is monotone; its minimum is an end already counted).
//! 4. By Descartes' rule of signs, one sign change means exactly one root of `g`: a minimum if
//!    `g` goes from negative to positive (found by bracketed Newton), a maximum otherwise
//!    (discarded).
//! 5. The first time an interval needs more than steps 3–4 (several critical points may lie
//!    in it), the neighbourhood `|u − u_s| ≤ 0.25` of the seed `u_s = k_min/(2n)` (where `f`'s
//!    smallest coefficient sits) is cut out (two de Casteljau passes), `f(u_s)` becomes a
//!    candidate, and that piece is examined first: it usually holds the global minimum, found
//!    by step 4's Newton finish, whose value then prunes the two outer pieces by step 3 alone.
//!    Measured on the cases of `nendo bench closest` (callgrind): 5–7 % fewer instructions
//!    per query than the previous version, which only evaluated `f` at the seed (spread,
//!    close and 3D cubics), though more intervals are counted (spread 1.69 → 2.08
//!    per query, close 3.51 → 3.84, the cut's pieces included); the seed `k_min/(2n)` needed fewer clips than the control polygon's point
//!    nearest `Q` or the best of nine samples of `f`, and half-width 0.25 fewer than 0.05–0.4.
//! 6. Otherwise clip: keep the part of the interval where `f`'s hull dips below `d_min²`
//!    (end-line bounds of the hull, [`clip::end_lines_below`]); if that removes less than
//!    20 %, split it in two (one de Casteljau pass; the right half waits on a stack).
//!    Clipping `g`'s own hull against zero as well was measured and not kept: it made the
//!    queries of `nendo bench closest` 20–30 % more expensive (close queries 30 %), since
//!    Descartes' rule on `g` (step 4) already isolates the roots after a split or two.
//!    The split threshold (a clip that removes less than 20 %) was measured at 10, 20, 35 and
//!    50 %: 20–50 % lie within 0.5 % of each other in instructions per query; 10 % costs close
//!    queries 2.5 % more.
//! 7. Every better value found shrinks `d_min` for the intervals still to come.
//!
//! Also measured and not kept (callgrind, instructions per query on 500 cases of each set of
//! `nendo bench closest`, spread / close / 3D cubics): a Newton descent on `g` from the seed
//! over the whole interval before step 5's cut — steps taken only where `g' > 0`, so that they
//! head for a minimum, up to 12 — to have a tight bound before any split. It cost more than it
//! saved however its end point `u*` was used: the cut centred on `u*` (half-width 0.25:
//! +14 / +21 / +15 %; 0.1: +16 / +18 / +16 %; 0.05: +17 / +20 / +17 %), no cut and the whole
//! interval clipped against the tight bound (fewer intervals, 1.66 instead of 2.08 on spread
//! queries, but +17 / +30 / +17 %), or the cut kept at `k_min/(2n)` with `f(u*)` as the bound
//! and `u*` as the start of the bracketed Newton finish (+13 / +15 / +13 %). The descent adds
//! about 1.1 Newton iterations per spread query and 2.4 per close query, plus a power-basis
//! conversion, while the cut path it would shorten is taken by 46 % of the spread queries
//! (916 of 2 000; the others hold one critical point or none).
//!
//! Where the work goes (callgrind, 2D cubic spread queries, about 1 300 instructions each):
//! about a third before and after the search (the translation, the magnitude check for
//! rescaling, `f`'s product coefficients, the seed, `C(u) − Q` by de Casteljau for the
//! result), the rest in the clipping loop (`minimize_fixed`): about 90 per interval for the
//! tests of steps 3–4 (2.08 intervals per query), about 190 for the Newton finish (the
//! power-basis conversion and 2.4 iterations), and the cut's two de Casteljau passes.
//!
//! The result's distance is `|C(u) − Q|` evaluated by de Casteljau on the translated control
//! points `p_i`, so it is accurate to rounding even where `f` suffers cancellation (a query on
//! the curve); the point is `Q + (C(u) − Q)`.

use super::bernstein;
use super::bezier::{Bezier, MAX_DEGREE};
use super::clip;
use super::point::Point;

/// Width (in the curve's parameter) below which an interval that still holds several sign
/// changes of `g` is taken as converged: reached only at multiple roots of `g`.
const U_WIDTH: f64 = 1e-12;

/// Half the width (in the curve's parameter) of the neighbourhood of the seed that is cut out
/// and examined first when the whole interval holds several critical points.
const SEED_HALF_WIDTH: f64 = 0.25;

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

const W: usize = MAX_DEGREE + 1;

/// `C(n,i) C(n,j) / C(2n,i+j)` for `n ≤ MAX_DEGREE`: the weights of the product formula.
static PRODUCT_WEIGHTS: [[[f64; W]; W]; W] = product_weights();

const fn product_weights() -> [[[f64; W]; W]; W] {
    // Pascal's triangle up to 2 · MAX_DEGREE, exactly in f64 (all values < 2^53).
    const R: usize = 2 * MAX_DEGREE + 1;
    let mut c = [[0.0f64; R]; R];
    let mut n = 0;
    while n < R {
        c[n][0] = 1.0;
        let mut k = 1;
        while k <= n {
            c[n][k] = c[n - 1][k - 1] + if k < n { c[n - 1][k] } else { 0.0 };
            k += 1;
        }
        n += 1;
    }
    let mut w = [[[0.0f64; W]; W]; W];
    let mut n = 0;
    while n < W {
        let mut i = 0;
        while i <= n {
            let mut j = 0;
            while j <= n {
                w[n][i][j] = c[n][i] * c[n][j] / c[2 * n][i + j];
                j += 1;
            }
            i += 1;
        }
        n += 1;
    }
    w
}

/// `f_k` of `|C(u) − Q|²` for the translated control points `p` (docs/design.md §4, the product formula
/// `f_k = Σ_{i+j=k} C(n,i) C(n,j)/C(2n,k) p_i·p_j`), written into `out[..2n+1]`.
///
/// # Panics
/// If `p` has more than `MAX_DEGREE + 1` points or `out` fewer than `2n + 1` entries.
#[inline(always)]
pub(crate) fn distance_squared_coeffs<P: Point>(p: &[P], out: &mut [f64]) {
    let n = p.len() - 1;
    let w = &PRODUCT_WEIGHTS[n];
    for o in out.iter_mut().take(2 * n + 1) {
        *o = 0.0;
    }
    for i in 0..=n {
        out[2 * i] += w[i][i] * p[i].dot(p[i]);
        for j in i + 1..=n {
            out[i + j] += 2.0 * w[i][j] * p[i].dot(p[j]);
        }
    }
}

/// An interval still to examine: `[a, b]` and `f` restricted to it.
#[derive(Clone, Copy)]
struct Pending<const F: usize> {
    w: [f64; F],
    a: f64,
    b: f64,
}

/// A small stack of pending intervals that only allocates past 4 entries (deeper splits are
/// rare: they happen only near several close roots of `g`).
struct IntervalStack<const F: usize> {
    small: [Option<Pending<F>>; 4],
    len: usize,
    spill: Vec<Pending<F>>,
}

impl<const F: usize> IntervalStack<F> {
    #[inline]
    fn new() -> Self {
        Self {
            // Only the tags are written: no zeroing of the coefficient arrays per query.
            small: [None, None, None, None],
            len: 0,
            spill: Vec::new(),
        }
    }
    #[inline]
    fn push(&mut self, p: Pending<F>) {
        if self.len < self.small.len() {
            self.small[self.len] = Some(p);
            self.len += 1;
        } else {
            self.spill.push(p);
        }
    }
    #[inline]
    fn pop(&mut self) -> Option<Pending<F>> {
        if let Some(p) = self.spill.pop() {
            return Some(p);
        }
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        self.small[self.len].take()
    }
}

/// Global minimum of the Bernstein function `f` (coefficients on `[0,1]`, `F = 2n + 1` of them)
/// over `[a0, b0]`, among values below `bound` (strictly): returns `(u, f(u))`, or `None` when
/// `f ≥ bound` on the whole interval. Steps 3–7 of the module documentation; `f`'s values at
/// the ends of every interval examined are candidates. With `SEEDED`, the first interval
/// that needs clipping first has `seed`'s neighbourhood cut out (step 5); without, that code
/// is compiled out (the ray query).
fn minimize_fixed<const F: usize, const SEEDED: bool>(
    f: &[f64; F],
    a0: f64,
    b0: f64,
    bound: f64,
    mut seed: Option<f64>,
    stats: &mut ClipStats,
) -> Option<(f64, f64)> {
    let m = F - 1;
    let mut best_f = bound;
    let mut best_u = f64::NAN;
    let mut w = *f;
    let mut g = [0.0; F];
    let mut stack = IntervalStack::new();
    let mut steps = 0u32;
    let (mut a, mut b) = (a0, b0);
    bernstein::restrict_fixed(&mut w, a, b);
    loop {
        'interval: loop {
            steps += 1;
            stats.clips += 1;
            if steps > MAX_STEPS {
                break 'interval;
            }
            if w[0] < best_f {
                best_f = w[0];
                best_u = a;
            }
            if w[m] < best_f {
                best_f = w[m];
                best_u = b;
            }
            let mut low = w[0];
            for &v in &w[1..] {
                if v < low {
                    low = v;
                }
            }
            if low >= best_f || low.is_nan() || m == 0 {
                break 'interval;
            }
            for k in 0..m {
                g[k] = w[k + 1] - w[k];
            }
            let gk = &g[..m];
            let changes = bernstein::sign_changes(gk);
            if changes == 0 {
                break 'interval;
            }
            if changes == 1 {
                let first = if gk[0] != 0.0 {
                    gk[0]
                } else {
                    gk.iter().copied().find(|&v| v != 0.0).unwrap_or(0.0)
                };
                if first > 0.0 {
                    break 'interval; // a maximum inside; both ends already counted
                }
                if gk[0] != 0.0 && gk[m - 1] != 0.0 {
                    let (s, it) = clip::clipped_root(gk);
                    stats.newton += it;
                    let v = bernstein::eval_scalar_fast(&w, s);
                    if v < best_f {
                        best_f = v;
                        best_u = a + s * (b - a);
                    }
                    break 'interval;
                }
            }
            if let Some(u_seed) = if SEEDED { seed.take() } else { None } {
                // Several critical points may lie here: first cut out the seed's neighbourhood
                // (two de Casteljau passes give the three pieces), evaluate f at the seed, and
                // examine that piece first; its minimum, usually the global one, becomes the
                // bound that prunes the two outer pieces, which wait on the stack.
                let span = b - a;
                let s = ((u_seed - a) / span).clamp(0.0, 1.0);
                let h = SEED_HALF_WIDTH / span;
                let (sl, sr) = ((s - h).max(0.0), (s + h).min(1.0));
                if sl > 0.0 || sr < 1.0 {
                    stats.splits += 1;
                    let mut rest = w;
                    if sl > 0.0 {
                        let mut left = Pending {
                            w: [0.0; F],
                            a,
                            b: a + sl * span,
                        };
                        bernstein::subdivide_fixed(&w, sl, &mut left.w, &mut rest);
                        stack.push(left);
                    }
                    if sr < 1.0 {
                        let mut right = Pending {
                            w: [0.0; F],
                            a: a + sr * span,
                            b,
                        };
                        let t = (sr - sl) / (1.0 - sl);
                        bernstein::subdivide_fixed(&rest, t, &mut w, &mut right.w);
                        stack.push(right);
                    } else {
                        w = rest;
                    }
                    b = a + sr * span;
                    a += sl * span;
                    let local = ((u_seed - a) / (b - a)).clamp(0.0, 1.0);
                    let v = bernstein::eval_scalar_fast(&w, local);
                    if v < best_f {
                        best_f = v;
                        best_u = a + local * (b - a);
                    }
                    continue 'interval;
                }
            }
            let Some((lo, hi)) = clip::end_lines_below(&w, best_f) else {
                break 'interval;
            };
            if lo > hi {
                break 'interval;
            }
            let (lo, hi) = clip::widen(lo, hi);
            let span = b - a;
            if (hi - lo) * span < U_WIDTH {
                let s = 0.5 * (lo + hi);
                let v = bernstein::eval_scalar_fast(&w, s);
                if v < best_f {
                    best_f = v;
                    best_u = a + s * span;
                }
                break 'interval;
            }
            if hi - lo > 0.8 {
                // The clip removed less than 20 %: split the interval (the curve) in two. One
                // de Casteljau pass at 1/2 gives both halves; the right one waits on the stack.
                stats.splits += 1;
                bernstein::restrict_fixed(&mut w, lo, hi);
                let whole = w;
                let mut right = Pending {
                    w: [0.0; F],
                    a: a + 0.5 * (lo + hi) * span,
                    b: a + hi * span,
                };
                bernstein::subdivide_fixed(&whole, 0.5, &mut w, &mut right.w);
                stack.push(right);
                b = right.a;
                a += lo * span;
                continue 'interval;
            }
            bernstein::restrict_fixed(&mut w, lo, hi);
            b = a + hi * span;
            a += lo * span;
        }
        let Some(next) = stack.pop() else { break };
        (w, a, b) = (next.w, next.a, next.b);
    }
    best_u.is_finite().then_some((best_u, best_f))
}

/// Calls `$body` with `F` bound, as a const, to the odd length `2n + 1` of a degree-`2n`
/// Bernstein function (`n ≤ MAX_DEGREE`); evaluates `$none` for any other length.
macro_rules! with_product_len {
    ($len:expr, $F:ident => $body:expr, $none:expr) => {
        match $len {
            1 => {
                const $F: usize = 1;
                $body
            }
            3 => {
                const $F: usize = 3;
                $body
            }
            5 => {
                const $F: usize = 5;
                $body
            }
            7 => {
                const $F: usize = 7;
                $body
            }
            9 => {
                const $F: usize = 9;
                $body
            }
            11 => {
                const $F: usize = 11;
                $body
            }
            13 => {
                const $F: usize = 13;
                $body
            }
            15 => {
                const $F: usize = 15;
                $body
            }
            17 => {
                const $F: usize = 17;
                $body
            }
            19 => {
                const $F: usize = 19;
                $body
            }
            21 => {
                const $F: usize = 21;
                $body
            }
            23 => {
                const $F: usize = 23;
                $body
            }
            25 => {
                const $F: usize = 25;
                $body
            }
            27 => {
                const $F: usize = 27;
                $body
            }
            29 => {
                const $F: usize = 29;
                $body
            }
            31 => {
                const $F: usize = 31;
                $body
            }
            33 => {
                const $F: usize = 33;
                $body
            }
            35 => {
                const $F: usize = 35;
                $body
            }
            37 => {
                const $F: usize = 37;
                $body
            }
            39 => {
                const $F: usize = 39;
                $body
            }
            41 => {
                const $F: usize = 41;
                $body
            }
            _ => $none,
        }
    };
}

/// [`minimize_fixed`] for a slice of odd length `2n + 1 ≤ 2 MAX_DEGREE + 1`.
pub(crate) fn minimize_below(
    f: &[f64],
    a0: f64,
    b0: f64,
    bound: f64,
    stats: &mut ClipStats,
) -> Option<(f64, f64)> {
    with_product_len!(f.len(), F => {
        let arr: &[f64; F] = f.try_into().ok()?;
        minimize_fixed::<F, false>(arr, a0, b0, bound, None, stats)
    }, None)
}

/// The part of `[0,1]` where the curve `p` (translated control points) lies inside the band
/// `|p(u)·L| ≤ d` perpendicular to its chord; `[0,1]` when the chord is degenerate.
#[inline]
fn chord_band<P: Point>(p: &[P], d: f64) -> Option<(f64, f64)> {
    let n = p.len() - 1;
    let chord = p[n] - p[0];
    let len2 = chord.dot(chord);
    if len2.is_nan() || len2 <= 0.0 || n == 0 {
        return Some((0.0, 1.0));
    }
    let l = chord * (1.0 / len2.sqrt());
    let mut s = [0.0; MAX_DEGREE + 1];
    for (si, &pi) in s.iter_mut().zip(p) {
        *si = pi.dot(l);
    }
    let s = &s[..=n];
    let (a1, b1) = clip::hull_range(s, d, 1.0)?;
    let (a2, b2) = clip::hull_range(s, -d, -1.0)?;
    let lo = if a1 > a2 { a1 } else { a2 };
    let hi = if b1 < b2 { b1 } else { b2 };
    (lo <= hi).then_some(clip::widen(lo, hi))
}

/// The parameter `u` of the closest point and `C(u) − Q` (steps 1–2, then [`minimize_fixed`]).
#[inline]
fn closest_u<P: Point, const F: usize, const N: usize>(
    pts: &[P],
    q: P,
    r_max: f64,
    stats: &mut ClipStats,
) -> Option<(f64, P)> {
    // The degree as a constant of this instantiation, so the fixed-size loops below unroll.
    let n = N - 1;
    if pts.len() != N || F != 2 * n + 1 {
        return None;
    }
    let mut buf = [P::ZERO; N];
    for (pi, &c) in buf.iter_mut().zip(pts) {
        *pi = c - q;
    }
    let p = &buf;
    let u = closest_u_translated::<P, F>(p, r_max, stats)?;
    // C(u) − Q by de Casteljau on the translated points: accurate to rounding even where f
    // suffers cancellation (a query on the curve).
    let mut at = buf;
    for r in 1..N {
        for i in 0..N - r {
            at[i] = at[i].lerp_to(at[i + 1], u);
        }
    }
    Some((u, at[0]))
}

/// The parameter of the closest point for the translated control points `p` (`C − Q`).
#[inline(always)]
fn closest_u_translated<P: Point, const F: usize>(
    p: &[P],
    r_max: f64,
    stats: &mut ClipStats,
) -> Option<f64> {
    let n = (F - 1) / 2;
    // Step 1: the end points are candidates; d_min bounds the search.
    let d0 = p[0].length();
    let dn = p[n].length();
    let mut d_min = r_max;
    let mut best = None;
    if d0 <= d_min {
        d_min = d0;
        best = Some(0.0);
    }
    if dn < d_min {
        d_min = dn;
        best = Some(1.0);
    }
    if n == 0 || d_min.is_nan() || d_min <= 0.0 {
        return best;
    }
    // Step 2: the band perpendicular to the chord, where R_max is what bounds the search (a
    // pick among many curves, a probe). When d_min comes from an end point the band seldom
    // removes anything and costs more than it saves (measured: `nendo bench closest`).
    let (lo, hi) = if d_min < d0 && d_min < dn {
        match chord_band(p, d_min) {
            Some(band) => band,
            None => return best,
        }
    } else {
        (0.0, 1.0)
    };
    let mut f = [0.0; F];
    distance_squared_coeffs(p, &mut f);
    let bound = if d_min.is_finite() {
        d_min * d_min
    } else {
        f64::INFINITY
    };
    // The seed: where f's smallest coefficient sits (the control polygon of f dips lowest
    // there; measured against the control polygon's point nearest the query and against the
    // best of nine samples of f, it needed the fewest clips on `nendo bench closest`).
    let mut k_min = 0;
    for k in 1..F {
        if f[k] < f[k_min] {
            k_min = k;
        }
    }
    let u_seed = k_min as f64 / (F - 1) as f64;
    let u_seed = u_seed.clamp(lo, hi);
    match minimize_fixed::<F, true>(&f, lo, hi, bound, Some(u_seed), stats) {
        Some((u, _)) => Some(u),
        None => best,
    }
}

/// Coordinates beyond this magnitude (or below its reciprocal) are rescaled before a query,
/// so that the squares in `f` neither overflow nor underflow (`2^400 ≈ 2.6e120`).
const EXTREME: f64 = 2.582_249_878_086_908_6e120;

/// The largest coordinate magnitude among `pts` and `q`.
#[inline]
pub(crate) fn magnitude<P: Point>(pts: &[P], q: P) -> f64 {
    let (mut lo, mut hi) = (q, q);
    for &c in pts {
        lo = lo.min_by_coord(c);
        hi = hi.max_by_coord(c);
    }
    let mut m = 0.0f64;
    for i in 0..P::DIM {
        let a = hi.coord(i).max(-lo.coord(i));
        if a > m {
            m = a;
        }
    }
    m
}

/// A power of two `s` that brings a magnitude `m` near 1 when it lies outside
/// `[1/EXTREME, EXTREME]`, else 1. Scaling by a power of two is exact (short of subnormals),
/// so distances and parameters found on the scaled copy are those of the original.
#[inline]
#[allow(clippy::manual_range_contains)]
pub(crate) fn rescale_for(m: f64) -> f64 {
    // Plain comparisons: `RangeInclusive::contains` cost about 80 instructions per query here.
    if !(m >= 1.0 / EXTREME && m <= EXTREME) && m > 0.0 && m.is_finite() {
        let e = m.log2().floor() as i32;
        2f64.powi(-e)
    } else {
        1.0
    }
}

/// The slack, relative to the coordinates' magnitude, with which "within `R_max`" is
/// inclusive: a point at exactly `R_max` (or on the curve, for `R_max = 0`) is found even when
/// rounding puts its computed distance an ulp beyond (`2^-50 ≈ 8.9e-16`).
pub(crate) const WITHIN_SLACK: f64 = 8.881_784_197_001_252e-16;

/// The closest point of a Bezier curve to `q` no farther than `r_max` (pass `f64::INFINITY`
/// for no limit), with the work counted into `stats`. `None` when nothing lies within `r_max`
/// or when the query is not finite. "Within" is inclusive up to rounding: a point whose
/// distance is `r_max` to within `WITHIN_SLACK` times the coordinates' magnitude counts.
/// Ties (two equally close points) resolve to the point found first, deterministically.
/// Coordinates of extreme magnitude (beyond about 1e120, or below 1e-120) are rescaled by a
/// power of two for the search, so their squares neither overflow nor underflow.
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
    let m = magnitude(pts, q);
    let slack = WITHIN_SLACK * m;
    let s = rescale_for(m);
    let scaled: Vec<P>;
    let (search, qs) = if s == 1.0 {
        (pts, q)
    } else {
        scaled = pts.iter().map(|&c| c * s).collect();
        (&scaled[..], q * s)
    };
    let (u, at) = with_product_len!(2 * pts.len() - 1, F => {
        const N: usize = F.div_ceil(2);
        closest_u::<P, F, N>(search, qs, (r_max + slack) * s, stats)
    }, None)?;
    // `at = C(u) − Q` (on the scaled copy when rescaled: de Casteljau's differences of huge
    // coordinates could overflow on the original).
    let (point, distance) = if s == 1.0 {
        (at + q, at.length())
    } else {
        ((at + qs) * (1.0 / s), at.length() / s)
    };
    (distance <= r_max + slack).then_some(Nearest { u, point, distance })
}

/// The closest point of a Bezier curve to `q` within `r_max` (`f64::INFINITY` for no limit).
///
/// ```
/// use glam::DVec2;
/// use nendo_geom::curve::{closest_bezier, Bezier};
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
    q.box_distance_squared(lo, hi)
}
