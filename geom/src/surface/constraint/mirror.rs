//! Mirror symmetry across a coordinate plane `x = 0`, `y = 0` or `z = 0`.
//!
//! The reflection `R` negates one coordinate (exactly, in floating point). A grid is
//! symmetric about the plane when a permutation `σ` of its control points satisfies
//! `x_σ(n) = R x_n` for every node `n`: every control point's mirror image is a control point.
//! `σ` is looked for among the maps of the control lattice that keep its structure — along
//! each direction the identity or a reflection `a ↦ c − a` (wrapping around a closed
//! direction, `c` a multiple of 3 so that grid lines go to grid lines; `a ↦ 3M − a` on an open
//! one) — as the candidate with the smallest error
//!
//! ```text
//! asymmetry = max_n |R x_n − x_σ(n)| / max_n |x_n|.
//! ```
//!
//! Every primitive is symmetric about `x = 0` and `y = 0` (the closed direction runs around
//! the z axis starting on the x axis: `φ ↦ π − φ` and `φ ↦ −φ` are lattice reflections for an
//! even `M`), to rounding (≈ 10⁻¹⁶).
//!
//! **Enforcing** ([`Symmetry::enforce`]): each pair of partners is replaced by the mean
//! `x'_n = (x_n + R x_σ(n)) / 2`, `x'_σ(n) = R x'_n` (a point that is its own partner is put
//! on the plane). The G1 conditions of the exact regulation are linear within each group, and
//! `σ` maps groups to groups with the same spacing ratios (checked: a reversed direction
//! must have `ρ_σ = 1/ρ`), so the mean of two nets that satisfy them satisfies them. A pole's
//! tangent plane is not linear: after the mean, the first ring of a pole is projected onto the
//! fitted plane through the pole (an affine map, which keeps the ring's ratio conditions),
//! the plane's normal made symmetric first when the pole is its own partner, and the partner
//! pole's ring set to the exact mirror image otherwise.

use glam::DVec3;

pub use super::symmetry::{Symmetry, group_error};
use crate::surface::bounds::Aabb;
use crate::surface::grid::Grid;

use super::isometry::Isometry;

/// The largest [`asymmetry`](Asymmetry::relative) a model may have to be sculpted with a
/// mirror: 10⁻⁹ of its size (the primitives are symmetric to ≈ 10⁻¹⁶).
pub const SYMMETRY_TOLERANCE: f64 = 1e-9;

/// A mirror plane through the origin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Plane {
    /// `x = 0`.
    X,
    /// `y = 0`.
    Y,
    /// `z = 0`.
    Z,
}

impl Plane {
    /// Every plane.
    pub const ALL: [Plane; 3] = [Plane::X, Plane::Y, Plane::Z];

    /// The coordinate the reflection negates (0, 1, 2).
    #[must_use]
    pub fn axis(self) -> usize {
        match self {
            Plane::X => 0,
            Plane::Y => 1,
            Plane::Z => 2,
        }
    }

    /// The name on the command line: `x`, `y`, `z`.
    #[must_use]
    pub fn name(self) -> &'static str {
        ["x", "y", "z"][self.axis()]
    }

    /// `R v`: `v` with one coordinate negated (exact).
    #[inline]
    #[must_use]
    pub fn reflect(self, v: DVec3) -> DVec3 {
        let mut a = v.to_array();
        a[self.axis()] = -a[self.axis()];
        DVec3::from_array(a)
    }

    /// The mirror image of a box.
    #[must_use]
    pub fn reflect_box(self, b: &Aabb) -> Aabb {
        let (mut lo, mut hi) = (b.min.to_array(), b.max.to_array());
        let k = self.axis();
        (lo[k], hi[k]) = (-hi[k], -lo[k]);
        Aabb {
            min: DVec3::from_array(lo),
            max: DVec3::from_array(hi),
        }
    }
}

impl std::fmt::Display for Plane {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} = 0", self.name())
    }
}

impl std::str::FromStr for Plane {
    type Err = crate::surface::error::UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Plane::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| crate::surface::error::UnknownName {
                kind: "mirror plane",
                given: s.to_owned(),
                expected: "x, y, z",
            })
    }
}

