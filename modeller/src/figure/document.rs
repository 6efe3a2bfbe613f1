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
//!   map them to pixels through a [`RasterView`](super::View).
//! * `format` and `version` are required; every other member is optional: `threshold` (default
//!   0.5, positive), `name`, `view` (the rectangle drawn; default the figure's bounds),
//!   `background` (default white), `metacircles` (default none; `colour` default `#8a5a3c`,
//!   `radius ≥ 0`, `density` of any sign), `contour` (a closed polygon, the outline the figure
//!   was fitted to, its coordinates within ±1e12), `polygons` (closed, each with a colour),
//!   `curves` (2D curves in the form of [`crate::curve::json`]; in a morph, curve `k` of the
//!   source corresponds to curve `k` of the destination).
//! * Reading refuses unknown and repeated members, validates every number and says where a
//!   problem is (the member's path, line and column; see [`crate::json_doc`]); the text is
//!   produced and consumed by the callers (the library reads and writes no files).

/// The most metacircles a figure file may hold (the shipped figures have about 200; the
/// benchmarks draw 300).
pub const MAX_METACIRCLES: usize = 2_000;

use glam::DVec2;
use serde::de::{DeserializeOwned, Error as _};
use serde::{Deserialize, Deserializer};
use serde_json::{Map, Value, json};

use crate::curve::Curve;
use crate::curve::json::{PlanarCurve, curve_to_json};
use crate::json_doc::{self, JsonError};

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

    /// Reads a document from JSON text (unknown or repeated members refused).
    ///
    /// # Errors
    /// [`FigureError::Json`] (naming the member's path, line and column) for malformed JSON
    /// or members, [`FigureError::Format`] for another format or version, and the validation
    /// errors of the parts.
    pub fn from_json(text: &str) -> Result<Self, FigureError> {
        let doc: FigureDoc = read_document(text, FORMAT, VERSION)?;
        check_header(
            Some(&doc.format.into()),
            Some(&doc.version.into()),
            FORMAT,
            VERSION,
        )?;
        let threshold = doc.threshold.unwrap_or(DEFAULT_THRESHOLD);
        let view = match doc.view {
            None => None,
            Some(v) => {
                let (min, max) = (DVec2::from_array(v.min), DVec2::from_array(v.max));
                if !(max.x > min.x && max.y > min.y) {
                    return Err(FigureError::Format(
                        "\"view\": max must exceed min on both axes".into(),
                    ));
                }
                Some((min, max))
            }
        };
        let listed = doc.metacircles.unwrap_or_default();
        if listed.len() > MAX_METACIRCLES {
            return Err(FigureError::Format(format!(
                "{} metacircles: at most {MAX_METACIRCLES} (every picture, fit and measure evaluates each at every sample)",
                listed.len()
            )));
        }
        let mut metacircles = Vec::with_capacity(listed.len());
        for (i, m) in listed.into_iter().enumerate() {
            let mc = Metacircle {
                centre: DVec2::from_array(m.centre),
                radius: m.radius,
                density: m.density,
                colour: m.colour.map_or(Rgb::CLAY, |c| c.0),
            };
            mc.validate(&format!("metacircle {i}"))?;
            metacircles.push(mc);
        }
        let figure = Figure {
            metacircles,
            threshold,
        };
        figure.validate()?;
        let contour = match doc.contour {
            None => None,
            Some(c) => Some(contour_from_points(&c, "contour")?),
        };
        let mut polygons = Vec::new();
        for (i, p) in doc.polygons.unwrap_or_default().into_iter().enumerate() {
            polygons.push(FilledPolygon {
                contour: contour_from_points(&p.points, &format!("polygon {i}"))?,
                colour: p.colour.map_or(Rgb::CLAY, |c| c.0),
            });
        }
        let curves = doc
            .curves
            .unwrap_or_default()
            .into_iter()
            .map(|c| c.0)
            .collect();
        Ok(Self {
            name: doc.name,
            figure,
            view,
            background: doc.background.map(|c| c.0),
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

/// A figure file as read: every member typed, unknown and repeated members refused.
#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a nendo-figure document (a JSON object)"
)]
struct FigureDoc {
    format: String,
    version: u64,
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    threshold: Option<f64>,
    #[serde(default)]
    view: Option<ViewDoc>,
    #[serde(default)]
    background: Option<Colour>,
    #[serde(default)]
    metacircles: Option<Vec<MetacircleDoc>>,
    #[serde(default)]
    contour: Option<Vec<[f64; 2]>>,
    #[serde(default)]
    polygons: Option<Vec<PolygonDoc>>,
    #[serde(default)]
    curves: Option<Vec<PlanarCurve>>,
}

/// `view`: the rectangle pictures show.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ViewDoc {
    min: [f64; 2],
    max: [f64; 2],
}

/// One of `metacircles`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MetacircleDoc {
    centre: [f64; 2],
    radius: f64,
    density: f64,
    #[serde(default)]
    colour: Option<Colour>,
}

/// One of `polygons`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PolygonDoc {
    points: Vec<[f64; 2]>,
    #[serde(default)]
    colour: Option<Colour>,
}

/// A colour `"#rrggbb"`.
pub(crate) struct Colour(pub(crate) Rgb);

