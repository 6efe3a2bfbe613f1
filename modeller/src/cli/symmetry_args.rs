//! The symmetry options `nendo sculpt` and `nendo replay` share: `--mirror x,y` (mirrors
//! across coordinate planes, combinable: a comma list or the option repeated), `--radial N`
//! (`N`-fold about the z axis, the axis of every rotational primitive; `N` must divide the
//! patch columns around it — refused otherwise, not refined) and `--lathe` (every operation
//! applied all the way round: radial with `N` = the patch columns, the operation's field the
//! envelope of its copies turned every `2π / K`, `K` the least multiple of `N` ≥
//! [`crate::surface::LATHE_TURNS`]). Together they make one group
//! ([`crate::surface::Symmetry::group`]).

use clap::Args as ClapArgs;

use crate::surface::{Grid, Regulation, Symmetry, SymmetrySpec};

/// `--radial N` and `--lathe`.
#[derive(Debug, Clone, Copy, Default, ClapArgs)]
pub struct TurnArgs {
    /// Apply every operation together with its turns by 2π k / N about the z axis (N-fold
    /// radial symmetry; N must divide the patch columns around the axis). Combines with
    /// --mirror.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub radial: Option<u32>,
    /// Lathe: every operation applied all the way round the z axis (radial symmetry with N =
    /// the patch columns, the operation turned continuously). Combines with --mirror.
    #[arg(long, conflicts_with = "radial")]
    pub lathe: bool,
}

impl TurnArgs {
    /// Whether either option was given.
    #[must_use]
    pub fn given(&self) -> bool {
        self.radial.is_some() || self.lathe
    }

    /// The options as a group with the mirror planes `planes`.
    #[must_use]
    pub fn spec(&self, planes: &[crate::surface::Plane]) -> SymmetrySpec {
        let mut spec = SymmetrySpec {
            radial: self.radial.unwrap_or(0),
            lathe: self.lathe,
            ..SymmetrySpec::default()
        };
        for &p in planes {
            spec.add_plane(p);
        }
        spec
    }
}

/// The group `spec` on `grid`, made exact on it (`None` when `spec` asks for nothing).
///
/// # Errors
/// The model does not have the symmetry: the reason, naming the options.
pub fn symmetry_for(
    grid: &mut Grid,
    spec: &SymmetrySpec,
    regulation: Regulation,
) -> anyhow::Result<Option<Symmetry>> {
    if spec.is_none() {
        return Ok(None);
    }
    let flags = flags(spec);
    let s = Symmetry::group(grid, spec)
        .map_err(|e| anyhow::anyhow!("{flags}: {e}; nothing written"))?;
    s.enforce_all(grid, regulation != Regulation::None)
        .map_err(|e| anyhow::anyhow!("{flags}: {e}"))?;
    Ok(Some(s))
}

/// The command-line options that ask for `spec`.
#[must_use]
pub fn flags(spec: &SymmetrySpec) -> String {
    let mut parts = Vec::new();
    if !spec.planes.is_empty() {
        let names: Vec<&str> = spec.planes.iter().map(|p| p.name()).collect();
        parts.push(format!("--mirror {}", names.join(",")));
    }
    if spec.lathe {
        parts.push("--lathe".to_string());
    } else if spec.radial > 1 {
        parts.push(format!("--radial {}", spec.radial));
    }
    parts.join(" ")
}
