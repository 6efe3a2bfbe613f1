//! Grab and move, exactly: the surface analogue of the curves' exact grab (docs/design.md §5; P0
//! §3, P4 §3(2)).
//!
//! `{"op":"move","at":A,"to":T,"radius":r_f}` takes the surface point nearest `A`,
//! `S* = S_p(u*, v*)` ([`crate::surface::nearest`]), and
//!
//! 1. **spreads** the movement `δ₀ = T − S*` with the shape functions' falloff: every sample
//!    within `r_f` of `S*` moves by `(1 − r²/r_f²)·δ₀` (a ball-shaped finger), through the
//!    Bernstein inverse and the regulation like any operation ([`crate::surface::engine`]);
//! 2. **lands exactly**: the regulation leaves a residual `δ = T − S(u*, v*)`. The control
//!    points of patch `p` belong to the (up to four) groups at its corners ([`crate::surface::group`];
//!    at a pole, to the pole group: the pole and its whole first ring) — group `g` owns the
//!    points `P_ij` with `i ∈ I_g`, `j ∈ J_g` (`{0, 1}` next to the vertex at the patch's
//!    start, `{2, 3}` at its end). Translating a whole group by `t_g` moves `S(u*, v*)` by
//!    `w_g t_g` with `w_g = Σ_{i∈I_g, j∈J_g} B_i(u*) B_j(v*)` (and `Σ_g w_g = 1`), and keeps
//!    every G1 condition: they are linear with coefficients summing to zero within a group
//!    (`ρ P₋ − (1 + ρ) P₀ + P₊ = 0`; a pole ring in a plane through the pole). The
//!    minimum-norm translations that remove the residual are
//!
//!    ```text
//!    t_g = w_g δ / Σ_h w_h²
//!    ```
//!
//!    — the curve grab's `ΔP_i = B_i(t) δ / Σ B_k(t)²` with the groups as the control points.
//!    Local (the groups of one patch, so nothing beyond the regulated ring moves) and exact to
//!    rounding; applied twice to absorb the rounding of the first.
//!
//! With a mirror ([`crate::surface::mirror`]) the translations are kept symmetric: a group and its
//! partner move by `t` and `R t`. Per coordinate (`R` is diagonal) the weights of a group and
//! its partner add (with a sign along the mirror axis), and a group that is its own partner
//! cannot move along the mirror axis: a grabbed point on the mirror plane stays on it (the
//! target's coordinate across the plane is then not reached). Likewise, when the grabbed
//! patch's groups and their mirror images overlap (a grab within about a patch of the plane)
//! and their weights across the plane nearly cancel (`Σ c² <` [`MIN_WEIGHT`]), the point is
//! not pulled across the plane (the translation would grow without bound): it lands exactly
//! along the plane's two other axes only.
//!
//! With a group of mirrors and turns ([`Symmetry`]) the same holds with matrices: the orbit
//! of a group `r` (its images `h r`, `h` in the symmetry group `G`) moves by `h P_r t_r`,
//! `P_r = (1/|G_r|) Σ_{s ∈ G_r} s` the projector onto the translations the stabiliser `G_r`
//! of `r` keeps. The surface point moves by `Σ_r A_r t_r`, `A_r = Σ_{h r ∋ patch} w_{hr} H P_r`,
//! and the minimum-norm translations are `t_r = A_rᵀ (Σ_s A_s A_sᵀ)⁺ δ`, the pseudo-inverse
//! dropping directions of eigenvalue below [`MIN_WEIGHT`] (the point is not pulled where the
//! symmetry holds it, e.g. off the axis at a pole a turn keeps).

// Per-coordinate and per-slot loops index several small fixed arrays at once; the index
// form follows the formulas.
#![allow(clippy::needless_range_loop)]

use glam::{DMat3, DVec3};

use crate::surface::grid::Grid;
use crate::surface::group::PoleEnd;
use crate::surface::mirror::Symmetry;
use crate::surface::patch::cubic_basis;

/// Smallest sum of squared group weights along one axis for which a landing moves along it
/// (a single patch's weights give at least 1/4).
pub const MIN_WEIGHT: f64 = 0.05;

