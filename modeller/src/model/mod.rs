//! The `nendo-model` JSON document: one surface and any number of curves — the contract
//! between nendo's tools, its window and its tests.
//!
//! ```json
//! {"format": "nendo-model", "version": 1,
//!  "surface": {"topology": "sphere", "patches_u": 8, "patches_v": 4,
//!              "regulation": "exact",
//!              "ratios": {"u": [1, …], "v": [1, …]},
//!              "refined": {"u": [1, 3], "v": []},
//!              "patches": [[[x, y, z], … 16 points …], …]},
//!  "curves": [{"bezier": [[x, y, z], …]}, {"bspline": {"degree": 3, "knots": […], "points": […]}}]}
//! ```
//!
//! - `patches[iv * patches_u + iu]` holds patch `(iu, iv)`'s control points `P[4*i + j]`, `i`
//!   along `u`, `j` along `v` (see [`crate::surface::grid`]). In memory the shared control net
//!   is the truth; the file repeats shared points per patch for interoperability, and reading
//!   merges them back, checking that every copy of a shared point (common edges, closed seams,
//!   poles) coincides to within [`SHARED_POINT_TOLERANCE`] times the model's size.
//! - `regulation` (optional, default the default method) is how the surface is regulated
//!   when it is sculpted.
//! - `ratios` (optional) are the reference spacing ratios of the grid lines (one per grid
//!   vertex along u and along v; see [`crate::surface::grid`]), saved so that regulation after
//!   reading behaves exactly as before writing; without them they are measured from the net.
//!   A saved ratio of a line whose rows of control points share one ratio must be that ratio
//!   within [`crate::surface::RATIO_TOLERANCE`] (`1e-7` relative), or the file is refused
//!   naming the line and both values ([`crate::surface::Grid::ratio_mismatch`]).
//! - `refined` (optional) lists the grid lines refinement made (u and v grid vertex indices,
//!   as for `ratios`; see [`crate::surface::Grid::refined_u`]): the window draws them fainter
//!   than the primitive's own lines. Written only when there is one; a file without it reads
//!   as all lines the primitive's own. An index past the grid lines is refused, naming it.
//! - `curves` (optional, default empty) in the JSON form of [`crate::curve::json`].
//! - `autosave` (optional) marks the window's autosave file ([`crate::editor::autosave`]);
//!   reading a model passes over it.
//!
//! Reading is strict and says where a problem is: the text is deserialized straight into typed
//! structures (serde derive, no intermediate JSON tree, so a model of 65 536 patches costs its
//! text and the patches), an unknown member (a misspelled `"curvs"`) or a repeated one (two
//! `"surface"` members) is refused, and every error names the member's path and position
//! (`surface.patches[3][7]: ... (line 40 column 9)`; see [`crate::json_doc`]). A document of
//! another `format` or `version` is named as such. Then counts, shared points and ratios are
//! validated. Writing is atomic: the document
//! goes to a temporary file in the same directory, which is flushed and then renamed over the
//! target, so a reader never sees half a file.

pub mod ops;

use serde::de::Error as _;
use serde::{Deserialize, Deserializer};
use serde_json::{Value, json};
use std::fs;
use std::path::{Path, PathBuf};

use crate::curve::json::{DynCurve, dyn_curve_to_json};
use crate::json_doc::{self, JsonError};
use crate::surface::{Grid, Regulation, SurfaceError, Topology};

/// The `format` member of every model file.
pub const FORMAT: &str = "nendo-model";
/// The version this build reads and writes.
pub const VERSION: u64 = 1;
/// Largest model file read: 512 MB, several times the largest grid
/// ([`crate::surface::MAX_PATCHES`] patches of 16 points).
pub const MAX_FILE_BYTES: u64 = 512 << 20;
/// Copies of a shared point may differ by this much relative to the model's size (1 or the
/// largest coordinate, whichever is larger).
pub const SHARED_POINT_TOLERANCE: f64 = 1e-9;

