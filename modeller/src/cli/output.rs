//! Standard output of the subcommands: writes that return errors instead of panicking, as
//! `println!` does ("failed printing to stdout") when stdout is full or closed.
//!
//! The convention every subcommand follows:
//! - a write that fails (a full disk, `> /dev/full`, an I/O error) is reported on stderr as
//!   `nendo CMD: cannot write to standard output: …` and the command exits with status 1;
//! - a closed pipe (`nendo check m.json | head -c1`) ends the command quietly with status
//!   [`BROKEN_PIPE_EXIT`] (141 = 128 + SIGPIPE): what a shell reports for a Unix tool that a
//!   broken pipe ended (Rust programs ignore SIGPIPE, so the status is given explicitly).
//!
//! Messages on stderr still use `eprintln!`.

use std::fmt::Display;
use std::io::{self, Write};
use std::process::ExitCode;

/// The exit status after a closed pipe: 128 + SIGPIPE, as a shell reports it.
pub const BROKEN_PIPE_EXIT: u8 = 141;

/// Standard output could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write to standard output: {0}")]
pub struct StdoutError(#[from] pub io::Error);

/// Writes `text` to standard output and flushes it.
///
/// # Errors
/// [`StdoutError`] when the write or the flush fails.
pub fn print(text: impl Display) -> Result<(), StdoutError> {
    let mut out = io::stdout().lock();
    write!(out, "{text}")?;
    out.flush()?;
    Ok(())
}

/// Writes `text` and a newline to standard output and flushes it.
///
/// # Errors
/// [`StdoutError`] when the write or the flush fails.
pub fn println(text: impl Display) -> Result<(), StdoutError> {
    let mut out = io::stdout().lock();
    writeln!(out, "{text}")?;
    out.flush()?;
    Ok(())
}

/// The exit for a failed write to standard output by `command` (such as `nendo check`): quiet
/// on a closed pipe, else a message on stderr.
#[must_use]
pub fn stdout_failed(command: &str, error: &io::Error) -> ExitCode {
    if error.kind() == io::ErrorKind::BrokenPipe {
        ExitCode::from(BROKEN_PIPE_EXIT)
    } else {
        eprintln!("{command}: cannot write to standard output: {error}");
        ExitCode::FAILURE
    }
}

/// The exit for a failed `command` (such as `nendo figure`): a [`StdoutError`] as
/// [`stdout_failed`], anything else printed with its causes, status 1.
#[must_use]
pub fn failed(command: &str, error: &anyhow::Error) -> ExitCode {
    match error.downcast_ref::<StdoutError>() {
        Some(StdoutError(e)) => stdout_failed(command, e),
        None => {
            eprintln!("{command}: {error:#}");
            ExitCode::FAILURE
        }
    }
}

/// Success, or the exit for a failed write to standard output by `command`.
#[must_use]
pub fn exit_after(command: &str, written: Result<(), StdoutError>) -> ExitCode {
    match written {
        Ok(()) => ExitCode::SUCCESS,
        Err(StdoutError(e)) => stdout_failed(command, &e),
    }
}
