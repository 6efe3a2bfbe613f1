//! The JSON Lines loop shared by the batch subcommands (`nendo closest --batch`,
//! `nendo curve --batch`): one request per input line on stdin, one answer per output line on
//! stdout, in the same order.
//!
//! A line that is not UTF-8 or that the command cannot answer gets `{"error":"<what is wrong>"}`
//! and later lines are still answered; blank lines are skipped; every answer is flushed as it is
//! written, so a caller can talk to the command line by line. The exit status is 0 when every
//! line was answered, 1 if any line failed, 2 on an input or output error (named as one of
//! standard input or standard output), and [`super::output::BROKEN_PIPE_EXIT`] when the reader
//! closed the pipe.

use serde_json::{Value, json};
use std::fmt::Display;
use std::io::{self, BufRead, Write};
use std::process::ExitCode;

/// Why the loop stopped before the end of its input.
#[derive(Debug, thiserror::Error)]
pub enum LinesError {
    /// Reading a request failed.
    #[error("cannot read standard input: {0}")]
    Read(io::Error),
    /// Writing or flushing an answer failed.
    #[error("cannot write to standard output: {0}")]
    Write(io::Error),
}

/// Runs a batch subcommand `nendo COMMAND --batch` over stdin and stdout with `answer`
/// answering each request line. Without `--batch` it says that only batch mode exists.
pub fn run<E: Display>(
    command: &str,
    batch: bool,
    answer: impl FnMut(&str) -> Result<Value, E>,
) -> ExitCode {
    if !batch {
        eprintln!(
            "nendo {command}: only --batch mode exists: JSON Lines requests on stdin (see `nendo {command} --help` and the module docs)"
        );
        return ExitCode::from(2);
    }
    let stdin = io::stdin();
    let stdout = io::stdout();
    let mut out = io::BufWriter::new(stdout.lock());
    match answer_lines(stdin.lock(), &mut out, answer) {
        Ok(0) => ExitCode::SUCCESS,
        Ok(_) => ExitCode::from(1),
        // A closed pipe ends the command quietly (see `super::output`).
        Err(LinesError::Write(e)) if e.kind() == io::ErrorKind::BrokenPipe => {
            ExitCode::from(super::output::BROKEN_PIPE_EXIT)
        }
        Err(e) => {
            eprintln!("nendo {command}: {e}");
            ExitCode::from(2)
        }
    }
}

/// Answers every request line of `input` on `output` with `answer`; returns how many lines
/// failed.
///
/// # Errors
/// [`LinesError::Read`] when reading the input failed, [`LinesError::Write`] when writing the
/// output did.
pub fn answer_lines<E: Display>(
    input: impl BufRead,
    mut output: impl Write,
    mut answer: impl FnMut(&str) -> Result<Value, E>,
) -> Result<usize, LinesError> {
    let mut failed = 0;
    for line in input.lines() {
        let line = match line {
            Ok(l) => l,
            Err(e) if e.kind() == io::ErrorKind::InvalidData => {
                failed += 1;
                writeln!(output, "{}", json!({ "error": "line is not valid UTF-8" }))
                    .map_err(LinesError::Write)?;
                continue;
            }
            Err(e) => return Err(LinesError::Read(e)),
        };
        if line.trim().is_empty() {
            continue;
        }
        let reply = match answer(&line) {
            Ok(v) => v,
            Err(e) => {
                failed += 1;
                json!({ "error": e.to_string() })
            }
        };
        writeln!(output, "{reply}")
            .and_then(|()| output.flush())
            .map_err(LinesError::Write)?;
    }
    Ok(failed)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn echo(line: &str) -> Result<Value, String> {
        match line.trim() {
            "bad" => Err("bad line".to_string()),
            other => Ok(json!({ "echo": other })),
        }
    }

    #[test]
    fn answers_in_order_skips_blank_lines_and_counts_failures() {
        let input: &[u8] = b"a\n\n  \nbad\nb\n\xff\xfe\nc";
        let mut out = Vec::new();
        let failed = answer_lines(input, &mut out, echo).expect("in-memory io");
        assert_eq!(failed, 2);
        let text = String::from_utf8(out).expect("utf-8 output");
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines,
            [
                r#"{"echo":"a"}"#,
                r#"{"error":"bad line"}"#,
                r#"{"echo":"b"}"#,
                r#"{"error":"line is not valid UTF-8"}"#,
                r#"{"echo":"c"}"#,
            ]
        );
    }
}
