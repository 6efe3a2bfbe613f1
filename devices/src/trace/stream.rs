//! Reading a trace file frame by frame, in memory flat in its length: [`TraceStream`] holds the
//! header and one line at a time, so a day's recording (10 million frames at 120 Hz) is
//! replayed in the memory of one frame, and no line — however long, or never ending, as
//! `/dev/zero` given as a trace — is ever held beyond its limit:
//!
//! - the first line at most [`MAX_FIRST_LINE_BYTES`] (256 bytes: `nendo-hand-trace 3`);
//! - a header line at most [`MAX_HEADER_LINE_BYTES`] (640 MB: the `scene` line may embed a
//!   whole model, and model files are at most 512 MB);
//! - a frame line at most [`MAX_FRAME_LINE_BYTES`] (1 MB; a skeleton frame is about 4 kB).
//!
//! It reads as [`Trace::read_recovering`] does (which collects it): an interrupted
//! recording's complete frames, then [`TraceStream::interrupted`] says what was dropped; a bad
//! line with an `end` line after it is an error. Where the whole-text reader looks ahead (is
//! there an `end` line after a bad one?), the stream reads the rest of the file through once,
//! holding nothing of it. A frame line over its limit is a bad line like any other (`the line
//! is longer than 1 MB`); a header line over its limit is an error.

use std::fs::File;
use std::io::{self, BufRead, BufReader};
use std::path::{Path, PathBuf};

use super::{
    DroppedTail, HandFrame, HeldMarks, Interrupted, TraceHeader, parse_header_line,
    parse_marked_frame, parse_version_line,
};
use crate::DeviceError;

/// Longest first line read.
pub const MAX_FIRST_LINE_BYTES: usize = 256;
/// Longest header line read (a `scene` may hold a model of up to 512 MB).
pub const MAX_HEADER_LINE_BYTES: usize = 640 << 20;
/// Longest frame line read.
pub const MAX_FRAME_LINE_BYTES: usize = 1 << 20;

/// One line as read.
enum Raw {
    /// The input ended before another byte.
    End,
    /// A line within the limit, in the buffer; `newline`: it ended with one.
    Line { newline: bool },
    /// A line over the limit, skipped through to its newline (or the end).
    TooLong { newline: bool },
}

/// A trace read frame by frame (see the module docs).
pub struct TraceStream<R> {
    input: R,
    /// The file, to name in read errors.
    path: Option<PathBuf>,
    header: TraceHeader,
    /// The number of the last line read (1-based).
    line: usize,
    frames: usize,
    last_time: u64,
    /// The gate's marks on the last frame read.
    held: HeldMarks,
    buf: Vec<u8>,
    /// The last line read had no newline (it ended the file).
    cut: bool,
    /// `Some` once the frames are over: `None` inside for a finished trace.
    done: Option<Option<Interrupted>>,
}

impl std::fmt::Debug for TraceStream<BufReader<File>> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TraceStream")
            .field("line", &self.line)
            .field("frames", &self.frames)
            .finish_non_exhaustive()
    }
}

fn syntax(line: usize, message: String) -> DeviceError {
    DeviceError::TraceSyntax { line, message }
}

/// The message of an error on a last line without its newline: the file was cut mid-write.
fn cut_short(e: DeviceError) -> DeviceError {
    match e {
        DeviceError::TraceSyntax { line, message } => syntax(
            line,
            format!("the trace is truncated: its last line is cut short ({message})"),
        ),
        other => other,
    }
}

impl TraceStream<BufReader<File>> {
    /// Opens a trace file and reads its header.
    ///
    /// # Errors
    /// [`DeviceError::File`] when it cannot be read; [`DeviceError::TraceSyntax`] when its
    /// header does not read.
    pub fn open(path: &Path) -> Result<Self, DeviceError> {
        let file = File::open(path).map_err(|error| DeviceError::File {
            path: path.to_path_buf(),
            error,
        })?;
        TraceStream::start(BufReader::with_capacity(1 << 16, file), Some(path))
    }
}

impl<R: BufRead> TraceStream<R> {
    /// Reads the header from `input`; the frames follow with [`TraceStream::next_frame`].
    ///
    /// # Errors
    /// As [`TraceStream::open`] ([`DeviceError::Io`] for a read error).
    pub fn new(input: R) -> Result<Self, DeviceError> {
        TraceStream::start(input, None)
    }

