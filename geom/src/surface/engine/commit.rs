//! The transaction every deformation ends in (docs/design.md §11, steps 4–5): regulation around what
//! moved → the mirror → verification, then either the new boxes or an exact rollback.
//!
//! A [`Commit`] keeps a journal of the first old position of every control point written
//! during one operation ([`Commit::write`], [`Commit::keep`]) and the set of patches whose
//! control points may change ([`Commit::include`]). [`Commit::finish`] then
//!
//! 1. regulates the groups and poles it is given ([`regulate::regulate`]); under
//!    [`Regulation::G2`] then projects a window around the included patches onto the
//!    curvature-continuous nets ([`regulate::g2`]), taking in the window's patches (a
//!    contact of the hand projects its own exact net there, see [`G2Contact`]),
//! 2. with a symmetry, takes in the images of every included patch under every isometry of
//!    the group and makes their control points exactly symmetric ([`Symmetry::enforce`]), then takes in every other patch holding
//!    a control point that moved; a mirror made for a grid of other patch counts is an error,
//!    never dropped,
//! 3. lands a move's grabbed point exactly on its target ([`grab::land`]),
//! 4. verifies the result ([`verify_marked`]: coordinates within the limit, G1 under
//!    [`Regulation::Exact`] and [`Regulation::G2`], G2 under the latter),
//! 5. refits the boxes of the included patches — or, on any refusal, puts every journaled
//!    control point back, so the grid is bit for bit as it was.

use glam::DVec3;

use crate::surface::error::SurfaceError;
use crate::surface::grab::{self, Hold};
use crate::surface::grid::Grid;
use crate::surface::group::PoleEnd;
use crate::surface::marks::Marks;
use crate::surface::mirror::Symmetry;
use crate::surface::regulate::g2::G2Cache;
use crate::surface::regulate::{self, Projections, Regulation};
use crate::surface::topology::wrap;
use crate::surface::verify::verify_marked;

/// One operation's transaction; keeps its buffers between operations.
#[derive(Debug, Clone, Default)]
pub(crate) struct Commit {
    /// `(node, first old position)` of every node written, each node once.
    journal: Vec<(usize, DVec3)>,
    journaled: Marks,
    /// The patches whose control points may change.
    changed: Vec<usize>,
    included: Marks,
    verify_marks: Marks,
    pub(crate) projections: Projections,
    scratch: Vec<usize>,
    /// The positions of the nodes given to the mirror, before it.
    before_mirror: Vec<DVec3>,
    /// The nodes the mirror moved.
    moved_by_mirror: Marks,
    asymmetry: f64,
    /// The g2 step's projections, kept for the next operation on the same window.
    g2_cache: G2Cache,
    /// A contact's g2 state ([`Commit::start_contact`]); `None` for one-off operations.
    contact: Option<G2Contact>,
}

/// What the g2 step of a contact of the hand keeps between frames.
///
/// A contact ([`super::presser`]) re-applies its envelope every frame to the grid as the last
/// frame left it, re-regulating (exactly) only the groups the changed fingers reach. Were the
/// g2 step then to project the grid, it would project the last frame's g2 result in the window's
/// margin, where the exact step wrote nothing this frame: each frame would move it a little
/// further (a held contact drifted ≈ 3e-3 side per frame) and the result would depend on the
/// frames' history. So the contact keeps its **exact net** — the grid as `exact` alone would
/// leave it: the reference, with every node the exact step writes updated — and every frame
/// the g2 step projects that net, in the window around the patches where it differs from the
/// reference, with `α` measured on the reference. A node a former frame's window made free and
/// this one does not goes back to the exact net. The g2 result is therefore a function of the
/// contact's exact net alone, which is itself a function of the placements: the same
/// placements give the same surface, bit for bit, whatever came before them.
#[derive(Debug, Clone, Default)]
struct G2Contact {
    /// The grid at the contact's start (empty until the first g2 step).
    reference: Vec<DVec3>,
    /// The exact net.
    exact: Vec<DVec3>,
    /// The last g2 step's free nodes (sorted) and window patches.
    free: Vec<usize>,
    patches: Vec<usize>,
    /// This operation's changes to the above, for a rollback.
    undo_exact: Vec<(usize, DVec3)>,
    undo_window: Option<(Vec<usize>, Vec<usize>)>,
}

