//! A grid of `M × N` bicubic Bezier patches sharing one control net (P2 §3).
//!
//! ## The control net
//! Every control point exists once. The net is a lattice of columns `a` (along `u`) and rows `b`
//! (along `v`); patch `(iu, iv)` uses the lattice points `(3·iu + i, 3·iv + j)`, `i, j ∈ 0..=3`,
//! as its `P[4*i + j]`. So a boundary control point is one value however many patches hold it:
//! neighbours can never drift apart (C0 holds by construction), closed seams stay closed and
//! poles stay degenerate.
//!
//! - Along an open direction there are `3M + 1` columns; along a closed one `3M`, and column
//!   `3M` *is* column 0 (indices wrap).
//! - A pole collapses the whole row `b = 0` (or `b = 3N`) into one node.
//!
//! Node ids (the order of [`Grid::nodes`]): the pole at `v = 0` if there is one, then the
//! regular rows `b` in increasing order, each with its columns `a` in increasing order, then
//! the pole at `v = N` if there is one.
//!
//! ## Patches
//! Patch `(iu, iv)` has index `iv * M + iu`; its points are `P[4*i + j]`, `i` along `u`, `j`
//! along `v` (see [`Grid::patch`]). With the primitives' orientation `S_u × S_v` points
//! outward.
//!
//! ## Spacing ratios
//! For every shared grid line the grid keeps a reference spacing ratio
//! `ρ = |P₊ − P₀| / |P₀ − P₋|` of the three-point rows of control points that cross it, taken
//! (as a mean over the line) when the grid is built. The default regulation keeps every such
//! row collinear with exactly that ratio, which makes the surface G1 along whole edges.
//!
//! ## Refined lines
//! Each grid line also records whether refinement made it ([`Grid::refined_u`],
//! [`Grid::refined_v`]): a grid as built has none; a refinement
//! ([`crate::surface::refine`]) marks the lines it inserts and keeps the marks of the lines it
//! keeps. The surface does not depend on them — the window draws refined lines fainter than
//! the primitive's own.

use glam::DVec3;

use crate::surface::bounds::{Aabb, Hierarchy};
use crate::surface::error::SurfaceError;
use crate::surface::limits::MAX_PATCHES;
use crate::surface::patch::{Patch, PatchPoints};
use crate::surface::topology::Topology;

/// A grid of bicubic Bezier patches on a shared control net.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    topology: Topology,
    m: usize,
    n: usize,
    /// Lattice columns (`3M` or `3M + 1`).
    la: usize,
    /// Lattice rows (`3N` or `3N + 1`).
    lb: usize,
    nodes: Vec<DVec3>,
    /// Reference spacing ratio per u grid line `k` (lattice column `3k`); 1 on open boundaries.
    ratios_u: Vec<f64>,
    /// Reference spacing ratio per v grid line `q` (lattice row `3q`); 1 on boundaries and poles.
    ratios_v: Vec<f64>,
    /// Per u grid line: made by refinement (see the module docs).
    refined_u: Vec<bool>,
    /// Per v grid line: made by refinement.
    refined_v: Vec<bool>,
    hierarchy: Hierarchy,
}

impl Grid {
    /// Checks patch counts against a topology: at least one patch along an open direction;
    /// an even count of at least 2 (6 around a pole) along a closed one; a sphere needs at
    /// least 2 patches from pole to pole.
    ///
    /// # Errors
    /// [`SurfaceError::TooFewPatches`], [`SurfaceError::OddClosedCount`],
    /// [`SurfaceError::TooLarge`].
    pub fn check_counts(topology: Topology, m: usize, n: usize) -> Result<(), SurfaceError> {
        let min_u = if !topology.closed_u() {
            1
        } else if topology.pole_count() > 0 {
            6
        } else {
            2
        };
        let min_v = match topology {
            Topology::Sphere | Topology::Torus => 2,
            _ => 1,
        };
        for (direction, got, min, closed) in [
            ("u", m, min_u, topology.closed_u()),
            ("v", n, min_v, topology.closed_v()),
        ] {
            if got < min {
                return Err(SurfaceError::TooFewPatches {
                    topology,
                    direction,
                    min,
                    got,
                });
            }
            if closed && got % 2 == 1 {
                return Err(SurfaceError::OddClosedCount {
                    topology,
                    direction,
                    got,
                });
            }
        }
        if m.checked_mul(n).is_none_or(|c| c > MAX_PATCHES) {
            return Err(SurfaceError::TooLarge {
                patches_u: m,
                patches_v: n,
            });
        }
        Ok(())
    }

