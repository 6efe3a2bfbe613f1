//! The hand stream over emulated devices: merged frames, the watchdog, unplug and reconnect,
//! overflow of a slow consumer, corrupt bytes on a live line, and trace replay.
#![cfg(unix)]

use std::time::{Duration, Instant};

use nendo_devices::cyberglove::SensorCount;
use nendo_devices::emulator::{CyberGloveModel, FastrakModel, PtyEmulator};
use nendo_devices::profile::{self, Profile};
use nendo_devices::{
    DeviceError, HandFrame, HandStream, SourceState, StreamOptions, Trace, TraceHeader,
};

fn glove_and_tracker() -> (PtyEmulator, PtyEmulator, Profile, StreamOptions) {
    let glove = PtyEmulator::spawn(CyberGloveModel::new(SensorCount::Eighteen)).unwrap();
    let tracker = PtyEmulator::spawn(FastrakModel::new()).unwrap();
    let profile = profile::resolve("cyberglove2-18-fastrak").unwrap();
    let options = StreamOptions {
        glove_port: Some(glove.port()),
        tracker_port: Some(tracker.port()),
        watchdog: Some(Duration::from_millis(150)),
        retry: Duration::from_millis(50),
        ..StreamOptions::default()
    };
    (glove, tracker, profile, options)
}

/// Collects frames until `done` says so or `limit` passes; returns them.
fn collect_until(
    stream: &HandStream,
    limit: Duration,
    mut done: impl FnMut(&HandFrame) -> bool,
) -> Vec<HandFrame> {
    let end = Instant::now() + limit;
    let mut frames = Vec::new();
    while Instant::now() < end {
        if let Some(f) = stream.next_timeout(Duration::from_millis(20)) {
            let stop = done(&f);
            frames.push(f);
            if stop {
                break;
            }
        }
    }
    frames
}

#[test]
fn frames_merge_glove_and_tracker_with_increasing_timestamps() {
    let (_g, _t, profile, options) = glove_and_tracker();
    let stream = HandStream::open(&profile, &options).unwrap();
    assert_eq!(stream.joints().len(), 18);
    let frames = collect_until(&stream, Duration::from_millis(400), |_| false);
    assert!(frames.len() > 40, "{} frames in 0.4 s", frames.len());
    assert!(frames.windows(2).all(|w| w[0].time <= w[1].time));
    assert!(
        frames.iter().any(|f| f.status.glove_fresh)
            && frames.iter().any(|f| f.status.tracker_fresh)
    );
    let late = &frames[frames.len() / 2..];
    assert!(
        late.iter()
            .all(|f| f.pose.is_some() && f.joints.is_some() && f.is_complete())
    );
    let stats = stream.close();
    assert_eq!(stats.overflow, 0);
    assert!(stats.glove.decode.records > 20 && stats.tracker.decode.records > 20);
}

/// Every frame from real ports carries its arrival: the port read that completed it came
/// after the stream opened and before it was sent; the channel's order is the order of
/// sending; and the device samples were stamped by the backend at the read (distinct reads
/// of a 120 Hz tracker and a 100 Hz glove: the read instants spread over the run, not one
/// per batch).
#[test]
fn frames_carry_monotone_arrivals_from_the_port_reads() {
    let (_g, _t, profile, options) = glove_and_tracker();
    let opened = Instant::now();
    let stream = HandStream::open(&profile, &options).unwrap();
    let end = Instant::now() + Duration::from_millis(400);
    let mut stamped = Vec::new();
    while Instant::now() < end {
        stamped.extend(stream.next_stamped_timeout(Duration::from_millis(20)));
        stamped.extend(stream.drain_stamped());
    }
    let taken = Instant::now();
    assert!(stamped.len() > 40, "{} frames in 0.4 s", stamped.len());
    for s in &stamped {
        assert!(opened <= s.arrival.read, "read before the stream opened");
        assert!(s.arrival.read <= s.arrival.sent && s.arrival.sent <= taken);
        assert_eq!(s.arrival.parse(), s.arrival.sent - s.arrival.read);
    }
    assert!(
        stamped
            .windows(2)
            .all(|w| w[0].arrival.sent <= w[1].arrival.sent && w[0].frame.time <= w[1].frame.time)
    );
    let mut reads: Vec<Instant> = stamped.iter().map(|s| s.arrival.read).collect();
    reads.dedup();
    assert!(reads.len() > 20, "{} distinct read instants", reads.len());
}