/// Where a move must land: the surface at `(u, v)` of `patch` goes to `to`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hold {
    /// Patch index `iv * M + iu`.
    pub patch: usize,
    /// Parameter along `u`.
    pub u: f64,
    /// Parameter along `v`.
    pub v: f64,
    /// The target.
    pub to: DVec3,
}

/// A control-point group: around a regular grid vertex, or a pole.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Owner {
    Vertex(usize, usize),
    Pole(bool),
}

impl Owner {
    fn nodes(self, grid: &Grid) -> Vec<usize> {
        match self {
            Owner::Vertex(k, q) => grid
                .group(k, q)
                .map(|g| g.nodes.iter().flatten().flatten().copied().collect())
                .unwrap_or_default(),
            Owner::Pole(end) => {
                let end = if end { PoleEnd::End } else { PoleEnd::Start };
                grid.pole(end)
                    .map(|p| {
                        let mut v = vec![p.node];
                        v.extend(p.ring);
                        v
                    })
                    .unwrap_or_default()
            }
        }
    }

    fn partner(self, grid: &Grid, s: &Symmetry) -> Owner {
        match self {
            Owner::Vertex(k, q) => {
                let (k2, q2) = s.vertex_partner(grid, k, q);
                Owner::Vertex(k2, q2)
            }
            Owner::Pole(end) => {
                let e = if end { PoleEnd::End } else { PoleEnd::Start };
                Owner::Pole(s.pole_partner(e) == PoleEnd::End)
            }
        }
    }
}

/// The groups owning the control points of `patch` and their Bernstein weights at `(u, v)`.
fn owners(grid: &Grid, patch: usize, u: f64, v: f64) -> Vec<(Owner, f64)> {
    let m = grid.patches_u();
    let (iu, iv) = (patch % m, patch / m);
    let (bu, bv) = (cubic_basis(u), cubic_basis(v));
    let (vu, vv) = (grid.vertices_u(), grid.vertices_v());
    let mut out: Vec<(Owner, f64)> = Vec::with_capacity(4);
    for (du, dv) in [(0usize, 0usize), (1, 0), (0, 1), (1, 1)] {
        let w = (bu[2 * du] + bu[2 * du + 1]) * (bv[2 * dv] + bv[2 * dv + 1]);
        let (k, q) = ((iu + du) % vu, (iv + dv) % vv);
        let owner = if grid.is_pole_line(q) {
            Owner::Pole(q != 0)
        } else {
            Owner::Vertex(k, q)
        };
        match out.iter_mut().find(|(o, _)| *o == owner) {
            Some(entry) => entry.1 += w,
            None => out.push((owner, w)),
        }
    }
    out
}