    /// Number of control-net nodes of a grid with this topology and these counts (which must
    /// pass [`Grid::check_counts`]).
    #[must_use]
    pub fn net_len(topology: Topology, m: usize, n: usize) -> usize {
        let (la, lb) = lattice_dims(topology, m, n);
        let poles = topology.pole_count();
        poles + (lb - poles) * la
    }

    /// A grid from its control net, in node-id order (see the module docs).
    ///
    /// # Errors
    /// Bad counts (see [`Grid::check_counts`]), a net of the wrong length
    /// ([`SurfaceError::WrongCount`]), a non-finite coordinate ([`SurfaceError::NotFinite`],
    /// with the node index in `patch`) or one beyond [`crate::surface::limits::COORDINATE_LIMIT`]
    /// ([`SurfaceError::OutOfRange`], node index in `patch`).
    pub fn from_net(
        topology: Topology,
        m: usize,
        n: usize,
        nodes: Vec<DVec3>,
    ) -> Result<Self, SurfaceError> {
        Self::check_counts(topology, m, n)?;
        let expected = Self::net_len(topology, m, n);
        if nodes.len() != expected {
            return Err(SurfaceError::WrongCount {
                what: "control points",
                expected,
                got: nodes.len(),
            });
        }
        if let Some(bad) = nodes.iter().position(|p| !p.is_finite()) {
            return Err(SurfaceError::NotFinite {
                patch: bad,
                point: 0,
            });
        }
        if let Some(bad) = nodes
            .iter()
            .position(|p| p.abs().max_element() > crate::surface::limits::COORDINATE_LIMIT)
        {
            return Err(SurfaceError::OutOfRange {
                patch: bad,
                point: 0,
                limit: crate::surface::limits::COORDINATE_LIMIT,
            });
        }
        let (la, lb) = lattice_dims(topology, m, n);
        let mut grid = Grid {
            topology,
            m,
            n,
            la,
            lb,
            nodes,
            ratios_u: Vec::new(),
            ratios_v: Vec::new(),
            refined_u: Vec::new(),
            refined_v: Vec::new(),
            hierarchy: Hierarchy::new(0, 0, Vec::new()),
        };
        grid.refined_u = vec![false; grid.vertices_u()];
        grid.refined_v = vec![false; grid.vertices_v()];
        grid.ratios_u = (0..grid.vertices_u())
            .map(|k| grid.measure_ratio_u(k))
            .collect();
        grid.ratios_v = (0..grid.vertices_v())
            .map(|q| grid.measure_ratio_v(q))
            .collect();
        let leaves = (0..m * n).map(|p| grid.patch_struct(p).bounds()).collect();
        grid.hierarchy = Hierarchy::new(m, n, leaves);
        Ok(grid)
    }

    /// A grid from per-patch control points (`patches[iv * M + iu]`), merging the copies of
    /// every shared point. Copies may differ by at most `tolerance`; the first copy (lowest
    /// patch index, then lowest point index) is kept. Returns the grid and the largest
    /// distance found between copies of one point (the file's G0 gap).
    ///
    /// # Errors
    /// Bad counts, a wrong number of patches, a non-finite coordinate, or copies further apart
    /// than `tolerance` ([`SurfaceError::NotCoincident`]).
    pub fn from_patches(
        topology: Topology,
        m: usize,
        n: usize,
        patches: &[PatchPoints],
        tolerance: f64,
    ) -> Result<(Self, f64), SurfaceError> {
        Self::check_counts(topology, m, n)?;
        if patches.len() != m * n {
            return Err(SurfaceError::WrongCount {
                what: "patches",
                expected: m * n,
                got: patches.len(),
            });
        }
        for (pi, p) in patches.iter().enumerate() {
            if let Some(k) = p.iter().position(|x| !x.is_finite()) {
                return Err(SurfaceError::NotFinite {
                    patch: pi,
                    point: k,
                });
            }
        }
        let len = Self::net_len(topology, m, n);
        let (la, lb) = lattice_dims(topology, m, n);
        let shape = Shape { topology, la, lb };
        // First copy of each node: (patch, point).
        let mut owner: Vec<Option<(usize, usize)>> = vec![None; len];
        let mut nodes = vec![DVec3::ZERO; len];
        let mut gap = 0.0f64;
        for iv in 0..n {
            for iu in 0..m {
                let pi = iv * m + iu;
                for i in 0..4 {
                    for j in 0..4 {
                        let id = shape.local_id(iu, iv, i, j);
                        let x = patches[pi][4 * i + j];
                        match owner[id] {
                            None => {
                                owner[id] = Some((pi, 4 * i + j));
                                nodes[id] = x;
                            }
                            Some((op, ok)) => {
                                let d = (x - nodes[id]).length();
                                gap = gap.max(d);
                                if d > tolerance {
                                    let what = if shape.is_pole_row(3 * iv + j) {
                                        "pole"
                                    } else if 3 * iu + i >= la || 3 * iv + j >= lb {
                                        "closed seam"
                                    } else {
                                        "shared edge"
                                    };
                                    return Err(SurfaceError::NotCoincident {
                                        patch: pi,
                                        point: 4 * i + j,
                                        other: op,
                                        other_point: ok,
                                        what,
                                        distance: d,
                                    });
                                }
                            }
                        }
                    }
                }
            }
        }
        Ok((Self::from_net(topology, m, n, nodes)?, gap))
    }

