//! [`TraceWriter`]: a whole trace written atomically, frame by frame (for traces made of
//! frames already at hand; a live recording is written by [`super::TraceRecorder`]).

use std::io::Write;
use std::path::{Path, PathBuf};

use super::{HeldMarks, TraceHeader, format_header, format_marked_frame};
use crate::{DeviceError, HandFrame, Joint};

/// Writes a whole trace frame by frame with the one safe writer ([`nendo_file::AtomicFile`]):
/// into a temporary file beside the target, renamed into place by [`TraceWriter::finish`]
/// (through a symbolic link, keeping the replaced file's permissions); dropped unfinished, or
/// on a stop signal handled by the binary, the temporary file is removed. For traces made of
/// frames already at hand; a live recording, which must survive being killed, is written by
/// [`super::TraceRecorder`].
#[derive(Debug)]
pub struct TraceWriter {
    out: Option<nendo_file::AtomicFile>,
    path: PathBuf,
    joints: Vec<Joint>,
    skeleton: bool,
    /// The header has `marks held`.
    marks_held: bool,
    count: u64,
    line: String,
}

impl TraceWriter {
    /// Starts a trace at `path` (nothing appears there until [`TraceWriter::finish`]). A
    /// directory, device, pipe or socket at `path` is refused.
    pub fn create(path: &Path, header: TraceHeader) -> Result<TraceWriter, DeviceError> {
        // Errors name the trace asked for, not the temporary file beside it.
        let io = |error| DeviceError::File {
            path: path.to_path_buf(),
            error,
        };
        let mut out = nendo_file::AtomicFile::create(path).map_err(|e| io(e.into_io()))?;
        // Dropping `out` on failure removes the temporary file.
        out.write_all(format_header(&header).as_bytes())
            .map_err(io)?;
        Ok(TraceWriter {
            out: Some(out),
            path: path.to_path_buf(),
            skeleton: header.skeleton.is_some(),
            marks_held: header.marks_held,
            joints: header.joints,
            count: 0,
            line: String::new(),
        })
    }

    /// Appends a frame. Errors name the trace (not its temporary file).
    pub fn push(&mut self, frame: &HandFrame) -> Result<(), DeviceError> {
        self.push_marked(frame, &HeldMarks::default())
    }

    /// Appends a frame with the gate's marks (written only when the header has `marks held`:
    /// see [`format_marked_frame`]).
    pub fn push_marked(&mut self, frame: &HandFrame, held: &HeldMarks) -> Result<(), DeviceError> {
        self.line.clear();
        let none = HeldMarks::default();
        let held = if self.marks_held { held } else { &none };
        format_marked_frame(&self.joints, self.skeleton, frame, held, &mut self.line);
        let Some(out) = self.out.as_mut() else {
            return Err(DeviceError::File {
                path: self.path.clone(),
                error: std::io::Error::other("trace writer already finished"),
            });
        };
        out.write_all(self.line.as_bytes())
            .map_err(|error| DeviceError::File {
                path: self.path.clone(),
                error,
            })?;
        self.count += 1;
        Ok(())
    }

    /// Frames written so far.
    pub fn frames(&self) -> u64 {
        self.count
    }

    /// Writes the `end` line, flushes, syncs and renames the file into place. Returns the number
    /// of frames. On failure the temporary file is removed and nothing appears at the path.
    pub fn finish(mut self) -> Result<u64, DeviceError> {
        let Some(mut out) = self.out.take() else {
            return Ok(self.count);
        };
        writeln!(out, "end {}", self.count).map_err(|error| DeviceError::File {
            path: self.path.clone(),
            error,
        })?;
        out.commit().map_err(|e| DeviceError::File {
            path: self.path.clone(),
            error: e.into_io(),
        })?;
        Ok(self.count)
    }
}
