//! The document's lifecycle: unsaved changes, the questions asked before they are dropped, the
//! action waiting on those answers, autosave and recovery.
//!
//! Two layers:
//!
//! - [`Lifecycle`] is the state machine alone. It does no I/O: it is told what happened (the
//!   user asked to close, answered a question, picked a file, a save worked or failed) and
//!   answers with the [`Next`] step for its owner to carry out. Its stages:
//!
//!   ```text
//!   Editing ──request(action), dirty──▶ Unsaved(action) ──Cancel──▶ Editing
//!      ▲                                   │  │
//!      │                       Discard ────┘  └──Save──▶ (file known) Save(path) ─┐
//!      │                      Proceed(action)             (no file) ChoosingSavePath(action)
//!      │                                                      │ path chosen: Save(path) ─┤
//!      └────────── dialog cancelled / replaced ───────────────┘                          │
//!                    saved(true): Proceed(action) · saved(false): Unsaved(action) ◀──────┘
//!   ```
//!
//!   The pending action (Close, Create, Open) lives in the stage, so it survives the file
//!   dialog that "Save…" opens for a document that has no file yet.
//!
//!   A save to the document's own file that finds the file changed on disk since it was
//!   opened or last saved (another program wrote it: its length or content hash differs,
//!   see [`DiskStamp`](super::document::DiskStamp)) writes nothing and asks
//!   ([`Prompt::ChangedOnDisk`]): overwrite it, save as another file, reload the file
//!   (dropping the edits), or cancel; the action waiting on the save waits on the answer.
//! - Saves take the file's writer lock ([`nendo_file::lock`]) for the check and the write, so
//!   a `nendo sculpt --model m --out m` running at the same time is either done before the
//!   check (and seen by it) or waits for the save.
//! - [`DocumentSession`] is the document with that machine, its autosave file and the exit rules: the
//!   autosave is removed only when it is this session's and holds nothing unsaved.
//!
//! Limits: one question at a time; a Save that fails asks the same question again (the error
//! is the caller's to show).

use std::path::{Path, PathBuf};
use std::time::Instant;

use std::collections::VecDeque;

use super::autosave::{Autosave, Orphan, Recovery};
use super::document::Document;
use crate::model::ModelError;
use crate::surface::{Primitive, PrimitiveParams};

/// The form for a new primitive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrimitiveForm {
    /// Which primitive.
    pub primitive: Primitive,
    /// Patches around (u) and along (v).
    pub patches: (usize, usize),
    /// Radius (major radius of a torus).
    pub radius: f64,
    /// Height of a cylinder or tube.
    pub height: f64,
    /// Minor radius of a torus.
    pub minor_radius: f64,
}

impl PrimitiveForm {
    /// The primitive's own defaults.
    #[must_use]
    pub fn defaults_for(primitive: Primitive) -> Self {
        let d = primitive.defaults();
        Self {
            primitive,
            patches: d.patches,
            radius: d.radius,
            height: d.height,
            minor_radius: d.minor_radius,
        }
    }

    /// The parameters to build the primitive with.
    #[must_use]
    pub fn params(&self) -> PrimitiveParams {
        PrimitiveParams {
            patches: Some(self.patches),
            radius: Some(self.radius),
            height: Some(self.height),
            minor_radius: Some(self.minor_radius),
        }
    }
}

/// Something that replaces or closes the document: it waits for the answer to
/// [`Prompt::Unsaved`] when the document has unsaved changes.
#[derive(Debug, Clone, PartialEq)]
pub enum Pending {
    /// Close the window.
    Close,
    /// Start a new document from the primitive form.
    Create(PrimitiveForm),
    /// Open a model file.
    Open(PathBuf),
}

/// A modal question on screen.
#[derive(Debug, Clone, PartialEq)]
pub enum Prompt {
    /// An autosave from a session that did not close cleanly.
    Recover(PathBuf),
    /// The model has unsaved changes and the action would drop them.
    Unsaved(Pending),
    /// The document's file changed on disk since it was opened or saved: a save would
    /// overwrite another program's work.
    ChangedOnDisk(PathBuf),
}

