//! The document being edited: the model, where it lives on disk, its undo history, and a
//! revision number that changes with every edit (what the display and the autosave watch).
//!
//! ## Strokes
//!
//! A stroke (many operations while the button is held) is one undo step:
//! [`Document::begin_stroke`], then the operations, then [`Document::end_stroke`] — or
//! [`Document::cancel_stroke`], which puts back exactly the surface the stroke started from.
//! The operations come in two kinds:
//!
//! - **shown** ([`Document::show_in_stroke`], a live push, groove or move): each replaces the
//!   last, applied afresh to the stroke's start `S₀` through the engine's
//!   [`LiveOperation`] — the one "re-apply from the start" there is, shared with the hand's
//!   pinch. Before each operation the document puts `S₀` back from the live operation's
//!   journal (the first old position of every control point the last one wrote: bit for bit,
//!   at the cost of what it touched), lets the caller move the stroke onto a finer grid of
//!   `S₀` (auto-refinement, without losing the way back to the original grid), then shows the
//!   operation;
//! - **added** ([`Document::apply`], [`Document::add_to_stroke`], a smoothing stroke's dabs):
//!   each works on the surface the earlier ones left. Adding makes whatever is shown part of
//!   the stroke (the live operation settles).
//!
//! ## The file on disk
//!
//! The document remembers what its file held when it was opened or last saved, as a
//! [`DiskStamp`]: the length `n` and the 64-bit FNV-1a hash of the bytes,
//! `h₀ = 0xcbf29ce484222325`, `hₖ₊₁ = (hₖ ⊕ bₖ) · 0x100000001b3 (mod 2⁶⁴)`.
//! [`Document::changed_on_disk`] compares it with the file now, so a save does not silently
//! overwrite another program's changes (the modification time is not used: a rewrite with the
//! same bytes is no change, and a change within the clock's resolution still is one).
//!
//! Every change is noted with the patches it changed, so the history compares only those when
//! the stroke ends and [`Document::surface_changes_since`] tells the display which patches to
//! re-tessellate.

use glam::DVec3;
use std::path::{Path, PathBuf};
use std::time::Instant;

use std::collections::VecDeque;

use super::history::{History, Restored};
use crate::curve::Curve;
use crate::curve::json::DynCurve;
use crate::model::{Model, ModelError};
use crate::surface::{
    Grid, LiveOperation, Op, Regulation, Sculptor, SurfaceError, Symmetry, Touched,
};

/// What a file held: its length and the FNV-1a hash of its bytes (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DiskStamp {
    /// Bytes.
    pub len: u64,
    /// 64-bit FNV-1a of the bytes.
    pub hash: u64,
}

impl DiskStamp {
    /// The stamp of `bytes`.
    #[must_use]
    pub fn of_bytes(bytes: &[u8]) -> Self {
        let hash = bytes.iter().fold(0xcbf2_9ce4_8422_2325_u64, |h, &b| {
            (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
        });
        Self {
            len: bytes.len() as u64,
            hash,
        }
    }

    /// The stamp of the file at `path` now; `Ok(None)` when there is no file.
    ///
    /// # Errors
    /// When the file is there but cannot be read.
    pub fn of_file(path: &Path) -> std::io::Result<Option<Self>> {
        // At most one byte more than a model file may hold: a larger file differs from any
        // model loaded, whatever its stamp.
        let mut bytes = Vec::new();
        let read = std::fs::File::open(path).and_then(|f| {
            std::io::Read::read_to_end(
                &mut std::io::Read::take(f, crate::model::MAX_FILE_BYTES + 1),
                &mut bytes,
            )
        });
        match read {
            Ok(_) => Ok(Some(Self::of_bytes(&bytes))),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(e),
        }
    }
}

/// What the last sculpting operation did and cost.
#[derive(Debug, Clone, PartialEq)]
pub struct OpTiming {
    /// Milliseconds spent in the deformation (inverse mapping and regulation).
    pub ms: f64,
    /// Patches changed.
    pub patches: usize,
}

/// The model being edited.
#[derive(Debug)]
pub struct Document {
    model: Model,
    /// The file it was opened from or last saved to.
    pub path: Option<PathBuf>,
    history: History,
    revision: u64,
    /// The revision last saved to (or opened from) a file; `None` when the model is in no
    /// file at all (a recovered autosave).
    saved_revision: Option<u64>,
    sculptor: Sculptor,
    /// The operation shown in the stroke in progress ([`Document::show_in_stroke`]), with the
    /// journal that puts the stroke's start back.
    live: LiveOperation,
    /// The last sculpting operation's cost.
    pub last_op: Option<OpTiming>,
    /// Operations applied since recording started, when recording.
    pub recording: Option<Vec<Op>>,
    /// The stroke in progress: the recording's length when it began.
    stroke: Option<usize>,
    /// What the last revisions changed on the surface, oldest first.
    surface_log: VecDeque<(u64, SurfaceChange)>,
    /// The file as it was when opened or last saved, and its stamp then.
    disk: Option<(PathBuf, DiskStamp)>,
}

/// What one revision changed on the surface.
#[derive(Debug, Clone, PartialEq)]
enum SurfaceChange {
    /// The control points of these patches (sorted); empty: nothing on the surface.
    Patches(Vec<usize>),
    /// Anything (a new model, an edit that did not say what it touched).
    Everything,
}

/// Revisions [`Document::surface_changes_since`] can look back over.
const SURFACE_LOG_LEN: usize = 256;

impl Document {
    /// A document holding `model`, not yet saved anywhere.
    #[must_use]
    pub fn new(model: Model) -> Self {
        Self {
            history: History::new(&model),
            model,
            path: None,
            revision: 0,
            saved_revision: Some(0),
            sculptor: Sculptor::new(),
            live: LiveOperation::new(),
            last_op: None,
            recording: None,
            stroke: None,
            surface_log: VecDeque::new(),
            disk: None,
        }
    }

