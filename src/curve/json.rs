//! The JSON form of curves and points, shared by `nendo closest --batch`, `nendo curve --batch`
//! and the `nendo-model` file:
//!
//! * a Bezier curve: `{"bezier": [[x,y], ...]}` or `{"bezier": [[x,y,z], ...]}`;
//! * a B-spline: `{"bspline": {"degree": p, "knots": [...], "points": [[...], ...]}}` (`p` a
//!   whole number, `3` or `3.0`);
//! * a point: `[x,y]` or `[x,y,z]`.
//!
//! The dimension of a curve is that of its points; all must agree. Everything is validated
//! (finite numbers, counts, knots) with errors that say what is wrong.

use glam::{DVec2, DVec3};
use nendo_geom::curve::BSpline;
use nendo_geom::curve::Bezier;
use nendo_geom::curve::Curve;
use nendo_geom::curve::CurveError;
use nendo_geom::curve::Point;
use serde_json::{Value, json};

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

/// Reads a point `[x, y]` or `[x, y, z]` of finite numbers; `what` names it in errors.
pub fn point_from_json(v: &Value, what: &str) -> Result<Vec<f64>, CurveError> {
    let arr = v
        .as_array()
        .ok_or_else(|| CurveError::Format(format!("{what} must be an array of numbers")))?;
    if arr.len() != 2 && arr.len() != 3 {
        return Err(CurveError::Dimension(format!(
            "{what} has {} coordinates; expected 2 or 3",
            arr.len()
        )));
    }
    arr.iter()
        .map(|x| {
            let f = x.as_f64().ok_or_else(|| {
                CurveError::Format(format!("{what} has a coordinate that is not a number"))
            })?;
            if f.is_finite() {
                Ok(f)
            } else {
                Err(CurveError::NotFinite {
                    what: what.to_string(),
                })
            }
        })
        .collect()
}

/// Reads a point of a known dimension `P::DIM`.
pub fn typed_point<P: Point>(v: &Value, what: &str) -> Result<P, CurveError> {
    let c = point_from_json(v, what)?;
    P::from_coords(&c).ok_or_else(|| {
        CurveError::Dimension(format!(
            "{what} has {} coordinates but the curve is {}D",
            c.len(),
            P::DIM
        ))
    })
}

fn points_from_json(v: &Value, what: &str) -> Result<(usize, Vec<Vec<f64>>), CurveError> {
    let arr = v
        .as_array()
        .ok_or_else(|| CurveError::Format(format!("{what} must be an array of points")))?;
    if arr.is_empty() {
        return Err(CurveError::Empty);
    }
    let mut dim = 0;
    let mut out = Vec::with_capacity(arr.len());
    for (i, p) in arr.iter().enumerate() {
        let c = point_from_json(p, &format!("control point {i}"))?;
        if i == 0 {
            dim = c.len();
        } else if c.len() != dim {
            return Err(CurveError::Dimension(format!(
                "control point {i} has {} coordinates but control point 0 has {dim}",
                c.len()
            )));
        }
        out.push(c);
    }
    Ok((dim, out))
}

fn typed<P: Point>(pts: &[Vec<f64>]) -> Vec<P> {
    pts.iter().filter_map(|c| P::from_coords(c)).collect()
}

fn build<P: Point>(kind: &Kind, pts: &[Vec<f64>]) -> Result<Curve<P>, CurveError> {
    let pts = typed::<P>(pts);
    Ok(match kind {
        Kind::Bezier => Curve::Bezier(Bezier::try_new(pts)?),
        Kind::BSpline { degree, knots } => {
            Curve::BSpline(BSpline::try_new(*degree, knots.clone(), pts)?)
        }
    })
}

enum Kind {
    Bezier,
    BSpline { degree: usize, knots: Vec<f64> },
}

/// A non-negative whole number written as an integer (`3`) or as a float with no fractional
/// part (`3.0`, as some JSON writers print every number); `None` for anything else.
#[must_use]
pub fn whole_number(v: &Value) -> Option<u64> {
    if let Some(n) = v.as_u64() {
        return Some(n);
    }
    let f = v.as_f64()?;
    // 2⁵³: every whole float below is exactly an integer.
    (f.is_finite() && f >= 0.0 && f.fract() == 0.0 && f <= 9_007_199_254_740_992.0)
        .then_some(f as u64)
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
pub fn curve_from_json(v: &Value) -> Result<DynCurve, CurveError> {
    let obj = v.as_object().ok_or_else(|| {
        CurveError::Format(
            "a curve must be an object {\"bezier\": [...]} or {\"bspline\": {...}}".into(),
        )
    })?;
    if obj.contains_key("bezier") && obj.contains_key("bspline") {
        return Err(CurveError::Format(
            "a curve is either {\"bezier\": ...} or {\"bspline\": ...}, not both".into(),
        ));
    }
    let (kind, pts_v) = if let Some(b) = obj.get("bezier") {
        (Kind::Bezier, b)
    } else if let Some(s) = obj.get("bspline") {
        let s = s
            .as_object()
            .ok_or_else(|| CurveError::Format("\"bspline\" must be an object".into()))?;
        let degree = s.get("degree").and_then(whole_number).ok_or_else(|| {
            CurveError::Format("\"bspline\" needs a non-negative integer \"degree\"".into())
        })?;
        let knots_v = s
            .get("knots")
            .and_then(Value::as_array)
            .ok_or_else(|| CurveError::Format("\"bspline\" needs an array \"knots\"".into()))?;
        let mut knots = Vec::with_capacity(knots_v.len());
        for (i, k) in knots_v.iter().enumerate() {
            let f = k
                .as_f64()
                .ok_or_else(|| CurveError::Format(format!("knot {i} is not a number")))?;
            if !f.is_finite() {
                return Err(CurveError::NotFinite {
                    what: format!("knot {i}"),
                });
            }
            knots.push(f);
        }
        let pts = s
            .get("points")
            .ok_or_else(|| CurveError::Format("\"bspline\" needs \"points\"".into()))?;
        let degree = usize::try_from(degree).unwrap_or(usize::MAX);
        (Kind::BSpline { degree, knots }, pts)
    } else {
        return Err(CurveError::Format(
            "a curve needs a \"bezier\" or a \"bspline\" member".into(),
        ));
    };
    let (dim, pts) = points_from_json(pts_v, "points")?;
    match dim {
        2 => Ok(DynCurve::D2(build::<DVec2>(&kind, &pts)?)),
        _ => Ok(DynCurve::D3(build::<DVec3>(&kind, &pts)?)),
    }
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