    fn start(input: R, path: Option<&Path>) -> Result<Self, DeviceError> {
        let mut s = TraceStream {
            input,
            path: path.map(Path::to_path_buf),
            header: TraceHeader::default(),
            line: 0,
            frames: 0,
            last_time: 0,
            held: HeldMarks::default(),
            buf: Vec::new(),
            cut: false,
            done: None,
        };
        let (first, cut) = match s.read(MAX_FIRST_LINE_BYTES, false)? {
            Raw::Line { newline } => (std::str::from_utf8(&s.buf).unwrap_or(""), !newline),
            Raw::End | Raw::TooLong { .. } => ("", false),
        };
        let version = parse_version_line(first).map_err(|e| if cut { cut_short(e) } else { e })?;
        loop {
            match s.read(MAX_HEADER_LINE_BYTES, false)? {
                Raw::End => {
                    let e = syntax(
                        s.line.max(1),
                        "the header never ends (no `frames` line)".into(),
                    );
                    // The text reader calls a header cut mid-line truncated too.
                    return Err(if s.line > 0 && s.last_line_cut() {
                        cut_short(e)
                    } else {
                        e
                    });
                }
                Raw::TooLong { .. } => {
                    return Err(syntax(
                        s.line,
                        format!(
                            "a header line longer than {} MB",
                            MAX_HEADER_LINE_BYTES >> 20
                        ),
                    ));
                }
                Raw::Line { newline } => {
                    let n = s.line;
                    let text = std::str::from_utf8(&s.buf)
                        .map_err(|_| syntax(n, "not UTF-8 text".into()))?;
                    match parse_header_line(&mut s.header, version, n, text) {
                        Ok(true) => break,
                        Ok(false) => {}
                        Err(e) if !newline => return Err(cut_short(e)),
                        Err(e) => return Err(e),
                    }
                }
            }
        }
        Ok(s)
    }

    /// Whether the file's last line had no newline (known once the end is read).
    fn last_line_cut(&self) -> bool {
        self.cut
    }

    /// The header.
    pub fn header(&self) -> &TraceHeader {
        &self.header
    }

    /// Lines read so far (after [`TraceStream::open`]: the header's).
    pub fn lines_read(&self) -> usize {
        self.line
    }

    /// Frames read so far.
    pub fn frames_read(&self) -> usize {
        self.frames
    }

    /// Once [`TraceStream::next_frame`] has returned `None`: what an interrupted recording
    /// dropped (`None` for a finished trace, with its `end` line).
    pub fn interrupted(&self) -> Option<&Interrupted> {
        self.done.as_ref().and_then(Option::as_ref)
    }

    /// The gate's marks on the frame [`TraceStream::next_frame`] returned last (its `held=`
    /// field; empty without one, and always in a trace without `marks held`).
    pub fn held(&self) -> HeldMarks {
        self.held
    }

    /// The next frame, or `None` after the last (then see [`TraceStream::interrupted`]).
    ///
    /// # Errors
    /// [`DeviceError::TraceSyntax`] for a bad line of a finished trace (an `end` line follows
    /// it), a wrong `end` count, or text after the `end` line; [`DeviceError::File`] (or
    /// [`DeviceError::Io`] for a stream not opened from a file) for a read error.
    pub fn next_frame(&mut self) -> Result<Option<HandFrame>, DeviceError> {
        self.held = HeldMarks::default();
        if self.done.is_some() {
            return Ok(None);
        }
        let n = self.line + 1;
        let newline = match self.read(MAX_FRAME_LINE_BYTES, true)? {
            Raw::End => return Ok(self.finish(None)),
            Raw::TooLong { newline } => {
                let reason = format!("the line is longer than {} MB", MAX_FRAME_LINE_BYTES >> 20);
                return self.bad_line(n, newline, reason);
            }
            Raw::Line { newline } => newline,
        };
        let Ok(text) = std::str::from_utf8(&self.buf) else {
            return self.not_text(n);
        };
        if let Some(count) = text.strip_prefix("end ") {
            // An error on a last line without its newline: the file was cut there.
            let cut = |e| if newline { e } else { cut_short(e) };
            let count: usize = count
                .trim()
                .parse()
                .map_err(|_| cut(syntax(n, format!("malformed end line `{text}`"))))?;
            if count != self.frames {
                return Err(cut(syntax(
                    n,
                    format!("end says {count} frames, the trace has {}", self.frames),
                )));
            }
            self.after_end()?;
            self.done = Some(None);
            return Ok(None);
        }
        // A last line without its newline was cut mid-write: dropped even if what is left
        // of it reads (the writer ends every frame line with its newline).
        if !newline {
            let tail = DroppedTail {
                line: n,
                lines: 1,
                cut_short: true,
                reason: "no newline".into(),
            };
            return Ok(self.finish(Some(tail)));
        }
        let h = &self.header;
        let frame = parse_marked_frame(&h.joints, h.skeleton, h.marks_held, text)
            .map_err(|e| e.to_string())
            .and_then(|(f, marks)| {
                if f.time.as_micros() < self.last_time {
                    Err("time goes backwards".to_owned())
                } else {
                    Ok((f, marks))
                }
            });
        match frame {
            Ok((f, marks)) => {
                self.last_time = f.time.as_micros();
                self.frames += 1;
                self.held = marks;
                Ok(Some(f))
            }
            Err(reason) => self.bad_line(n, newline, reason),
        }
    }

