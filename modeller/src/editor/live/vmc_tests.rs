//! A VMC session in the window without a window: the listening address typed in the Devices
//! panel's field is the one the receiver binds on connect, and the session — skeleton frames
//! through the hand loop's gate and filter, a one-bundle glitch included — recorded by the
//! window replays with `nendo replay` to the window's surface bit for bit.

use std::time::{Duration, Instant};

use glam::{DQuat, DVec3};
use nendo_devices::profile::{self, Side};
use nendo_devices::vmc::VmcState;
use nendo_devices::vmc::send::{bundle, straight_arms};
use nendo_devices::{HandSize, Trace};

use super::profiles::ProfileEntry;
use super::*;
use crate::editor::document::Document;
use crate::hand::{Digit, Hand};

fn plane_doc() -> Document {
    use crate::model::Model;
    use crate::surface::{Primitive, PrimitiveParams};
    Document::new(Model::new(
        Primitive::Plane
            .build(&PrimitiveParams::default())
            .expect("plane"),
    ))
}

/// The bundles of a press: the right hand, index down, its tip from 1 side above the plane
/// at (1, 0.5) to 0.3 into it and back, at 60 Hz; bundle 10 (hovering 0.5 side above) has
/// the whole hand 6 cm low, a glitch the gate must hold in the window and in the replay.
fn press_bundles(world: nendo_devices::WorldFromTracker) -> Vec<Vec<u8>> {
    let side = Side::Right;
    let size = HandSize {
        side,
        ..HandSize::default()
    };
    let hand = Hand::new(size, world).expect("hand");
    let bones = straight_arms(side, DQuat::from_rotation_z(-std::f64::consts::FRAC_PI_2));
    let mut state = VmcState::new(size);
    let at_origin = state
        .packet(&bundle((DVec3::ZERO, DQuat::IDENTITY), &bones, 0.0).expect("bundle"))
        .expect("a hand");
    let tip0 = hand
        .skeleton_pose(&at_origin)
        .expect("placed")
        .finger(Digit::Index)
        .tip();
    let mut depths: Vec<f64> = (0..=26).map(|k| 1.0 - 0.05 * f64::from(k)).collect();
    depths.extend(std::iter::repeat_n(-0.3, 10));
    depths.extend((0..=26).rev().map(|k| 1.0 - 0.05 * f64::from(k)));
    depths
        .iter()
        .enumerate()
        .map(|(k, depth)| {
            let d = (DVec3::new(1.0, 0.5, *depth) - tip0) / world.scale;
            let mut root = DVec3::new(d.x, d.z, d.y);
            if k == 10 {
                root.y -= 0.06;
            }
            bundle((root, DQuat::IDENTITY), &bones, k as f32).expect("bundle")
        })
        .collect()
}

#[test]
fn a_vmc_session_listens_where_the_panel_says_and_replays_bit_for_bit() {
    let dir = std::env::temp_dir().join(format!("nendo-live-vmc-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let profile = profile::resolve("vmc").expect("shipped");
    let bundles = press_bundles(profile.world_from_tracker);
    let port = std::net::UdpSocket::bind("127.0.0.1:0")
        .and_then(|s| s.local_addr())
        .expect("a free port")
        .port();
    let trace_path = dir.join("window.trace");
    let mut live = LiveInput {
        entries: vec![ProfileEntry {
            profile,
            source: super::profiles::ProfileSource::Builtin,
        }],
        selected: 0,
        record: true,
        record_to: trace_path.display().to_string(),
        ..LiveInput::default()
    };
    live.show_entry(0);
    assert_eq!(
        live.tracker_port, "127.0.0.1:39539",
        "the profile's own address"
    );
    // A bad address is refused with a message, before anything is opened.
    live.tracker_port = "localhost:99999".into();
    assert!(live.listen_error().is_some());
    let mut doc = plane_doc();
    live.connect(&mut doc);
    assert!(!live.is_connected());
    assert!(
        live.message
            .as_deref()
            .is_some_and(|m| m.contains("ADDR:PORT")),
        "{:?}",
        live.message
    );
    // The address typed is the one bound, and is remembered in the settings.
    live.tracker_port = format!("127.0.0.1:{port}");
    assert_eq!(live.listen_error(), None);
    let mut settings = crate::editor::settings::Settings::default();
    live.store_settings(&mut settings);
    assert_eq!(
        settings.ports.get("vmc").and_then(|p| p.tracker.clone()),
        Some(format!("127.0.0.1:{port}"))
    );
    let start = doc.model().clone();
    live.connect(&mut doc);
    assert!(live.is_connected(), "{:?}", live.message);
    let sender = std::thread::spawn(move || {
        let tx = std::net::UdpSocket::bind("127.0.0.1:0").expect("sender");
        let to = format!("127.0.0.1:{port}");
        // A few hovering bundles first, so the receiver is surely reading.
        let begun = Instant::now();
        for (k, b) in bundles.iter().enumerate() {
            let due = Duration::from_secs_f64(k as f64 / 60.0);
            if let Some(wait) = due.checked_sub(begun.elapsed()) {
                std::thread::sleep(wait);
            }
            let _ = tx.send_to(b, &to);
        }
    });
    let begun = Instant::now();
    // The gesture lasts 1.1 s; the deadline only guards against a hang.
    while begun.elapsed() < Duration::from_millis(2500) {
        std::thread::sleep(Duration::from_millis(20));
        let _ = live.poll(&mut doc);
    }
    sender.join().expect("sender");
    let _ = live.poll(&mut doc);
    let held = live
        .driver
        .as_ref()
        .map(|d| d.hand_loop().filter().stats().skeleton_positions.total());
    live.disconnect_from(&mut doc);
    assert!(live.contacts >= 1, "the press reached the clay");
    assert_ne!(doc.model(), &start, "the hand pressed the document");
    let recorded = Trace::read(&trace_path).expect("the recording");
    assert_eq!(recorded.header.skeleton, Some(Side::Right));
    assert!(
        recorded
            .frames
            .iter()
            .filter(|f| f.skeleton.is_some())
            .count()
            >= 40
    );
    // The glitch is in the trace as it came (raw: its wrist 2 cm below the deepest press's),
    // and the window's gate held it.
    let mut wrists: Vec<f64> = recorded
        .frames
        .iter()
        .filter_map(|f| {
            f.skeleton
                .and_then(|s| s.get(nendo_devices::HandJoint::Wrist).copied())
        })
        .map(|w| w.position.z)
        .collect();
    wrists.sort_by(f64::total_cmp);
    eprintln!(
        "skeleton positions held in the window: {held:?}; {} hands recorded",
        wrists.len()
    );
    if wrists.len() > 1 && wrists[1] - wrists[0] > 0.015 {
        assert!(
            held.is_some_and(|n| n >= 1),
            "the glitch was not held: {held:?}"
        );
    }
    let out = dir.join("replayed.json");
    let replayed = super::tests::replay_with_defaults(trace_path, &out);
    let bits = |m: &crate::model::Model| -> Vec<[u64; 3]> {
        m.surface
            .nodes()
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect()
    };
    let window = doc.model();
    let (a, b) = (bits(&replayed), bits(window));
    assert_eq!(a.len(), b.len());
    let differing = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert_eq!(
        differing,
        0,
        "{differing} of {} control points differ",
        a.len()
    );
    assert_eq!(&replayed, window);
    let _ = std::fs::remove_dir_all(&dir);
}