impl G2Contact {
    /// Back to the state before this operation's g2 step.
    fn undo(&mut self) {
        for &(id, x) in self.undo_exact.iter().rev() {
            self.exact[id] = x;
        }
        self.undo_exact.clear();
        if let Some((free, patches)) = self.undo_window.take() {
            self.free = free;
            self.patches = patches;
        }
    }
}

/// The error of a mirror map made for another grid.
pub(super) fn other_grid() -> SurfaceError {
    SurfaceError::BadOp("the mirror map was made for a grid of other patch counts".to_string())
}

impl Commit {
    /// Starts a transaction on `grid`.
    pub(crate) fn begin(&mut self, grid: &Grid) {
        self.journal.clear();
        self.changed.clear();
        self.journaled.start(grid.nodes().len());
        self.included.start(grid.patch_count());
        self.asymmetry = 0.0;
        if let Some(c) = &mut self.contact {
            c.undo_exact.clear();
            c.undo_window = None;
        }
    }

    /// Starts a contact of the hand: the following operations are the frames of one contact,
    /// each applied to the grid the last one left, from the grid as it is at the next
    /// operation's start (see [`G2Contact`]; only the g2 step keeps state).
    pub(crate) fn start_contact(&mut self) {
        self.contact = Some(G2Contact::default());
    }

    /// Adds patch `p` to those whose control points may change.
    #[inline]
    pub(crate) fn include(&mut self, p: usize) {
        if self.included.mark(p) {
            self.changed.push(p);
        }
    }

    /// Journals node `id`'s present position (only its first, the old one, is kept).
    #[inline]
    pub(crate) fn keep(&mut self, grid: &Grid, id: usize) {
        if self.journaled.mark(id) {
            self.journal.push((id, grid.nodes()[id]));
        }
    }

    /// Journals every control point of the included patches.
    pub(crate) fn keep_included(&mut self, grid: &Grid) {
        let m = grid.patches_u();
        for i in 0..self.changed.len() {
            let p = self.changed[i];
            for id in grid.patch_node_ids(p % m, p / m) {
                self.keep(grid, id);
            }
        }
    }

    /// Writes node `id`, journaling its old position.
    #[inline]
    pub(crate) fn write(&mut self, grid: &mut Grid, id: usize, x: DVec3) {
        self.keep(grid, id);
        grid.nodes_mut()[id] = x;
    }

