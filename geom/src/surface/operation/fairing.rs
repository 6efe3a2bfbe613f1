//! The smoothing dab: **implicit fairing** of the surface under the brush — one
//! backward-Euler step of the heat equation `∂x/∂t = Δx` on the surface's samples, taken along
//! their normals, falloff-weighted (Desbrun–Meyer–Schröder–Barr's implicit fairing, restricted
//! to the brush). The engine takes the samples' displacements through its Bernstein inverse and
//! regulation ([`crate::surface::Sculptor`]).
//!
//! **Samples.** Every patch within reach is sampled at `{0, 1/3, 2/3, 1}²`, the engine's own
//! samples ([`crate::surface::inverse`]). Sample `(i, j)` of patch `(iu, iv)` is node
//! `(3 iu + i, 3 iv + j)` of the control net's lattice, so a sample on a shared edge, a seam or
//! a pole is one node. Two samples are neighbours when they are neighbours in that lattice;
//! the edge between them weighs `w_ij = 1 / |x_i − x_j|²`, so that `Σ_j w_ij (x_j − x_i)` is
//! the five-point Laplacian `Δx` in world units on an even lattice (whatever the patches' size).
//!
//! **The dab** `{"op":"smooth","at":A,"radius":r,"strength":s}` moves every sample `x_i`
//! within `r` of `A` (or of an image of `A` under the symmetry) along its unit normal `n_i` by
//! `h_i`, where
//!
//! ```text
//! h_i = a_i Σ_j w_ij ((x_j + h_j n_j − x_i − h_i n_i) · n_i),
//! a_i = τ f_i,   τ = K s r²,   f_i = (1 − |x_i − A|² / r²)²,   K = DIFFUSION
//! ```
//!
//! (`h_j = 0` for a sample outside the brush): the new samples' Laplacian along the normal, a
//! backward-Euler step of length `a_i` — `τ` at the brush's centre, fading to nothing at its
//! rim with a continuous slope. Divided by `a_i` the system is
//!
//! ```text
//! (1/a_i + W_i) h_i − Σ_j w_ij (n_i · n_j) h_j = Σ_j w_ij (x_j − x_i) · n_i,   W_i = Σ_j w_ij,
//! ```
//!
//! symmetric and strictly diagonally dominant with a positive diagonal, hence positive
//! definite; it is solved by conjugate gradients with the diagonal as preconditioner, to a
//! residual of `10⁻¹³` of the right-hand side's.
//!
//! Properties:
//! - **Flat clay stays.** On a plane `(x_j − x_i) · n_i = 0` exactly, so the right-hand side
//!   and the solution are exactly zero: nothing moves.
//! - **No overshoot.** Where the normals are parallel (a height field `z` on a plane) row `i`
//!   reads `z'_i = (z_i / a_i + Σ_j w_ij z'_j) / (1/a_i + W_i)`: each new height is a convex
//!   combination of its old height and its neighbours' new ones, so no sample rises above the
//!   highest sample around it (the discrete maximum principle).
//! - **Any strength is stable.** The implicit step is stable for every `τ`, where an explicit
//!   step (the thin-plate descent this replaces, damped to its stability bound) moved a groove
//!   by a tenth of a percent per dab. The dab diffuses the surface over about
//!   `√(2 a_i) = r √(2 K s)` around each sample, whatever the patches' size: at the window's
//!   default strength 0.5, three passes of dabs along a 0.3 groove (the window's finger)
//!   flatten it below half its depth (`tests/it/smoothing.rs`).
//! - **A vanishing strength moves nothing**: `h = O(τ)`.
//!
//! Like every smoothing brush it also shrinks what it flattens (a sphere smoothed is a sphere
//! locally flattened).

use glam::DVec3;

use crate::surface::grid::Grid;
use crate::surface::inverse::{SAMPLE_PARAMS, samples};
use crate::surface::marks::Marks;
use crate::surface::patch::Patch;

/// `K` of the module docs: the diffusion time of a full-strength dab, in units of the brush
/// radius squared.
pub const DIFFUSION: f64 = 0.1;

/// No node at all (a `u32` slot not in use).
const NONE: u32 = u32::MAX;

