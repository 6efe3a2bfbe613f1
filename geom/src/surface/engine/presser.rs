//! The envelope of several finger placements applied as one displacement field: the
//! operation of one contact of the hand (`nendo::hand`) — the finger's placements while it
//! touched the clay, applied together to the surface as it was before the contact.
//!
//! Public API: [`Presser::begin`] starts a contact on a reference grid, [`Presser::apply`]
//! makes a grid the reference deformed by the envelope of a list of [`Placement`]s (refusing,
//! and leaving the grid as it was, a result [`crate::surface::verify()`] rejects), and [`describe`] lists the
//! shape-function operations the placements stand for. Nothing outside this crate needs the
//! control-point storage or the regulation internals to deform a grid.
//!
//! Limits: the placements of one stroke share one finger radius and capsule length (several
//! strokes — several fingers, the palm — each have their own, see [`Stroke`]); the engine keeps
//! its own unregulated net, so a contact must be applied to the grid it was begun on (a grid
//! of another size starts a new contact).
//!
//! A contact is a sequence of finger placements `T_0, T_1, …` (pressed fingertip, direction
//! `d̂_j`, depth `D_j`). The first is a push (P2 §5.1: the finger half-line ending at
//! `T_0`, `M = D_0·d̂_0`); every later one is a draw-a-line segment (§5.2) from the previous
//! pressed tip to `T_j`, its finger centre-line `L_f = D_j·d̂_j` and stroke `M_f = T_j − T_{j−1}`
//! — the paper's polyline, one segment at a time, each with its own `L_f`.
//!
//! A contact of the whole hand is several such polylines at once, one [`Stroke`] per finger
//! (and the palm) that touched: each starts with its own push, and all their placements join
//! the one envelope below — one displacement field, regulated once.
//!
//! The paper's shape functions are displacement fields: a sample within `r_f` of a finger
//! moves by `(1 − r²/r_f²)·M` wherever it already is. Applied one after another, two
//! overlapping placements press the clay between them twice — a stroke drawn frame by frame
//! would cut a groove twice as deep as the finger went, since the clay behind the moving
//! finger is pressed again by every later frame. Here every sample of the surface before the
//! contact moves by the **strongest** of the placements' flows, `F = argmax_j |F_j|` (the mean of
//! the equally strongest: the engine's one envelope rule, [`super::field`]): the
//! envelope of the finger's passage. Within one draw-a-line of constant `d̂` and depth that is
//! exactly the surface module's own rule for a polyline (the distance to the union of the swept
//! strips, so the joints are not pressed twice), and a contact of one placement is exactly a
//! push.
//!
//! The contact is applied like [`crate::surface::deform()`] applies one operation, through the
//! same [`super::field::displace`] and [`super::commit::Commit`] — reachable
//! patches from the box pyramid, 16 samples and flows per patch, the Bernstein inverse
//! `ΔP = B₄⁻¹ F B₄⁻ᵀ`, the pole moved by its own sample's flow, regulation of the groups around
//! the moved patches — with the envelope of several fingers in place of one, and
//! incrementally: a frame recomputes only what its changed placements reach.

use glam::DVec3;

use super::commit::{Commit, other_grid};
use super::field::{DisplacementField, Envelope, displace};
use crate::surface::Isometry;
use crate::surface::bounds::Aabb;
use crate::surface::error::SurfaceError;
use crate::surface::grid::Grid;
use crate::surface::group::PoleEnd;
use crate::surface::marks::Marks;
use crate::surface::mirror::Symmetry;
use crate::surface::regulate::Regulation;
use crate::surface::shape_fn::{Finger, Op};
use crate::surface::topology::wrap;

/// One placement of the finger during a contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// The pressed fingertip `T_j`.
    pub tip: DVec3,
    /// The unit direction `d̂_j` the finger points in.
    pub dir: DVec3,
    /// How far the finger presses along `d̂_j` (negative: the clay is pulled back with it).
    pub depth: f64,
}

