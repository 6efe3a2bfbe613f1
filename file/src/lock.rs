//! Writers of one file taking turns: [`WriterLock`], an advisory lock held while a program
//! reads a file, works on it and writes it back, so that two such read–modify–write runs
//! (`nendo sculpt --model m --out m` twice at once, or the window saving while one runs)
//! follow each other instead of one silently losing the other's update.
//!
//! The lock is an exclusive `flock` on a lock file beside the target's real file (symbolic
//! links resolved): `.NAME.nendo-lock` for a target `NAME`. It is taken with
//! [`WriterLock::acquire`], which waits up to a given time and then fails with
//! [`LockError::Busy`] naming the lock file; it is let go when the [`WriterLock`] is dropped,
//! and by the system when its process ends, however it ends.
//!
//! The lock file is removed on release so none is left beside the user's files. Removing a
//! lock file another process may have opened is safe because every taker checks, once it
//! holds the lock, that the file it locked is still the one at the lock's path (same device
//! and inode); a taker that locked a removed file lets it go and tries again.
//!
//! Limits: advisory — a program that does not take the lock is not stopped; network file
//! systems may emulate `flock` poorly.

use std::fs::{self, File, OpenOptions};
use std::io;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// What can go wrong taking a [`WriterLock`].
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    /// Another writer held the lock for the whole wait.
    #[error(
        "{}: another nendo is writing it (lock {} held for {:.0} s); nothing written, try again",
        target.display(),
        lock.display(),
        waited.as_secs_f64()
    )]
    Busy {
        /// The file to be written.
        target: PathBuf,
        /// The lock file.
        lock: PathBuf,
        /// How long the taker waited.
        waited: Duration,
    },
    /// The lock file could not be created or locked.
    #[error("{}: cannot take the writer lock {}: {error}", target.display(), lock.display())]
    Io {
        /// The file to be written.
        target: PathBuf,
        /// The lock file.
        lock: PathBuf,
        /// The underlying error.
        error: io::Error,
    },
}

/// An exclusive lock on writing one file (see the module docs); let go when dropped.
#[derive(Debug)]
pub struct WriterLock {
    file: Option<File>,
    lock: PathBuf,
}

/// The lock file of `target`: `.NAME.nendo-lock` beside the target's real file.
#[must_use]
pub fn lock_path(target: &Path) -> PathBuf {
    // The file the target finally names, so a link and its file share one lock.
    let real = fs::canonicalize(target).unwrap_or_else(|_| {
        let parent = target
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let parent = fs::canonicalize(parent).unwrap_or_else(|_| parent.to_path_buf());
        match target.file_name() {
            Some(name) => parent.join(name),
            None => target.to_path_buf(),
        }
    });
    let mut name = std::ffi::OsString::from(".");
    name.push(real.file_name().unwrap_or_default());
    name.push(".nendo-lock");
    real.with_file_name(name)
}

/// True when `file` is the file at `path` now (not one removed or replaced since it was
/// opened).
fn still_there(file: &File, path: &Path) -> io::Result<bool> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let held = file.metadata()?;
        match fs::metadata(path) {
            Ok(now) => Ok(now.dev() == held.dev() && now.ino() == held.ino()),
            Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(false),
            Err(e) => Err(e),
        }
    }
    #[cfg(not(unix))]
    {
        let _ = file;
        Ok(path.exists())
    }
}

impl WriterLock {
    /// How often a waiting taker tries again.
    const POLL: Duration = Duration::from_millis(10);

    /// Takes the lock on writing `target`, waiting up to `wait` for another writer to finish.
    ///
    /// # Errors
    /// [`LockError::Busy`] when another writer held it for the whole wait; [`LockError::Io`]
    /// when the lock file cannot be created or locked (a read-only folder, say).
    pub fn acquire(target: &Path, wait: Duration) -> Result<WriterLock, LockError> {
        let lock = lock_path(target);
        let io_error = |error| LockError::Io {
            target: target.to_path_buf(),
            lock: lock.clone(),
            error,
        };
        let start = Instant::now();
        loop {
            let file = OpenOptions::new()
                .create(true)
                .truncate(false)
                .write(true)
                .open(&lock)
                .map_err(io_error)?;
            match file.try_lock() {
                Ok(()) => {
                    if still_there(&file, &lock).map_err(io_error)? {
                        return Ok(WriterLock {
                            file: Some(file),
                            lock,
                        });
                    }
                    // A lock file its holder removed on release: try the new one.
                    continue;
                }
                Err(fs::TryLockError::WouldBlock) => {}
                Err(fs::TryLockError::Error(e)) => return Err(io_error(e)),
            }
            drop(file);
            let waited = start.elapsed();
            if waited >= wait {
                return Err(LockError::Busy {
                    target: target.to_path_buf(),
                    lock,
                    waited,
                });
            }
            std::thread::sleep(Self::POLL.min(wait - waited));
        }
    }

    /// The lock file.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.lock
    }
}

impl Drop for WriterLock {
    fn drop(&mut self) {
        // Removed while still held, so a taker never locks a file about to go unnoticed.
        let _ = fs::remove_file(&self.lock);
        drop(self.file.take());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;
    use std::sync::atomic::{AtomicUsize, Ordering};

    fn temp(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("nendo-writer-lock-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).expect("temp dir");
        dir
    }

    /// Eight threads each add one line to a file, read–modify–write under the lock: every
    /// line is there, and no lock file is left.
    #[test]
    fn writers_take_turns_and_leave_no_lock_file() {
        let dir = temp("turns");
        let target = dir.join("m.txt");
        fs::write(&target, "").expect("written");
        let inside = Arc::new(AtomicUsize::new(0));
        let threads: Vec<_> = (0..8)
            .map(|i| {
                let target = target.clone();
                let inside = Arc::clone(&inside);
                std::thread::spawn(move || {
                    let lock = WriterLock::acquire(&target, Duration::from_secs(60)).expect("lock");
                    assert_eq!(inside.fetch_add(1, Ordering::SeqCst), 0, "one at a time");
                    let mut text = fs::read_to_string(&target).expect("read");
                    std::thread::sleep(Duration::from_millis(5));
                    text.push_str(&format!("{i}\n"));
                    crate::write_bytes(&target, text.as_bytes()).expect("write");
                    inside.fetch_sub(1, Ordering::SeqCst);
                    drop(lock);
                })
            })
            .collect();
        for t in threads {
            t.join().expect("thread");
        }
        let text = fs::read_to_string(&target).expect("read");
        let mut lines: Vec<_> = text.lines().collect();
        lines.sort_unstable();
        assert_eq!(lines, ["0", "1", "2", "3", "4", "5", "6", "7"]);
        assert!(!lock_path(&target).exists(), "the lock file is removed");
        let _ = fs::remove_dir_all(&dir);
    }

    /// A lock held for the whole wait fails with a message naming the lock file.
    #[test]
    fn a_held_lock_fails_clearly_after_the_wait() {
        let dir = temp("busy");
        let target = dir.join("m.json");
        let held = WriterLock::acquire(&target, Duration::ZERO).expect("first");
        let e = WriterLock::acquire(&target, Duration::from_millis(50)).expect_err("busy");
        assert!(matches!(e, LockError::Busy { .. }), "{e}");
        let text = e.to_string();
        assert!(
            text.contains("another nendo is writing") && text.contains(".m.json.nendo-lock"),
            "{text}"
        );
        drop(held);
        WriterLock::acquire(&target, Duration::ZERO).expect("free again");
        let _ = fs::remove_dir_all(&dir);
    }
}