#[test]
fn a_silent_device_trips_the_watchdog_and_resumes_when_it_speaks_again() {
    let (glove, _t, profile, options) = glove_and_tracker();
    let stream = HandStream::open(&profile, &options).unwrap();
    collect_until(&stream, Duration::from_secs(2), |f| f.status.glove_fresh);
    glove.set_silent(true);
    let frames = collect_until(&stream, Duration::from_secs(2), |f| {
        f.status.glove == SourceState::Silent
    });
    let silent = frames.last().unwrap();
    assert_eq!(silent.status.glove, SourceState::Silent);
    assert!(
        silent.joints.is_none(),
        "a silent glove's last angles are withdrawn"
    );
    // The tracker keeps delivering while the glove is silent.
    let frames = collect_until(&stream, Duration::from_millis(200), |_| false);
    assert!(
        frames
            .iter()
            .any(|f| f.status.tracker_fresh && f.pose.is_some() && f.joints.is_none())
    );
    glove.set_silent(false);
    let frames = collect_until(&stream, Duration::from_secs(3), |f| f.status.glove_fresh);
    assert!(frames.last().unwrap().joints.is_some(), "the glove resumed");
    let stats = stream.close();
    assert!(stats.watchdog_trips >= 1);
    assert!(stats.glove.starts >= 2, "the handshake was sent again");
    // The handshake went out at least twice: at open and after the watchdog.
    let sent = glove.received();
    assert!(
        sent.windows(2).filter(|w| w == b"GS").count() >= 2,
        "{sent:?}"
    );
}

#[test]
fn unplugging_reports_lost_and_replugging_resumes() {
    let (_g, tracker, profile, options) = glove_and_tracker();
    let stream = HandStream::open(&profile, &options).unwrap();
    collect_until(&stream, Duration::from_secs(2), |f| f.status.tracker_fresh);
    tracker.unplug();
    let frames = collect_until(&stream, Duration::from_secs(2), |f| {
        f.status.tracker == SourceState::Disconnected
    });
    let lost = frames.last().unwrap();
    assert_eq!(lost.status.tracker, SourceState::Disconnected);
    assert!(lost.pose.is_none());
    assert!(stream.last_error().is_some());
    std::thread::sleep(Duration::from_millis(120));
    tracker.replug();
    let frames = collect_until(&stream, Duration::from_secs(3), |f| f.status.tracker_fresh);
    let back = frames.last().unwrap();
    assert_eq!(back.status.tracker, SourceState::Ok);
    assert!(back.pose.is_some());
    assert!(tracker.ptys_opened() >= 2);
    let stats = stream.close();
    assert!(stats.disconnects >= 1);
    assert!(stats.tracker.starts >= 2);
}

#[test]
fn a_glove_pulled_out_of_its_interface_unit_is_lost_until_plugged_back_in() {
    let model = CyberGloveModel::new(SensorCount::Eighteen);
    let plug = model.glove_plug();
    let glove = PtyEmulator::spawn(model).unwrap();
    let tracker = PtyEmulator::spawn(FastrakModel::new()).unwrap();
    let profile = profile::resolve("cyberglove2-18-fastrak").unwrap();
    let options = StreamOptions {
        glove_port: Some(glove.port()),
        tracker_port: Some(tracker.port()),
        watchdog: Some(Duration::from_millis(150)),
        retry: Duration::from_millis(50),
        ..StreamOptions::default()
    };
    let stream = HandStream::open(&profile, &options).unwrap();
    collect_until(&stream, Duration::from_secs(2), |f| f.status.glove_fresh);
    plug.set_plugged(false);
    let frames = collect_until(&stream, Duration::from_secs(2), |f| {
        f.status.glove == SourceState::Disconnected
    });
    let lost = frames.last().unwrap();
    assert_eq!(lost.status.glove, SourceState::Disconnected, "not `silent`");
    assert!(lost.joints.is_none());
    assert!(
        stream.last_error().is_some_and(|e| e.contains("unplugged")),
        "{:?}",
        stream.last_error()
    );
    // While the glove is out, the stream keeps retrying and the glove stays lost (never
    // `silent`, never `ok`); the tracker keeps delivering.
    let frames = collect_until(&stream, Duration::from_millis(300), |_| false);
    assert!(
        frames
            .iter()
            .all(|f| f.status.glove == SourceState::Disconnected && f.joints.is_none())
    );
    assert!(frames.iter().any(|f| f.status.tracker_fresh));
    plug.set_plugged(true);
    let frames = collect_until(&stream, Duration::from_secs(3), |f| f.status.glove_fresh);
    let back = frames.last().unwrap();
    assert_eq!(back.status.glove, SourceState::Ok);
    assert!(back.joints.is_some(), "the glove resumed");
    let stats = stream.close();
    assert!(stats.disconnects >= 1, "{stats:?}");
    assert!(stats.glove.faults >= 1, "{stats:?}");
    assert!(stats.glove.starts >= 2, "{stats:?}");
}