    /// The connection topology.
    #[must_use]
    pub fn topology(&self) -> Topology {
        self.topology
    }

    /// `M`, the number of patches along `u`.
    #[must_use]
    pub fn patches_u(&self) -> usize {
        self.m
    }

    /// `N`, the number of patches along `v`.
    #[must_use]
    pub fn patches_v(&self) -> usize {
        self.n
    }

    /// `M × N`.
    #[must_use]
    pub fn patch_count(&self) -> usize {
        self.m * self.n
    }

    /// The lattice size `(columns, rows)`: `3M` or `3M + 1` columns, `3N` or `3N + 1` rows.
    #[must_use]
    pub fn lattice_size(&self) -> (usize, usize) {
        (self.la, self.lb)
    }

    /// Every node of the control net, in node-id order (see the module docs).
    #[must_use]
    pub fn nodes(&self) -> &[DVec3] {
        &self.nodes
    }

    pub(crate) fn nodes_mut(&mut self) -> &mut [DVec3] {
        &mut self.nodes
    }

    /// The node id of lattice point `(a, b)`; indices wrap around closed directions; `None`
    /// beyond an open boundary.
    #[must_use]
    pub fn node_id(&self, a: isize, b: isize) -> Option<usize> {
        self.shape().node_id(a, b)
    }

    /// The node ids of patch `(iu, iv)`, `ids[4*i + j]`.
    ///
    /// # Panics
    /// If `iu ≥ M` or `iv ≥ N`.
    #[must_use]
    pub fn patch_node_ids(&self, iu: usize, iv: usize) -> [usize; 16] {
        assert!(
            iu < self.m && iv < self.n,
            "patch ({iu}, {iv}) out of range"
        );
        self.shape().patch_ids(iu, iv)
    }

    /// The 16 control points of patch `(iu, iv)`, `P[4*i + j]`, `i` along `u`, `j` along `v`.
    ///
    /// # Panics
    /// If `iu ≥ M` or `iv ≥ N`.
    #[must_use]
    pub fn patch(&self, iu: usize, iv: usize) -> PatchPoints {
        let ids = self.patch_node_ids(iu, iv);
        ids.map(|id| self.nodes[id])
    }

    /// The control points of the patch with index `iv * M + iu`.
    ///
    /// # Panics
    /// If the index is not below [`Grid::patch_count`].
    #[must_use]
    pub fn patch_at(&self, index: usize) -> PatchPoints {
        self.patch(index % self.m, index / self.m)
    }

    /// Every patch, in index order (`iv * M + iu`).
    #[must_use]
    pub fn patches(&self) -> Vec<PatchPoints> {
        (0..self.patch_count()).map(|p| self.patch_at(p)).collect()
    }

    pub(crate) fn patch_struct(&self, index: usize) -> Patch {
        Patch::new(self.patch_at(index))
    }

    /// `S(u, v)` on patch `(iu, iv)`.
    ///
    /// # Panics
    /// If the patch is out of range.
    #[must_use]
    pub fn eval(&self, iu: usize, iv: usize, u: f64, v: f64) -> DVec3 {
        Patch::new(self.patch(iu, iv)).eval(u, v)
    }

