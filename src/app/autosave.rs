//! Autosave and crash recovery.
//!
//! While the window is open, every change of the model is written, at most once per
//! [`Autosave::INTERVAL`] and after the model has been still for [`Autosave::SETTLE`], to one
//! file: `--autosave PATH`, or by default `$XDG_STATE_HOME/nendo/autosave.nendo.json`
//! (`~/.local/state/nendo/…` without `XDG_STATE_HOME`). Writes are atomic (temporary file,
//! then rename), so the file is always a whole model. A clean exit removes it; finding it at
//! start-up therefore means the last session ended without closing (a crash, a kill), and the
//! window offers to recover it.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

use crate::model::{Model, ModelError};

/// The default autosave file, if a state directory can be named.
#[must_use]
pub fn default_path() -> Option<PathBuf> {
    let state = std::env::var_os("XDG_STATE_HOME")
        .filter(|s| !s.is_empty())
        .map(PathBuf::from)
        .or_else(|| {
            std::env::var_os("HOME")
                .filter(|h| !h.is_empty())
                .map(|h| PathBuf::from(h).join(".local/state"))
        })?;
    Some(state.join("nendo").join("autosave.nendo.json"))
}

/// An autosave left by an earlier session.
#[derive(Debug, Clone)]
pub struct Recovery {
    /// The file.
    pub path: PathBuf,
    /// When it was last written, if the file system says.
    pub modified: Option<SystemTime>,
}

/// Writes the model to the autosave file when it changes.
#[derive(Debug)]
pub struct Autosave {
    path: PathBuf,
    /// Revision of the model last written.
    saved_revision: Option<u64>,
    /// When the revision last changed.
    changed_at: Option<(u64, Instant)>,
    last_write: Option<Instant>,
    /// The last write error, kept for the status line.
    pub last_error: Option<String>,
}

impl Autosave {
    /// Least time between two writes.
    pub const INTERVAL: Duration = Duration::from_secs(2);
    /// How long the model must stay unchanged before it is written (so a stroke in progress
    /// is not written at every frame).
    pub const SETTLE: Duration = Duration::from_millis(300);

    /// Autosave to `path`.
    #[must_use]
    pub fn new(path: PathBuf) -> Self {
        Self {
            path,
            saved_revision: None,
            changed_at: None,
            last_write: None,
            last_error: None,
        }
    }

    /// The autosave file.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The autosave left by an earlier session, if the file exists.
    #[must_use]
    pub fn pending_recovery(&self) -> Option<Recovery> {
        let meta = std::fs::metadata(&self.path).ok()?;
        meta.is_file().then(|| Recovery {
            path: self.path.clone(),
            modified: meta.modified().ok(),
        })
    }

    /// Marks `revision` as already saved (the model just loaded or recovered).
    pub fn mark_saved(&mut self, revision: u64) {
        self.saved_revision = Some(revision);
    }

    /// Called every frame: writes `model` when its `revision` is new, has settled, and the
    /// last write is old enough. Returns true when it wrote.
    pub fn tick(&mut self, model: &Model, revision: u64, now: Instant) -> bool {
        if self.saved_revision == Some(revision) {
            return false;
        }
        let since = match self.changed_at {
            Some((r, t)) if r == revision => t,
            _ => {
                self.changed_at = Some((revision, now));
                now
            }
        };
        if now.duration_since(since) < Self::SETTLE {
            return false;
        }
        if self
            .last_write
            .is_some_and(|t| now.duration_since(t) < Self::INTERVAL)
        {
            return false;
        }
        self.write_now(model, revision);
        true
    }

    /// When [`Autosave::tick`] should next be called for `revision` to be written (`None`
    /// when it is already written): the window wakes up then even without input.
    #[must_use]
    pub fn due(&self, revision: u64, now: Instant) -> Option<Instant> {
        if self.saved_revision == Some(revision) {
            return None;
        }
        let settled = match self.changed_at {
            Some((r, t)) if r == revision => t + Self::SETTLE,
            _ => now + Self::SETTLE,
        };
        let allowed = self.last_write.map_or(settled, |t| t + Self::INTERVAL);
        Some(settled.max(allowed))
    }

    /// Writes `model` immediately.
    pub fn write_now(&mut self, model: &Model, revision: u64) {
        self.last_write = Some(Instant::now());
        let result = self
            .path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map_or(Ok(()), std::fs::create_dir_all)
            .map_err(|error| ModelError::Io {
                path: self.path.clone(),
                error,
            })
            .and_then(|()| model.write(&self.path));
        match result {
            Ok(()) => {
                self.saved_revision = Some(revision);
                self.last_error = None;
            }
            Err(e) => self.last_error = Some(e.to_string()),
        }
    }

    /// Removes the autosave file (a clean exit, or a recovery the user declined).
    pub fn discard(&mut self) {
        let _ = std::fs::remove_file(&self.path);
        self.saved_revision = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Primitive, PrimitiveParams};

    #[test]
    fn writes_settled_changes_and_recovers_them() {
        let dir = std::env::temp_dir().join(format!("nendo-autosave-test-{}", std::process::id()));
        let path = dir.join("sub").join("auto.nendo.json");
        let mut autosave = Autosave::new(path.clone());
        assert!(autosave.pending_recovery().is_none());
        let model = Model::new(
            Primitive::Plane
                .build(&PrimitiveParams::default())
                .expect("plane"),
        );
        let t0 = Instant::now();
        autosave.mark_saved(0);
        assert!(!autosave.tick(&model, 0, t0), "nothing new");
        assert!(!autosave.tick(&model, 1, t0), "not settled yet");
        assert_eq!(autosave.due(1, t0), Some(t0 + Autosave::SETTLE));
        assert!(
            autosave.tick(&model, 1, t0 + Autosave::SETTLE),
            "settled: written"
        );
        assert!(
            !autosave.tick(&model, 1, t0 + Autosave::SETTLE * 2),
            "already written"
        );
        assert_eq!(autosave.due(1, t0), None, "written");
        let recovery = autosave.pending_recovery().expect("the file exists");
        let loaded = Model::read(&recovery.path).expect("a whole model");
        assert_eq!(loaded.model, model);
        autosave.discard();
        assert!(autosave.pending_recovery().is_none());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