/// The answers to [`Prompt::ChangedOnDisk`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConflictAnswer {
    /// Save over the file anyway.
    Overwrite,
    /// Save to another file (the save dialog).
    SaveAs,
    /// Drop the edits and open the file as it is on disk now.
    Reload,
    /// Do nothing (the waiting action is dropped).
    Cancel,
}

/// The answers to [`Prompt::Unsaved`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnsavedAnswer {
    /// Save first (asking for a file when the document has none), then go on.
    Save,
    /// Go on and drop the changes.
    Discard,
    /// Do nothing.
    Cancel,
}

/// What the owner of a [`Lifecycle`] does next.
#[derive(Debug, Clone, PartialEq)]
#[must_use]
pub enum Next {
    /// Nothing now (a question is open, or the user cancelled).
    Wait,
    /// Carry out the action: the question about unsaved changes is answered.
    Proceed(Pending),
    /// Show the save dialog; its answer goes to [`Lifecycle::save_path_chosen`] or
    /// [`Lifecycle::save_dialog_closed`].
    ChooseSavePath,
    /// Save the document to this file, then report with [`Lifecycle::saved`].
    Save(PathBuf),
    /// Save the document to this file even though it changed on disk (the user said so),
    /// then report with [`Lifecycle::saved`].
    Overwrite(PathBuf),
}

/// Where the lifecycle is.
#[derive(Debug, Clone, PartialEq, Default)]
enum Stage {
    /// No question open.
    #[default]
    Editing,
    /// Asking whether to recover an earlier session's autosave.
    Recover(PathBuf),
    /// Asking what to do with unsaved changes before the action.
    Unsaved(Pending),
    /// "Save…" chose: the save dialog is open, the action waits for the save.
    ChoosingSavePath(Pending),
    /// Saving to a file, then the action (if any) runs.
    Saving(Option<Pending>),
    /// The file to save to changed on disk: asking, the action (if any) waiting.
    Conflict(PathBuf, Option<Pending>),
}

/// The state machine of unsaved work (see the module docs). No I/O.
#[derive(Debug, Clone, Default)]
pub struct Lifecycle {
    stage: Stage,
    /// The window should close.
    quit: bool,
    /// The user chose to quit without saving: the exit may remove the autosave.
    quit_discarding: bool,
}

impl Lifecycle {
    /// Starts by asking whether to recover the autosave at `path`.
    #[must_use]
    pub fn recovering(path: PathBuf) -> Self {
        Self {
            stage: Stage::Recover(path),
            ..Self::default()
        }
    }

    /// The question on screen, if any.
    #[must_use]
    pub fn prompt(&self) -> Option<Prompt> {
        match &self.stage {
            Stage::Recover(path) => Some(Prompt::Recover(path.clone())),
            Stage::Unsaved(action) => Some(Prompt::Unsaved(action.clone())),
            Stage::Conflict(path, _) => Some(Prompt::ChangedOnDisk(path.clone())),
            Stage::Editing | Stage::ChoosingSavePath(_) | Stage::Saving(_) => None,
        }
    }

    /// The action waiting for a save the user chose ("Save…"), if any.
    #[must_use]
    pub fn waiting(&self) -> Option<&Pending> {
        match &self.stage {
            Stage::ChoosingSavePath(action)
            | Stage::Saving(Some(action))
            | Stage::Conflict(_, Some(action)) => Some(action),
            _ => None,
        }
    }

    /// True once the window should close.
    #[must_use]
    pub fn wants_to_quit(&self) -> bool {
        self.quit
    }

    /// True when the user chose to quit without saving.
    #[must_use]
    pub fn quit_discarding(&self) -> bool {
        self.quit_discarding
    }

    /// The recovery question was answered (either way).
    pub fn recovery_answered(&mut self) {
        if matches!(self.stage, Stage::Recover(_)) {
            self.stage = Stage::Editing;
        }
    }

