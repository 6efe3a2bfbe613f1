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

use crate::surface::bounds::Aabb;
use crate::surface::grid::Grid;
use crate::surface::group::PoleEnd;
use crate::surface::plane_fit::plane_normal;

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

/// Why a grid cannot be sculpted with a mirror.
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
}

/// A lattice index map along one direction: the identity or `a ↦ (c − a) mod len`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum LatticeMap {
    Identity,
    Reflect { c: usize, len: usize },
}

impl LatticeMap {
    #[inline]
    fn apply(self, a: usize) -> isize {
        match self {
            LatticeMap::Identity => a as isize,
            LatticeMap::Reflect { c, len } => (c as isize - a as isize).rem_euclid(len as isize),
        }
    }

    fn candidates(len: usize, closed: bool) -> Vec<LatticeMap> {
        let mut out = vec![LatticeMap::Identity];
        if closed {
            out.extend((0..len).step_by(3).map(|c| LatticeMap::Reflect { c, len }));
        } else {
            // a ↦ len − 1 − a.
            out.push(LatticeMap::Reflect {
                c: len - 1,
                len: len + 1,
            });
        }
        out
    }

    fn reverses(self) -> bool {
        self != LatticeMap::Identity
    }
}

/// The mirror map of a symmetric grid: each control point's partner, each patch's, each grid
/// vertex's. Made once per grid shape ([`Symmetry::of`]) and reused for every operation.
#[derive(Debug, Clone, PartialEq)]
pub struct Symmetry {
    plane: Plane,
    mu: LatticeMap,
    mv: LatticeMap,
    counts: (usize, usize),
    nodes: Vec<usize>,
    patches: Vec<usize>,
}

