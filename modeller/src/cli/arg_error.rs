//! The typed error of the command line's own value parsers (`--size`, `--samples`,
//! `--background` and the like), which clap shows after "invalid value … for …".
//!
//! Only the parsers in this crate's subcommands use it; arguments clap parses itself (numbers,
//! enums) keep clap's messages.

use std::num::ParseIntError;

use crate::figure::FigureError;

/// Why a command-line value does not parse. Each message starts with the value as given
/// (quoted) and is complete on its own, so no variant exposes an inner error as a `source()`.
#[derive(Debug, thiserror::Error)]
pub enum ArgError {
    /// A size without the `x` between width and height.
    #[error("{value:?}: expected WIDTHxHEIGHT, e.g. {example}")]
    NotASize {
        /// The value as given.
        value: String,
        /// An example of a good value (the option's default).
        example: &'static str,
    },
    /// A width or height that is not a whole number.
    #[error("{value:?}: {error}")]
    NotAWholeNumber {
        /// The value as given.
        value: String,
        /// Why the number did not parse.
        error: ParseIntError,
    },
    /// A picture size that is out of range for a figure image.
    #[error("{0}")]
    ImageSize(FigureError),
    /// A render size whose width or height is not a whole number from 1 to 8192.
    #[error("{0:?}: width and height must be whole numbers from 1 to 8192")]
    RenderSize(String),
    /// A sample count other than 1 or 4.
    #[error("{0:?}: samples per pixel must be 1 or 4")]
    Samples(String),
    /// A colour that is not `#rrggbb`.
    #[error("{0:?}: expected a colour #rrggbb")]
    NotAColour(String),
    /// Patch counts without the `x` between them.
    #[error("{0:?}: expected MxN, e.g. 8x4")]
    NotCounts(String),
    /// A patch count that is not a whole number.
    #[error("{value:?}: {which} is not a count")]
    NotACount {
        /// The value as given.
        value: String,
        /// `M` or `N`.
        which: &'static str,
    },
    /// A name outside its set (primitive, regulation, finger).
    #[error("{0}")]
    Unknown(#[from] crate::surface::UnknownName),
    /// A finger that is neither a digit's name nor `ray`.
    #[error("{0}, or ray")]
    Finger(crate::surface::UnknownName),
}

/// `MxN` → `(M, N)`, the patch counts of `sculpt` and `replay`.
///
/// # Errors
/// [`ArgError::NotCounts`] without the `x`, [`ArgError::NotACount`] for a count that is not a
/// whole number.
pub fn parse_counts(s: &str) -> Result<(usize, usize), ArgError> {
    let (m, n) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| ArgError::NotCounts(s.to_owned()))?;
    let count = |v: &str, which| {
        v.trim().parse().map_err(|_| ArgError::NotACount {
            value: s.to_owned(),
            which,
        })
    };
    Ok((count(m, "M")?, count(n, "N")?))
}

/// A primitive's name (`plane`, `sphere`, …).
///
/// # Errors
/// [`ArgError::Unknown`].
pub fn parse_primitive(s: &str) -> Result<crate::surface::Primitive, ArgError> {
    Ok(s.parse()?)
}

/// A regulation method's name (`none`, `c1`, `g1`, `exact`, `default`, `g2`).
///
/// # Errors
/// [`ArgError::Unknown`].
pub fn parse_regulation(s: &str) -> Result<crate::surface::Regulation, ArgError> {
    Ok(s.parse()?)
}
