#![forbid(unsafe_code)]
//! The one safe writer of nendo: every file the program writes for the user (models, meshes,
//! pictures, figures, traces, the window's autosave) goes through [`AtomicFile`].
//!
//! What a write guarantees:
//! - **Atomic replacement.** The bytes go to a temporary file in the *target's* directory, named
//!   `.NAME.nendo-tmp-XXXXXX` (`NAME` the target's file name, `XXXXXX` random); on
//!   [`AtomicFile::commit`] it is flushed, synced (`fsync`), renamed over the target, and the
//!   directory is synced. A reader sees the old file or the new one, never a part.
//! - **Symbolic links are written through**: the link stays a link and the file it finally
//!   points at is replaced (a dangling link gets its file created).
//! - **Permissions are kept**: a replaced file's permission bits (`0600` stays `0600`) are
//!   given to the new one; a new file gets `0666` less the umask, as `File::create` would.
//!   Ownership, extended attributes and hard links are not carried over (a hard-linked target
//!   is replaced by a new inode).
//! - **Only regular files are replaced**: a directory, device, fifo or socket at the target (or
//!   at the end of its links) is refused before anything is written ([`WriteError`]).
//! - **No temporaries left behind**: the temporary is removed on every error, when an
//!   [`AtomicFile`] is dropped without commit, and by [`remove_live_temporaries`], which a
//!   binary's SIGINT / SIGTERM handler calls before exiting.
//! - **Stale temporaries are swept**: each live temporary is held under an exclusive advisory
//!   lock (`flock`) for its whole life, and locks die with their process however it ends. Every
//!   new write to a target first removes the temporaries of that target (same name pattern, in
//!   the same directory) that nobody holds locked: those of a run that was killed. The live
//!   temporaries of other writers, in this process or another, are locked and left alone.
//!
//!
//! Recordings are the one kind of file not written atomically: [`AppendFile`] grows a file
//! under its own name, record by record, so that whatever ends the program (a SIGKILL, a power
//! cut, a full disk) leaves every complete record readable. Its head still appears whole
//! through a temporary and a rename, and it never replaces an existing file unless asked to
//! ([`Existing`]); see [`append`] for its reasoning.
//!
//! Read–modify–write runs on one file (`sculpt --model m --out m`, the window's Save) take
//! turns through [`WriterLock`], a lock file `.NAME.nendo-lock` beside the target held for the
//! whole run (see [`lock`]).
//!
//! Limits: the locks are advisory `flock` locks, which network file systems may emulate
//! poorly; the directory sync is skipped where the file system does not support it; a
//! target name longer than 200 bytes is shortened in its temporary's name, so temporaries of
//! two such targets sharing their first 200 bytes are recognised as each other's (only
//! unlocked, i.e. stale, ones are ever removed).

use std::ffi::{OsStr, OsString};
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

pub mod append;
pub mod lock;
pub use append::{AppendFile, Existing};
pub use lock::{LockError, WriterLock};
pub mod lines;
pub use lines::{Line, Overlong, read_line_bounded};
pub mod read;
pub use read::{ReadError, read_text_limited};

/// The marker between a target's name and the random part of its temporaries' names.
pub const TEMP_MARKER: &str = ".nendo-tmp-";
/// Random characters at the end of a temporary's name.
const RANDOM_LEN: usize = 6;
/// Longest target name (bytes) kept whole in a temporary's name (`NAME_MAX` is 255).
const MAX_NAME_IN_TEMP: usize = 200;
/// Symbolic links followed before giving up (as Linux's `ELOOP` limit).
const MAX_LINKS: usize = 40;
/// Attempts at a temporary that a concurrent sweep of another writer removed.
const CREATE_ATTEMPTS: usize = 4;