#[test]
fn a_slow_consumer_loses_frames_but_never_blocks_the_devices() {
    let (_g, _t, profile, mut options) = glove_and_tracker();
    options.capacity = 4;
    let stream = HandStream::open(&profile, &options).unwrap();
    // Nobody drains: wait until frames are dropped (the deadline only guards against a hang).
    let end = Instant::now() + Duration::from_secs(60);
    while stream.stats().overflow <= 10 && Instant::now() < end {
        std::thread::sleep(Duration::from_millis(10));
    }
    let overflowed = stream.stats().overflow;
    assert!(overflowed > 10, "{overflowed} frames dropped");
    assert_eq!(stream.drain().len(), 4);
    // The device threads kept running: fresh frames keep coming.
    let frames = collect_until(&stream, Duration::from_millis(300), |_| false);
    assert!(frames.len() > 10);
}

#[test]
fn corrupt_records_on_a_live_line_are_dropped_and_counted() {
    let (glove, tracker, profile, options) = glove_and_tracker();
    let stream = HandStream::open(&profile, &options).unwrap();
    glove.corrupt_every(Some(3));
    tracker.corrupt_every(Some(3));
    glove.inject(&[0xFF; 40]);
    tracker.inject(b"0\x01garbage 0 1 1");
    let frames = collect_until(&stream, Duration::from_millis(600), |_| false);
    let stats = stream.close();
    assert!(frames.iter().filter(|f| f.status.glove_fresh).count() > 20);
    assert!(frames.iter().filter(|f| f.status.tracker_fresh).count() > 20);
    // Every delivered value passed validation (the quaternion unit to the six decimals a
    // stream rounds its frames to, as a trace stores them).
    for f in &frames {
        if let Some(p) = f.pose {
            assert!(p.position.is_finite() && (p.orientation.length() - 1.0).abs() < 2e-6);
        }
        if let Some(a) = f.joints {
            assert!(
                a.iter()
                    .all(|(_, v)| v.is_finite() && v.abs() <= nendo_devices::ANGLE_LIMIT_RAD)
            );
        }
    }
    let dropped =
        |s: nendo_devices::DeviceStats| s.decode.rejected + s.decode.skipped_bytes + s.invalid;
    assert!(
        dropped(stats.glove) > 0 && dropped(stats.tracker) > 0,
        "{stats:?}"
    );
    assert!(stats.tracker.decode.resyncs > 0);
}

#[test]
fn opening_fails_cleanly_when_a_port_is_absent() {
    let glove = PtyEmulator::spawn(CyberGloveModel::new(SensorCount::Eighteen)).unwrap();
    let profile = profile::resolve("cyberglove2-18-fastrak").unwrap();
    let options = StreamOptions {
        glove_port: Some(glove.port()),
        tracker_port: Some("/dev/nendo-no-such-tracker".into()),
        ..StreamOptions::default()
    };
    let e = HandStream::open(&profile, &options)
        .unwrap_err()
        .to_string();
    assert!(e.contains("/dev/nendo-no-such-tracker"), "{e}");
    // The glove that had started was stopped again.
    let end = Instant::now() + Duration::from_secs(1);
    while glove.received().last() != Some(&0x03) && Instant::now() < end {
        std::thread::sleep(Duration::from_millis(5));
    }
    assert_eq!(glove.received().last(), Some(&0x03));
}

#[test]
fn mouse_profiles_are_not_streams() {
    let p = profile::resolve("mouse").unwrap();
    match HandStream::open(&p, &StreamOptions::default()) {
        Err(DeviceError::Unsupported(why)) => {
            assert!(why.contains("mouse") && why.contains("window"), "{why}");
        }
        Err(e) => panic!("the wrong error: {e}"),
        Ok(_) => panic!("a mouse profile opened as a stream"),
    }
}

