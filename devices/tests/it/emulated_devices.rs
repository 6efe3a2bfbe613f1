//! Each serial backend against its byte-exact emulator on a pseudo-terminal, opened with the
//! real `serialport` crate: the handshake the backend sends, the emulator's answers, and the
//! decoded samples checked against the emulator's ground truth.
#![cfg(unix)]

use std::time::{Duration, Instant};

use nendo_devices::cyberglove::SensorCount;
use nendo_devices::emulator::{
    CyberGloveModel, FastrakModel, FlockModel, Glove5Model, Glove16Model, PtyEmulator,
};
use nendo_devices::profile::{self, GloveProfile, TrackerProfile, calibrate};
use nendo_devices::{GloveSample, Joint, TrackerPose, open_glove, open_tracker};

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

fn read_gloves(g: &mut dyn nendo_devices::Glove, want: usize) -> Vec<GloveSample> {
    let mut out = Vec::new();
    let end = Instant::now() + Duration::from_secs(5);
    while out.len() < want && Instant::now() < end {
        g.read(Duration::from_millis(20), &mut out).unwrap();
    }
    out
}

fn read_poses(t: &mut dyn nendo_devices::Tracker, want: usize) -> Vec<TrackerPose> {
    let mut out = Vec::new();
    let end = Instant::now() + Duration::from_secs(5);
    while out.len() < want && Instant::now() < end {
        t.read(Duration::from_millis(20), &mut out).unwrap();
    }
    out
}

