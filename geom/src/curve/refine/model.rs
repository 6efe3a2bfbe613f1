//! The refined curve as a linear model: the unknowns are its control points, flattened to
//! `[x₀, y₀, x₁, y₁, …]`, and every point or derivative of the curve is a sparse linear form in
//! them.

use crate::curve::any::Curve;
use crate::curve::bezier::Bezier;
use crate::curve::bspline::BSpline;
use crate::curve::edit::control_weights;
use crate::curve::error::CurveError;
use glam::DVec2;

/// A sparse linear form over the unknowns: `(index, coefficient)`.
pub(super) type Sparse = Vec<(usize, f64)>;

/// `Σ c_k v_k`.
pub(super) fn dot_sparse(row: &Sparse, v: &[f64]) -> f64 {
    row.iter().map(|&(k, c)| c * v[k]).sum()
}

/// Points flattened to `[x₀, y₀, x₁, y₁, …]`.
pub(super) fn flatten(points: &[DVec2]) -> Vec<f64> {
    points.iter().flat_map(|p| [p.x, p.y]).collect()
}

fn unflatten(v: &[f64]) -> Vec<DVec2> {
    v.chunks_exact(2).map(|c| DVec2::new(c[0], c[1])).collect()
}

/// The original curve the refinement starts from, as Bezier segments on unit parameter spans
/// (a single Bezier curve or a piecewise curve) or as a B-spline.
#[derive(Debug, Clone)]
pub(super) enum Model {
    /// Segment `i` on the global parameters `[i, i+1]`; its points are unknowns
    /// `first[i] .. first[i] + degree + 1`.
    Segments {
        /// The original segments, as curves.
        segs: Vec<Curve<DVec2>>,
        /// Index of each segment's first control point among all.
        first: Vec<usize>,
    },
    /// A B-spline: its control points are the unknowns.
    BSpline(Curve<DVec2>),
}

impl Model {
    pub(super) fn from_curve(curve: &Curve<DVec2>) -> Self {
        match curve {
            Curve::Bezier(_) => Model::Segments {
                segs: vec![curve.clone()],
                first: vec![0],
            },
            Curve::BSpline(_) => Model::BSpline(curve.clone()),
        }
    }

    pub(super) fn from_segments(segments: &[Bezier<DVec2>]) -> Result<Self, CurveError> {
        if segments.is_empty() {
            return Err(CurveError::Refine(
                "a piecewise curve needs at least one segment".into(),
            ));
        }
        let mut first = Vec::with_capacity(segments.len());
        let mut count = 0;
        for s in segments {
            first.push(count);
            count += s.points().len();
        }
        Ok(Model::Segments {
            segs: segments.iter().map(|s| Curve::Bezier(s.clone())).collect(),
            first,
        })
    }

    /// The original control points, flattened.
    pub(super) fn original(&self) -> Vec<f64> {
        match self {
            Model::Segments { segs, .. } => segs.iter().flat_map(|s| flatten(s.points())).collect(),
            Model::BSpline(c) => flatten(c.points()),
        }
    }

    /// The global parameter domain.
    pub(super) fn domain(&self) -> (f64, f64) {
        match self {
            Model::Segments { segs, .. } => (0.0, segs.len() as f64),
            Model::BSpline(c) => c.domain(),
        }
    }

    /// Number of joints between segments (0 for a B-spline or a single curve).
    pub(super) fn joints(&self) -> usize {
        match self {
            Model::Segments { segs, .. } => segs.len() - 1,
            Model::BSpline(_) => 0,
        }
    }

    /// The spans similarity samples are placed on: `(start, end, degree)`.
    pub(super) fn spans(&self) -> Vec<(f64, f64, usize)> {
        match self {
            Model::Segments { segs, .. } => segs
                .iter()
                .enumerate()
                .map(|(i, s)| (i as f64, i as f64 + 1.0, s.points().len() - 1))
                .collect(),
            Model::BSpline(c) => {
                let p = match c {
                    Curve::BSpline(s) => s.degree(),
                    Curve::Bezier(b) => b.degree(),
                };
                c.segments().iter().map(|s| (s.start, s.end, p)).collect()
            }
        }
    }