    /// Bumps the revision, noting what it changed on the surface.
    fn bump(&mut self, change: SurfaceChange) {
        self.revision += 1;
        if self.surface_log.len() == SURFACE_LOG_LEN {
            self.surface_log.pop_front();
        }
        self.surface_log.push_back((self.revision, change));
    }

    /// The patches whose control points changed after `revision` up to now (sorted; empty
    /// when only curves, the regulation or nothing changed), or `None` when that is not known
    /// (a new model, an edit that did not say, a revision too far back): then anything may
    /// have changed.
    #[must_use]
    pub fn surface_changes_since(&self, revision: u64) -> Option<Vec<usize>> {
        if revision == self.revision {
            return Some(Vec::new());
        }
        if revision > self.revision {
            return None;
        }
        let first = self
            .surface_log
            .iter()
            .position(|(r, _)| *r == revision + 1)?;
        let mut patches = Vec::new();
        for (_, change) in self.surface_log.iter().skip(first) {
            match change {
                SurfaceChange::Patches(p) => patches.extend_from_slice(p),
                SurfaceChange::Everything => return None,
            }
        }
        patches.sort_unstable();
        patches.dedup();
        Some(patches)
    }

    fn note_restored(&mut self, restored: Restored) {
        self.bump(match restored {
            Restored::Patches(p) => SurfaceChange::Patches(p),
            Restored::Everything => SurfaceChange::Everything,
        });
    }

    /// Opens a model file.
    ///
    /// # Errors
    /// As [`Model::read`].
    pub fn open(path: &Path) -> Result<Self, ModelError> {
        // Taken before the read: a change in between is seen as a change at the next save.
        let stamp = DiskStamp::of_file(path).ok().flatten();
        let loaded = Model::read(path)?;
        let mut doc = Self::new(loaded.model);
        doc.path = Some(path.to_path_buf());
        doc.disk = stamp.map(|s| (path.to_path_buf(), s));
        Ok(doc)
    }

    /// What the document's file held when the document read or wrote it (`None`: not known).
    #[must_use]
    pub fn disk_stamp(&self) -> Option<DiskStamp> {
        self.disk
            .as_ref()
            .filter(|(p, _)| self.path.as_deref() == Some(p.as_path()))
            .map(|(_, s)| *s)
    }

    /// Sets what the document's file held when its work began (a recovered autosave's
    /// record of it).
    pub fn set_disk_stamp(&mut self, stamp: Option<DiskStamp>) {
        self.disk = self.path.clone().zip(stamp);
    }