/// What the emulator has received, once it has at least `n` bytes (or after 2 s).
fn received(emu: &PtyEmulator, n: usize) -> Vec<u8> {
    let end = Instant::now() + Duration::from_secs(2);
    loop {
        let r = emu.received();
        if r.len() >= n || Instant::now() > end {
            return r;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}

fn contains(haystack: &[u8], needle: &[u8]) -> bool {
    haystack.windows(needle.len()).any(|w| w == needle)
}

#[test]
fn cyberglove_18_handshake_and_samples_are_exact() {
    for (profile_name, sensors) in [
        ("cyberglove2-18", SensorCount::Eighteen),
        ("cyberglove2-22", SensorCount::TwentyTwo),
    ] {
        let emu = PtyEmulator::spawn(CyberGloveModel::new(sensors)).unwrap();
        let profile = glove_profile(profile_name, &emu.port());
        let mut glove = open_glove(&profile).unwrap();
        glove.start().unwrap();
        // Stop, status byte on (answered U NUL), one poll (answered by a G record), stream.
        assert_eq!(received(&emu, 5), vec![0x03, b'U', 1, b'G', b'S']);
        let samples = read_gloves(glove.as_mut(), 20);
        assert!(samples.len() >= 20, "{} samples", samples.len());
        let table = profile.calibration();
        let (offset, gain) = (table[0].offset, table[0].gain);
        let mut previous: Option<u64> = None;
        for s in &samples {
            // Sensor 0 carries k (mod 255); rebuild the whole record from it.
            let raw0 = (s.angles.get(Joint::ThumbRoll).unwrap() / gain + offset).round() as u64;
            let k = raw0 - 1 + previous.map_or(0, |p| (p + 1) / 255 * 255);
            let raw: Vec<f64> = CyberGloveModel::values_at(sensors, k)
                .into_iter()
                .map(f64::from)
                .collect();
            assert_eq!(s.angles, calibrate(table, &raw).unwrap());
            let status = CyberGloveModel::status_at(k);
            assert_eq!(s.switch, Some(status & 0x02 != 0));
            if let Some(p) = previous {
                assert_eq!(k, p + 1, "a record was lost");
            }
            previous = Some(k);
        }
        assert_eq!(glove.stats().decode.rejected, 0);
        glove.stop();
        assert_eq!(received(&emu, 6).last(), Some(&0x03));
    }
}

#[test]
fn cyberglove_with_the_wrong_sensor_count_fails_its_handshake() {
    let emu = PtyEmulator::spawn(CyberGloveModel::new(SensorCount::TwentyTwo)).unwrap();
    let mut glove = open_glove(&glove_profile("cyberglove2-18", &emu.port())).unwrap();
    let e = glove.start().unwrap_err().to_string();
    assert!(e.contains("did not answer G"), "{e}");
}

#[test]
fn glove5_handshake_and_samples_are_exact() {
    let emu = PtyEmulator::spawn(Glove5Model::new()).unwrap();
    let profile = glove_profile("5dt-glove5-serial", &emu.port());
    let mut glove = open_glove(&profile).unwrap();
    glove.start().unwrap();
    // One record asked for (it ends any streaming left over), initialise, information, stream.
    assert_eq!(received(&emu, 4), b"CAGD");
    let samples = read_gloves(glove.as_mut(), 20);
    assert!(samples.len() >= 20);
    let table = profile.calibration();
    let first = (samples[0].angles.get(Joint::ThumbMcp).unwrap() / table[0].gain).round() as u64;
    for (i, s) in samples.iter().enumerate() {
        let rec = Glove5Model::record_at(first + i as u64);
        assert_eq!(
            s.angles,
            calibrate(table, &rec.fingers.map(f64::from)).unwrap(),
            "sample {i}"
        );
    }
}

/// Records the emulator streams within `window`.
fn streamed_during(emu: &PtyEmulator, window: Duration) -> u64 {
    let before = emu.records_sent();
    std::thread::sleep(window);
    emu.records_sent() - before
}

#[test]
fn glove5_stop_ends_streaming_and_a_restart_reads_a_quiet_glove() {
    let emu = PtyEmulator::spawn(Glove5Model::new()).unwrap();
    let profile = glove_profile("5dt-glove5-serial", &emu.port());
    let mut glove = open_glove(&profile).unwrap();
    glove.start().unwrap();
    assert!(read_gloves(glove.as_mut(), 10).len() >= 10);
    assert!(streamed_during(&emu, Duration::from_millis(100)) > 3);
    glove.stop();
    assert_eq!(received(&emu, 5).last(), Some(&b'C'));
    std::thread::sleep(Duration::from_millis(50));
    assert_eq!(
        streamed_during(&emu, Duration::from_millis(150)),
        0,
        "the glove still streams after stop"
    );
    // A restart (as after the watchdog) finds the glove quiet and streams again, exactly.
    glove.start().unwrap();
    assert!(received(&emu, 9).ends_with(b"CAGD"));
    let samples = read_gloves(glove.as_mut(), 20);
    assert!(samples.len() >= 20);
    let table = profile.calibration();
    let first = (samples[0].angles.get(Joint::ThumbMcp).unwrap() / table[0].gain).round() as u64;
    for (i, s) in samples.iter().enumerate() {
        let rec = Glove5Model::record_at(first + i as u64);
        assert_eq!(
            s.angles,
            calibrate(table, &rec.fingers.map(f64::from)).unwrap(),
            "sample {i}"
        );
    }
    assert_eq!(glove.stats().decode.rejected, 0);
}

#[test]
fn a_cyberglove_out_of_its_interface_unit_is_reported_as_disconnected() {
    let model = CyberGloveModel::new(SensorCount::Eighteen);
    let plug = model.glove_plug();
    let emu = PtyEmulator::spawn(model).unwrap();
    let mut glove = open_glove(&glove_profile("cyberglove2-18", &emu.port())).unwrap();
    // Unplugged at start: the poll is answered by `G e g`, a disconnect naming the port.
    plug.set_plugged(false);
    let e = glove.start().unwrap_err();
    assert!(e.is_disconnect(), "{e}");
    assert!(
        e.to_string().contains(&emu.port()) && e.to_string().contains("unplugged"),
        "{e}"
    );
    // Plugged in, started, then pulled out while streaming: `S e g` records.
    plug.set_plugged(true);
    glove.start().unwrap();
    assert!(read_gloves(glove.as_mut(), 5).len() >= 5);
    plug.set_plugged(false);
    let end = Instant::now() + Duration::from_secs(2);
    let mut out = Vec::new();
    let e = loop {
        match glove.read(Duration::from_millis(20), &mut out) {
            Err(e) => break e,
            Ok(()) => assert!(
                Instant::now() < end,
                "no error after the glove was pulled out"
            ),
        }
    };
    assert!(e.is_disconnect(), "{e}");
    assert!(glove.stats().faults >= 1);
}

#[test]
fn flagged_fastrak_records_are_dropped_and_counted_as_faults() {
    let emu = PtyEmulator::spawn(FastrakModel::new().flagging_every(4)).unwrap();
    let mut t = tracker_profile("fastrak", &emu.port());
    if let TrackerProfile::Fastrak { format, .. } = &mut t {
        *format = profile::FastrakFormat::Binary;
    }
    let mut tracker = open_tracker(&t).unwrap();
    tracker.start().unwrap();
    let poses = read_poses(tracker.as_mut(), 30);
    assert!(poses.len() >= 30);
    // Every pose is an unflagged record of the path, and one in four records is missing.
    let on_path = |p: &TrackerPose, k: u64| {
        let t = FastrakModel::pose_at(k);
        (p.position - t.position).abs().max_element() <= 1e-6
            && p.orientation.angle_between(t.orientation) <= 1e-6
    };
    let mut k = 0;
    for (i, p) in poses.iter().enumerate() {
        k = (k..k + 5000)
            .find(|&k| on_path(p, k))
            .unwrap_or_else(|| panic!("pose {i} is not on the path"));
        assert!(
            !FastrakModel::is_flagged(4, k),
            "pose {i} is flagged record {k}"
        );
        k += 1;
    }
    let stats = tracker.stats();
    assert!(stats.faults >= 8, "{stats:?}");
    assert_eq!(stats.decode.rejected, 0, "flagged records are well formed");
}

#[test]
fn glove16_streams_and_skips_information_packets() {
    let emu = PtyEmulator::spawn(Glove16Model::new()).unwrap();
    let mut table = profile::resolve("5dt-ultra14-usb")
        .unwrap()
        .glove()
        .unwrap()
        .calibration()
        .to_vec();
    table[14].joint = None;
    let profile = GloveProfile::FiveDtGlove16 {
        port: emu.port(),
        baud: 19200,
        usb: None,
        calibration: table.clone(),
    };
    let mut glove = open_glove(&profile).unwrap();
    glove.start().unwrap();
    let samples = read_gloves(glove.as_mut(), 45);
    assert!(samples.len() >= 45);
    let first = (samples[0].angles.get(Joint::ThumbMcp).unwrap() / table[0].gain).round() as u64;
    for (i, s) in samples.iter().enumerate() {
        let raw = Glove16Model::values_at(first + i as u64).map(f64::from);
        assert_eq!(s.angles, calibrate(&table, &raw).unwrap(), "sample {i}");
    }
    assert!(
        glove.stats().ignored >= 1,
        "information packets are decoded and skipped"
    );
    assert_eq!(glove.stats().decode.rejected, 0);
}

/// Finds the record index of the first pose, then checks the rest follow one by one.
fn check_path(
    poses: &[TrackerPose],
    truth: impl Fn(u64) -> TrackerPose,
    pos_tol: f64,
    rot_tol: f64,
) {
    let close = |p: &TrackerPose, k: u64| {
        let t = truth(k);
        (p.position - t.position).abs().max_element() <= pos_tol
            && p.orientation.angle_between(t.orientation) <= rot_tol
    };
    let k0 = (0..5000)
        .find(|&k| close(&poses[0], k))
        .expect("the first pose is on the emulator's path");
    for (i, p) in poses.iter().enumerate() {
        let t = truth(k0 + i as u64);
        assert!(close(p, k0 + i as u64), "pose {i}: {p:?} vs {t:?}");
    }
}

#[test]
fn fastrak_binary_and_ascii_handshakes_and_poses() {
    for (format, units, command, pos_tol, rot_tol) in [
        (
            profile::FastrakFormat::Binary,
            profile::FastrakUnits::Centimetres,
            &b"cufO1,2,11,1\rPC"[..],
            1e-6,
            1e-6,
        ),
        (
            profile::FastrakFormat::Ascii,
            profile::FastrakUnits::Inches,
            &b"cUFO1,2,11,1\rPC"[..],
            0.0254 * 0.006,
            2e-4,
        ),
    ] {
        let emu = PtyEmulator::spawn(FastrakModel::new()).unwrap();
        let mut t = tracker_profile("fastrak", &emu.port());
        if let TrackerProfile::Fastrak {
            format: f,
            units: u,
            ..
        } = &mut t
        {
            *f = format;
            *u = units;
        }
        let mut tracker = open_tracker(&t).unwrap();
        tracker.start().unwrap();
        assert_eq!(received(&emu, command.len()), command);
        let poses = read_poses(tracker.as_mut(), 30);
        assert!(poses.len() >= 30);
        check_path(&poses, FastrakModel::pose_at, pos_tol, rot_tol);
        assert_eq!(tracker.stats().decode.rejected, 0);
        tracker.stop();
        assert_eq!(received(&emu, command.len() + 1).last(), Some(&b'c'));
    }
}

#[test]
fn fastrak_euler_orientation_matches_the_quaternion_path() {
    let emu = PtyEmulator::spawn(FastrakModel::new()).unwrap();
    let mut t = tracker_profile("fastrak", &emu.port());
    if let TrackerProfile::Fastrak {
        orientation,
        format,
        ..
    } = &mut t
    {
        *orientation = profile::FastrakOrientation::Euler;
        *format = profile::FastrakFormat::Ascii;
    }
    let mut tracker = open_tracker(&t).unwrap();
    tracker.start().unwrap();
    assert!(contains(&received(&emu, 15), b"O1,2,4,1\r"));
    let poses = read_poses(tracker.as_mut(), 20);
    // Two decimals of a degree: 1e-4 rad per angle, a few of them combined.
    check_path(&poses, FastrakModel::pose_at, 0.0001, 5e-4);
}

#[test]
fn flock_handshake_and_poses_in_each_orientation_mode() {
    for (mode, command) in [
        (profile::FlockRecordMode::PositionQuaternion, b"?]B@"),
        (profile::FlockRecordMode::PositionAngles, b"?YB@"),
        (profile::FlockRecordMode::PositionMatrix, b"?ZB@"),
    ] {
        let emu = PtyEmulator::spawn(FlockModel::new()).unwrap();
        let mut t = tracker_profile("flock", &emu.port());
        if let TrackerProfile::Flock { record, .. } = &mut t {
            *record = mode;
        }
        let mut tracker = open_tracker(&t).unwrap();
        tracker.start().unwrap();
        assert_eq!(received(&emu, command.len()), command);
        let poses = read_poses(tracker.as_mut(), 20);
        assert!(poses.len() >= 20);
        // 14-bit words: 36 in / 8192 ≈ 0.11 mm; unit values to 1.2e-4.
        check_path(&poses, FlockModel::pose_at, 0.0254 * 36.0 / 8192.0, 2e-3);
        tracker.stop();
        assert_eq!(received(&emu, command.len() + 1).last(), Some(&b'?'));
    }
}

#[test]
fn opening_an_absent_port_is_a_clear_error() {
    let mut glove =
        open_glove(&glove_profile("cyberglove2-18", "/dev/nendo-no-such-port")).unwrap();
    let e = glove.start().unwrap_err();
    assert!(e.is_disconnect());
    assert!(e.to_string().contains("/dev/nendo-no-such-port"), "{e}");
}
