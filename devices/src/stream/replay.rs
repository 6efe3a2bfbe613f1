//! [`HandStream::replay`]: a trace played back as a stream.

use super::*;

impl HandStream {
    /// Plays a trace back in real time (scaled by `speed`) as a stream: the recorded-trace mock
    /// backend. With `repeat`, it starts over at the end with timestamps continuing.
    pub fn replay(trace: Trace, speed: f64, repeat: bool, capacity: usize) -> HandStream {
        let (tx, rx) = sync_channel(capacity.max(1));
        let shared = Arc::new(Shared::new(
            tx,
            Merge::default(),
            trace.header.joints.clone(),
        ));
        for role in [DeviceRole::Glove, DeviceRole::Tracker] {
            shared.role(role, |r| {
                r.present = true;
                r.description = format!("{} of the replayed trace", role.name());
            });
        }
        let joints = trace.header.joints.clone();
        let source_header = trace.header.clone();
        let worker = Arc::clone(&shared);
        let speed = if speed.is_finite() && speed > 0.0 {
            speed
        } else {
            1.0
        };
        let thread = std::thread::Builder::new()
            .name("nendo-replay".into())
            .spawn(move || {
                let frames = trace.frames;
                let Some(first) = frames.first().map(|f| f.time.as_micros()) else {
                    worker.finished.store(true, Ordering::Relaxed);
                    return;
                };
                let span = frames.last().map_or(0, |f| f.time.as_micros() - first);
                let period = if frames.len() > 1 {
                    span / (frames.len() as u64 - 1)
                } else {
                    0
                };
                let mut offset = 0u64;
                let t0 = Instant::now();
                loop {
                    for f in &frames {
                        let t = f.time.as_micros() - first + offset;
                        // Never a panic, whatever the speed: a delay beyond a day waits a day.
                        let delay = (t as f64 * 1e-6 / speed).clamp(0.0, 86_400.0);
                        let due = t0 + Duration::from_secs_f64(delay);
                        loop {
                            if worker.stop.load(Ordering::Relaxed) {
                                return;
                            }
                            let now = Instant::now();
                            if now >= due {
                                break;
                            }
                            std::thread::sleep((due - now).min(POLL));
                        }
                        // The replay's states are the trace's, frame by frame.
                        {
                            let mut m = lock(&worker.merge);
                            m.tracker = f.status.tracker;
                            m.glove = f.status.glove;
                        }
                        if f.status.tracker_fresh {
                            worker.role(DeviceRole::Tracker, |r| r.samples(1));
                        }
                        if f.status.glove_fresh {
                            worker.role(DeviceRole::Glove, |r| r.samples(1));
                        }
                        // No port: the frame arrives as it is sent.
                        worker.send(
                            HandFrame {
                                time: Timestamp(t),
                                ..*f
                            },
                            Instant::now(),
                        );
                    }
                    if !repeat {
                        break;
                    }
                    offset += span + period.max(1);
                }
                worker.finished.store(true, Ordering::Relaxed);
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
            source_header: Some(source_header),
            warnings: Vec::new(),
        }
    }
}