    /// The unit normal on patch `(iu, iv)` (see [`Patch::normal`]).
    ///
    /// # Panics
    /// If the patch is out of range.
    #[must_use]
    pub fn normal(&self, iu: usize, iv: usize, u: f64, v: f64) -> Option<DVec3> {
        Patch::new(self.patch(iu, iv)).normal(u, v)
    }

    /// Bounding box of the whole control net.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        self.hierarchy.root()
    }

    /// Bounding box of one patch's control points.
    ///
    /// # Panics
    /// If the index is out of range.
    #[must_use]
    pub fn patch_bounds(&self, index: usize) -> Aabb {
        self.hierarchy.leaf(index)
    }

    pub(crate) fn hierarchy(&self) -> &Hierarchy {
        &self.hierarchy
    }

    /// Appends to `out` the patches whose bounding boxes `accept` takes, in no particular
    /// order (each once), descending the box pyramid: `accept` must be conservative — true
    /// for a box whenever it is true for some box inside it (an overlap or a ray-clip test),
    /// else leaves under a rejected parent are missed. `out` is not cleared.
    pub fn patches_where(&self, accept: impl Fn(&Aabb) -> bool, out: &mut Vec<usize>) {
        self.hierarchy.query(&accept, out);
    }

    /// Recomputes the boxes of the given patches (after their control points changed).
    pub(crate) fn refit(&mut self, patches: &[usize], scratch: &mut Vec<usize>) {
        let changed: Vec<(usize, Aabb)> = patches
            .iter()
            .map(|&p| (p, self.patch_struct(p).bounds()))
            .collect();
        self.hierarchy.refit(&changed, scratch);
    }

    /// Number of grid vertices along `u`: `M` when closed, `M + 1` when open.
    #[must_use]
    pub fn vertices_u(&self) -> usize {
        if self.topology.closed_u() {
            self.m
        } else {
            self.m + 1
        }
    }

    /// Number of grid vertices along `v`: `N` when closed, `N + 1` when open (pole rows
    /// included).
    #[must_use]
    pub fn vertices_v(&self) -> usize {
        if self.topology.closed_v() {
            self.n
        } else {
            self.n + 1
        }
    }

    /// Reference spacing ratio of u grid line `k` (lattice column `3k`); see the module docs.
    ///
    /// # Panics
    /// If `k ≥ vertices_u()`.
    #[must_use]
    pub fn ratio_u(&self, k: usize) -> f64 {
        self.ratios_u[k]
    }

    /// Reference spacing ratio of v grid line `q` (lattice row `3q`).
    ///
    /// # Panics
    /// If `q ≥ vertices_v()`.
    #[must_use]
    pub fn ratio_v(&self, q: usize) -> f64 {
        self.ratios_v[q]
    }

    /// Every u grid line's reference spacing ratio (see [`Grid::ratio_u`]).
    #[must_use]
    pub fn ratios_u(&self) -> &[f64] {
        &self.ratios_u
    }

    /// Every v grid line's reference spacing ratio (see [`Grid::ratio_v`]).
    #[must_use]
    pub fn ratios_v(&self) -> &[f64] {
        &self.ratios_v
    }

    /// Replaces the reference spacing ratios (e.g. those saved with a model, so that
    /// regulation after reading behaves exactly as before writing). Entries for lines that are
    /// not shared are ignored and set to 1.
    ///
    /// # Errors
    /// [`SurfaceError::WrongCount`] unless there is one ratio per grid line
    /// ([`Grid::vertices_u`], [`Grid::vertices_v`]); [`SurfaceError::BadParameter`] for a ratio
    /// that is not a positive finite number.
    pub fn set_ratios(&mut self, u: &[f64], v: &[f64]) -> Result<(), SurfaceError> {
        for (got, expected) in [(u.len(), self.vertices_u()), (v.len(), self.vertices_v())] {
            if got != expected {
                return Err(SurfaceError::WrongCount {
                    what: "spacing ratios",
                    expected,
                    got,
                });
            }
        }
        if let Some(&bad) = u.iter().chain(v).find(|r| !(r.is_finite() && **r > 0.0)) {
            return Err(SurfaceError::BadParameter {
                name: "spacing ratio",
                value: bad,
            });
        }
        self.ratios_u = (0..u.len())
            .map(|k| if self.u_line_shared(k) { u[k] } else { 1.0 })
            .collect();
        self.ratios_v = (0..v.len())
            .map(|q| if self.v_line_shared(q) { v[q] } else { 1.0 })
            .collect();
        Ok(())
    }

    /// Per u grid line `k` (one per [`Grid::vertices_u`]): true when refinement made it, false
    /// for the lines the grid was built with (see the module docs).
    #[must_use]
    pub fn refined_u(&self) -> &[bool] {
        &self.refined_u
    }

    /// Per v grid line `q` (one per [`Grid::vertices_v`]): true when refinement made it.
    #[must_use]
    pub fn refined_v(&self) -> &[bool] {
        &self.refined_v
    }

    /// Marks which grid lines refinement made (e.g. as saved with a model).
    ///
    /// # Errors
    /// [`SurfaceError::WrongCount`] unless there is one mark per grid line
    /// ([`Grid::vertices_u`], [`Grid::vertices_v`]); nothing changes then.
    pub fn set_refined(&mut self, u: &[bool], v: &[bool]) -> Result<(), SurfaceError> {
        for (got, expected) in [(u.len(), self.vertices_u()), (v.len(), self.vertices_v())] {
            if got != expected {
                return Err(SurfaceError::WrongCount {
                    what: "refined-line marks",
                    expected,
                    got,
                });
            }
        }
        self.refined_u = u.to_vec();
        self.refined_v = v.to_vec();
        Ok(())
    }

    /// True when u grid line `k` is shared by two patches (not an open boundary).
    #[must_use]
    pub fn u_line_shared(&self, k: usize) -> bool {
        self.topology.closed_u() || (k > 0 && k < self.m)
    }

    /// True when v grid line `q` is shared by two patches (not an open boundary, not a pole).
    #[must_use]
    pub fn v_line_shared(&self, q: usize) -> bool {
        if self.topology.closed_v() {
            return true;
        }
        q > 0 && q < self.n
    }

    /// True when grid row `q` is collapsed into a pole.
    #[must_use]
    pub fn is_pole_line(&self, q: usize) -> bool {
        (q == 0 && self.topology.pole_at_start()) || (q == self.n && self.topology.pole_at_end())
    }

    fn measure_ratio_u(&self, k: usize) -> f64 {
        if !self.u_line_shared(k) {
            return 1.0;
        }
        let a = 3 * k as isize;
        let rows = (0..self.lb as isize).map(|b| {
            let at = |da: isize| self.node_id(a + da, b).map(|id| self.nodes[id]);
            (at(-1), at(0), at(1))
        });
        mean_ratio(rows)
    }

    fn measure_ratio_v(&self, q: usize) -> f64 {
        if !self.v_line_shared(q) {
            return 1.0;
        }
        let b = 3 * q as isize;
        let cols = (0..self.la as isize).map(|a| {
            let at = |db: isize| self.node_id(a, b + db).map(|id| self.nodes[id]);
            (at(-1), at(0), at(1))
        });
        mean_ratio(cols)
    }

    /// Sets control-net nodes to new positions (`changes`: node id and position, each id at
    /// most once) and refits the boxes of every patch holding one of them; returns those
    /// patches (sorted). What undo and redo use to put back exactly what an edit changed, at a
    /// cost proportional to the nodes changed.
    ///
    /// # Errors
    /// [`SurfaceError::WrongCount`] for a node id past the net (nothing changes then),
    /// [`SurfaceError::NotFinite`] / [`SurfaceError::OutOfRange`] for a bad position (node id
    /// in `patch`; nothing changes then).
    pub fn set_nodes(&mut self, changes: &[(usize, DVec3)]) -> Result<Vec<usize>, SurfaceError> {
        for &(id, x) in changes {
            if id >= self.nodes.len() {
                return Err(SurfaceError::WrongCount {
                    what: "control points",
                    expected: self.nodes.len(),
                    got: id + 1,
                });
            }
            if !x.is_finite() {
                return Err(SurfaceError::NotFinite {
                    patch: id,
                    point: 0,
                });
            }
            if x.abs().max_element() > crate::surface::limits::COORDINATE_LIMIT {
                return Err(SurfaceError::OutOfRange {
                    patch: id,
                    point: 0,
                    limit: crate::surface::limits::COORDINATE_LIMIT,
                });
            }
        }
        let mut patches = Vec::with_capacity(changes.len());
        for &(id, x) in changes {
            self.nodes[id] = x;
            self.patches_of_node(id, &mut patches);
        }
        patches.sort_unstable();
        patches.dedup();
        let mut scratch = Vec::new();
        self.refit(&patches, &mut scratch);
        Ok(patches)
    }

    /// Appends the patches holding node `id` (a pole: its whole patch row).
    fn patches_of_node(&self, id: usize, out: &mut Vec<usize>) {
        let (m, n) = (self.m, self.n);
        let start = usize::from(self.topology.pole_at_start());
        if start == 1 && id == 0 {
            out.extend(0..m);
            return;
        }
        if self.topology.pole_at_end() && id + 1 == self.nodes.len() {
            out.extend((n - 1) * m..n * m);
            return;
        }
        let (a, b) = ((id - start) % self.la, start + (id - start) / self.la);
        // Patches along one direction holding lattice index `x` (`count` patches, closed or not).
        let along = |x: usize, count: usize, closed: bool| -> [Option<usize>; 2] {
            let k = x / 3;
            let here = (k < count).then_some(k);
            let before = if !x.is_multiple_of(3) {
                None
            } else if k >= 1 {
                Some(k - 1)
            } else if closed {
                Some(count - 1)
            } else {
                None
            };
            [here, before]
        };
        for iu in along(a, m, self.topology.closed_u()).into_iter().flatten() {
            for iv in along(b, n, self.topology.closed_v()).into_iter().flatten() {
                out.push(iv * m + iu);
            }
        }
    }

    pub(crate) fn shape(&self) -> Shape {
        Shape {
            topology: self.topology,
            la: self.la,
            lb: self.lb,
        }
    }
}

