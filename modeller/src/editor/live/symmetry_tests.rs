//! Device sessions in the window and the symmetry group (the `symmetry` module): a glove
//! session follows the window's symmetry between contacts, a recording keeps the group it
//! started with and replays bit for bit, a replayed trace presses with its scene's group as
//! `nendo replay` does. The devices are the emulated CyberGlove and Fastrak pressing the plane
//! at x = y = 0.5 (off the mirror x = 0), so a one-sided press is far from symmetric.

use super::tests::{
    EmulatedPress, differing, plane_doc, poll_through_the_press, poll_to_end, replay_with_defaults,
};
use super::*;
use crate::editor::document::Document;
use crate::hand::scene::Scene;
use crate::surface::{Plane, Symmetry, SymmetrySpec, group_error};
use nendo_devices::Trace;

/// How far `doc`'s surface is from invariant under the mirror x = 0, with the node map of the
/// plane it started as (relative to the model's size).
fn asymmetry(doc: &Document) -> f64 {
    let plane = plane_doc();
    let mirror = Symmetry::of(&plane.model().surface, Plane::X).expect("the plane's mirror");
    group_error(&doc.model().surface, &mirror)
}

fn mirror_x() -> Option<SymmetrySpec> {
    Some(SymmetrySpec::mirror(Plane::X))
}

/// A glove session that does not record presses with the window's symmetry, taken up between
/// contacts: the press is symmetric about x = 0 although the window's symmetry is turned off
/// while it presses (a contact keeps the group it began with), and once the hand has left the
/// clay the session has taken up "off".
#[test]
fn a_glove_session_presses_with_the_windows_symmetry() {
    let press = EmulatedPress::start();
    let mut live = press.live();
    live.set_window_symmetry(mirror_x());
    let mut doc = plane_doc();
    live.connect(&mut doc);
    assert!(live.is_connected(), "{:?}", live.message);
    assert_eq!(live.symmetry_note(), None, "the session follows the window");
    let mut turned_off_in_contact = false;
    poll_through_the_press(&mut live, &mut doc, |live| {
        if live.in_contact() && !turned_off_in_contact {
            live.set_window_symmetry(None);
            turned_off_in_contact = true;
        }
    });
    assert!(
        turned_off_in_contact && live.contacts >= 1,
        "the press reached the clay"
    );
    let mirrored_after = live
        .driver
        .as_ref()
        .and_then(|d| d.hand_loop().mirror().map(|s| s.spec().clone()));
    live.disconnect_from(&mut doc);
    let worst = asymmetry(&doc);
    println!("glove session with the window's mirror x: worst asymmetry {worst:e} (relative)");
    assert!(worst <= 1e-12, "worst asymmetry {worst:e}");
    assert_eq!(mirrored_after, None, "taken up between contacts: off");
}

/// The control: with the window's symmetry off the same press is one-sided — the figure the
/// test above measures is far from 0 when the mirror is not used.
#[test]
fn without_the_windows_symmetry_a_glove_session_presses_one_side() {
    let press = EmulatedPress::start();
    let mut live = press.live();
    live.set_window_symmetry(None);
    let mut doc = plane_doc();
    live.connect(&mut doc);
    assert!(live.is_connected(), "{:?}", live.message);
    poll_through_the_press(&mut live, &mut doc, |_| {});
    live.disconnect_from(&mut doc);
    assert!(live.contacts >= 1);
    let worst = asymmetry(&doc);
    println!("glove session without symmetry: asymmetry {worst:e} (relative)");
    assert!(worst > 1e-3, "one-sided: {worst:e}");
}

