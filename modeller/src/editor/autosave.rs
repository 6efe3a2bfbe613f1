//! Autosave and crash recovery.
//!
//! While the window is open, every change of the model is written, at most once per
//! [`Autosave::INTERVAL`] and after the model has been still for [`Autosave::SETTLE`], to one
//! file: `--autosave PATH`, or by default `$XDG_STATE_HOME/nendo/autosave.nendo.json`
//! (`~/.local/state/nendo/…` without `XDG_STATE_HOME`). Writes are atomic (temporary file,
//! then rename), so the file is always a whole model. A clean exit removes it; finding it at
//! start-up therefore means the last session ended without closing (a crash, a kill), and the
//! window offers to recover it.
//!
//! ## One file per running window
//!
//! Each window claims its own slot ([`Autosave::claim`]): the file above, or, while another
//! window holds that one, `autosave-2.nendo.json`, `autosave-3.nendo.json`, … (up to
//! [`Autosave::SLOTS`]). A slot is held by an exclusive `flock` on `FILE.lock` beside it, kept
//! for the life of the window; the system drops it when the process ends, however it ends. So
//! a slot's file found at start-up is always a dead session's, never a live window's: a second
//! window never offers to recover the first one's work. The lock files are left in place (removing
//! one another process may have opened would let two windows share a slot).
//!
//! Beside the model, `FILE.source` holds the path of the file the model was opened from or last
//! saved to, so a recovered model keeps its name (it is still unsaved work until saved).

use std::fs::File;
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
    /// The lock that makes the slot this window's (`None`: not locked).
    lock: Option<File>,
    /// The document's own file, written beside the model.
    source: Option<PathBuf>,
}

/// The slot files for a base autosave path: `base` itself, then `stem-k.ext` for k = 2, 3, …
/// (the extension is everything from the first dot of the file name: `.nendo.json`).
fn slot_path(base: &Path, k: usize) -> PathBuf {
    if k <= 1 {
        return base.to_path_buf();
    }
    let name = base
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let (stem, ext) = name.split_at(name.find('.').unwrap_or(name.len()));
    base.with_file_name(format!("{stem}-{k}{ext}"))
}

/// `path` with `suffix` added to its file name.
fn beside(path: &Path, suffix: &str) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(suffix);
    path.with_file_name(name)
}

/// Tries to take the slot `path`: `Ok(Some(lock))` when this process now holds it,
/// `Ok(None)` when another process does.
fn try_lock(path: &Path) -> std::io::Result<Option<File>> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    let file = std::fs::OpenOptions::new()
        .create(true)
        .truncate(false)
        .write(true)
        .open(beside(path, ".lock"))?;
    match file.try_lock() {
        Ok(()) => Ok(Some(file)),
        Err(std::fs::TryLockError::WouldBlock) => Ok(None),
        Err(std::fs::TryLockError::Error(e)) => Err(e),
    }
}

impl Autosave {
    /// Least time between two writes.
    pub const INTERVAL: Duration = Duration::from_secs(2);
    /// How long the model must stay unchanged before it is written (so a stroke in progress
    /// is not written at every frame).
    pub const SETTLE: Duration = Duration::from_millis(300);

    /// Most windows that autosave side by side from one base path.
    pub const SLOTS: usize = 64;

    /// Autosave to `path`, without claiming it (see [`Autosave::claim`]).
    #[must_use]
    pub fn new(path: PathBuf) -> Self {
        Self {
            path,
            saved_revision: None,
            changed_at: None,
            last_write: None,
            last_error: None,
            lock: None,
            source: None,
        }
    }

    /// Autosave to the first slot of `base` no running window holds, and hold it (see the
    /// module docs). When no lock can be taken at all (a file system without locks, every
    /// slot held), autosaves to `base` unlocked and says so on the status line.
    #[must_use]
    pub fn claim(base: &Path) -> Self {
        let mut problem = None;
        for k in 1..=Self::SLOTS {
            let path = slot_path(base, k);
            match try_lock(&path) {
                Ok(Some(lock)) => {
                    let mut a = Self::new(path);
                    a.lock = Some(lock);
                    return a;
                }
                Ok(None) => {}
                Err(e) => {
                    problem = Some(e.to_string());
                    break;
                }
            }
        }
        let mut a = Self::new(base.to_path_buf());
        a.last_error = Some(format!(
            "not locked ({}): another window may share this file",
            problem.unwrap_or_else(|| "every slot is held".into())
        ));
        a
    }

    /// True while this window holds its slot's lock.
    #[must_use]
    pub fn is_locked(&self) -> bool {
        self.lock.is_some()
    }

    /// Lets the slot go (the window is closing).
    pub fn release(&mut self) {
        self.lock = None;
    }

    /// The document's own file, written beside the next autosave so a recovery keeps it.
    pub fn set_source(&mut self, source: Option<&Path>) {
        self.source = source.map(Path::to_path_buf);
    }

    /// The document file an autosave at `path` was of, if it recorded one.
    #[must_use]
    pub fn source_of(path: &Path) -> Option<PathBuf> {
        let text = std::fs::read_to_string(beside(path, ".source")).ok()?;
        let line = text.lines().next()?.trim_end();
        (!line.is_empty()).then(|| PathBuf::from(line))
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
            .and_then(|()| model.write(&self.path))
            .and_then(|()| {
                let source = beside(&self.path, ".source");
                match &self.source {
                    Some(p) => crate::model::write_atomically(
                        &source,
                        format!("{}\n", p.display()).as_bytes(),
                    ),
                    None => {
                        let _ = std::fs::remove_file(&source);
                        Ok(())
                    }
                }
            });
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
        let _ = std::fs::remove_file(beside(&self.path, ".source"));
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

    /// Two windows on one base path autosave to two files; a slot let go is taken again; the
    /// document's own file is kept beside the model.
    #[test]
    fn each_window_claims_its_own_slot() {
        let dir = std::env::temp_dir().join(format!("nendo-autosave-slots-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let base = dir.join("autosave.nendo.json");
        let mut first = Autosave::claim(&base);
        let second = Autosave::claim(&base);
        assert!(first.is_locked() && second.is_locked());
        assert_eq!(first.path(), base.as_path());
        assert_eq!(second.path(), dir.join("autosave-2.nendo.json").as_path());
        first.release();
        let third = Autosave::claim(&base);
        assert_eq!(
            third.path(),
            base.as_path(),
            "a released slot is free again"
        );

        let model = Model::new(
            Primitive::Plane
                .build(&PrimitiveParams::default())
                .expect("plane"),
        );
        let mut a = third;
        a.set_source(Some(Path::new("/models/vase.nendo.json")));
        a.write_now(&model, 1);
        assert_eq!(
            Autosave::source_of(a.path()),
            Some(PathBuf::from("/models/vase.nendo.json"))
        );
        a.set_source(None);
        a.write_now(&model, 2);
        assert_eq!(Autosave::source_of(a.path()), None);
        drop((a, second));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