#[test]
fn a_trace_replays_in_real_time_with_its_frames() {
    let frames: Vec<HandFrame> = (0..20u64)
        .map(|i| HandFrame {
            time: nendo_devices::Timestamp(1_000_000 + i * 5_000),
            buttons: i as u32,
            ..HandFrame::default()
        })
        .collect();
    let trace = Trace {
        header: TraceHeader::default(),
        frames: frames.clone(),
        held: Vec::new(),
    };
    let start = Instant::now();
    let stream = HandStream::replay(trace.clone(), 1.0, false, 64);
    let got = collect_until(&stream, Duration::from_secs(2), |f| f.buttons == 19);
    let took = start.elapsed();
    assert_eq!(got.len(), 20);
    assert!(
        took >= Duration::from_millis(90),
        "played in {took:?}, recorded over 95 ms"
    );
    for (g, f) in got.iter().zip(&frames) {
        assert_eq!(g.buttons, f.buttons);
        assert_eq!(g.time.as_micros(), f.time.as_micros() - 1_000_000);
    }
    let end = Instant::now() + Duration::from_secs(1);
    while !stream.finished() && Instant::now() < end {
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(stream.finished());
    // Repeating keeps timestamps increasing across the loop.
    let stream = HandStream::replay(trace, 10.0, true, 256);
    let got = collect_until(&stream, Duration::from_millis(400), |_| false);
    assert!(got.len() > 40, "{} frames", got.len());
    assert!(got.windows(2).all(|w| w[0].time < w[1].time));
}

/// Plays `stream` to its end (at most 10 s) and returns every frame.
fn play_to_end(stream: &HandStream) -> Vec<HandFrame> {
    let end = Instant::now() + Duration::from_secs(10);
    let mut got = Vec::new();
    while Instant::now() < end {
        let finished = stream.finished();
        got.extend(stream.drain());
        if finished {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(stream.finished(), "the replay ended");
    got
}

/// A trace file streamed frame by frame plays exactly what the trace read whole plays (the
/// same frames at the same times, repeated with the same offsets); a frame line over its
/// 1 MB limit ends the replay there with the file and line as the last error, and an
/// interrupted recording plays its complete frames, saying what was dropped.
#[test]
fn a_trace_file_streamed_plays_as_the_trace_read_whole() {
    let frames: Vec<HandFrame> = (0..30u64)
        .map(|i| HandFrame {
            time: nendo_devices::Timestamp(500_000 + i * 1_000 + i * i),
            buttons: i as u32,
            ..HandFrame::default()
        })
        .collect();
    let trace = Trace {
        header: TraceHeader::default(),
        frames,
        held: Vec::new(),
    };
    let dir = std::env::temp_dir().join(format!("nendo-replay-file-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("t.trace");
    trace.write(&path).expect("written");
    let whole = play_to_end(&HandStream::replay(trace.clone(), 20.0, false, 1024));
    let streamed = HandStream::replay_file(&path, 20.0, false, 1024).expect("the header reads");
    assert_eq!(play_to_end(&streamed), whole);
    assert_eq!(streamed.last_error(), None);
    // Repeated: the same frames and times as the whole trace's repeat, pass after pass.
    let a = HandStream::replay(trace, 1.0, true, 1024);
    let b = HandStream::replay_file(&path, 1.0, true, 1024).expect("the header reads");
    let a = collect_until(&a, Duration::from_millis(300), |_| false);
    let b = collect_until(&b, Duration::from_millis(300), |_| false);
    let n = a.len().min(b.len());
    assert!(n > 60, "{n} frames: more than two passes");
    assert_eq!(a[..n], b[..n]);
    // A 2 MB frame line after 10 frames, with the `end` line after it: an error at its line.
    let text = std::fs::read_to_string(&path).expect("read");
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    let first_frame = lines.iter().position(|l| l == "frames").expect("frames") + 1;
    lines.insert(first_frame + 10, "7".repeat(2 << 20));
    let long = dir.join("long.trace");
    std::fs::write(&long, lines.join("\n") + "\n").expect("written");
    let s = HandStream::replay_file(&long, 20.0, false, 1024).expect("the header reads");
    assert_eq!(play_to_end(&s).len(), 10);
    let e = s.last_error().expect("the error");
    assert!(
        e.contains(&long.display().to_string())
            && e.contains(&format!("line {}", first_frame + 11))
            && e.contains("longer than 1 MB"),
        "{e}"
    );
    // Without its `end` line: an interrupted recording, its 30 frames played.
    let cut: Vec<&str> = text.lines().filter(|l| !l.starts_with("end ")).collect();
    let cut_path = dir.join("cut.trace");
    std::fs::write(&cut_path, cut.join("\n") + "\n").expect("written");
    let s = HandStream::replay_file(&cut_path, 20.0, false, 1024).expect("the header reads");
    assert_eq!(play_to_end(&s).len(), 30);
    let e = s.last_error().expect("the note");
    assert!(e.contains("interrupted recording"), "{e}");
    // A file that is no trace is refused at once.
    assert!(HandStream::replay_file(std::path::Path::new("/dev/zero"), 1.0, false, 8).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}
