//! Issue 16: start-up that retries and values that make sense — one garbled handshake answer
//! per protocol still starts the device; values beyond the device's range are dropped and
//! counted; a stream connects with a device absent, takes it in when it comes, and its status
//! clears the error on recovery.
#![cfg(unix)]

use std::time::{Duration, Instant};

use nendo_devices::cyberglove::SensorCount;
use nendo_devices::emulator::{
    CyberGloveModel, FastrakModel, FlockModel, Glove5Model, PtyEmulator,
};
use nendo_devices::fastrak::{self, DataFormat, FastrakFraming, FastrakRecord};
use nendo_devices::flock::{self, BirdOrientation, FlockFraming, FlockRecord, RecordMode};
use nendo_devices::profile::{self, GloveProfile, TrackerProfile};
use nendo_devices::{
    DeviceRole, GloveSample, HandStream, SourceState, StreamOptions, TrackerPose, open_glove,
    open_tracker,
};

fn glove_profile(name: &str, port: &str) -> GloveProfile {
    let mut g = profile::resolve(name).unwrap().glove().unwrap().clone();
    g.set_port(port);
    g
}

fn tracker_profile(name: &str, port: &str) -> TrackerProfile {
    let mut t = profile::resolve(name).unwrap().tracker().unwrap().clone();
    t.set_port(port);
    t
}

fn poses_for(t: &mut dyn nendo_devices::Tracker, time: Duration) -> Vec<TrackerPose> {
    let mut out = Vec::new();
    let end = Instant::now() + time;
    while Instant::now() < end {
        t.read(Duration::from_millis(20), &mut out).unwrap();
    }
    out
}

fn gloves_for(g: &mut dyn nendo_devices::Glove, want: usize) -> Vec<GloveSample> {
    let mut out = Vec::new();
    let end = Instant::now() + Duration::from_secs(3);
    while out.len() < want && Instant::now() < end {
        g.read(Duration::from_millis(20), &mut out).unwrap();
    }
    out
}

#[test]
fn a_garbled_answer_to_fastrak_p_is_retried() {
    let emu = PtyEmulator::spawn(FastrakModel::new()).unwrap();
    // The record's type byte `0` becomes `1`: not a record.
    emu.garble_answer_to(fastrak::POINT, 0x01);
    let mut t = open_tracker(&tracker_profile("fastrak", &emu.port())).unwrap();
    t.start().unwrap();
    assert_eq!(emu.answers_garbled(), 1);
    assert_eq!(t.stats().handshake_retries, 1);
    assert_eq!(t.stats().starts, 1);
    assert!(!poses_for(t.as_mut(), Duration::from_millis(200)).is_empty());
    let sent = emu.received();
    assert_eq!(
        sent.iter().filter(|&&b| b == fastrak::POINT).count(),
        2,
        "P resent"
    );
}

#[test]
fn a_garbled_answer_to_flock_b_is_retried() {
    let emu = PtyEmulator::spawn(FlockModel::new()).unwrap();
    // The phasing bit of the record's first byte is lost: no record starts.
    emu.garble_answer_to(flock::POINT, flock::PHASE_BIT);
    let mut t = open_tracker(&tracker_profile("flock", &emu.port())).unwrap();
    t.start().unwrap();
    assert_eq!(emu.answers_garbled(), 1);
    assert_eq!(t.stats().handshake_retries, 1);
    assert!(!poses_for(t.as_mut(), Duration::from_millis(200)).is_empty());
}

#[test]
fn a_garbled_answer_to_cyberglove_g_is_retried() {
    let emu = PtyEmulator::spawn(CyberGloveModel::new(SensorCount::Eighteen)).unwrap();
    // The record's header `G` becomes `F`.
    emu.garble_answer_to(b'G', 0x01);
    let mut g = open_glove(&glove_profile("cyberglove2-18", &emu.port())).unwrap();
    g.start().unwrap();
    assert_eq!(emu.answers_garbled(), 1);
    assert_eq!(g.stats().handshake_retries, 1);
    assert!(gloves_for(g.as_mut(), 5).len() >= 5);
}

