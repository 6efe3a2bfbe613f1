//! Recorded traces: a versioned, line-oriented, human-readable format for hand frames.
//!
//! ```text
//! nendo-hand-trace 2
//! # comments may appear anywhere before `frames`
//! profile cyberglove2-18-fastrak
//! world_from_tracker {"translation":[0.0,-0.3,0.0],"rotation_wxyz":[1.0,0.0,0.0,0.0],"scale":1.0}
//! hand {"side":"right","palm_length":0.095,…}
//! joints index_mcp index_pip
//! scene {"primitive":{"name":"sphere","patches":[8,4],"radius":3.0},"finger":"index",…}
//! frames
//! 0 ok* ok 0 P 0.100000 0.200000 -0.050000 1.000000 0.000000 0.000000 0.000000 J 0.250000 0.500000
//! 8333 ok ok* 1 P 0.100000 0.200000 -0.050000 1.000000 0.000000 0.000000 0.000000 J 0.260000 ?
//! 16666 lost ok* 1 P - J 0.270000 0.510000
//! end 3
//! ```
//!
//! - Line 1 names the format and its version ([`TRACE_FORMAT`], [`TRACE_VERSION`]). This crate
//!   reads versions 1 to 4 ([`OLDEST_TRACE_VERSION`]) and writes the oldest that holds the
//!   header: version 2, version 3 for a trace of skeleton frames (a `skeleton` header line),
//!   version 4 for a trace whose header says its frames carry the gate's marks (`marks held`).
//!   A recorder decides that before its first frame (it runs the gate or it does not,
//!   [`TraceRecorder::create_gated`]), so a version-4 recording in which the gate never held
//!   anything has the line and no `held=` field: it says "nothing was held", where a version-3
//!   trace says nothing about the gate.
//! - Header lines, each a keyword and its value: `profile` (optional, the rest of the line),
//!   `world_from_tracker` and `hand` (optional, one-line JSON as in profiles, validated by the
//!   same rules; defaults when absent), `joints` (the glove columns of every frame, by joint
//!   name; may be empty), and — since version 2 — `scene`: the scene the trace was recorded
//!   on, `none` or one line of JSON (an object). This crate knows nothing of geometry: it
//!   checks only that the scene is one line of well-formed JSON that is an object and carries
//!   it as text ([`SceneText`]); the application defines its members (in nendo, the start
//!   surface and the session's settings, `nendo::hand::scene`). The writer always writes
//!   the `scene` line (last, as it may hold a whole model); a version-2 header without one
//!   reads as `scene none`, and a version-1 header must not have one.
//! - Since version 3, `skeleton left` or `skeleton right` (before `scene`): the frames carry a
//!   hand as joint poses ([`crate::skeleton`]), each in an `S` section after its `J` columns
//!   (module `skeleton` says how it is written). A trace without the line has no `S` sections.
//! - Since version 4, `marks held` (before `scene`): the frames carry the plausibility gate's
//!   marks, the per-frame field `held=` below. `marks` names the per-frame fields the frames
//!   may carry; `held` is the only one defined.
//! - `frames` ends the header. Each following line is one frame:
//!   `time tracker glove buttons P pose J angles`, where
//!   - `time` is in microseconds since the recording started, never decreasing;
//!   - `tracker` and `glove` are source states `none`, `ok`, `silent`, `lost`, with `*` appended
//!     when the frame carries a new sample of that source; only an `ok` source carries values
//!     (a pose after `P`, angles after `J`): a frame with values for a `none`, `silent` or
//!     `lost` source is an error, so a trace can never drive the surface from a device that
//!     was not delivering;
//!   - `buttons` is the decimal button mask;
//!   - `P` is followed by `x y z qw qx qy qz` (metres, unit quaternion) or by `-`;
//!   - `J` is followed by one column per header joint (radians, `?` for a joint missing in this
//!     frame) or by a single `-` when the frame has no glove data;
//!   - then optional **per-frame fields**, each one word `name=value` (`name` lowercase ASCII
//!     letters, digits and `_`, starting with a letter; `value` not empty). They are the
//!     format's extension point for what a frame carries besides its samples. No joint
//!     column, `-` or `?` holds an `=`, so the first word that does starts them. Version 4
//!     defines one, `held=CHANNELS` ([`HeldMarks`], module `held`: e.g.
//!     `held=position,orientation`, `held=index_pip`, `held=index_tip.position`): the channels
//!     of this frame the recording's plausibility gate ([`crate::filter`]) rejected, written
//!     only on such frames and only in a trace whose header has `marks held` (elsewhere it
//!     is refused, [`FrameError::HeldUndeclared`]), at most once per frame. The reader refuses
//!     any field it does not know ([`FrameError::UnknownField`]) instead of replaying a frame
//!     without what it says.
//! - `end N` closes the trace and repeats the number of frames, so truncation is detected.
//!
//! **Interrupted recordings.** A recording ([`TraceRecorder`], module `recorder`) writes its
//! header first and appends each frame line as it comes, so a recording that is killed, cut
//! by a power failure or stopped by a full disk is a trace without its `end` line, perhaps
//! ending in a torn line. [`Trace::parse`] and [`Trace::read`] refuse it (as truncated);
//! [`Trace::parse_recovering`] and [`Trace::read_recovering`] read it up to its last complete
//! frame and say so ([`Recovered`], [`Interrupted`]: how many frames, which lines were
//! dropped). A finished trace reads the same either way, and a bad line in one is an error
//! either way: only the end of an unfinished trace is ever dropped.
//!
//! Version 1 is version 2 without the `scene` line: its frames read the same, and its header
//! reads with no scene. Writing a parsed version-1 trace writes it as version 2 (with
//! `scene none`).
//!
//! Every number is written with exactly six decimals (1 µm, 1 µrad, 10⁻⁶ of a quaternion) and
//! read back only in that form, so traces diff cleanly and parse back bit-exactly: writing a
//! parsed (version-2) trace reproduces its text, and parsing a written trace reproduces its
//! frames rounded to six decimals ([`quantize_frame`], the one rounding of frames, which a
//! [`crate::HandStream`] applies to every frame it delivers — so a live session and the
//! replay of its recording see the same numbers); the scene is carried as its exact text.
//! Reading errors carry the 1-based line number; a file whose last line is cut short (no
//! final newline, and the line does not read) is reported as truncated.