/// The operations a contact's placements stand for: a push at the first, then one
/// draw-a-line segment per later placement (see the module docs; applied one after another
/// they would press overlaps twice — the contact applies them as an envelope).
#[must_use]
pub fn describe(placements: &[Placement], radius: f64) -> Vec<Op> {
    let mut ops = Vec::with_capacity(placements.len());
    for (j, p) in placements.iter().enumerate() {
        let at = p.tip - p.depth * p.dir;
        ops.push(match j {
            0 => Op::Push {
                at,
                dir: p.dir,
                depth: p.depth,
                radius,
            },
            _ => Op::Drag {
                path: vec![placements[j - 1].tip - p.depth * p.dir, at],
                dir: p.dir,
                depth: p.depth,
                radius,
            },
        });
    }
    ops
}

/// The placements of one finger (or the palm) during a contact: a push at the first, a
/// draw-a-line segment to each later one, with the finger's radius `r_f` and capsule length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stroke<'a> {
    /// The placements, in the order the finger made them.
    pub placements: &'a [Placement],
    /// The finger radius `r_f` of the shape functions.
    pub radius: f64,
    /// How far behind the pressed tips the finger reaches (see [`Presser::apply`]).
    pub length: f64,
}

/// A placement with its stroke's settings, as the engine keeps them.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Seg {
    placement: Placement,
    /// The first placement of its stroke: a push (else a segment from the one before).
    start: bool,
    radius: f64,
    length: f64,
}

/// A placement's finger and the segment of pressed tips it sweeps (one point for the push).
#[derive(Debug, Clone)]
struct Reach {
    finger: Finger,
    from: DVec3,
    to: DVec3,
    dir: DVec3,
    /// How far behind the tips the finger reaches.
    length: f64,
    /// Holds every point within the finger radius of the capsule (tips to `length` behind).
    bounds: Aabb,
    /// Its flows on the patches it was asked about (see [`Memo`]).
    memo: Memo,
}

/// What a finger did to the patches of the reference it was asked about, kept while the
/// finger stays in the contact (a placement that does not change keeps its finger, and the
/// reference does not change during a contact): per patch, whether the finger may touch it,
/// and if so its flows at the patch's 16 reference samples (then, with a mirror, the mirrored
/// finger's). A frame that recomputes a patch reads the flows of the fingers it kept instead
/// of evaluating them again: the same numbers, so the same envelope. A clone starts empty.
#[derive(Debug, Default)]
struct Memo {
    /// `(patch, offset of its flows in `flows`)`, [`Memo::NONE`] for a patch not touched.
    patches: Vec<(usize, usize)>,
    flows: Vec<DVec3>,
}

impl Memo {
    const NONE: usize = usize::MAX;

    fn find(&self, patch: usize) -> Option<usize> {
        self.patches
            .iter()
            .find(|(q, _)| *q == patch)
            .map(|&(_, at)| at)
    }
}

impl Clone for Memo {
    /// Empty: a cache, not part of the finger.
    fn clone(&self) -> Self {
        Memo::default()
    }
}

impl Reach {
    /// Whether the finger may move something in the box.
    fn may_touch(&self, b: &Aabb) -> bool {
        self.overlaps(b) && self.finger.may_touch(b, self.length)
    }

    /// Whether the box meets the finger's bounds (the cheap first half of `may_touch`).
    fn overlaps(&self, b: &Aabb) -> bool {
        self.bounds.min.cmple(b.max).all() && b.min.cmple(self.bounds.max).all()
    }

