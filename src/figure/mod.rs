//! Figures in 2D made of metacircles, and shapes in 3D made of metaballs (seed 000 §4, SPEC §4).
//!
//! Geometry only: this module uses `curve`, glam and std; reading and writing files is left to
//! the callers (the `nendo figure` and `nendo morph` subcommands).

mod contour;
pub mod document;
mod error;
pub mod falloff;
pub mod fit;
mod index;
pub mod iso;
pub mod medial;
mod metacircle;
pub mod morph;
pub mod optimise;
pub mod picture;
pub mod raster;
pub mod svg;
pub mod warp;

pub use contour::Contour;
pub use document::{FigureDocument, FilledPolygon};
pub use error::FigureError;
pub use fit::{FitOptions, FitReport, fit_contour, refit};
pub use index::CircleGrid;
pub use iso::{IsoLine, Lattice, iso_lines};
pub use metacircle::{Figure, Metacircle, Rgb};
pub use morph::{Morph, MorphOptions};
pub use picture::{Picture, PictureOptions, picture};
pub use raster::{Image, ImageSize, RasterStyle, View};
