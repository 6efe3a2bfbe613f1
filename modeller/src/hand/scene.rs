//! The scene of a recorded hand session: the surface it started from and the session's
//! settings, carried by a trace's `scene` header line (trace version 2, see
//! [`nendo_devices::trace`]), so that `nendo replay TRACE --out M.json` reproduces the session
//! with no other argument.
//!
//! ```json
//! {"regulation":"exact","finger":"index","finger_radius":1.0,"auto_refine":false,
//!  "primitive":{"name":"sphere","patches":[8,4],"radius":3.0}}
//! {"regulation":"g1","finger":"index","finger_radius":0.5,"mirror":"x","auto_refine":false,
//!  "model":{"format":"nendo-model","version":1,"surface":{…},"curves":[]}}
//! {"finger":"index","mirror":"x,y","radial":4,"auto_refine":false,"primitive":{"name":"tube"}}
//! {"finger":"index","model_file":{"path":"start.json","sha256":"9f86d0…"}}
//! ```
//!
//! (each on one line in a trace). The start surface is exactly one of
//! - `primitive`: a primitive by name with the parameters it was built with (`patches` as
//!   `[M, N]`, `radius`, `height`, `minor_radius`; an absent one takes the primitive's
//!   default, [`Primitive::defaults`]);
//! - `model`: a whole `nendo-model` document embedded in the trace ([`crate::model`]) — what
//!   the window's recorder and `nendo record --model` write: the trace is then complete on
//!   its own;
//! - `model_file`: a model file named by `path` (relative to the trace's directory unless
//!   absolute) and the SHA-256 of its bytes (64 lowercase hexadecimal digits), written by
//!   `nendo record --model M --reference`; a file whose hash differs is refused, naming both
//!   hashes.
//!
//! The settings, each optional: `regulation` (a method's name; absent: the start model's),
//! `finger` (the value of `--finger`, parsed by the command line's own parser; absent: the
//! profile's default), `finger_radius` (`r_f` in sides, a positive finite number; absent:
//! [`super::DEFAULT_FINGER_RADIUS`]), `mirror` (`x`, `y` or `z`, or several joined by commas,
//! `x,y`: every combination of the mirrors; absent: none), `radial` (`N` of the radial symmetry
//! about the z axis, at least 2; absent: none) or `lathe` (`true`: every contact applied all the
//! way round; not with `radial`) — together the group of [`crate::surface::SymmetrySpec`],
//! as `nendo record` and `nendo replay` take it with `--mirror`, `--radial` and `--lathe` —
//! `auto_refine` (default `false`; not with a symmetry), `filter` (the plausibility gate and One-Euro filter the
//! session's frames went through, as a profile's `filter` member, every member written out:
//! [`nendo_devices::FilterSettings`]; absent: `nendo replay` uses `--profile`'s, else the
//! defaults for the finger, [`super::filter::default_for`]). Unknown and repeated members are refused, like every
//! value that does not validate, with the member's path ([`crate::json_doc`]).

use serde::Deserialize;
use serde_json::{Value, json};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

use super::FingerModel;
use crate::json_doc::{self, JsonError};
use crate::model::{Model, ModelError, first_non_finite};
use crate::surface::{
    Grid, Plane, Primitive, PrimitiveParams, Regulation, SurfaceError, UnknownName,
};
use nendo_devices::{FilterSettings, SceneText};

/// What is wrong with a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The text is not JSON, or a member is unknown, repeated or of the wrong type.
    #[error("{0}")]
    Json(#[from] JsonError),
    /// The scene names no start surface, or more than one.
    #[error(
        "the scene must name exactly one start surface (`primitive`, `model` or `model_file`); it names {0}"
    )]
    Start(String),
    /// A name outside its set (primitive, regulation, mirror plane).
    #[error("{0}")]
    Unknown(#[from] UnknownName),
    /// The primitive's parameters do not build a surface.
    #[error("primitive {primitive}: {error}")]
    Primitive {
        /// The primitive.
        primitive: Primitive,
        /// Why it does not build.
        error: SurfaceError,
    },
    /// The embedded model does not read, or the named model file does not.
    #[error("start model{}: {error}", path.as_ref().map(|p| format!(" {}", p.display())).unwrap_or_default())]
    Model {
        /// The model file, when the model is named by path.
        path: Option<PathBuf>,
        /// Why it does not read.
        error: ModelError,
    },
    /// The named model file's content is not the one the scene names.
    #[error(
        "start model {}: its SHA-256 is {found}, the trace names {expected} (the file changed since the recording)",
        path.display()
    )]
    Hash {
        /// The model file.
        path: PathBuf,
        /// The hash the scene names.
        expected: String,
        /// The file's hash.
        found: String,
    },
    /// A number or text out of its range (a finger radius that is not a positive finite
    /// number, a hash that is not 64 hexadecimal digits).
    #[error("{name}: {message}")]
    Value {
        /// The member.
        name: &'static str,
        /// What is wrong.
        message: String,
    },
}

