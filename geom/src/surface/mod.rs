//! Clay surfaces: grids of bicubic Bezier patches in five topologies, deformed by shape
//! functions through the Bernstein inverse and kept tangent-continuous (P2; docs/design.md §9–§14).
//!
//! - [`Grid`]: `M × N` patches on one shared control net ([`grid`]), in a [`Topology`]
//!   (plane, cylinder, hemisphere, sphere, torus); [`Patch`] evaluates one patch.
//! - [`Primitive`]: the starting shapes ([`primitive`]).
//! - [`Group`] / [`Pole`]: the connected control-point groups regulation works on ([`group`]).
//! - [`Op`] (push / pull / drag, along a direction or the normals; move; smooth) and its
//!   [`Finger`]: the shape functions ([`shape_fn`]); [`nearest`]: the surface point nearest a
//!   point; [`grab`]: the exact landing of a move; [`fairing`]: the smoothing dab (implicit
//!   fairing of the surface under the brush); [`smooth`]: the thin-plate energy a smoothing
//!   dab must lower; [`mirror`]: symmetry about `x = 0`, `y = 0` or `z = 0`, radial about the z axis, and groups of them.
//! - [`continuity::report`]: G0 gap, G1 angles along shared edges, pole spread ([`continuity`]);
//!   [`curvature::g2_report`]: the curvature mismatch (G2) across every seam and at poles.
//! - The deformation engine ([`engine`]): one pipeline — displacement field → reachable
//!   patches → envelope flows → Bernstein inverse ([`inverse`]) → [`Regulation`]
//!   ([`regulate`]) → mirror → [`verify()`] or an exact rollback — with two drivers:
//!   [`deform()`] / [`Sculptor`] apply one operation, returning what was [`Touched`];
//!   [`Presser`] applies the envelope of several finger [`Placement`]s (one contact of the
//!   hand) incrementally; the hand (`nendo::hand`) only builds placements.
//! - [`limits`]: how large a coordinate may grow ([`COORDINATE_LIMIT`]) and how much crease
//!   the exact regulation may leave ([`G1_TOLERANCE_DEG`]).
//! - [`Grid::patches_where`]: the patches whose boxes a geometric test accepts (contact queries).
//! - [`Grid::one_spline`]: the whole grid as one bicubic B-spline surface with double interior
//!   knots spaced by the patch widths, exact for a grid the `exact` regulation keeps ([`spline`]).
//! - [`refine`]: more patches, the same surface (de Casteljau splits of whole patch columns /
//!   rows, uniform ×K, and the refinement a finger needs), spacing ratios carried over.
//! - [`deviation`]: distances between surfaces sample by sample, and to the ideal shape.
//!
//! ## Layers
//!
//! The folders are the layers, each using only those below it (`.ci/checks/layers.sh` holds
//! them):
//!
//! | folder | what it holds |
//! |---|---|
//! | `base/` | limits, topology, boxes, errors, the patch evaluator ([`Patch`], also the mesher's), the plane fit, generation marks |
//! | `net/` | the grid and its control net, groups and poles, the primitives |
//! | `constraint/` | regulation, verification, continuity, mirror symmetry |
//! | `operation/` | shape functions, nearest point, the landing of a move, smoothing, the Bernstein inverse, refinement, deviation |
//! | `engine/` | the pipeline every deformation runs through, and its drivers |
//!
//! The modules are private; what the rest of the workspace uses is re-exported below, and the
//! namespaces with many items ([`continuity`], [`regulate`], [`refine`], [`deviation`],
//! [`inverse`], [`engine`]) are public as modules.
//!
//! Geometry only: this module uses nothing but glam, std and [`crate::curve`].

mod base;
mod constraint;
pub mod engine;
mod net;
mod operation;

// Every module by its own name inside the crate (`crate::surface::grid`, …).
pub(crate) use base::{bounds, error, limits, marks, patch, plane_fit, topology};
pub(crate) use constraint::{mirror, verify, verify_g2};
pub(crate) use net::{grid, group, primitive, ratio_check, spline};
pub(crate) use operation::{grab, nearest, shape_fn, smooth};
// The namespaces the workspace uses as modules.
pub use constraint::{continuity, curvature, regulate, shape_operator};
pub use operation::{brush, deviation, fairing, inverse, refine, sculpt_brush};

pub use bounds::Aabb;
pub use brush::{Brush, Falloff};
pub use continuity::{ContinuityReport, PoleReport};
pub use engine::{LiveOperation, Placement, Presser, Sculptor, Stroke, Touched, deform, describe};
pub use error::{SurfaceError, UnknownName};
pub use sculpt_brush::{SculptBrush, SculptKind};

pub use constraint::isometry::Isometry;
pub use grab::Hold;
pub use grid::Grid;
pub use group::{Group, Pole, PoleEnd};
pub use limits::{COORDINATE_LIMIT, G1_TOLERANCE_DEG, G2_FLAT, G2_TOLERANCE, MAX_PATCHES};
pub use mirror::{
    Asymmetry, LATHE_TURNS, MirrorError, Plane, SYMMETRY_TOLERANCE, Symmetry, SymmetrySpec,
    group_error, is_symmetric, symmetry_error,
};
pub use nearest::{SurfacePoint, nearest};
pub use patch::{Patch, PatchFrame, PatchPoints};
pub use primitive::{Ideal, Primitive, PrimitiveParams, PrimitiveSize};
pub use ratio_check::{RATIO_TOLERANCE, RatioMismatch};
pub use refine::{FingerRefinement, RefineError, Refinement, for_finger};
pub use regulate::{Regulation, regulate_all};
pub use shape_fn::{Dirs, Finger, Op};
pub use smooth::{EnergyDrop, thin_plate_energy};
pub use spline::{GridSpline, NotOneSpline, ONE_SPLINE_TOLERANCE};
pub use topology::{Topology, UnknownTopology};
pub use verify::verify;