    /// Ends the frames of an interrupted recording.
    fn finish(&mut self, dropped: Option<DroppedTail>) -> Option<HandFrame> {
        self.done = Some(Some(Interrupted {
            frames: self.frames,
            dropped,
        }));
        None
    }

    /// A frame line `n` that does not read: the damaged end of an interrupted recording when
    /// no `end` line follows it, else an error. Lines from the first one that is not UTF-8
    /// on are counted as the whole-text reader counts them (non-empty pieces) and an `end`
    /// among them does not count.
    fn bad_line(
        &mut self,
        n: usize,
        newline: bool,
        reason: String,
    ) -> Result<Option<HandFrame>, DeviceError> {
        let mut after = 0usize;
        let mut end_follows = false;
        let mut not_text = false;
        loop {
            match self.read(MAX_FRAME_LINE_BYTES, true)? {
                Raw::End => break,
                Raw::TooLong { .. } => after += 1,
                Raw::Line { .. } => match std::str::from_utf8(&self.buf) {
                    Ok(l) if !not_text => {
                        after += 1;
                        end_follows |= l.starts_with("end ");
                    }
                    _ => {
                        not_text = true;
                        after += usize::from(!self.buf.is_empty());
                    }
                },
            }
        }
        if end_follows {
            return Err(syntax(n, reason));
        }
        let tail = DroppedTail {
            line: n,
            lines: after + 1,
            cut_short: after == 0 && !newline && !not_text,
            reason,
        };
        Ok(self.finish(Some(tail)))
    }

    /// Frame line `n` is not UTF-8: it and every non-empty line after it are dropped.
    fn not_text(&mut self, n: usize) -> Result<Option<HandFrame>, DeviceError> {
        let mut lines = 1usize;
        loop {
            match self.read(MAX_FRAME_LINE_BYTES, true)? {
                Raw::End => break,
                Raw::TooLong { .. } => lines += 1,
                Raw::Line { .. } => lines += usize::from(!self.buf.is_empty()),
            }
        }
        let tail = DroppedTail {
            line: n,
            lines,
            cut_short: false,
            reason: "not UTF-8 text".into(),
        };
        Ok(self.finish(Some(tail)))
    }

    /// After the `end` line only blank lines may follow.
    fn after_end(&mut self) -> Result<(), DeviceError> {
        loop {
            let raw = self.read(MAX_FRAME_LINE_BYTES, true)?;
            let n = self.line;
            match raw {
                Raw::End => return Ok(()),
                Raw::TooLong { .. } => {
                    return Err(syntax(n, "text after the end line".into()));
                }
                Raw::Line { .. } => match std::str::from_utf8(&self.buf) {
                    Ok(l) if l.trim().is_empty() => {}
                    Ok(l) => {
                        let e = syntax(n, format!("text after the end line: `{l}`"));
                        return Err(if self.cut { cut_short(e) } else { e });
                    }
                    Err(_) => {
                        return Err(syntax(n, "text after the end line (and not UTF-8)".into()));
                    }
                },
            }
        }
    }

    /// Reads one line into the buffer (without its newline and a `\r` before it), holding
    /// at most `limit` bytes: a longer line is read `through` to its newline without being
    /// kept (frame lines), or not read on (header lines, whose excess ends the reading: an
    /// endless first line is refused at once).
    fn read(&mut self, limit: usize, through: bool) -> Result<Raw, DeviceError> {
        self.buf.clear();
        let mut any = false;
        let mut over = false;
        let mut newline = false;
        loop {
            let available = match self.input.fill_buf() {
                Ok(b) => b,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(error) => {
                    return Err(match &self.path {
                        Some(path) => DeviceError::File {
                            path: path.clone(),
                            error,
                        },
                        None => DeviceError::Io {
                            device: "the trace".into(),
                            error,
                        },
                    });
                }
            };
            if available.is_empty() {
                break;
            }
            any = true;
            let at = available.iter().position(|&b| b == b'\n');
            let part = &available[..at.unwrap_or(available.len())];
            if !over && self.buf.len() + part.len() > limit {
                over = true;
                self.buf = Vec::new();
                if !through {
                    self.line += 1;
                    self.cut = false;
                    return Ok(Raw::TooLong { newline: false });
                }
            } else if !over {
                self.buf.extend_from_slice(part);
            }
            let used = part.len() + usize::from(at.is_some());
            self.input.consume(used);
            if at.is_some() {
                newline = true;
                break;
            }
        }
        if !any {
            return Ok(Raw::End);
        }
        self.line += 1;
        self.cut = !newline;
        if over {
            return Ok(Raw::TooLong { newline });
        }
        if self.buf.last() == Some(&b'\r') {
            self.buf.pop();
        }
        Ok(Raw::Line { newline })
    }
}

