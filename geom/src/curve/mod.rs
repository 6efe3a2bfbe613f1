//! Curves: Bernstein forms, Bezier and B-spline curves in 2D and 3D, and the queries of docs/design.md §4
//! (closest point within a radius, picking among many curves, probe-sphere intervals, closest
//! point to a ray), all by Bezier clipping.
//!
//! Geometry only: this module uses glam, nalgebra (the refinement's least squares) and std; the
//! curve file formats (JSON, SVG) live in the `nendo` crate.

mod any;
pub mod bernstein;
mod bezier;
mod bspline;
pub mod clip;
mod closest;
pub mod edit;
mod error;

pub mod point;
mod ray;
pub mod refine;
mod sphere;

pub mod warp;

pub use any::{Curve, CurveSet, Picked, check_radius, pick};
pub use bezier::{Bezier, MAX_COORDINATE, MAX_DEGREE};
pub use bspline::{BSpline, Segment};
pub use closest::{ClipStats, Nearest, closest_bezier, closest_bezier_with_stats};
pub use error::CurveError;
pub use point::{Coeff, Point};
pub use ray::{RayNearest, ray_closest_bezier, ray_closest_bezier_with_stats};
pub use sphere::{sphere_function, sphere_intervals_bezier};
