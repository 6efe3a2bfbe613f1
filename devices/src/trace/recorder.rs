//! [`TraceRecorder`]: recording a trace so that whatever ends the recording leaves a trace.
//!
//! A recording is the user's work as it happens: a glove session of minutes cannot be redone
//! the way a file can be saved again. So it is not written atomically (as [`crate::Trace::write`]
//! writes a whole trace), where a SIGKILL or a power cut leaves only a hidden temporary and a
//! full disk loses everything; it is appended, frame by frame, to the file under its own name
//! ([`nendo_file::AppendFile`]):
//!
//! - the header appears first and whole (a temporary renamed into place, synced), so the file
//!   is a trace from its first moment;
//! - **each frame is handed to the kernel as it is pushed** (one `write` per frame line, no
//!   user-space buffer): a SIGKILL loses no frame pushed before it — only those still on their
//!   way from the devices (the stream's channel, at most one poll of the recording loop);
//! - **the file is synced (`fdatasync`) at most [`SYNC_INTERVAL`] after a frame was pushed**
//!   (checked at every push and by [`TraceRecorder::sync_if_due`], which a recording loop calls
//!   while it waits for frames), and at the end: a power cut loses at most about the last
//!   second of frames (what the file system keeps beyond that is its business);
//! - the `end N` line comes last, written by [`TraceRecorder::finish`]. A trace without it is an
//!   interrupted recording, which [`crate::Trace::read_recovering`] reads up to its last
//!   complete frame, saying how many it recovered;
//! - **a write that fails (a full disk, an I/O error) stops the recording**: the frame line it
//!   was writing is taken back, so the file ends with the last complete frame, and every later
//!   push fails with the same [`DeviceError::RecordingStopped`], which names the file and the
//!   frames it keeps. Nothing is retried: frames lost between a failure and a retry would make
//!   a recording with a silent hole in time;
//! - **an existing file is never replaced unless asked** ([`Existing`]): `nendo record` refuses
//!   one unless given `--replace`; the window asks first. A replaced file stays whole until the
//!   new header is in place.
//!
//! Every frame is written as [`crate::trace::quantize_frame`] rounds it, like every trace line.
//!
//! **The gate's marks.** A recorder made with [`TraceRecorder::create_gated`] runs the
//! plausibility gate and filter ([`FrameFilter`]) of the given settings over the frames as it
//! writes them (rounded, as the trace stores them and a replay reads them) and marks each
//! frame where the gate held something (`held=`, [`crate::trace::HeldMarks`]); its header says
//! `marks held` (trace version 4). The gate is a pure function of the frames and the settings,
//! so these are the marks any hand loop with the same settings — the window's, `nendo
//! replay`'s — computes on the same frames. With the gate off ([`FilterSettings::enabled`]
//! false), or made with [`TraceRecorder::create`], it writes no marks and no `marks` line.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use nendo_file::{AppendFile, Existing};

use super::{HeldMarks, TraceHeader, format_header, format_marked_frame, quantize_frame};
use crate::filter::{FilterSettings, FrameFilter};
use crate::{DeviceError, HandFrame, Joint};

/// The longest a pushed frame waits for its `fdatasync`.
pub const SYNC_INTERVAL: Duration = Duration::from_secs(1);

/// A trace being recorded (see the module docs).
#[derive(Debug)]
pub struct TraceRecorder {
    /// The file; `None` once the recording has stopped on an error or finished.
    out: Option<AppendFile>,
    path: PathBuf,
    joints: Vec<Joint>,
    /// The frames carry skeletons (the header's `skeleton` line).
    skeleton: bool,
    /// The gate whose rejections the frames are marked with (the header's `marks held`).
    gate: Option<FrameFilter>,
    /// Frames written with a `held=` mark.
    marked: u64,
    count: u64,
    line: String,
    /// When the file was last synced.
    synced_at: Instant,
    /// Frames pushed since the last sync.
    unsynced: bool,
    /// The error that stopped the recording (its message, repeated by later calls).
    stopped: Option<String>,
}

impl TraceRecorder {
    /// Starts recording to `path`: its header is in the file, synced, when this returns. No
    /// gate runs and no frame is marked (the header is written without `marks held`, whatever
    /// `header.marks_held` says; see [`TraceRecorder::create_gated`]).
    ///
    /// # Errors
    /// [`DeviceError::File`] naming `path`: a file already there with [`Existing::Refuse`]
    /// (kind [`std::io::ErrorKind::AlreadyExists`]), a directory or device at `path`, no
    /// directory, no permission, no space for the header (nothing is then left behind).
    pub fn create(
        path: &Path,
        header: TraceHeader,
        existing: Existing,
    ) -> Result<TraceRecorder, DeviceError> {
        TraceRecorder::create_gated(path, header, existing, FilterSettings::off())
    }