/// What can go wrong writing a file. Each message names the target once.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The target is a directory.
    #[error("{}: is a directory", path.display())]
    IsDirectory {
        /// The target asked for.
        path: PathBuf,
    },
    /// The target is a device, fifo or socket, which renaming a file over would destroy.
    #[error(
        "{}: is not a regular file (a device, pipe or socket): nendo replaces files by \
         renaming a new one over them and will not replace it",
        path.display()
    )]
    NotRegularFile {
        /// The target asked for.
        path: PathBuf,
    },
    /// The path names no file (it is empty, a root, or ends in `..`).
    #[error("{}: names no file", path.display())]
    NoFileName {
        /// The target asked for.
        path: PathBuf,
    },
    /// The target's symbolic links do not end.
    #[error("{}: too many levels of symbolic links", path.display())]
    SymlinkLoop {
        /// The target asked for.
        path: PathBuf,
    },
    /// A file is already at the target, and the write was asked never to replace one
    /// ([`Existing::Refuse`]).
    #[error("{}: a file is already there, and it is not replaced", path.display())]
    Exists {
        /// The target asked for.
        path: PathBuf,
    },
    /// The process is ending ([`remove_live_temporaries`] has run): nothing is written.
    #[error("{}: not written, the program is stopping", path.display())]
    Stopping {
        /// The target asked for.
        path: PathBuf,
    },
    /// The file system refused (creating, writing, syncing or renaming).
    #[error("{}: {error}", path.display())]
    Io {
        /// The target asked for (never the temporary).
        path: PathBuf,
        /// The underlying error (part of the message, not a `source()`, so printing an error
        /// chain does not repeat it).
        error: io::Error,
    },
}

impl WriteError {
    /// The target the error is about.
    #[must_use]
    pub fn path(&self) -> &Path {
        match self {
            WriteError::IsDirectory { path }
            | WriteError::NotRegularFile { path }
            | WriteError::NoFileName { path }
            | WriteError::SymlinkLoop { path }
            | WriteError::Exists { path }
            | WriteError::Stopping { path }
            | WriteError::Io { path, .. } => path,
        }
    }

    /// The message without the path, for callers whose own message names it.
    #[must_use]
    pub fn reason(&self) -> String {
        match self {
            WriteError::Io { error, .. } => error.to_string(),
            other => {
                let text = other.to_string();
                let path = other.path().display().to_string();
                text.strip_prefix(&path)
                    .and_then(|t| t.strip_prefix(": "))
                    .map_or_else(|| text.clone(), str::to_owned)
            }
        }
    }

    /// The error as an [`io::Error`] whose message does *not* name the path, for callers whose
    /// own error type names it (such as `{path}: {io error}`).
    #[must_use]
    pub fn into_io(self) -> io::Error {
        match self {
            WriteError::Io { error, .. } => error,
            WriteError::IsDirectory { .. } => {
                io::Error::new(io::ErrorKind::IsADirectory, "is a directory")
            }
            WriteError::NotRegularFile { .. } => io::Error::new(
                io::ErrorKind::InvalidInput,
                "is not a regular file (a device, pipe or socket): nendo replaces files by \
                 renaming a new one over them and will not replace it",
            ),
            WriteError::NoFileName { .. } => {
                io::Error::new(io::ErrorKind::InvalidInput, "names no file")
            }
            WriteError::SymlinkLoop { .. } => io::Error::new(
                io::ErrorKind::InvalidInput,
                "too many levels of symbolic links",
            ),
            WriteError::Exists { .. } => io::Error::new(
                io::ErrorKind::AlreadyExists,
                "a file is already there, and it is not replaced",
            ),
            WriteError::Stopping { .. } => io::Error::new(
                io::ErrorKind::Interrupted,
                "not written, the program is stopping",
            ),
        }
    }
}

/// The live temporaries of this process, for [`remove_live_temporaries`].
struct Registry {
    next_id: u64,
    live: Vec<(u64, PathBuf)>,
    /// Set by [`remove_live_temporaries`]: no new temporaries from then on.
    closed: bool,
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    next_id: 0,
    live: Vec::new(),
    closed: false,
});

fn registry() -> MutexGuard<'static, Registry> {
    // The registry stays consistent even if a thread panicked holding it (each update is a
    // single push or removal).
    REGISTRY.lock().unwrap_or_else(PoisonError::into_inner)
}

fn deregister(id: u64) {
    registry().live.retain(|(i, _)| *i != id);
}

/// Removes every temporary file of this process's unfinished writes and refuses new ones; for
/// a binary's SIGINT / SIGTERM handler to call just before it exits. Returns how many files
/// were removed.
///
/// It takes a lock, so it must run on an ordinary thread (as the `ctrlc` crate's handlers do),
/// not inside an asynchronous signal handler. Writers still running afterwards fail with
/// [`WriteError::Stopping`] or an I/O error; their targets are untouched.
pub fn remove_live_temporaries() -> usize {
    let mut registry = registry();
    registry.closed = true;
    registry
        .live
        .drain(..)
        .filter(|(_, path)| fs::remove_file(path).is_ok())
        .count()
}

