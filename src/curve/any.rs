//! [`Curve`]: a Bezier curve or a B-spline, behind one set of queries; [`pick`] and
//! [`CurveSet`] for the nearest of many curves (seed 000 §3).
//!
//! B-splines are queried through their Bezier segments (seed 004 §3(1)); parameters are
//! reported in the B-spline's own parameter.

use super::bezier::Bezier;
use super::bspline::{BSpline, Segment};
use super::closest::{box_distance_squared, closest_bezier_with_stats, ClipStats, Nearest};
use super::error::CurveError;
use super::point::Point;
use super::ray::{ray_closest_bezier_with_stats, RayNearest};
use super::sphere::sphere_intervals_bezier;
use std::borrow::Cow;

/// A curve of either kind.
#[derive(Debug, Clone, PartialEq)]
pub enum Curve<P> {
    /// A Bezier curve on `[0,1]`.
    Bezier(Bezier<P>),
    /// A B-spline on its domain `[t_p, t_n]`.
    BSpline(BSpline<P>),
}

/// The nearest curve of a set, and the closest point on it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Picked<P> {
    /// Index of the curve in the set.
    pub index: usize,
    /// The closest point on that curve.
    pub nearest: Nearest<P>,
}

impl<P: Point> From<Bezier<P>> for Curve<P> {
    fn from(b: Bezier<P>) -> Self {
        Curve::Bezier(b)
    }
}

impl<P: Point> From<BSpline<P>> for Curve<P> {
    fn from(b: BSpline<P>) -> Self {
        Curve::BSpline(b)
    }
}

impl<P: Point> Curve<P> {
    /// The parameter domain: `[0,1]` for Bezier curves.
    #[must_use]
    pub fn domain(&self) -> (f64, f64) {
        match self {
            Curve::Bezier(_) => (0.0, 1.0),
            Curve::BSpline(s) => s.domain(),
        }
    }

    /// The point at parameter `u` (clamped to the domain).
    #[must_use]
    pub fn eval(&self, u: f64) -> P {
        match self {
            Curve::Bezier(b) => b.eval(u.clamp(0.0, 1.0)),
            Curve::BSpline(s) => s.eval(u),
        }
    }

    /// The control points.
    #[must_use]
    pub fn points(&self) -> &[P] {
        match self {
            Curve::Bezier(b) => b.points(),
            Curve::BSpline(s) => s.points(),
        }
    }

    /// The curve as Bezier segments with the parameter range each covers.
    #[must_use]
    pub fn segments(&self) -> Cow<'_, [Segment<P>]> {
        match self {
            Curve::Bezier(b) => Cow::Owned(vec![Segment { bezier: b.clone(), start: 0.0, end: 1.0 }]),
            Curve::BSpline(s) => Cow::Owned(s.to_bezier_segments()),
        }
    }

    /// The closest point to `q` within `r_max` (`f64::INFINITY` for no limit).
    #[must_use]
    pub fn closest(&self, q: P, r_max: f64) -> Option<Nearest<P>> {
        self.closest_with_stats(q, r_max, &mut ClipStats::default())
    }

    /// [`Self::closest`], counting the clipping work.
    pub fn closest_with_stats(&self, q: P, r_max: f64, stats: &mut ClipStats) -> Option<Nearest<P>> {
        match self {
            Curve::Bezier(b) => closest_bezier_with_stats(b, q, r_max, stats),
            Curve::BSpline(s) => closest_in_segments(&s.to_bezier_segments(), None, q, r_max, stats),
        }
    }

    /// The sorted maximal parameter intervals inside the sphere (circle in 2D).
    #[must_use]
    pub fn sphere_intervals(&self, centre: P, radius: f64) -> Vec<(f64, f64)> {
        let mut out: Vec<(f64, f64)> = Vec::new();
        for seg in self.segments().iter() {
            for (a, b) in sphere_intervals_bezier(&seg.bezier, centre, radius) {
                let (ga, gb) = (seg.to_global(a), seg.to_global(b));
                match out.last_mut() {
                    Some(last) if last.1 >= ga => last.1 = last.1.max(gb),
                    _ => out.push((ga, gb)),
                }
            }
        }
        out
    }

    /// The closest pair between the ray `origin + s·dir` (`s ≥ 0`) and the curve.
    #[must_use]
    pub fn ray_closest(&self, origin: P, dir: P) -> Option<RayNearest<P>> {
        let mut best: Option<RayNearest<P>> = None;
        let mut stats = ClipStats::default();
        for seg in self.segments().iter() {
            if let Some(mut r) = ray_closest_bezier_with_stats(&seg.bezier, origin, dir, &mut stats) {
                r.u = seg.to_global(r.u);
                if best.is_none_or(|b| r.distance < b.distance) {
                    best = Some(r);
                }
            }
        }
        best
    }

    /// Axis-aligned bounds of the control points (which contain the curve).
    #[must_use]
    pub fn control_bounds(&self) -> (P, P) {
        match self {
            Curve::Bezier(b) => b.control_bounds(),
            Curve::BSpline(s) => s.control_bounds(),
        }
    }
}

/// Closest point among Bezier segments, using the best distance so far as `R_max` for the next
/// segment, and the segments' control boxes (when given) to skip those that cannot be closer.
fn closest_in_segments<P: Point>(
    segs: &[Segment<P>],
    boxes: Option<&[(P, P)]>,
    q: P,
    r_max: f64,
    stats: &mut ClipStats,
) -> Option<Nearest<P>> {
    let mut best: Option<Nearest<P>> = None;
    let mut r = r_max;
    for (i, seg) in segs.iter().enumerate() {
        if let Some(bx) = boxes {
            let (lo, hi) = bx[i];
            let lb = box_distance_squared(lo, hi, q);
            if lb > r * r {
                continue;
            }
        }
        if let Some(mut n) = closest_bezier_with_stats(&seg.bezier, q, r, stats) {
            n.u = seg.to_global(n.u);
            if best.is_none_or(|b| n.distance < b.distance) {
                r = n.distance;
                best = Some(n);
            }
        }
    }
    best
}

