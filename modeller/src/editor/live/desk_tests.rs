//! The desk's aids without a window: the hand fitted on a profile's first connect and kept,
//! the pressing parts chosen and remembered, the clutch key in a window recording, and the
//! contact feedback while a trace presses.

use super::profiles::*;
use super::*;
use crate::editor::document::Document;
use crate::editor::settings::Settings;
use crate::hand::{Digit, Fingers, Part};
use nendo_devices::profile::{self, Input};
use nendo_devices::{Profile, Trace, buttons};

fn plane_doc() -> Document {
    use crate::model::Model;
    use crate::surface::{Primitive, PrimitiveParams};
    Document::new(Model::new(
        Primitive::Plane
            .build(&PrimitiveParams::default())
            .expect("plane"),
    ))
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("nendo-desk-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// The shipped serial glove + tracker profile, selected, its ports absent (the stream retries
/// them: the session runs without devices).
fn glove_selected(live: &mut LiveInput) -> usize {
    let k = live
        .entries
        .iter()
        .position(|e| e.profile.name == "cyberglove2-18-fastrak")
        .expect("the shipped glove + tracker profile");
    live.select(k);
    live.glove_port = "/nonexistent/nendo-glove".into();
    live.tracker_port = "/nonexistent/nendo-tracker".into();
    k
}

const ANCHOR: ViewAnchor = ViewAnchor {
    point: DVec3::ZERO,
    normal: DVec3::Z,
    extent: 10.0,
};

/// The first connect of the shipped glove profile fits the hand to the model (4 sides long
/// on the 10-side plane: 0.4 of it) into a user copy, selected; the next connect keeps the
/// profile's scale — also one set by hand since; after a restart (settings applied) the
/// profile is still known as fitted.
#[test]
fn the_first_connect_fits_the_hand_and_the_next_ones_keep_the_profile() {
    let dir = temp("fit");
    let mut live = LiveInput::with_profile_dir(Some(dir.clone()));
    let k = glove_selected(&mut live);
    let shipped_key = live.entries[k].key();
    assert!(!live.is_fitted(&shipped_key));
    let mut doc = plane_doc();
    live.set_view_anchor(ANCHOR);
    live.connect(&mut doc);
    assert!(live.is_connected(), "{:?}", live.message);
    let copy = dir.join("cyberglove2-18-fastrak-mine.json");
    let saved = Profile::load(&copy).expect("the fit saved into a user copy");
    let length = alignment::hand_length(&saved.hand);
    let scale = saved.world_from_tracker.scale;
    println!(
        "first connect: {scale:.3} sides per metre, the hand {:.3} sides; {:?}",
        scale * length,
        live.message
    );
    assert!((scale * length - 4.0).abs() < 1e-9, "{scale}");
    assert_eq!(
        live.running_devices().map(|p| p.world_from_tracker.scale),
        Some(scale),
        "the session runs the fitted hand"
    );
    assert!(
        live.message
            .as_deref()
            .is_some_and(|m| m.contains("fitted")),
        "{:?}",
        live.message
    );
    let copy_key = copy.display().to_string();
    assert_eq!(live.entries[live.selected].key(), copy_key);
    assert!(live.is_fitted(&shipped_key) && live.is_fitted(&copy_key));
    live.disconnect_from(&mut doc);

    // A scale set by hand is kept at the next connect, even on a bigger model.
    live.set_scale(&mut doc, 7.5);
    live.set_view_anchor(ViewAnchor {
        extent: 40.0,
        ..ANCHOR
    });
    live.connect(&mut doc);
    assert_eq!(
        live.running_devices().map(|p| p.world_from_tracker.scale),
        Some(7.5)
    );
    live.disconnect_from(&mut doc);

    let mut settings = Settings::default();
    live.store_settings(&mut settings);
    assert!(settings.fitted.contains(&shipped_key), "{settings:?}");
    let mut again = LiveInput::with_profile_dir(Some(dir.clone()));
    again.apply_settings(&settings);
    assert!(again.is_fitted(&copy_key) && again.is_fitted(&shipped_key));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Without a view anchor (no window yet) or for a replay profile nothing is fitted; a
/// profile fitted by hand ("Fit the hand to the model") is not fitted again on connect.
#[test]
fn only_an_unfitted_glove_profile_is_fitted_on_connect() {
    let mut live = LiveInput::default();
    live.rescan();
    let k = glove_selected(&mut live);
    let mut doc = plane_doc();
    live.connect(&mut doc);
    assert_eq!(
        live.running_devices().map(|p| p.world_from_tracker.scale),
        Some(1.0),
        "no anchor: the shipped scale"
    );
    live.disconnect_from(&mut doc);
    live.fit_hand(&mut doc, &ANCHOR);
    live.set_scale(&mut doc, 3.0);
    live.set_view_anchor(ANCHOR);
    live.connect(&mut doc);
    assert_eq!(
        live.running_devices().map(|p| p.world_from_tracker.scale),
        Some(3.0),
        "fitted by hand before: kept"
    );
    assert!(live.is_fitted(&live.entries[k].key()));
    live.disconnect_from(&mut doc);
}

/// The pressing parts: every finger by default; chosen by name in the panel, remembered in
/// the settings (as `--finger` writes them), used by the device hand, and never empty.
#[test]
fn the_pressing_parts_are_chosen_remembered_and_used() {
    let mut live = LiveInput::default();
    live.rescan();
    glove_selected(&mut live);
    let mut doc = plane_doc();
    assert_eq!(live.pressing(), Fingers::ALL);
    let names: Vec<&str> = Part::ALL.iter().map(|p| p.name()).collect();
    assert_eq!(
        names,
        ["thumb", "index", "middle", "ring", "pinky", "palm"],
        "the names the panel shows"
    );
    // Take the thumb, ring and little finger out, add the palm.
    for part in [
        Part::Digit(Digit::Thumb),
        Part::Digit(Digit::Ring),
        Part::Digit(Digit::Pinky),
        Part::Palm,
    ] {
        live.toggle_pressing(&mut doc, part);
    }
    let chosen: Fingers = "index,middle,palm".parse().expect("parts");
    assert_eq!(live.pressing(), chosen);
    live.connect(&mut doc);
    let finger = live.driver.as_ref().map(|d| d.hand_loop().options().finger);
    assert_eq!(finger, Some(FingerModel::Hand(chosen)));
    // Changed while connected: the running hand takes it.
    live.toggle_pressing(&mut doc, Part::Palm);
    let finger = live.driver.as_ref().map(|d| d.hand_loop().options().finger);
    assert_eq!(
        finger,
        Some(FingerModel::Hand("index,middle".parse().expect("parts")))
    );
    live.disconnect_from(&mut doc);
    // Never none.
    live.toggle_pressing(&mut doc, Part::Digit(Digit::Middle));
    live.toggle_pressing(&mut doc, Part::Digit(Digit::Index));
    assert_eq!(live.pressing(), Fingers::one(Part::Digit(Digit::Index)));
    assert!(
        live.message
            .as_deref()
            .is_some_and(|m| m.contains("at least one"))
    );
    let mut settings = Settings::default();
    live.store_settings(&mut settings);
    assert_eq!(settings.pressing.as_deref(), Some("index"));
    let mut again = LiveInput::default();
    again.rescan();
    again.apply_settings(&settings);
    assert_eq!(again.pressing(), Fingers::one(Part::Digit(Digit::Index)));
    // A file naming no part is read as the default, with a message.
    settings.pressing = Some("elbow".into());
    let mut odd = LiveInput::default();
    odd.apply_settings(&settings);
    assert_eq!(odd.pressing(), Fingers::ALL);
    assert!(odd.message.is_some());
    // The mouse stays the view ray.
    let mouse = profile::builtin()
        .into_iter()
        .find(|p| matches!(p.input, Input::Mouse(_)))
        .expect("the mouse profile");
    assert_eq!(live.finger_for(&mouse), FingerModel::Ray);
}

/// A replay profile of the shipped groove, played fast, recorded to `record`.
fn groove_replay(dir: &Path, record: Option<&Path>) -> LiveInput {
    std::fs::create_dir_all(dir).expect("temp dir");
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../devices/traces/plane-groove.trace");
    let profile_path = dir.join("replay.json");
    let json = serde_json::json!({
        "format": "nendo-device-profile",
        "version": 1,
        "name": "groove-replay",
        "input": {"replay": {"trace": source, "speed": 40.0}},
    });
    std::fs::write(&profile_path, json.to_string()).expect("profile written");
    let profile = profile::resolve(&profile_path.display().to_string()).expect("replay profile");
    LiveInput {
        entries: vec![ProfileEntry {
            profile,
            source: ProfileSource::File(profile_path),
        }],
        selected: 0,
        record: record.is_some(),
        record_to: record.map(|p| p.display().to_string()).unwrap_or_default(),
        ..LiveInput::default()
    }
}

/// Polls until the session ends (a 60 s hang guard), calling `each` after every poll.
fn play(live: &mut LiveInput, doc: &mut Document, mut each: impl FnMut(&LiveInput)) {
    let deadline = Instant::now() + Duration::from_secs(60);
    while live.is_connected() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(5));
        let _ = live.poll(doc);
        each(live);
    }
    assert!(!live.is_connected(), "the replay ended");
}

/// The clutch key held through a whole session: the hand is drawn and moves, the clay is
/// untouched, the recording carries the clutch on every frame, and `nendo replay` of it
/// leaves the plane untouched too (no contact).
#[test]
fn the_clutch_key_held_moves_the_hand_without_touching_and_is_recorded() {
    let dir = temp("clutch");
    let trace_path = dir.join("clutched.trace");
    let mut live = groove_replay(&dir, Some(&trace_path));
    let mut doc = plane_doc();
    let start = doc.model().clone();
    live.set_clutch(true);
    live.connect(&mut doc);
    assert!(live.is_connected(), "{:?}", live.message);
    let mut drawn = false;
    let mut clutched = false;
    play(&mut live, &mut doc, |l| {
        drawn |= l
            .driver
            .as_ref()
            .is_some_and(|d| d.hand_loop().pose().is_some());
        clutched |= l.clutched();
    });
    assert!(drawn && clutched);
    assert_eq!(doc.model(), &start, "the clay untouched");
    assert_eq!(live.contacts, 0);
    let recorded = Trace::read(&trace_path).expect("the recording");
    assert!(!recorded.frames.is_empty());
    assert!(
        recorded
            .frames
            .iter()
            .all(|f| f.buttons & buttons::CLUTCH != 0),
        "every frame carries the clutch"
    );
    let out = dir.join("replayed.json");
    let o = crate::cli::replay::replay(&crate::cli::replay::ReplayArgs {
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
        mirror: Vec::new(),
        turns: crate::cli::symmetry_args::TurnArgs::default(),
        no_filter: false,
        out: out.clone(),
    })
    .expect("replayed");
    assert!(
        o.contains(": 0 contacts") && o.contains("frames clutched"),
        "{o}"
    );
    let replayed = crate::model::Model::read(&out).expect("the replay").model;
    assert_eq!(&replayed, doc.model());
    let _ = std::fs::remove_dir_all(&dir);
}

/// While the groove is pressed the feedback shows the touched region (the patches the clay
/// moved in, outlined) and how deep: the clay moved 0.3 where the index went 0.3 in; once
/// the finger leaves, no feedback.
#[test]
fn contact_feedback_shows_the_region_and_the_depth_while_pressed() {
    let dir = temp("feedback");
    let mut live = groove_replay(&dir, None);
    let mut doc = plane_doc();
    live.connect(&mut doc);
    let mut most = (0.0f64, 0.0f64, 0usize, None);
    let mut drawn = 0;
    play(&mut live, &mut doc, |l| {
        if let Some(f) = l.feedback() {
            let moved = f.moved().map_or(0.0, |m| m.0);
            let h = f.deepest.map_or(0.0, |d| d.1);
            if moved > most.0 {
                most = (moved, h, f.region().len(), f.deepest.map(|d| d.0));
                let mut lines = crate::render::LineBatch::new();
                let mut spheres = Vec::new();
                l.draw(&mut lines, &mut spheres);
                drawn = lines.len();
            }
            assert!(f.describe().contains("clay moved"));
        }
    });
    let (moved, h, region, part) = most;
    println!(
        "groove feedback: clay moved {moved:.3}, index {h:.3} in, {region} patches, {drawn} lines"
    );
    assert!((moved - 0.3).abs() < 0.03, "{moved}");
    assert!((h - 0.3).abs() < 0.03, "{h}");
    assert_eq!(part, Some(Part::Digit(Digit::Index)));
    assert!((1..100).contains(&region), "{region}");
    assert!(drawn > 0);
    assert!(live.feedback().is_none(), "the finger has left the clay");
    let _ = std::fs::remove_dir_all(&dir);
}