    /// The flow of the finger at `x`, zero when `x` is more than `length` behind the tips
    /// along the finger (out of the capsule's reach).
    fn flow(&self, x: DVec3) -> DVec3 {
        let length = self.length;
        let e = self.to - self.from;
        let t = if e.length_squared() > 0.0 {
            ((x - self.from).dot(e) / e.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let behind = -(x - (self.from + t * e)).dot(self.dir);
        if behind > length {
            DVec3::ZERO
        } else {
            self.finger.flow(x)
        }
    }
}

/// Applies contacts incrementally; keeps the contact's unregulated net and its buffers.
///
/// The surface during a contact is a pure function of the placements: every patch moved by
/// `reference + ΔP` (the Bernstein inverse of its envelope flows) into an *unregulated* net,
/// and every control-point group with a moved patch around it regulated from that net; the
/// other groups keep the reference. When placements change, only the patches the changed
/// placements reach (before or after the change) are recomputed, and the groups at their
/// corners re-regulated — with the paper's methods and group by group, a group depends on its
/// own points only, so the cost of a frame follows what the finger did in it; with the
/// default exact regulation, whose solve couples the groups, every touched group connected to
/// those is re-regulated too ([`Presser::couple_components`]), so a continuous stroke costs
/// each frame what it has touched so far.
#[derive(Debug, Clone, Default)]
pub struct Presser {
    /// The contact's net before regulation.
    unregulated: Vec<DVec3>,
    /// Per patch: whether the envelope moves it.
    deformed: Vec<bool>,
    /// The placements of the last application.
    applied: Vec<Seg>,
    /// The placements of this application.
    pending: Vec<Seg>,
    /// The fingers of the last application, one per placement.
    fingers: Vec<Reach>,
    /// The fingers of this application (swapped into `fingers` when it is accepted).
    next: Vec<Reach>,
    /// Per finger of this application: whether it is new (not one of the last application's).
    fresh: Vec<bool>,
    /// Per finger of the last application: whether this application keeps it.
    kept: Vec<bool>,
    area: Vec<usize>,
    area_marks: Marks,
    vertex_marks: Marks,
    /// The fingers near the patch at hand, with the offset of their flows there.
    near: Vec<(usize, usize)>,
    regulate: Vec<(usize, usize)>,
    /// Vertices whose touched neighbours join the coupled solve (see
    /// [`Presser::couple_components`]).
    queue: Vec<(usize, usize)>,
    poles: Vec<PoleEnd>,
    /// The patches the last application changed.
    changed: Vec<usize>,
    /// The unregulated net and `deformed` flags of the area before this application.
    saved_unregulated: Vec<(usize, DVec3)>,
    saved_deformed: Vec<(usize, bool)>,
    /// Regulation, mirror, verification or rollback of each application.
    commit: Commit,
    /// Every placement pressed together with its mirror image (see [`Presser::set_mirror`]).
    mirror: Option<Symmetry>,
}

impl Presser {
    /// Presses every placement together with its mirror image across the symmetry's plane
    /// (`None`: no mirror): the mirrored fingers join the envelope (each sample follows the
    /// strongest flow of all), and after the regulation the touched control points and their
    /// partners are made exactly symmetric ([`Symmetry::enforce`]). The grids applied must be
    /// the ones the symmetry was made for: [`Presser::apply`] refuses others.
    pub fn set_mirror(&mut self, symmetry: Option<Symmetry>) {
        self.mirror = symmetry;
        // The fingers' memos hold the flows of the mirror they were made with.
        for f in &mut self.fingers {
            f.memo = Memo::default();
        }
    }

    /// The mirror set by [`Presser::set_mirror`].
    #[must_use]
    pub fn mirror(&self) -> Option<&Symmetry> {
        self.mirror.as_ref()
    }

    /// Starts a contact on `reference` (the surface as it is).
    pub fn begin(&mut self, reference: &Grid) {
        self.unregulated.clear();
        self.unregulated.extend_from_slice(reference.nodes());
        self.deformed.clear();
        self.deformed.resize(reference.patch_count(), false);
        self.applied.clear();
        self.fingers.clear();
        self.commit.start_contact();
    }

    /// Makes `grid` (which holds the previous application, or `reference` after
    /// [`Presser::begin`]) the surface `reference` deformed by the envelope of `placements`.
    /// The finger is a capsule `length` long: clay further than that behind the pressed tips
    /// is out of reach (the shape functions' finger extends back without end, which from
    /// inside a closed shape would press the opposite wall too). Returns the patches whose
    /// control points changed, sorted.
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] for a placement that makes no valid finger, or a mirror
    /// ([`Presser::set_mirror`]) made for a grid of other patch counts;
    /// [`SurfaceError::OutOfRange`] or [`SurfaceError::NotG1`] for a result the surface
    /// refuses ([`crate::surface::verify`]). `grid` and the contact's state are then left as
    /// they were after the last accepted application.
    pub fn apply(
        &mut self,
        reference: &Grid,
        grid: &mut Grid,
        placements: &[Placement],
        radius: f64,
        length: f64,
        regulation: Regulation,
    ) -> Result<&[usize], SurfaceError> {
        let stroke = Stroke {
            placements,
            radius,
            length,
        };
        self.apply_strokes(reference, grid, &[stroke], regulation)
    }

    /// [`Presser::apply`] for several strokes at once — every finger (and the palm) of a
    /// contact of the whole hand, each with its own radius and length: the envelope of all
    /// their placements, regulated once. One stroke is exactly [`Presser::apply`].
    ///
    /// # Errors
    /// As [`Presser::apply`].
    pub fn apply_strokes(
        &mut self,
        reference: &Grid,
        grid: &mut Grid,
        strokes: &[Stroke<'_>],
        regulation: Regulation,
    ) -> Result<&[usize], SurfaceError> {
        self.changed.clear();
        if self.unregulated.len() != reference.nodes().len() {
            self.begin(reference);
        }
        if let Some(s) = &self.mirror
            && !(s.fits(reference) && s.fits(grid))
        {
            return Err(other_grid());
        }
        let mut pending = std::mem::take(&mut self.pending);
        pending.clear();
        for s in strokes {
            pending.extend(s.placements.iter().enumerate().map(|(j, &placement)| Seg {
                placement,
                start: j == 0,
                radius: s.radius,
                length: s.length,
            }));
        }
        let result = self.apply_segs(reference, grid, &pending, regulation);
        self.pending = pending;
        result.map(|()| &self.changed[..])
    }

    fn apply_segs(
        &mut self,
        reference: &Grid,
        grid: &mut Grid,
        placements: &[Seg],
        regulation: Regulation,
    ) -> Result<(), SurfaceError> {
        if placements == &self.applied[..] {
            return Ok(());
        }
        // Which fingers changed. A placement's finger depends on the placement and, within a
        // stroke, on the one before it; strokes are matched by their order (a contact's parts
        // keep theirs), placements within a stroke by their position. A finger whose
        // placement and predecessor are those of the last application is that application's
        // finger, and every patch it alone reaches keeps its flows: only the patches a new
        // finger or a dropped one reaches are recomputed (the fingers stay in the order of
        // the placements, so the envelope's choice between equal flows does not change).
        self.next.clear();
        self.fresh.clear();
        self.kept.clear();
        self.kept.resize(self.applied.len(), false);
        let (mut j, mut i) = (0, 0);
        while j < placements.len() {
            let end = stroke_end(placements, j);
            let old_end = stroke_end(&self.applied, i);
            for k in 0..end - j {
                let same = i + k < old_end
                    && placements[j + k] == self.applied[i + k]
                    && (k == 0 || placements[j + k - 1] == self.applied[i + k - 1]);
                if same {
                    self.kept[i + k] = true;
                    // The finger with its memo (the last application's list keeps the finger,
                    // for going back, without the memo: a cache).
                    let kept = &mut self.fingers[i + k];
                    let mut f = kept.clone();
                    f.memo = std::mem::take(&mut kept.memo);
                    self.next.push(f);
                } else {
                    self.next.push(reach(placements, j + k)?);
                }
                self.fresh.push(!same);
            }
            j = end;
            i = old_end;
        }
        self.commit.begin(grid);
        self.vertex_marks
            .start(grid.vertices_u() * grid.vertices_v());

        // 1. The patches the changed placements reach, before and after the change.
        self.area.clear();
        self.area_marks.start(reference.patch_count());
        let images: Vec<(Isometry, Isometry)> = self
            .mirror
            .as_ref()
            .map_or(&[][..], Symmetry::field_images)
            .iter()
            .map(|g| (*g, g.inverse()))
            .collect();
        let new = self.next.iter().zip(&self.fresh).filter(|(_, f)| **f);
        let dropped = self.fingers.iter().zip(&self.kept).filter(|(_, k)| !**k);
        for (f, _) in new.chain(dropped) {
            let start = self.area.len();
            reference.hierarchy().query(
                &|b| f.may_touch(b) || images.iter().any(|(_, inv)| f.may_touch(&inv.apply_box(b))),
                &mut self.area,
            );
            let mut keep = start;
            for k in start..self.area.len() {
                let p = self.area[k];
                if self.area_marks.mark(p) {
                    self.area[keep] = p;
                    keep += 1;
                }
            }
            self.area.truncate(keep);
        }
        self.area.sort_unstable();

        // 2–3. Envelope flows on the reference samples, Bernstein inverse, unregulated net.
        let (m, n) = (grid.patches_u(), grid.patches_v());
        let topology = grid.topology();
        self.saved_unregulated.clear();
        self.saved_deformed.clear();
        for &p in &self.area {
            self.saved_deformed.push((p, self.deformed[p]));
            for id in grid.patch_node_ids(p % m, p / m) {
                self.saved_unregulated.push((id, self.unregulated[id]));
            }
        }
        let mut field = ContactField {
            fingers: &mut self.next,
            near: &mut self.near,
            images: &images,
        };
        let (unregulated, deformed) = (&mut self.unregulated, &mut self.deformed);
        displace(reference, &self.area, &mut field, |p, delta| {
            let ids = reference.patch_node_ids(p % m, p / m);
            deformed[p] = delta.is_some();
            match delta {
                None => {
                    for id in ids {
                        unregulated[id] = reference.nodes()[id];
                    }
                }
                // Shared control points get bit-identical updates from every patch holding
                // them (see `field`), so writing `reference + ΔP` from each is consistent.
                Some(delta) => {
                    for (k, &id) in ids.iter().enumerate() {
                        unregulated[id] = reference.nodes()[id] + delta[k];
                    }
                }
            }
        });

        // 4. The groups at the corners of those patches: from the unregulated net, regulated
        // when a patch around them moved.
        let (vu, vv) = (grid.vertices_u(), grid.vertices_v());
        self.regulate.clear();
        self.queue.clear();
        self.poles.clear();
        let mut pole_rows = [false; 2];
        for i in 0..self.area.len() {
            let p = self.area[i];
            // A patch the envelope moves neither now nor before keeps the reference: nothing
            // of it changes (a group at its corners that must be re-regulated is reached from
            // a moved patch, or through `couple_components`).
            if !self.deformed[p] && !self.saved_deformed[i].1 {
                continue;
            }
            let (iu, iv) = (p % m, p / m);
            self.commit.include(p);
            if regulation == Regulation::None {
                // Nothing is regulated: the grid is the unregulated net.
                for id in grid.patch_node_ids(iu, iv) {
                    self.commit.write(grid, id, self.unregulated[id]);
                }
                continue;
            }
            for (du, dv) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let (k, q) = ((iu + du) % vu, (iv + dv) % vv);
                if grid.is_pole_line(q) {
                    pole_rows[usize::from(q != 0)] = true;
                    continue;
                }
                if !self.vertex_marks.mark(q * vu + k) {
                    continue;
                }
                if !self.unregulate_group(grid, k, q) {
                    continue;
                }
                let mut moved = false;
                for (eu, ev) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let Some(pu) = wrap(k as isize - eu, m, topology.closed_u()) else {
                        continue;
                    };
                    let Some(pv) = wrap(q as isize - ev, n, topology.closed_v()) else {
                        continue;
                    };
                    let around = pv * m + pu;
                    moved |= self.deformed[around];
                    self.commit.include(around);
                }
                if moved {
                    self.regulate.push((k, q));
                }
                self.queue.push((k, q));
            }
        }
        if regulation.promises_g1() && self.commit.projections.coupled {
            self.couple_components(grid);
        }
        for (row, end) in [(0, PoleEnd::Start), (1, PoleEnd::End)] {
            if !pole_rows[row] {
                continue;
            }
            let Some(pole) = grid.pole(end) else { continue };
            for &id in std::iter::once(&pole.node).chain(&pole.ring) {
                self.commit.write(grid, id, self.unregulated[id]);
            }
            let iv = if end == PoleEnd::Start { 0 } else { n - 1 };
            let mut moved = false;
            for iu in 0..m {
                let around = iv * m + iu;
                moved |= self.deformed[around];
                self.commit.include(around);
            }
            if moved {
                self.poles.push(end);
            }
        }
        match self.commit.finish(
            grid,
            regulation,
            &self.regulate,
            &self.poles,
            self.mirror.as_ref(),
            None,
        ) {
            Ok(_) => {
                self.changed.extend_from_slice(self.commit.changed());
                self.applied.clear();
                self.applied.extend_from_slice(placements);
                std::mem::swap(&mut self.fingers, &mut self.next);
                Ok(())
            }
            Err(e) => {
                // Back to the last application: the grid (rolled back by the commit), the
                // unregulated net, the fingers.
                for &(id, x) in self.saved_unregulated.iter().rev() {
                    self.unregulated[id] = x;
                }
                for &(p, d) in &self.saved_deformed {
                    self.deformed[p] = d;
                }
                Err(e)
            }
        }
    }

