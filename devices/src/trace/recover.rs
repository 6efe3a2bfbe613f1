//! Reading an interrupted recording: what [`Trace::parse_recovering`] recovers, the notice it
//! gives, and [`Trace::read_recovering`], which also copes with bytes that are not text at the
//! end of a file (see the format's docs in [`super`]).

use std::path::Path;

use super::{Trace, TraceHeader};
use crate::{DeviceError, HandFrame};

/// A trace read with [`Trace::parse_recovering`] or [`Trace::read_recovering`].
#[derive(Debug, Clone, PartialEq)]
pub struct Recovered {
    /// The trace: whole, or the complete frames of an interrupted recording.
    pub trace: Trace,
    /// `Some` when the trace has no `end` line: a recording interrupted (killed, a power
    /// cut, a full disk) — what it recovered and what it dropped.
    pub interrupted: Option<Interrupted>,
}

impl Recovered {
    pub(super) fn interrupted(
        header: TraceHeader,
        frames: Vec<HandFrame>,
        dropped: Option<DroppedTail>,
    ) -> Self {
        Recovered {
            interrupted: Some(Interrupted {
                frames: frames.len(),
                dropped,
            }),
            trace: Trace { header, frames },
        }
    }
}

/// What reading an interrupted recording recovered; its `Display` is the notice users see:
/// `an interrupted recording (no `end` line): recovered its 1234 complete frames; its last
/// line (line 1240) was cut short and is dropped`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Interrupted {
    /// The complete frames recovered.
    pub frames: usize,
    /// The lines dropped at its end, if any.
    pub dropped: Option<DroppedTail>,
}

/// The damaged end of an interrupted recording, dropped when it is read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DroppedTail {
    /// Its first line (1-based).
    pub line: usize,
    /// How many lines it has (from its first to the end of the file).
    pub lines: usize,
    /// It is one last line without its newline: cut short mid-write.
    pub cut_short: bool,
    /// Why its first line does not read.
    pub reason: String,
}

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "an interrupted recording (no `end` line): recovered its {} complete frame{}",
            self.frames,
            if self.frames == 1 { "" } else { "s" }
        )?;
        match &self.dropped {
            None => Ok(()),
            Some(t) if t.cut_short => write!(
                f,
                "; its last line (line {}) was cut short and is dropped",
                t.line
            ),
            Some(t) if t.lines <= 1 => write!(
                f,
                "; its last line (line {}) does not read ({}) and is dropped",
                t.line, t.reason
            ),
            Some(t) => write!(
                f,
                "; line {} does not read ({}) and is dropped with the {} line{} after it",
                t.line,
                t.reason,
                t.lines - 1,
                if t.lines == 2 { "" } else { "s" }
            ),
        }
    }
}

impl Trace {
    /// Reads a trace file, recovering an interrupted recording (see
    /// [`Trace::parse_recovering`]). Bytes that are not UTF-8 text at the end of an
    /// unfinished trace (what a power cut can leave) are dropped with the line they start in.
    pub fn read_recovering(path: &Path) -> Result<Recovered, DeviceError> {
        let bytes = std::fs::read(path).map_err(|error| DeviceError::File {
            path: path.to_path_buf(),
            error,
        })?;
        let (text, rest) = match std::str::from_utf8(&bytes) {
            Ok(text) => (text, &[][..]),
            Err(e) => {
                // Cut at the start of the line holding the first byte that is not UTF-8.
                let valid = &bytes[..e.valid_up_to()];
                let cut = valid.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
                let (text, rest) = bytes.split_at(cut);
                (std::str::from_utf8(text).unwrap_or_default(), rest)
            }
        };
        let mut recovered = Trace::parse_recovering(text)?;
        if !rest.is_empty() {
            let line = text.lines().count() + 1;
            let lines = rest
                .split(|&b| b == b'\n')
                .filter(|l| !l.is_empty())
                .count();
            match &mut recovered.interrupted {
                // A finished trace followed by bytes that are not text.
                None => {
                    return Err(DeviceError::TraceSyntax {
                        line,
                        message: "text after the end line (and not UTF-8)".into(),
                    });
                }
                Some(i) => match &mut i.dropped {
                    Some(tail) => {
                        tail.lines += lines;
                        tail.cut_short = false;
                    }
                    None => {
                        i.dropped = Some(DroppedTail {
                            line,
                            lines,
                            cut_short: false,
                            reason: "not UTF-8 text".into(),
                        });
                    }
                },
            }
        }
        Ok(recovered)
    }
}