use std::fmt::Write as _;

use std::path::Path;

use glam::{DQuat, DVec3};

use crate::profile::{HandSize, WorldFromTracker};

mod header;
mod held;
mod recorder;
mod recover;
mod skeleton;
mod stream;
mod writer;
use crate::{
    DeviceError, FrameStatus, HandFrame, Joint, JointAngles, SourceState, Timestamp, TrackerPose,
};
use header::{parse_header_line, parse_version_line};
pub use held::{HELD_FIELD, HeldMarks};
pub use nendo_file::Existing;
pub use recorder::{SYNC_INTERVAL, TraceRecorder};
pub use recover::{DroppedTail, Interrupted, Recovered};
pub use stream::{MAX_FRAME_LINE_BYTES, MAX_HEADER_LINE_BYTES, TraceStream};
pub use writer::TraceWriter;

/// The format name on the first line.
pub const TRACE_FORMAT: &str = "nendo-hand-trace";
/// The newest format version this crate writes and reads: version 4, the gate's marks.
pub const TRACE_VERSION: u32 = 4;
/// The version of a trace without skeleton frames or marks (written as before they came).
pub const GLOVE_TRACE_VERSION: u32 = 2;
/// The version of a trace of skeleton frames without marks.
pub const SKELETON_TRACE_VERSION: u32 = 3;
/// The version of a trace with the gate's marks (the header line `marks held`).
pub const MARKED_TRACE_VERSION: u32 = 4;
/// The oldest format version this crate reads: version 1, without the `scene` header line.
pub const OLDEST_TRACE_VERSION: u32 = 1;
/// Decimals of every number in a trace.
pub const DECIMALS: usize = 6;

/// The header of a trace.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TraceHeader {
    /// The profile the trace was recorded with.
    pub profile: Option<String>,
    /// The profile's tracker-to-world transform.
    pub world_from_tracker: WorldFromTracker,
    /// The profile's hand dimensions.
    pub hand: HandSize,
    /// The glove columns of every frame.
    pub joints: Vec<Joint>,
    /// The scene the trace was recorded on (`None`: the trace does not say; always `None`
    /// for a version-1 trace).
    pub scene: Option<SceneText>,
    /// The hand of the frames' skeletons (`None`: the frames carry none; trace version 3).
    pub skeleton: Option<crate::profile::Side>,
    /// The frames carry the plausibility gate's marks, `held=` (the header line `marks held`,
    /// trace version 4; see [`HeldMarks`]): a frame without one had nothing held. `false`:
    /// the trace says nothing about the gate.
    pub marks_held: bool,
}