#[test]
fn a_garbled_answer_to_glove5_a_is_retried_and_a_mute_device_is_given_up_on() {
    let emu = PtyEmulator::spawn(Glove5Model::new()).unwrap();
    emu.garble_answer_to(b'A', 0x01);
    let mut g = open_glove(&glove_profile("5dt-glove5-serial", &emu.port())).unwrap();
    g.start().unwrap();
    assert_eq!((emu.answers_garbled(), g.stats().handshake_retries), (1, 1));
    assert!(gloves_for(g.as_mut(), 5).len() >= 5);
    g.stop();
    // Silent: every attempt times out; after the last the device is declared absent.
    emu.set_silent(true);
    let started = Instant::now();
    let e = g.start().unwrap_err().to_string();
    assert!(e.contains("did not answer"), "{e}");
    assert_eq!(
        g.stats().handshake_retries,
        1 + u64::from(nendo_devices::device::HANDSHAKE_ATTEMPTS)
    );
    // The retries are counted above; the clock only guards against a hang.
    assert!(started.elapsed() < Duration::from_secs(60));
}

/// A Fastrak binary position + quaternion record in centimetres (the `fastrak` profile's
/// format) at `position`.
fn fastrak_record(position: [f64; 3]) -> Vec<u8> {
    let mut out = Vec::new();
    fastrak::encode_record(
        &FastrakFraming::position_quaternion(DataFormat::Binary),
        &FastrakRecord {
            station: 1,
            error: fastrak::NO_ERROR,
            position: Some(position),
            euler: None,
            quaternion: Some([1.0, 0.0, 0.0, 0.0]),
        },
        &mut out,
    )
    .unwrap();
    out
}

#[test]
fn fastrak_positions_beyond_its_range_are_dropped_and_counted() {
    // The emulator streams at 120 Hz; the records injected between its records are the
    // tracker's too (same framing), three of them out of range.
    let emu = PtyEmulator::spawn(FastrakModel::new()).unwrap();
    let mut t = open_tracker(&tracker_profile("fastrak", &emu.port())).unwrap();
    t.start().unwrap();
    poses_for(t.as_mut(), Duration::from_millis(50));
    let before = t.stats();
    // 990 cm and −400 cm (within the decoder's ±1000 units, beyond the 381 cm range), and
    // one within range (300 cm).
    for p in [[990.0, 10.0, 5.0], [10.0, -400.0, 5.0], [10.0, 5.0, 300.0]] {
        emu.inject(&fastrak_record(p));
        let poses = poses_for(t.as_mut(), Duration::from_millis(60));
        assert!(
            poses
                .iter()
                .all(|p| p.position.abs().max_element() <= fastrak::POSITION_LIMIT_M),
            "{poses:?}"
        );
    }
    let after = t.stats();
    assert_eq!(after.invalid - before.invalid, 2, "{after:?}");
    assert_eq!(after.decode.rejected, before.decode.rejected);
    assert!((fastrak::POSITION_LIMIT_M - 3.81).abs() < 1e-9);
}

#[test]
fn flock_angles_and_matrices_that_are_not_rotations_are_dropped_and_counted() {
    let framing = |mode| FlockFraming {
        mode,
        scale_inches: 36.0,
    };
    let record = |orientation| FlockRecord {
        position: Some([1.0, 2.0, 3.0]),
        orientation: Some(orientation),
    };
    // Elevation beyond ±90°.
    let bad = record(BirdOrientation::Angles([10.0, 120.0, 5.0]));
    assert!(bad.pose(false).is_err());
    assert!(
        record(BirdOrientation::Angles([10.0, 80.0, 5.0]))
            .pose(false)
            .is_ok()
    );
    // A shear of determinant 1 is no rotation.
    let shear = record(BirdOrientation::Matrix([
        1.0, 0.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 1.0,
    ]));
    assert!(shear.pose(false).is_err());
    // Through the backend, on the line: counted as invalid, never passed on.
    let emu = PtyEmulator::spawn(FlockModel::new()).unwrap();
    let mut t = open_tracker(&tracker_profile("flock", &emu.port())).unwrap();
    t.start().unwrap();
    poses_for(t.as_mut(), Duration::from_millis(50));
    let before = t.stats().invalid;
    // The `flock` profile streams position + quaternion: a quaternion of norm 1.4 is
    // rejected by the decoder; send an in-range one and a bad one in position + quaternion.
    let mut bytes = Vec::new();
    flock::encode_record(
        &framing(RecordMode::PositionQuaternion),
        &FlockRecord {
            position: Some([40.0, 0.0, 0.0]),
            orientation: Some(BirdOrientation::Quaternion([1.0, 0.0, 0.0, 0.0])),
        },
        &mut bytes,
    );
    emu.inject(&bytes);
    let poses = poses_for(t.as_mut(), Duration::from_millis(100));
    // 40 in is beyond the 36-inch scale: the encoder clips it to the word's end (35.99 in),
    // the most a bird can report.
    assert!(
        poses
            .iter()
            .all(|p| p.position.x.abs() <= 36.0 * 0.0254 + 1e-9)
    );
    assert_eq!(t.stats().invalid, before);
}