/// What can go wrong reading or writing a model.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The file could not be read or written.
    #[error("{}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error (named in the message, so not also chained as a source:
        /// printing the chain would repeat it).
        error: std::io::Error,
    },
    /// The text is not JSON, or a member is missing, unknown, repeated or of the wrong type
    /// (with the member's path, line and column), or a curve is invalid.
    #[error("{0}")]
    Json(#[from] JsonError),
    /// The document's parts do not fit together (a patch count against the grid) or the file
    /// is too large.
    #[error("{0}")]
    Format(String),
    /// The file is another format or version.
    #[error("{0}")]
    Version(String),
    /// The surface's counts, numbers or shared points are invalid.
    #[error("surface: {0}")]
    Surface(#[from] SurfaceError),
}

impl ModelError {
    /// The message for a user who asked for `path`: errors that do not already name the file
    /// are prefixed with it.
    #[must_use]
    pub fn in_file(&self, path: &Path) -> String {
        match self {
            ModelError::Io { .. } => self.to_string(),
            _ => format!("{}: {self}", path.display()),
        }
    }
}

/// The document as read: every member typed, unknown and repeated members refused.
#[derive(Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a nendo-model document (a JSON object)"
)]
struct ModelDoc {
    format: String,
    version: u64,
    surface: SurfaceDoc,
    #[serde(default)]
    curves: Vec<DynCurve>,
    /// The autosave header (see [`crate::editor::autosave`]): read past, a model either way.
    #[serde(default, rename = "autosave")]
    _autosave: Option<serde::de::IgnoredAny>,
}

/// The `surface` member as read.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a surface object")]
struct SurfaceDoc {
    #[serde(deserialize_with = "topology")]
    topology: Topology,
    patches_u: usize,
    patches_v: usize,
    #[serde(default, deserialize_with = "regulation")]
    regulation: Option<Regulation>,
    #[serde(default)]
    ratios: Option<RatiosDoc>,
    #[serde(default)]
    refined: Option<RefinedDoc>,
    patches: Vec<[[f64; 3]; 16]>,
}

/// The `surface.refined` member as read: indices of the grid lines refinement made.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RefinedDoc {
    #[serde(default)]
    u: Vec<usize>,
    #[serde(default)]
    v: Vec<usize>,
}

/// The indices of the marked lines.
fn marked(marks: &[bool]) -> Vec<usize> {
    marks
        .iter()
        .enumerate()
        .filter_map(|(k, m)| m.then_some(k))
        .collect()
}

/// Marks from indices: one per line of `count`; an index past them is an error naming it.
fn marks(indices: &[usize], count: usize, direction: &str) -> Result<Vec<bool>, ModelError> {
    let mut out = vec![false; count];
    for (i, &k) in indices.iter().enumerate() {
        let Some(m) = out.get_mut(k) else {
            return Err(ModelError::Format(format!(
                "surface.refined.{direction}[{i}]: grid line {k} does not exist (the grid has {count} {direction} lines, 0 to {})",
                count.saturating_sub(1)
            )));
        };
        *m = true;
    }
    Ok(out)
}

/// The `surface.ratios` member as read.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RatiosDoc {
    u: Vec<f64>,
    v: Vec<f64>,
}

/// Only `format` and `version`, any other member ignored: what a document that failed to read
/// says it is, so that another format or version is named as such.
#[derive(Deserialize)]
struct Header {
    #[serde(default)]
    format: Option<Value>,
    #[serde(default)]
    version: Option<Value>,
}

fn topology<'de, D: Deserializer<'de>>(d: D) -> Result<Topology, D::Error> {
    let name = String::deserialize(d)?;
    name.parse()
        .map_err(|e: crate::surface::UnknownTopology| D::Error::custom(e))
}

fn regulation<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Regulation>, D::Error> {
    let name = String::deserialize(d)?;
    name.parse().map(Some).map_err(D::Error::custom)
}

/// Checks `format` and `version` (either may be missing).
fn check_header(format: Option<&Value>, version: Option<&Value>) -> Result<(), ModelError> {
    match format.map(|f| (f, f.as_str())) {
        Some((_, Some(FORMAT))) => {}
        Some((_, Some(other))) => {
            return Err(ModelError::Version(format!(
                "format is {other:?}, expected {FORMAT:?}"
            )));
        }
        Some((f, None)) => {
            return Err(ModelError::Version(format!(
                "format is {f}, expected {FORMAT:?}"
            )));
        }
        None => {
            return Err(ModelError::Version(format!(
                "no \"format\": {FORMAT:?} member; not a nendo model"
            )));
        }
    }
    match version.map(|x| (x, x.as_u64())) {
        Some((_, Some(VERSION))) | None => Ok(()),
        Some((x, _)) => Err(ModelError::Version(format!(
            "version {x} is not supported (this build reads {VERSION})"
        ))),
    }
}

/// The error for a document that is not a JSON object.
fn not_an_object() -> ModelError {
    JsonError::at("", "a nendo-model document must be a JSON object").into()
}

