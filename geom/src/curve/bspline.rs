//! B-spline curves: `C(t) = Σ_{k=0..n−1} P_k N_{k,p}(t)` over a knot vector `t_0 ≤ … ≤ t_{n+p}`,
//! on the domain `[t_p, t_n]` (docs/design.md §3, P4 §3).
//!
//! Evaluation by de Boor's algorithm, knot insertion by Boehm's algorithm, conversion to Bezier
//! segments by blossoming (each segment's control points are the blossom values
//! `b(a,…,a,b,…,b)` on its span), and splitting at a parameter by knot insertion. Clamped and
//! unclamped knot vectors are both accepted; every query works on the domain `[t_p, t_n]`.

use super::bezier::{Bezier, MAX_DEGREE};
use super::error::CurveError;
use super::point::Point;

/// A B-spline curve of degree `p ≥ 1`.
///
/// ```
/// use glam::DVec2;
/// use nendo_geom::curve::BSpline;
/// // A clamped cubic with one interior knot: two Bezier segments.
/// let pts = vec![DVec2::ZERO, DVec2::X, DVec2::new(2.0, 1.0), DVec2::new(3.0, 0.0), DVec2::new(4.0, 0.0)];
/// let s = BSpline::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0], pts)?;
/// assert_eq!(s.domain(), (0.0, 1.0));
/// assert_eq!(s.to_bezier_segments().len(), 2);
/// # Ok::<(), nendo_geom::curve::CurveError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct BSpline<P> {
    degree: usize,
    knots: Vec<f64>,
    points: Vec<P>,
}

/// One Bezier segment of a B-spline and the B-spline parameters `[start, end]` it covers.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment<P> {
    /// The segment as a Bezier curve on `[0,1]`.
    pub bezier: Bezier<P>,
    /// B-spline parameter at the segment's `t = 0`.
    pub start: f64,
    /// B-spline parameter at the segment's `t = 1`.
    pub end: f64,
}

impl<P> Segment<P> {
    /// The B-spline parameter of the segment parameter `s ∈ [0,1]`.
    #[inline]
    #[must_use]
    pub fn to_global(&self, s: f64) -> f64 {
        // The segment's ends map to its knots exactly (so that pieces meeting at a knot meet
        // exactly, and no parameter leaves the domain by an ulp).
        if s <= 0.0 {
            return self.start;
        }
        if s >= 1.0 {
            return self.end;
        }
        let t = self.start + s * (self.end - self.start);
        t.clamp(self.start, self.end)
    }
}

impl<P: Point> BSpline<P> {
    /// A B-spline from its degree, knots and control points, validated: degree in
    /// `1..=Bezier::MAX_DEGREE`, at least `p + 1` points, exactly `n + p + 1` finite knots,
    /// non-decreasing, a non-empty domain, no knot inside the domain of multiplicity above `p`
    /// (the curve stays connected) and none elsewhere above `p + 1`, finite points.
    pub fn try_new(degree: usize, knots: Vec<f64>, points: Vec<P>) -> Result<Self, CurveError> {
        if degree == 0 {
            return Err(CurveError::ZeroDegree);
        }
        if degree > Bezier::<P>::MAX_DEGREE {
            return Err(CurveError::DegreeTooHigh {
                degree,
                max: Bezier::<P>::MAX_DEGREE,
            });
        }
        if points.is_empty() {
            return Err(CurveError::Empty);
        }
        if points.len() < degree + 1 {
            return Err(CurveError::TooFewPoints {
                degree,
                needed: degree + 1,
                got: points.len(),
            });
        }
        let expected = points.len() + degree + 1;
        if knots.len() != expected {
            return Err(CurveError::KnotCount {
                degree,
                points: points.len(),
                expected,
                got: knots.len(),
            });
        }
        if let Some(i) = knots.iter().position(|k| !k.is_finite()) {
            return Err(CurveError::NotFinite {
                what: format!("knot {i}"),
            });
        }
        if let Some(i) = (1..knots.len()).find(|&i| knots[i] < knots[i - 1]) {
            return Err(CurveError::KnotsDecreasing { index: i });
        }
        let (start, end) = (knots[degree], knots[points.len()]);
        if start >= end {
            return Err(CurveError::EmptyDomain { start, end });
        }
        let mut i = 0;
        while i < knots.len() {
            let mut j = i;
            while j < knots.len() && knots[j] == knots[i] {
                j += 1;
            }
            // Inside the domain a knot of multiplicity p + 1 would break the curve apart.
            let max = if knots[i] > start && knots[i] < end {
                degree
            } else {
                degree + 1
            };
            if j - i > max {
                return Err(CurveError::KnotMultiplicity {
                    value: knots[i],
                    multiplicity: j - i,
                    max,
                });
            }
            i = j;
        }
        if let Some(i) = points.iter().position(|p| !p.is_finite_coeff()) {
            return Err(CurveError::NotFinite {
                what: format!("control point {i}"),
            });
        }
        if let Some(i) = points.iter().position(|&p| super::bezier::too_large(p)) {
            return Err(CurveError::TooLarge {
                what: format!("control point {i}"),
            });
        }
        Ok(Self {
            degree,
            knots,
            points,
        })
    }

