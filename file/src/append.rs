//! [`AppendFile`]: a file written by appending records under its own name, for recordings that
//! must survive the program being killed, the power failing or the disk filling up.
//!
//! A document is written atomically ([`crate::AtomicFile`]): nothing of it exists until it is
//! complete. A recording is the opposite case: it grows for minutes, and what it holds so far is
//! worth keeping whatever ends the program. Written atomically, a SIGKILL or a power cut would
//! leave only a hidden temporary (which the next write to the same target sweeps away), and a
//! full disk would lose every record. So a recording is appended to the file the user named:
//!
//! - **The head appears whole.** The first bytes (a trace's header) are written to a temporary
//!   beside the target, synced, and renamed into place (with [`Existing::Refuse`] only if no file
//!   is there: `renameat2(RENAME_NOREPLACE)`, else a link-and-unlink). So the target is never a
//!   file with half a header, and a replaced file stays whole until the new head is on disk.
//! - **One write per record.** [`AppendFile::append`] hands each record to the kernel at once
//!   (no user-space buffer): a record appended before a SIGKILL is in the file, since the page
//!   cache outlives the process. A power cut keeps what was synced ([`AppendFile::sync`]; the
//!   caller chooses the cadence).
//! - **A failed append is taken back.** When the file system refuses a record part-way (a full
//!   disk, a file size limit, an I/O error), the file is cut back to its length before that
//!   record, so it still ends with the last complete one; the error names the target. (If even
//!   cutting back fails, the error says so, and the file ends with a torn record, which a
//!   reader of recordings must cope with anyway: a power cut can leave one.)
//! - **An existing file is never replaced by surprise.** [`Existing::Refuse`] refuses a target
//!   that exists ([`crate::WriteError::Exists`]); [`Existing::Replace`] replaces it, keeping its
//!   permission bits, at the moment the new head is in place.
//!
//! As for [`crate::AtomicFile`]: symbolic links are written through, only regular files are
//! replaced, the short-lived temporary is locked and registered for
//! [`crate::remove_live_temporaries`]. Unlike it, creating an append file sweeps no stale
//! temporaries of its target: an older nendo wrote recordings atomically, and a temporary it
//! left when killed holds that session's frames (a recovering trace reader reads them). A
//! stale temporary of an append file itself holds only a head; the next atomic write to the
//! same target sweeps it.

use std::fs::File;
use std::io::{self, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use crate::{
    WriteError, deregister, directory_of, registry, resolve_links, sync_directory, temp_prefix,
    without_temporary_path,
};

/// What [`AppendFile::create`] does when a file is already at the target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Existing {
    /// Refuse: the file is left as it is ([`WriteError::Exists`]).
    Refuse,
    /// Replace it (after asking the user, or on their explicit option): the old file stays
    /// whole until the new head is in place.
    Replace,
}

/// A file grown by appending records (see the module docs). Not buffered: each
/// [`AppendFile::append`] is one write to the kernel.
#[derive(Debug)]
pub struct AppendFile {
    file: File,
    /// The path asked for (named by errors).
    target: PathBuf,
    /// The file's length: its head and every complete record appended.
    len: u64,
}