/// The `scene` of a trace header: one line of well-formed JSON whose value is an object,
/// carried as its exact text. What its members mean is the application's business (this
/// crate knows nothing of geometry); a trace only guarantees that the text reads as JSON and
/// fits on its header line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SceneText(String);

impl SceneText {
    /// Checks that `json` is one line of well-formed JSON whose value is an object; blanks
    /// around it are dropped (the header line would not keep them).
    ///
    /// # Errors
    /// [`DeviceError::InvalidValue`] saying what is wrong: a line break (the scene must fit
    /// on its header line), text that is not JSON (with serde_json's line and column), or a
    /// JSON value that is not an object.
    pub fn new(json: impl Into<String>) -> Result<SceneText, DeviceError> {
        let mut json = json.into();
        let trimmed = json.trim();
        if trimmed.len() != json.len() {
            json = trimmed.to_owned();
        }
        if json.contains(['\n', '\r']) {
            return Err(DeviceError::InvalidValue(
                "scene: the JSON must be on one line (a line break in it)".into(),
            ));
        }
        // Validated without building a JSON tree: a scene may hold a whole model.
        serde_json::from_str::<serde::de::IgnoredAny>(&json)
            .map_err(|e| DeviceError::InvalidValue(format!("scene: not well-formed JSON: {e}")))?;
        if !json.starts_with('{') {
            return Err(DeviceError::InvalidValue(
                "scene: expected a JSON object `{...}`".into(),
            ));
        }
        Ok(SceneText(json))
    }

    /// The JSON text.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl std::fmt::Display for SceneText {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// A whole trace in memory.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Trace {
    /// The header.
    pub header: TraceHeader,
    /// The frames, in time order.
    pub frames: Vec<HandFrame>,
    /// The gate's marks: the frames where it held something (by index into `frames`,
    /// increasing) and what it held, as the `held=` fields say (see [`HeldMarks`]). Read only
    /// from a trace with `marks held` (empty otherwise). Written by [`Trace::to_text`] and
    /// [`Trace::write`]; a trace with marks is written with `marks held` whatever its header
    /// says, and marks on an index past the frames, or empty ones, are not written.
    pub held: Vec<(usize, HeldMarks)>,
}

/// Rounds a value to the trace's six decimals, exactly as writing and reading it would.
pub fn quantize(x: f64) -> f64 {
    format!("{x:.DECIMALS$}").parse().unwrap_or(x)
}

/// A frame as it will read back from a trace with these header joints: numbers rounded to six
/// decimals, joints outside the header dropped, values of a source that is not `ok` withdrawn.
///
/// The one rounding of frames: [`format_frame`] writes exactly this frame, and a
/// [`crate::HandStream`] delivers its frames through it, so whatever consumes a stream (the
/// window's hand loop, `nendo record`) sees the numbers a recording of it stores, bit for bit.
/// It is idempotent.
pub fn quantize_frame(frame: &HandFrame, joints: &[Joint]) -> HandFrame {
    let mut f = withdraw_stale(frame);
    if let Some(p) = &mut f.pose {
        p.position = DVec3::from_array(p.position.to_array().map(quantize));
        p.orientation = DQuat::from_array(p.orientation.to_array().map(quantize));
    }
    if let Some(a) = f.joints {
        let mut q = JointAngles::new();
        for &j in joints {
            if let Some(v) = a.get(j) {
                // Rounding never leaves the allowed range by more than the rounding itself; a
                // value that did is dropped, as the reader would refuse it.
                let _ = q.set(j, quantize(v));
            }
        }
        f.joints = Some(q);
    }
    if let Some(s) = &f.skeleton {
        f.skeleton = Some(skeleton::quantize_skeleton(s));
    }
    f
}

fn state_token(state: SourceState, fresh: bool, out: &mut String) {
    out.push_str(state.token());
    if fresh {
        out.push('*');
    }
}

