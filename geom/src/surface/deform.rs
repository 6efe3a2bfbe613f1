//! The deformation pipeline (seed 002 §2.1, Fig. 1; SPEC §7): finger → reachable patches →
//! samples and flows → Bernstein inverse per patch → regulation of the touched groups.
//!
//! 1. **Reach.** The patches whose control-point boxes the finger may reach are found in the
//!    bounding-box pyramid ([`super::bounds`]), so the cost follows the touched area, not the
//!    patch count (the paper's own future work).
//! 2. **Flow.** Each such patch is sampled at `{0, 1/3, 2/3, 1}²` and every sample gets its
//!    flow from the shape function ([`super::shape_fn`]). A patch whose 16 flows are all zero
//!    is left alone, bit for bit.
//! 3. **Inverse.** `ΔP = B₄⁻¹ F B₄⁻ᵀ` per patch ([`super::inverse`]). Shared control points get
//!    bit-identical updates from every patch holding them (shared samples are computed from
//!    the same nodes the same way, and rows 0 and 3 of `B₄⁻¹` are copies), and they exist once
//!    in the net, so each is moved once. At a pole every patch moves the pole by the flow of
//!    the pole sample itself.
//! 4. **Regulation** ([`super::regulate`]) of the groups around the corners of the moved
//!    patches (and of a pole one of them touches), with the chosen method. Groups are
//!    disjoint, so this is local too; the patches returned in [`Touched`] are all those whose
//!    control points may have changed.
//!
//! Everything runs in a fixed order on plain `f64` arithmetic: the same operation applied to
//! the same grid gives bit-identical results.

use glam::DVec3;

use super::error::SurfaceError;
use super::grid::Grid;
use super::group::PoleEnd;
use super::inverse::{control_update, samples};
use super::regulate::{self, Projections, Regulation};
use super::shape_fn::{Finger, Op};

/// What one operation changed.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Touched {
    /// Indices (`iv * M + iu`, increasing) of every patch whose control points may have
    /// changed: the patches the finger moved and their neighbours through regulated groups.
    pub patches: Vec<usize>,
    /// How many patches the finger itself moved.
    pub deformed: usize,
    /// How many patches the box pyramid let through for sampling (at least `deformed`).
    pub examined: usize,
    /// How many groups and poles were regulated.
    pub groups: usize,
}

/// Deforms grids; keeps the scratch buffers between operations so that an operation costs
/// what it touches (reuse one `Sculptor` for a stream of operations).
#[derive(Debug, Clone, Default)]
pub struct Sculptor {
    generation: u32,
    node_mark: Vec<u32>,
    vertex_mark: Vec<u32>,
    patch_mark: Vec<u32>,
    candidates: Vec<usize>,
    updates: Vec<(usize, [DVec3; 16])>,
    segments: Vec<usize>,
    vertices: Vec<(usize, usize)>,
    poles: Vec<PoleEnd>,
    scratch: Vec<usize>,
    projections: Projections,
}

/// Applies one operation to a grid with a fresh [`Sculptor`] (allocates buffers the size of
/// the grid; use a `Sculptor` for a stream of operations).
///
/// # Errors
/// [`SurfaceError::BadOp`] for an invalid operation; the grid is then unchanged.
pub fn deform(grid: &mut Grid, op: &Op, regulation: Regulation) -> Result<Touched, SurfaceError> {
    Sculptor::new().apply(grid, op, regulation)
}

