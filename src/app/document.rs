//! The document being edited: the model, where it lives on disk, its undo history, and a
//! revision number that changes with every edit (what the display and the autosave watch).

use glam::DVec3;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::history::History;
use crate::curve::Curve;
use crate::curve::json::DynCurve;
use crate::model::{Model, ModelError};
use crate::surface::{Grid, Op, Regulation, Sculptor, SurfaceError, Touched};

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
    /// The last sculpting operation's cost.
    pub last_op: Option<OpTiming>,
    /// Operations applied since recording started, when recording.
    pub recording: Option<Vec<Op>>,
}

impl Document {
    /// A document holding `model`, not yet saved anywhere.
    #[must_use]
    pub fn new(model: Model) -> Self {
        Self {
            model,
            path: None,
            history: History::default(),
            revision: 0,
            saved_revision: Some(0),
            sculptor: Sculptor::new(),
            last_op: None,
            recording: None,
        }
    }

    /// Opens a model file.
    ///
    /// # Errors
    /// As [`Model::read`].
    pub fn open(path: &Path) -> Result<Self, ModelError> {
        let loaded = Model::read(path)?;
        let mut doc = Self::new(loaded.model);
        doc.path = Some(path.to_path_buf());
        Ok(doc)
    }

    /// Saves the model to `path` (atomically) and remembers it as the document's file.
    ///
    /// # Errors
    /// As [`Model::write`].
    pub fn save(&mut self, path: &Path) -> Result<(), ModelError> {
        self.model.write(path)?;
        self.path = Some(path.to_path_buf());
        self.saved_revision = Some(self.revision);
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

    /// Applies a sculpting operation (with the model's regulation), recording it for undo and,
    /// when recording, in the recording.
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] for an invalid operation; nothing changes then.
    pub fn apply(&mut self, op: &Op) -> Result<Touched, SurfaceError> {
        op.validate()?;
        let before = self.model.clone();
        let start = Instant::now();
        let regulation = self.model.regulation;
        let touched = self
            .sculptor
            .apply(&mut self.model.surface, op, regulation)?;
        self.last_op = Some(OpTiming {
            ms: start.elapsed().as_secs_f64() * 1e3,
            patches: touched.patches.len(),
        });
        let what = super::stroke::edit_name(op);
        self.history.record(what, before);
        if let Some(rec) = &mut self.recording {
            rec.push(op.clone());
        }
        self.revision += 1;
        Ok(touched)
    }

    /// Runs `f` on the surface with the model's regulation (a hand loop deforming it); `f`
    /// returns how many patches it changed, and any change bumps the revision. Undo is the
    /// caller's ([`Document::record_undo`]).
    pub fn sculpt_surface<R>(&mut self, f: impl FnOnce(&mut Grid, Regulation) -> (R, usize)) -> R {
        let start = Instant::now();
        let regulation = self.model.regulation;
        let (out, patches) = f(&mut self.model.surface, regulation);
        if patches > 0 {
            self.revision += 1;
            self.last_op = Some(OpTiming {
                ms: start.elapsed().as_secs_f64() * 1e3,
                patches,
            });
        }
        out
    }

    /// Records `before` for undo as the edit `what` (an edit made through
    /// [`Document::sculpt_surface`]).
    pub fn record_undo(&mut self, what: &str, before: Model) {
        self.history.record(what, before);
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
    pub fn replace(&mut self, what: &str, model: Model) {
        let before = std::mem::replace(&mut self.model, model);
        self.history.record(what, before);
        self.revision += 1;
    }

    /// Starts an edit made of many small changes (a curve drag): records the model once for
    /// undo. Follow with [`Document::curves_mut`] changes.
    pub fn begin_edit(&mut self, what: &str) {
        self.history.record(what, self.model.clone());
    }

    /// The curves, for an edit begun with [`Document::begin_edit`] (bumps the revision).
    pub fn curves_mut(&mut self) -> &mut Vec<DynCurve> {
        self.revision += 1;
        &mut self.model.curves
    }

    /// Changes the regulation method (undoable).
    pub fn set_regulation(&mut self, regulation: crate::surface::Regulation) {
        if self.model.regulation != regulation {
            self.begin_edit("regulation");
            self.model.regulation = regulation;
            self.revision += 1;
        }
    }

    /// Undoes the last edit; false when there was none.
    pub fn undo(&mut self) -> bool {
        match self.history.undo(self.model.clone()) {
            Some(m) => {
                self.model = m;
                self.revision += 1;
                true
            }
            None => false,
        }
    }

    /// Redoes the last undone edit; false when there was none.
    pub fn redo(&mut self) -> bool {
        match self.history.redo(self.model.clone()) {
            Some(m) => {
                self.model = m;
                self.revision += 1;
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
