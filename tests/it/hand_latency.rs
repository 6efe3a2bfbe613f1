//! The hand's latency record through the headless editor (no GPU): a replayed trace as a
//! device session, frames marked as the window marks them, with delays injected through the
//! instants handed to the editor (nothing timed): every sample is counted once, its stages add
//! up to its CPU side, the arrivals come in channel order, the figure moves by exactly what was
//! injected — and the display the hand left is the full rebuild's.

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use nendo::editor::display_cache::DisplayCache;
use nendo::editor::live::{DeviceWaker, LatencyMeter};
use nendo::editor::{Document, Modeller};
use nendo::model::Model;
use nendo::surface::{Primitive, PrimitiveParams};
use nendo_devices::Trace;

/// What the test adds to each frame's submission, and to its presentation after that.
const SUBMIT_LATE: Duration = Duration::from_millis(50);
const PRESENT_LATE: Duration = Duration::from_millis(30);

#[test]
fn every_replayed_sample_is_timed_to_its_frame_stage_by_stage() {
    let trace_path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("devices/traces/plane-groove.trace");
    let sent = Trace::read(&trace_path)
        .expect("the shipped trace")
        .frames
        .len() as u64;
    let dir = std::env::temp_dir().join(format!("nendo-it-latency-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let profile = dir.join("replay.json");
    let json = serde_json::json!({
        "format": "nendo-device-profile",
        "version": 1,
        "name": "groove-replay",
        "input": {"replay": {"trace": trace_path, "speed": 20.0}},
    });
    std::fs::write(&profile, json.to_string()).expect("profile written");

    let plane = Primitive::Plane
        .build(&PrimitiveParams::default())
        .expect("plane");
    let mut modeller = Modeller::new(Document::new(Model::new(plane)), None, false);
    let wakes = Arc::new(AtomicU64::new(0));
    let counter = Arc::clone(&wakes);
    modeller.set_device_waker(DeviceWaker(Arc::new(move || {
        counter.fetch_add(1, Ordering::Relaxed);
    })));
    modeller
        .connect_profile(&profile.display().to_string())
        .expect("the replay profile");
    assert!(modeller.devices_mut().0.is_connected());
    // Every sample kept (the window keeps the latest 240).
    *modeller.devices_mut().0.latency_mut() = LatencyMeter::with_window(usize::MAX);

    // (first sample's index, the frame's submission) per frame that showed samples.
    let mut frames: Vec<(usize, Instant)> = Vec::new();
    let mut frame = |modeller: &mut Modeller| {
        let before = modeller.devices_mut().0.latency().total() as usize;
        modeller.tick(Instant::now());
        modeller.refresh();
        let submitted = Instant::now() + SUBMIT_LATE;
        modeller.frame_submitted(submitted);
        modeller.frame_presented(submitted + PRESENT_LATE);
        let after = modeller.devices_mut().0.latency().total() as usize;
        if after > before {
            frames.push((before, submitted));
        }
    };
    let deadline = Instant::now() + Duration::from_secs(120);
    let mut figure = None;
    while modeller.devices_mut().0.is_connected() && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(5));
        frame(&mut modeller);
        figure = modeller.hand_latency().or(figure);
    }
    assert!(!modeller.devices_mut().0.is_connected(), "the replay ended");
    // The samples of the frame that found the stream ended are shown by it too.
    let latency = modeller.devices_mut().0.latency().clone();
    assert_eq!(latency.pending(), 0);
    assert_eq!(latency.total(), sent, "every sample timed once");
    assert!(
        wakes.load(Ordering::Relaxed) > 0,
        "the loop thread woke the window"
    );

    // The figure: every CPU side at least the injected lateness, the
    // presentation exactly its own.
    let figure = figure.expect("a figure while the session ran");
    assert!(figure.cpu.median >= SUBMIT_LATE && figure.cpu.p95 >= figure.cpu.median);
    let shown = figure.presented.expect("presented frames");
    assert_eq!(shown.median, figure.cpu.median + PRESENT_LATE);
    assert_eq!(shown.p95, figure.cpu.p95 + PRESENT_LATE);

    // Sample by sample: the stages add up to submission − read, the
    // arrivals in channel order.
    let samples: Vec<_> = latency.shown().copied().collect();
    assert_eq!(samples.len() as u64, sent);
    let mut changed = 0;
    for (i, s) in samples.iter().enumerate() {
        let k = i;
        let submitted = frames
            .iter()
            .rev()
            .find(|(start, _)| *start <= k)
            .map(|(_, t)| *t)
            .expect("its frame");
        assert_eq!(s.stages.all().iter().sum::<Duration>(), s.cpu());
        assert_eq!(s.read + s.cpu(), submitted, "sample {k}");
        assert_eq!(s.present, Some(PRESENT_LATE));
        assert!(s.stages.render >= SUBMIT_LATE);
        changed += usize::from(s.changed);
    }
    assert!(
        samples
            .windows(2)
            .all(|w| w[0].read + w[0].stages.parse <= w[1].read + w[1].stages.parse)
    );
    assert!(changed > 0, "the groove changed the surface while timed");

    // The hand's frames re-tessellated only the patches it changed: the display is the full
    // rebuild's.
    let mut fresh = DisplayCache::default();
    fresh.refresh(modeller.document(), false);
    assert_eq!(modeller.surface().mesh, fresh.display().mesh);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The window's latch (`Modeller::latch_devices`): without a session it returns at once
/// saying nothing came; while a replay streams, it returns when a sample newer than the inbox
/// came, which the frame's refresh then takes — and that frame's newest sample is the latest
/// port read it shows, counted once in the newest figure.
#[test]
fn the_latch_takes_a_fresh_sample_into_the_frame() {
    let trace_path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("devices/traces/plane-groove.trace");
    let dir = std::env::temp_dir().join(format!("nendo-it-latch-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let profile = dir.join("replay.json");
    let json = serde_json::json!({
        "format": "nendo-device-profile",
        "version": 1,
        "name": "groove-latch",
        "input": {"replay": {"trace": trace_path, "speed": 4.0}},
    });
    std::fs::write(&profile, json.to_string()).expect("profile written");
    let plane = Primitive::Plane
        .build(&PrimitiveParams::default())
        .expect("plane");
    let mut modeller = Modeller::new(Document::new(Model::new(plane)), None, false);
    // Hang guard only: without a session the latch must not wait its bound.
    assert!(!modeller.latch_devices(Duration::from_secs(600)));
    modeller
        .connect_profile(&profile.display().to_string())
        .expect("the replay profile");
    *modeller.devices_mut().0.latency_mut() = LatencyMeter::with_window(usize::MAX);

    let (mut latched, mut frames) = (0, 0);
    let deadline = Instant::now() + Duration::from_secs(120);
    while modeller.devices_mut().0.is_connected() && Instant::now() < deadline {
        // What came before the latch: taken and submitted as a frame of its own.
        modeller.tick(Instant::now());
        modeller.refresh();
        modeller.frame_submitted(Instant::now());
        let before = modeller.devices_mut().0.latency().total();
        // Hang guard only: a streaming replay sends a sample well within the bound.
        let came = modeller.latch_devices(Duration::from_secs(10));
        modeller.refresh();
        let taken = modeller.devices_mut().0.latency().pending();
        modeller.frame_submitted(Instant::now());
        let latency = modeller.devices_mut().0.latency();
        let shown: Vec<_> = latency.shown().skip(before as usize).copied().collect();
        assert_eq!(shown.len(), taken);
        if came {
            latched += 1;
            assert!(
                taken >= 1,
                "a latched sample is taken by the refresh after it"
            );
        }
        if !shown.is_empty() {
            frames += 1;
            let newest: Vec<_> = shown.iter().filter(|s| s.newest).collect();
            assert_eq!(newest.len(), 1, "one newest sample per frame");
            assert!(shown.iter().all(|s| s.read <= newest[0].read));
        }
    }
    assert!(!modeller.devices_mut().0.is_connected(), "the replay ended");
    assert!(
        latched > 0 && frames >= latched,
        "{latched} latched of {frames}"
    );
    // Once the session is over, the latch does not wait (hang guard only).
    assert!(!modeller.latch_devices(Duration::from_secs(600)));
    let _ = std::fs::remove_dir_all(&dir);
}
