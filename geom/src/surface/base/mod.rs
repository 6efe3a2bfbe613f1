//! The bottom layer: limits, topology, boxes, errors, the patch evaluator, the plane fit and
//! generation marks — what every other part of the surface stands on. Uses nothing above it.

pub(crate) mod bounds;
pub(crate) mod error;
pub(crate) mod limits;
pub(crate) mod marks;
pub(crate) mod patch;
pub(crate) mod plane_fit;
pub(crate) mod topology;
