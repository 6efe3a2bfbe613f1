//! Curves: the geometry of [`nendo_geom::curve`] (re-exported here under the same names) and
//! the two file formats curves travel in — the JSON objects of the batch protocols and model
//! files ([`json`]) and SVG paths ([`svg`]) — and the cap on a warp's work ([`warp_work`]).

pub use nendo_geom::curve::*;

pub mod json;
pub mod svg;
pub mod warp_work;