    /// The coupled projection ([`crate::surface::regulate`]) makes a group's regulated points
    /// a function of the unregulated net of every group in its *connected touched set* (groups
    /// with a moved patch around them, linked when they are corners of one patch), not of its
    /// own patches alone. So a frame re-regulates, besides the groups at the corners of the
    /// patches it reaches (`queue` on entry, already reset to the unregulated net), every
    /// touched group connected to them: their points go back to the unregulated net and their
    /// patches join the changed ones. A group outside these sets has the same connected set,
    /// with the same unregulated net, as when it was last regulated, and keeps its points —
    /// the frame-by-frame result is the contact applied at once.
    fn couple_components(&mut self, grid: &mut Grid) {
        let (m, n) = (grid.patches_u(), grid.patches_v());
        let (vu, vv) = (grid.vertices_u(), grid.vertices_v());
        let topology = grid.topology();
        let around = |k: usize, q: usize| {
            let mut out = [None; 4];
            for (slot, (eu, ev)) in [(0, 0), (1, 0), (0, 1), (1, 1)].into_iter().enumerate() {
                let pu = wrap(k as isize - eu, m, topology.closed_u());
                let pv = wrap(q as isize - ev, n, topology.closed_v());
                if let (Some(pu), Some(pv)) = (pu, pv) {
                    out[slot] = Some(pv * m + pu);
                }
            }
            out
        };
        let mut next = 0;
        while next < self.queue.len() {
            let (k, q) = self.queue[next];
            next += 1;
            for (dk, dq) in [
                (-1, -1),
                (0, -1),
                (1, -1),
                (-1, 0),
                (1, 0),
                (-1, 1),
                (0, 1),
                (1, 1),
            ] {
                let Some(k2) = wrap(k as isize + dk, vu, topology.closed_u()) else {
                    continue;
                };
                let Some(q2) = wrap(q as isize + dq, vv, topology.closed_v()) else {
                    continue;
                };
                if grid.is_pole_line(q2) {
                    continue;
                }
                let v = q2 * vu + k2;
                if self.vertex_marks.get(v) {
                    continue;
                }
                let patches = around(k2, q2);
                if !patches.iter().flatten().any(|&p| self.deformed[p]) {
                    continue;
                }
                self.vertex_marks.set(v);
                if !self.unregulate_group(grid, k2, q2) {
                    continue;
                }
                for p in patches.into_iter().flatten() {
                    self.commit.include(p);
                }
                self.regulate.push((k2, q2));
                self.queue.push((k2, q2));
            }
        }
    }