/// Translates groups so that the surface at the hold lands on its target (see the module
/// docs); returns the node ids moved (each once). Every moved node belongs to a group at a
/// corner of the held patch (or its partner's): callers must have backed them up.
pub(crate) fn land(grid: &mut Grid, hold: &Hold, symmetry: Option<&Symmetry>) -> Vec<usize> {
    let (symmetry, plane) = match symmetry {
        Some(s) => match s.plane() {
            Some(plane) => (Some(s), plane),
            None => return land_group(grid, hold, s),
        },
        None => (None, crate::surface::mirror::Plane::X),
    };
    let m = grid.patches_u();
    let (iu, iv) = (hold.patch % m, hold.patch / m);
    let owned = owners(grid, hold.patch, hold.u, hold.v);
    // Orbits: (representative, its partner, per-axis weight of the representative's
    // translation in S(u*, v*)).
    let mut orbits: Vec<(Owner, Option<Owner>, [f64; 3])> = Vec::new();
    for &(g, w) in &owned {
        let (rep, partner, sign) = match symmetry {
            None => (g, None, [1.0; 3]),
            Some(s) => {
                let p = g.partner(grid, s);
                let rep = g.min(p);
                let mut sign = [1.0; 3];
                if g != rep {
                    sign[plane.axis()] = -1.0;
                }
                if p == g {
                    // Its own partner: no movement across the mirror plane.
                    sign[plane.axis()] = 0.0;
                }
                (rep, Some(p.max(g)), sign)
            }
        };
        let c = [w * sign[0], w * sign[1], w * sign[2]];
        match orbits.iter_mut().find(|(r, _, _)| *r == rep) {
            Some(entry) => {
                for k in 0..3 {
                    entry.2[k] += c[k];
                }
            }
            None => orbits.push((rep, partner.filter(|p| *p != rep), c)),
        }
    }
    let mut moved = Vec::new();
    for _pass in 0..2 {
        let s = grid.eval(iu, iv, hold.u, hold.v);
        let delta = (hold.to - s).to_array();
        let mut norm = [0.0f64; 3];
        for (_, _, c) in &orbits {
            for k in 0..3 {
                norm[k] += c[k] * c[k];
            }
        }
        for &(rep, partner, c) in &orbits {
            let mut t = [0.0f64; 3];
            for k in 0..3 {
                if norm[k] >= MIN_WEIGHT {
                    t[k] = c[k] * delta[k] / norm[k];
                }
            }
            let t = DVec3::from_array(t);
            if t == DVec3::ZERO {
                continue;
            }
            let ids = rep.nodes(grid);
            let nodes = grid.nodes_mut();
            for &id in &ids {
                nodes[id] += t;
            }
            moved.extend_from_slice(&ids);
            if let (Some(p), Some(_)) = (partner, symmetry) {
                let rt = plane.reflect(t);
                let ids = p.nodes(grid);
                let nodes = grid.nodes_mut();
                for &id in &ids {
                    nodes[id] += rt;
                }
                moved.extend_from_slice(&ids);
            }
        }
    }
    moved.sort_unstable();
    moved.dedup();
    moved
}

/// An orbit of control-point groups under a symmetry group: its representative, the
/// projector `P_r`, `A_r`, and every member with an isometry taking the representative to it.
type Orbit = (Owner, DMat3, DMat3, Vec<(Owner, DMat3)>);

/// [`land`] for a group that is not one mirror (see the module docs).
fn land_group(grid: &mut Grid, hold: &Hold, s: &Symmetry) -> Vec<usize> {
    let m = grid.patches_u();
    let (iu, iv) = (hold.patch % m, hold.patch / m);
    let isos: Vec<DMat3> = s.isometries().map(|g| g.matrix()).collect();
    let image = |o: Owner, e: usize| match o {
        Owner::Vertex(k, q) => {
            let (k2, q2) = s.vertex_image(e, grid, k, q);
            Owner::Vertex(k2, q2)
        }
        Owner::Pole(end) => {
            let e2 = if end { PoleEnd::End } else { PoleEnd::Start };
            Owner::Pole(s.pole_image(e, e2) == PoleEnd::End)
        }
    };
    // Orbits: (representative, projector P_r, A_r, members).
    let mut orbits: Vec<Orbit> = Vec::new();
    for (o, w) in owners(grid, hold.patch, hold.u, hold.v) {
        let images: Vec<Owner> = (0..isos.len()).map(|e| image(o, e)).collect();
        let rep = images.iter().copied().fold(o, Owner::min);
        // H: an isometry taking the representative to `o`.
        let h = if rep == o {
            DMat3::IDENTITY
        } else {
            (0..isos.len())
                .find(|&e| image(rep, e) == o)
                .map_or(DMat3::IDENTITY, |e| isos[e])
        };
        let stab: Vec<usize> = (0..isos.len()).filter(|&e| image(rep, e) == rep).collect();
        let p = stab.iter().fold(DMat3::IDENTITY, |acc, &e| acc + isos[e])
            * (1.0 / (stab.len() + 1) as f64);
        let a = h * p * w;
        match orbits.iter_mut().find(|(r, _, _, _)| *r == rep) {
            Some(entry) => entry.2 += a,
            None => {
                // Every member of the orbit once, with an isometry taking the
                // representative to it.
                let mut members = vec![(rep, DMat3::IDENTITY)];
                for (e, g) in isos.iter().enumerate() {
                    let o = image(rep, e);
                    if !members.iter().any(|(x, _)| *x == o) {
                        members.push((o, *g));
                    }
                }
                orbits.push((rep, p, a, members));
            }
        }
    }
    let mut moved = Vec::new();
    for _pass in 0..2 {
        let delta = hold.to - grid.eval(iu, iv, hold.u, hold.v);
        let total = orbits
            .iter()
            .fold(DMat3::ZERO, |acc, (_, _, a, _)| acc + *a * a.transpose());
        let y = pseudo_inverse(total, MIN_WEIGHT) * delta;
        for (_, p, a, members) in &orbits {
            let t = *p * (a.transpose() * y);
            if t == DVec3::ZERO || !t.is_finite() {
                continue;
            }
            for (o, g) in members {
                let ids = o.nodes(grid);
                let tg = *g * t;
                let nodes = grid.nodes_mut();
                for &id in &ids {
                    nodes[id] += tg;
                }
                moved.extend_from_slice(&ids);
            }
        }
    }
    moved.sort_unstable();
    moved.dedup();
    moved
}

