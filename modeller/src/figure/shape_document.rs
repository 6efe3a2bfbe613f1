//! The shape file (`nendo-shape` JSON): the horizontal sections of a metaball shape, the curves
//! laid along them, the drags to apply to those curves, and (once fitted) the metaballs — the
//! input and output of `nendo figure shape`.
//!
//! ```json
//! {"format": "nendo-shape", "version": 1,
//!  "name": "torso",
//!  "threshold": 0.5,
//!  "sections": [
//!    {"z": 30.0,
//!     "contour": [[x, y], …],
//!     "curves": [{"bezier": [[x, y], …]}, …],
//!     "moves": [{"curve": 2, "from": [x, y], "to": [x, y], "method": "largest", "keep_ends": false},
//!               {"curve": 3, "deformed": {"bezier": [[x, y], …]}}]},
//!    …],
//!  "metaballs": [{"centre": [x, y, z], "radius": R, "density": q}, …]}
//! ```
//!
//! * Coordinates: `x, y` in each section's horizontal plane, `z` up (the modeller's axes,
//!   right-handed); any unit.
//! * `format` and `version` are required, and at least one section; every section needs `z`
//!   (finite) and `contour` (a closed polygon: at least three distinct vertices, non-zero
//!   area; the closing vertex need not be repeated). Sections may share a height (two legs).
//! * `curves` (optional, per section): 2D curves in the form of [`crate::curve::json`], laid
//!   along (or near) the section's outline; dragging them moves the outline
//!   ([`super::section`]).
//! * `moves` (optional, per section), applied in order, each naming a curve of the section by
//!   its index: `{"curve": k, "from": P, "to": Q}` grabs curve `k` at its point closest to `P`
//!   and moves that point by `Q − P` exactly (`method` `"largest"` — the default, the control
//!   point of largest weight —, `"nearest"` or `"least_change"`, and `keep_ends`, as in
//!   `nendo curve --batch`); `{"curve": k, "deformed": C}` replaces the curve by `C` (same
//!   parameter domain).
//! * `metaballs` (optional): a fitted shape to start from; without it the shape is fitted to
//!   the sections first. `threshold` (default 0.5, positive) is the iso-surface's.
//! * Written back ([`ShapeDocument::to_json`]) with the moved curves and warped contours in
//!   place of the originals, the fitted metaballs, and no `moves`: the file of the deformed
//!   shape, ready for further drags.

use glam::{DVec2, DVec3};
use serde::Deserialize;
use serde_json::{Map, Value, json};

/// Most metaballs a shape file may hold.
pub const MAX_METABALLS: usize = 2_000;

/// The most sections a shape file may hold (each is fitted, meshed and measured on its own).
pub const MAX_SECTIONS: usize = 256;

use crate::curve::edit::{GrabMethod, GrabOptions};
use crate::curve::json::{PlanarCurve, WholeNumber, curve_to_json};

use super::document::{
    check_header, contour_from_points, curves_to_json, points_json, read_document,
};
use super::error::FigureError;
use super::falloff::DEFAULT_THRESHOLD;
use super::metaball::{Metaball, Shape};
use super::section::{CurveMove, Section};

/// The `format` member of every shape file.
pub const FORMAT: &str = "nendo-shape";
/// The version this build reads and writes.
pub const VERSION: u64 = 1;

/// Everything a shape file holds.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeDocument {
    /// A name, for people.
    pub name: Option<String>,
    /// The threshold of the iso-surface.
    pub threshold: f64,
    /// The sections, in the order of the file.
    pub sections: Vec<Section>,
    /// Per section, the drags of its curves (empty when none).
    pub moves: Vec<Vec<CurveMove>>,
    /// The fitted metaballs, if the file has them.
    pub shape: Option<Shape>,
}