/// A file being written atomically: a temporary beside the target until [`AtomicFile::commit`]
/// renames it into place. Dropped without commit, it removes the temporary and leaves the
/// target untouched. Writes are buffered.
#[derive(Debug)]
pub struct AtomicFile {
    /// The temporary, open and locked; `None` once committed. (The plain file, not
    /// `tempfile::NamedTempFile`, whose I/O errors would name the temporary.)
    out: Option<BufWriter<File>>,
    /// The temporary's path, removed when dropped; `None` once committed.
    temp: Option<tempfile::TempPath>,
    /// The path asked for (named by errors).
    target: PathBuf,
    /// The file actually replaced: the target with its symbolic links followed.
    resolved: PathBuf,
    /// The registry entry of the temporary.
    id: u64,
}

impl AtomicFile {
    /// Starts writing `target`: checks it (a regular file, a symbolic link to one, or nothing
    /// yet), removes stale temporaries of an earlier killed run, and creates the temporary.
    /// Nothing appears at the target until [`AtomicFile::commit`].
    ///
    /// # Errors
    /// [`WriteError::IsDirectory`], [`WriteError::NotRegularFile`], [`WriteError::NoFileName`],
    /// [`WriteError::SymlinkLoop`], [`WriteError::Stopping`], or [`WriteError::Io`] when the
    /// temporary cannot be created (no directory, no permission, …).
    pub fn create(target: impl AsRef<Path>) -> Result<AtomicFile, WriteError> {
        let target = target.as_ref();
        let io = |error| WriteError::Io {
            path: target.to_path_buf(),
            error,
        };
        let resolved = resolve_links(target)?;
        let existing = match fs::symlink_metadata(&resolved) {
            Ok(m) if m.is_file() => Some(m.permissions()),
            Ok(m) if m.is_dir() => {
                return Err(WriteError::IsDirectory {
                    path: target.to_path_buf(),
                });
            }
            Ok(_) => {
                return Err(WriteError::NotRegularFile {
                    path: target.to_path_buf(),
                });
            }
            Err(e) if e.kind() == io::ErrorKind::NotFound => None,
            Err(e) => return Err(io(e)),
        };
        let name = match resolved.file_name() {
            Some(n) => n.to_os_string(),
            None => {
                return Err(WriteError::NoFileName {
                    path: target.to_path_buf(),
                });
            }
        };
        let dir = directory_of(&resolved);
        let prefix = temp_prefix(&name);
        sweep_stale(&dir, &prefix);

        let mut registry = registry();
        if registry.closed {
            return Err(WriteError::Stopping {
                path: target.to_path_buf(),
            });
        }
        let temp = create_locked_temporary(&dir, &prefix, existing.as_ref())
            .map_err(|e| io(without_temporary_path(e)))?;
        let id = registry.next_id;
        registry.next_id += 1;
        registry.live.push((id, temp.path().to_path_buf()));
        drop(registry);
        let (file, temp) = temp.into_parts();
        Ok(AtomicFile {
            out: Some(BufWriter::new(file)),
            temp: Some(temp),
            target: target.to_path_buf(),
            resolved,
            id,
        })
    }

    /// The path asked for.
    #[must_use]
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// The temporary file's path (until commit).
    #[must_use]
    pub fn temporary_path(&self) -> Option<&Path> {
        self.temp.as_deref()
    }

    /// Finishes the write: flushes, syncs the file, renames it over the target and syncs the
    /// directory. On failure the temporary is removed and the target is untouched (unless only
    /// the final directory sync failed: the new contents are then in place but perhaps not yet
    /// durable).
    ///
    /// # Errors
    /// [`WriteError::Io`] naming the target.
    pub fn commit(mut self) -> Result<(), WriteError> {
        // `self` drops afterwards: whatever is left of the temporary is removed then.
        self.finish().map_err(|error| WriteError::Io {
            path: self.target.clone(),
            error,
        })
    }