fn number(x: f64, out: &mut String) {
    // Negative zero prints as "-0.000000", which reads back as -0.0: bit-exact either way.
    let _ = write!(out, " {x:.DECIMALS$}");
}

/// The frame with the values of every source that is not [`SourceState::Ok`] removed: the
/// stream never delivers them (see [`HandFrame`]), and a trace never carries them.
pub fn withdraw_stale(frame: &HandFrame) -> HandFrame {
    let mut f = *frame;
    if f.status.tracker != SourceState::Ok {
        f.pose = None;
        f.skeleton = None;
    }
    if f.status.glove != SourceState::Ok {
        f.joints = None;
    }
    f
}

/// Appends one frame line (with its newline): the frame as [`quantize_frame`] makes it, so
/// the line reads back as exactly that frame. Values of a source that is not `ok` are not
/// written (`P -`, `J -`; see [`withdraw_stale`]).
pub fn format_frame(joints: &[Joint], f: &HandFrame, out: &mut String) {
    format_frame_of(joints, false, f, out);
}

/// [`format_frame`] for a trace with or without skeleton frames (`skeleton`: the header has a
/// `skeleton` line, and the frame gets its `S` section).
pub fn format_frame_of(joints: &[Joint], skeleton: bool, f: &HandFrame, out: &mut String) {
    format_marked_frame(joints, skeleton, f, &HeldMarks::default(), out);
}

/// [`format_frame_of`] with the gate's marks: a `held=` field when `held` marks a channel the
/// written frame carries (see [`HeldMarks`]; the marks on channels it does not carry — a
/// joint outside the columns, a value the frame does not have — are not written, so the line
/// always reads back). For a trace whose header has `marks held`.
pub fn format_marked_frame(
    joints: &[Joint],
    skeleton: bool,
    f: &HandFrame,
    held: &HeldMarks,
    out: &mut String,
) {
    let f = &quantize_frame(f, joints);
    let _ = write!(out, "{} ", f.time.as_micros());
    state_token(f.status.tracker, f.status.tracker_fresh, out);
    out.push(' ');
    state_token(f.status.glove, f.status.glove_fresh, out);
    let _ = write!(out, " {} P", f.buttons);
    match &f.pose {
        Some(p) => {
            for x in p.position.to_array() {
                number(x, out);
            }
            let q = p.orientation;
            for x in [q.w, q.x, q.y, q.z] {
                number(x, out);
            }
        }
        None => out.push_str(" -"),
    }
    out.push_str(" J");
    match &f.joints {
        Some(a) => {
            for &j in joints {
                match a.get(j) {
                    Some(v) => number(v, out),
                    None => out.push_str(" ?"),
                }
            }
        }
        None => out.push_str(" -"),
    }
    if skeleton {
        skeleton::format_skeleton(f.skeleton.as_ref(), out);
    }
    let held = held.carried_by(f, joints, skeleton);
    if !held.is_empty() {
        let _ = write!(out, " {HELD_FIELD}={}", held.to_value(joints));
    }
    out.push('\n');
}

/// The header lines, up to and including `frames`.
pub fn format_header(h: &TraceHeader) -> String {
    let version = if h.marks_held {
        MARKED_TRACE_VERSION
    } else if h.skeleton.is_some() {
        SKELETON_TRACE_VERSION
    } else {
        GLOVE_TRACE_VERSION
    };
    let mut s = format!("{TRACE_FORMAT} {version}\n");
    if let Some(p) = &h.profile {
        let _ = writeln!(s, "profile {}", p.replace(['\n', '\r'], " "));
    }
    let _ = writeln!(
        s,
        "world_from_tracker {}",
        serde_json::to_string(&h.world_from_tracker).unwrap_or_default()
    );
    let _ = writeln!(
        s,
        "hand {}",
        serde_json::to_string(&h.hand).unwrap_or_default()
    );
    s.push_str("joints");
    for j in &h.joints {
        s.push(' ');
        s.push_str(j.name());
    }
    if let Some(side) = h.skeleton {
        let _ = write!(s, "\nskeleton {}", skeleton::side_token(side));
    }
    if h.marks_held {
        let _ = write!(s, "\nmarks {HELD_FIELD}");
    }
    match &h.scene {
        Some(scene) => {
            let _ = write!(s, "\nscene {scene}");
        }
        None => s.push_str("\nscene none"),
    }
    s.push_str("\nframes\n");
    s
}

