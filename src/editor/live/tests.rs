//! The device loop without a window: no sample dropped, typed start outcomes, a recording
//! that replays to the window's surface, profiles, ports, the radius that follows the hand.

use super::inbox::*;
use super::profiles::*;
use super::*;
use crate::editor::document::Document;
use crate::editor::settings::Settings;
use nendo_devices::profile::{self, Input};
use nendo_devices::{FrameStatus, Timestamp, TraceHeader};
use nendo_devices::{HandFrame, HandStream, Trace};

/// A window frame far slower than the device (here a whole second) loses nothing: the
/// loop thread keeps draining the stream's small channel into the inbox.
#[test]
fn a_slow_window_frame_drops_no_sample() {
    let n = 1000u64;
    let frames = (0..n)
        .map(|i| HandFrame {
            time: Timestamp::from_micros(i * 10_000),
            status: FrameStatus::default(),
            ..Default::default()
        })
        .collect();
    let trace = Trace {
        header: TraceHeader::default(),
        frames,
    };
    // 100 Hz played 10 times faster: 1 000 frames/s through a 64-frame channel.
    let stream = HandStream::replay(trace, 10.0, false, 64);
    let session = DeviceSession::start(stream, None).expect("loop thread");
    let deadline = Instant::now() + Duration::from_secs(10);
    while !lock(&session.shared.status).finished && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(1100));
    }
    let got = std::mem::take(&mut *lock(&session.shared.inbox));
    assert_eq!(got.len() as u64, n, "every sample arrives");
    assert!(got.windows(2).all(|w| w[0].time < w[1].time), "in order");
}

/// A recording that cannot start is refused with the trace writer's error, and a finished
/// recording reports how many frames it wrote.
#[test]
fn session_start_and_recording_report_typed_outcomes() {
    let trace = || Trace {
        header: TraceHeader::default(),
        frames: (0..5u64)
            .map(|i| HandFrame {
                time: Timestamp::from_micros(i * 1000),
                status: FrameStatus::default(),
                ..Default::default()
            })
            .collect(),
    };
    let profile = profile::builtin()
        .into_iter()
        .next()
        .expect("a built-in profile");
    let dir = std::env::temp_dir().join(format!("nendo-live-record-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let missing = dir.join("no-such-folder").join("t.trace");
    let stream = HandStream::replay(trace(), 100.0, false, 64);
    let err = DeviceSession::start(stream, Some((missing.clone(), &profile, None)))
        .map(|_| ())
        .expect_err("no folder to record into");
    assert!(matches!(err, LiveError::Record(_)), "{err:?}");
    assert!(
        err.to_string().contains(&missing.display().to_string()),
        "{err}"
    );
    let path = dir.join("t.trace");
    let stream = HandStream::replay(trace(), 100.0, false, 64);
    let mut session =
        DeviceSession::start(stream, Some((path.clone(), &profile, None))).expect("started");
    let deadline = Instant::now() + Duration::from_secs(10);
    while !lock(&session.shared.status).finished && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(10));
    }
    session.stop();
    let recorded = lock(&session.shared.recorded).take();
    assert!(matches!(recorded, Some(Ok(5))), "{recorded:?}");
    assert_eq!(
        Trace::read(&path).expect("the recorded trace").frames.len(),
        5
    );
    let _ = std::fs::remove_dir_all(&dir);
}

fn plane_doc() -> Document {
    use crate::model::Model;
    use crate::surface::{Primitive, PrimitiveParams};
    Document::new(Model::new(
        Primitive::Plane
            .build(&PrimitiveParams::default())
            .expect("plane"),
    ))
}

