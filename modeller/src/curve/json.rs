//! The JSON form of curves and points, shared by `nendo closest --batch`, `nendo curve --batch`,
//! the `nendo-model` file and the figure and shape documents:
//!
//! * a Bezier curve: `{"bezier": [[x,y], ...]}` or `{"bezier": [[x,y,z], ...]}`;
//! * a B-spline: `{"bspline": {"degree": p, "knots": [...], "points": [[...], ...]}}` (`p` a
//!   whole number, `3` or `3.0`);
//! * a point: `[x,y]` or `[x,y,z]`.
//!
//! The dimension of a curve is that of its points; all must agree. Curves and points are read
//! by serde ([`DynCurve`], [`PlanarCurve`] and [`JsonPoint`] implement `Deserialize`) inside
//! the documents that hold them: an unknown or repeated member is refused, and everything is
//! validated (finite numbers, counts, knots) with a [`JsonError`] that names the member's path.
//! Limits: a validation error of a whole curve (knot count, mixed dimensions) is placed at the
//! curve, not at the knot or point it concerns (the message names those).

use glam::{DVec2, DVec3};
use nendo_geom::curve::BSpline;
use nendo_geom::curve::Bezier;
use nendo_geom::curve::Curve;
use nendo_geom::curve::CurveError;
use nendo_geom::curve::Point;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer};
use serde_json::{Value, json};

pub use crate::json_doc::JsonError;

/// A curve in 2D or in 3D.
#[derive(Debug, Clone, PartialEq)]
pub enum DynCurve {
    /// A planar curve.
    D2(Curve<DVec2>),
    /// A space curve.
    D3(Curve<DVec3>),
}

impl DynCurve {
    /// The dimension, 2 or 3.
    #[must_use]
    pub fn dim(&self) -> usize {
        match self {
            DynCurve::D2(_) => 2,
            DynCurve::D3(_) => 3,
        }
    }
}

/// A point `[x, y]` or `[x, y, z]` as read (two or three finite numbers); its dimension is
/// checked against a curve's with [`JsonPoint::typed`].
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(try_from = "Vec<f64>")]
pub struct JsonPoint(Vec<f64>);

/// A point that has neither two nor three coordinates.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("a point has {0} coordinates; expected 2 or 3")]
pub struct PointDimension(usize);

impl TryFrom<Vec<f64>> for JsonPoint {
    type Error = PointDimension;
    fn try_from(c: Vec<f64>) -> Result<Self, PointDimension> {
        if c.len() == 2 || c.len() == 3 {
            Ok(JsonPoint(c))
        } else {
            Err(PointDimension(c.len()))
        }
    }
}

impl JsonPoint {
    /// The coordinates (two or three).
    #[must_use]
    pub fn coords(&self) -> &[f64] {
        &self.0
    }

    /// The dimension, 2 or 3.
    #[must_use]
    pub fn dim(&self) -> usize {
        self.0.len()
    }

    /// The point in `P`'s dimension; `path` names the member in the error.
    ///
    /// # Errors
    /// [`JsonError`] when the dimensions differ or a coordinate is not finite.
    pub fn typed<P: Point>(&self, path: &str) -> Result<P, JsonError> {
        if self.0.iter().any(|x| !x.is_finite()) {
            return Err(JsonError::at(path, "a coordinate is not a finite number"));
        }
        P::from_coords(&self.0).ok_or_else(|| {
            JsonError::at(
                path,
                format!(
                    "the point has {} coordinates but the curve is {}D",
                    self.0.len(),
                    P::DIM
                ),
            )
        })
    }
}

/// A non-negative whole number written as an integer (`3`) or as a float with no fractional
/// part (`3.0`, as some JSON writers print every number).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WholeNumber(pub u64);

impl<'de> Deserialize<'de> for WholeNumber {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let n = serde_json::Number::deserialize(d)?;
        whole_number(&n)
            .map(WholeNumber)
            .ok_or_else(|| D::Error::custom(format!("{n} is not a non-negative whole number")))
    }
}

/// The value of a JSON number that is a non-negative whole number (`3` or `3.0`); `None` for
/// anything else.
#[must_use]
pub fn whole_number(n: &serde_json::Number) -> Option<u64> {
    if let Some(n) = n.as_u64() {
        return Some(n);
    }
    let f = n.as_f64()?;
    // 2⁵³: every whole float below is exactly an integer.
    (f.is_finite() && f >= 0.0 && f.fract() == 0.0 && f <= 9_007_199_254_740_992.0)
        .then_some(f as u64)
}

#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a curve {\"bezier\": [...]} or {\"bspline\": {...}}"
)]
struct CurveRepr {
    #[serde(default)]
    bezier: Option<Vec<JsonPoint>>,
    #[serde(default)]
    bspline: Option<BSplineRepr>,
}