impl Trace {
    /// The trace as text.
    pub fn to_text(&self) -> String {
        let header = self.written_header();
        let mut s = format_header(&header);
        let mut held = self.held.iter().peekable();
        for (k, f) in self.frames.iter().enumerate() {
            format_marked_frame(
                &header.joints,
                header.skeleton.is_some(),
                f,
                &marks_at(&mut held, k),
                &mut s,
            );
        }
        let _ = writeln!(s, "end {}", self.frames.len());
        s
    }

    /// The header as written: with `marks held` when the trace has marks.
    fn written_header(&self) -> TraceHeader {
        let mut header = self.header.clone();
        header.marks_held |= !self.held.is_empty();
        header
    }

    /// Parses a whole trace; errors name the 1-based line. A trace without its `end` line is
    /// refused (see [`Trace::parse_recovering`] for reading an interrupted recording); an error
    /// on a last line that has no final newline says the trace is truncated: that is what a
    /// file cut mid-write (or mid-copy) looks like.
    pub fn parse(text: &str) -> Result<Trace, DeviceError> {
        Trace::parse_lines(text, false).map(|r| r.trace)
    }

    /// Parses a trace, recovering an interrupted recording: a trace whose `end` line is
    /// missing reads up to its last frame line that reads, and says so
    /// ([`Recovered::interrupted`]). The lines from the first one that does not read on (a
    /// line cut short by a kill or a full disk, blocks a power cut left unwritten) are
    /// dropped — but only when no `end` line follows: a finished trace with a bad line is an
    /// error, as for [`Trace::parse`]. A header that does not read is an error either way.
    pub fn parse_recovering(text: &str) -> Result<Recovered, DeviceError> {
        Trace::parse_lines(text, true)
    }

    fn parse_lines(text: &str, recover: bool) -> Result<Recovered, DeviceError> {
        let truncated = |e| match e {
            DeviceError::TraceSyntax { line, message }
                if !text.is_empty() && !text.ends_with('\n') && line == text.lines().count() =>
            {
                DeviceError::TraceSyntax {
                    line,
                    message: format!(
                        "the trace is truncated: its last line is cut short ({message})"
                    ),
                }
            }
            other => other,
        };
        Trace::parse_text(text, recover).map_err(truncated)
    }

    fn parse_text(text: &str, recover: bool) -> Result<Recovered, DeviceError> {
        let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
        let err = |line: usize, message: String| DeviceError::TraceSyntax { line, message };
        let first = lines.next().map(|(_, l)| l).unwrap_or("");
        let version = parse_version_line(first)?;
        let mut header = TraceHeader::default();
        let mut in_frames = false;
        for (n, line) in lines.by_ref() {
            if parse_header_line(&mut header, version, n, line)? {
                in_frames = true;
                break;
            }
        }
        if !in_frames {
            return Err(err(
                text.lines().count().max(1),
                "the header never ends (no `frames` line)".into(),
            ));
        }
        let mut frames = Vec::new();
        let mut held = Vec::new();
        let mut last = 0u64;
        let last_line = text.lines().count();
        while let Some((n, line)) = lines.next() {
            if let Some(count) = line.strip_prefix("end ") {
                let count: usize = count
                    .trim()
                    .parse()
                    .map_err(|_| err(n, format!("malformed end line `{line}`")))?;
                if count != frames.len() {
                    return Err(err(
                        n,
                        format!("end says {count} frames, the trace has {}", frames.len()),
                    ));
                }
                if let Some((m, extra)) = lines.find(|(_, l)| !l.trim().is_empty()) {
                    return Err(err(m, format!("text after the end line: `{extra}`")));
                }
                return Ok(Recovered {
                    trace: Trace {
                        header,
                        frames,
                        held,
                    },
                    interrupted: None,
                });
            }
            // The last line of an unfinished file without its newline was cut mid-write: it
            // is dropped even if what is left of it reads (a frame cut after `J` reads as one
            // without joints), since the writer ends every frame line with its newline.
            if recover && n == last_line && !text.ends_with('\n') {
                let tail = DroppedTail {
                    line: n,
                    lines: 1,
                    cut_short: true,
                    reason: "no newline".into(),
                };
                let trace = Trace {
                    header,
                    frames,
                    held,
                };
                return Ok(Recovered::interrupted(trace, Some(tail)));
            }
            let frame =
                parse_marked_frame(&header.joints, header.skeleton, header.marks_held, line)
                    .map_err(|e| e.to_string())
                    .and_then(|(f, marks)| {
                        if f.time.as_micros() < last {
                            Err("time goes backwards".to_owned())
                        } else {
                            Ok((f, marks))
                        }
                    });
            match frame {
                Ok((f, marks)) => {
                    last = f.time.as_micros();
                    if !marks.is_empty() {
                        held.push((frames.len(), marks));
                    }
                    frames.push(f);
                }
                // The damaged end of an interrupted recording: nothing after it says the
                // trace was finished.
                Err(reason) if recover && !lines.clone().any(|(_, l)| l.starts_with("end ")) => {
                    let after = lines.count();
                    let tail = DroppedTail {
                        line: n,
                        lines: after + 1,
                        cut_short: after == 0 && !text.ends_with('\n'),
                        reason,
                    };
                    let trace = Trace {
                        header,
                        frames,
                        held,
                    };
                    return Ok(Recovered::interrupted(trace, Some(tail)));
                }
                Err(reason) => return Err(err(n, reason)),
            }
        }
        if recover {
            let trace = Trace {
                header,
                frames,
                held,
            };
            return Ok(Recovered::interrupted(trace, None));
        }
        Err(err(
            text.lines().count() + 1,
            "the trace is truncated (no `end` line): an interrupted recording? `nendo replay` recovers its complete frames".into(),
        ))
    }

