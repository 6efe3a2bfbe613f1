//! Regulation: restoring tangent continuity after the per-patch Bernstein inverse
//! (seed 002 §4; SPEC §8).
//!
//! The inverse mapping moves every patch on its own; C0 holds (the net is shared) but the
//! rows of control points that cross a grid line are no longer collinear, so the surface
//! creases along patch edges. Regulation works on the connected control-point groups
//! ([`super::group`]) around the grid vertices the operation touched, one group at a time
//! (groups are disjoint, and every tangent-continuity condition lies inside one group).

use super::grid::Grid;
use super::group::PoleEnd;

/// How control points are regulated after the inverse mapping.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Regulation {
    /// The Bernstein inverse alone: C0, no tangent continuity.
    #[default]
    None,
}

impl Regulation {
    /// Every method.
    pub const ALL: [Regulation; 1] = [Regulation::None];

    /// The name used on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Regulation::None => "none",
        }
    }
}

impl std::fmt::Display for Regulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Regulation {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Regulation::ALL
            .into_iter()
            .find(|r| r.name() == s)
            .ok_or_else(|| format!("unknown regulation {s:?}: expected none"))
    }
}

/// Regulates the groups around the grid vertices `(k, q)` and the poles listed; returns how
/// many groups and poles were worked on.
pub(crate) fn regulate(
    grid: &mut Grid,
    method: Regulation,
    vertices: &[(usize, usize)],
    poles: &[PoleEnd],
) -> usize {
    match method {
        Regulation::None => {
            let _ = (grid, vertices, poles);
            0
        }
    }
}