    /// True when `path` is the file the document was opened from or last saved to, and it
    /// holds something else now (another program wrote it). A file gone since, or one the
    /// document never read, is no change.
    #[must_use]
    pub fn changed_on_disk(&self, path: &Path) -> bool {
        let Some((file, stamp)) = &self.disk else {
            return false;
        };
        let same = file == path
            || matches!(
                (std::fs::canonicalize(file), std::fs::canonicalize(path)),
                (Ok(a), Ok(b)) if a == b
            );
        // A file that cannot be read now is left to the write to report.
        same && DiskStamp::of_file(path).is_ok_and(|now| now.is_some_and(|n| n != *stamp))
    }

    /// Saves the model to `path` (atomically) and remembers it as the document's file.
    ///
    /// # Errors
    /// As [`Model::write`].
    pub fn save(&mut self, path: &Path) -> Result<(), ModelError> {
        self.model.write(path)?;
        self.path = Some(path.to_path_buf());
        self.saved_revision = Some(self.revision);
        // Read back (the window's save holds the file's writer lock meanwhile).
        self.disk = DiskStamp::of_file(path)
            .ok()
            .flatten()
            .map(|s| (path.to_path_buf(), s));
        Ok(())
    }

    /// Marks the whole model as unsaved work (a recovered autosave: it is in no file the user
    /// chose), dirty until it is saved.
    pub fn mark_unsaved(&mut self) {
        self.saved_revision = None;
    }

    /// The model.
    #[must_use]
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// Changes with every edit, undo and redo.
    #[must_use]
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// True when there are edits not saved to [`Document::path`].
    #[must_use]
    pub fn is_dirty(&self) -> bool {
        self.saved_revision != Some(self.revision)
    }

    /// The undo history.
    #[must_use]
    pub fn history(&self) -> &History {
        &self.history
    }

    /// Applies a sculpting operation (with the model's regulation), recording it for undo (as
    /// one step, or as part of the stroke in progress) and, when recording, in the recording.
    /// Costs what the operation touches (the history notes the touched patches only).
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] for an invalid operation; nothing changes then.
    pub fn apply(&mut self, op: &Op) -> Result<Touched, SurfaceError> {
        let touched = self.apply_unnoted(op, None)?;
        self.bump(SurfaceChange::Patches(touched.patches.clone()));
        Ok(touched)
    }

    /// [`Document::apply`] without the revision bump (the caller bumps once for a frame).
    /// With `mirror`, the operation is applied together with its mirror image
    /// ([`Sculptor::apply_mirrored`]); the recording keeps the one-sided operation.
    fn apply_unnoted(
        &mut self,
        op: &Op,
        mirror: Option<&Symmetry>,
    ) -> Result<Touched, SurfaceError> {
        op.validate()?;
        // What is shown becomes part of the stroke: this operation works on it.
        self.live.settle();
        if self.stroke.is_none() {
            self.history.commit(&self.model);
        }
        let start = Instant::now();
        let regulation = self.model.regulation;
        let touched = match mirror {
            Some(m) => self
                .sculptor
                .apply_mirrored(&mut self.model.surface, op, regulation, m)?,
            None => self
                .sculptor
                .apply(&mut self.model.surface, op, regulation)?,
        };
        self.last_op = Some(OpTiming {
            ms: start.elapsed().as_secs_f64() * 1e3,
            patches: touched.patches.len(),
        });
        let what = super::stroke::edit_name(op);
        if self.stroke.is_none() {
            self.history.begin(what, &self.model);
            self.history.touch_patches(&touched.patches);
            self.history.commit(&self.model);
        } else {
            self.history.touch_patches(&touched.patches);
        }
        if let Some(rec) = &mut self.recording {
            rec.push(op.clone());
        }
        Ok(touched)
    }

    /// Begins a stroke named `what` (`"push"`, `"draw a line"`…): the operations applied until
    /// [`Document::end_stroke`] make one undo step. Ends a stroke in progress first.
    pub fn begin_stroke(&mut self, what: &str) {
        self.end_stroke();
        self.history.begin(what, &self.model);
        self.stroke = Some(self.recording.as_ref().map_or(0, Vec::len));
    }

    /// True while a stroke is in progress.
    #[must_use]
    pub fn in_stroke(&self) -> bool {
        self.stroke.is_some()
    }

    /// Ends the stroke in progress, recording it as one undo step (costs what it touched).
    pub fn end_stroke(&mut self) {
        self.live.settle();
        if self.stroke.take().is_some() {
            self.history.commit(&self.model);
        }
    }