/// A recording glove session presses with the window's symmetry at Connect until it stops,
/// whatever the toggle says meanwhile (here turned off at once), says so, names the group in
/// its trace's scene, and `nendo replay` of the trace alone gives the window's surface bit for
/// bit (0 control points differ).
#[test]
fn a_mirrored_glove_recording_replays_bit_for_bit() {
    let dir = std::env::temp_dir().join(format!("nendo-live-sym-rec-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let press = EmulatedPress::start();
    let trace_path = dir.join("mirrored.trace");
    let mut live = LiveInput {
        record: true,
        record_to: trace_path.display().to_string(),
        ..press.live()
    };
    live.set_window_symmetry(mirror_x());
    let mut doc = plane_doc();
    live.connect(&mut doc);
    assert!(live.is_connected(), "{:?}", live.message);
    live.set_window_symmetry(None);
    let note = live.symmetry_note().unwrap_or_default();
    assert!(
        note.contains("mirror x = 0") && note.contains("until it stops"),
        "{note}"
    );
    let line = live.session_line().unwrap_or_default();
    assert!(line.ends_with(&note), "the Devices panel says so: {line}");
    poll_through_the_press(&mut live, &mut doc, |_| {});
    live.disconnect_from(&mut doc);
    assert!(live.contacts >= 1, "the press reached the clay");
    assert_eq!(live.symmetry_note(), None, "the recording stopped");
    let worst = asymmetry(&doc);
    println!("recorded glove session, mirror x: worst asymmetry {worst:e} (relative)");
    assert!(worst <= 1e-12, "worst asymmetry {worst:e}");
    let recorded = Trace::read(&trace_path).expect("the recording");
    let scene = Scene::of_trace(&recorded.header)
        .expect("a valid scene")
        .expect("a scene");
    assert_eq!(scene.mirror, vec![Plane::X]);
    assert_eq!((scene.radial, scene.lathe), (None, false));
    let replayed = replay_with_defaults(trace_path, &dir.join("replayed.json"));
    let (differ, by) = differing(&replayed, doc.model());
    println!("nendo replay of the window's mirrored recording: {differ} control points differ");
    assert_eq!(differ, 0, "{differ} control points differ, by up to {by:e}");
    assert_eq!(&replayed, doc.model());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `nendo` with these arguments, run in this process.
#[derive(clap::Parser)]
struct Line {
    #[command(subcommand)]
    command: crate::cli::Subcommand,
}

/// A trace recorded by `nendo record --primitive plane --mirror x` (the shipped groove trace
/// replayed as the device) played in the window — whose symmetry is another (mirror y) — presses
/// with the scene's mirror x and equals `nendo replay` of it bit for bit; on a model without
/// that symmetry the window refuses it, as `nendo replay` does.
#[test]
fn a_trace_recorded_with_a_mirror_plays_in_the_window_as_nendo_replay() {
    use clap::Parser;
    let dir = std::env::temp_dir().join(format!("nendo-live-sym-play-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let source = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../devices/traces/plane-groove.trace");
    let profile_path = dir.join("replay.json");
    let json = serde_json::json!({
        "format": "nendo-device-profile",
        "version": 1,
        "name": "groove-replay",
        "input": {"replay": {"trace": source, "speed": 40.0}},
    });
    std::fs::write(&profile_path, json.to_string()).expect("profile written");
    let trace = dir.join("mirrored.trace");
    let (p, t) = (
        profile_path.display().to_string(),
        trace.display().to_string(),
    );
    let line = Line::try_parse_from([
        "nendo",
        "record",
        "--seconds",
        "60",
        "--profile",
        &p,
        "--primitive",
        "plane",
        "--mirror",
        "x",
        "--out",
        &t,
    ])
    .expect("the command line");
    let _ = line.command.run();
    let header = Trace::read(&trace).expect("the recording").header;
    let scene = Scene::of_trace(&header).expect("valid").expect("a scene");
    assert_eq!(scene.mirror, vec![Plane::X]);

    // The window on the scene's start, its own symmetry mirror y.
    let mut start = scene.start_model(&dir).expect("the start model");
    if let Some(r) = scene.regulation {
        start.regulation = r;
    }
    let mut doc = Document::new(start.clone());
    let mut live = LiveInput::default();
    live.set_window_symmetry(Some(SymmetrySpec::mirror(Plane::Y)));
    live.replay(&trace, &mut doc);
    assert!(live.is_connected(), "{:?}", live.message);
    let note = live.symmetry_note().unwrap_or_default();
    assert!(note.contains("its scene's mirror x = 0"), "{note}");
    poll_to_end(&mut live, &mut doc);
    assert_eq!(live.message.as_deref(), Some("the stream ended"));
    assert_ne!(
        doc.model().surface,
        start.surface,
        "the groove pressed the plane"
    );
    let worst = asymmetry(&doc);
    println!("a --mirror x trace played in the window: worst asymmetry {worst:e} (relative)");
    assert!(worst <= 1e-12, "worst asymmetry {worst:e}");
    let replayed = replay_with_defaults(trace.clone(), &dir.join("replayed.json"));
    let (differ, by) = differing(&replayed, doc.model());
    println!("the window's play of it against nendo replay: {differ} control points differ");
    assert_eq!(differ, 0, "{differ} control points differ, by up to {by:e}");

    // A start without the mirror: refused at once, naming why.
    let mut bumped = start.clone();
    let k = bumped
        .surface
        .nodes()
        .iter()
        .position(|p| p.x > 0.5 && p.y > 0.5)
        .expect("a node off the plane x = 0");
    let p = bumped.surface.nodes()[k];
    bumped
        .surface
        .set_nodes(&[(k, p + glam::DVec3::new(0.0, 0.0, 0.4))])
        .expect("moved");
    let mut doc = Document::new(bumped.clone());
    live.replay(&trace, &mut doc);
    assert!(!live.is_connected());
    let message = live.message.clone().unwrap_or_default();
    assert!(
        message.contains("cannot replay") && message.contains("does not have"),
        "{message}"
    );
    assert_eq!(doc.model(), &bumped, "the model untouched");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Through the modeller, as the window runs it: its symmetry (on by default for the plane:
/// mirror x) reaches the glove session it connects, whose press leaves the model symmetric.
#[test]
fn the_windows_default_symmetry_reaches_a_connected_glove_session() {
    use crate::editor::Modeller;
    let dir = std::env::temp_dir().join(format!("nendo-live-sym-window-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let press = EmulatedPress::start();
    let shipped = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../devices/profiles/cyberglove2-18-fastrak.json");
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(shipped).expect("shipped profile"))
            .expect("json");
    json["name"] = "symmetry-check".into();
    json["input"]["devices"]["glove"]["port"] = press.glove.port().into();
    json["input"]["devices"]["tracker"]["port"] = press.tracker.port().into();
    json["world_from_tracker"]["translation"] = serde_json::json!([0.0, 0.0, 0.0]);
    json["world_from_tracker"]["scale"] = 21.5.into();
    let profile = dir.join("glove.json");
    std::fs::write(&profile, json.to_string()).expect("profile written");
    let mut m = Modeller::new(plane_doc(), None, false);
    m.refresh();
    let start = m.document().model().clone();
    m.connect_profile(&profile.display().to_string())
        .expect("the profile");
    let begun = Instant::now();
    while begun.elapsed() < Duration::from_millis(4500) {
        std::thread::sleep(Duration::from_millis(20));
        m.tick(Instant::now());
    }
    let (live, doc) = m.devices_mut();
    live.disconnect_from(doc);
    assert_ne!(doc.model(), &start, "the press reached the clay");
    let worst = asymmetry(doc);
    println!("the window's glove session, default symmetry: worst asymmetry {worst:e} (relative)");
    assert!(worst <= 1e-12, "worst asymmetry {worst:e}");
    let _ = std::fs::remove_dir_all(&dir);
}
