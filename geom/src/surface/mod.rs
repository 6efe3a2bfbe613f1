//! Clay surfaces: grids of bicubic Bezier patches in five topologies, deformed by shape
//! functions through the Bernstein inverse and kept tangent-continuous (seed 002; SPEC §6–9).
//!
//! - [`Grid`]: `M × N` patches on one shared control net ([`grid`]), in a [`Topology`]
//!   (plane, cylinder, hemisphere, sphere, torus); [`Patch`] evaluates one patch.
//! - [`Primitive`]: the starting shapes ([`primitive`]).
//! - [`Group`] / [`Pole`]: the connected control-point groups regulation works on ([`group`]).
//! - [`Op`] (push / pull / drag, along a direction or the normals; move; smooth) and its
//!   [`Finger`]: the shape functions ([`shape_fn`]); [`nearest`]: the surface point nearest a
//!   point; [`grab`]: the exact landing of a move; [`smooth`]: the thin-plate energy a
//!   smoothing stroke lowers; [`mirror`]: symmetry about `x = 0`, `y = 0` or `z = 0`.
//! - [`continuity::report`]: G0 gap, G1 angles along shared edges, pole spread ([`continuity`]).
//! - The deformation engine ([`engine`]): one pipeline — displacement field → reachable
//!   patches → envelope flows → Bernstein inverse ([`inverse`]) → [`Regulation`]
//!   ([`regulate`]) → mirror → [`verify()`] or an exact rollback — with two drivers:
//!   [`deform()`] / [`Sculptor`] apply one operation, returning what was [`Touched`];
//!   [`Presser`] applies the envelope of several finger [`Placement`]s (one contact of the
//!   hand) incrementally; the hand (`nendo::hand`) only builds placements.
//! - [`limits`]: how large a coordinate may grow ([`COORDINATE_LIMIT`]) and how much crease
//!   the exact regulation may leave ([`G1_TOLERANCE_DEG`]).
//! - [`Grid::patches_where`]: the patches whose boxes a geometric test accepts (contact queries).
//! - [`refine`]: more patches, the same surface (de Casteljau splits of whole patch columns /
//!   rows, uniform ×K, and the refinement a finger needs), spacing ratios carried over.
//! - [`deviation`]: distances between surfaces sample by sample, and to the ideal shape.
//!
//! Geometry only: this module uses nothing but glam, std and [`crate::curve`].

pub mod bounds;
pub mod continuity;
pub mod deviation;
pub mod engine;
pub mod error;
pub mod grab;
pub mod grid;
pub mod group;
pub mod inverse;
pub mod limits;
pub mod mirror;
pub mod nearest;
pub mod patch;
pub mod plane_fit;
pub mod primitive;
pub mod refine;
pub mod regulate;
pub mod shape_fn;
pub mod smooth;
pub mod topology;
pub mod verify;

pub use bounds::Aabb;
pub use continuity::{ContinuityReport, PoleReport};
pub use engine::{LiveOperation, Placement, Presser, Sculptor, Stroke, Touched, deform, describe};
pub use error::{SurfaceError, UnknownName};
pub use grab::Hold;
pub use grid::Grid;
pub use group::{Group, Pole, PoleEnd};
pub use limits::{COORDINATE_LIMIT, G1_TOLERANCE_DEG};
pub use mirror::{Asymmetry, MirrorError, Plane, Symmetry, is_symmetric, symmetry_error};
pub use nearest::{SurfacePoint, nearest};
pub use patch::{Patch, PatchFrame, PatchPoints};
pub use primitive::{Ideal, Primitive, PrimitiveParams, PrimitiveSize};
pub use refine::{FingerRefinement, RefineError, Refinement, for_finger};
pub use regulate::{Regulation, regulate_all};
pub use shape_fn::{Dirs, Finger, Op};
pub use smooth::{EnergyDrop, thin_plate_energy};
pub use topology::Topology;
pub use verify::verify;