/// The nearest of many curves to `q` within `r_max` (seed 000 §3): the best distance found so
/// far becomes `R_max` for the next curve, so that curves whose control-point box lies farther
/// are skipped without any clipping, and the rest are rejected by the hull test of the first
/// clipping step. For repeated picks among the same curves, [`CurveSet`] keeps the Bezier
/// segments and boxes ready.
///
/// ```
/// use glam::DVec2;
/// use nendo::curve::{pick, Bezier, Curve};
/// let curves: Vec<Curve<DVec2>> = (0..5)
///     .map(|i| Bezier::new(vec![DVec2::new(0.0, i as f64), DVec2::new(1.0, i as f64)]).into())
///     .collect();
/// let p = pick(&curves, DVec2::new(0.5, 2.2), f64::INFINITY).expect("some curve");
/// assert_eq!(p.index, 2);
/// ```
#[must_use]
pub fn pick<P: Point>(curves: &[Curve<P>], q: P, r_max: f64) -> Option<Picked<P>> {
    let mut best: Option<Picked<P>> = None;
    let mut r = r_max;
    let mut stats = ClipStats::default();
    for (index, c) in curves.iter().enumerate() {
        let (lo, hi) = c.control_bounds();
        if box_distance_squared(lo, hi, q) > r * r {
            continue;
        }
        if let Some(n) = c.closest_with_stats(q, r, &mut stats)
            && best.is_none_or(|b| n.distance < b.nearest.distance)
        {
            r = n.distance;
            best = Some(Picked { index, nearest: n });
        }
    }
    best
}

/// Curves prepared for repeated queries: each curve's Bezier segments and their control boxes
/// are computed once. Picking visits the boxes first (a lower bound on the distance to the
/// curves inside), queries the curve with the nearest box to get a tight `R_max`, then the
/// remaining curves whose boxes are within it.
#[derive(Debug, Clone)]
pub struct CurveSet<P> {
    segments: Vec<Segment<P>>,
    seg_boxes: Vec<(P, P)>,
    /// For curve `i`, its segments are `segments[first[i]..first[i + 1]]`.
    first: Vec<usize>,
    boxes: Vec<(P, P)>,
}

impl<P: Point> CurveSet<P> {
    /// Prepares a set of curves.
    #[must_use]
    pub fn new(curves: &[Curve<P>]) -> Self {
        let mut s = Self { segments: Vec::new(), seg_boxes: Vec::new(), first: vec![0], boxes: Vec::new() };
        for c in curves {
            for seg in c.segments().iter() {
                s.seg_boxes.push(seg.bezier.control_bounds());
                s.segments.push(seg.clone());
            }
            s.first.push(s.segments.len());
            s.boxes.push(c.control_bounds());
        }
        s
    }

    /// Number of curves.
    #[must_use]
    pub fn len(&self) -> usize {
        self.boxes.len()
    }

    /// True when the set holds no curve.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.boxes.is_empty()
    }

    fn closest_in(&self, i: usize, q: P, r: f64, stats: &mut ClipStats) -> Option<Nearest<P>> {
        let range = self.first[i]..self.first[i + 1];
        closest_in_segments(&self.segments[range.clone()], Some(&self.seg_boxes[range]), q, r, stats)
    }

    /// The nearest curve to `q` within `r_max`, counting the clipping work into `stats`.
    pub fn pick_with_stats(&self, q: P, r_max: f64, stats: &mut ClipStats) -> Option<Picked<P>> {
        if !q.is_finite_coeff() || r_max.is_nan() || r_max < 0.0 {
            return None;
        }
        // The curve whose box is nearest gives a first, usually tight, R_max.
        let mut seed = None;
        let mut seed_lb = f64::INFINITY;
        for (i, &(lo, hi)) in self.boxes.iter().enumerate() {
            let lb = box_distance_squared(lo, hi, q);
            if lb < seed_lb {
                seed_lb = lb;
                seed = Some(i);
            }
        }
        let seed = seed?;
        let mut r = r_max;
        let mut best = self.closest_in(seed, q, r, stats).map(|n| Picked { index: seed, nearest: n });
        if let Some(b) = best {
            r = b.nearest.distance;
        }
        for (i, &(lo, hi)) in self.boxes.iter().enumerate() {
            if i == seed || box_distance_squared(lo, hi, q) > r * r {
                continue;
            }
            if let Some(n) = self.closest_in(i, q, r, stats) {
                let better = match best {
                    None => true,
                    Some(b) => n.distance < b.nearest.distance || (n.distance == b.nearest.distance && i < b.index),
                };
                if better {
                    r = n.distance;
                    best = Some(Picked { index: i, nearest: n });
                }
            }
        }
        best
    }

    /// The nearest curve to `q` within `r_max`.
    #[must_use]
    pub fn pick(&self, q: P, r_max: f64) -> Option<Picked<P>> {
        self.pick_with_stats(q, r_max, &mut ClipStats::default())
    }
}

/// Checks a query radius: non-negative (infinity allowed), not NaN.
pub fn check_radius(what: &'static str, r: f64) -> Result<f64, CurveError> {
    if r.is_nan() || r < 0.0 {
        return Err(CurveError::Negative { what, value: r });
    }
    Ok(r)
}
