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
//!
//! Lines are read with a bounded reader ([`nendo_file::read_line_bounded`]): a line holds at most [`MAX_LINE_BYTES`] (16 MB, room
//! for a request of about 300 000 points). A longer line is never held: its bytes are skipped
//! up to its newline, it is answered with `{"error":"line N is longer than …"}`, and the next
//! line is read, so an endless line costs the limit in memory and is answered at the end of
//! the input.

use nendo_file::{Line, Overlong, read_line_bounded};
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

/// Longest request line held: 16 MB.
pub const MAX_LINE_BYTES: usize = 16 << 20;

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
    output: impl Write,
    answer: impl FnMut(&str) -> Result<Value, E>,
) -> Result<usize, LinesError> {
    answer_lines_limited(input, output, MAX_LINE_BYTES, answer)
}

/// [`answer_lines`] with a line limit of `limit` bytes.
///
/// # Errors
/// As [`answer_lines`].
pub fn answer_lines_limited<E: Display>(
    mut input: impl BufRead,
    mut output: impl Write,
    limit: usize,
    mut answer: impl FnMut(&str) -> Result<Value, E>,
) -> Result<usize, LinesError> {
    let mut failed = 0;
    let mut buf = Vec::new();
    let mut number = 0u64;
    loop {
        let read = read_line_bounded(&mut input, &mut buf, limit, Overlong::SkipThrough)
            .map_err(LinesError::Read)?;
        number += 1;
        let error = match read {
            Line::End => break,
            Line::TooLong { bytes: n } => Some(format!(
                "line {number} is longer than the limit of {} MB ({n} bytes): not read; the next line is",
                limit >> 20
            )),
            Line::Text { .. } => match std::str::from_utf8(&buf) {
                Ok(_) => None,
                Err(_) => Some("line is not valid UTF-8".to_owned()),
            },
        };
        if let Some(error) = error {
            failed += 1;
            writeln!(output, "{}", json!({ "error": error }))
                .and_then(|()| output.flush())
                .map_err(LinesError::Write)?;
            continue;
        }
        let line = std::str::from_utf8(&buf).unwrap_or_default();
        if line.trim().is_empty() {
            continue;
        }
        let reply = match answer(line) {
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

    #[test]
    fn an_over_long_line_is_answered_with_an_error_and_the_next_line_is_read() {
        let long = "x".repeat(100);
        let input = format!("a\r\n{long}\nb\n{long}");
        let mut out = Vec::new();
        // A reader that hands over a few bytes at a time: lines cross buffer boundaries.
        let reader = io::BufReader::with_capacity(7, input.as_bytes());
        let failed = answer_lines_limited(reader, &mut out, 50, echo).expect("in-memory io");
        assert_eq!(failed, 2);
        let text = String::from_utf8(out).expect("utf-8 output");
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 4, "{text}");
        assert_eq!(lines[0], r#"{"echo":"a"}"#);
        assert!(
            lines[1].contains("line 2 is longer than the limit"),
            "{text}"
        );
        assert!(lines[1].contains("100 bytes"), "{text}");
        assert_eq!(lines[2], r#"{"echo":"b"}"#);
        assert!(lines[3].contains("line 4 is longer"), "{text}");
    }
}
