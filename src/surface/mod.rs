//! Clay surfaces: grids of bicubic Bezier patches in five topologies, deformed by shape
//! functions through the Bernstein inverse and kept tangent-continuous (seed 002; SPEC §6–9).
//!
//! - [`Grid`]: `M × N` patches on one shared control net ([`grid`]), in a [`Topology`]
//!   (plane, cylinder, hemisphere, sphere, torus); [`Patch`] evaluates one patch.
//! - [`Primitive`]: the starting shapes ([`primitive`]).
//! - [`Group`] / [`Pole`]: the connected control-point groups regulation works on ([`group`]).
//!
//! Geometry only: this module uses nothing but glam, std and [`crate::curve`].

pub mod bounds;
pub mod error;
pub mod grid;
pub mod group;
pub mod patch;
pub mod primitive;
pub mod topology;

pub use bounds::Aabb;
pub use error::SurfaceError;
pub use grid::Grid;
pub use group::{Group, Pole, PoleEnd};
pub use patch::{Patch, PatchFrame, PatchPoints};
pub use primitive::{Ideal, Primitive, PrimitiveParams};
pub use topology::Topology;