    /// Steps 1–5 of the module docs. `vertices` and `poles` are the groups to regulate (with
    /// `regulation`), `symmetry` the mirror, `hold` a move's landing. Returns how many groups
    /// and poles were regulated; afterwards [`Commit::changed`] lists the included patches,
    /// sorted.
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] for a mirror made for another grid, [`SurfaceError::OutOfRange`]
    /// or [`SurfaceError::NotG1`] for a result [`verify_marked`] refuses; the grid is then as
    /// it was before the first write.
    pub(crate) fn finish(
        &mut self,
        grid: &mut Grid,
        regulation: Regulation,
        vertices: &[(usize, usize)],
        poles: &[PoleEnd],
        symmetry: Option<&Symmetry>,
        hold: Option<&Hold>,
    ) -> Result<usize, SurfaceError> {
        let mut groups = 0;
        if regulation != Regulation::None && (!vertices.is_empty() || !poles.is_empty()) {
            for &end in poles {
                if let Some(pole) = grid.pole(end) {
                    for &id in std::iter::once(&pole.node).chain(&pole.ring) {
                        self.keep(grid, id);
                    }
                }
            }
            groups = regulate::regulate(grid, regulation, vertices, poles, &mut self.projections);
            if regulation == Regulation::G2 {
                self.curvature_step(grid)?;
            }
        }
        if let Some(s) = symmetry {
            if !s.fits(grid) {
                self.rollback(grid);
                return Err(other_grid());
            }
            for i in 0..self.changed.len() {
                let p = self.changed[i];
                for q in s.patch_images(p) {
                    self.include(q);
                }
            }
            self.changed.sort_unstable();
            self.keep_included(grid);
            let isometries: Vec<_> = s.isometries().copied().collect();
            let b = grid.bounds();
            let scale = b
                .min
                .abs()
                .max(b.max.abs())
                .max_element()
                .max(f64::MIN_POSITIVE);
            let m = grid.patches_u();
            let mut worst = 0.0f64;
            self.scratch.clear();
            for &p in &self.changed {
                for id in grid.patch_node_ids(p % m, p / m) {
                    for (e, g) in isometries.iter().enumerate() {
                        let d = (g.apply(grid.nodes()[id]) - grid.nodes()[s.node_image(e, id)])
                            .length();
                        worst = worst.max(d);
                    }
                    self.scratch.push(id);
                }
            }
            self.asymmetry = worst / scale;
            let poles: &[PoleEnd] = if regulation == Regulation::None {
                &[]
            } else {
                poles
            };
            let ids = std::mem::take(&mut self.scratch);
            self.before_mirror.clear();
            self.before_mirror
                .extend(ids.iter().map(|&id| grid.nodes()[id]));
            let enforced = s.enforce(grid, &ids, poles);
            if let Err(e) = enforced {
                self.scratch = ids;
                self.rollback(grid);
                return Err(SurfaceError::BadOp(e.to_string()));
            }
            self.include_enforced(grid, &ids);
            self.scratch = ids;
        }
        if let Some(h) = hold {
            if regulation == Regulation::G2 {
                self.land_g2(grid, h, symmetry);
            } else {
                grab::land(grid, h, symmetry);
            }
        }
        self.changed.sort_unstable();
        if let Err(e) = verify_marked(
            grid,
            &self.changed,
            regulation,
            &self.journal,
            &mut self.verify_marks,
        ) {
            self.rollback(grid);
            return Err(e);
        }
        grid.refit(&self.changed, &mut self.scratch);
        Ok(groups)
    }

    /// The g2 step ([`regulate::g2`]) on the window around the included patches: its writes
    /// journaled, its patches included. On failure the grid is rolled back.
    fn curvature_step(&mut self, grid: &mut Grid) -> Result<(), SurfaceError> {
        if let Some(mut contact) = self.contact.take() {
            let result = self.contact_curvature_step(grid, &mut contact);
            self.contact = Some(contact);
            if result.is_err() {
                self.rollback(grid);
            }
            return result;
        }
        let old = self.first_positions();
        let step = {
            let now = grid.nodes();
            let before = |id: usize| old.get(&id).copied().unwrap_or(now[id]);
            let base = |id: usize| now[id];
            regulate::g2::regulate(grid, &before, &base, &self.changed, &mut self.g2_cache)
        };
        let step = match step {
            Ok(step) => step,
            Err(e) => {
                self.rollback(grid);
                return Err(SurfaceError::G2Singular { patches: e.patches });
            }
        };
        for &p in &step.patches {
            self.include(p);
        }
        self.keep_included(grid);
        for &(id, x) in &step.writes {
            self.write(grid, id, x);
        }
        Ok(())
    }

    /// The g2 step of one frame of a contact ([`G2Contact`]). Every node this operation wrote
    /// so far is the exact step's (a contact's frame writes a node only from its exact net).
    fn contact_curvature_step(
        &mut self,
        grid: &mut Grid,
        c: &mut G2Contact,
    ) -> Result<(), SurfaceError> {
        if c.reference.len() != grid.nodes().len() {
            // The first g2 step of the contact: the grid before this operation.
            let mut reference = grid.nodes().to_vec();
            for &(id, x) in &self.journal {
                reference[id] = x;
            }
            c.exact.clone_from(&reference);
            c.reference = reference;
            c.free.clear();
            c.patches.clear();
        }
        for &(id, _) in &self.journal {
            let x = grid.nodes()[id];
            c.undo_exact.push((id, c.exact[id]));
            c.exact[id] = x;
        }
        let bits = |x: DVec3| x.to_array().map(f64::to_bits);
        let m = grid.patches_u();
        let deformed: Vec<usize> = (0..grid.patch_count())
            .filter(|&p| {
                grid.patch_node_ids(p % m, p / m)
                    .iter()
                    .any(|&id| bits(c.exact[id]) != bits(c.reference[id]))
            })
            .collect();
        let step = if deformed.is_empty() {
            regulate::g2::G2Step::default()
        } else {
            let (reference, exact) = (&c.reference, &c.exact);
            regulate::g2::regulate(
                grid,
                &|id| reference[id],
                &|id| exact[id],
                &deformed,
                &mut self.g2_cache,
            )
            .map_err(|e| SurfaceError::G2Singular { patches: e.patches })?
        };
        // The last window's patches, where its free nodes go back to the exact net, and this
        // one's.
        for &p in c.patches.iter().chain(&step.patches) {
            self.include(p);
        }
        self.keep_included(grid);
        for &id in &c.free {
            if step.free.binary_search(&id).is_err() && bits(grid.nodes()[id]) != bits(c.exact[id])
            {
                self.write(grid, id, c.exact[id]);
            }
        }
        for &(id, x) in &step.writes {
            self.write(grid, id, x);
        }
        let free = std::mem::replace(&mut c.free, step.free);
        let patches = std::mem::replace(&mut c.patches, step.patches);
        c.undo_window = Some((free, patches));
        Ok(())
    }

    /// A move's landing under [`Regulation::G2`]. [`grab::land`] translates whole control-point
    /// groups, which keeps every G1 condition but not the g2 ones (a group's translation `t`
    /// changes `D₂⁺` by `−t` and the right side by `−ρ²t`, and the next seam's `D₂⁻` by `t`),
    /// so the landed net is projected again — which moves the point off its target. Both maps
    /// are linear: the translations are linear in the residual `δ` they remove, and the g2
    /// projection of this window is `P(x + Δ) = P(x) + AΔ` (fixed outer nodes). So with
    /// `S₀ = S(P(x))` and the responses `s_i = S(P(x + Δ(e_i))) − S₀` of the three unit
    /// residuals, the landing that puts the projected point on the target `T` solves the
    /// 3 × 3 system `[s_x s_y s_z] c = T − S₀` (by the pseudo-inverse: a direction a mirror
    /// forbids stays unreached, as without g2), and the result is `P(x + Δ(c))` — G2, and on
    /// the target to rounding.
    fn land_g2(&mut self, grid: &mut Grid, hold: &Hold, symmetry: Option<&Symmetry>) {
        let m = grid.patches_u();
        let (iu, iv) = (hold.patch % m, hold.patch / m);
        let at = |g: &Grid| g.eval(iu, iv, hold.u, hold.v);
        let base: Vec<DVec3> = grid.nodes().to_vec();
        let old = self.first_positions();
        let before = |id: usize| old.get(&id).copied().unwrap_or(base[id]);
        let here = at(grid);
        // Lands the residual `delta` from the base net, projects, and returns the nodes
        // touched; the grid then holds the result.
        let project = |grid: &mut Grid, delta: Option<DVec3>, cache: &mut G2Cache| {
            let mut touched = match delta {
                Some(d) => grab::land(
                    grid,
                    &Hold {
                        to: here + d,
                        ..*hold
                    },
                    symmetry,
                ),
                None => Vec::new(),
            };
            let step = {
                let now = grid.nodes();
                regulate::g2::regulate(grid, &before, &|id: usize| now[id], &self.changed, cache)
            };
            if let Ok(step) = step {
                let nodes = grid.nodes_mut();
                for (id, x) in step.writes {
                    nodes[id] = x;
                    touched.push(id);
                }
            }
            touched
        };
        let restore = |grid: &mut Grid, touched: &[usize]| {
            let nodes = grid.nodes_mut();
            for &id in touched {
                nodes[id] = base[id];
            }
        };
        let mut cache = std::mem::take(&mut self.g2_cache);
        let b = grid.bounds();
        let scale = (b.max - b.min).max_element().max(f64::MIN_POSITIVE);
        let touched = project(grid, None, &mut cache);
        let s0 = at(grid);
        restore(grid, &touched);
        let mut response = nalgebra::Matrix3::zeros();
        for i in 0..3 {
            let touched = project(grid, Some(DVec3::AXES[i] * scale), &mut cache);
            let s = (at(grid) - s0) / scale;
            restore(grid, &touched);
            for r in 0..3 {
                response[(r, i)] = s[r];
            }
        }
        let r = hold.to - s0;
        let c = response
            .svd(true, true)
            .pseudo_inverse(1e-9)
            .map(|inv| inv * nalgebra::Vector3::new(r.x, r.y, r.z))
            .map_or(DVec3::ZERO, |c| DVec3::new(c.x, c.y, c.z));
        let mut touched = project(grid, Some(c), &mut cache);
        self.g2_cache = cache;
        touched.sort_unstable();
        touched.dedup();
        // Journaled with the values before the operation (the base net's, for a node not
        // written before this step).
        for id in touched {
            if self.journaled.mark(id) {
                self.journal.push((id, base[id]));
            }
        }
    }

    /// Every journaled node's position before the operation.
    fn first_positions(&self) -> std::collections::HashMap<usize, DVec3> {
        self.journal.iter().copied().collect()
    }

    /// Takes in the patches outside the included ones that hold a control point the mirror
    /// moved (a shared edge node of an included patch, nudged by rounding where the net was
    /// symmetric only to the last bit; a pole node shared by its whole row): their boxes
    /// change too. `ids` are the nodes the mirror was given, `self.before_mirror` their
    /// positions before it.
    fn include_enforced(&mut self, grid: &Grid, ids: &[usize]) {
        let bits = |x: DVec3| x.to_array().map(f64::to_bits);
        self.moved_by_mirror.start(grid.nodes().len());
        let mut any = false;
        for (&id, &old) in ids.iter().zip(&self.before_mirror) {
            if bits(grid.nodes()[id]) != bits(old) {
                self.moved_by_mirror.set(id);
                any = true;
            }
        }
        if !any {
            return;
        }
        let (m, n) = (grid.patches_u(), grid.patches_v());
        let topology = grid.topology();
        let holds_moved = |grid: &Grid, marks: &Marks, q: usize| {
            grid.patch_node_ids(q % m, q / m)
                .iter()
                .any(|&id| marks.get(id))
        };
        let count = self.changed.len();
        for i in 0..count {
            let p = self.changed[i];
            let (iu, iv) = (p % m, p / m);
            for dv in -1..=1isize {
                for du in -1..=1isize {
                    let (Some(qu), Some(qv)) = (
                        wrap(iu as isize + du, m, topology.closed_u()),
                        wrap(iv as isize + dv, n, topology.closed_v()),
                    ) else {
                        continue;
                    };
                    let q = qv * m + qu;
                    if !self.included.get(q) && holds_moved(grid, &self.moved_by_mirror, q) {
                        self.include(q);
                    }
                }
            }
            // A pole node belongs to every patch of its row.
            let pole_row =
                (iv == 0 && topology.pole_at_start()) || (iv + 1 == n && topology.pole_at_end());
            if pole_row {
                for qu in 0..m {
                    let q = iv * m + qu;
                    if !self.included.get(q) && holds_moved(grid, &self.moved_by_mirror, q) {
                        self.include(q);
                    }
                }
            }
        }
    }

    /// Puts every journaled control point back (the boxes were not refitted yet, or are
    /// refitted by the caller).
    pub(crate) fn rollback(&mut self, grid: &mut Grid) {
        if let Some(c) = &mut self.contact {
            c.undo();
        }
        let nodes = grid.nodes_mut();
        for &(id, x) in &self.journal {
            nodes[id] = x;
        }
    }

    /// The included patches (sorted after [`Commit::finish`]).
    #[must_use]
    pub(crate) fn changed(&self) -> &[usize] {
        &self.changed
    }

    /// Every node written, with its old position.
    #[must_use]
    pub(crate) fn journal(&self) -> &[(usize, DVec3)] {
        &self.journal
    }

    /// How far the result was from symmetric before the mirror made it exact, relative to
    /// the model's size (0 without a mirror).
    #[must_use]
    pub(crate) fn asymmetry(&self) -> f64 {
        self.asymmetry
    }
}
