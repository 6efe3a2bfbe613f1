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
//!
//! ## The header: an autosave path holds an autosave or nothing
//!
//! An autosave is a `nendo-model` document with one more member, its header
//! `"autosave": {"version": 1}` (reading a model passes over it, so the file opens as a model
//! too); when the model came from a file, the header also holds what that file held then
//! (`"source_len"`, `"source_fnv1a"`: its [`DiskStamp`]), so that saving recovered work over
//! a file changed since still asks first. An autosave written before the header existed is recognised by the slot lock file
//! `FILE.lock` beside it. A path is used for autosave only when it holds no file or an
//! autosave ([`holds_autosave`]), and never when it is the document being edited:
//! `nendo --autosave PATH` refuses anything else before the window opens
//! ([`check_path`]), and [`Autosave::claim`] passes over such a slot, so nothing else is ever
//! written over or removed at exit.
//!
//! ## Every orphaned slot is offered
//!
//! At start-up the window offers its own slot's file and then every other slot's file that
//! no running window holds ([`orphans`]: its lock can be taken), one after another. Each
//! orphan's lock is held while it is offered, so two windows starting together never offer
//! the same one. Recovering a slot that is not the window's own copies the model into the
//! window's slot first and only then removes the orphan; after one recovery the others are
//! left in place for the next start.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

use super::document::DiskStamp;
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
    /// Nothing is written or removed (no usable slot).
    disabled: bool,
    /// What the document's own file held when the document read or wrote it.
    source_stamp: Option<DiskStamp>,
}

/// The member that marks an autosave ([`AUTOSAVE_MEMBER`]`: {"version": 1}`).
pub const AUTOSAVE_MEMBER: &str = "autosave";

/// Why a path cannot be an autosave file.
#[derive(Debug, thiserror::Error)]
pub enum AutosavePathError {
    /// The path is the document being edited.
    #[error(
        "--autosave {}: that is the model being edited; the autosave must be a file of its own",
        path.display()
    )]
    IsTheDocument {
        /// The path.
        path: PathBuf,
    },
    /// A file that is not an autosave is there.
    #[error(
        "--autosave {}: the file there is not a nendo autosave ({reason}); it is neither \
         overwritten nor removed — give a new file or an earlier autosave",
        path.display()
    )]
    NotAnAutosave {
        /// The path.
        path: PathBuf,
        /// What the file is instead.
        reason: String,
    },
}

/// What is at an autosave path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AutosaveFile {
    /// Nothing: the path is free.
    Missing,
    /// An autosave (with the header, or an older one with its slot lock beside it).
    Autosave,
    /// Something else, and why it is not an autosave.
    Other(String),
}

/// What `path` holds (see the module docs): nothing, an autosave, or something else.
#[must_use]
pub fn holds_autosave(path: &Path) -> AutosaveFile {
    use std::io::Read;
    #[derive(serde::Deserialize)]
    struct Head {
        #[serde(default)]
        format: Option<serde_json::Value>,
        #[serde(default)]
        autosave: Option<serde_json::Value>,
    }
    let meta = match std::fs::metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            // A dangling symbolic link is not free: writing would create its target.
            return if std::fs::symlink_metadata(path).is_ok() {
                AutosaveFile::Other("a symbolic link to nothing".into())
            } else {
                AutosaveFile::Missing
            };
        }
        Err(e) => return AutosaveFile::Other(e.to_string()),
    };
    if !meta.is_file() {
        return AutosaveFile::Other("not a regular file".into());
    }
    let mut text = String::new();
    let read = std::fs::File::open(path).and_then(|f| {
        f.take(crate::model::MAX_FILE_BYTES + 1)
            .read_to_string(&mut text)
    });
    if let Err(e) = read {
        return AutosaveFile::Other(e.to_string());
    }
    let head = match serde_json::from_str::<Head>(&text) {
        Ok(h) => h,
        Err(_) => return AutosaveFile::Other("not a nendo model".into()),
    };
    let model = head.format.as_ref().and_then(|f| f.as_str()) == Some(crate::model::FORMAT);
    if model && head.autosave.is_some() {
        AutosaveFile::Autosave
    } else if model && beside(path, ".lock").is_file() {
        // Written before the header, by a window that held this slot.
        AutosaveFile::Autosave
    } else if model {
        AutosaveFile::Other("a model without the autosave header".into())
    } else {
        AutosaveFile::Other("not a nendo model".into())
    }
}

/// True when `a` and `b` name one file (the same path, or the same file once resolved).
fn same_file(a: &Path, b: &Path) -> bool {
    a == b
        || matches!(
            (std::fs::canonicalize(a), std::fs::canonicalize(b)),
            (Ok(x), Ok(y)) if x == y
        )
}