#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a B-spline {\"degree\": p, \"knots\": [...], \"points\": [...]}"
)]
struct BSplineRepr {
    degree: WholeNumber,
    knots: Vec<f64>,
    points: Vec<JsonPoint>,
}

enum Kind {
    Bezier,
    BSpline { degree: usize, knots: Vec<f64> },
}

fn typed<P: Point>(pts: &[JsonPoint]) -> Vec<P> {
    pts.iter().filter_map(|c| P::from_coords(&c.0)).collect()
}

fn build<P: Point>(kind: Kind, pts: &[JsonPoint]) -> Result<Curve<P>, CurveError> {
    let pts = typed::<P>(pts);
    Ok(match kind {
        Kind::Bezier => Curve::Bezier(Bezier::try_new(pts)?),
        Kind::BSpline { degree, knots } => Curve::BSpline(BSpline::try_new(degree, knots, pts)?),
    })
}

/// Why a curve's members (read well-formed) do not make a curve.
#[derive(Debug, thiserror::Error)]
enum Invalid {
    #[error("a curve is either {{\"bezier\": ...}} or {{\"bspline\": ...}}, not both")]
    Both,
    #[error("a curve needs a \"bezier\" or a \"bspline\" member")]
    Neither,
    #[error("control point {index} has {got} coordinates but control point 0 has {dim}")]
    MixedDimensions {
        index: usize,
        got: usize,
        dim: usize,
    },
    #[error(transparent)]
    Curve(#[from] CurveError),
}

impl CurveRepr {
    fn into_curve(self) -> Result<DynCurve, Invalid> {
        let (kind, pts) = match (self.bezier, self.bspline) {
            (Some(_), Some(_)) => return Err(Invalid::Both),
            (None, None) => return Err(Invalid::Neither),
            (Some(b), None) => (Kind::Bezier, b),
            (None, Some(s)) => (
                Kind::BSpline {
                    degree: usize::try_from(s.degree.0).unwrap_or(usize::MAX),
                    knots: s.knots,
                },
                s.points,
            ),
        };
        let dim = pts.first().map_or(0, JsonPoint::dim);
        if let Some((index, p)) = pts.iter().enumerate().find(|(_, p)| p.dim() != dim) {
            return Err(Invalid::MixedDimensions {
                index,
                got: p.dim(),
                dim,
            });
        }
        Ok(match dim {
            2 => DynCurve::D2(build(kind, &pts)?),
            _ => DynCurve::D3(build(kind, &pts)?),
        })
    }
}

impl<'de> Deserialize<'de> for DynCurve {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        CurveRepr::deserialize(d)?
            .into_curve()
            .map_err(D::Error::custom)
    }
}

/// A planar (2D) curve, for documents that hold only those (figures, shape sections).
#[derive(Debug, Clone, PartialEq)]
pub struct PlanarCurve(pub Curve<DVec2>);

impl<'de> Deserialize<'de> for PlanarCurve {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        match DynCurve::deserialize(d)? {
            DynCurve::D2(c) => Ok(PlanarCurve(c)),
            DynCurve::D3(_) => Err(D::Error::custom(
                "the curve is 3D; a planar (2D) curve is needed here",
            )),
        }
    }
}

/// Reads a curve from its JSON form.
///
/// ```
/// use nendo::curve::json::{curve_from_json, DynCurve};
/// let v: serde_json::Value = serde_json::from_str(r#"{"bezier": [[0,0,0],[1,2,0],[2,0,1]]}"#)?;
/// assert!(matches!(curve_from_json(&v)?, DynCurve::D3(_)));
/// let bad: serde_json::Value = serde_json::from_str(r#"{"bezier": [[0,0],[1,2,0]]}"#)?;
/// assert!(curve_from_json(&bad).is_err());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`JsonError`] naming the bad member and what is wrong.
pub fn curve_from_json(v: &Value) -> Result<DynCurve, JsonError> {
    crate::json_doc::from_value(v)
}

/// A point as a JSON array.
pub fn point_to_json<P: Point>(p: P) -> Value {
    Value::from(p.to_vec())
}

/// The JSON form of a curve.
pub fn curve_to_json<P: Point>(c: &Curve<P>) -> Value {
    match c {
        Curve::Bezier(b) => {
            json!({ "bezier": b.points().iter().map(|&p| point_to_json(p)).collect::<Vec<_>>() })
        }
        Curve::BSpline(s) => json!({ "bspline": {
            "degree": s.degree(),
            "knots": s.knots(),
            "points": s.points().iter().map(|&p| point_to_json(p)).collect::<Vec<_>>(),
        }}),
    }
}

/// The JSON form of a curve of either dimension.
pub fn dyn_curve_to_json(c: &DynCurve) -> Value {
    match c {
        DynCurve::D2(c) => curve_to_json(c),
        DynCurve::D3(c) => curve_to_json(c),
    }
}
