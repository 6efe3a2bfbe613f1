//! The figure file (`nendo-figure` JSON): a figure's metacircles with what surrounds them — the
//! contour it was fitted to, polygons a warp carries along, and the curves laid over it.
//!
//! ```json
//! {"format": "nendo-figure", "version": 1,
//!  "name": "horse",
//!  "threshold": 0.5,
//!  "view": {"min": [0, 0], "max": [512, 512]},
//!  "background": "#ffffff",
//!  "metacircles": [{"centre": [x, y], "radius": R, "density": q, "colour": "#8a5a3c"}, …],
//!  "contour": [[x, y], …],
//!  "polygons": [{"points": [[x, y], …], "colour": "#204080"}, …],
//!  "curves": [{"bezier": [[x, y], …]}, {"bspline": {"degree": 3, "knots": […], "points": […]}}, …]}
//! ```
//!
//! * Coordinates are in figure units with **y pointing down** (SVG's convention); pictures
//!   map them to pixels through a [`View`](super::View).
//! * `format` and `version` are required; every other member is optional: `threshold` (default
//!   0.5, positive), `name`, `view` (the rectangle drawn; default the figure's bounds),
//!   `background` (default white), `metacircles` (default none; `colour` default `#8a5a3c`,
//!   `radius ≥ 0`, `density` of any sign), `contour` (a closed polygon, the outline the figure
//!   was fitted to), `polygons` (closed, each with a colour), `curves` (2D curves in the form of
//!   [`crate::curve::json`]; in a morph, curve `k` of the source corresponds to curve `k` of
//!   the destination).
//! * Reading validates every number and says where a problem is; the text is produced and
//!   consumed by the callers (the library reads and writes no files).

use glam::DVec2;
use serde_json::{Map, Value, json};

use crate::curve::Curve;
use crate::curve::json::{DynCurve, curve_from_json, curve_to_json};

use super::contour::Contour;
use super::error::FigureError;
use super::falloff::DEFAULT_THRESHOLD;
use super::metacircle::{Figure, Metacircle, Rgb};

/// The `format` member of every figure file.
pub const FORMAT: &str = "nendo-figure";
/// The version this build reads and writes.
pub const VERSION: u64 = 1;

/// A closed polygon with a colour.
#[derive(Debug, Clone, PartialEq)]
pub struct FilledPolygon {
    /// The outline.
    pub contour: Contour,
    /// The fill.
    pub colour: Rgb,
}

/// Everything a figure file holds.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FigureDocument {
    /// A name, for people.
    pub name: Option<String>,
    /// The metacircles and the threshold.
    pub figure: Figure,
    /// The rectangle `(min, max)` pictures show.
    pub view: Option<(DVec2, DVec2)>,
    /// The background of pictures.
    pub background: Option<Rgb>,
    /// The outline the figure was fitted to.
    pub contour: Option<Contour>,
    /// Coloured polygons (a warp moves their vertices).
    pub polygons: Vec<FilledPolygon>,
    /// The curves laid over the figure.
    pub curves: Vec<Curve<DVec2>>,
}

impl FigureDocument {
    /// The rectangle to draw: the `view` if given, else the bounds of the figure, its contour,
    /// its polygons and its curves' control points; `None` when there is nothing at all.
    #[must_use]
    pub fn frame(&self) -> Option<(DVec2, DVec2)> {
        if self.view.is_some() {
            return self.view;
        }
        let mut b = self.figure.bounds();
        let mut add = |lo: DVec2, hi: DVec2| {
            b = Some(match b {
                None => (lo, hi),
                Some((a, c)) => (a.min(lo), c.max(hi)),
            });
        };
        if let Some(c) = &self.contour {
            let (lo, hi) = c.bounds();
            add(lo, hi);
        }
        for p in &self.polygons {
            let (lo, hi) = p.contour.bounds();
            add(lo, hi);
        }
        for c in &self.curves {
            let (lo, hi) = c.control_bounds();
            add(lo, hi);
        }
        b
    }