    /// Reads a whole trace file (see [`Trace::parse`]).
    pub fn read(path: &Path) -> Result<Trace, DeviceError> {
        let text = std::fs::read_to_string(path).map_err(|error| DeviceError::File {
            path: path.to_path_buf(),
            error,
        })?;
        Trace::parse(&text)
    }

    /// Writes the trace atomically (temporary file, then rename).
    pub fn write(&self, path: &Path) -> Result<(), DeviceError> {
        let mut w = TraceWriter::create(path, self.written_header())?;
        let mut held = self.held.iter().peekable();
        for (k, f) in self.frames.iter().enumerate() {
            w.push_marked(f, &marks_at(&mut held, k))?;
        }
        w.finish().map(|_| ())
    }
}

/// The marks of frame `k` from a list by frame index (increasing; an entry out of order is
/// passed over).
fn marks_at<'a>(
    held: &mut std::iter::Peekable<impl Iterator<Item = &'a (usize, HeldMarks)>>,
    k: usize,
) -> HeldMarks {
    while held.next_if(|(i, _)| *i < k).is_some() {}
    held.next_if(|(i, _)| *i == k)
        .map_or_else(HeldMarks::default, |(_, m)| *m)
}

/// Why one frame line of a trace does not read. [`Trace::parse`] wraps it in
/// [`DeviceError::TraceSyntax`] with the line number; the messages are the ones users see.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FrameError {
    /// The line is empty.
    #[error("empty line")]
    Empty,
    /// The line stops before all its fields.
    #[error("the line ends early")]
    EndsEarly,
    /// The time field is not a whole number of microseconds.
    #[error("the time is not a whole number of microseconds")]
    BadTime,
    /// A source state is not one of `none`, `ok`, `silent`, `lost` (with an optional `*`).
    #[error("unknown source state `{0}`")]
    UnknownState(String),
    /// The button mask is not a decimal number.
    #[error("malformed buttons")]
    BadButtons,
    /// A number is not written with exactly [`DECIMALS`] decimals.
    #[error("`{0}` is not a number with {DECIMALS} decimals")]
    NotSixDecimals(String),
    /// A number has the right shape but does not parse.
    #[error("`{0}` is not a number")]
    NotANumber(String),
    /// The `P` marker is missing.
    #[error("expected `P` before the pose")]
    MissingPoseMarker,
    /// The `J` marker is missing.
    #[error("expected `J` before the joint angles")]
    MissingJointMarker,
    /// The frame has a pose although its tracker is not `ok`.
    #[error(
        "the tracker is `{}` but the frame has a pose: only an `ok` source carries values",
        .0.token()
    )]
    PoseWithoutTracker(SourceState),
    /// The frame has joint angles although its glove is not `ok`.
    #[error(
        "the glove is `{}` but the frame has joint angles: only an `ok` source carries values",
        .0.token()
    )]
    AnglesWithoutGlove(SourceState),
    /// The number of joint columns differs from the header's joints.
    #[error("{found} joint columns, the header names {expected}")]
    JointCount {
        /// Columns in the frame.
        found: usize,
        /// Joints named by the header.
        expected: usize,
    },
    /// The pose does not validate (not finite, out of range, not a unit quaternion); the
    /// message is the validation's.
    #[error("{0}")]
    BadPose(String),
    /// A joint angle does not validate; the message is the validation's.
    #[error("{0}")]
    BadJoint(String),
    /// A word after the joint columns is not a per-frame field `name=value` (or a joint
    /// column follows a field).
    #[error("`{0}` is not a per-frame field `name=value`")]
    BadField(String),
    /// The `S` section of a skeleton trace's frame is missing.
    #[error("expected `S` before the skeleton (the header says the frames carry one)")]
    MissingSkeletonMarker,
    /// A joint of the `S` section does not read or validate.
    #[error("skeleton: {0}")]
    BadSkeleton(String),
    /// A per-frame field this version of the format does not know.
    #[error("unknown per-frame field `{0}` (a trace from a newer nendo?)")]
    UnknownField(String),
    /// A `held=` field in a trace whose header does not say `marks held`.
    #[error("a `held=` field, but the header does not say `marks held` (trace version 4)")]
    HeldUndeclared,
    /// A `held=` field that does not read (the message says why: see [`HeldMarks`]).
    #[error("held: {0}")]
    BadHeld(String),
}