/// Mean of `|P₊ − P₀| / |P₀ − P₋|` over rows with both lengths well above rounding; 1 when
/// no row qualifies or the mean is not a positive finite number.
fn mean_ratio(rows: impl Iterator<Item = (Option<DVec3>, Option<DVec3>, Option<DVec3>)>) -> f64 {
    let mut sum = 0.0;
    let mut count = 0usize;
    for r in rows {
        let (Some(m), Some(o), Some(p)) = r else {
            continue;
        };
        let (lm, lp) = ((o - m).length(), (p - o).length());
        let scale = m.length().max(o.length()).max(p.length()).max(1.0);
        if lm > 1e-9 * scale && lp > 1e-9 * scale {
            sum += lp / lm;
            count += 1;
        }
    }
    let r = if count > 0 { sum / count as f64 } else { 1.0 };
    if r.is_finite() && r > 0.0 { r } else { 1.0 }
}

fn lattice_dims(topology: Topology, m: usize, n: usize) -> (usize, usize) {
    let la = 3 * m + usize::from(!topology.closed_u());
    let lb = 3 * n + usize::from(!topology.closed_v());
    (la, lb)
}

/// The index arithmetic of a net, apart from its points.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Shape {
    pub(crate) topology: Topology,
    pub(crate) la: usize,
    pub(crate) lb: usize,
}