    /// Cancels the stroke in progress: the surface (and the recording) go back exactly to
    /// what they were when it began, and nothing is recorded for undo. False when no stroke
    /// was in progress.
    pub fn cancel_stroke(&mut self) -> bool {
        let Some(recorded) = self.stroke.take() else {
            return false;
        };
        // The shown operation from its journal, then what was added (or the original grid of
        // a refined stroke) from the history.
        let shown = self.live.cancel(&mut self.model.surface);
        let restored = self.history.revert(&mut self.model);
        if let Some(rec) = &mut self.recording {
            rec.truncate(recorded);
        }
        self.bump(match restored {
            Restored::Patches(mut p) => {
                p.extend_from_slice(&shown);
                p.sort_unstable();
                p.dedup();
                SurfaceChange::Patches(p)
            }
            Restored::Everything => SurfaceChange::Everything,
        });
        true
    }

    /// One frame of a live stroke, as one revision: puts back the stroke's start (what the
    /// last shown operation wrote, from its journal), moves the stroke onto the grid `prepare`
    /// gives for that start if it gives one (an auto-refinement where the finger reaches: the
    /// same surface, more patches — the undo step still leads from the model the stroke began
    /// with, and a cancel puts that model back, grid and all), then shows `op` on it: the
    /// surface is exactly `apply(S₀, op)`, what the same operation applied once makes. The
    /// recording holds `op` in place of the last one shown.
    ///
    /// `prepare` sees the start and gives the finer grid to move onto, if any, and the mirror
    /// map to apply `op` with (`None`: one-sided).
    ///
    /// Returns `None` when no stroke is in progress (nothing done); otherwise the patches whose
    /// control points `op` changed, sorted (empty for no `op`: the start is shown), or why it
    /// was refused — then the start is shown. The revision notes the patches put back and
    /// those `op` changed (everything after a refinement); nothing when neither changed
    /// anything.
    pub fn show_in_stroke<'m>(
        &mut self,
        op: Option<&Op>,
        prepare: impl FnOnce(&Grid) -> (Option<Grid>, Option<&'m Symmetry>),
    ) -> Option<Result<Vec<usize>, SurfaceError>> {
        let recorded = self.stroke?;
        if let Some(rec) = &mut self.recording {
            rec.truncate(recorded);
        }
        let mut change = SurfaceChange::Patches(self.live.cancel(&mut self.model.surface));
        let (finer, mirror) = prepare(&self.model.surface);
        if let Some(finer) = finer {
            self.model.surface = finer;
            self.history.rebase_open(&self.model);
            change = SurfaceChange::Everything;
        }
        let result = match op {
            None => Ok(Vec::new()),
            Some(op) => self.show_op(op, mirror),
        };
        if let (Ok(changed), SurfaceChange::Patches(p)) = (&result, &mut change) {
            p.extend_from_slice(changed);
            p.sort_unstable();
            p.dedup();
        }
        if change != SurfaceChange::Patches(Vec::new()) {
            self.bump(change);
        }
        Some(result)
    }

    /// Shows `op` through the live operation (nothing shown before it: the start), noting what
    /// it changed for the history and the recording.
    fn show_op(&mut self, op: &Op, mirror: Option<&Symmetry>) -> Result<Vec<usize>, SurfaceError> {
        op.validate()?;
        let start = Instant::now();
        let regulation = self.model.regulation;
        let changed = self
            .live
            .show(&mut self.model.surface, op, regulation, mirror)?
            .to_vec();
        self.last_op = Some(OpTiming {
            ms: start.elapsed().as_secs_f64() * 1e3,
            patches: changed.len(),
        });
        self.history.touch_patches(&changed);
        if let Some(rec) = &mut self.recording {
            rec.push(op.clone());
        }
        Ok(changed)
    }

    /// Applies `op` on top of what the stroke in progress has done so far (a smoothing
    /// stroke's dabs: each works on the surface the previous ones left), as one revision
    /// noting the patches it changed. `prepare` is as for [`Document::show_in_stroke`]: a finer
    /// grid to move onto first (the undo step and a cancel still lead back to the model the
    /// stroke began with) and the mirror map. `None` when no stroke is in progress (nothing
    /// done).
    pub fn add_to_stroke<'m>(
        &mut self,
        op: &Op,
        prepare: impl FnOnce(&Grid) -> (Option<Grid>, Option<&'m Symmetry>),
    ) -> Option<Result<Touched, SurfaceError>> {
        self.stroke?;
        self.live.settle();
        let (finer, mirror) = prepare(&self.model.surface);
        let mut change = SurfaceChange::Patches(Vec::new());
        if let Some(finer) = finer {
            self.model.surface = finer;
            self.history.rebase_open(&self.model);
            change = SurfaceChange::Everything;
        }
        let result = self.apply_unnoted(op, mirror);
        if let (Ok(touched), SurfaceChange::Patches(p)) = (&result, &mut change) {
            p.extend_from_slice(&touched.patches);
        }
        if change != SurfaceChange::Patches(Vec::new()) {
            self.bump(change);
        }
        Some(result)
    }