    /// Reads a document from JSON text.
    ///
    /// # Errors
    /// [`FigureError::Format`] (naming the member) for malformed JSON or members,
    /// [`FigureError::Curve`] for a bad curve, and the validation errors of the parts.
    pub fn from_json(text: &str) -> Result<Self, FigureError> {
        let v = header_checked(text, "figure", FORMAT, VERSION)?;
        let obj = v
            .as_object()
            .ok_or_else(|| FigureError::Format("a figure file must be a JSON object".into()))?;
        let threshold = match obj.get("threshold") {
            None => DEFAULT_THRESHOLD,
            Some(t) => number(t, "threshold")?,
        };
        let name = match obj.get("name") {
            None | Some(Value::Null) => None,
            Some(Value::String(s)) => Some(s.clone()),
            Some(_) => return Err(FigureError::Format("\"name\" must be a string".into())),
        };
        let view = match obj.get("view") {
            None | Some(Value::Null) => None,
            Some(v) => {
                let o = v.as_object().ok_or_else(|| {
                    FigureError::Format("\"view\" must be an object {\"min\", \"max\"}".into())
                })?;
                let min = point(o.get("min").unwrap_or(&Value::Null), "view min")?;
                let max = point(o.get("max").unwrap_or(&Value::Null), "view max")?;
                if !(max.x > min.x && max.y > min.y) {
                    return Err(FigureError::Format(
                        "\"view\": max must exceed min on both axes".into(),
                    ));
                }
                Some((min, max))
            }
        };
        let background = match obj.get("background") {
            None | Some(Value::Null) => None,
            Some(c) => Some(colour(c, "background")?),
        };
        let mut metacircles = Vec::new();
        for (i, m) in array(obj, "metacircles")?.iter().enumerate() {
            let what = format!("metacircle {i}");
            let o = m
                .as_object()
                .ok_or_else(|| FigureError::Format(format!("{what} must be an object")))?;
            let get = |k: &str| {
                o.get(k)
                    .ok_or_else(|| FigureError::Format(format!("{what} needs \"{k}\"")))
            };
            let mc = Metacircle {
                centre: point(get("centre")?, &format!("{what} centre"))?,
                radius: number(get("radius")?, &format!("{what} radius"))?,
                density: number(get("density")?, &format!("{what} density"))?,
                colour: match o.get("colour") {
                    None => Rgb::CLAY,
                    Some(c) => colour(c, &format!("{what} colour"))?,
                },
            };
            mc.validate(&what)?;
            metacircles.push(mc);
        }
        let figure = Figure {
            metacircles,
            threshold,
        };
        figure.validate()?;
        let contour = match obj.get("contour") {
            None | Some(Value::Null) => None,
            Some(c) => Some(contour_from_json(c, "contour")?),
        };
        let mut polygons = Vec::new();
        for (i, p) in array(obj, "polygons")?.iter().enumerate() {
            let what = format!("polygon {i}");
            let o = p
                .as_object()
                .ok_or_else(|| FigureError::Format(format!("{what} must be an object")))?;
            let pts = o
                .get("points")
                .ok_or_else(|| FigureError::Format(format!("{what} needs \"points\"")))?;
            polygons.push(FilledPolygon {
                contour: contour_from_json(pts, &what)?,
                colour: match o.get("colour") {
                    None => Rgb::CLAY,
                    Some(c) => colour(c, &format!("{what} colour"))?,
                },
            });
        }
        let curves = curves_from_json(obj.get("curves").unwrap_or(&Value::Null))?;
        Ok(Self {
            name,
            figure,
            view,
            background,
            contour,
            polygons,
            curves,
        })
    }