/// The error of candidate `(mu, mv)` on the nodes listed (all when `None`).
fn map_error(
    grid: &Grid,
    plane: Plane,
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
            let e = (plane.reflect(nodes[id]) - nodes[partner]).length();
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

fn best_map(grid: &Grid, plane: Plane) -> (LatticeMap, LatticeMap, Asymmetry) {
    let t = grid.topology();
    let (la, lb) = grid.lattice_size();
    let us = LatticeMap::candidates(la, t.closed_u());
    let vs = LatticeMap::candidates(lb, t.closed_v());
    let total = la * lb;
    let step = (total / 64).max(1);
    let mut ranked: Vec<(f64, LatticeMap, LatticeMap)> = Vec::new();
    for &mu in &us {
        for &mv in &vs {
            ranked.push((map_error(grid, plane, mu, mv, step).0, mu, mv));
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
        let (e, node) = map_error(grid, plane, mu, mv, 1);
        if e < best.2 {
            best = (mu, mv, e, node);
        }
    }
    (
        best.0,
        best.1,
        Asymmetry {
            plane,
            relative: best.2 / scale,
            node: best.3,
        },
    )
}

/// How far `grid` is from being symmetric about `plane` (see the module docs).
#[must_use]
pub fn symmetry_error(grid: &Grid, plane: Plane) -> Asymmetry {
    best_map(grid, plane).2
}

/// True when `grid` is symmetric about `plane` within [`SYMMETRY_TOLERANCE`] and its spacing
/// mirrors (a mirror can be used: [`Symmetry::of`] succeeds).
#[must_use]
pub fn is_symmetric(grid: &Grid, plane: Plane) -> bool {
    Symmetry::of(grid, plane).is_ok()
}

impl Symmetry {
    /// The mirror map of a grid symmetric about `plane`.
    ///
    /// # Errors
    /// [`MirrorError::NotSymmetric`] (with the worst node) beyond [`SYMMETRY_TOLERANCE`];
    /// [`MirrorError::Spacing`] when a reversed grid line's spacing ratio does not mirror.
    pub fn of(grid: &Grid, plane: Plane) -> Result<Symmetry, MirrorError> {
        let (mu, mv, asym) = best_map(grid, plane);
        if asym.relative.is_nan() || asym.relative > SYMMETRY_TOLERANCE {
            return Err(MirrorError::NotSymmetric(asym));
        }
        let (m, n) = (grid.patches_u(), grid.patches_v());
        let (la, lb) = grid.lattice_size();
        // Spacing: line k goes to line k' = mu(3k)/3; reversed, its ratio must invert.
        let ratio_check = |count: usize, map: LatticeMap, ratio: &dyn Fn(usize) -> f64| {
            for k in 0..count {
                let k2 = (map.apply(3 * k) / 3) as usize;
                let (r, r2) = (ratio(k), ratio(k2));
                let want = if map.reverses() { 1.0 / r } else { r };
                if (want - r2).abs() > 1e-9 * want.abs().max(1.0) {
                    return Err(MirrorError::Spacing {
                        plane,
                        ratio: r,
                        partner: r2,
                    });
                }
            }
            Ok(())
        };
        ratio_check(grid.vertices_u(), mu, &|k| grid.ratio_u(k))?;
        ratio_check(grid.vertices_v(), mv, &|q| grid.ratio_v(q))?;
        let mut nodes = vec![0usize; grid.nodes().len()];
        for b in 0..lb {
            for a in 0..la {
                if let (Some(id), Some(p)) = (
                    grid.node_id(a as isize, b as isize),
                    grid.node_id(mu.apply(a), mv.apply(b)),
                ) {
                    nodes[id] = p;
                }
            }
        }
        let patch_of = |map: LatticeMap, i: usize, count: usize, closed: bool| -> usize {
            match map {
                LatticeMap::Identity => i,
                // Columns 3i..3i+3 go to c − 3i − 3 .. c − 3i.
                LatticeMap::Reflect { c, .. } => {
                    let start = c as isize - 3 * i as isize - 3;
                    let p = start.div_euclid(3);
                    if closed {
                        p.rem_euclid(count as isize) as usize
                    } else {
                        p as usize
                    }
                }
            }
        };
        let t = grid.topology();
        let mut patches = vec![0usize; m * n];
        for iv in 0..n {
            for iu in 0..m {
                let pu = patch_of(mu, iu, m, t.closed_u());
                let pv = patch_of(mv, iv, n, t.closed_v());
                patches[iv * m + iu] = pv * m + pu;
            }
        }
        Ok(Symmetry {
            plane,
            mu,
            mv,
            counts: (m, n),
            nodes,
            patches,
        })
    }

    /// The mirror plane.
    #[must_use]
    pub fn plane(&self) -> Plane {
        self.plane
    }

    /// The partner of node `id`.
    #[must_use]
    pub fn node_partner(&self, id: usize) -> usize {
        self.nodes[id]
    }

    /// The partner of patch `p` (`iv * M + iu`).
    #[must_use]
    pub fn patch_partner(&self, p: usize) -> usize {
        self.patches[p]
    }

    /// The partner of grid vertex `(k, q)`.
    #[must_use]
    pub fn vertex_partner(&self, grid: &Grid, k: usize, q: usize) -> (usize, usize) {
        let wrap = |x: isize, len: usize| x.rem_euclid(len as isize) as usize;
        let (vu, vv) = (grid.vertices_u(), grid.vertices_v());
        (
            wrap(self.mu.apply(3 * k) / 3, vu),
            wrap(self.mv.apply(3 * q) / 3, vv),
        )
    }

    /// The partner of a pole.
    #[must_use]
    pub fn pole_partner(&self, end: PoleEnd) -> PoleEnd {
        match (self.mv.reverses(), end) {
            (false, e) => e,
            (true, PoleEnd::Start) => PoleEnd::End,
            (true, PoleEnd::End) => PoleEnd::Start,
        }
    }

    /// Whether this map was made for a grid of these counts.
    #[must_use]
    pub fn fits(&self, grid: &Grid) -> bool {
        self.counts == (grid.patches_u(), grid.patches_v())
            && self.nodes.len() == grid.nodes().len()
    }

    /// Makes the listed nodes and their partners exactly symmetric (see the module docs), and
    /// the listed poles and their partners' first rings (where the regulation keeps a tangent
    /// plane).
    ///
    /// # Errors
    /// [`MirrorError::OtherGrid`] when the map does not fit the grid.
    pub fn enforce(
        &self,
        grid: &mut Grid,
        ids: &[usize],
        poles: &[PoleEnd],
    ) -> Result<(), MirrorError> {
        if !self.fits(grid) {
            return Err(MirrorError::OtherGrid);
        }
        let plane = self.plane;
        let nodes = grid.nodes_mut();
        for &id in ids {
            let partner = self.nodes[id];
            if partner == id {
                nodes[id] = (nodes[id] + plane.reflect(nodes[id])) * 0.5;
            } else {
                let mean = (nodes[id] + plane.reflect(nodes[partner])) * 0.5;
                nodes[id] = mean;
                nodes[partner] = plane.reflect(mean);
            }
        }
        if !poles.is_empty() {
            self.enforce_poles(grid, poles);
        }
        Ok(())
    }

    /// Makes the whole grid exactly symmetric.
    ///
    /// # Errors
    /// [`MirrorError::OtherGrid`] when the map does not fit the grid.
    pub fn enforce_all(&self, grid: &mut Grid, poles: bool) -> Result<(), MirrorError> {
        let ids: Vec<usize> = (0..grid.nodes().len()).collect();
        let ends: Vec<PoleEnd> = if poles {
            grid.poles().iter().map(|p| p.end).collect()
        } else {
            Vec::new()
        };
        self.enforce(grid, &ids, &ends)?;
        let all: Vec<usize> = (0..grid.patch_count()).collect();
        grid.refit(&all, &mut Vec::new());
        Ok(())
    }

    fn enforce_poles(&self, grid: &mut Grid, listed: &[PoleEnd]) {
        let plane = self.plane;
        for pole in grid.poles() {
            let partner_end = self.pole_partner(pole.end);
            if !listed.contains(&pole.end) && !listed.contains(&partner_end) {
                continue;
            }
            if partner_end != pole.end && pole.end == PoleEnd::End {
                continue; // set from its partner
            }
            let o = grid.nodes()[pole.node];
            let Some(mut n) = plane_normal(pole.ring.iter().map(|&id| grid.nodes()[id] - o)) else {
                continue;
            };
            if partner_end == pole.end {
                // A symmetric plane: its normal in the mirror plane or along its axis.
                let mut a = n.to_array();
                let k = plane.axis();
                if a[k].abs() <= (1.0 - a[k] * a[k]).max(0.0).sqrt() {
                    a[k] = 0.0;
                } else {
                    a = [0.0; 3];
                    a[k] = 1.0;
                }
                let Some(sym) = DVec3::from_array(a).try_normalize() else {
                    continue;
                };
                n = sym;
            }
            let nodes = grid.nodes_mut();
            for &id in &pole.ring {
                nodes[id] -= n * n.dot(nodes[id] - o);
            }
            // Exact partners again.
            for &id in &pole.ring {
                let partner = self.nodes[id];
                if partner == id {
                    nodes[id] = (nodes[id] + plane.reflect(nodes[id])) * 0.5;
                } else if partner_end != pole.end || id < partner {
                    nodes[partner] = plane.reflect(nodes[id]);
                }
            }
            if partner_end != pole.end {
                let p = self.nodes[pole.node];
                nodes[p] = plane.reflect(nodes[pole.node]);
            }
        }
    }
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