fn parse_number(word: Option<&str>) -> Result<f64, FrameError> {
    let w = word.ok_or(FrameError::EndsEarly)?;
    let body = w.strip_prefix('-').unwrap_or(w);
    let ok = match body.split_once('.') {
        Some((int, frac)) => {
            !int.is_empty()
                && int.bytes().all(|b| b.is_ascii_digit())
                && frac.len() == DECIMALS
                && frac.bytes().all(|b| b.is_ascii_digit())
        }
        None => false,
    };
    if !ok {
        return Err(FrameError::NotSixDecimals(w.to_owned()));
    }
    w.parse().map_err(|_| FrameError::NotANumber(w.to_owned()))
}

fn parse_state(word: Option<&str>) -> Result<(SourceState, bool), FrameError> {
    let w = word.ok_or(FrameError::EndsEarly)?;
    let (token, fresh) = match w.strip_suffix('*') {
        Some(t) => (t, true),
        None => (w, false),
    };
    let state =
        SourceState::from_token(token).ok_or_else(|| FrameError::UnknownState(w.to_owned()))?;
    Ok((state, fresh))
}

/// Reads one per-frame field `name=value` (see the module docs: the format's extension
/// point), returning the value of a `held=` field (the one field version 4 defines; a trace
/// without `marks held` may not have it). Every other well-formed field is refused as
/// unknown rather than ignored — a frame whose meaning depends on a field must not be
/// replayed as if it had none. Error messages quote at most 40 characters of the word.
fn read_field(word: &str, marks_held: bool) -> Result<&str, FrameError> {
    let bad = || FrameError::BadField(held::clip(word));
    let (name, value) = word.split_once('=').ok_or_else(bad)?;
    let name_ok = name.starts_with(|c: char| c.is_ascii_lowercase())
        && name
            .bytes()
            .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'_');
    if !name_ok || value.is_empty() {
        return Err(bad());
    }
    match name {
        HELD_FIELD if marks_held => Ok(value),
        HELD_FIELD => Err(FrameError::HeldUndeclared),
        _ => Err(FrameError::UnknownField(held::clip(name))),
    }
}

/// Parses one frame line given the header's joint columns.
pub fn parse_frame(joints: &[Joint], line: &str) -> Result<HandFrame, FrameError> {
    parse_frame_of(joints, None, line)
}