impl Shape {
    pub(crate) fn is_pole_row(&self, b: usize) -> bool {
        (b == 0 && self.topology.pole_at_start())
            || (b + 1 == self.lb && self.topology.pole_at_end())
    }

    pub(crate) fn node_id(&self, a: isize, b: isize) -> Option<usize> {
        let (la, lb) = (self.la as isize, self.lb as isize);
        let a = if self.topology.closed_u() {
            a.rem_euclid(la)
        } else if (0..la).contains(&a) {
            a
        } else {
            return None;
        };
        let b = if self.topology.closed_v() {
            b.rem_euclid(lb)
        } else if (0..lb).contains(&b) {
            b
        } else {
            return None;
        };
        Some(self.id_unchecked(a as usize, b as usize))
    }

    #[inline]
    fn id_unchecked(&self, a: usize, b: usize) -> usize {
        let start = usize::from(self.topology.pole_at_start());
        if start == 1 && b == 0 {
            return 0;
        }
        if self.topology.pole_at_end() && b + 1 == self.lb {
            return start + (self.lb - 1 - start) * self.la;
        }
        start + (b - start) * self.la + a
    }

    /// The node ids of patch `(iu, iv)` (`iu < M`, `iv < N`), `ids[4*i + j]` =
    /// [`Shape::local_id`]`(iu, iv, i, j)`: the four columns and the four rows' offsets worked
    /// out once (a pole row's nodes are all the pole).
    #[inline]
    pub(crate) fn patch_ids(&self, iu: usize, iv: usize) -> [usize; 16] {
        let start = usize::from(self.topology.pole_at_start());
        let pole_end = self.topology.pole_at_end();
        let (a0, b0) = (3 * iu, 3 * iv);
        let mut ids = [0; 16];
        // Most patches: no seam crossed, no pole row; the ids are `base + j L_a + i`.
        if a0 + 3 < self.la && b0 + 3 < self.lb && b0 >= start && !(pole_end && b0 + 4 == self.lb) {
            let base = start + (b0 - start) * self.la + a0;
            for i in 0..4 {
                for j in 0..4 {
                    ids[4 * i + j] = base + j * self.la + i;
                }
            }
            return ids;
        }
        let wrap = |x: usize, n: usize| if x >= n { x - n } else { x };
        let cols = [0, 1, 2, 3].map(|i| wrap(a0 + i, self.la));
        for j in 0..4 {
            let b = wrap(b0 + j, self.lb);
            // The id of column 0 and whether the id follows the column.
            let (base, step) = if start == 1 && b == 0 {
                (0, 0)
            } else if pole_end && b + 1 == self.lb {
                (start + (self.lb - 1 - start) * self.la, 0)
            } else {
                (start + (b - start) * self.la, 1)
            };
            for i in 0..4 {
                ids[4 * i + j] = base + step * cols[i];
            }
        }
        ids
    }