impl ShapeDocument {
    /// Reads a document from JSON text (unknown or repeated members refused).
    ///
    /// # Errors
    /// [`FigureError::Json`] naming the member's path, line and column for malformed JSON or
    /// members, [`FigureError::Format`] for another format or version or a move naming no
    /// curve, and the validation errors of the parts (contours, curves, metaballs).
    pub fn from_json(text: &str) -> Result<Self, FigureError> {
        let doc: ShapeDoc = read_document(text, FORMAT, VERSION)?;
        check_header(
            Some(&doc.format.into()),
            Some(&doc.version.into()),
            FORMAT,
            VERSION,
        )?;
        let threshold = doc.threshold.unwrap_or(DEFAULT_THRESHOLD);
        if threshold <= 0.0 {
            return Err(FigureError::Threshold(threshold));
        }
        if doc.sections.is_empty() {
            return Err(FigureError::Format(
                "\"sections\" must list at least one section {\"z\", \"contour\"}".into(),
            ));
        }
        if doc.sections.len() > MAX_SECTIONS {
            return Err(FigureError::Format(format!(
                "{} sections: at most {MAX_SECTIONS}",
                doc.sections.len()
            )));
        }
        let mut sections = Vec::with_capacity(doc.sections.len());
        let mut moves = Vec::with_capacity(doc.sections.len());
        for (i, s) in doc.sections.into_iter().enumerate() {
            let what = format!("section {i}");
            let contour = contour_from_points(&s.contour, &format!("{what} contour"))?;
            let curves: Vec<_> = s.curves.into_iter().map(|c| c.0).collect();
            let section_moves = s
                .moves
                .into_iter()
                .enumerate()
                .map(|(j, m)| m.into_move(&format!("{what} move {j}"), curves.len()))
                .collect::<Result<Vec<_>, _>>()?;
            sections.push(Section::new(s.z, contour, curves)?);
            moves.push(section_moves);
        }
        let shape = match doc.metaballs {
            None => None,
            Some(list) => {
                if list.len() > MAX_METABALLS {
                    return Err(FigureError::Format(format!(
                        "{} metaballs: at most {MAX_METABALLS} (the fit's Jacobian grows with their number)",
                        list.len()
                    )));
                }
                let mut balls = Vec::with_capacity(list.len());
                for (i, b) in list.into_iter().enumerate() {
                    let ball = Metaball {
                        centre: DVec3::from_array(b.centre),
                        radius: b.radius,
                        density: b.density,
                    };
                    ball.validate(&format!("metaball {i}"))?;
                    balls.push(ball);
                }
                Some(Shape { balls, threshold })
            }
        };
        Ok(Self {
            name: doc.name,
            threshold,
            sections,
            moves,
            shape,
        })
    }

    /// Whether any section has a move.
    #[must_use]
    pub fn has_moves(&self) -> bool {
        self.moves.iter().any(|m| !m.is_empty())
    }

    /// The document as pretty-printed JSON text (moves included).
    #[must_use]
    pub fn to_json(&self) -> String {
        let mut o = Map::new();
        o.insert("format".into(), json!(FORMAT));
        o.insert("version".into(), json!(VERSION));
        if let Some(n) = &self.name {
            o.insert("name".into(), json!(n));
        }
        o.insert("threshold".into(), json!(self.threshold));
        let sections: Vec<Value> = self
            .sections
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let mut so = Map::new();
                so.insert("z".into(), json!(s.z));
                so.insert("contour".into(), points_json(s.contour.points()));
                if !s.curves.is_empty() {
                    so.insert("curves".into(), curves_to_json(&s.curves));
                }
                let moves = self.moves.get(i).map_or(&[][..], Vec::as_slice);
                if !moves.is_empty() {
                    so.insert(
                        "moves".into(),
                        Value::Array(moves.iter().map(move_json).collect()),
                    );
                }
                Value::Object(so)
            })
            .collect();
        o.insert("sections".into(), Value::Array(sections));
        if let Some(shape) = &self.shape {
            o.insert(
                "metaballs".into(),
                Value::Array(
                    shape
                        .balls
                        .iter()
                        .map(|b| {
                            json!({
                                "centre": [b.centre.x, b.centre.y, b.centre.z],
                                "radius": b.radius,
                                "density": b.density,
                            })
                        })
                        .collect(),
                ),
            );
        }
        let mut s = serde_json::to_string_pretty(&Value::Object(o)).unwrap_or_default();
        s.push('\n');
        s
    }
}