    /// A clamped uniform B-spline (end knots of multiplicity `p + 1`, interior knots evenly
    /// spaced on `[0,1]`).
    pub fn clamped_uniform(degree: usize, points: Vec<P>) -> Result<Self, CurveError> {
        let n = points.len();
        if n < degree + 1 {
            return Err(CurveError::TooFewPoints {
                degree,
                needed: degree + 1,
                got: n,
            });
        }
        let spans = n - degree;
        let mut knots = vec![0.0; degree + 1];
        knots.extend((1..spans).map(|i| i as f64 / spans as f64));
        knots.extend(std::iter::repeat_n(1.0, degree + 1));
        Self::try_new(degree, knots, points)
    }

    /// The degree `p`.
    #[inline]
    #[must_use]
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knot vector.
    #[inline]
    #[must_use]
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// The control points.
    #[inline]
    #[must_use]
    pub fn points(&self) -> &[P] {
        &self.points
    }

    /// The parameter domain `[t_p, t_n]`.
    #[inline]
    #[must_use]
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.points.len()])
    }

    /// The span index `k ∈ [p, n−1]` with `t_k ≤ t < t_{k+1}`; at (or beyond) the domain end the
    /// last non-empty span, before the domain start the first.
    #[must_use]
    pub fn span(&self, t: f64) -> usize {
        let p = self.degree;
        let n = self.points.len();
        if t >= self.knots[n] {
            let mut k = n - 1;
            while k > p && self.knots[k] >= self.knots[n] {
                k -= 1;
            }
            return k;
        }
        if t <= self.knots[p] {
            let mut k = p;
            while k + 1 < n && self.knots[k + 1] <= self.knots[p] {
                k += 1;
            }
            return k;
        }
        // Binary search for the last k with t_k ≤ t.
        let (mut lo, mut hi) = (p, n);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if self.knots[mid] <= t {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// The blossom `b(u_1, …, u_p)` of the span `k` by the de Boor recurrence: at level `r`,
    /// `P_i^r = (1 − α) P_{i−1}^{r−1} + α P_i^{r−1}`, `α = (u_r − t_i)/(t_{i+p+1−r} − t_i)`,
    /// `i = k−p+r … k`; the curve point is the blossom with every `u_r = t`.
    fn blossom(&self, k: usize, us: &[f64]) -> P {
        let p = self.degree;
        let mut d: [P; MAX_DEGREE + 1] = [P::ZERO; MAX_DEGREE + 1];
        d[..=p].copy_from_slice(&self.points[k - p..=k]);
        for (r, &u) in us.iter().enumerate().map(|(r, u)| (r + 1, u)) {
            for j in (r..=p).rev() {
                let i = k - p + j;
                let denom = self.knots[i + p + 1 - r] - self.knots[i];
                let alpha = if denom > 0.0 {
                    (u - self.knots[i]) / denom
                } else {
                    0.0
                };
                d[j] = d[j - 1].lerp_to(d[j], alpha);
            }
        }
        d[p]
    }

    /// `C(t)` by de Boor's algorithm; `t` is clamped to the domain.
    #[must_use]
    pub fn eval(&self, t: f64) -> P {
        let (a, b) = self.domain();
        let t = t.clamp(a, b);
        let k = self.span(t);
        let us = [t; MAX_DEGREE];
        self.blossom(k, &us[..self.degree])
    }

    /// The Bezier segments of the curve, one per non-empty knot span of the domain, each with
    /// the B-spline parameters it covers. Control point `j` of the segment on `[a,b]` is the
    /// blossom `b(a^{p−j}, b^j)` (`a` repeated `p − j` times).
    #[must_use]
    pub fn to_bezier_segments(&self) -> Vec<Segment<P>> {
        let p = self.degree;
        let n = self.points.len();
        let mut out = Vec::with_capacity(n - p);
        for k in p..n {
            let (a, b) = (self.knots[k], self.knots[k + 1]);
            if a >= b {
                continue;
            }
            let mut us = [0.0; MAX_DEGREE];
            let pts: Vec<P> = (0..=p)
                .map(|j| {
                    for (r, u) in us[..p].iter_mut().enumerate() {
                        *u = if r < p - j { a } else { b };
                    }
                    self.blossom(k, &us[..p])
                })
                .collect();
            out.push(Segment {
                bezier: Bezier::from_derived(pts),
                start: a,
                end: b,
            });
        }
        out
    }

    /// Inserts the knot `t` once (Boehm): with `t` in span `k`,
    /// `Q_i = (1 − a_i) P_{i−1} + a_i P_i`, `a_i = (t − t_i)/(t_{i+p} − t_i)` for
    /// `i = k−p+1 … k`, `Q_i = P_i` before and `P_{i−1}` after. The curve is unchanged.
    /// Errors if `t` is outside the domain, or if the insertion would raise its multiplicity
    /// above `p + 1` (above `p` at a domain end).
    pub fn insert_knot(&self, t: f64) -> Result<Self, CurveError> {
        let (a, b) = self.domain();
        if !t.is_finite() || t < a || t > b {
            return Err(CurveError::OutOfDomain {
                t,
                range: format!(
                    "the domain [{}, {}]",
                    crate::num::Compact(a),
                    crate::num::Compact(b)
                ),
            });
        }
        let p = self.degree;
        let mult = self.knots.iter().filter(|&&k| k == t).count();
        if mult > p || ((t == a || t == b) && mult >= p) {
            return Err(CurveError::KnotMultiplicity {
                value: t,
                multiplicity: mult + 1,
                max: p,
            });
        }
        let k = self.span(t);
        let n = self.points.len();
        let mut q = Vec::with_capacity(n + 1);
        for i in 0..=n {
            let pt = if i + p <= k {
                self.points[i]
            } else if i > k {
                self.points[i - 1]
            } else {
                let denom = self.knots[i + p] - self.knots[i];
                let alpha = if denom > 0.0 {
                    (t - self.knots[i]) / denom
                } else {
                    0.0
                };
                self.points[i - 1].lerp_to(self.points[i], alpha)
            };
            q.push(pt);
        }
        let mut knots = Vec::with_capacity(self.knots.len() + 1);
        knots.extend_from_slice(&self.knots[..=k]);
        knots.push(t);
        knots.extend_from_slice(&self.knots[k + 1..]);
        Ok(Self {
            degree: p,
            knots,
            points: q,
        })
    }

    /// Splits the curve at `t` (strictly inside the domain) into two B-splines covering
    /// `[t_p, t]` and `[t, t_n]`: `t` is inserted until it has multiplicity `p`, so that the curve
    /// passes through a control point there, and each half receives a clamped end at `t`.
    pub fn split(&self, t: f64) -> Result<(Self, Self), CurveError> {
        let (a, b) = self.domain();
        if !t.is_finite() || t <= a || t >= b {
            return Err(CurveError::OutOfDomain {
                t,
                range: format!(
                    "the open domain ({}, {})",
                    crate::num::Compact(a),
                    crate::num::Compact(b)
                ),
            });
        }
        let p = self.degree;
        let mut s = self.clone();
        while s.knots.iter().filter(|&&k| k == t).count() < p {
            s = s.insert_knot(t)?;
        }
        // First index of t in the knot vector; the curve point at t is P_{m−1}.
        let m = s.knots.iter().position(|&k| k == t).unwrap_or(0);
        let mut lk = s.knots[..m + p].to_vec();
        lk.push(t);
        let lp = s.points[..m].to_vec();
        let mut rk = vec![t];
        rk.extend_from_slice(&s.knots[m..]);
        let rp = s.points[m - 1..].to_vec();
        Ok((Self::try_new(p, lk, lp)?, Self::try_new(p, rk, rp)?))
    }

    /// Axis-aligned bounds of the control points that influence the domain.
    #[must_use]
    pub fn control_bounds(&self) -> (P, P) {
        let mut lo = self.points[0];
        let mut hi = self.points[0];
        for &p in &self.points[1..] {
            lo = lo.min_by_coord(p);
            hi = hi.max_by_coord(p);
        }
        (lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    fn sample() -> BSpline<DVec2> {
        let pts = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 2.0),
            DVec2::new(2.0, -1.0),
            DVec2::new(3.0, 3.0),
            DVec2::new(4.0, 0.0),
            DVec2::new(5.0, 1.0),
        ];
        BSpline::try_new(
            3,
            vec![0.0, 0.1, 0.2, 0.3, 0.5, 0.5, 0.9, 1.0, 1.1, 1.3],
            pts,
        )
        .expect("valid")
    }

    /// Cox–de Boor recursion: an independent reference for evaluation.
    fn cox_de_boor(s: &BSpline<DVec2>, t: f64) -> DVec2 {
        fn n(knots: &[f64], i: usize, p: usize, t: f64, last: bool) -> f64 {
            if p == 0 {
                let inside = knots[i] <= t && t < knots[i + 1];
                let at_end = last && t == knots[i + 1] && knots[i] < knots[i + 1];
                return if inside || at_end { 1.0 } else { 0.0 };
            }
            let mut v = 0.0;
            let d1 = knots[i + p] - knots[i];
            if d1 > 0.0 {
                v += (t - knots[i]) / d1 * n(knots, i, p - 1, t, last);
            }
            let d2 = knots[i + p + 1] - knots[i + 1];
            if d2 > 0.0 {
                v += (knots[i + p + 1] - t) / d2 * n(knots, i + 1, p - 1, t, last);
            }
            v
        }
        let (_, b) = s.domain();
        let last = t >= b;
        s.points()
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                p * n(
                    s.knots(),
                    i,
                    s.degree(),
                    if last { b - 1e-15 } else { t },
                    false,
                )
            })
            .fold(DVec2::ZERO, |a, b| a + b)
    }

    #[test]
    fn de_boor_matches_cox_de_boor() {
        let s = sample();
        let (a, b) = s.domain();
        for k in 0..=40 {
            let t = a + (b - a) * k as f64 / 40.0;
            assert!((s.eval(t) - cox_de_boor(&s, t)).length() < 1e-12, "t = {t}");
        }
    }

    #[test]
    fn segments_cover_the_domain_and_match() {
        let s = sample();
        let segs = s.to_bezier_segments();
        assert_eq!(segs.len(), 2);
        for seg in &segs {
            for k in 0..=10 {
                let u = k as f64 / 10.0;
                let t = seg.to_global(u);
                assert!((seg.bezier.eval(u) - s.eval(t)).length() < 1e-12);
            }
        }
    }

    #[test]
    fn knot_insertion_keeps_the_curve() {
        let s = sample();
        for &t in &[0.3, 0.37, 0.5, 0.7, 0.9] {
            let r = s.insert_knot(t).expect("insertable");
            assert_eq!(r.points().len(), s.points().len() + 1);
            for k in 0..=30 {
                let u = 0.3 + 0.6 * k as f64 / 30.0;
                assert!(
                    (r.eval(u) - s.eval(u)).length() < 1e-12,
                    "insert {t}, eval {u}"
                );
            }
        }
    }

    #[test]
    fn split_halves_reproduce_the_curve() {
        let s = sample();
        let (l, r) = s.split(0.62).expect("inside");
        assert_eq!(l.domain(), (0.3, 0.62));
        assert_eq!(r.domain(), (0.62, 0.9));
        for k in 0..=20 {
            let t = 0.3 + 0.32 * k as f64 / 20.0;
            assert!((l.eval(t) - s.eval(t)).length() < 1e-12);
            let t = 0.62 + 0.28 * k as f64 / 20.0;
            assert!((r.eval(t) - s.eval(t)).length() < 1e-12);
        }
        assert!(s.split(0.3).is_err());
    }

    #[test]
    fn validation_errors() {
        let p = vec![DVec2::ZERO; 4];
        assert!(matches!(
            BSpline::try_new(3, vec![0.0; 7], p.clone()),
            Err(CurveError::KnotCount { .. })
        ));
        assert!(matches!(
            BSpline::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.5, 1.0], p.clone()),
            Err(CurveError::KnotsDecreasing { index: 6 })
        ));
        assert!(matches!(
            BSpline::try_new(3, vec![0.0; 8], p.clone()),
            Err(CurveError::EmptyDomain { .. })
        ));
        let interior = vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0];
        assert!(matches!(
            BSpline::try_new(3, interior, vec![DVec2::ZERO; 8]),
            Err(CurveError::KnotMultiplicity {
                max: 3,
                multiplicity: 4,
                ..
            })
        ));
        assert!(matches!(
            BSpline::try_new(0, vec![0.0; 5], p.clone()),
            Err(CurveError::ZeroDegree)
        ));
        assert!(matches!(
            BSpline::try_new(4, vec![0.0; 9], p),
            Err(CurveError::TooFewPoints { .. })
        ));
    }
}