/// One implicit fairing dab over the samples within `radius` of the centres (see the module
/// docs); keeps its scratch between dabs.
#[derive(Debug, Clone, Default)]
pub(crate) struct Fairing {
    /// The nodes seen in this dab, and each one's slot in `pos`.
    seen: Marks,
    slot: Vec<u32>,
    /// Per slot: the node id, its sample, its unit normal (`None`: no tangent plane).
    ids: Vec<usize>,
    pos: Vec<DVec3>,
    normal: Vec<Option<DVec3>>,
    /// Lattice edges between slots (each once, the smaller slot first).
    edges: Vec<(u32, u32)>,
    /// Per slot: its unknown's index (`NONE`: held).
    unknown: Vec<u32>,
    /// The unknowns' rows: `(start of its entries, 1/a_i + W_i, right-hand side)`.
    rows: Vec<(usize, f64, f64)>,
    /// Off-diagonal entries `(column slot, w_ij)` of each unknown's row, by row.
    entries: Vec<(u32, f64)>,
    /// Per unknown: its slot.
    slots: Vec<u32>,
    /// The solution `h` and the solver's vectors.
    h: Vec<f64>,
    cg: [Vec<f64>; 4],
    /// The patches within reach of the last dab.
    pub(crate) candidates: Vec<usize>,
}

impl Fairing {
    /// The flows of one dab at the 16 samples of every patch it moves, into `flows`
    /// (`(patch, flows)`, patches whose flows are all zero left out; indexed like the
    /// samples, `F[4i + j]`).
    pub(crate) fn flows(
        &mut self,
        grid: &Grid,
        centres: &[DVec3],
        radius: f64,
        strength: f64,
        flows: &mut Vec<(usize, [DVec3; 16])>,
    ) {
        flows.clear();
        self.candidates.clear();
        grid.hierarchy().query(
            &|b| {
                centres.iter().any(|c| {
                    let d = (b.min - *c).max(*c - b.max).max(DVec3::ZERO);
                    d.length() <= radius
                })
            },
            &mut self.candidates,
        );
        self.candidates.sort_unstable();
        self.collect_samples(grid);
        let tau = DIFFUSION * strength * radius * radius;
        if !self.assemble(centres, radius, tau) {
            return;
        }
        self.solve();
        let m = grid.patches_u();
        for &p in &self.candidates {
            let ids = grid.patch_node_ids(p % m, p / m);
            let f: [DVec3; 16] = std::array::from_fn(|k| {
                let s = self.slot[ids[k]] as usize;
                match (self.unknown[s], self.normal[s]) {
                    (u, Some(n)) if u != NONE => n * self.h[u as usize],
                    _ => DVec3::ZERO,
                }
            });
            if f.iter().any(|x| *x != DVec3::ZERO) {
                flows.push((p, f));
            }
        }
    }

    /// The samples, normals and lattice edges of the candidate patches.
    fn collect_samples(&mut self, grid: &Grid) {
        let len = grid.nodes().len();
        self.seen.start(len);
        if self.slot.len() != len {
            self.slot = vec![NONE; len];
        }
        self.ids.clear();
        self.pos.clear();
        self.normal.clear();
        self.edges.clear();
        let m = grid.patches_u();
        for &p in &self.candidates {
            let ids = grid.patch_node_ids(p % m, p / m);
            let points = grid.patch_at(p);
            let r = samples(&points);
            let patch = Patch::new(points);
            for i in 0..4 {
                for j in 0..4 {
                    let id = ids[4 * i + j];
                    if self.seen.mark(id) {
                        self.slot[id] = self.ids.len() as u32;
                        self.ids.push(id);
                        self.pos.push(r[4 * i + j]);
                        self.normal
                            .push(patch.normal(SAMPLE_PARAMS[i], SAMPLE_PARAMS[j]));
                    }
                }
            }
            for i in 0..4 {
                for j in 0..4 {
                    let a = self.slot[ids[4 * i + j]];
                    for (di, dj) in [(1, 0), (0, 1)] {
                        if i + di > 3 || j + dj > 3 {
                            continue;
                        }
                        let b = self.slot[ids[4 * (i + di) + j + dj]];
                        // A collapsed row (a pole) joins a node to itself.
                        if a != b {
                            self.edges.push((a.min(b), a.max(b)));
                        }
                    }
                }
            }
        }
        // An edge along a shared patch boundary comes from both patches.
        self.edges.sort_unstable();
        self.edges.dedup();
    }