    /// Puts the nodes of the group at vertex `(k, q)` back to the unregulated net (the commit
    /// journals what they held); `false` (nothing changed) when the vertex has no group.
    fn unregulate_group(&mut self, grid: &mut Grid, k: usize, q: usize) -> bool {
        let Some(group) = grid.group(k, q) else {
            return false;
        };
        for id in group.nodes.iter().flatten().flatten() {
            self.commit.write(grid, *id, self.unregulated[*id]);
        }
        true
    }
}

/// The fingers of one application as a [`DisplacementField`] on the contact's reference:
/// each finger's flows at a patch's samples come from its memo, or are evaluated and kept.
struct ContactField<'a> {
    fingers: &'a mut [Reach],
    /// The fingers near the patch at hand, with the offset of their flows there.
    near: &'a mut Vec<(usize, usize)>,
    /// The symmetry's images of the field, each with its inverse (empty: none).
    images: &'a [(Isometry, Isometry)],
}

impl DisplacementField for ContactField<'_> {
    fn may_touch(&self, b: &Aabb) -> bool {
        self.fingers.iter().any(|f| {
            f.may_touch(b)
                || self
                    .images
                    .iter()
                    .any(|(_, inv)| f.may_touch(&inv.apply_box(b)))
        })
    }

    fn touches(&mut self, _patch: usize, _bounds: &Aabb) -> bool {
        true
    }

    fn flows(&mut self, p: usize, bounds: &Aabb, r: &[DVec3; 16]) -> [DVec3; 16] {
        let images = self.images;
        let mirrored: Vec<Aabb> = images
            .iter()
            .map(|(_, inv)| inv.apply_box(bounds))
            .collect();
        self.near.clear();
        for (k, f) in self.fingers.iter_mut().enumerate() {
            if !(f.overlaps(bounds) || mirrored.iter().any(|b| f.overlaps(b))) {
                continue;
            }
            let at = match f.memo.find(p) {
                Some(at) => at,
                None => {
                    let touches = f.may_touch(bounds) || mirrored.iter().any(|b| f.may_touch(b));
                    let at = if touches {
                        let at = f.memo.flows.len();
                        for x in r {
                            let flow = f.flow(*x);
                            f.memo.flows.push(flow);
                        }
                        // g F(g⁻¹ x) for every image g.
                        for (g, inv) in images {
                            for x in r {
                                let flow = g.apply(f.flow(inv.apply(*x)));
                                f.memo.flows.push(flow);
                            }
                        }
                        at
                    } else {
                        Memo::NONE
                    };
                    f.memo.patches.push((p, at));
                    at
                }
            };
            if at != Memo::NONE {
                self.near.push((k, at));
            }
        }
        // Every sample follows the envelope of the fingers' flows and their mirror images'.
        std::array::from_fn(|k| {
            let mut e = Envelope::default();
            for &(f, at) in self.near.iter() {
                let memo = &self.fingers[f].memo.flows;
                e.add(memo[at + k]);
                for i in 0..images.len() {
                    e.add(memo[at + 16 * (i + 1) + k]);
                }
            }
            e.flow()
        })
    }
}