    /// The document as pretty-printed JSON text.
    #[must_use]
    pub fn to_json(&self) -> String {
        let mut o = Map::new();
        o.insert("format".into(), json!(FORMAT));
        o.insert("version".into(), json!(VERSION));
        if let Some(n) = &self.name {
            o.insert("name".into(), json!(n));
        }
        o.insert("threshold".into(), json!(self.figure.threshold));
        if let Some((lo, hi)) = self.view {
            o.insert(
                "view".into(),
                json!({"min": [lo.x, lo.y], "max": [hi.x, hi.y]}),
            );
        }
        if let Some(b) = self.background {
            o.insert("background".into(), json!(b.to_hex()));
        }
        o.insert(
            "metacircles".into(),
            Value::Array(
                self.figure
                    .metacircles
                    .iter()
                    .map(|m| json!({"centre": [m.centre.x, m.centre.y], "radius": m.radius, "density": m.density, "colour": m.colour.to_hex()}))
                    .collect(),
            ),
        );
        if let Some(c) = &self.contour {
            o.insert("contour".into(), points_json(c.points()));
        }
        if !self.polygons.is_empty() {
            o.insert(
                "polygons".into(),
                Value::Array(self.polygons.iter().map(|p| json!({"points": points_json(p.contour.points()), "colour": p.colour.to_hex()})).collect()),
            );
        }
        if !self.curves.is_empty() {
            o.insert("curves".into(), curves_to_json(&self.curves));
        }
        let mut s = serde_json::to_string_pretty(&Value::Object(o)).unwrap_or_default();
        s.push('\n');
        s
    }
}

/// Parses `text` as JSON and checks its `format` and `version` members (the header every
/// nendo figure and shape file starts with); `kind` names the file in errors.
///
/// # Errors
/// [`FigureError::Format`] for text that is not JSON, not an object, of another format, or
/// of another version.
pub(crate) fn header_checked(
    text: &str,
    kind: &str,
    format: &str,
    version: u64,
) -> Result<Value, FigureError> {
    let v: Value = serde_json::from_str(text)
        .map_err(|e| FigureError::Format(format!("not valid JSON: {e}")))?;
    let obj = v
        .as_object()
        .ok_or_else(|| FigureError::Format(format!("a {kind} file must be a JSON object")))?;
    match obj.get("format").and_then(Value::as_str) {
        Some(f) if f == format => {}
        Some(other) => {
            return Err(FigureError::Format(format!(
                "\"format\" is {other:?}; expected {format:?}"
            )));
        }
        None => {
            return Err(FigureError::Format(format!(
                "missing \"format\": {format:?}"
            )));
        }
    }
    match obj.get("version").and_then(Value::as_u64) {
        Some(v) if v == version => {}
        Some(v) => {
            return Err(FigureError::Format(format!(
                "version {v} is not supported (this build reads {version})"
            )));
        }
        None => return Err(FigureError::Format("missing \"version\"".into())),
    }
    Ok(v)
}

/// Reads a list of 2D curves: a JSON array of curves, or an object with a `"curves"` array
/// (a figure file, or `{"curves": […]}`); `null` reads as none.
///
/// # Errors
/// [`FigureError::Curve`] naming the curve, or [`FigureError::Format`].
pub fn curves_from_json(v: &Value) -> Result<Vec<Curve<DVec2>>, FigureError> {
    let arr = match v {
        Value::Null => return Ok(Vec::new()),
        Value::Array(a) => a,
        Value::Object(o) => match o.get("curves") {
            Some(Value::Array(a)) => a,
            _ => {
                return Err(FigureError::Format(
                    "expected an array of curves or an object with a \"curves\" array".into(),
                ));
            }
        },
        _ => return Err(FigureError::Format("\"curves\" must be an array".into())),
    };
    arr.iter()
        .enumerate()
        .map(|(index, c)| match curve_from_json(c) {
            Ok(DynCurve::D2(c)) => Ok(c),
            Ok(DynCurve::D3(_)) => Err(FigureError::Format(format!(
                "curve {index} is 3D; figures need 2D curves"
            ))),
            Err(source) => Err(FigureError::Curve { index, source }),
        })
        .collect()
}

/// The JSON array of 2D curves.
#[must_use]
pub fn curves_to_json(curves: &[Curve<DVec2>]) -> Value {
    Value::Array(curves.iter().map(curve_to_json).collect())
}

pub(crate) fn points_json(p: &[DVec2]) -> Value {
    Value::Array(p.iter().map(|p| json!([p.x, p.y])).collect())
}

pub(crate) fn array<'a>(
    obj: &'a Map<String, Value>,
    key: &str,
) -> Result<&'a [Value], FigureError> {
    match obj.get(key) {
        None | Some(Value::Null) => Ok(&[]),
        Some(Value::Array(a)) => Ok(a),
        Some(_) => Err(FigureError::Format(format!("\"{key}\" must be an array"))),
    }
}