impl<'de> Deserialize<'de> for Colour {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        Rgb::parse_hex(&s)
            .map(Colour)
            .ok_or_else(|| D::Error::custom(format!("{s:?} is not a colour \"#rrggbb\"")))
    }
}

/// Only `format` and `version`, any other member ignored: what a document that failed to
/// read says it is, so that another format or version is named as such.
#[derive(Deserialize)]
struct Header {
    #[serde(default)]
    format: Option<Value>,
    #[serde(default)]
    version: Option<Value>,
}

/// Reads the document `T` from `text`; when that fails and the text is of another `format`
/// or `version`, says so rather than naming the first member that does not fit.
///
/// # Errors
/// [`FigureError::Format`] for another format or version, else [`FigureError::Json`].
pub(crate) fn read_document<T: DeserializeOwned>(
    text: &str,
    format: &str,
    version: u64,
) -> Result<T, FigureError> {
    // serde reads a struct from an array too: the document itself must be an object.
    let object = text.trim_start().starts_with('{');
    let doc = json_doc::from_str::<T>(text);
    if !object && !matches!(doc, Err(JsonError::Bom)) {
        return Err(FigureError::Json(JsonError::at(
            "",
            format!("a {format} document must be a JSON object"),
        )));
    }
    doc.map_err(|e| match json_doc::from_str::<Header>(text) {
        Ok(h) => check_header(h.format.as_ref(), h.version.as_ref(), format, version)
            .err()
            .unwrap_or(FigureError::Json(e)),
        Err(_) => FigureError::Json(e),
    })
}

/// Checks the `format` and `version` members every nendo figure and shape file starts with.
///
/// # Errors
/// [`FigureError::Format`] for a missing or other format or version.
pub(crate) fn check_header(
    found_format: Option<&Value>,
    found_version: Option<&Value>,
    format: &str,
    version: u64,
) -> Result<(), FigureError> {
    match found_format {
        Some(Value::String(f)) if f == format => {}
        Some(other) => {
            return Err(FigureError::Format(format!(
                "\"format\" is {other}; expected {format:?}"
            )));
        }
        None => {
            return Err(FigureError::Format(format!(
                "missing \"format\": {format:?}"
            )));
        }
    }
    match found_version {
        Some(v) if v.as_u64() == Some(version) => Ok(()),
        Some(v) => Err(FigureError::Format(format!(
            "version {v} is not supported (this build reads {version})"
        ))),
        None => Err(FigureError::Format("missing \"version\"".into())),
    }
}

/// Reads a list of 2D curves: a JSON array of curves, or an object with a `"curves"` array
/// (a figure file, or `{"curves": […]}`; its other members are not read); `null` reads as
/// none.
///
/// # Errors
/// [`FigureError::Json`] naming the bad curve's path, or [`FigureError::Format`].
pub fn curves_from_json(v: &Value) -> Result<Vec<Curve<DVec2>>, FigureError> {
    let list: Vec<PlanarCurve> = match v {
        Value::Null => return Ok(Vec::new()),
        Value::Array(_) => json_doc::from_value(v)?,
        Value::Object(o) => match o.get("curves") {
            Some(a @ Value::Array(_)) => json_doc::from_value(a).map_err(|e| e.within("curves"))?,
            _ => {
                return Err(FigureError::Format(
                    "expected an array of curves or an object with a \"curves\" array".into(),
                ));
            }
        },
        _ => return Err(FigureError::Format("\"curves\" must be an array".into())),
    };
    Ok(list.into_iter().map(|c| c.0).collect())
}

/// Reads a list of 2D curves from JSON text, as [`curves_from_json`] (a byte-order mark and
/// JSON errors named with their line and column).
///
/// # Errors
/// As [`curves_from_json`].
pub fn curves_from_json_str(text: &str) -> Result<Vec<Curve<DVec2>>, FigureError> {
    curves_from_json(&json_doc::from_str::<Value>(text)?)
}

/// The JSON array of 2D curves.
#[must_use]
pub fn curves_to_json(curves: &[Curve<DVec2>]) -> Value {
    Value::Array(curves.iter().map(curve_to_json).collect())
}

pub(crate) fn points_json(p: &[DVec2]) -> Value {
    Value::Array(p.iter().map(|p| json!([p.x, p.y])).collect())
}

/// A closed polygon from its vertices; `what` names it in errors.
pub(crate) fn contour_from_points(v: &[[f64; 2]], what: &str) -> Result<Contour, FigureError> {
    Contour::new(v.iter().map(|&p| DVec2::from_array(p)).collect(), what)
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
                "metacircles[0].centre",
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
                "curves[0]",
            ),
            (
                r#"{"format": "nendo-figure", "version": 1, "metacircle": []}"#,
                "unknown field \"metacircle\"",
            ),
            (
                r#"{"format": "nendo-figure", "version": 1, "name": "a", "name": "b"}"#,
                "duplicate field \"name\"",
            ),
            (
                r#"{"format": "nendo-figure", "version": 1, "background": "red"}"#,
                "background",
            ),
            ("{not json", "line 1 column 2"),
        ] {
            let e = FigureDocument::from_json(text).unwrap_err().to_string();
            assert!(e.contains(needle), "{text}: {e}");
        }
    }
}