/// A shape file as read: every member typed, unknown and repeated members refused.
#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a nendo-shape document (a JSON object)"
)]
struct ShapeDoc {
    format: String,
    version: u64,
    #[serde(default)]
    name: Option<String>,
    #[serde(default)]
    threshold: Option<f64>,
    #[serde(default)]
    sections: Vec<SectionDoc>,
    #[serde(default)]
    metaballs: Option<Vec<MetaballDoc>>,
}

/// One of `sections`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SectionDoc {
    z: f64,
    contour: Vec<[f64; 2]>,
    #[serde(default)]
    curves: Vec<PlanarCurve>,
    #[serde(default)]
    moves: Vec<MoveDoc>,
}

/// One of a section's `moves`: a grab (`from`, `to`, `method`, `keep_ends`) or a replacement
/// (`deformed`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MoveDoc {
    curve: WholeNumber,
    #[serde(default)]
    from: Option<[f64; 2]>,
    #[serde(default)]
    to: Option<[f64; 2]>,
    #[serde(default)]
    method: Option<MethodDoc>,
    #[serde(default)]
    keep_ends: Option<bool>,
    #[serde(default)]
    deformed: Option<PlanarCurve>,
}

/// A grab's `method`.
#[derive(Deserialize)]
#[serde(rename_all = "snake_case")]
enum MethodDoc {
    Largest,
    Nearest,
    LeastChange,
}

/// One of `metaballs`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MetaballDoc {
    centre: [f64; 3],
    radius: f64,
    density: f64,
}

impl MoveDoc {
    /// The move, checked against the section's `curves` count; `what` names it in errors.
    fn into_move(self, what: &str, curves: usize) -> Result<CurveMove, FigureError> {
        let curve = usize::try_from(self.curve.0).unwrap_or(usize::MAX);
        if curve >= curves {
            return Err(FigureError::Format(format!(
                "{what} names curve {curve}, but the section has {curves} curves"
            )));
        }
        let grab = self.from.is_some()
            || self.to.is_some()
            || self.method.is_some()
            || self.keep_ends.is_some();
        match (self.deformed, self.from, self.to) {
            (Some(_), _, _) if grab => Err(FigureError::Format(format!(
                "{what} is either a grab (\"from\", \"to\") or a replacement (\"deformed\"), not both"
            ))),
            (Some(d), _, _) => Ok(CurveMove::Replace {
                curve,
                deformed: d.0,
            }),
            (None, Some(from), Some(to)) => Ok(CurveMove::Grab {
                curve,
                from: DVec2::from_array(from),
                to: DVec2::from_array(to),
                options: GrabOptions {
                    method: match self.method {
                        None | Some(MethodDoc::Largest) => GrabMethod::LargestWeight,
                        Some(MethodDoc::Nearest) => GrabMethod::NearestParameter,
                        Some(MethodDoc::LeastChange) => GrabMethod::LeastChange,
                    },
                    keep_ends: self.keep_ends.unwrap_or(false),
                },
            }),
            (None, _, _) => Err(FigureError::Format(format!(
                "{what} needs \"from\" and \"to\" (a grab) or \"deformed\" (a curve)"
            ))),
        }
    }
}