/// The window's recorder writes the scene it records on — the document's model embedded,
/// the hand's finger and radius — and `nendo replay` of the recording, with no other
/// argument, gives the window's surface.
#[test]
fn a_window_recording_replays_to_the_windows_surface() {
    use crate::hand::scene::{Scene, Start};
    let dir = std::env::temp_dir().join(format!("nendo-live-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let source =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("devices/traces/plane-groove.trace");
    let profile_path = dir.join("replay.json");
    let json = serde_json::json!({
        "format": "nendo-device-profile",
        "version": 1,
        "name": "groove-replay",
        "input": {"replay": {"trace": source, "speed": 40.0}},
    });
    std::fs::write(&profile_path, json.to_string()).expect("profile written");
    let profile =
        profile::resolve(&profile_path.display().to_string()).expect("the replay profile");
    // A start that is no primitive: the plane with a bump beside the groove's path.
    let mut doc = plane_doc();
    let mut start = doc.model().clone();
    let k = start
        .surface
        .nodes()
        .iter()
        .position(|p| (p.x - 1.0).abs() < 1e-9 && (p.y - 2.0).abs() < 1e-9)
        .expect("a node at (1, 2)");
    let p = start.surface.nodes()[k];
    start
        .surface
        .set_nodes(&[(k, p + glam::DVec3::new(0.0, 0.0, 0.4))])
        .expect("moved");
    doc.replace("bump", start.clone());
    let trace_path = dir.join("window.trace");
    let mut live = LiveInput {
        entries: vec![ProfileEntry {
            profile,
            source: ProfileSource::File(profile_path.clone()),
        }],
        selected: 0,
        radius_set: Some(0.8),
        record: true,
        record_to: trace_path.display().to_string(),
        ..LiveInput::default()
    };
    live.connect(&mut doc);
    assert!(live.is_connected(), "{:?}", live.message);
    let deadline = Instant::now() + Duration::from_secs(30);
    while live.is_connected() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(20));
        let _ = live.poll(&mut doc);
    }
    assert!(!live.is_connected(), "the replayed trace ended");
    assert_ne!(doc.model(), &start, "the hand grooved the document");
    let recorded = Trace::read(&trace_path).expect("the recording");
    let scene = Scene::of_trace(&recorded.header)
        .expect("a valid scene")
        .expect("a scene");
    assert_eq!(scene.start, Start::Model(Box::new(start)));
    assert_eq!(scene.finger.as_deref(), Some("index"));
    assert_eq!(scene.finger_radius, Some(0.8));
    let out = dir.join("replayed.json");
    // `nendo replay TRACE --out OUT` (it reports its outcome on standard error).
    let _ = crate::cli::replay::run(crate::cli::replay::Args {
        trace: trace_path,
        primitive: None,
        shape: crate::cli::primitive_args::ShapeArgs::default(),
        model: None,
        regulation: None,
        profile: None,
        finger: None,
        finger_radius: None,
        auto_refine: false,
        no_auto_refine: false,
        mirror: None,
        no_filter: false,
        out: out.clone(),
    });
    let replayed = crate::model::Model::read(&out).expect("the replay").model;
    assert_eq!(replayed.surface.nodes(), doc.model().surface.nodes());
    assert_eq!(&replayed, doc.model());
    let _ = std::fs::remove_dir_all(&dir);
}

fn listed() -> LiveInput {
    let mut live = LiveInput::default();
    live.rescan();
    live
}

fn glove_and_tracker(live: &LiveInput) -> usize {
    live.entries
        .iter()
        .position(|e| {
            matches!(&e.profile.input, Input::Devices { glove: Some(g), tracker: Some(_) } if g.port().is_some())
        })
        .expect("a built-in serial glove and tracker profile")
}

/// Connect on the mouse profile opens no stream: it hands the mouse settings to the Hand
/// tool, with no error.
#[test]
fn the_mouse_profile_selects_the_mouse_hand() {
    let mut live = listed();
    let mouse = live
        .entries
        .iter()
        .position(|e| matches!(e.profile.input, Input::Mouse(_)))
        .expect("a built-in mouse profile");
    live.select(mouse);
    let mut doc = plane_doc();
    let got = live.connect_or_mouse(&mut doc);
    assert!(got.is_some(), "the mouse profile's settings");
    assert!(!live.is_connected());
    assert_eq!(
        live.message.as_deref(),
        Some("the mouse drives the hand (Hand tool)")
    );
}

/// Connect starts even when neither device is there now (both ports, chosen in the panel,
/// missing): the stream keeps retrying them, as for a device unplugged mid-session, and
/// each device's status says why it waits.
#[test]
fn connect_starts_with_absent_devices_and_retries_them() {
    let mut live = listed();
    let k = glove_and_tracker(&live);
    live.select(k);
    live.glove_port = "/nonexistent/nendo-glove".into();
    live.tracker_port = "/nonexistent/nendo-tracker".into();
    let mut doc = plane_doc();
    assert!(live.connect_or_mouse(&mut doc).is_none());
    assert!(
        live.is_connected(),
        "connected, retrying: {:?}",
        live.message
    );
    let (devices, _, replay) = live.device_status().expect("a session");
    assert!(!replay);
    assert_eq!(devices.len(), 2);
    for d in &devices {
        assert_eq!(d.state, SourceState::Disconnected, "{d:?}");
        let e = d.last_error.as_deref().unwrap_or_default();
        assert!(e.contains("/nonexistent/nendo-"), "{e}");
    }
    let running = live.running_devices().expect("the running profile");
    assert_eq!(
        running.tracker().map(|t| t.port()),
        Some("/nonexistent/nendo-tracker")
    );
    live.disconnect_from(&mut doc);
    assert!(!live.is_connected());
}

