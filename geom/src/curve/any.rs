//! [`Curve`]: a Bezier curve or a B-spline, behind one set of queries; [`pick`] and
//! [`CurveSet`] for the nearest of many curves (P0 §3).
//!
//! B-splines are queried through their Bezier segments (P4 §3(1)); parameters are
//! reported in the B-spline's own parameter.

use super::bezier::Bezier;
use super::bspline::{BSpline, Segment};
use super::closest::{ClipStats, Nearest, box_distance_squared, closest_bezier_with_stats};
use super::error::CurveError;
use super::point::Point;
use super::ray::{RayNearest, ray_closest_bezier_with_stats};
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
            Curve::Bezier(b) => Cow::Owned(vec![Segment {
                bezier: b.clone(),
                start: 0.0,
                end: 1.0,
            }]),
            Curve::BSpline(s) => Cow::Owned(s.to_bezier_segments()),
        }
    }

    /// The closest point to `q` within `r_max` (`f64::INFINITY` for no limit).
    #[must_use]
    pub fn closest(&self, q: P, r_max: f64) -> Option<Nearest<P>> {
        self.closest_with_stats(q, r_max, &mut ClipStats::default())
    }

    /// [`Self::closest`], counting the clipping work.
    pub fn closest_with_stats(
        &self,
        q: P,
        r_max: f64,
        stats: &mut ClipStats,
    ) -> Option<Nearest<P>> {
        match self {
            Curve::Bezier(b) => closest_bezier_with_stats(b, q, r_max, stats),
            Curve::BSpline(s) => {
                closest_in_segments(&s.to_bezier_segments(), None, q, r_max, stats)
            }
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
            if let Some(mut r) = ray_closest_bezier_with_stats(&seg.bezier, origin, dir, &mut stats)
            {
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

/// The nearest of many curves to `q` within `r_max` (P0 §3): the best distance found so
/// far becomes `R_max` for the next curve, so that curves whose control-point box lies farther
/// are skipped without any clipping, and the rest are rejected by the hull test of the first
/// clipping step. For repeated picks among the same curves, [`CurveSet`] keeps the Bezier
/// segments and boxes ready.
///
/// ```
/// use glam::DVec2;
/// use nendo_geom::curve::{pick, Bezier, Curve};
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

/// Curves prepared for repeated picking: every curve's Bezier segments with their control
/// boxes, in a bounding-volume hierarchy (median splits along the longest axis, up to
/// [`CurveSet::LEAF`] segments per leaf). A pick visits the nodes nearest first and skips every
/// node whose box lies farther than the best distance so far (the `R_max` of P0 §3), so
/// its cost follows the curves near the query, not the size of the set.
#[derive(Debug, Clone)]
pub struct CurveSet<P> {
    /// Segments in leaf order, each with the index of its curve.
    segments: Vec<(Segment<P>, usize)>,
    seg_boxes: Vec<(P, P)>,
    nodes: Vec<Node<P>>,
    curves: usize,
}

/// A node of the hierarchy: a leaf holds `segments[first..first + count]`; an inner node
/// (`count == 0`) has its first child next to it and its second at `first`.
#[derive(Debug, Clone, Copy)]
struct Node<P> {
    lo: P,
    hi: P,
    first: usize,
    count: usize,
}

impl<P: Point> CurveSet<P> {
    /// Largest number of segments in a leaf.
    pub const LEAF: usize = 4;

    /// Prepares a set of curves.
    #[must_use]
    pub fn new(curves: &[Curve<P>]) -> Self {
        let mut items: Vec<(Segment<P>, usize, (P, P))> = Vec::new();
        for (i, c) in curves.iter().enumerate() {
            for seg in c.segments().iter() {
                let b = seg.bezier.control_bounds();
                items.push((seg.clone(), i, b));
            }
        }
        let mut nodes = Vec::new();
        if !items.is_empty() {
            build(&mut items, 0, &mut nodes);
        }
        let seg_boxes = items.iter().map(|it| it.2).collect();
        let segments = items.into_iter().map(|(s, i, _)| (s, i)).collect();
        Self {
            segments,
            seg_boxes,
            nodes,
            curves: curves.len(),
        }
    }

    /// Number of curves.
    #[must_use]
    pub fn len(&self) -> usize {
        self.curves
    }

    /// True when the set holds no curve.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.curves == 0
    }

    /// The nearest curve to `q` within `r_max`, counting the clipping work into `stats`. Of
    /// two curves at exactly the same distance, the one with the smaller index is picked.
    pub fn pick_with_stats(&self, q: P, r_max: f64, stats: &mut ClipStats) -> Option<Picked<P>> {
        if !q.is_finite_coeff() || r_max.is_nan() || r_max < 0.0 || self.nodes.is_empty() {
            return None;
        }
        let mut best: Option<Picked<P>> = None;
        let mut r = r_max;
        let mut stack = [0usize; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top]];
            let idx = stack[top];
            if q.box_distance_squared(node.lo, node.hi) > r * r {
                continue;
            }
            if node.count > 0 {
                // The segments' end points are points of the curves: the nearest of them bounds
                // the answer before any clipping, so that the boxes and the clipping of the
                // segments below prune more. A hair above that distance, so that rounding in
                // the box test never skips the segment the end point belongs to.
                for k in node.first..node.first + node.count {
                    let pts = self.segments[k].0.bezier.points();
                    let (Some(&first), Some(&last)) = (pts.first(), pts.last()) else {
                        continue;
                    };
                    let d = (first - q).length().min((last - q).length()) * (1.0 + 1e-12);
                    if d < r {
                        r = d;
                    }
                }
                for k in node.first..node.first + node.count {
                    let (lo, hi) = self.seg_boxes[k];
                    if q.box_distance_squared(lo, hi) > r * r {
                        continue;
                    }
                    let (seg, curve) = &self.segments[k];
                    if let Some(mut n) = closest_bezier_with_stats(&seg.bezier, q, r, stats) {
                        n.u = seg.to_global(n.u);
                        let better = match best {
                            None => true,
                            Some(b) => {
                                n.distance < b.nearest.distance
                                    || (n.distance == b.nearest.distance && *curve < b.index)
                            }
                        };
                        if better {
                            r = n.distance;
                            best = Some(Picked {
                                index: *curve,
                                nearest: n,
                            });
                        }
                    }
                }
                continue;
            }
            // Visit the nearer child first: push it last.
            let (a, b) = (idx + 1, node.first);
            let da = q.box_distance_squared(self.nodes[a].lo, self.nodes[a].hi);
            let db = q.box_distance_squared(self.nodes[b].lo, self.nodes[b].hi);
            let (near, far) = if da <= db { (a, b) } else { (b, a) };
            if top + 2 <= stack.len() {
                stack[top] = far;
                stack[top + 1] = near;
                top += 2;
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

/// Builds the hierarchy over `items` (reordering them into leaf order); `offset` is the index
/// of `items[0]` in the whole list. Returns the index of the node made.
fn build<P: Point>(
    items: &mut [(Segment<P>, usize, (P, P))],
    offset: usize,
    nodes: &mut Vec<Node<P>>,
) -> usize {
    let (mut lo, mut hi) = items[0].2;
    for it in items.iter() {
        lo = lo.min_by_coord(it.2.0);
        hi = hi.max_by_coord(it.2.1);
    }
    let me = nodes.len();
    nodes.push(Node {
        lo,
        hi,
        first: offset,
        count: items.len(),
    });
    if items.len() <= CurveSet::<P>::LEAF {
        return me;
    }
    // Split at the median box centre along the longest axis of the centres' extent.
    let centre = |it: &(Segment<P>, usize, (P, P))| (it.2.0 + it.2.1) * 0.5;
    let (mut clo, mut chi) = (centre(&items[0]), centre(&items[0]));
    for it in items.iter() {
        clo = clo.min_by_coord(centre(it));
        chi = chi.max_by_coord(centre(it));
    }
    let ext = chi - clo;
    let axis = (0..P::DIM).fold(0, |a, i| if ext.coord(i) > ext.coord(a) { i } else { a });
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |x, y| {
        centre(x).coord(axis).total_cmp(&centre(y).coord(axis))
    });
    let (left, right) = items.split_at_mut(mid);
    build(left, offset, nodes);
    let second = build(right, offset + mid, nodes);
    nodes[me].count = 0;
    nodes[me].first = second;
    me
}

/// Checks a query radius: non-negative (infinity allowed), not NaN.
pub fn check_radius(what: &'static str, r: f64) -> Result<f64, CurveError> {
    if r.is_nan() || r < 0.0 {
        return Err(CurveError::Negative { what, value: r });
    }
    Ok(r)
}