/// How far a grid is from being symmetric about a plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Asymmetry {
    /// The plane.
    pub plane: Plane,
    /// `max_n |R x_n − x_σ(n)| / max_n |x_n|` for the best lattice map `σ`.
    pub relative: f64,
    /// The node where it is largest.
    pub node: usize,
}

/// Why a grid cannot be sculpted with a symmetry.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum MirrorError {
    /// The grid is not symmetric about the plane.
    #[error(
        "the model is not symmetric about the plane {}: control point {} is {:.3e} of the model's size from the mirror image of its partner (tolerance {:.0e})",
        .0.plane, .0.node, .0.relative, SYMMETRY_TOLERANCE
    )]
    NotSymmetric(Asymmetry),
    /// The mirror map reverses a grid line whose spacing ratio does not mirror.
    #[error(
        "the model's grid line spacing is not symmetric about the plane {plane} (ratio {} against {}): the regulation would break the symmetry",
        crate::num::Compact(*.ratio),
        crate::num::Compact(*.partner)
    )]
    Spacing {
        /// The plane.
        plane: Plane,
        /// A line's reference spacing ratio.
        ratio: f64,
        /// Its partner's.
        partner: f64,
    },
    /// The symmetry was found for a grid of other counts.
    #[error("the mirror map was made for a grid of other patch counts")]
    OtherGrid,
    /// Radial symmetry needs a grid closed around the z axis.
    #[error(
        "radial symmetry needs a model that closes around the z axis (a cylinder, tube, hemisphere, sphere or torus)"
    )]
    NotRotational,
    /// `N` does not divide the patch columns around the axis.
    #[error(
        "{n}-fold radial symmetry needs a number of patch columns around the axis divisible by {n}; the model has {columns}"
    )]
    Columns {
        /// The `N` asked for.
        n: u32,
        /// The patch columns around the axis.
        columns: usize,
    },
    /// The grid is not invariant under the turn by `2π / N` about the z axis.
    #[error(
        "the model is not {n}-fold symmetric about the z axis: control point {node} is {relative:.3e} of the model's size from the turned image of its partner (tolerance {:.0e})",
        SYMMETRY_TOLERANCE
    )]
    NotRadial {
        /// The `N` asked for.
        n: u32,
        /// The worst relative distance.
        relative: f64,
        /// The node where it is largest.
        node: usize,
    },
    /// The turn by `2π / N` maps a grid line to one of another spacing ratio.
    #[error(
        "the model's grid line spacing is not {n}-fold symmetric about the z axis: the regulation would break the symmetry"
    )]
    RadialSpacing {
        /// The `N` asked for.
        n: u32,
    },
}

/// The symmetry a model is sculpted with: any of the three coordinate mirrors, and an
/// `N`-fold turn about the z axis (the axis of every rotational primitive); together they
/// generate the group kept (see [`Symmetry`]).
#[derive(Debug, Clone, Default, PartialEq, Eq, Hash)]
pub struct SymmetrySpec {
    /// The mirror planes (sorted, each once).
    pub planes: Vec<Plane>,
    /// `N` of the radial symmetry (0 or 1: none).
    pub radial: u32,
    /// Lathe: every operation applied all the way round. The group is the radial symmetry
    /// with `N` = the patch columns around the axis (when `radial` is not given: a group made
    /// for a lathe keeps its `N` in `radial`, so a refined grid keeps the same group), and the displacement field the envelope
    /// of the operation turned by every `2π / K`, `K` = the smallest multiple of `N` that is
    /// at least [`LATHE_TURNS`].
    pub lathe: bool,
}

/// The least number of turned copies of an operation a lathe stroke applies (every 3.75°).
pub const LATHE_TURNS: u32 = 96;

impl SymmetrySpec {
    /// The mirror across one plane.
    #[must_use]
    pub fn mirror(plane: Plane) -> Self {
        Self {
            planes: vec![plane],
            ..Self::default()
        }
    }

    /// Nothing to keep.
    #[must_use]
    pub fn is_none(&self) -> bool {
        self.planes.is_empty() && self.radial <= 1 && !self.lathe
    }