    fn finish(&mut self) -> io::Result<()> {
        let (Some(out), Some(temp)) = (self.out.take(), self.temp.take()) else {
            return Err(io::Error::other("already committed"));
        };
        // On any failure below, `temp` is dropped, which removes the temporary.
        let file = out.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        drop(file);
        // On failure the returned error holds the temporary's path; dropping it removes it.
        temp.persist(&self.resolved).map_err(|e| e.error)?;
        deregister(self.id);
        sync_directory(&directory_of(&self.resolved))
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match self.out.as_mut() {
            Some(out) => out.write(buf),
            None => Err(io::Error::other("already committed")),
        }
    }

    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        match self.out.as_mut() {
            Some(out) => out.write_all(buf),
            None => Err(io::Error::other("already committed")),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match self.out.as_mut() {
            Some(out) => out.flush(),
            None => Ok(()),
        }
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        // Closing the file (its buffered bytes are flushed into it first, harmlessly), then
        // dropping the temporary's path removes it.
        drop(self.out.take());
        drop(self.temp.take());
        deregister(self.id);
    }
}

/// Writes `target` atomically with `write`, committing when it returns `Ok`; when it returns
/// an error (or panics) nothing is written and the temporary is removed.
///
/// # Errors
/// `write`'s error, or a [`WriteError`] converted into `E`.
pub fn write_atomic<T, E: From<WriteError>>(
    target: impl AsRef<Path>,
    write: impl FnOnce(&mut AtomicFile) -> Result<T, E>,
) -> Result<T, E> {
    let mut file = AtomicFile::create(target)?;
    let value = write(&mut file)?;
    file.commit()?;
    Ok(value)
}

/// Writes `bytes` to `target` atomically.
///
/// # Errors
/// As [`AtomicFile::create`], [`AtomicFile::commit`], or [`WriteError::Io`] from writing.
pub fn write_bytes(target: impl AsRef<Path>, bytes: &[u8]) -> Result<(), WriteError> {
    write_atomic(target, |f| {
        f.write_all(bytes).map_err(|error| WriteError::Io {
            path: f.target().to_path_buf(),
            error,
        })
    })
}

/// `target` with its symbolic links followed to the end (not required to exist).
fn resolve_links(target: &Path) -> Result<PathBuf, WriteError> {
    let mut path = target.to_path_buf();
    for _ in 0..MAX_LINKS {
        match fs::symlink_metadata(&path) {
            Ok(m) if m.file_type().is_symlink() => {
                let link = fs::read_link(&path).map_err(|error| WriteError::Io {
                    path: target.to_path_buf(),
                    error,
                })?;
                path = if link.is_absolute() {
                    link
                } else {
                    directory_of(&path).join(link)
                };
            }
            _ => return Ok(path),
        }
    }
    Err(WriteError::SymlinkLoop {
        path: target.to_path_buf(),
    })
}

/// The directory holding `path` (`.` for a bare name).
fn directory_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// `.NAME.nendo-tmp-`, with `NAME` shortened to [`MAX_NAME_IN_TEMP`] bytes.
fn temp_prefix(name: &OsStr) -> OsString {
    let mut prefix = OsString::from(".");
    if name.len() <= MAX_NAME_IN_TEMP {
        prefix.push(name);
    } else {
        prefix.push(shorten(name));
    }
    prefix.push(TEMP_MARKER);
    prefix
}

#[cfg(unix)]
fn shorten(name: &OsStr) -> OsString {
    use std::os::unix::ffi::OsStrExt;
    OsStr::from_bytes(&name.as_bytes()[..MAX_NAME_IN_TEMP]).to_os_string()
}

#[cfg(not(unix))]
fn shorten(name: &OsStr) -> OsString {
    name.to_string_lossy()
        .chars()
        .scan(0, |len, c| {
            *len += c.len_utf8();
            (*len <= MAX_NAME_IN_TEMP).then_some(c)
        })
        .collect::<String>()
        .into()
}

/// Whether `file_name` is a temporary of the target whose prefix is `prefix`.
fn is_temporary_of(file_name: &OsStr, prefix: &OsStr) -> bool {
    let name = file_name.as_encoded_bytes();
    let prefix = prefix.as_encoded_bytes();
    name.len() == prefix.len() + RANDOM_LEN
        && name.starts_with(prefix)
        && name[prefix.len()..].iter().all(u8::is_ascii_alphanumeric)
}

/// Whether `file` is still the one named `path` (not removed or replaced meanwhile).
#[cfg(unix)]
fn still_named(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), fs::symlink_metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn still_named(_file: &File, path: &Path) -> bool {
    path.exists()
}