/// A document that failed to read: named as another format or version if its header says
/// so, else the error as found.
fn explain(header: Result<Header, JsonError>, error: JsonError) -> ModelError {
    match header {
        Ok(h) => match check_header(h.format.as_ref(), h.version.as_ref()) {
            Err(e) => e,
            Ok(()) => error.into(),
        },
        Err(_) => error.into(),
    }
}

/// A model: the surface, how it is regulated, and the curves.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    /// The surface.
    pub surface: Grid,
    /// How the surface is regulated when sculpted.
    pub regulation: Regulation,
    /// The curves.
    pub curves: Vec<DynCurve>,
}

/// A model read from text, with what reading found.
#[derive(Debug, Clone, PartialEq)]
pub struct Loaded {
    /// The model.
    pub model: Model,
    /// The largest distance between two copies of one shared point in the file (side).
    pub seam_gap: f64,
}

impl Model {
    /// A model holding only a surface, with the default regulation.
    #[must_use]
    pub fn new(surface: Grid) -> Self {
        Self {
            surface,
            regulation: Regulation::default(),
            curves: Vec::new(),
        }
    }

    /// The JSON document.
    #[must_use]
    pub fn to_json(&self) -> Value {
        let g = &self.surface;
        let patches: Vec<Value> = (0..g.patch_count())
            .map(|p| {
                Value::Array(
                    g.patch_at(p)
                        .iter()
                        .map(|x| json!([x.x, x.y, x.z]))
                        .collect(),
                )
            })
            .collect();
        let mut surface = json!({
            "topology": g.topology().name(),
            "patches_u": g.patches_u(),
            "patches_v": g.patches_v(),
            "regulation": self.regulation.name(),
            "ratios": {"u": g.ratios_u(), "v": g.ratios_v()},
        });
        let (ru, rv) = (marked(g.refined_u()), marked(g.refined_v()));
        if !(ru.is_empty() && rv.is_empty()) {
            surface["refined"] = json!({"u": ru, "v": rv});
        }
        surface["patches"] = Value::Array(patches);
        json!({
            "format": FORMAT,
            "version": VERSION,
            "surface": surface,
            "curves": self.curves.iter().map(dyn_curve_to_json).collect::<Vec<_>>(),
        })
    }

    /// The document as compact JSON text.
    #[must_use]
    pub fn to_json_string(&self) -> String {
        self.to_json().to_string()
    }

    /// Reads a model from JSON text, without building a JSON tree (a big model costs its
    /// text and the patches).
    ///
    /// # Errors
    /// Any [`ModelError`] but `Io`, saying where the problem is: [`ModelError::Json`] names
    /// the member's path, line and column.
    pub fn from_json_str(text: &str) -> Result<Loaded, ModelError> {
        // serde reads a struct from an array too: the document itself must be an object.
        let object = text.trim_start().starts_with('{');
        match json_doc::from_str::<ModelDoc>(text) {
            Err(JsonError::Bom) => Err(JsonError::Bom.into()),
            _ if !object => Err(not_an_object()),
            Ok(doc) => Self::from_doc(doc),
            Err(e) => Err(explain(json_doc::from_str::<Header>(text), e)),
        }
    }

    /// Reads a model from a parsed JSON document.
    ///
    /// # Errors
    /// Any [`ModelError`] but `Io`.
    pub fn from_json(v: &Value) -> Result<Loaded, ModelError> {
        if !v.is_object() {
            return Err(not_an_object());
        }
        match json_doc::from_value::<ModelDoc>(v) {
            Ok(doc) => Self::from_doc(doc),
            Err(e) => Err(explain(json_doc::from_value::<Header>(v), e)),
        }
    }