    /// Starts recording to `path` as [`TraceRecorder::create`] does, marking the frames the
    /// gate of `gate` holds (see the module docs): with the gate on, the header says `marks
    /// held` (whatever `header.marks_held` says); off, it has no marks.
    ///
    /// # Errors
    /// As [`TraceRecorder::create`].
    pub fn create_gated(
        path: &Path,
        mut header: TraceHeader,
        existing: Existing,
        gate: FilterSettings,
    ) -> Result<TraceRecorder, DeviceError> {
        header.marks_held = gate.enabled;
        let out =
            AppendFile::create(path, format_header(&header).as_bytes(), existing).map_err(|e| {
                DeviceError::File {
                    path: path.to_path_buf(),
                    error: e.into_io(),
                }
            })?;
        Ok(TraceRecorder {
            out: Some(out),
            path: path.to_path_buf(),
            skeleton: header.skeleton.is_some(),
            gate: gate.enabled.then(|| FrameFilter::new(gate)),
            marked: 0,
            joints: header.joints,
            count: 0,
            line: String::new(),
            synced_at: Instant::now(),
            unsynced: false,
            stopped: None,
        })
    }

    /// The trace's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Frames in the file.
    pub fn frames(&self) -> u64 {
        self.count
    }

    /// Frames in the file marked `held=` (none without the gate).
    pub fn marked(&self) -> u64 {
        self.marked
    }

    /// The gate the frames are marked by (`None`: no marks), with its counters.
    pub fn gate(&self) -> Option<&FrameFilter> {
        self.gate.as_ref()
    }

    /// Appends a frame (one write), syncing the file if [`SYNC_INTERVAL`] has passed.
    ///
    /// # Errors
    /// [`DeviceError::RecordingStopped`]: the write failed (the recording has stopped; the
    /// file keeps every frame before this one), or it had stopped already.
    pub fn push(&mut self, frame: &HandFrame) -> Result<(), DeviceError> {
        if self.out.is_none() {
            return Err(self.not_writable());
        }
        let frame = &quantize_frame(frame, &self.joints);
        let held = match &mut self.gate {
            Some(gate) => {
                gate.apply(frame);
                HeldMarks::from(gate.held()).carried_by(frame, &self.joints, self.skeleton)
            }
            None => HeldMarks::default(),
        };
        self.line.clear();
        format_marked_frame(&self.joints, self.skeleton, frame, &held, &mut self.line);
        let Some(out) = self.out.as_mut() else {
            return Err(self.not_writable());
        };
        if let Err(e) = out.append(self.line.as_bytes()) {
            return Err(self.stop(e.into_io()));
        }
        self.count += 1;
        self.marked += u64::from(!held.is_empty());
        self.unsynced = true;
        self.sync_if_due()
    }

    /// Syncs the file if a frame has waited [`SYNC_INTERVAL`] for it; for a recording loop
    /// to call while no frame comes.
    ///
    /// # Errors
    /// [`DeviceError::RecordingStopped`] when the sync fails (the file system could not keep
    /// what it had taken: the recording stops), or the recording had stopped already.
    pub fn sync_if_due(&mut self) -> Result<(), DeviceError> {
        if self.unsynced && self.synced_at.elapsed() >= SYNC_INTERVAL {
            self.sync()?;
        }
        match &self.stopped {
            Some(_) => Err(self.stopped_error()),
            None => Ok(()),
        }
    }

    fn sync(&mut self) -> Result<(), DeviceError> {
        let Some(out) = self.out.as_mut() else {
            return Err(self.not_writable());
        };
        if let Err(e) = out.sync() {
            return Err(self.stop(e.into_io()));
        }
        self.synced_at = Instant::now();
        self.unsynced = false;
        Ok(())
    }

    /// Ends the recording: the `end` line, then a sync. Returns the number of frames.
    ///
    /// # Errors
    /// [`DeviceError::RecordingStopped`] when the `end` line or the sync fails, or the
    /// recording had stopped already: the file keeps its frames as an interrupted trace.
    pub fn finish(mut self) -> Result<u64, DeviceError> {
        let end = format!("end {}\n", self.count);
        let Some(out) = self.out.as_mut() else {
            return Err(self.not_writable());
        };
        if let Err(e) = out.append(end.as_bytes()) {
            return Err(self.stop(e.into_io()));
        }
        self.sync()?;
        self.out = None;
        Ok(self.count)
    }

    /// Why nothing can be written: the recording stopped on an error, or finished.
    fn not_writable(&self) -> DeviceError {
        match self.stopped {
            Some(_) => self.stopped_error(),
            None => DeviceError::File {
                path: self.path.clone(),
                error: std::io::Error::other("the recording has finished"),
            },
        }
    }

    /// Stops the recording on `error`, returning the error to report.
    fn stop(&mut self, error: std::io::Error) -> DeviceError {
        self.out = None;
        self.stopped = Some(error.to_string());
        DeviceError::RecordingStopped {
            path: self.path.clone(),
            frames: self.count,
            error,
        }
    }

    fn stopped_error(&self) -> DeviceError {
        DeviceError::RecordingStopped {
            path: self.path.clone(),
            frames: self.count,
            error: std::io::Error::other(self.stopped.clone().unwrap_or_default()),
        }
    }
}