/// Removes the temporaries of a target (names starting with `prefix` in `dir`) that no live
/// writer holds locked. Best effort: what cannot be examined is left. Returns how many were
/// removed.
fn sweep_stale(dir: &Path, prefix: &OsStr) -> usize {
    let Ok(entries) = fs::read_dir(dir) else {
        return 0;
    };
    let mut removed = 0;
    for entry in entries.flatten() {
        if !is_temporary_of(&entry.file_name(), prefix) {
            continue;
        }
        if !entry.file_type().is_ok_and(|t| t.is_file()) {
            continue;
        }
        let path = entry.path();
        // A lock needs an open file, not a writable one (a temporary may be read-only).
        let Ok(file) = File::open(&path).or_else(|_| OpenOptions::new().write(true).open(&path))
        else {
            continue;
        };
        // Held by a live writer (here or in another process): not stale.
        if file.try_lock().is_err() {
            continue;
        }
        if still_named(&file, &path) && fs::remove_file(&path).is_ok() {
            removed += 1;
        }
    }
    removed
}

/// Creates a temporary `prefix` + random in `dir`, locked, with the replaced file's
/// permissions (or `0666` less the umask), retrying when a concurrent sweep removed it between
/// its creation and its lock.
fn create_locked_temporary(
    dir: &Path,
    prefix: &OsStr,
    existing: Option<&fs::Permissions>,
) -> io::Result<tempfile::NamedTempFile> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(prefix).rand_bytes(RANDOM_LEN);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // The mode passed to `open`, which the umask narrows, as for `File::create`. A
        // replaced file's exact bits are set below.
        builder.permissions(fs::Permissions::from_mode(0o666));
    }
    let mut last = io::Error::other("cannot create a temporary file");
    for _ in 0..CREATE_ATTEMPTS {
        let temp = builder.tempfile_in(dir)?;
        match temp.as_file().try_lock() {
            Ok(()) if still_named(temp.as_file(), temp.path()) => {
                if let Some(permissions) = existing {
                    temp.as_file().set_permissions(permissions.clone())?;
                }
                return Ok(temp);
            }
            // Swept (or being swept) by another writer in the instant before the lock.
            Ok(()) => last = io::Error::other("the temporary file was removed while created"),
            Err(e) => last = io::Error::other(e.to_string()),
        }
    }
    Err(last)
}

/// `error` without the temporary's path that `tempfile` appends to creation errors
/// (`… at path "/dir/.NAME.nendo-tmp-XXXXXX"`): errors name the target, never the temporary.
fn without_temporary_path(error: io::Error) -> io::Error {
    if error.raw_os_error().is_some() {
        return error;
    }
    let message = error.to_string();
    match message.rsplit_once(" at path ") {
        Some((head, _)) => io::Error::new(error.kind(), head.to_owned()),
        None => error,
    }
}

/// Syncs a directory so a rename in it is durable; file systems that cannot are skipped.
fn sync_directory(dir: &Path) -> io::Result<()> {
    #[cfg(unix)]
    {
        match File::open(dir).and_then(|d| d.sync_all()) {
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::InvalidInput | io::ErrorKind::Unsupported
                ) =>
            {
                Ok(())
            }
            other => other,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = dir;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_names_are_recognised_only_for_their_target() {
        let prefix = temp_prefix(OsStr::new("m.json"));
        assert_eq!(prefix, OsStr::new(".m.json.nendo-tmp-"));
        assert!(is_temporary_of(
            OsStr::new(".m.json.nendo-tmp-aB3xY9"),
            &prefix
        ));
        assert!(!is_temporary_of(
            OsStr::new(".m.json.nendo-tmp-aB3xY"),
            &prefix
        ));
        assert!(!is_temporary_of(
            OsStr::new(".m.json.nendo-tmp-aB3x.9"),
            &prefix
        ));
        assert!(!is_temporary_of(
            OsStr::new(".m.jsonx.nendo-tmp-aB3xY9"),
            &prefix
        ));
        assert!(!is_temporary_of(OsStr::new("m.json"), &prefix));
    }

    #[test]
    fn long_names_are_shortened_in_temporaries() {
        let name = "n".repeat(250);
        let prefix = temp_prefix(OsStr::new(&name));
        assert_eq!(prefix.len(), 1 + MAX_NAME_IN_TEMP + TEMP_MARKER.len());
    }
}