impl Sculptor {
    /// A sculptor with empty buffers.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Applies one operation.
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] for an invalid operation; the grid is then unchanged.
    pub fn apply(
        &mut self,
        grid: &mut Grid,
        op: &Op,
        regulation: Regulation,
    ) -> Result<Touched, SurfaceError> {
        let finger = op.finger()?;
        Ok(self.apply_finger(grid, &finger, regulation))
    }

    /// Applies a validated finger.
    pub fn apply_finger(
        &mut self,
        grid: &mut Grid,
        finger: &Finger,
        regulation: Regulation,
    ) -> Touched {
        self.next_generation(grid);
        let stamp = self.generation;
        let depth = finger.reach_depth(&grid.bounds());

        // 1. Reach.
        self.candidates.clear();
        grid.hierarchy()
            .query(&|b| finger.may_touch(b, depth), &mut self.candidates);

        // 2–3. Flows and control-point updates, from the unchanged net.
        self.updates.clear();
        let (m, n) = (grid.patches_u(), grid.patches_v());
        let topology = grid.topology();
        for &p in &self.candidates {
            if !finger.restricted_to(&grid.patch_bounds(p), depth, &mut self.segments) {
                continue;
            }
            let points = grid.patch_at(p);
            let r = samples(&points);
            let mut flows = [DVec3::ZERO; 16];
            let mut any = false;
            for k in 0..16 {
                flows[k] = finger.flow_over(r[k], &self.segments);
                any |= flows[k] != DVec3::ZERO;
            }
            if !any {
                continue;
            }
            let mut delta = control_update(&flows);
            let iv = p / m;
            // A pole moves by the flow of the pole sample (the unit rows give it exactly at
            // i = 0; make the other copies of the collapsed row agree).
            for (at_pole, j) in [
                (iv == 0 && topology.pole_at_start(), 0),
                (iv + 1 == n && topology.pole_at_end(), 3),
            ] {
                if at_pole {
                    for i in 1..4 {
                        delta[4 * i + j] = delta[j];
                    }
                }
            }
            self.updates.push((p, delta));
        }
        let nodes_changed = !self.updates.is_empty();
        {
            let shape = grid.shape();
            let nodes = grid.nodes_mut();
            for (p, delta) in &self.updates {
                let (iu, iv) = (p % m, p / m);
                for i in 0..4 {
                    for j in 0..4 {
                        let id = shape.local_id(iu, iv, i, j);
                        if self.node_mark[id] != stamp {
                            self.node_mark[id] = stamp;
                            nodes[id] += delta[4 * i + j];
                        }
                    }
                }
            }
        }
        let deformed = self.updates.len();
        let mut changed: Vec<usize> = Vec::with_capacity(deformed * 2);
        for (p, _) in &self.updates {
            self.patch_mark[*p] = stamp;
            changed.push(*p);
        }

        // 4. Regulation of the groups around the moved patches.
        let mut groups = 0;
        if nodes_changed && regulation != Regulation::None {
            self.collect_groups(grid);
            groups = regulate::regulate(
                grid,
                regulation,
                &self.vertices,
                &self.poles,
                &mut self.projections,
            );
            for &(k, q) in &self.vertices {
                for (du, dv) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let Some(iu) = wrap(k as isize - du, m, topology.closed_u()) else {
                        continue;
                    };
                    let Some(iv) = wrap(q as isize - dv, n, topology.closed_v()) else {
                        continue;
                    };
                    let p = iv * m + iu;
                    if self.patch_mark[p] != stamp {
                        self.patch_mark[p] = stamp;
                        changed.push(p);
                    }
                }
            }
            for &end in &self.poles {
                let iv = if end == PoleEnd::Start { 0 } else { n - 1 };
                for iu in 0..m {
                    let p = iv * m + iu;
                    if self.patch_mark[p] != stamp {
                        self.patch_mark[p] = stamp;
                        changed.push(p);
                    }
                }
            }
        }
        changed.sort_unstable();
        grid.refit(&changed, &mut self.scratch);
        Touched {
            patches: changed,
            deformed,
            examined: self.candidates.len(),
            groups,
        }
    }

    /// The grid vertices at the corners of the moved patches (deduplicated, in a fixed
    /// order), and the poles they touch.
    fn collect_groups(&mut self, grid: &Grid) {
        let stamp = self.generation;
        let m = grid.patches_u();
        let vu = grid.vertices_u();
        let vv = grid.vertices_v();
        self.vertices.clear();
        self.poles.clear();
        for (p, _) in &self.updates {
            let (iu, iv) = (p % m, p / m);
            for (du, dv) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let k = (iu + du) % vu;
                let q = (iv + dv) % vv;
                if grid.is_pole_line(q) {
                    let end = if q == 0 { PoleEnd::Start } else { PoleEnd::End };
                    if !self.poles.contains(&end) {
                        self.poles.push(end);
                    }
                    continue;
                }
                let v = q * vu + k;
                if self.vertex_mark[v] != stamp {
                    self.vertex_mark[v] = stamp;
                    self.vertices.push((k, q));
                }
            }
        }
        self.poles.sort_unstable_by_key(|e| *e == PoleEnd::End);
    }

    fn next_generation(&mut self, grid: &Grid) {
        let sizes = [
            grid.nodes().len(),
            grid.vertices_u() * grid.vertices_v(),
            grid.patch_count(),
        ];
        for (marks, len) in [
            &mut self.node_mark,
            &mut self.vertex_mark,
            &mut self.patch_mark,
        ]
        .into_iter()
        .zip(sizes)
        {
            if marks.len() != len {
                marks.clear();
                marks.resize(len, 0);
            }
        }
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            for marks in [
                &mut self.node_mark,
                &mut self.vertex_mark,
                &mut self.patch_mark,
            ] {
                marks.fill(0);
            }
            self.generation = 1;
        }
        // Marks from a different grid of the same size must not count: they are only ever
        // compared with the current generation, which no earlier operation used.
    }
}

/// `i` wrapped into `0..len` around a closed direction; `None` outside an open one.
fn wrap(i: isize, len: usize, closed: bool) -> Option<usize> {
    if closed {
        Some(i.rem_euclid(len as isize) as usize)
    } else if (0..len as isize).contains(&i) {
        Some(i as usize)
    } else {
        None
    }
}