/// Checks a path given for autosave: it must hold no file or an autosave, and not be
/// `document` (the model being edited).
///
/// # Errors
/// [`AutosavePathError`] saying which.
pub fn check_path(path: &Path, document: Option<&Path>) -> Result<(), AutosavePathError> {
    if document.is_some_and(|d| same_file(d, path)) {
        return Err(AutosavePathError::IsTheDocument {
            path: path.to_path_buf(),
        });
    }
    match holds_autosave(path) {
        AutosaveFile::Missing | AutosaveFile::Autosave => Ok(()),
        AutosaveFile::Other(reason) => Err(AutosavePathError::NotAnAutosave {
            path: path.to_path_buf(),
            reason,
        }),
    }
}

/// An earlier session's autosave in another slot than this window's, its lock held while it
/// is offered.
#[derive(Debug)]
pub struct Orphan {
    /// The file.
    pub path: PathBuf,
    /// The slot's lock, held by this process.
    _lock: File,
}

/// The autosaves of `base`'s slots other than `own` that no running window holds (their lock
/// is free, and is now taken), in slot order. Only slots whose file exists are looked at
/// (no lock file is created for an empty slot).
#[must_use]
pub fn orphans(base: &Path, own: &Path) -> Vec<Orphan> {
    (1..=Autosave::SLOTS)
        .map(|k| slot_path(base, k))
        .filter(|p| p != own && holds_autosave(p) == AutosaveFile::Autosave)
        .filter_map(|path| match try_lock(&path) {
            Ok(Some(lock)) => Some(Orphan { path, _lock: lock }),
            _ => None,
        })
        .collect()
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
///
/// A lock found held is tried again for about a tenth of a second before the slot is taken
/// for a running window's: a process that forks (to run any other program) gives its child a
/// copy of every open descriptor, and with it every `flock`, until the child's `exec` closes
/// them — a few microseconds, or milliseconds on a loaded machine. A window holds its lock
/// for its whole life, so a lock still held after the retries is a window's.
fn try_lock(path: &Path) -> std::io::Result<Option<File>> {
    let mut pause = Duration::from_millis(2);
    loop {
        match try_lock_once(path)? {
            Some(lock) => return Ok(Some(lock)),
            None if pause > Duration::from_millis(64) => return Ok(None),
            None => {
                std::thread::sleep(pause);
                pause *= 2;
            }
        }
    }
}

/// One attempt of [`try_lock`].
fn try_lock_once(path: &Path) -> std::io::Result<Option<File>> {
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
            disabled: false,
            source_stamp: None,
        }
    }

    /// Autosave to the first slot of `base` no running window holds, and hold it (see the
    /// module docs). A slot that holds something other than an autosave, or is `document`,
    /// is passed over. When no lock can be taken at all (a file system without locks, every
    /// slot held), autosaves unlocked — to `base` if it is usable, else nowhere — and says
    /// so on the status line.
    #[must_use]
    pub fn claim(base: &Path, document: Option<&Path>) -> Self {
        let mut problem = None;
        for k in 1..=Self::SLOTS {
            let path = slot_path(base, k);
            if check_path(&path, document).is_err() {
                continue;
            }
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
        if let Err(e) = check_path(base, document) {
            a.disabled = true;
            a.last_error = Some(format!("off: {e}"));
            return a;
        }
        a.last_error = Some(format!(
            "not locked ({}): another window may share this file",
            problem.unwrap_or_else(|| "every slot is held".into())
        ));
        a
    }

    /// True when this autosave writes nothing (no usable slot; see [`Autosave::claim`]).
    #[must_use]
    pub fn is_disabled(&self) -> bool {
        self.disabled
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

    /// What the document's own file held when the document read or wrote it (kept in the
    /// header).
    pub fn set_source_stamp(&mut self, stamp: Option<DiskStamp>) {
        self.source_stamp = stamp;
    }

    /// The stamp of the document's own file an autosave at `path` recorded, if any.
    #[must_use]
    pub fn source_stamp_of(path: &Path) -> Option<DiskStamp> {
        #[derive(serde::Deserialize)]
        struct Head {
            autosave: Option<serde_json::Value>,
        }
        let text =
            nendo_file::read_text_limited(path, crate::model::MAX_FILE_BYTES, "model file").ok()?;
        let head = serde_json::from_str::<Head>(&text).ok()?.autosave?;
        let len = head.get("source_len")?.as_u64()?;
        let hash = u64::from_str_radix(head.get("source_fnv1a")?.as_str()?, 16).ok()?;
        Some(DiskStamp { len, hash })
    }

    /// The document file an autosave at `path` was of, if it recorded one.
    #[must_use]
    pub fn source_of(path: &Path) -> Option<PathBuf> {
        // A path: 64 kB is far beyond any.
        let text = nendo_file::read_text_limited(&beside(path, ".source"), 64 << 10, "source note")
            .ok()?;
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
        if self.disabled || holds_autosave(&self.path) != AutosaveFile::Autosave {
            return None;
        }
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
        if self.disabled || self.saved_revision == Some(revision) {
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
        if self.disabled || self.saved_revision == Some(revision) {
            return None;
        }
        let settled = match self.changed_at {
            Some((r, t)) if r == revision => t + Self::SETTLE,
            _ => now + Self::SETTLE,
        };
        let allowed = self.last_write.map_or(settled, |t| t + Self::INTERVAL);
        Some(settled.max(allowed))
    }

    /// Writes `model` immediately, with the autosave header (nothing when disabled).
    pub fn write_now(&mut self, model: &Model, revision: u64) {
        self.last_write = Some(Instant::now());
        if self.disabled {
            return;
        }
        let result = self
            .path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map_or(Ok(()), std::fs::create_dir_all)
            .map_err(|error| ModelError::Io {
                path: self.path.clone(),
                error,
            })
            .and_then(|()| {
                // The last guard before the file: what could not be read back is not written.
                if let Some((patch, point)) = crate::model::first_non_finite(&model.surface) {
                    return Err(ModelError::Surface(
                        crate::surface::SurfaceError::NotFinite { patch, point },
                    ));
                }
                let mut doc = model.to_json();
                if let Some(o) = doc.as_object_mut() {
                    let header = match self.source_stamp {
                        Some(s) => serde_json::json!({
                            "version": 1,
                            "source_len": s.len,
                            "source_fnv1a": format!("{:016x}", s.hash),
                        }),
                        None => serde_json::json!({"version": 1}),
                    };
                    o.insert(AUTOSAVE_MEMBER.into(), header);
                }
                crate::model::write_atomically(&self.path, doc.to_string().as_bytes())
            })
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

    /// Removes the autosave file (a clean exit, or a recovery the user declined) — only if
    /// it is an autosave.
    pub fn discard(&mut self) {
        if !self.disabled {
            remove_autosave(&self.path);
        }
        self.saved_revision = None;
    }
}

/// Removes the autosave at `path` and its `.source`, if `path` holds an autosave.
pub fn remove_autosave(path: &Path) {
    if holds_autosave(path) == AutosaveFile::Autosave {
        let _ = std::fs::remove_file(path);
        let _ = std::fs::remove_file(beside(path, ".source"));
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

    /// An autosave carries its header; a path holds an autosave, nothing, or something that
    /// is refused (and passed over by a claim, and never removed by a discard).
    #[test]
    fn an_autosave_path_holds_an_autosave_or_nothing() {
        let dir = std::env::temp_dir().join(format!("nendo-autosave-kind-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("dir");
        let model = Model::new(
            Primitive::Plane
                .build(&PrimitiveParams::default())
                .expect("plane"),
        );
        let auto = dir.join("a.nendo.json");
        assert_eq!(holds_autosave(&auto), AutosaveFile::Missing);
        let mut a = Autosave::new(auto.clone());
        a.write_now(&model, 1);
        assert_eq!(holds_autosave(&auto), AutosaveFile::Autosave);
        let text = std::fs::read_to_string(&auto).expect("read");
        assert!(text.contains("\"autosave\":{\"version\":1}"), "{text}");
        assert_eq!(Model::read(&auto).expect("still a model").model, model);

        let plain = dir.join("m.json");
        model.write(&plain).expect("model");
        assert!(matches!(holds_autosave(&plain), AutosaveFile::Other(_)));
        let notes = dir.join("notes.txt");
        std::fs::write(&notes, "notes").expect("notes");
        assert!(check_path(&notes, None).is_err());
        assert!(check_path(&auto, None).is_ok());
        assert!(matches!(
            check_path(&auto, Some(&auto)),
            Err(AutosavePathError::IsTheDocument { .. })
        ));
        // An older autosave: a model with its slot lock beside it.
        std::fs::write(dir.join("m.json.lock"), "").expect("lock");
        assert_eq!(holds_autosave(&plain), AutosaveFile::Autosave);
        std::fs::remove_file(dir.join("m.json.lock")).expect("unlock");

        let claimed = Autosave::claim(&notes, None);
        assert_eq!(claimed.path(), dir.join("notes-2.txt").as_path());
        let mut on_notes = Autosave::new(notes.clone());
        on_notes.discard();
        assert!(notes.is_file(), "a discard never removes another file");
        drop(claimed);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Two windows on one base path autosave to two files; a slot let go is taken again; the
    /// document's own file is kept beside the model.
    #[test]
    fn each_window_claims_its_own_slot() {
        let dir = std::env::temp_dir().join(format!("nendo-autosave-slots-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let base = dir.join("autosave.nendo.json");
        let mut first = Autosave::claim(&base, None);
        let second = Autosave::claim(&base, None);
        assert!(first.is_locked() && second.is_locked());
        assert_eq!(first.path(), base.as_path());
        assert_eq!(second.path(), dir.join("autosave-2.nendo.json").as_path());
        first.release();
        let third = Autosave::claim(&base, None);
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
