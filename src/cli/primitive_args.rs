//! The options that shape a primitive — `--patches MxN`, `--radius R`, `--height H`,
//! `--minor-radius r` — shared by `nendo sculpt`, `nendo replay` and `nendo record`, which each
//! name the primitive itself (`--primitive`) or a model instead (`--model`).

use clap::Args as ClapArgs;

use super::arg_error::parse_counts;
use crate::surface::PrimitiveParams;

/// `--patches`, `--radius`, `--height`, `--minor-radius`.
#[derive(Debug, Clone, Copy, Default, ClapArgs)]
pub struct ShapeArgs {
    /// Patch counts `MxN` of the primitive (M along u — around a closed direction —, N along v).
    #[arg(long, value_parser = clap::builder::ValueParser::new(parse_counts))]
    pub patches: Option<(usize, usize)>,
    /// Radius R in sides (major radius of a torus).
    #[arg(long, allow_hyphen_values = true)]
    pub radius: Option<f64>,
    /// Height H in sides (cylinder; the walls of the tube).
    #[arg(long, allow_hyphen_values = true)]
    pub height: Option<f64>,
    /// Minor radius r of a torus.
    #[arg(long, allow_hyphen_values = true)]
    pub minor_radius: Option<f64>,
}

impl ShapeArgs {
    /// Whether any of them was given.
    #[must_use]
    pub fn given(&self) -> bool {
        self.patches.is_some()
            || self.radius.is_some()
            || self.height.is_some()
            || self.minor_radius.is_some()
    }

    /// The primitive's parameters they give (the others left to the primitive's defaults).
    #[must_use]
    pub fn params(&self) -> PrimitiveParams {
        PrimitiveParams {
            patches: self.patches,
            radius: self.radius,
            height: self.height,
            minor_radius: self.minor_radius,
        }
    }

    /// The error for these options given with `--model`.
    #[must_use]
    pub fn not_for_a_model() -> anyhow::Error {
        anyhow::anyhow!(
            "--patches, --radius, --height and --minor-radius shape a primitive; they do not apply to --model"
        )
    }
}