#[test]
fn connect_starts_what_is_present_and_takes_in_the_rest_when_it_comes() {
    let glove = PtyEmulator::spawn(CyberGloveModel::new(SensorCount::Eighteen)).unwrap();
    let tracker = PtyEmulator::spawn(FastrakModel::new()).unwrap();
    tracker.unplug();
    let profile = profile::resolve("cyberglove2-18-fastrak").unwrap();
    let options = StreamOptions {
        glove_port: Some(glove.port()),
        tracker_port: Some(tracker.port()),
        watchdog: Some(Duration::from_millis(150)),
        retry: Duration::from_millis(50),
        ..StreamOptions::default()
    };
    // `open` wants both now; `connect` starts the glove and retries the tracker.
    match HandStream::open(&profile, &options) {
        Err(e) => assert!(e.to_string().contains(&tracker.port()), "{e}"),
        Ok(_) => panic!("open started without the unplugged tracker"),
    }
    let stream = HandStream::connect(&profile, &options).unwrap();
    let status = stream.status();
    assert_eq!(status.len(), 2);
    assert_eq!(status[0].role, DeviceRole::Glove);
    assert_eq!(status[0].state, SourceState::Ok);
    assert_eq!(status[1].role, DeviceRole::Tracker);
    assert_eq!(status[1].state, SourceState::Disconnected);
    let error = status[1].last_error.clone().unwrap();
    assert!(error.contains("cannot open serial port"), "{error}");
    std::thread::sleep(Duration::from_millis(700));
    let status = stream.status();
    // The emulator sends at most 100 Hz; a loaded machine may run it slower, so only the
    // bounds a stream cannot break are checked here: some rate, never above the sender's.
    assert!(
        status[0].rate_hz > 0.0 && status[0].rate_hz < 140.0,
        "the glove streams at up to 100 Hz: {}",
        status[0].rate_hz
    );
    assert_eq!(status[1].rate_hz, 0.0);
    assert!(status[1].last_error.is_some());
    tracker.replug();
    // Waits for the event; the deadline only guards against a hang.
    let end = Instant::now() + Duration::from_secs(30);
    while stream.states().0 != SourceState::Ok && Instant::now() < end {
        stream.drain();
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(700));
    stream.drain();
    let status = stream.status();
    assert_eq!(status[1].state, SourceState::Ok);
    assert_eq!(
        status[1].last_error, None,
        "the error is cleared on recovery"
    );
    assert!(
        status[1].rate_hz > 0.0 && status[1].rate_hz < 150.0,
        "the tracker streams at up to 120 Hz: {}",
        status[1].rate_hz
    );
    assert!(status[1].samples > 50);
    assert_eq!(status[1].stats.starts, 1);
    // Unplugged mid-session: counted, and the error is back until it recovers.
    tracker.unplug();
    let end = Instant::now() + Duration::from_secs(30);
    while stream.states().0 != SourceState::Disconnected && Instant::now() < end {
        stream.drain();
        std::thread::sleep(Duration::from_millis(20));
    }
    let status = stream.status();
    assert_eq!(status[1].state, SourceState::Disconnected);
    assert!(status[1].disconnects >= 1 && status[1].last_error.is_some());
}

#[test]
fn a_replay_reports_the_traces_states() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("traces/plane-groove.trace");
    let trace = nendo_devices::Trace::read(&path).unwrap();
    let stream = HandStream::replay(trace, 4.0, false, 4096);
    let end = Instant::now() + Duration::from_secs(3);
    while stream.drain().is_empty() && Instant::now() < end {
        std::thread::sleep(Duration::from_millis(10));
    }
    assert_eq!(stream.states(), (SourceState::Ok, SourceState::Ok));
    let status = stream.status();
    assert_eq!(status.len(), 2);
    assert!(
        status
            .iter()
            .all(|s| s.state == SourceState::Ok && s.samples > 0)
    );
}