    /// With `plane` added (kept sorted, each once).
    pub fn add_plane(&mut self, plane: Plane) {
        if !self.planes.contains(&plane) {
            self.planes.push(plane);
            self.planes.sort_by_key(|p| p.axis());
        }
    }
}

impl std::fmt::Display for SymmetrySpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut parts: Vec<String> = self.planes.iter().map(|p| format!("mirror {p}")).collect();
        if self.lathe && self.radial > 1 {
            parts.push(format!("lathe about the z axis ({}-fold)", self.radial));
        } else if self.lathe {
            parts.push("lathe about the z axis".to_string());
        } else if self.radial > 1 {
            parts.push(format!("{}-fold about the z axis", self.radial));
        }
        if parts.is_empty() {
            write!(f, "none")
        } else {
            write!(f, "{}", parts.join(", "))
        }
    }
}

/// A lattice index map along one direction: the identity, `a ↦ (a + s) mod len` or
/// `a ↦ (c − a) mod len`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum LatticeMap {
    Identity,
    Shift { s: usize, len: usize },
    Reflect { c: usize, len: usize },
}

impl LatticeMap {
    #[inline]
    pub(super) fn apply(self, a: usize) -> isize {
        match self {
            LatticeMap::Identity => a as isize,
            LatticeMap::Shift { s, len } => ((a + s) % len) as isize,
            LatticeMap::Reflect { c, len } => (c as isize - a as isize).rem_euclid(len as isize),
        }
    }

    fn candidates(len: usize, closed: bool, turns: bool) -> Vec<LatticeMap> {
        let mut out = vec![LatticeMap::Identity];
        if closed {
            out.extend((0..len).step_by(3).map(|c| LatticeMap::Reflect { c, len }));
            if turns {
                out.extend((3..len).step_by(3).map(|s| LatticeMap::Shift { s, len }));
            }
        } else {
            // a ↦ len − 1 − a.
            out.push(LatticeMap::Reflect {
                c: len - 1,
                len: len + 1,
            });
        }
        out
    }

    pub(super) fn reverses(self) -> bool {
        matches!(self, LatticeMap::Reflect { .. })
    }

    /// The map on a global grid parameter `T ∈ [0, count]` (lattice index `3T`).
    pub(super) fn parameter(self, t: f64, count: usize, closed: bool) -> f64 {
        let r = match self {
            LatticeMap::Identity => return t,
            LatticeMap::Shift { s, .. } => t + s as f64 / 3.0,
            LatticeMap::Reflect { c, .. } => c as f64 / 3.0 - t,
        };
        if closed {
            r.rem_euclid(count as f64)
        } else {
            r
        }
    }
}

/// The error of candidate `(mu, mv)` on the nodes listed (every `step`-th).
fn map_error(
    grid: &Grid,
    iso: &Isometry,
    mu: LatticeMap,
    mv: LatticeMap,
    step: usize,
) -> (f64, usize) {
    let (la, lb) = grid.lattice_size();
    let nodes = grid.nodes();
    let mut worst = (0.0f64, 0usize);
    let mut k = 0usize;
    for b in 0..lb {
        for a in 0..la {
            k += 1;
            if step > 1 && !k.is_multiple_of(step) {
                continue;
            }
            let (Some(id), Some(partner)) = (
                grid.node_id(a as isize, b as isize),
                grid.node_id(mu.apply(a), mv.apply(b)),
            ) else {
                return (f64::INFINITY, 0);
            };
            let e = (iso.apply(nodes[id]) - nodes[partner]).length();
            if e.is_nan() {
                return (f64::INFINITY, id);
            }
            if e > worst.0 {
                worst = (e, id);
            }
        }
    }
    worst
}