    /// A length scale of the original control points.
    pub(super) fn extent(&self) -> f64 {
        let pts = self.original();
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for p in unflatten(&pts) {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        (hi - lo).length()
    }

    /// The segment holding global parameter `u` and the local parameter (Segments only).
    fn locate(segs: usize, u: f64) -> (usize, f64) {
        let i = (u.floor().max(0.0) as usize).min(segs - 1);
        (i, (u - i as f64).clamp(0.0, 1.0))
    }

    /// Weights of the control points in `C^{(order)}(u)`: `(point index, weight)`.
    pub(super) fn weights(&self, u: f64, order: usize) -> Result<Vec<(usize, f64)>, CurveError> {
        Ok(match self {
            Model::Segments { segs, first } => {
                let (i, s) = Self::locate(segs.len(), u);
                Self::segment_weights(&segs[i], first[i], s, order)?
            }
            Model::BSpline(c) => sparse(control_weights(c, u, order)?, 0),
        })
    }

    fn segment_weights(
        seg: &Curve<DVec2>,
        first: usize,
        s: f64,
        order: usize,
    ) -> Result<Vec<(usize, f64)>, CurveError> {
        Ok(sparse(control_weights(seg, s, order)?, first))
    }

    /// The weights of `C_at^{(r)}(1) − C_{at+1}^{(r)}(0)` (a joint's continuity condition).
    pub(super) fn join_weights(
        &self,
        at: usize,
        r: usize,
    ) -> Result<Vec<(usize, f64)>, CurveError> {
        match self {
            Model::Segments { segs, first } if at + 1 < segs.len() => {
                let mut w = Self::segment_weights(&segs[at], first[at], 1.0, r)?;
                w.extend(
                    Self::segment_weights(&segs[at + 1], first[at + 1], 0.0, r)?
                        .into_iter()
                        .map(|(k, x)| (k, -x)),
                );
                Ok(w)
            }
            _ => Err(CurveError::Refine(format!(
                "there is no joint {at} between segments of this curve"
            ))),
        }
    }

    /// The continuity `C^k` (k = 0, 1, 2; `None` for none) the original has at joint `at`:
    /// derivatives equal within `1e-9` of their size.
    pub(super) fn original_continuity(&self, at: usize) -> Result<Option<usize>, CurveError> {
        let v0 = self.original();
        let scale = self.extent().max(f64::MIN_POSITIVE);
        let mut level = None;
        for r in 0..=2 {
            let w = self.join_weights(at, r)?;
            let gap = DVec2::new(
                w.iter().map(|&(k, x)| x * v0[2 * k]).sum(),
                w.iter().map(|&(k, x)| x * v0[2 * k + 1]).sum(),
            );
            let size: f64 = w
                .iter()
                .map(|&(k, x)| x.abs() * DVec2::new(v0[2 * k], v0[2 * k + 1]).length())
                .sum::<f64>()
                + scale;
            if gap.length() > 1e-9 * size {
                break;
            }
            level = Some(r);
        }
        Ok(level)
    }

    /// The original's `order`-th derivative at `u`.
    pub(super) fn original_derivative(&self, u: f64, order: usize) -> Result<DVec2, CurveError> {
        let v0 = self.original();
        Ok(self
            .weights(u, order)?
            .iter()
            .fold(DVec2::ZERO, |acc, &(k, w)| {
                acc + DVec2::new(v0[2 * k], v0[2 * k + 1]) * w
            }))
    }

    /// The refined curve of the original's kind from flattened points.
    pub(super) fn curve_with(
        &self,
        original: &Curve<DVec2>,
        v: &[f64],
    ) -> Result<Curve<DVec2>, CurveError> {
        let pts = unflatten(v);
        Ok(match original {
            Curve::Bezier(_) => Curve::Bezier(Bezier::try_new(pts)?),
            Curve::BSpline(s) => {
                Curve::BSpline(BSpline::try_new(s.degree(), s.knots().to_vec(), pts)?)
            }
        })
    }

    /// The refined segments from flattened points (Segments only). Joints held together meet
    /// exactly: both end points become their mean (they differ by rounding only).
    pub(super) fn segments_with(
        &self,
        v: &[f64],
        joined: &[bool],
    ) -> Result<Vec<Bezier<DVec2>>, CurveError> {
        let mut pts = unflatten(v);
        if let Model::Segments { first, .. } = self {
            for (at, _) in joined.iter().enumerate().filter(|j| *j.1) {
                let (end, start) = (first[at + 1] - 1, first[at + 1]);
                let mid = (pts[end] + pts[start]) * 0.5;
                pts[end] = mid;
                pts[start] = mid;
            }
        }
        match self {
            Model::Segments { segs, first } => segs
                .iter()
                .zip(first)
                .map(|(s, &f)| Bezier::try_new(pts[f..f + s.points().len()].to_vec()))
                .collect(),
            Model::BSpline(_) => Err(CurveError::Refine(
                "a B-spline is not a piecewise curve".into(),
            )),
        }
    }
}

fn sparse(w: Vec<f64>, offset: usize) -> Vec<(usize, f64)> {
    w.into_iter()
        .enumerate()
        .filter(|&(_, x)| x != 0.0)
        .map(|(k, x)| (k + offset, x))
        .collect()
}
