//! The control net: the grid of patches on one shared net, its connected control-point groups and
//! poles, the primitives. Uses only [`super::base`]'s parts.

pub(crate) mod grid;
pub(crate) mod group;
pub(crate) mod primitive;
pub(crate) mod ratio_check;
pub(crate) mod spline;