    /// The user asks for `action`; `dirty`: the document has unsaved changes. Closing while
    /// the recovery question is open quits at once (the autosave stays for the next start).
    pub fn request(&mut self, action: Pending, dirty: bool) -> Next {
        if action == Pending::Close && matches!(self.stage, Stage::Recover(_)) {
            self.quit = true;
            return Next::Wait;
        }
        if dirty {
            self.stage = Stage::Unsaved(action);
            Next::Wait
        } else {
            self.proceed(action)
        }
    }

    /// The answer to [`Prompt::Unsaved`]; `file`: where the document was opened from or last
    /// saved to. Nothing happens when that question is not open.
    pub fn answer_unsaved(&mut self, answer: UnsavedAnswer, file: Option<&Path>) -> Next {
        let Stage::Unsaved(action) = std::mem::take(&mut self.stage) else {
            return Next::Wait;
        };
        match answer {
            UnsavedAnswer::Cancel => Next::Wait,
            UnsavedAnswer::Discard => {
                if action == Pending::Close {
                    self.quit_discarding = true;
                }
                self.proceed(action)
            }
            UnsavedAnswer::Save => match file {
                Some(path) => {
                    self.stage = Stage::Saving(Some(action));
                    Next::Save(path.to_path_buf())
                }
                None => {
                    self.stage = Stage::ChoosingSavePath(action);
                    Next::ChooseSavePath
                }
            },
        }
    }

    /// The save dialog picked `path` (the one "Save…" opened, or a plain "Save as…").
    pub fn save_path_chosen(&mut self, path: PathBuf) -> Next {
        self.stage = match std::mem::take(&mut self.stage) {
            Stage::ChoosingSavePath(action) => Stage::Saving(Some(action)),
            Stage::Editing | Stage::Saving(_) => Stage::Saving(None),
            // A question that came up while a "Save as…" dialog was open stays open.
            question @ (Stage::Recover(_) | Stage::Unsaved(_) | Stage::Conflict(..)) => question,
        };
        Next::Save(path)
    }

    /// A plain save (Ctrl+S, "Save as…") with no action waiting on it.
    pub fn save_requested(&self, file: Option<&Path>) -> Next {
        match file {
            Some(path) => Next::Save(path.to_path_buf()),
            None => Next::ChooseSavePath,
        }
    }

    /// The save dialog went away without a file (cancelled, or replaced by another dialog):
    /// the waiting action is dropped and the document stays as it is.
    pub fn save_dialog_closed(&mut self) {
        if matches!(self.stage, Stage::ChoosingSavePath(_)) {
            self.stage = Stage::Editing;
        }
    }

    /// The save asked for by [`Next::Save`] found `path` changed on disk and wrote nothing:
    /// the user is asked ([`Prompt::ChangedOnDisk`]), the action waiting.
    pub fn changed_on_disk(&mut self, path: PathBuf) {
        let then = match std::mem::take(&mut self.stage) {
            Stage::Saving(then) | Stage::Conflict(_, then) => then,
            _ => None,
        };
        self.stage = Stage::Conflict(path, then);
    }

    /// The answer to [`Prompt::ChangedOnDisk`]. Nothing happens when that question is not
    /// open.
    pub fn answer_conflict(&mut self, answer: ConflictAnswer) -> Next {
        let Stage::Conflict(path, then) = std::mem::take(&mut self.stage) else {
            return Next::Wait;
        };
        match answer {
            ConflictAnswer::Overwrite => {
                self.stage = Stage::Saving(then);
                Next::Overwrite(path)
            }
            ConflictAnswer::SaveAs => {
                if let Some(action) = then {
                    self.stage = Stage::ChoosingSavePath(action);
                }
                Next::ChooseSavePath
            }
            // The file as it is now replaces the edits; the waiting action is dropped.
            ConflictAnswer::Reload => Next::Proceed(Pending::Open(path)),
            ConflictAnswer::Cancel => Next::Wait,
        }
    }

    /// Asks whether to recover the autosave at `path` (the next one left by an earlier
    /// session), unless another question is open.
    pub fn ask_recovery(&mut self, path: PathBuf) {
        if matches!(self.stage, Stage::Editing) {
            self.stage = Stage::Recover(path);
        }
    }

