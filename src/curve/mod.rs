//! Curves: Bernstein forms, Bezier and B-spline curves in 2D and 3D, and the queries of SPEC §2
//! (closest point within a radius, picking among many curves, probe-sphere intervals, closest
//! point to a ray), all by Bezier clipping.
//!
//! Geometry only: this module uses nothing but glam and std.

pub mod bernstein;
pub mod point;

pub use point::{Coeff, Point};