impl AppendFile {
    /// Creates `target` holding `head`, synced, and keeps it open for appending.
    ///
    /// # Errors
    /// [`WriteError::Exists`] (with [`Existing::Refuse`]), [`WriteError::IsDirectory`],
    /// [`WriteError::NotRegularFile`], [`WriteError::NoFileName`], [`WriteError::SymlinkLoop`],
    /// [`WriteError::Stopping`], or [`WriteError::Io`] (no directory, no permission, no space
    /// for the head: nothing is then left at the target nor beside it).
    pub fn create(
        target: impl AsRef<Path>,
        head: &[u8],
        existing: Existing,
    ) -> Result<AppendFile, WriteError> {
        let target = target.as_ref();
        let io = |error| WriteError::Io {
            path: target.to_path_buf(),
            error,
        };
        let resolved = resolve_links(target)?;
        let permissions = match std::fs::symlink_metadata(&resolved) {
            Ok(m) if m.is_dir() => {
                return Err(WriteError::IsDirectory {
                    path: target.to_path_buf(),
                });
            }
            Ok(m) if !m.is_file() => {
                return Err(WriteError::NotRegularFile {
                    path: target.to_path_buf(),
                });
            }
            Ok(_) if existing == Existing::Refuse => {
                return Err(WriteError::Exists {
                    path: target.to_path_buf(),
                });
            }
            Ok(m) => Some(m.permissions()),
            Err(e) if e.kind() == io::ErrorKind::NotFound => None,
            Err(e) => return Err(io(e)),
        };
        let Some(name) = resolved.file_name().map(std::ffi::OsStr::to_os_string) else {
            return Err(WriteError::NoFileName {
                path: target.to_path_buf(),
            });
        };
        let dir = directory_of(&resolved);
        let prefix = temp_prefix(&name);
        // No sweep of stale temporaries here (unlike `AtomicFile::create`): beside a recording,
        // a stale temporary may be an older nendo's killed recording, whose frames it holds.
        let mut registry = registry();
        if registry.closed {
            return Err(WriteError::Stopping {
                path: target.to_path_buf(),
            });
        }
        let mut temp = crate::create_locked_temporary(&dir, &prefix, permissions.as_ref())
            .map_err(|e| io(without_temporary_path(e)))?;
        let id = registry.next_id;
        registry.next_id += 1;
        registry.live.push((id, temp.path().to_path_buf()));
        drop(registry);
        // On any failure below, dropping `temp` removes the temporary.
        // Through the plain file: `NamedTempFile`'s own errors would name the temporary.
        let written = temp
            .as_file_mut()
            .write_all(head)
            .and_then(|()| temp.as_file().sync_all());
        let placed = written.map_err(io).and_then(|()| {
            let persisted = match existing {
                Existing::Refuse => temp.persist_noclobber(&resolved),
                Existing::Replace => temp.persist(&resolved),
            };
            persisted.map_err(|e| match e.error.kind() {
                io::ErrorKind::AlreadyExists => WriteError::Exists {
                    path: target.to_path_buf(),
                },
                _ => io(e.error),
            })
        });
        deregister(id);
        let file = placed?;
        // The rename is durable once the directory is synced; the head itself was synced.
        sync_directory(&dir).map_err(io)?;
        Ok(AppendFile {
            file,
            target: target.to_path_buf(),
            len: head.len() as u64,
        })
    }

    /// The path asked for.
    #[must_use]
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// The file's length: the head and every record appended.
    #[must_use]
    pub fn len(&self) -> u64 {
        self.len
    }

    /// Whether the file is empty (an empty head and no record).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Appends `record`, whole or not at all: on failure the file is cut back to its length
    /// before, so it ends with the last complete record.
    ///
    /// # Errors
    /// [`WriteError::Io`] naming the target: the file system's error (a full disk is
    /// [`io::ErrorKind::StorageFull`]); when cutting back failed too, the message says so.
    pub fn append(&mut self, record: &[u8]) -> Result<(), WriteError> {
        match self.file.write_all(record) {
            Ok(()) => {
                self.len += record.len() as u64;
                Ok(())
            }
            Err(error) => {
                let cut = self
                    .file
                    .set_len(self.len)
                    .and_then(|()| self.file.seek(SeekFrom::Start(self.len)).map(|_| ()));
                let error = match cut {
                    Ok(()) => error,
                    Err(cut) => io::Error::new(
                        error.kind(),
                        format!(
                            "{error}; cutting the file back to its last complete record failed too ({cut}): it may end with a torn record"
                        ),
                    ),
                };
                Err(WriteError::Io {
                    path: self.target.clone(),
                    error,
                })
            }
        }
    }

    /// Makes every record appended so far durable (`fdatasync`): a power cut keeps them.
    ///
    /// # Errors
    /// [`WriteError::Io`] naming the target (a file system that could not write back what it
    /// had accepted reports it here).
    pub fn sync(&mut self) -> Result<(), WriteError> {
        self.file.sync_data().map_err(|error| WriteError::Io {
            path: self.target.clone(),
            error,
        })
    }
}