/// The surface a session starts from.
#[derive(Debug, Clone, PartialEq)]
pub enum Start {
    /// A primitive with its parameters.
    Primitive {
        /// The primitive.
        primitive: Primitive,
        /// Its parameters (absent ones take the defaults).
        params: PrimitiveParams,
    },
    /// A model embedded in the trace.
    Model(Box<Model>),
    /// A model file named by path and content hash.
    ModelFile {
        /// The file, relative to the trace's directory unless absolute.
        path: PathBuf,
        /// The SHA-256 of its bytes, 64 lowercase hexadecimal digits.
        sha256: String,
    },
}

/// The scene of a hand session: start surface and settings (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The start surface.
    pub start: Start,
    /// The regulation method (`None`: the start model's).
    pub regulation: Option<Regulation>,
    /// The touching finger(s), as the command line's `--finger` value (`None`: the profile's
    /// default).
    pub finger: Option<String>,
    /// The finger radius `r_f` (`None`: the default).
    pub finger_radius: Option<f64>,
    /// The mirror planes every contact is mirrored across (every combination; empty: none).
    pub mirror: Vec<Plane>,
    /// `N` of the radial symmetry about the z axis every contact is turned with (`None`: none).
    pub radial: Option<u32>,
    /// Every contact applied all the way round the z axis.
    pub lathe: bool,
    /// Whether the grid is refined before each contact.
    pub auto_refine: bool,
    /// The gate and filter the frames go through (`None`: the trace does not say).
    pub filter: Option<FilterSettings>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a scene (a JSON object)")]
struct SceneDoc {
    #[serde(default)]
    primitive: Option<PrimitiveDoc>,
    #[serde(default)]
    model: Option<Value>,
    #[serde(default)]
    model_file: Option<ModelFileDoc>,
    #[serde(default)]
    regulation: Option<String>,
    #[serde(default)]
    finger: Option<String>,
    #[serde(default)]
    finger_radius: Option<f64>,
    #[serde(default)]
    mirror: Option<String>,
    #[serde(default)]
    radial: Option<u32>,
    #[serde(default)]
    lathe: bool,
    #[serde(default)]
    auto_refine: bool,
    #[serde(default)]
    filter: Option<FilterSettings>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a primitive object")]
struct PrimitiveDoc {
    name: String,
    #[serde(default)]
    patches: Option<[usize; 2]>,
    #[serde(default)]
    radius: Option<f64>,
    #[serde(default)]
    height: Option<f64>,
    #[serde(default)]
    minor_radius: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a model_file object")]
struct ModelFileDoc {
    path: PathBuf,
    sha256: String,
}

/// The SHA-256 of `bytes`, as 64 lowercase hexadecimal digits.
#[must_use]
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The `--finger` value of a finger model: `ray` or the digit's name.
#[must_use]
pub fn finger_name(finger: FingerModel) -> String {
    match finger {
        FingerModel::Ray => "ray".into(),
        FingerModel::Hand(fingers) => fingers.to_string(),
    }
}

/// The parameters `primitive` is built from (the others are ignored by it).
fn uses(primitive: Primitive) -> [bool; 3] {
    // radius, height, minor radius
    match primitive {
        Primitive::Plane => [false, false, false],
        Primitive::Cylinder | Primitive::Tube => [true, true, false],
        Primitive::Hemisphere | Primitive::Sphere => [true, false, false],
        Primitive::Torus => [true, false, true],
    }
}

fn check_filter(f: Option<FilterSettings>) -> Result<Option<FilterSettings>, SceneError> {
    if let Some(f) = &f {
        f.validate().map_err(|e| SceneError::Value {
            name: "filter",
            message: e.to_string(),
        })?;
    }
    Ok(f)
}

/// The planes of a `mirror` member: `x`, `y` or `z`, or several joined by commas (each kept
/// once); `None`: none.
fn parse_planes(text: Option<&str>) -> Result<Vec<Plane>, SceneError> {
    let mut planes: Vec<Plane> = Vec::new();
    for name in text.into_iter().flat_map(|t| t.split(',')) {
        let plane: Plane = name.trim().parse()?;
        if !planes.contains(&plane) {
            planes.push(plane);
        }
    }
    Ok(planes)
}

/// The `mirror` member's text: the planes' names joined by commas.
fn plane_list(planes: &[Plane]) -> String {
    planes
        .iter()
        .map(|p| p.name())
        .collect::<Vec<_>>()
        .join(",")
}

/// `radial` is at least 2 and not given with `lathe`.
fn check_turns(radial: Option<u32>, lathe: bool) -> Result<Option<u32>, SceneError> {
    match radial {
        Some(n) if !(2..=4096).contains(&n) => Err(SceneError::Value {
            name: "radial",
            message: format!("{n} is not an N of 2 to 4096"),
        }),
        Some(_) if lathe => Err(SceneError::Value {
            name: "radial",
            message: "not with lathe (the lathe turns by every patch column)".into(),
        }),
        r => Ok(r),
    }
}

fn check_radius(r: Option<f64>) -> Result<Option<f64>, SceneError> {
    match r {
        Some(r) if !(r.is_finite() && r > 0.0) => Err(SceneError::Value {
            name: "finger_radius",
            message: format!("{r} is not a positive number"),
        }),
        r => Ok(r),
    }
}

impl Scene {
    /// A scene starting from `start` with no settings (every one its default).
    #[must_use]
    pub fn new(start: Start) -> Self {
        Self {
            start,
            regulation: None,
            finger: None,
            finger_radius: None,
            mirror: Vec::new(),
            radial: None,
            lathe: false,
            auto_refine: false,
            filter: None,
        }
    }