    /// The save asked for by [`Next::Save`] worked (`ok`) or failed: on success the waiting
    /// action runs; on failure the question is asked again.
    pub fn saved(&mut self, ok: bool) -> Next {
        let Stage::Saving(then) = std::mem::take(&mut self.stage) else {
            return Next::Wait;
        };
        match (then, ok) {
            (Some(action), true) => self.proceed(action),
            (Some(action), false) => {
                self.stage = Stage::Unsaved(action);
                Next::Wait
            }
            (None, _) => Next::Wait,
        }
    }

    fn proceed(&mut self, action: Pending) -> Next {
        self.stage = Stage::Editing;
        if action == Pending::Close {
            self.quit = true;
        }
        Next::Proceed(action)
    }
}

/// The document with its lifecycle and autosave.
#[derive(Debug)]
pub struct DocumentSession {
    /// The document being edited.
    pub doc: Document,
    lifecycle: Lifecycle,
    autosave: Option<Autosave>,
    /// The autosave file is this session's: it did not exist at start-up, or this session
    /// wrote it, or the user answered the recovery question. Only then may a clean exit remove
    /// it (an earlier session's autosave nobody looked at stays for the next start).
    owns_autosave: bool,
    /// Other slots' autosaves left by earlier sessions, offered after the one on screen
    /// (their locks held meanwhile).
    orphans: VecDeque<Orphan>,
    /// Earlier sessions' autosaves left in place for the next start when one was recovered.
    left_for_next_start: usize,
}

