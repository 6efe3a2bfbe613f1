//! How the patches of a grid connect (P2 §3, Fig. 2).
//!
//! A grid has `M` patches along `u` and `N` along `v`. A direction is *open* (the grid has a
//! boundary there) or *closed* (the last patch connects back to the first). A *pole* is a whole
//! boundary row of control points collapsed into one point, where all the patches of that row
//! meet (a degenerate point, 2n ≥ 6 patches).
//!
//! | topology | u | v | poles |
//! |---|---|---|---|
//! | plane | open | open | none |
//! | cylinder | closed | open | none |
//! | hemisphere | closed | open | one, at `v = 0` |
//! | sphere | closed | open | two, at `v = 0` and `v = N` |
//! | torus | closed | closed | none |
//!
//! Plane and hemisphere have the same shape topology (a disc) but different connection
//! topologies, as the paper notes.

use std::fmt;
use std::str::FromStr;

/// The connection topology of a patch grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Topology {
    /// Open × open.
    Plane,
    /// Closed along u, open along v.
    Cylinder,
    /// Closed along u, open along v, one pole at `v = 0`.
    Hemisphere,
    /// Closed along u, open along v, poles at `v = 0` and `v = N`.
    Sphere,
    /// Closed × closed.
    Torus,
}

impl Topology {
    /// Every topology.
    pub const ALL: [Topology; 5] = [
        Topology::Plane,
        Topology::Cylinder,
        Topology::Hemisphere,
        Topology::Sphere,
        Topology::Torus,
    ];

    /// The name used in files and on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Topology::Plane => "plane",
            Topology::Cylinder => "cylinder",
            Topology::Hemisphere => "hemisphere",
            Topology::Sphere => "sphere",
            Topology::Torus => "torus",
        }
    }

    /// True when the last patch along `u` connects back to the first.
    #[must_use]
    pub fn closed_u(self) -> bool {
        !matches!(self, Topology::Plane)
    }

    /// True when the last patch along `v` connects back to the first.
    #[must_use]
    pub fn closed_v(self) -> bool {
        matches!(self, Topology::Torus)
    }

    /// True when the control-point row `v = 0` is collapsed into a pole.
    #[must_use]
    pub fn pole_at_start(self) -> bool {
        matches!(self, Topology::Hemisphere | Topology::Sphere)
    }

    /// True when the control-point row `v = N` is collapsed into a pole.
    #[must_use]
    pub fn pole_at_end(self) -> bool {
        matches!(self, Topology::Sphere)
    }

    /// Number of poles (0, 1 or 2).
    #[must_use]
    pub fn pole_count(self) -> usize {
        usize::from(self.pole_at_start()) + usize::from(self.pole_at_end())
    }
}

impl fmt::Display for Topology {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The error of parsing a [`Topology`] name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown topology {0:?}: expected plane, cylinder, hemisphere, sphere or torus")]
pub struct UnknownTopology(pub String);

impl FromStr for Topology {
    type Err = UnknownTopology;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Topology::ALL
            .into_iter()
            .find(|t| t.name() == s)
            .ok_or_else(|| UnknownTopology(s.to_string()))
    }
}

/// `i` wrapped into `0..len` around a closed direction; `None` outside an open one.
pub(crate) fn wrap(i: isize, len: usize, closed: bool) -> Option<usize> {
    if closed {
        Some(i.rem_euclid(len as isize) as usize)
    } else if (0..len as isize).contains(&i) {
        Some(i as usize)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for t in Topology::ALL {
            assert_eq!(t.name().parse::<Topology>(), Ok(t));
        }
        assert!("cube".parse::<Topology>().is_err());
    }
}
