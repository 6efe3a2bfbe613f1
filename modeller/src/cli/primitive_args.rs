//! The options that shape a primitive — `--patches MxN`, `--radius R`, `--height H`,
//! `--minor-radius r` — shared by `nendo sculpt`, `nendo replay` and `nendo record`, which each
//! name the primitive itself (`--primitive`) or a model instead (`--model`).
//!
//! A size option that does not shape the chosen primitive (`--height` with a sphere, see
//! [`Primitive::uses`]) is refused rather than ignored: [`ShapeArgs::check_applies`].

use clap::Args as ClapArgs;

use super::arg_error::parse_counts;
use crate::surface::{Primitive, PrimitiveParams, PrimitiveSize};

/// A size option given with a primitive it does not shape.
#[derive(Debug, thiserror::Error)]
#[error("{option} applies to {applies}, not {primitive}")]
pub struct NotForPrimitive {
    /// The option as written (`--height`).
    pub option: &'static str,
    /// The primitives it shapes, as a list (`cylinder and tube`).
    pub applies: String,
    /// The primitive chosen.
    pub primitive: Primitive,
}

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

    /// Refuses a size option that does not shape `primitive` (`--height` with a sphere,
    /// `--minor-radius` with a plane) instead of ignoring it.
    ///
    /// # Errors
    /// [`NotForPrimitive`] for the first such option (in the order radius, height, minor
    /// radius).
    pub fn check_applies(&self, primitive: Primitive) -> Result<(), NotForPrimitive> {
        for (option, size, given) in [
            ("--radius", PrimitiveSize::Radius, self.radius.is_some()),
            ("--height", PrimitiveSize::Height, self.height.is_some()),
            (
                "--minor-radius",
                PrimitiveSize::MinorRadius,
                self.minor_radius.is_some(),
            ),
        ] {
            if given && !primitive.uses(size) {
                let names: Vec<&str> = Primitive::ALL
                    .into_iter()
                    .filter(|p| p.uses(size))
                    .map(Primitive::name)
                    .collect();
                let applies = match names.split_last() {
                    Some((last, rest)) if !rest.is_empty() => {
                        format!("{} and {last}", rest.join(", "))
                    }
                    _ => names.concat(),
                };
                return Err(NotForPrimitive {
                    option,
                    applies,
                    primitive,
                });
            }
        }
        Ok(())
    }

    /// The error for these options given with `--model`.
    #[must_use]
    pub fn not_for_a_model() -> anyhow::Error {
        anyhow::anyhow!(
            "--patches, --radius, --height and --minor-radius shape a primitive; they do not apply to --model"
        )
    }
}