    /// The symmetry the scene's contacts are pressed with (mirrors, radial `N`, lathe).
    #[must_use]
    pub fn symmetry(&self) -> crate::surface::SymmetrySpec {
        let mut spec = crate::surface::SymmetrySpec {
            radial: self.radial.unwrap_or(0),
            lathe: self.lathe,
            ..crate::surface::SymmetrySpec::default()
        };
        for &p in &self.mirror {
            spec.add_plane(p);
        }
        spec
    }

    /// A primitive's scene with every parameter it is built from written out (the defaults
    /// filled in), so that the scene does not depend on the defaults of a later build.
    ///
    /// # Errors
    /// [`SceneError::Primitive`] for parameters that do not build.
    pub fn primitive(primitive: Primitive, params: &PrimitiveParams) -> Result<Self, SceneError> {
        let r = primitive
            .resolve(params)
            .map_err(|error| SceneError::Primitive { primitive, error })?;
        let [radius, height, minor] = uses(primitive);
        let params = PrimitiveParams {
            patches: Some(r.patches),
            radius: radius.then_some(r.radius),
            height: height.then_some(r.height),
            minor_radius: minor.then_some(r.minor_radius),
        };
        Grid::check_counts(primitive.topology(), r.patches.0, r.patches.1)
            .map_err(|error| SceneError::Primitive { primitive, error })?;
        Ok(Self::new(Start::Primitive { primitive, params }))
    }

    /// The scene of a session in the window: the document's model embedded, its regulation,
    /// the finger and radius of the hand; the window mirrors nothing and does not refine for
    /// the hand.
    #[must_use]
    pub fn of_window(model: &Model, finger: FingerModel, finger_radius: f64) -> Self {
        Self {
            regulation: Some(model.regulation),
            finger: Some(finger_name(finger)),
            finger_radius: Some(finger_radius),
            ..Self::new(Start::Model(Box::new(model.clone())))
        }
    }

