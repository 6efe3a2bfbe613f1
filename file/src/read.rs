//! Bounded reading of the files nendo reads whole (figure, shape, curve and profile files):
//! at most a stated number of bytes is ever read, so a runaway file, a device such as
//! `/dev/zero` or an endless pipe is refused after `limit + 1` bytes — quickly and with a
//! clear error — instead of growing memory until allocation fails.
//!
//! The bound is `limit + 1` bytes read through [`std::io::Read::take`]: a file of exactly
//! `limit` bytes is read, one byte more is refused as [`ReadError::TooLarge`].

use std::io::Read;
use std::path::{Path, PathBuf};

/// Why a bounded read failed. Each message names the file once.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file cannot be opened or read.
    #[error("cannot read {}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        #[source]
        error: std::io::Error,
    },
    /// The file holds more than the limit (or is a device or pipe that never ends).
    #[error(
        "{}: larger than {} ({limit} bytes), the limit for a {what}; not a {what} this build reads",
        path.display(),
        human(*limit)
    )]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// What the file was read as (`figure file`, `device profile`).
        what: &'static str,
        /// The limit in bytes.
        limit: u64,
    },
    /// The file is not UTF-8 text.
    #[error("{}: not UTF-8 text ({error})", path.display())]
    NotText {
        /// The file.
        path: PathBuf,
        /// Where the text stops being UTF-8.
        error: std::str::Utf8Error,
    },
}

/// `bytes` in MB or kB, as the limits are stated.
fn human(bytes: u64) -> String {
    if bytes >= 1 << 20 {
        format!("{} MB", bytes >> 20)
    } else {
        format!("{} kB", bytes >> 10)
    }
}

/// Reads the text file `path` of at most `limit` bytes (`what` names the kind of file in the
/// error), reading no more than `limit + 1` bytes whatever the file is.
///
/// # Errors
/// [`ReadError::Io`], [`ReadError::TooLarge`] or [`ReadError::NotText`].
pub fn read_text_limited(path: &Path, limit: u64, what: &'static str) -> Result<String, ReadError> {
    let io = |error| ReadError::Io {
        path: path.to_path_buf(),
        error,
    };
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(limit.saturating_add(1)).read_to_end(&mut bytes))
        .map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(ReadError::TooLarge {
            path: path.to_path_buf(),
            what,
            limit,
        });
    }
    String::from_utf8(bytes).map_err(|e| ReadError::NotText {
        path: path.to_path_buf(),
        error: e.utf8_error(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_at_the_limit_reads_one_byte_more_is_refused_and_a_device_stops_at_the_limit() {
        let dir = std::env::temp_dir().join(format!("nendo-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temporary directory");
        let path = dir.join("f.json");
        std::fs::write(&path, "0123456789").expect("written");
        assert_eq!(
            read_text_limited(&path, 10, "figure file").expect("at the limit"),
            "0123456789"
        );
        let e = read_text_limited(&path, 9, "figure file").expect_err("over the limit");
        assert!(matches!(e, ReadError::TooLarge { limit: 9, .. }), "{e}");
        assert!(e.to_string().contains("limit for a figure file"), "{e}");
        std::fs::write(&path, b"ab\xffcd").expect("written");
        assert!(matches!(
            read_text_limited(&path, 10, "figure file"),
            Err(ReadError::NotText { .. })
        ));
        #[cfg(unix)]
        {
            let e = read_text_limited(Path::new("/dev/zero"), 1 << 20, "shape file")
                .expect_err("endless");
            assert!(matches!(e, ReadError::TooLarge { .. }), "{e}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
