//! Constraints and measures on the net: regulation (G1 by the paper's methods and by projection),
//! verification of an operation's result, continuity measures (G1 and, in [`curvature`], G2;
//! the curvatures of the surface itself in [`shape_operator`]),
//! symmetry groups (mirrors and turns about the z axis). Uses the net and
//! the base, nothing of the operations or the engine.

pub mod continuity;
pub mod curvature;
pub mod isometry;
pub(crate) mod mirror;
pub mod regulate;
pub mod shape_operator;
mod symmetry;
pub(crate) mod verify;
pub(crate) mod verify_g2;