pub(crate) fn number(v: &Value, what: &str) -> Result<f64, FigureError> {
    let f = v
        .as_f64()
        .ok_or_else(|| FigureError::Format(format!("{what} must be a number")))?;
    if f.is_finite() {
        Ok(f)
    } else {
        Err(FigureError::NotFinite {
            what: what.to_string(),
        })
    }
}

pub(crate) fn point(v: &Value, what: &str) -> Result<DVec2, FigureError> {
    match v.as_array().map(Vec::as_slice) {
        Some([x, y]) => Ok(DVec2::new(number(x, what)?, number(y, what)?)),
        _ => Err(FigureError::Format(format!(
            "{what} must be a point [x, y]"
        ))),
    }
}

pub(crate) fn contour_from_json(v: &Value, what: &str) -> Result<Contour, FigureError> {
    let arr = v
        .as_array()
        .ok_or_else(|| FigureError::Format(format!("{what} must be an array of points [x, y]")))?;
    let pts = arr
        .iter()
        .enumerate()
        .map(|(i, p)| point(p, &format!("{what} vertex {i}")))
        .collect::<Result<Vec<_>, _>>()?;
    Contour::new(pts, what)
}

fn colour(v: &Value, what: &str) -> Result<Rgb, FigureError> {
    v.as_str()
        .and_then(Rgb::parse_hex)
        .ok_or_else(|| FigureError::Format(format!("{what} must be a colour \"#rrggbb\"")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::Bezier;

    #[test]
    fn round_trip() {
        let mut doc = FigureDocument {
            name: Some("blob".into()),
            figure: Figure::new(vec![Metacircle::new(DVec2::new(1.0, 2.0), 3.0, -0.25)]),
            view: Some((DVec2::ZERO, DVec2::new(10.0, 5.0))),
            background: Some(Rgb([1, 2, 3])),
            contour: Some(Contour::new(vec![DVec2::ZERO, DVec2::X, DVec2::Y], "c").unwrap()),
            polygons: vec![],
            curves: vec![
                Bezier::new(vec![
                    DVec2::ZERO,
                    DVec2::new(1.0, 1.0),
                    DVec2::new(2.0, 0.1),
                ])
                .into(),
            ],
        };
        doc.figure.threshold = 0.4;
        doc.figure.metacircles[0].colour = Rgb([200, 100, 50]);
        doc.polygons.push(FilledPolygon {
            contour: Contour::new(vec![DVec2::ZERO, DVec2::X, DVec2::ONE], "p").unwrap(),
            colour: Rgb::BLACK,
        });
        let back = FigureDocument::from_json(&doc.to_json()).unwrap();
        assert_eq!(back, doc);
    }

    #[test]
    fn minimal_document_and_errors() {
        let d = FigureDocument::from_json(r#"{"format": "nendo-figure", "version": 1}"#).unwrap();
        assert!(d.figure.metacircles.is_empty() && d.frame().is_none());
        for (text, needle) in [
            (r#"{"format": "nendo-model", "version": 1}"#, "format"),
            (r#"{"format": "nendo-figure", "version": 9}"#, "version 9"),
            (
                r#"{"format": "nendo-figure", "version": 1, "metacircles": [{"centre": [0, 0], "radius": -1, "density": 1}]}"#,
                "metacircle 0",
            ),
            (
                r#"{"format": "nendo-figure", "version": 1, "metacircles": [{"centre": [0], "radius": 1, "density": 1}]}"#,
                "metacircle 0 centre",
            ),
            (
                r#"{"format": "nendo-figure", "version": 1, "threshold": 0}"#,
                "threshold",
            ),
            (
                r#"{"format": "nendo-figure", "version": 1, "contour": [[0, 0], [1, 1]]}"#,
                "contour",
            ),
            (
                r#"{"format": "nendo-figure", "version": 1, "curves": [{"bezier": [[0, 0, 0]]}]}"#,
                "curve 0",
            ),
            (
                r#"{"format": "nendo-figure", "version": 1, "background": "red"}"#,
                "background",
            ),
            ("{not json", "JSON"),
        ] {
            let e = FigureDocument::from_json(text).unwrap_err().to_string();
            assert!(e.contains(needle), "{text}: {e}");
        }
    }
}