    /// The id of column 0 of lattice row `b` (`b < L_b`) and whether the id follows the column
    /// (a pole row is one node): the id of `(a, b)` is `base + step · a`.
    #[inline]
    fn row(&self, b: usize) -> (usize, usize) {
        let start = usize::from(self.topology.pole_at_start());
        if start == 1 && b == 0 {
            (0, 0)
        } else if self.topology.pole_at_end() && b + 1 == self.lb {
            (start + (self.lb - 1 - start) * self.la, 0)
        } else {
            (start + (b - start) * self.la, 1)
        }
    }

    /// The node ids of the three rows of control points along the edge between patches
    /// `a = (iu, iv)` and `b`, `b` after `a` along u when `along_u` (else along v): `a`'s row
    /// next to the edge (local index 2 across it), the edge (`a`'s 3), `b`'s row next to it
    /// (`b`'s 1); each `[k]` for `k = 0..4` along the edge.
    #[inline]
    // `ids[r][k]` follows the rows `r` across the edge and `k` along it.
    #[allow(clippy::needless_range_loop)]
    pub(crate) fn edge_ids(
        &self,
        a: (usize, usize),
        b: (usize, usize),
        along_u: bool,
    ) -> [[usize; 4]; 3] {
        let wrap = |x: usize, n: usize| if x >= n { x - n } else { x };
        let mut ids = [[0; 4]; 3];
        if along_u {
            let across = [
                3 * a.0 + 2,
                wrap(3 * a.0 + 3, self.la),
                wrap(3 * b.0 + 1, self.la),
            ];
            for k in 0..4 {
                let (base, step) = self.row(wrap(3 * a.1 + k, self.lb));
                for r in 0..3 {
                    ids[r][k] = base + step * across[r];
                }
            }
        } else {
            let across = [
                3 * a.1 + 2,
                wrap(3 * a.1 + 3, self.lb),
                wrap(3 * b.1 + 1, self.lb),
            ];
            for r in 0..3 {
                let (base, step) = self.row(across[r]);
                for k in 0..4 {
                    ids[r][k] = base + step * wrap(3 * a.0 + k, self.la);
                }
            }
        }
        ids
    }

    /// Node id of local point `(i, j)` of patch `(iu, iv)`.
    #[inline]
    pub(crate) fn local_id(&self, iu: usize, iv: usize, i: usize, j: usize) -> usize {
        let mut a = 3 * iu + i;
        if a >= self.la {
            a -= self.la;
        }
        let mut b = 3 * iv + j;
        if b >= self.lb {
            b -= self.lb;
        }
        self.id_unchecked(a, b)
    }
}

#[cfg(test)]
mod tests;
