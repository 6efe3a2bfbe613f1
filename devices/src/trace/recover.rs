//! Reading an interrupted recording: what [`Trace::parse_recovering`] recovers, the notice it
//! gives, and [`Trace::read_recovering`], which also copes with bytes that are not text at the
//! end of a file (see the format's docs in [`super`]).

use std::path::Path;

use super::Trace;
use crate::DeviceError;

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
    pub(super) fn interrupted(trace: Trace, dropped: Option<DroppedTail>) -> Self {
        Recovered {
            interrupted: Some(Interrupted {
                frames: trace.frames.len(),
                dropped,
            }),
            trace,
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
    /// The file is read line by line ([`super::TraceStream`]): no line beyond its limit is
    /// held, and only the frames are kept.
    pub fn read_recovering(path: &Path) -> Result<Recovered, DeviceError> {
        let mut stream = super::TraceStream::open(path)?;
        let mut frames = Vec::new();
        let mut held = Vec::new();
        while let Some(f) = stream.next_frame()? {
            if !stream.held().is_empty() {
                held.push((frames.len(), stream.held()));
            }
            frames.push(f);
        }
        let interrupted = stream.interrupted().cloned();
        Ok(Recovered {
            trace: Trace {
                header: stream.header().clone(),
                frames,
                held,
            },
            interrupted,
        })
    }
}