#[cfg(test)]
mod tests {
    use super::super::Trace;
    use super::*;

    /// What the stream reads from `bytes`, as [`Trace::parse_recovering`] reports it.
    fn streamed(bytes: &[u8]) -> Result<super::super::Recovered, String> {
        let mut s = TraceStream::new(bytes).map_err(|e| e.to_string())?;
        let (mut frames, mut held) = (Vec::new(), Vec::new());
        while let Some(f) = s.next_frame().map_err(|e| e.to_string())? {
            if !s.held().is_empty() {
                held.push((frames.len(), s.held()));
            }
            frames.push(f);
        }
        Ok(super::super::Recovered {
            interrupted: s.interrupted().cloned(),
            trace: Trace {
                header: s.header().clone(),
                frames,
                held,
            },
        })
    }

    #[test]
    fn the_stream_reads_every_damaged_trace_as_the_whole_text_reader_does() {
        let text = include_str!("../../traces/mouse-sphere.trace");
        let lines: Vec<&str> = text.lines().collect();
        let frames_at = lines.iter().position(|l| *l == "frames").expect("header") + 1;
        let mut variants: Vec<String> = Vec::new();
        // Cut anywhere in the header, early frames and the end.
        for at in (0..text.len().min(4000))
            .step_by(53)
            .chain((text.len().saturating_sub(3000)..text.len()).step_by(41))
        {
            if text.is_char_boundary(at) {
                variants.push(text[..at].to_owned());
            }
        }
        let body = |from: usize, to: usize| lines[from..to].join("\n");
        let n = lines.len();
        let unfinished = body(0, n - 1);
        variants.push(format!("{unfinished}\n"));
        variants.push(format!(
            "{}\ngarbage\n{}\n",
            body(0, frames_at + 20),
            body(frames_at + 20, n - 1)
        ));
        variants.push(format!(
            "{}\ngarbage\n{}\n",
            body(0, frames_at + 20),
            body(frames_at + 20, n)
        ));
        variants.push(format!("{}\n\n", body(0, frames_at + 5)));
        variants.push(format!("{text}\n\n  \n"));
        variants.push(format!("{text}after"));
        variants.push(format!("{text}after\n"));
        variants.push(format!("{}\nend 3\n", body(0, frames_at + 5)));
        variants.push(format!("{}\nend 5", body(0, frames_at + 5)));
        variants.push(format!("{}\nend x\n", body(0, frames_at + 5)));
        variants.push(format!(
            "{}\r\n{}\n",
            body(0, frames_at + 2),
            body(frames_at + 2, n)
        ));
        variants.push(String::new());
        variants.push("nendo-hand-trace 2\nprofile x".into());
        variants.push("nendo-hand-trace 9\n".into());
        for v in &variants {
            let whole = Trace::parse_recovering(v).map_err(|e| e.to_string());
            assert_eq!(
                streamed(v.as_bytes()),
                whole,
                "{:?}",
                &v[v.len().saturating_sub(80)..]
            );
        }
    }

    #[test]
    fn a_frame_line_over_its_limit_is_a_bad_line_and_is_never_held() {
        let text = include_str!("../../traces/mouse-sphere.trace");
        let unfinished: Vec<&str> = text.lines().filter(|l| !l.starts_with("end ")).collect();
        let frames = unfinished.len()
            - unfinished
                .iter()
                .position(|l| *l == "frames")
                .expect("header")
            - 1;
        let long = "7".repeat(MAX_FRAME_LINE_BYTES + 10);
        let bytes = format!("{}\n{long}\n", unfinished.join("\n"));
        let r = streamed(bytes.as_bytes()).expect("recovered");
        assert_eq!(r.trace.frames.len(), frames);
        let i = r.interrupted.expect("interrupted");
        let tail = i.dropped.expect("dropped");
        assert_eq!(tail.reason, "the line is longer than 1 MB");
        let with_end = format!("{bytes}end {frames}\n");
        let e = streamed(with_end.as_bytes()).expect_err("a finished trace");
        assert!(e.contains("longer than 1 MB"), "{e}");
        // Endless: /dev/zero's first line is refused at 256 bytes.
        let zeros = vec![0u8; 1 << 16];
        let e = streamed(&zeros).expect_err("not a trace");
        assert!(e.contains("not a nendo hand trace"), "{e}");
    }
}