/// Why a save from the window wrote nothing.
#[derive(Debug, thiserror::Error)]
pub enum SaveError {
    /// The file changed on disk since the document was opened or last saved.
    #[error(
        "{} changed on disk since it was opened: overwrite it, save as another file, or reload it",
        path.display()
    )]
    ChangedOnDisk {
        /// The file.
        path: PathBuf,
    },
    /// The file is the window's autosave.
    #[error("{} is the autosave file: save the model to a file of its own", path.display())]
    IsTheAutosave {
        /// The file.
        path: PathBuf,
    },
    /// Another program holds the file's writer lock.
    #[error(transparent)]
    Locked(#[from] nendo_file::LockError),
    /// Writing failed.
    #[error(transparent)]
    Model(#[from] ModelError),
}

/// How long a save from the window waits for another writer of the file (a running
/// `nendo sculpt --out` on it) before it fails and says so.
const SAVE_LOCK_WAIT: std::time::Duration = std::time::Duration::from_secs(2);

impl DocumentSession {
    /// A session editing `doc`, autosaving to `autosave` (asking first about an earlier
    /// session's autosave when there is one and `offer_recovery` is set).
    ///
    /// Every autosave an earlier session left is offered: this window's own slot's first,
    /// then every other slot's that no running window holds (see
    /// [`autosave`](super::autosave)), one question each.
    #[must_use]
    pub fn new(doc: Document, autosave: Option<PathBuf>, offer_recovery: bool) -> Self {
        let mut orphans = VecDeque::new();
        let autosave = autosave.map(|base| {
            // This window's own slot: no other running window's file is ever offered, nor a
            // file that is not an autosave, nor the document itself.
            let mut a = Autosave::claim(&base, doc.path.as_deref());
            // The model as opened (or the starting plane) is not worth writing.
            a.mark_saved(doc.revision());
            if offer_recovery && !a.is_disabled() {
                orphans.extend(super::autosave::orphans(&base, a.path()));
            }
            a
        });
        let earlier = autosave.as_ref().and_then(Autosave::pending_recovery);
        let owns_autosave = earlier.is_none();
        let mut lifecycle = Lifecycle::default();
        if offer_recovery {
            match earlier {
                Some(Recovery { path, .. }) => lifecycle = Lifecycle::recovering(path),
                None => {
                    if let Some(o) = orphans.front() {
                        lifecycle = Lifecycle::recovering(o.path.clone());
                    }
                }
            }
        }
        Self {
            doc,
            lifecycle,
            autosave,
            owns_autosave,
            orphans,
            left_for_next_start: 0,
        }
    }

    /// The autosave on screen is answered: offers the next orphan, if any.
    fn next_recovery(&mut self, answered: &Path) {
        if self.orphans.front().is_some_and(|o| o.path == answered) {
            self.orphans.pop_front();
        }
        if let Some(o) = self.orphans.front() {
            self.lifecycle.ask_recovery(o.path.clone());
        }
    }

    /// Earlier sessions' autosaves left in place (for the next start) because another was
    /// recovered.
    #[must_use]
    pub fn left_for_next_start(&self) -> usize {
        self.left_for_next_start
    }

    /// The state machine.
    #[must_use]
    pub fn lifecycle(&self) -> &Lifecycle {
        &self.lifecycle
    }

    /// The question on screen, if any.
    #[must_use]
    pub fn prompt(&self) -> Option<Prompt> {
        self.lifecycle.prompt()
    }

    /// The autosave, if on.
    #[must_use]
    pub fn autosave(&self) -> Option<&Autosave> {
        self.autosave.as_ref()
    }

    /// See [`Lifecycle::request`].
    pub fn request(&mut self, action: Pending) -> Next {
        let dirty = self.doc.is_dirty();
        self.lifecycle.request(action, dirty)
    }

    /// See [`Lifecycle::answer_unsaved`].
    pub fn answer_unsaved(&mut self, answer: UnsavedAnswer) -> Next {
        let file = self.doc.path.clone();
        self.lifecycle.answer_unsaved(answer, file.as_deref())
    }

    /// See [`Lifecycle::save_requested`].
    pub fn save_requested(&self) -> Next {
        let file = self.doc.path.clone();
        self.lifecycle.save_requested(file.as_deref())
    }

    /// See [`Lifecycle::save_path_chosen`].
    pub fn save_path_chosen(&mut self, path: PathBuf) -> Next {
        self.lifecycle.save_path_chosen(path)
    }

    /// See [`Lifecycle::save_dialog_closed`].
    pub fn save_dialog_closed(&mut self) {
        self.lifecycle.save_dialog_closed();
    }

    /// Saves the document to `path` and tells the lifecycle how it went; the next step and
    /// the save's own outcome. A save to the document's own file that changed on disk since
    /// it was opened or saved writes nothing and asks ([`Prompt::ChangedOnDisk`];
    /// [`SaveError::ChangedOnDisk`]).
    pub fn save_to(&mut self, path: &Path) -> (Next, Result<(), SaveError>) {
        self.save_checked(path, true)
    }

    /// [`DocumentSession::save_to`] over a file changed on disk (the user chose Overwrite).
    pub fn save_overwriting(&mut self, path: &Path) -> (Next, Result<(), SaveError>) {
        self.save_checked(path, false)
    }

    fn save_checked(&mut self, path: &Path, check: bool) -> (Next, Result<(), SaveError>) {
        let result = self.try_save(path, check);
        if matches!(result, Err(SaveError::ChangedOnDisk { .. })) {
            self.lifecycle.changed_on_disk(path.to_path_buf());
            return (Next::Wait, result);
        }
        let next = self.lifecycle.saved(result.is_ok());
        (next, result)
    }

    fn try_save(&mut self, path: &Path, check: bool) -> Result<(), SaveError> {
        if let Some(a) = &self.autosave
            && super::autosave::check_path(a.path(), Some(path)).is_err_and(|e| {
                matches!(e, super::autosave::AutosavePathError::IsTheDocument { .. })
            })
        {
            return Err(SaveError::IsTheAutosave {
                path: path.to_path_buf(),
            });
        }
        // The check and the write under the file's writer lock: a concurrent writer either
        // finished before the check or waits for this save.
        let _lock = nendo_file::WriterLock::acquire(path, SAVE_LOCK_WAIT)?;
        if check && self.doc.changed_on_disk(path) {
            return Err(SaveError::ChangedOnDisk {
                path: path.to_path_buf(),
            });
        }
        self.doc.save(path)?;
        Ok(())
    }

    /// See [`Lifecycle::answer_conflict`].
    pub fn answer_conflict(&mut self, answer: ConflictAnswer) -> Next {
        self.lifecycle.answer_conflict(answer)
    }

    /// Replaces the document (opened file, new primitive, recovery); the autosave starts
    /// from the new one.
    pub fn replace(&mut self, doc: Document) {
        self.doc = doc;
        if let Some(a) = &mut self.autosave {
            a.mark_saved(self.doc.revision());
        }
    }

    /// Recovers the autosave at `path`: the model comes back as unsaved work (dirty until
    /// saved; the autosave stays until then). The caller puts it in place with
    /// [`DocumentSession::replace`] (which needs the window's own state reset too).
    ///
    /// # Errors
    /// As [`Document::open`]; the question is answered either way.
    ///
    /// Another slot's autosave is first written to this window's own slot, and removed only
    /// once that worked (else it stays for the next start). The other earlier autosaves are
    /// left in place for the next start ([`DocumentSession::left_for_next_start`]).
    pub fn recover(&mut self, path: &Path) -> Result<Document, ModelError> {
        self.lifecycle.recovery_answered();
        // One recovery per start: the others are not offered over the recovered work.
        let others: Vec<_> = self.orphans.drain(..).filter(|o| o.path != path).collect();
        self.left_for_next_start = others.len();
        drop(others);
        let mut doc = Document::open(path)?;
        // The model keeps the name of the file it was of (unsaved work until saved).
        doc.path = Autosave::source_of(path);
        // What that file held then: saving over it asks if it changed since.
        doc.set_disk_stamp(Autosave::source_stamp_of(path));
        doc.mark_unsaved();
        if let Some(a) = &mut self.autosave
            && a.path() != path
        {
            a.set_source(doc.path.as_deref());
            a.set_source_stamp(doc.disk_stamp());
            a.write_now(doc.model(), doc.revision());
            match a.last_error.clone() {
                None => super::autosave::remove_autosave(path),
                Some(e) => {
                    return Err(ModelError::Format(format!(
                        "not moved into this window's autosave ({e}); {} stays for the next start",
                        path.display()
                    )));
                }
            }
        }
        self.owns_autosave = true;
        Ok(doc)
    }

    /// Declines the recovery: the earlier autosave on screen is removed, and the next one (if
    /// any) is offered.
    pub fn discard_recovery(&mut self) {
        let Some(Prompt::Recover(path)) = self.lifecycle.prompt() else {
            return;
        };
        self.lifecycle.recovery_answered();
        match &mut self.autosave {
            Some(a) if a.path() == path => {
                a.discard();
                self.owns_autosave = true;
            }
            _ => super::autosave::remove_autosave(&path),
        }
        self.next_recovery(&path);
    }

    /// Removes this session's autosave before the document is replaced by one that holds no
    /// unsaved work (the old one was saved, or the user chose to drop it) — unless the new
    /// document or the one replaced is the autosave file itself (opened by name), which must
    /// stay.
    pub fn forget_autosave(&mut self, new_path: Option<&Path>) {
        if !self.owns_autosave {
            return;
        }
        if let Some(a) = &mut self.autosave {
            let same = |p: &Path| {
                p == a.path()
                    || matches!(
                        (std::fs::canonicalize(p), std::fs::canonicalize(a.path())),
                        (Ok(x), Ok(y)) if x == y
                    )
            };
            // Nor when the document being replaced is that file (opened by name earlier).
            if !new_path.is_some_and(same) && !self.doc.path.as_deref().is_some_and(same) {
                a.discard();
            }
        }
    }

    /// Writes the autosave when it is due (never while a question is open: the recovery
    /// question is about the file this would overwrite).
    pub fn tick_autosave(&mut self, now: Instant) {
        let revision = self.doc.revision();
        if let Some(a) = &mut self.autosave {
            a.set_source(self.doc.path.as_deref());
            a.set_source_stamp(self.doc.disk_stamp());
        }
        if let Some(a) = &mut self.autosave
            && self.lifecycle.prompt().is_none()
            && a.tick(self.doc.model(), revision, now)
        {
            self.owns_autosave = true;
        }
    }

    /// When the next autosave is due, if one is.
    #[must_use]
    pub fn autosave_due(&self, now: Instant) -> Option<Instant> {
        self.autosave
            .as_ref()
            .filter(|_| self.lifecycle.prompt().is_none())
            .and_then(|a| a.due(self.doc.revision(), now))
    }

    /// True once the window should close.
    #[must_use]
    pub fn wants_to_quit(&self) -> bool {
        self.lifecycle.wants_to_quit()
    }

    /// The exit: the autosave is removed only when it is this session's and holds nothing
    /// unsaved (or the user chose to quit without saving).
    pub fn on_exit(&mut self) {
        let nothing_unsaved = !self.doc.is_dirty() || self.lifecycle.quit_discarding();
        if self.owns_autosave
            && nothing_unsaved
            && let Some(a) = &mut self.autosave
        {
            a.discard();
        }
        if let Some(a) = &mut self.autosave {
            a.release();
        }
    }

    /// The window title: the file name, `*` when there are unsaved changes.
    #[must_use]
    pub fn title(&self) -> String {
        let name = self
            .doc
            .path
            .as_ref()
            .and_then(|p| p.file_name())
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "untitled".into());
        format!(
            "nendo — {name}{}",
            if self.doc.is_dirty() { " *" } else { "" }
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::Primitive;

    fn actions() -> [Pending; 3] {
        [
            Pending::Close,
            Pending::Create(PrimitiveForm::defaults_for(Primitive::Sphere)),
            Pending::Open(PathBuf::from("other.nendo.json")),
        ]
    }

    /// Dirty document, no file: the action → the question → "Save…" → the save dialog picks a
    /// file → the save works → the action goes on. It used to be dropped when the dialog
    /// opened.
    #[test]
    fn the_waiting_action_survives_the_save_dialog() {
        for action in actions() {
            let mut life = Lifecycle::default();
            assert_eq!(life.request(action.clone(), true), Next::Wait);
            assert_eq!(life.prompt(), Some(Prompt::Unsaved(action.clone())));
            assert_eq!(
                life.answer_unsaved(UnsavedAnswer::Save, None),
                Next::ChooseSavePath
            );
            assert_eq!(life.prompt(), None, "the dialog replaces the question");
            assert_eq!(life.waiting(), Some(&action));
            let file = PathBuf::from("work.nendo.json");
            assert_eq!(life.save_path_chosen(file.clone()), Next::Save(file));
            assert_eq!(life.saved(true), Next::Proceed(action.clone()));
            assert_eq!(life.wants_to_quit(), action == Pending::Close);
            assert_eq!(life.waiting(), None);
            assert!(!life.quit_discarding(), "the work was saved");
        }
    }

    /// With a file already, "Save…" saves there and goes on without a dialog.
    #[test]
    fn save_with_a_file_goes_on_without_a_dialog() {
        for action in actions() {
            let mut life = Lifecycle::default();
            let _ = life.request(action.clone(), true);
            let file = Path::new("mine.nendo.json");
            assert_eq!(
                life.answer_unsaved(UnsavedAnswer::Save, Some(file)),
                Next::Save(file.to_path_buf())
            );
            assert_eq!(life.saved(true), Next::Proceed(action));
        }
    }

    /// Cancel keeps everything, in the question and in the dialog; a failed save asks again.
    #[test]
    fn cancel_keeps_everything_and_a_failed_save_asks_again() {
        for action in actions() {
            let mut life = Lifecycle::default();
            let _ = life.request(action.clone(), true);
            assert_eq!(life.answer_unsaved(UnsavedAnswer::Cancel, None), Next::Wait);
            assert_eq!(life.prompt(), None);
            assert!(!life.wants_to_quit());

            let _ = life.request(action.clone(), true);
            let _ = life.answer_unsaved(UnsavedAnswer::Save, None);
            life.save_dialog_closed();
            assert_eq!(life.waiting(), None, "the dialog's cancel drops the action");
            assert_eq!(life.prompt(), None);
            assert!(!life.wants_to_quit());
            // A later plain save does not run the dropped action.
            let file = PathBuf::from("later.nendo.json");
            assert_eq!(life.save_path_chosen(file.clone()), Next::Save(file));
            assert_eq!(life.saved(true), Next::Wait);
            assert!(!life.wants_to_quit());

            let _ = life.request(action.clone(), true);
            let _ = life.answer_unsaved(UnsavedAnswer::Save, None);
            let _ = life.save_path_chosen(PathBuf::from("/no/such/dir/x.nendo.json"));
            assert_eq!(life.saved(false), Next::Wait);
            assert_eq!(life.prompt(), Some(Prompt::Unsaved(action)));
            assert!(!life.wants_to_quit());
        }
    }

    /// Discard goes on without saving; only a discarded Close lets the exit drop the autosave.
    #[test]
    fn discard_goes_on_without_saving() {
        for action in actions() {
            let mut life = Lifecycle::default();
            let _ = life.request(action.clone(), true);
            assert_eq!(
                life.answer_unsaved(UnsavedAnswer::Discard, None),
                Next::Proceed(action.clone())
            );
            assert_eq!(life.quit_discarding(), action == Pending::Close);
            assert_eq!(life.wants_to_quit(), action == Pending::Close);
        }
    }

    /// A save that finds its file changed on disk asks; each answer does what it says, and the
    /// action waiting on the save waits on the answer.
    #[test]
    fn a_file_changed_on_disk_asks_before_it_is_overwritten() {
        let file = PathBuf::from("m.nendo.json");
        for action in actions() {
            let mut life = Lifecycle::default();
            let _ = life.request(action.clone(), true);
            let _ = life.answer_unsaved(UnsavedAnswer::Save, Some(&file));
            life.changed_on_disk(file.clone());
            assert_eq!(life.prompt(), Some(Prompt::ChangedOnDisk(file.clone())));
            assert_eq!(life.waiting(), Some(&action));
            assert_eq!(
                life.answer_conflict(ConflictAnswer::Overwrite),
                Next::Overwrite(file.clone())
            );
            assert_eq!(life.saved(true), Next::Proceed(action.clone()));

            let mut life = Lifecycle::default();
            let _ = life.request(action.clone(), true);
            let _ = life.answer_unsaved(UnsavedAnswer::Save, Some(&file));
            life.changed_on_disk(file.clone());
            assert_eq!(
                life.answer_conflict(ConflictAnswer::SaveAs),
                Next::ChooseSavePath
            );
            assert_eq!(
                life.waiting(),
                Some(&action),
                "the action waits on the dialog"
            );
        }
        let mut life = Lifecycle::default();
        let _ = life.save_requested(Some(&file));
        life.changed_on_disk(file.clone());
        assert_eq!(
            life.answer_conflict(ConflictAnswer::Reload),
            Next::Proceed(Pending::Open(file.clone()))
        );
        assert!(!life.wants_to_quit());
        life.changed_on_disk(file.clone());
        assert_eq!(life.answer_conflict(ConflictAnswer::Cancel), Next::Wait);
        assert_eq!(life.prompt(), None);
        assert_eq!(life.answer_conflict(ConflictAnswer::Overwrite), Next::Wait);
    }

    /// A clean document goes on at once; closing during the recovery question quits and
    /// leaves that question's autosave alone.
    #[test]
    fn clean_documents_and_the_recovery_question() {
        for action in actions() {
            let mut life = Lifecycle::default();
            assert_eq!(life.request(action.clone(), false), Next::Proceed(action));
        }
        let autosave = PathBuf::from("autosave.nendo.json");
        let mut life = Lifecycle::recovering(autosave.clone());
        assert_eq!(life.prompt(), Some(Prompt::Recover(autosave)));
        let open = Pending::Open(PathBuf::from("x.nendo.json"));
        assert_eq!(life.request(open, true), Next::Wait);
        let mut life = Lifecycle::recovering(PathBuf::from("a"));
        assert_eq!(life.request(Pending::Close, true), Next::Wait);
        assert!(life.wants_to_quit() && !life.quit_discarding());
    }
}