/// Parses one frame line given the header's joint columns and skeleton hand (`Some`: the
/// frame has an `S` section), in a trace without marks (a `held=` field is refused).
pub fn parse_frame_of(
    joints: &[Joint],
    skeleton: Option<crate::profile::Side>,
    line: &str,
) -> Result<HandFrame, FrameError> {
    parse_marked_frame(joints, skeleton, false, line).map(|(f, _)| f)
}

/// Parses one frame line and its gate's marks ([`HeldMarks`], empty without a `held=`
/// field) given the header's joint columns, skeleton hand and whether it has `marks held`.
pub fn parse_marked_frame(
    joints: &[Joint],
    skeleton: Option<crate::profile::Side>,
    marks_held: bool,
    line: &str,
) -> Result<(HandFrame, HeldMarks), FrameError> {
    let mut w = line.split_whitespace();
    let time: u64 = w
        .next()
        .ok_or(FrameError::Empty)?
        .parse()
        .map_err(|_| FrameError::BadTime)?;
    let (tracker, tracker_fresh) = parse_state(w.next())?;
    let (glove, glove_fresh) = parse_state(w.next())?;
    let buttons: u32 = w
        .next()
        .ok_or(FrameError::EndsEarly)?
        .parse()
        .map_err(|_| FrameError::BadButtons)?;
    if w.next() != Some("P") {
        return Err(FrameError::MissingPoseMarker);
    }
    let mut peek = w.clone();
    let pose = if peek.next() == Some("-") {
        w.next();
        None
    } else if tracker != SourceState::Ok {
        return Err(FrameError::PoseWithoutTracker(tracker));
    } else {
        let mut v = [0.0; 7];
        for x in &mut v {
            *x = parse_number(w.next())?;
        }
        let position = DVec3::new(v[0], v[1], v[2]);
        let orientation = DQuat::from_xyzw(v[4], v[5], v[6], v[3]);
        // Validate, but keep the quaternion exactly as written so the trace round-trips.
        TrackerPose::new(position, orientation).map_err(|e| FrameError::BadPose(e.to_string()))?;
        Some(TrackerPose {
            position,
            orientation,
        })
    };
    if w.next() != Some("J") {
        return Err(FrameError::MissingJointMarker);
    }
    let words: Vec<&str> = w.collect();
    // Optional per-frame fields follow the joint columns: the first word holding `=` starts
    // them (no joint column, `-` or `?` holds one).
    let split = words
        .iter()
        .position(|w| w.contains('='))
        .unwrap_or(words.len());
    let (rest, fields) = words.split_at(split);
    let mut held_value = None;
    for field in fields {
        let value = read_field(field, marks_held)?;
        if held_value.replace(value).is_some() {
            return Err(FrameError::BadHeld(format!(
                "`{HELD_FIELD}=` given twice in one frame"
            )));
        }
    }
    let (rest, hand) = match skeleton {
        None => (rest, None),
        Some(side) => {
            let at = rest
                .iter()
                .position(|w| *w == "S")
                .ok_or(FrameError::MissingSkeletonMarker)?;
            let hand = skeleton::parse_skeleton(&rest[at + 1..], side)?;
            if hand.is_some() && tracker != SourceState::Ok {
                return Err(FrameError::PoseWithoutTracker(tracker));
            }
            (&rest[..at], hand)
        }
    };
    let angles = if rest == ["-"] {
        None
    } else if glove != SourceState::Ok {
        return Err(FrameError::AnglesWithoutGlove(glove));
    } else if rest.len() != joints.len() {
        return Err(FrameError::JointCount {
            found: rest.len(),
            expected: joints.len(),
        });
    } else {
        let mut a = JointAngles::new();
        for (&j, word) in joints.iter().zip(rest) {
            if *word != "?" {
                a.set(j, parse_number(Some(word))?)
                    .map_err(|e| FrameError::BadJoint(e.to_string()))?;
            }
        }
        Some(a)
    };
    let frame = HandFrame {
        time: Timestamp(time),
        pose,
        joints: angles,
        buttons,
        status: FrameStatus {
            tracker,
            glove,
            tracker_fresh,
            glove_fresh,
        },
        skeleton: hand,
    };
    let marks = match held_value {
        Some(v) => HeldMarks::parse(v, joints, skeleton, &frame)?,
        None => HeldMarks::default(),
    };
    Ok((frame, marks))
}

#[cfg(test)]
mod tests;