/// The best lattice maps for `iso` and the relative error with its worst node.
pub(super) fn best_map(grid: &Grid, iso: &Isometry) -> (LatticeMap, LatticeMap, f64, usize) {
    let t = grid.topology();
    let (la, lb) = grid.lattice_size();
    // A turn, or the half turn that the mirrors across x and y make together, shifts the
    // closed direction.
    let [fx, fy, _] = iso.flips();
    let us = LatticeMap::candidates(la, t.closed_u(), iso.turns() || (fx && fy));
    let vs = LatticeMap::candidates(lb, t.closed_v(), false);
    let total = la * lb;
    let step = (total / 64).max(1);
    let mut ranked: Vec<(f64, LatticeMap, LatticeMap)> = Vec::new();
    for &mu in &us {
        for &mv in &vs {
            ranked.push((map_error(grid, iso, mu, mv, step).0, mu, mv));
        }
    }
    ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
    let scale = grid
        .nodes()
        .iter()
        .map(|x| x.length())
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut best = (LatticeMap::Identity, LatticeMap::Identity, f64::INFINITY, 0);
    for &(_, mu, mv) in ranked.iter().take(4) {
        let (e, node) = map_error(grid, iso, mu, mv, 1);
        if e < best.2 {
            best = (mu, mv, e, node);
        }
    }
    (best.0, best.1, best.2 / scale, best.3)
}

/// How far `grid` is from being symmetric about `plane` (see the module docs).
#[must_use]
pub fn symmetry_error(grid: &Grid, plane: Plane) -> Asymmetry {
    let (_, _, relative, node) = best_map(grid, &Isometry::reflection(plane.axis()));
    Asymmetry {
        plane,
        relative,
        node,
    }
}

/// True when `grid` is symmetric about `plane` within [`SYMMETRY_TOLERANCE`] and its spacing
/// mirrors (a mirror can be used: [`Symmetry::of`] succeeds).
#[must_use]
pub fn is_symmetric(grid: &Grid, plane: Plane) -> bool {
    Symmetry::of(grid, plane).is_ok()
}

/// Whether every spacing ratio goes to an equal one under `map` (its inverse where the map
/// reverses the direction).
pub(super) fn spacing_maps(
    count: usize,
    map: LatticeMap,
    ratio: &dyn Fn(usize) -> f64,
) -> Result<(), (f64, f64)> {
    for k in 0..count {
        let k2 = (map.apply(3 * k) / 3) as usize;
        let (r, r2) = (ratio(k), ratio(k2));
        let want = if map.reverses() { 1.0 / r } else { r };
        if (want - r2).abs() > 1e-9 * want.abs().max(1.0) {
            return Err((r, r2));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Primitive, PrimitiveParams};

    #[test]
    fn every_primitive_is_symmetric_about_x_and_y() {
        for p in Primitive::ALL {
            let grid = p.build(&PrimitiveParams::default()).unwrap();
            for plane in [Plane::X, Plane::Y] {
                let a = symmetry_error(&grid, plane);
                assert!(a.relative < 1e-14, "{p} {plane}: {a:?}");
                let s = Symmetry::of(&grid, plane).unwrap();
                for id in 0..grid.nodes().len() {
                    let q = s.node_partner(id);
                    assert_eq!(s.node_partner(q), id, "{p} {plane}");
                }
                for pi in 0..grid.patch_count() {
                    let q = s.patch_partner(pi);
                    // The partner patch holds the partners of the patch's nodes.
                    let m = grid.patches_u();
                    let mine = grid.patch_node_ids(pi % m, pi / m);
                    let theirs = grid.patch_node_ids(q % m, q / m);
                    for id in mine {
                        assert!(theirs.contains(&s.node_partner(id)), "{p} {plane} {pi}");
                    }
                }
            }
        }
    }

    #[test]
    fn an_off_centre_model_is_refused_with_its_worst_point() {
        let grid = Primitive::Sphere
            .build(&PrimitiveParams::default())
            .unwrap();
        let mut nodes = grid.nodes().to_vec();
        nodes[5].x += 0.01;
        let moved =
            Grid::from_net(grid.topology(), grid.patches_u(), grid.patches_v(), nodes).unwrap();
        let e = Symmetry::of(&moved, Plane::X).unwrap_err();
        assert!(
            matches!(e, MirrorError::NotSymmetric(a) if a.relative > 1e-3),
            "{e}"
        );
        assert!(e.to_string().contains("x = 0"), "{e}");
    }
}
