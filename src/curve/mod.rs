//! Curves: Bernstein forms, Bezier and B-spline curves in 2D and 3D, and the queries of SPEC §2
//! (closest point within a radius, picking among many curves, probe-sphere intervals, closest
//! point to a ray), all by Bezier clipping.
//!
//! Geometry only: this module uses nothing but glam and std.

mod any;
pub mod bernstein;
mod bezier;
mod bspline;
pub mod clip;
mod closest;
pub mod edit;
mod error;
pub mod json;
pub mod point;
pub mod refine;
mod ray;
mod sphere;
pub mod svg;
pub mod warp;

pub use any::{check_radius, pick, Curve, CurveSet, Picked};
pub use bezier::{Bezier, MAX_DEGREE};
pub use bspline::{BSpline, Segment};
pub use closest::{closest_bezier, closest_bezier_with_stats, ClipStats, Nearest};
pub use error::CurveError;
pub use point::{Coeff, Point};
pub use ray::{ray_closest_bezier, ray_closest_bezier_with_stats, RayNearest};
pub use sphere::{sphere_function, sphere_intervals_bezier};