    /// The model of a document read well-formed: header, counts, shared points and ratios
    /// checked.
    fn from_doc(doc: ModelDoc) -> Result<Loaded, ModelError> {
        let version = Value::from(doc.version);
        check_header(Some(&Value::from(doc.format)), Some(&version))?;
        let s = doc.surface;
        let (m, n) = (s.patches_u, s.patches_v);
        Grid::check_counts(s.topology, m, n)?;
        if s.patches.len() != m * n {
            return Err(ModelError::Format(format!(
                "surface.patches has {} patches; a {m} x {n} grid needs {}",
                s.patches.len(),
                m * n
            )));
        }
        let mut extent = 1.0f64;
        // Converted in place (same layout), so the patches are held once.
        let patches = s
            .patches
            .into_iter()
            .enumerate()
            .map(|(pi, p)| {
                let mut out = [glam::DVec3::ZERO; 16];
                for (k, xyz) in p.iter().enumerate() {
                    // serde_json reads only finite numbers; a value from elsewhere may not be.
                    if xyz.iter().any(|f| !f.is_finite()) {
                        return Err(SurfaceError::NotFinite {
                            patch: pi,
                            point: k,
                        });
                    }
                    extent = xyz.iter().fold(extent, |e, f| e.max(f.abs()));
                    out[k] = glam::DVec3::from_array(*xyz);
                }
                Ok(out)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let (mut surface, seam_gap) =
            Grid::from_patches(s.topology, m, n, &patches, SHARED_POINT_TOLERANCE * extent)?;
        if let Some(r) = s.ratios {
            surface.set_ratios(&r.u, &r.v)?;
            // Saved ratios that are not the points' own would make every exact push near the
            // line fail for a reason nobody sees (see `crate::surface::ratio_check`).
            if let Some(m) = surface.ratio_mismatch(crate::surface::RATIO_TOLERANCE) {
                return Err(ModelError::Format(format!(
                    "surface.ratios.{}[{}]: the saved spacing ratio {} of {} grid line {} is not the ratio of its control points, {} (they differ by more than {} relative): the file was edited or its ratios rounded; write the ratio its points have, or remove \"ratios\" to measure every one from the points",
                    m.direction,
                    m.line,
                    m.saved,
                    m.direction,
                    m.line,
                    m.measured,
                    crate::surface::RATIO_TOLERANCE
                )));
            }
        }
        if let Some(r) = s.refined {
            let u = marks(&r.u, surface.vertices_u(), "u")?;
            let v = marks(&r.v, surface.vertices_v(), "v")?;
            surface.set_refined(&u, &v)?;
        }
        Ok(Loaded {
            model: Model {
                surface,
                regulation: s.regulation.unwrap_or_default(),
                curves: doc.curves,
            },
            seam_gap,
        })
    }

    /// Reads a model file.
    ///
    /// # Errors
    /// [`ModelError::Io`] when the file cannot be read; otherwise as [`Model::from_json_str`].
    pub fn read(path: &Path) -> Result<Loaded, ModelError> {
        use std::io::Read;
        let io = |error| ModelError::Io {
            path: path.to_path_buf(),
            error,
        };
        // Read at most one byte past the limit, so a device or a runaway file is refused
        // without reading it all.
        let mut text = String::new();
        fs::File::open(path)
            .and_then(|f| f.take(MAX_FILE_BYTES + 1).read_to_string(&mut text))
            .map_err(io)?;
        if text.len() as u64 > MAX_FILE_BYTES {
            return Err(ModelError::Format(format!(
                "larger than {} MB; not a model this build reads",
                MAX_FILE_BYTES >> 20
            )));
        }
        Self::from_json_str(&text)
    }

    /// Writes the model with the one safe writer ([`nendo_file`]): atomically, through a
    /// symbolic link to its file, keeping the replaced file's permissions.
    ///
    /// A model with a non-finite coordinate is refused before anything is written (a last
    /// guard: such a file could not be read back).
    ///
    /// # Errors
    /// [`ModelError::Surface`] ([`SurfaceError::NotFinite`], naming the first bad patch and
    /// control point) or [`ModelError::Io`]; the target is then untouched.
    pub fn write(&self, path: &Path) -> Result<(), ModelError> {
        if let Some((patch, point)) = first_non_finite(&self.surface) {
            return Err(ModelError::Surface(SurfaceError::NotFinite {
                patch,
                point,
            }));
        }
        write_atomically(path, self.to_json_string().as_bytes())
    }
}

/// The first patch and control point (`4 i + j`) of `grid` with a NaN or infinite coordinate.
#[must_use]
pub fn first_non_finite(grid: &Grid) -> Option<(usize, usize)> {
    if grid.nodes().iter().all(|p| p.is_finite()) {
        return None;
    }
    (0..grid.patch_count()).find_map(|patch| {
        grid.patch_at(patch)
            .iter()
            .position(|p| !p.is_finite())
            .map(|point| (patch, point))
    })
}

/// Writes `bytes` to `path` with the one safe writer ([`nendo_file::write_bytes`]).
///
/// # Errors
/// [`ModelError::Io`] naming `path`; the target is then untouched and no temporary is left.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), ModelError> {
    nendo_file::write_bytes(path, bytes).map_err(|e| ModelError::Io {
        path: path.to_path_buf(),
        error: e.into_io(),
    })
}