/// The end of the stroke that starts at `j` (the next placement that starts a stroke, or the
/// end of the list); `j` itself at the end of the list.
fn stroke_end(placements: &[Seg], j: usize) -> usize {
    if j >= placements.len() {
        return j;
    }
    placements[j + 1..]
        .iter()
        .position(|s| s.start)
        .map_or(placements.len(), |k| j + 1 + k)
}

/// The finger of `placements[j]` (see [`describe`]; a placement that starts a stroke is a
/// push).
fn reach(placements: &[Seg], j: usize) -> Result<Reach, SurfaceError> {
    let Seg {
        placement: p,
        start,
        radius,
        length,
    } = placements[j];
    let from = if start || j == 0 {
        p.tip
    } else {
        placements[j - 1].placement.tip
    };
    let op = if start || j == 0 {
        Op::Push {
            at: p.tip - p.depth * p.dir,
            dir: p.dir,
            depth: p.depth,
            radius,
        }
    } else {
        Op::Drag {
            path: vec![from - p.depth * p.dir, p.tip - p.depth * p.dir],
            dir: p.dir,
            depth: p.depth,
            radius,
        }
    };
    let finger = op.finger()?;
    // The shape function's finger ends `|depth| − depth` past the fingertip (at it for a push;
    // beyond it for a pull, whose finger mirrors the push).
    let back = length * p.dir;
    let ahead = (p.depth.abs() - p.depth) * p.dir;
    let bounds =
        Aabb::of_points(&[from - back, p.tip - back, from + ahead, p.tip + ahead]).inflated(radius);
    Ok(Reach {
        finger,
        from,
        to: p.tip,
        dir: p.dir,
        length,
        bounds,
        memo: Memo::default(),
    })
}

#[cfg(test)]
mod tests;