    /// Renames the stroke in progress (a stroke named after its final operation). False
    /// when no stroke was in progress.
    pub fn rename_stroke(&mut self, what: &str) -> bool {
        self.stroke.is_some() && self.history.rename_open(what)
    }

    /// Runs `f` on the surface with the model's regulation (a hand loop deforming it); `f`
    /// returns how many patches it changed, and any change bumps the revision. Undo is the
    /// caller's ([`Document::record_undo`]). Not knowing which patches changed, the display
    /// and the history compare everything; [`Document::sculpt_patches`] avoids that.
    pub fn sculpt_surface<R>(&mut self, f: impl FnOnce(&mut Grid, Regulation) -> (R, usize)) -> R {
        self.live.settle();
        let start = Instant::now();
        let regulation = self.model.regulation;
        let (out, patches) = f(&mut self.model.surface, regulation);
        if patches > 0 {
            self.history.touch_everything();
            self.bump(SurfaceChange::Everything);
            self.last_op = Some(OpTiming {
                ms: start.elapsed().as_secs_f64() * 1e3,
                patches,
            });
        }
        out
    }

    /// [`Document::sculpt_surface`] for an `f` that returns the patches it changed (sorted or
    /// not): the history and the display then cost what those patches hold.
    pub fn sculpt_patches<R>(
        &mut self,
        f: impl FnOnce(&mut Grid, Regulation) -> (R, Vec<usize>),
    ) -> R {
        self.live.settle();
        let start = Instant::now();
        let regulation = self.model.regulation;
        let (out, mut patches) = f(&mut self.model.surface, regulation);
        if !patches.is_empty() {
            patches.sort_unstable();
            patches.dedup();
            self.history.touch_patches(&patches);
            self.last_op = Some(OpTiming {
                ms: start.elapsed().as_secs_f64() * 1e3,
                patches: patches.len(),
            });
            self.bump(SurfaceChange::Patches(patches));
        }
        out
    }

    /// Records the edit `what` as starting from `before` (an edit made through
    /// [`Document::sculpt_surface`], noticed once it changed something): the undo step it
    /// makes leads from `before` to the model as it is when the next edit begins (or undo is
    /// asked for), so later frames of the same contact belong to it.
    pub fn record_undo(&mut self, what: &str, before: Model) {
        self.history.begin_from(what, before);
    }

    /// Adds operations made by other means than [`Document::apply`] (a hand contact) to the
    /// recording, when recording.
    pub fn record_ops(&mut self, ops: &[Op]) {
        if let Some(rec) = &mut self.recording {
            rec.extend_from_slice(ops);
        }
    }

    /// Replaces the whole model (a new primitive, a recovered autosave, a replayed trace) as
    /// one undoable edit.
    /// A model of another shape (other patch counts, a refinement) is kept whole in the
    /// history; one of the same shape as the differences of its control points.
    pub fn replace(&mut self, what: &str, model: Model) {
        self.end_stroke();
        self.history.begin(what, &self.model);
        self.model = model;
        self.history.touch_everything();
        self.history.commit(&self.model);
        self.bump(SurfaceChange::Everything);
    }

    /// Starts an edit made of many small changes (a curve drag): one undo step from here to
    /// the next edit. Follow with [`Document::curves_mut`] changes.
    pub fn begin_edit(&mut self, what: &str) {
        self.end_stroke();
        self.history.begin(what, &self.model);
    }

    /// The curves, for an edit begun with [`Document::begin_edit`] (bumps the revision).
    pub fn curves_mut(&mut self) -> &mut Vec<DynCurve> {
        self.bump(SurfaceChange::Patches(Vec::new()));
        &mut self.model.curves
    }