/// An existing recording is never replaced without asking: Connect waits with the
/// question; "Record to NAME-2.trace" records beside it and the first file is untouched.
#[test]
fn a_recording_never_overwrites_without_asking() {
    let dir = std::env::temp_dir().join(format!("nendo-live-ask-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let first = dir.join("session.trace");
    std::fs::write(&first, "an earlier recording").expect("written");
    let mut live = listed();
    let k = glove_and_tracker(&live);
    live.select(k);
    live.glove_port = "/nonexistent/nendo-glove".into();
    live.tracker_port = "/nonexistent/nendo-tracker".into();
    live.record = true;
    live.record_to = first.display().to_string();
    let mut doc = plane_doc();
    live.connect(&mut doc);
    assert!(!live.is_connected(), "waits for the answer");
    assert_eq!(live.confirm_overwrite.as_deref(), Some(first.as_path()));
    let fresh = fresh_name(&first);
    assert_eq!(fresh, dir.join("session-2.trace"));
    live.connect_recording(&mut doc, Some(fresh.clone()));
    assert!(live.is_connected());
    live.disconnect_from(&mut doc);
    assert_eq!(
        std::fs::read_to_string(&first).expect("kept"),
        "an earlier recording"
    );
    assert!(Trace::read(&fresh).is_ok(), "the new recording is a trace");
    assert_eq!(fresh_name(&first), dir.join("session-3.trace"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Alignment on a shipped profile goes into a user copy in the profile folder (selected
/// from then on); the shipped entry keeps its values; the ports chosen go with it; a
/// second change goes to the same copy.
#[test]
fn alignment_is_saved_into_a_user_copy_of_a_shipped_profile() {
    let dir = std::env::temp_dir().join(format!("nendo-live-copy-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut live = LiveInput::with_profile_dir(Some(dir.clone()));
    let k = glove_and_tracker(&live);
    live.select(k);
    let name = live.entries[k].profile.name.clone();
    live.tracker_port = "/dev/ttyUSB7".into();
    let mut doc = plane_doc();
    let anchor = ViewAnchor {
        point: DVec3::ZERO,
        normal: DVec3::Z,
        extent: 10.0,
    };
    live.fit_hand(&mut doc, &anchor);
    let copy = dir.join(format!("{name}-mine.json"));
    let saved = Profile::load(&copy).expect("the user copy");
    let hand = alignment::hand_length(&saved.hand);
    assert!((saved.world_from_tracker.scale * hand - 4.0).abs() < 1e-9);
    assert_eq!(saved.tracker().map(|t| t.port()), Some("/dev/ttyUSB7"));
    assert_eq!(live.entries[k].profile.world_from_tracker.scale, 1.0);
    assert_eq!(
        live.entries[live.selected].source,
        ProfileSource::File(copy.clone())
    );
    live.set_scale(&mut doc, 5.0);
    assert_eq!(
        Profile::load(&copy)
            .expect("the same copy")
            .world_from_tracker
            .scale,
        5.0
    );
    // Listed again from the folder after a rescan, and remembered by path.
    let mut settings = Settings::default();
    live.store_settings(&mut settings);
    let mut again = LiveInput::with_profile_dir(Some(dir.clone()));
    again.apply_settings(&settings);
    assert_eq!(
        again.entries[again.selected].key(),
        copy.display().to_string()
    );
    assert_eq!(again.tracker_port, "/dev/ttyUSB7");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Ports are remembered per profile, and a restart (settings applied) keeps every
/// profile's, not only the selected one's.
#[test]
fn ports_are_remembered_per_profile() {
    let mut live = listed();
    let k = glove_and_tracker(&live);
    assert!(live.entries[0].profile.glove().is_some() && k != 0);
    live.select(0);
    live.glove_port = "/dev/ttyA".into();
    live.select(k);
    live.tracker_port = "/dev/ttyB".into();
    let mut settings = Settings::default();
    live.store_settings(&mut settings);
    let mut again = listed();
    again.apply_settings(&settings);
    assert_eq!(again.selected, k);
    assert_eq!(again.tracker_port, "/dev/ttyB");
    again.select(0);
    assert_eq!(again.glove_port, "/dev/ttyA");
}

/// The follow-the-hand radius: the library's default for a hand fitted to the 10-side
/// plane, proportional to the hand's world size; a set radius wins; a replay reads with
/// the default, as `nendo replay`.
#[test]
fn the_finger_radius_follows_the_hand_unless_set() {
    let mut p = profile::resolve("cyberglove2-18-fastrak").expect("shipped");
    p.world_from_tracker.scale = alignment::fit_scale(&p.hand, 10.0).expect("fits");
    let mut live = LiveInput::default();
    assert!((live.radius(&p, false) - DEFAULT_FINGER_RADIUS).abs() < 1e-12);
    p.world_from_tracker.scale *= 0.5;
    assert!((live.radius(&p, false) - 0.5 * DEFAULT_FINGER_RADIUS).abs() < 1e-12);
    assert_eq!(live.radius(&p, true), DEFAULT_FINGER_RADIUS);
    live.radius_set = Some(0.3);
    assert_eq!(live.radius(&p, false), 0.3);
    assert_eq!(live.radius(&p, true), 0.3);
}