fn move_json(m: &CurveMove) -> Value {
    match m {
        CurveMove::Grab {
            curve,
            from,
            to,
            options,
        } => json!({
            "curve": curve,
            "from": [from.x, from.y],
            "to": [to.x, to.y],
            "method": match options.method {
                GrabMethod::LargestWeight => "largest",
                GrabMethod::NearestParameter => "nearest",
                GrabMethod::LeastChange => "least_change",
            },
            "keep_ends": options.keep_ends,
        }),
        CurveMove::Replace { curve, deformed } => {
            json!({"curve": curve, "deformed": curve_to_json(deformed)})
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SQUARE: &str = "[[0, 0], [2, 0], [2, 2], [0, 2]]";

    #[test]
    fn round_trip() {
        let text = format!(
            r#"{{"format": "nendo-shape", "version": 1, "name": "box",
               "sections": [
                 {{"z": 0, "contour": {SQUARE}}},
                 {{"z": 1.5, "contour": {SQUARE},
                   "curves": [{{"bezier": [[2, 0], [2, 1], [2, 2]]}}],
                   "moves": [{{"curve": 0, "from": [2, 1], "to": [2.5, 1], "method": "least_change"}},
                             {{"curve": 0, "deformed": {{"bezier": [[2, 0], [3, 1], [2, 2]]}}}}]}}],
               "metaballs": [{{"centre": [1, 1, 0.5], "radius": 2, "density": 0.8}}]}}"#
        );
        let doc = ShapeDocument::from_json(&text).unwrap();
        assert_eq!(doc.sections.len(), 2);
        assert_eq!(doc.moves[1].len(), 2);
        assert!(doc.has_moves());
        assert_eq!(doc.shape.as_ref().map(|s| s.balls.len()), Some(1));
        let back = ShapeDocument::from_json(&doc.to_json()).unwrap();
        assert_eq!(back, doc);
    }

    #[test]
    fn errors_name_the_member() {
        for (text, needle) in [
            (r#"{"format": "nendo-figure", "version": 1}"#.to_string(), "format"),
            (r#"{"format": "nendo-shape", "version": 2}"#.to_string(), "version 2"),
            (r#"{"format": "nendo-shape", "version": 1, "sections": []}"#.to_string(), "at least one"),
            (
                format!(r#"{{"format": "nendo-shape", "version": 1, "sections": [{{"contour": {SQUARE}}}]}}"#),
                "sections[0]: missing field \"z\"",
            ),
            (
                r#"{"format": "nendo-shape", "version": 1, "sections": [{"z": 0, "contour": [[0, 0], [1, 1]]}]}"#.to_string(),
                "section 0 contour",
            ),
            (
                format!(r#"{{"format": "nendo-shape", "version": 1, "sections": [{{"z": 0, "contour": {SQUARE}, "moves": [{{"curve": 0, "from": [0, 0], "to": [1, 1]}}]}}]}}"#),
                "section 0 move 0 names curve 0",
            ),
            (
                format!(r#"{{"format": "nendo-shape", "version": 1, "sections": [{{"z": 0, "contour": {SQUARE}, "curves": [{{"bezier": [[0, 0], [1, 0]]}}], "moves": [{{"curve": 0, "from": [0, 0], "to": [1, 1], "method": 3}}]}}]}}"#),
                "sections[0].moves[0].method",
            ),
            (
                format!(r#"{{"format": "nendo-shape", "version": 1, "sections": [{{"z": 0, "contour": {SQUARE}}}], "metaballs": [{{"centre": [0, 0], "radius": 1, "density": 1}}]}}"#),
                "metaballs[0].centre",
            ),
            (
                format!(r#"{{"format": "nendo-shape", "version": 1, "sections": [{{"z": 0, "contour": {SQUARE}}}], "metaballs": [{{"centre": [0, 0, 0], "radius": -1, "density": 1}}]}}"#),
                "metaball 0",
            ),
            (
                format!(r#"{{"format": "nendo-shape", "version": 1, "threshold": 0, "sections": [{{"z": 0, "contour": {SQUARE}}}]}}"#),
                "threshold",
            ),
        ] {
            let e = ShapeDocument::from_json(&text).unwrap_err().to_string();
            assert!(e.contains(needle), "{text}: {e}");
        }
    }
}