    /// Changes the regulation method (undoable).
    pub fn set_regulation(&mut self, regulation: crate::surface::Regulation) {
        if self.model.regulation != regulation {
            self.begin_edit("regulation");
            self.model.regulation = regulation;
            self.history.commit(&self.model);
            self.bump(SurfaceChange::Patches(Vec::new()));
        }
    }

    /// Undoes the last edit (ending a stroke in progress first); false when there was none.
    /// Costs what the edit changed.
    pub fn undo(&mut self) -> bool {
        self.end_stroke();
        match self.history.undo(&mut self.model) {
            Some(restored) => {
                self.note_restored(restored);
                true
            }
            None => false,
        }
    }

    /// Redoes the last undone edit; false when there was none.
    pub fn redo(&mut self) -> bool {
        self.end_stroke();
        match self.history.redo(&mut self.model) {
            Some(restored) => {
                self.note_restored(restored);
                true
            }
            None => false,
        }
    }

    /// The 3D curves (2D curves are drawn in the plane z = 0 but not edited), with their
    /// indices in the model.
    #[must_use]
    pub fn curves_3d(&self) -> Vec<(usize, &Curve<DVec3>)> {
        self.model
            .curves
            .iter()
            .enumerate()
            .filter_map(|(i, c)| match c {
                DynCurve::D3(c) => Some((i, c)),
                DynCurve::D2(_) => None,
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Primitive, PrimitiveParams};

    #[test]
    fn sculpting_is_undoable_and_marks_the_document_dirty() {
        let plane = Primitive::Plane
            .build(&PrimitiveParams::default())
            .expect("plane");
        let mut doc = Document::new(Model::new(plane));
        let original = doc.model().clone();
        assert!(!doc.is_dirty());
        let op = Op::Push {
            at: DVec3::new(0.5, 0.5, 0.0),
            dir: -DVec3::Z,
            depth: 0.4,
            radius: 1.25,
        };
        doc.apply(&op).expect("a valid push");
        assert!(doc.is_dirty());
        assert_ne!(doc.model(), &original);
        assert!(doc.undo());
        assert_eq!(doc.model(), &original);
        assert!(doc.redo());
        assert_ne!(doc.model(), &original);
        let bad = Op::Push {
            at: DVec3::ZERO,
            dir: DVec3::ZERO,
            depth: 0.4,
            radius: 1.25,
        };
        let revision = doc.revision();
        assert!(doc.apply(&bad).is_err());
        assert_eq!(doc.revision(), revision, "a rejected op changes nothing");
    }

    #[test]
    fn a_stroke_the_regulation_cannot_keep_g1_is_refused_and_changes_nothing() {
        // A pull of 30 sides at the pole of the default sphere folds the ring around it
        // (the window shows the error on its status line).
        let sphere = Primitive::Sphere
            .build(&PrimitiveParams::default())
            .expect("sphere");
        let top = sphere.nodes().iter().map(|p| p.z).fold(f64::MIN, f64::max);
        let mut doc = Document::new(Model::new(sphere));
        let original = doc.model().clone();
        let pull = Op::Push {
            at: DVec3::new(0.0, 0.0, top),
            dir: -DVec3::Z,
            depth: -30.0,
            radius: 0.5,
        };
        let err = doc.apply(&pull).expect_err("the folded pull is refused");
        assert!(matches!(err, SurfaceError::NotG1 { .. }), "{err}");
        assert_eq!(doc.model(), &original);
        assert!(!doc.is_dirty());
    }

    #[test]
    fn an_unsaved_document_stays_dirty_through_undo_until_saved() {
        let plane = Primitive::Plane
            .build(&PrimitiveParams::default())
            .expect("plane");
        let mut doc = Document::new(Model::new(plane));
        doc.mark_unsaved();
        assert!(doc.is_dirty(), "recovered work is unsaved");
        let op = Op::Push {
            at: DVec3::new(0.5, 0.5, 0.0),
            dir: -DVec3::Z,
            depth: 0.4,
            radius: 1.25,
        };
        doc.apply(&op).expect("push");
        assert!(doc.undo());
        assert!(doc.is_dirty(), "undo does not make it saved");
        let path = std::env::temp_dir().join(format!(
            "nendo-doc-unsaved-{}.nendo.json",
            std::process::id()
        ));
        doc.save(&path).expect("save");
        assert!(!doc.is_dirty());
        let _ = std::fs::remove_file(&path);
    }
}