    /// The rows of the system (see the module docs); `false` when nothing is to move.
    fn assemble(&mut self, centres: &[DVec3], radius: f64, tau: f64) -> bool {
        let n = self.ids.len();
        let r2 = radius * radius;
        // Edges shorter than this are a degenerate patch's, not the surface's.
        let tiny = (1e-12 * radius).powi(2);
        self.unknown.clear();
        self.unknown.resize(n, NONE);
        self.slots.clear();
        for s in 0..n {
            let f = centres
                .iter()
                .map(|c| 1.0 - (self.pos[s] - *c).length_squared() / r2)
                .fold(0.0f64, f64::max);
            if f > 0.0 && tau * f * f > 0.0 && self.normal[s].is_some() {
                self.unknown[s] = self.slots.len() as u32;
                self.slots.push(s as u32);
            }
        }
        if self.slots.is_empty() {
            return false;
        }
        // Each unknown's entries: the edges at its slot, in the edges' order.
        let mut per: Vec<Vec<(u32, f64)>> = vec![Vec::new(); self.slots.len()];
        for &(a, b) in &self.edges {
            let d2 = (self.pos[a as usize] - self.pos[b as usize]).length_squared();
            if d2.is_nan() || d2 <= tiny {
                continue;
            }
            let w = 1.0 / d2;
            for (x, y) in [(a, b), (b, a)] {
                let u = self.unknown[x as usize];
                if u != NONE {
                    per[u as usize].push((y, w));
                }
            }
        }
        self.rows.clear();
        self.entries.clear();
        for (u, list) in per.iter().enumerate() {
            let s = self.slots[u] as usize;
            let (x, n_i) = (self.pos[s], self.normal[s].unwrap_or(DVec3::ZERO));
            let f = centres
                .iter()
                .map(|c| 1.0 - (x - *c).length_squared() / r2)
                .fold(0.0f64, f64::max);
            let a = tau * f * f;
            let mut total = 0.0;
            let mut rhs = 0.0;
            for &(j, w) in list {
                total += w;
                rhs += w * (self.pos[j as usize] - x).dot(n_i);
            }
            self.rows.push((self.entries.len(), 1.0 / a + total, rhs));
            self.entries.extend_from_slice(list);
        }
        self.rows.iter().any(|r| r.2 != 0.0)
    }

    /// `y = A x` for the system's matrix.
    fn multiply(&self, x: &[f64], y: &mut [f64]) {
        for (u, &(start, diag, _)) in self.rows.iter().enumerate() {
            let end = self
                .rows
                .get(u + 1)
                .map_or(self.entries.len(), |next| next.0);
            let n_i = self.normal[self.slots[u] as usize].unwrap_or(DVec3::ZERO);
            let mut sum = diag * x[u];
            for &(j, w) in &self.entries[start..end] {
                let v = self.unknown[j as usize];
                if v != NONE {
                    let n_j = self.normal[j as usize].unwrap_or(DVec3::ZERO);
                    sum -= w * n_i.dot(n_j) * x[v as usize];
                }
            }
            y[u] = sum;
        }
    }

    /// Preconditioned conjugate gradients for `h` (see the module docs).
    fn solve(&mut self) {
        let n = self.rows.len();
        self.h.clear();
        self.h.resize(n, 0.0);
        let mut cg = std::mem::take(&mut self.cg);
        for v in &mut cg {
            v.clear();
            v.resize(n, 0.0);
        }
        let [r, z, p, q] = &mut cg;
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        for (u, row) in self.rows.iter().enumerate() {
            r[u] = row.2;
            z[u] = row.2 / row.1;
            p[u] = z[u];
        }
        let goal = 1e-13 * dot(r, r).sqrt();
        let mut rz = dot(r, z);
        for _ in 0..2 * n + 50 {
            if dot(r, r).sqrt() <= goal {
                break;
            }
            self.multiply(p, q);
            let pq = dot(p, q);
            if pq.is_nan() || pq <= 0.0 {
                break;
            }
            let alpha = rz / pq;
            for u in 0..n {
                self.h[u] += alpha * p[u];
                r[u] -= alpha * q[u];
                z[u] = r[u] / self.rows[u].1;
            }
            let next = dot(r, z);
            let beta = next / rz;
            rz = next;
            for u in 0..n {
                p[u] = z[u] + beta * p[u];
            }
        }
        self.cg = cg;
    }
}
