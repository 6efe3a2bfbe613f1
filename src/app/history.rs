//! Undo and redo as a stack of whole-model snapshots.
//!
//! A snapshot is the model as it was before an edit (a 40 × 40-patch grid is about 0.4 MB), so
//! undo is exact and needs no inverse of any operation. The stack holds at most
//! [`History::DEPTH`] snapshots; the oldest are dropped first.

use crate::model::Model;

/// Undo and redo stacks.
#[derive(Debug, Clone, Default)]
pub struct History {
    undo: Vec<(String, Model)>,
    redo: Vec<(String, Model)>,
}

impl History {
    /// Most snapshots kept for undo.
    pub const DEPTH: usize = 200;

    /// Records `before`, the model as it was before the edit named `what`; clears redo.
    pub fn record(&mut self, what: impl Into<String>, before: Model) {
        self.undo.push((what.into(), before));
        if self.undo.len() > Self::DEPTH {
            self.undo.remove(0);
        }
        self.redo.clear();
    }

    /// Undoes the last edit: returns the model to restore, given the current one (kept for
    /// redo); `None` when there is nothing to undo.
    pub fn undo(&mut self, current: Model) -> Option<Model> {
        let (what, before) = self.undo.pop()?;
        self.redo.push((what, current));
        Some(before)
    }

    /// Redoes the last undone edit, given the current model (kept for undo).
    pub fn redo(&mut self, current: Model) -> Option<Model> {
        let (what, after) = self.redo.pop()?;
        self.undo.push((what, current));
        Some(after)
    }

    /// The name of the edit undo would revert.
    #[must_use]
    pub fn undo_name(&self) -> Option<&str> {
        self.undo.last().map(|(w, _)| w.as_str())
    }

    /// The name of the edit redo would reapply.
    #[must_use]
    pub fn redo_name(&self) -> Option<&str> {
        self.redo.last().map(|(w, _)| w.as_str())
    }

    /// Forgets everything (a new or opened model).
    pub fn clear(&mut self) {
        self.undo.clear();
        self.redo.clear();
    }

    /// Number of edits that can be undone.
    #[must_use]
    pub fn undo_len(&self) -> usize {
        self.undo.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Primitive, PrimitiveParams};
    use glam::DVec3;

    fn plane(n: usize) -> Model {
        let params = PrimitiveParams {
            patches: Some((n, n)),
            ..PrimitiveParams::default()
        };
        Model::new(Primitive::Plane.build(&params).expect("plane"))
    }

    #[test]
    fn undo_then_redo_restores_each_state() {
        let (a, b, c) = (plane(1), plane(2), plane(3));
        let mut h = History::default();
        h.record("to b", a.clone());
        h.record("to c", b.clone());
        let mut now = c.clone();
        now = h.undo(now).expect("undo to b");
        assert_eq!(now, b);
        now = h.undo(now).expect("undo to a");
        assert_eq!(now, a);
        assert!(h.undo(now.clone()).is_none());
        now = h.redo(now).expect("redo to b");
        assert_eq!(now, b);
        assert_eq!(h.redo_name(), Some("to c"));
        // A new edit drops what could have been redone.
        h.record("elsewhere", now.clone());
        assert!(h.redo(now).is_none());
        let _ = DVec3::ZERO;
    }
}