    /// Reads a scene from its JSON text, validating every member (see the module docs). The
    /// `finger` is not parsed here: it is the command line's `--finger` value.
    ///
    /// # Errors
    /// [`SceneError`] naming the member that is wrong.
    pub fn parse(text: &str) -> Result<Scene, SceneError> {
        let doc: SceneDoc = json_doc::from_str(text)?;
        let named: Vec<&str> = [
            doc.primitive.as_ref().map(|_| "primitive"),
            doc.model.as_ref().map(|_| "model"),
            doc.model_file.as_ref().map(|_| "model_file"),
        ]
        .into_iter()
        .flatten()
        .collect();
        if named.len() != 1 {
            return Err(SceneError::Start(if named.is_empty() {
                "none".into()
            } else {
                named.join(" and ")
            }));
        }
        let start = if let Some(p) = doc.primitive {
            let primitive: Primitive = p.name.parse()?;
            let params = PrimitiveParams {
                patches: p.patches.map(|[m, n]| (m, n)),
                radius: p.radius,
                height: p.height,
                minor_radius: p.minor_radius,
            };
            let r = primitive
                .resolve(&params)
                .map_err(|error| SceneError::Primitive { primitive, error })?;
            Grid::check_counts(primitive.topology(), r.patches.0, r.patches.1)
                .map_err(|error| SceneError::Primitive { primitive, error })?;
            Start::Primitive { primitive, params }
        } else if let Some(m) = doc.model {
            let model = Model::from_json(&m)
                .map_err(|error| SceneError::Model { path: None, error })?
                .model;
            Start::Model(Box::new(model))
        } else if let Some(f) = doc.model_file {
            let ok = f.sha256.len() == 64
                && f.sha256
                    .bytes()
                    .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b));
            if !ok {
                return Err(SceneError::Value {
                    name: "model_file.sha256",
                    message: format!(
                        "{:?} is not a SHA-256 (64 lowercase hexadecimal digits)",
                        f.sha256
                    ),
                });
            }
            if f.path.as_os_str().is_empty() {
                return Err(SceneError::Value {
                    name: "model_file.path",
                    message: "empty".into(),
                });
            }
            Start::ModelFile {
                path: f.path,
                sha256: f.sha256,
            }
        } else {
            return Err(SceneError::Start("none".into()));
        };
        Ok(Scene {
            start,
            regulation: doc.regulation.map(|r| r.parse()).transpose()?,
            finger: doc.finger,
            finger_radius: check_radius(doc.finger_radius)?,
            mirror: parse_planes(doc.mirror.as_deref())?,
            radial: check_turns(doc.radial, doc.lathe)?,
            lathe: doc.lathe,
            auto_refine: doc.auto_refine,
            filter: check_filter(doc.filter)?,
        })
    }

    /// The scene of a trace header, if it has one.
    ///
    /// # Errors
    /// As [`Scene::parse`].
    pub fn of_trace(header: &nendo_devices::TraceHeader) -> Result<Option<Scene>, SceneError> {
        header
            .scene
            .as_ref()
            .map(|s| Scene::parse(s.as_str()))
            .transpose()
    }

    /// The scene as one line of JSON for a trace header: the settings first, then the start
    /// surface (which may be a whole model).
    ///
    /// # Errors
    /// [`SceneError::Value`] for a finger radius that is not a positive finite number,
    /// [`SceneError::Model`] for an embedded model with a coordinate that is not finite.
    pub fn to_text(&self) -> Result<SceneText, SceneError> {
        check_radius(self.finger_radius)?;
        check_filter(self.filter)?;
        // Each member's name and its JSON text, in this order.
        let mut members: Vec<(&str, String)> = Vec::new();
        if let Some(r) = self.regulation {
            members.push(("regulation", json!(r.name()).to_string()));
        }
        if let Some(f) = &self.finger {
            members.push(("finger", json!(f).to_string()));
        }
        if let Some(r) = self.finger_radius {
            members.push(("finger_radius", json!(r).to_string()));
        }
        if !self.mirror.is_empty() {
            members.push(("mirror", json!(plane_list(&self.mirror)).to_string()));
        }
        check_turns(self.radial, self.lathe)?;
        if let Some(n) = self.radial {
            members.push(("radial", json!(n).to_string()));
        }
        if self.lathe {
            members.push(("lathe", "true".to_string()));
        }
        members.push(("auto_refine", json!(self.auto_refine).to_string()));
        if let Some(f) = &self.filter {
            // In the members' own order (a `json!` object would sort them).
            let text = serde_json::to_string(f).map_err(|e| SceneError::Value {
                name: "filter",
                message: e.to_string(),
            })?;
            members.push(("filter", text));
        }
        match &self.start {
            Start::Primitive { primitive, params } => {
                let primitive = *primitive;
                primitive
                    .resolve(params)
                    .map_err(|error| SceneError::Primitive { primitive, error })?;
                // `name`, then the parameters in a fixed order.
                let mut text = format!("{{\"name\":{}", json!(primitive.name()));
                if let Some((m, n)) = params.patches {
                    text.push_str(&format!(",\"patches\":[{m},{n}]"));
                }
                for (name, v) in [
                    ("radius", params.radius),
                    ("height", params.height),
                    ("minor_radius", params.minor_radius),
                ] {
                    if let Some(v) = v {
                        text.push_str(&format!(",\"{name}\":{}", json!(v)));
                    }
                }
                text.push('}');
                members.push(("primitive", text));
            }
            Start::Model(model) => {
                if let Some((patch, point)) = first_non_finite(&model.surface) {
                    return Err(SceneError::Model {
                        path: None,
                        error: ModelError::Surface(SurfaceError::NotFinite { patch, point }),
                    });
                }
                members.push(("model", model.to_json_string()));
            }
            Start::ModelFile { path, sha256 } => {
                members.push((
                    "model_file",
                    json!({"path": path.to_string_lossy(), "sha256": sha256}).to_string(),
                ));
            }
        }
        let body: Vec<String> = members
            .iter()
            .map(|(k, v)| format!("{}:{v}", json!(k)))
            .collect();
        SceneText::new(format!("{{{}}}", body.join(","))).map_err(|e| SceneError::Value {
            name: "scene",
            message: e.to_string(),
        })
    }

