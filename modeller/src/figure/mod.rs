//! Figures in 2D made of metacircles, and shapes in 3D made of metaballs (P0 §4, docs/design.md §8).
//!
//! Geometry only: this module uses `curve`, `mesh` (the triangle mesh type its iso-surfaces are
//! returned in), glam and std; reading and writing files, and drawing meshes, is left to the
//! callers (the `nendo figure` and `nendo morph` subcommands).

mod contour;
pub mod document;
mod error;
pub mod falloff;
pub mod fit;
mod index;
pub mod iso;
pub mod marching;
pub mod medial;
mod metaball;
mod metacircle;
pub mod morph;
pub mod optimise;
pub mod picture;
pub mod raster;
pub mod section;
pub mod shape;
pub mod shape_document;
pub mod svg;
pub mod warp;

pub use contour::Contour;
pub use document::{FigureDocument, FilledPolygon};
pub use error::FigureError;
pub use fit::{FitOptions, FitReport, fit_contour, refit};
pub use index::CircleGrid;
pub use iso::{IsoLine, Lattice, iso_lines};
pub use metaball::{Metaball, Shape};
pub use metacircle::{Figure, Metacircle, Rgb};
pub use morph::{Morph, MorphOptions};
pub use picture::{Picture, PictureOptions, picture};
pub use raster::{Image, ImageSize, RasterStyle, RasterView};
pub use section::{CurveMove, Section};
pub use shape::{Deformed, ShapeFitOptions, ShapeFitReport, deform, fit_sections, refit_sections};
pub use shape_document::ShapeDocument;
