//! Errors of the figure part.

use thiserror::Error;

use crate::curve::CurveError;

/// Why a figure, a contour, a fit, a warp or a morph could not be built or carried out.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FigureError {
    /// A coordinate, radius, density or parameter is NaN or infinite.
    #[error("{what} is not a finite number")]
    NotFinite {
        /// Which value (e.g. "metacircle 3 radius").
        what: String,
    },
    /// A metacircle or metaball has a negative effective radius.
    #[error("{what} has a negative radius {}", crate::num::Compact(*.radius))]
    NegativeRadius {
        /// Which element.
        what: String,
        /// The radius found.
        radius: f64,
    },
    /// The iso-curve threshold must be positive (the region outside every support has density 0).
    #[error("the threshold must be a positive number, got {}", crate::num::Compact(*.0))]
    Threshold(f64),
    /// A closed contour needs at least three distinct vertices and a non-zero area.
    #[error("contour {what}: {reason}")]
    Contour {
        /// Which contour.
        what: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A document is malformed: a member missing, of the wrong type, or out of range.
    #[error("{0}")]
    Format(String),
    /// A document's JSON is malformed or a member is missing, unknown, repeated or of the
    /// wrong type (with the member's path, line and column). Transparent: the message is the
    /// JSON error's, once (a `{0}` message with the JSON error as its source printed it twice
    /// in a chain, `curves[0]: …: curves[0]: …`).
    #[error(transparent)]
    Json(#[from] crate::json_doc::JsonError),
    /// A curve inside a document is malformed.
    #[error("curve {index}: {source}")]
    Curve {
        /// Index of the curve in its list.
        index: usize,
        /// What is wrong with it.
        source: CurveError,
    },
    /// The curve warp refused its curves or parameters (e.g. a deformed curve on another
    /// parameter domain than its original).
    #[error("warp: {0}")]
    Warp(CurveError),
    /// A warp would carry so many points by so many curves that its work is over the cap
    /// ([`crate::curve::warp_work`]): refused before any work.
    #[error("{0}")]
    WarpTooLarge(#[from] crate::curve::warp_work::WarpTooLarge),
    /// Two lists that must correspond element by element differ in length (e.g. the curves laid
    /// over the source and over the destination of a morph).
    #[error("{what}: {left} against {right}")]
    Mismatch {
        /// What is being paired.
        what: String,
        /// Length of the first list.
        left: usize,
        /// Length of the second list.
        right: usize,
    },
    /// An option is out of its range (a frame count of zero, an image of zero pixels, …).
    #[error("{0}")]
    Option(String),
    /// The figure has nothing to fit, draw or morph (no metacircle, no sample).
    #[error("{0}")]
    Empty(String),
}
