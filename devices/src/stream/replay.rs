//! [`HandStream::replay`]: a trace played back as a stream — from memory, or from a file read
//! frame by frame ([`HandStream::replay_file`]), in memory flat in the trace's length.

use std::path::PathBuf;

use super::*;
use crate::trace::TraceStream;

/// The frames a replay plays.
enum Frames {
    /// A trace read whole.
    Memory(Vec<HandFrame>),
    /// A trace file read one frame at a time ([`TraceStream`]); `stream` is the pass under
    /// way (the file is opened again for each repeat).
    File {
        path: PathBuf,
        stream: Option<Box<TraceStream<std::io::BufReader<std::fs::File>>>>,
    },
}

/// Sends frames at their times (scaled by the speed) from the replay's start.
struct Player {
    worker: Arc<Shared>,
    speed: f64,
    t0: Instant,
}

impl Player {
    /// Waits for frame `f`'s time `t` (µs from the start) and sends it with that time; false
    /// when the stream was stopped meanwhile.
    fn play(&self, f: &HandFrame, t: u64) -> bool {
        // Never a panic, whatever the speed: a delay beyond a day waits a day.
        let delay = (t as f64 * 1e-6 / self.speed).clamp(0.0, 86_400.0);
        let due = self.t0 + Duration::from_secs_f64(delay);
        loop {
            if self.worker.stop.load(Ordering::Relaxed) {
                return false;
            }
            let now = Instant::now();
            if now >= due {
                break;
            }
            std::thread::sleep((due - now).min(POLL));
        }
        // The replay's states are the trace's, frame by frame.
        {
            let mut m = lock(&self.worker.merge);
            m.tracker = f.status.tracker;
            m.glove = f.status.glove;
        }
        if f.status.tracker_fresh {
            self.worker.role(DeviceRole::Tracker, |r| r.samples(1));
        }
        if f.status.glove_fresh {
            self.worker.role(DeviceRole::Glove, |r| r.samples(1));
        }
        // No port: the frame arrives as it is sent.
        self.worker.send(
            HandFrame {
                time: Timestamp(t),
                ..*f
            },
            Instant::now(),
        );
        true
    }

    /// Plays the trace in memory (repeated with timestamps continuing).
    fn memory(&self, frames: &[HandFrame], repeat: bool) {
        let Some(first) = frames.first().map(|f| f.time.as_micros()) else {
            return;
        };
        let span = frames.last().map_or(0, |f| f.time.as_micros() - first);
        let period = if frames.len() > 1 {
            span / (frames.len() as u64 - 1)
        } else {
            0
        };
        let mut offset = 0u64;
        loop {
            for f in frames {
                if !self.play(f, f.time.as_micros() - first + offset) {
                    return;
                }
            }
            if !repeat {
                return;
            }
            offset += span + period.max(1);
        }
    }

    /// Plays the trace file frame by frame, opening it again for each repeat. A bad line that
    /// is an error (an `end` line follows it) ends the replay with the error as the stream's
    /// last error, naming the file and line; an interrupted recording plays its complete
    /// frames and says what was dropped the same way.
    fn file(
        &self,
        path: &Path,
        mut stream: Option<Box<TraceStream<std::io::BufReader<std::fs::File>>>>,
        repeat: bool,
    ) {
        let note = |text: String| *lock(&self.worker.last_error) = Some(text);
        let mut offset = 0u64;
        loop {
            let mut s = match stream
                .take()
                .map_or_else(|| TraceStream::open(path).map(Box::new), Ok)
            {
                Ok(s) => s,
                Err(e) => return note(format!("{}: {e}", path.display())),
            };
            // First and last time and the count of this pass, for the next pass's offset.
            let (mut first, mut last, mut count) = (None, 0u64, 0u64);
            loop {
                match s.next_frame() {
                    Ok(Some(f)) => {
                        let time = f.time.as_micros();
                        let from = *first.get_or_insert(time);
                        last = time;
                        count += 1;
                        if !self.play(&f, time.saturating_sub(from) + offset) {
                            return;
                        }
                    }
                    Ok(None) => {
                        if let Some(i) = s.interrupted() {
                            note(format!("{}: {i}", path.display()));
                        }
                        break;
                    }
                    Err(e) => return note(format!("{}: {e}", path.display())),
                }
            }
            let Some(from) = first.filter(|_| repeat) else {
                return;
            };
            let span = last - from;
            let period = if count > 1 { span / (count - 1) } else { 0 };
            offset += span + period.max(1);
        }
    }
}

impl HandStream {
    /// Plays a trace back in real time (scaled by `speed`) as a stream: the recorded-trace mock
    /// backend. With `repeat`, it starts over at the end with timestamps continuing.
    pub fn replay(trace: Trace, speed: f64, repeat: bool, capacity: usize) -> HandStream {
        let header = trace.header;
        HandStream::play(
            header,
            Frames::Memory(trace.frames),
            speed,
            repeat,
            capacity,
        )
    }

    /// Plays the trace file `path` back as [`HandStream::replay`] does, reading it frame by
    /// frame ([`TraceStream`]): the memory of one frame line (at most 1 MB) whatever its
    /// length. Its header is read now; a frame line that is an error (over its limit or
    /// malformed, with an `end` line after it) ends the replay there, and the stream's
    /// [`HandStream::last_error`] says why, naming the file and line; an interrupted recording
    /// plays its complete frames and says the same way what was dropped.
    ///
    /// # Errors
    /// The file cannot be opened or its header does not read.
    pub fn replay_file(
        path: &Path,
        speed: f64,
        repeat: bool,
        capacity: usize,
    ) -> Result<HandStream, DeviceError> {
        let stream = TraceStream::open(path)?;
        let header = stream.header().clone();
        let frames = Frames::File {
            path: path.to_path_buf(),
            stream: Some(Box::new(stream)),
        };
        Ok(HandStream::play(header, frames, speed, repeat, capacity))
    }

    fn play(
        header: TraceHeader,
        frames: Frames,
        speed: f64,
        repeat: bool,
        capacity: usize,
    ) -> HandStream {
        let (tx, rx) = sync_channel(capacity.max(1));
        let shared = Arc::new(Shared::new(tx, Merge::default(), header.joints.clone()));
        for role in [DeviceRole::Glove, DeviceRole::Tracker] {
            shared.role(role, |r| {
                r.present = true;
                r.description = format!("{} of the replayed trace", role.name());
            });
        }
        let joints = header.joints.clone();
        let player = Player {
            worker: Arc::clone(&shared),
            speed: if speed.is_finite() && speed > 0.0 {
                speed
            } else {
                1.0
            },
            t0: Instant::now(),
        };
        let thread = std::thread::Builder::new()
            .name("nendo-replay".into())
            .spawn(move || {
                match frames {
                    Frames::Memory(frames) => player.memory(&frames, repeat),
                    Frames::File { path, stream } => player.file(&path, stream, repeat),
                }
                player.worker.finished.store(true, Ordering::Relaxed);
            });
        let threads = match thread {
            Ok(t) => vec![t],
            Err(e) => {
                // No thread, no frames: say so rather than pretend to play.
                shared.note_error(&DeviceError::Io {
                    device: "replay thread".into(),
                    error: e,
                });
                shared.finished.store(true, Ordering::Relaxed);
                Vec::new()
            }
        };
        HandStream {
            rx,
            shared,
            threads,
            joints,
            description: vec!["trace replay".into()],
            source_header: Some(header),
            warnings: Vec::new(),
        }
    }
}