    /// The model the session starts from. A model file named by the scene is read relative
    /// to `trace_dir` (unless its path is absolute) and must have the scene's hash.
    ///
    /// # Errors
    /// [`SceneError::Primitive`], [`SceneError::Model`] (the file does not read) or
    /// [`SceneError::Hash`].
    pub fn start_model(&self, trace_dir: &Path) -> Result<Model, SceneError> {
        match &self.start {
            Start::Primitive { primitive, params } => primitive
                .build(params)
                .map(Model::new)
                .map_err(|error| SceneError::Primitive {
                    primitive: *primitive,
                    error,
                }),
            Start::Model(m) => Ok((**m).clone()),
            Start::ModelFile { path, sha256 } => {
                let full = trace_dir.join(path);
                // At most one byte past the model limit: a device named by a scene is refused.
                use std::io::Read as _;
                let io = |error| SceneError::Model {
                    path: None,
                    error: ModelError::Io {
                        path: full.clone(),
                        error,
                    },
                };
                let mut bytes = Vec::new();
                std::fs::File::open(&full)
                    .and_then(|f| {
                        f.take(crate::model::MAX_FILE_BYTES + 1)
                            .read_to_end(&mut bytes)
                    })
                    .map_err(io)?;
                if bytes.len() as u64 > crate::model::MAX_FILE_BYTES {
                    return Err(SceneError::Model {
                        path: Some(full),
                        error: ModelError::Format(format!(
                            "larger than {} MB; not a model this build reads",
                            crate::model::MAX_FILE_BYTES >> 20
                        )),
                    });
                }
                let found = sha256_hex(&bytes);
                if &found != sha256 {
                    return Err(SceneError::Hash {
                        path: full,
                        expected: sha256.clone(),
                        found,
                    });
                }
                let text = String::from_utf8(bytes).map_err(|_| SceneError::Model {
                    path: Some(full.clone()),
                    error: ModelError::Format("not UTF-8 text".into()),
                })?;
                Model::from_json_str(&text)
                    .map(|l| l.model)
                    .map_err(|error| SceneError::Model {
                        path: Some(full),
                        error,
                    })
            }
        }
    }