/// The pseudo-inverse of a symmetric 3×3 matrix, eigenvalues below `floor` dropped (cyclic
/// Jacobi rotations).
fn pseudo_inverse(a: DMat3, floor: f64) -> DMat3 {
    let mut m = a.to_cols_array_2d();
    let mut v = DMat3::IDENTITY.to_cols_array_2d();
    for _sweep in 0..32 {
        let off = m[0][1].abs() + m[0][2].abs() + m[1][2].abs();
        if off < 1e-30 {
            break;
        }
        for (p, q) in [(0usize, 1usize), (0, 2), (1, 2)] {
            if m[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let c = 1.0 / (t * t + 1.0).sqrt();
            let sn = t * c;
            for k in 0..3 {
                let (mkp, mkq) = (m[k][p], m[k][q]);
                m[k][p] = c * mkp - sn * mkq;
                m[k][q] = sn * mkp + c * mkq;
            }
            for k in 0..3 {
                let (mpk, mqk) = (m[p][k], m[q][k]);
                m[p][k] = c * mpk - sn * mqk;
                m[q][k] = sn * mpk + c * mqk;
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - sn * vq;
                row[q] = sn * vp + c * vq;
            }
        }
    }
    // a = V diag(λ) Vᵀ with the eigenvectors the columns of V (rows of `v` index k).
    let mut out = DMat3::ZERO;
    for i in 0..3 {
        let l = m[i][i];
        if l < floor {
            continue;
        }
        let e = DVec3::new(v[0][i], v[1][i], v[2][i]);
        out += outer(e, e) * (1.0 / l);
    }
    out
}

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Primitive, PrimitiveParams, continuity};

    #[test]
    fn group_weights_sum_to_one_and_landing_is_exact_and_keeps_g1() {
        for p in Primitive::ALL {
            let mut grid = p.build(&PrimitiveParams::default()).unwrap();
            let before = continuity::report(&grid, 17).g1_max_deg;
            for (k, patch) in [0, grid.patch_count() / 2, grid.patch_count() - 1]
                .into_iter()
                .enumerate()
            {
                let (u, v) = (0.2 + 0.3 * k as f64, 0.7 - 0.25 * k as f64);
                let w: f64 = owners(&grid, patch, u, v).iter().map(|o| o.1).sum();
                assert!((w - 1.0).abs() < 1e-15, "{p}: {w}");
                let m = grid.patches_u();
                let s = grid.eval(patch % m, patch / m, u, v);
                let to = s + DVec3::new(0.1, -0.2, 0.15);
                land(&mut grid, &Hold { patch, u, v, to }, None);
                let got = grid.eval(patch % m, patch / m, u, v);
                assert!((got - to).length() < 1e-12, "{p}: {got} vs {to}");
            }
            let after = continuity::report(&grid, 17).g1_max_deg;
            assert!(after <= before + 1e-9, "{p}: {before} -> {after}");
        }
    }
}
