//! Errors of the curve part.

use thiserror::Error;

/// Why a curve could not be built or an operation could not be carried out.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CurveError {
    /// A curve needs at least one control point.
    #[error("a curve needs at least one control point")]
    Empty,
    /// The degree is above what nendo supports.
    #[error("degree {degree} is above the supported maximum {max}")]
    DegreeTooHigh {
        /// The requested degree.
        degree: usize,
        /// The largest supported degree.
        max: usize,
    },
    /// A coordinate, knot or parameter is NaN or infinite.
    #[error("{what} is not a finite number")]
    NotFinite {
        /// Which value (e.g. "control point 3", "knot 2", "query point").
        what: String,
    },
    /// A coordinate is so large that differences of coordinates overflow (beyond
    /// [`MAX_COORDINATE`](crate::curve::MAX_COORDINATE), half the largest double).
    #[error(
        "{what} is too large: coordinates beyond ±{:e} overflow the curve's arithmetic",
        crate::curve::MAX_COORDINATE
    )]
    TooLarge {
        /// Which value.
        what: String,
    },
    /// Points of different dimensions were mixed, or a point has a dimension other than 2 or 3.
    #[error("dimension mismatch: {0}")]
    Dimension(String),
    /// A B-spline of degree 0 (piecewise constant) is not a curve nendo edits.
    #[error("B-spline degree must be at least 1")]
    ZeroDegree,
    /// The knot vector's length does not fit the control points and degree.
    #[error(
        "a B-spline of degree {degree} with {points} control points needs {expected} knots, got {got}"
    )]
    KnotCount {
        /// Degree p.
        degree: usize,
        /// Number of control points n.
        points: usize,
        /// n + p + 1.
        expected: usize,
        /// Knots given.
        got: usize,
    },
    /// Too few control points for the degree.
    #[error("a B-spline of degree {degree} needs at least {needed} control points, got {got}")]
    TooFewPoints {
        /// Degree p.
        degree: usize,
        /// p + 1.
        needed: usize,
        /// Points given.
        got: usize,
    },
    /// Knots must be non-decreasing.
    #[error("knots must be non-decreasing (knot {index} is smaller than the one before it)")]
    KnotsDecreasing {
        /// Index of the offending knot.
        index: usize,
    },
    /// A knot's multiplicity is above what keeps the curve connected (`p` inside the domain,
    /// `p + 1` at or outside its ends).
    #[error(
        "knot {} has multiplicity {multiplicity}, more than the {max} allowed there",
        crate::num::Compact(*.value)
    )]
    KnotMultiplicity {
        /// The knot value.
        value: f64,
        /// Its multiplicity.
        multiplicity: usize,
        /// The largest multiplicity allowed at that knot.
        max: usize,
    },
    /// The parameter domain `[t_p, t_n]` is empty.
    #[error(
        "the B-spline's parameter domain [{}, {}] is empty",
        crate::num::Compact(*.start),
        crate::num::Compact(*.end)
    )]
    EmptyDomain {
        /// t_p.
        start: f64,
        /// t_n.
        end: f64,
    },
    /// A parameter lies outside where the operation is defined.
    #[error("parameter {} is outside {range}", crate::num::Compact(*.t))]
    OutOfDomain {
        /// The parameter.
        t: f64,
        /// The valid range, described.
        range: String,
    },
    /// A radius or distance must be non-negative (and finite).
    #[error("{what} must be a non-negative number, got {}", crate::num::Compact(*.value))]
    Negative {
        /// Which value.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// A control-point index beyond the curve's points.
    #[error("control point index {index} is out of range (the curve has {len} points)")]
    Index {
        /// The index given.
        index: usize,
        /// Number of control points.
        len: usize,
    },
    /// A direction vector has zero length.
    #[error("{0} has zero length")]
    ZeroVector(&'static str),
    /// An edit cannot be carried out as asked: no movable control point carries the grabbed
    /// point, two curves do not meet at the joint to edit, a tangent arm of zero length.
    #[error("edit: {0}")]
    Edit(String),
    /// A refinement cannot be set up or solved: a non-planar curve, a constraint that does not
    /// fit the curve, derivatives that vanish at every similarity sample.
    #[error("refine: {0}")]
    Refine(String),
}