    /// The `nendo replay` options naming this scene, for a scene whose start can be named on
    /// the command line (a primitive or a model file; `None` for an embedded model, or a
    /// filter other than the defaults or off). A model
    /// file's path is given as the scene names it (relative to the trace's directory).
    #[must_use]
    pub fn arguments(&self) -> Option<Vec<String>> {
        let mut a: Vec<String> = Vec::new();
        match &self.start {
            Start::Primitive { primitive, params } => {
                a.extend(["--primitive".into(), primitive.name().into()]);
                if let Some((m, n)) = params.patches {
                    a.extend(["--patches".into(), format!("{m}x{n}")]);
                }
                for (flag, v) in [
                    ("--radius", params.radius),
                    ("--height", params.height),
                    ("--minor-radius", params.minor_radius),
                ] {
                    if let Some(v) = v {
                        a.extend([flag.into(), v.to_string()]);
                    }
                }
            }
            Start::Model(_) => return None,
            Start::ModelFile { path, .. } => {
                a.extend(["--model".into(), path.display().to_string()]);
            }
        }
        if let Some(r) = self.regulation {
            a.extend(["--regulation".into(), r.name().into()]);
        }
        if let Some(f) = &self.finger {
            a.extend(["--finger".into(), f.clone()]);
        }
        if let Some(r) = self.finger_radius {
            a.extend(["--finger-radius".into(), r.to_string()]);
        }
        if !self.mirror.is_empty() {
            a.extend(["--mirror".into(), plane_list(&self.mirror)]);
        }
        if let Some(n) = self.radial {
            a.extend(["--radial".into(), n.to_string()]);
        }
        if self.lathe {
            a.push("--lathe".into());
        }
        if self.auto_refine {
            a.push("--auto-refine".into());
        }
        match self.filter {
            Some(f) if !f.enabled => a.push("--no-filter".into()),
            Some(f) if f != FilterSettings::default() => return None,
            _ => {}
        }
        Some(a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Several mirrors and a radial `N` (or the lathe) read back as written, and name the
    /// replay's options.
    #[test]
    fn a_scene_keeps_its_symmetry_group() {
        let mut s = Scene::primitive(Primitive::Tube, &PrimitiveParams::default()).unwrap();
        s.mirror = vec![Plane::X, Plane::Y];
        s.radial = Some(4);
        let text = s.to_text().unwrap();
        assert!(
            text.as_str().contains(r#""mirror":"x,y","radial":4,"#),
            "{}",
            text.as_str()
        );
        assert_eq!(Scene::parse(text.as_str()).unwrap(), s);
        let args = s.arguments().unwrap().join(" ");
        assert!(args.ends_with("--mirror x,y --radial 4"), "{args}");
        assert_eq!(
            s.symmetry().to_string(),
            "mirror x = 0, mirror y = 0, 4-fold about the z axis"
        );
        s.radial = None;
        s.lathe = true;
        let back = Scene::parse(s.to_text().unwrap().as_str()).unwrap();
        assert!(back.lathe && back.radial.is_none());
        assert!(
            s.arguments()
                .unwrap()
                .join(" ")
                .ends_with("--mirror x,y --lathe")
        );
    }

    #[test]
    fn a_scene_reads_back_what_it_writes() {
        let mut s = Scene::primitive(Primitive::Tube, &PrimitiveParams::default()).unwrap();
        s.regulation = Some(Regulation::G1);
        s.finger = Some("middle".into());
        s.finger_radius = Some(0.75);
        s.mirror = vec![Plane::Y];
        let text = s.to_text().unwrap();
        assert_eq!(
            text.as_str(),
            r#"{"regulation":"g1","finger":"middle","finger_radius":0.75,"mirror":"y","auto_refine":false,"primitive":{"name":"tube","patches":[16,8],"radius":2.0,"height":4.0}}"#
        );
        assert_eq!(Scene::parse(text.as_str()).unwrap(), s);
        assert_eq!(
            s.arguments().unwrap().join(" "),
            "--primitive tube --patches 16x8 --radius 2 --height 4 --regulation g1 --finger middle --finger-radius 0.75 --mirror y"
        );
        // An embedded model keeps every bit of its control points.
        let mut sphere = Model::new(
            Primitive::Sphere
                .build(&PrimitiveParams::default())
                .unwrap(),
        );
        let (a, b) = (sphere.surface.nodes()[20], sphere.surface.nodes()[21]);
        sphere
            .surface
            .set_nodes(&[
                (
                    20,
                    a + glam::DVec3::new(0.1 + 1e-12 * std::f64::consts::PI, 0.0, 0.0),
                ),
                (21, glam::DVec3::new(b.x, b.y, std::f64::consts::E / 3.0)),
            ])
            .unwrap();
        let w = Scene::of_window(&sphere, FingerModel::Ray, 1.25);
        let back = Scene::parse(w.to_text().unwrap().as_str()).unwrap();
        assert_eq!(back, w);
        let Start::Model(m) = back.start else {
            panic!("embedded")
        };
        assert_eq!(m.surface.nodes(), sphere.surface.nodes());
        assert_eq!(w.arguments(), None);
    }

    #[test]
    fn a_scene_carries_its_filter() {
        let mut s = Scene::primitive(Primitive::Plane, &PrimitiveParams::default()).unwrap();
        let mut f = FilterSettings::default();
        f.position.beta = 50.0;
        s.filter = Some(f);
        let text = s.to_text().unwrap();
        assert!(text.as_str().contains(r#""filter":{"enabled":true,"position":{"min_cutoff_hz":1.0,"beta":50.0,"d_cutoff_hz":1.0}"#), "{text}");
        assert_eq!(Scene::parse(text.as_str()).unwrap(), s);
        // The command line names only the defaults and no filter.
        assert_eq!(s.arguments(), None);
        s.filter = Some(FilterSettings::off());
        assert_eq!(
            s.arguments().unwrap().last().map(String::as_str),
            Some("--no-filter")
        );
        s.filter = Some(FilterSettings::default());
        assert_eq!(
            s.arguments().unwrap(),
            ["--primitive", "plane", "--patches", "10x10"]
        );
        // Members left out take their defaults; a bad value is refused with its name.
        let partial =
            Scene::parse(r#"{"filter":{"gate":{"hold_max_s":0.5}},"primitive":{"name":"plane"}}"#)
                .unwrap();
        assert_eq!(partial.filter.unwrap().gate.hold_max_s, 0.5);
        assert_eq!(
            partial.filter.unwrap().position,
            FilterSettings::default().position
        );
        let e = Scene::parse(r#"{"filter":{"joints":{"min_cutoff_hz":0.0,"beta":1.0,"d_cutoff_hz":1.0}},"primitive":{"name":"plane"}}"#)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "filter: filter.joints.min_cutoff_hz is 0; it must be a positive number"
        );
        assert!(
            Scene::parse(r#"{"filter":{"smooth":true},"primitive":{"name":"plane"}}"#).is_err()
        );
    }

    #[test]
    fn bad_scenes_are_refused_with_what_is_wrong() {
        for (text, says) in [
            (r#"{"auto_refine":false}"#, "names none"),
            (
                r#"{"primitive":{"name":"plane"},"model_file":{"path":"a","sha256":"0"}}"#,
                "primitive and model_file",
            ),
            (
                r#"{"primitive":{"name":"cube"}}"#,
                "unknown primitive \"cube\"",
            ),
            (
                r#"{"primitive":{"name":"sphere","radius":-1.0}}"#,
                "primitive sphere",
            ),
            (
                r#"{"primitive":{"name":"sphere","radius":1e999}}"#,
                "radius",
            ),
            (
                r#"{"primitive":{"name":"sphere"},"finger_radius":0.0}"#,
                "finger_radius: 0 is not a positive number",
            ),
            (r#"{"primitive":{"name":"sphere"},"mirror":"w"}"#, "\"w\""),
            (r#"{"primitive":{"name":"sphere"},"mirror":"x,w"}"#, "\"w\""),
            (r#"{"primitive":{"name":"tube"},"radial":1}"#, "radial: 1"),
            (
                r#"{"primitive":{"name":"tube"},"radial":4,"lathe":true}"#,
                "not with lathe",
            ),
            (r#"{"primitive":{"name":"sphere"},"regulation":"c9"}"#, "c9"),
            (
                r#"{"primitive":{"name":"sphere"},"fingers":"x"}"#,
                "fingers",
            ),
            (
                r#"{"model_file":{"path":"m.json","sha256":"ABC"}}"#,
                "not a SHA-256",
            ),
            (r#"{"model":{"format":"nendo-model"}}"#, "start model"),
        ] {
            let e = Scene::parse(text).map(|_| ()).unwrap_err().to_string();
            assert!(e.contains(says), "{text}: {e}");
        }
    }

    #[test]
    fn a_model_file_must_have_the_named_hash() {
        let dir = std::env::temp_dir().join(format!("nendo-scene-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let model = Model::new(Primitive::Plane.build(&PrimitiveParams::default()).unwrap());
        let text = model.to_json_string();
        std::fs::write(dir.join("m.json"), &text).unwrap();
        let good = sha256_hex(text.as_bytes());
        let s = Scene::new(Start::ModelFile {
            path: "m.json".into(),
            sha256: good.clone(),
        });
        assert_eq!(s.start_model(&dir).unwrap(), model);
        let wrong = "0".repeat(64);
        let s = Scene::new(Start::ModelFile {
            path: "m.json".into(),
            sha256: wrong.clone(),
        });
        let e = s.start_model(&dir).unwrap_err().to_string();
        assert!(e.contains(&good) && e.contains(&wrong), "{e}");
        // The SHA-256 of "abc" (FIPS 180-2, appendix B.1).
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
