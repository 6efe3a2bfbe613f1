//! The `nendo-model` JSON document: one surface and any number of curves — the contract
//! between nendo's tools, its window and its tests.
//!
//! ```json
//! {"format": "nendo-model", "version": 1,
//!  "surface": {"topology": "sphere", "patches_u": 8, "patches_v": 4,
//!              "regulation": "exact",
//!              "ratios": {"u": [1, …], "v": [1, …]},
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
//! - `curves` (optional, default empty) in the JSON form of [`crate::curve::json`].
//!
//! Reading validates everything and says where a problem is. Writing is atomic: the document
//! goes to a temporary file in the same directory, which is flushed and then renamed over the
//! target, so a reader never sees half a file.

pub mod ops;

use serde_json::{Map, Value, json};
use std::fs;
use std::path::{Path, PathBuf};

use crate::curve::CurveError;
use crate::curve::json::{DynCurve, curve_from_json, dyn_curve_to_json};
use crate::surface::{Grid, Regulation, SurfaceError, Topology};

/// The `format` member of every model file.
pub const FORMAT: &str = "nendo-model";
/// The version this build reads and writes.
pub const VERSION: u64 = 1;
/// Largest model file read: 512 MB, several times the largest grid
/// ([`crate::surface::grid::MAX_PATCHES`] patches of 16 points).
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
    /// The text is not JSON.
    #[error("not valid JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// The JSON does not have the shape of a model (a member missing or of the wrong type).
    #[error("{0}")]
    Format(String),
    /// The file is another format or version.
    #[error("{0}")]
    Version(String),
    /// The surface's counts, numbers or shared points are invalid.
    #[error("surface: {0}")]
    Surface(#[from] SurfaceError),
    /// A curve is invalid.
    #[error("curves[{index}]: {source}")]
    Curve {
        /// Which curve.
        index: usize,
        /// Why.
        source: CurveError,
    },
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

/// A JSON error made clearer where the text holds a number JSON cannot carry (`NaN`,
/// `Infinity`, or a literal too large for a double): model coordinates must be finite.
fn non_finite_hint(text: &str, e: serde_json::Error) -> ModelError {
    let (line, column) = (e.line(), e.column());
    let at = text
        .lines()
        .nth(line.saturating_sub(1))
        .and_then(|l| l.get(column.saturating_sub(1)..))
        .unwrap_or("");
    let bad = ["NaN", "-NaN", "Infinity", "-Infinity", "inf", "-inf", "nan"]
        .iter()
        .find(|t| at.starts_with(**t));
    if let Some(token) = bad {
        ModelError::Format(format!(
            "line {line} column {column}: {token} is not a finite number (every coordinate must be finite)"
        ))
    } else if e.to_string().contains("number out of range") {
        ModelError::Format(format!(
            "line {line} column {column}: a number is out of range (every coordinate must be a finite double)"
        ))
    } else {
        ModelError::Json(e)
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
        json!({
            "format": FORMAT,
            "version": VERSION,
            "surface": {
                "topology": g.topology().name(),
                "patches_u": g.patches_u(),
                "patches_v": g.patches_v(),
                "regulation": self.regulation.name(),
                "ratios": {"u": g.ratios_u(), "v": g.ratios_v()},
                "patches": patches,
            },
            "curves": self.curves.iter().map(dyn_curve_to_json).collect::<Vec<_>>(),
        })
    }

    /// The document as compact JSON text.
    #[must_use]
    pub fn to_json_string(&self) -> String {
        self.to_json().to_string()
    }

    /// Reads a model from JSON text.
    ///
    /// # Errors
    /// Any [`ModelError`] but `Io`, saying where the problem is.
    pub fn from_json_str(text: &str) -> Result<Loaded, ModelError> {
        let v: Value = serde_json::from_str(text).map_err(|e| non_finite_hint(text, e))?;
        Self::from_json(&v)
    }

    /// Reads a model from a parsed JSON document.
    ///
    /// # Errors
    /// Any [`ModelError`] but `Io` and `Json`.
    pub fn from_json(v: &Value) -> Result<Loaded, ModelError> {
        let top = object(v, "the document")?;
        match top.get("format").and_then(Value::as_str) {
            Some(FORMAT) => {}
            Some(other) => {
                return Err(ModelError::Version(format!(
                    "format is {other:?}, expected {FORMAT:?}"
                )));
            }
            None => {
                return Err(ModelError::Version(format!(
                    "no \"format\": {FORMAT:?} member; not a nendo model"
                )));
            }
        }
        match top.get("version").map(|x| (x, x.as_u64())) {
            Some((_, Some(VERSION))) => {}
            Some((x, _)) => {
                return Err(ModelError::Version(format!(
                    "version {x} is not supported (this build reads {VERSION})"
                )));
            }
            None => return Err(ModelError::Format("missing \"version\"".into())),
        }
        let s = object(member(top, "surface", "the document")?, "surface")?;
        let topology: Topology = member(s, "topology", "surface")?
            .as_str()
            .ok_or_else(|| ModelError::Format("surface.topology must be a string".into()))?
            .parse()
            .map_err(|e: crate::surface::topology::UnknownTopology| {
                ModelError::Format(format!("surface.topology: {e}"))
            })?;
        let count = |name: &str| -> Result<usize, ModelError> {
            member(s, name, "surface")?
                .as_u64()
                .and_then(|c| usize::try_from(c).ok())
                .ok_or_else(|| {
                    ModelError::Format(format!("surface.{name} must be a non-negative integer"))
                })
        };
        let (m, n) = (count("patches_u")?, count("patches_v")?);
        Grid::check_counts(topology, m, n)?;
        let regulation = match s.get("regulation") {
            None => Regulation::default(),
            Some(r) => r
                .as_str()
                .ok_or_else(|| ModelError::Format("surface.regulation must be a string".into()))?
                .parse()
                .map_err(|e: String| ModelError::Format(format!("surface.regulation: {e}")))?,
        };
        let list = member(s, "patches", "surface")?.as_array().ok_or_else(|| {
            ModelError::Format("surface.patches must be an array of patches".into())
        })?;
        if list.len() != m * n {
            return Err(ModelError::Format(format!(
                "surface.patches has {} patches; a {m} x {n} grid needs {}",
                list.len(),
                m * n
            )));
        }
        let mut patches = Vec::with_capacity(list.len());
        let mut extent = 1.0f64;
        for (pi, p) in list.iter().enumerate() {
            let pts = p.as_array().filter(|a| a.len() == 16).ok_or_else(|| {
                ModelError::Format(format!(
                    "surface.patches[{pi}] must be an array of 16 points [x, y, z]"
                ))
            })?;
            let mut out = [glam::DVec3::ZERO; 16];
            for (k, x) in pts.iter().enumerate() {
                let c = x.as_array().filter(|c| c.len() == 3).ok_or_else(|| {
                    ModelError::Format(format!(
                        "surface.patches[{pi}][{k}] must be a point [x, y, z]"
                    ))
                })?;
                let mut xyz = [0.0; 3];
                for (d, cv) in c.iter().enumerate() {
                    let f = cv.as_f64().ok_or_else(|| {
                        ModelError::Format(format!(
                            "surface.patches[{pi}][{k}][{d}] is not a number"
                        ))
                    })?;
                    if !f.is_finite() {
                        return Err(SurfaceError::NotFinite {
                            patch: pi,
                            point: k,
                        }
                        .into());
                    }
                    xyz[d] = f;
                    extent = extent.max(f.abs());
                }
                out[k] = glam::DVec3::from_array(xyz);
            }
            patches.push(out);
        }
        let (mut surface, seam_gap) =
            Grid::from_patches(topology, m, n, &patches, SHARED_POINT_TOLERANCE * extent)?;
        if let Some(r) = s.get("ratios") {
            let list = |name: &str| -> Result<Vec<f64>, ModelError> {
                r.get(name)
                    .and_then(Value::as_array)
                    .and_then(|a| a.iter().map(Value::as_f64).collect::<Option<Vec<f64>>>())
                    .ok_or_else(|| {
                        ModelError::Format(format!(
                            "surface.ratios.{name} must be an array of numbers"
                        ))
                    })
            };
            surface.set_ratios(&list("u")?, &list("v")?)?;
        }
        let curves = match top.get("curves") {
            None => Vec::new(),
            Some(c) => c
                .as_array()
                .ok_or_else(|| ModelError::Format("curves must be an array".into()))?
                .iter()
                .enumerate()
                .map(|(index, c)| {
                    curve_from_json(c).map_err(|source| ModelError::Curve { index, source })
                })
                .collect::<Result<_, _>>()?,
        };
        Ok(Loaded {
            model: Model {
                surface,
                regulation,
                curves,
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

fn object<'a>(v: &'a Value, what: &str) -> Result<&'a Map<String, Value>, ModelError> {
    v.as_object()
        .ok_or_else(|| ModelError::Format(format!("{what} must be a JSON object")))
}

fn member<'a>(o: &'a Map<String, Value>, name: &str, what: &str) -> Result<&'a Value, ModelError> {
    o.get(name)
        .ok_or_else(|| ModelError::Format(format!("{what} has no \"{name}\"")))
}
