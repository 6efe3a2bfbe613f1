//! The live device loop: a glove + tracker stream (or a recorded trace played back) read on
//! its own thread, so that a slow window frame never drops a device sample.
//!
//! `nendo_devices::HandStream` decodes each device on background threads into a bounded
//! channel; the loop here drains that channel continuously into an unbounded inbox (and, when
//! recording, into a trace file), and the window takes everything in the inbox once per frame.
//! However long a frame takes, every sample is kept, in order.
//!
//! The window then runs every frame, in order, through a [`HandDriver`] (the library's hand
//! loop: kinematic hand, fingertip contact, push / pull / draw-a-line on the document's
//! surface), and draws the hand. The geometry work happens on the window's thread, at frame
//! time, on all the frames received since the last one — so a slow frame delays the clay but
//! never loses a sample.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use nendo_devices::discover::{Inventory, inventory};
use nendo_devices::profile::{Input, MouseProfile};
use nendo_devices::{
    DeviceError, HandFrame, HandStream, Profile, SceneText, SourceState, StreamOptions, Trace,
    TraceWriter, profile,
};

use super::document::Document;
use super::hand_input::HandDriver;
use crate::hand::FingerModel;
use crate::hand::scene::Scene;
use crate::render::{LineBatch, SphereInstance};
use crate::surface::SurfaceError;

/// What the loop thread shares with the window.
#[derive(Debug, Default)]
struct Shared {
    inbox: Mutex<Vec<HandFrame>>,
    stop: AtomicBool,
    frames: AtomicU64,
    status: Mutex<LoopStatus>,
    /// The recording's outcome (frames written), once the loop has ended.
    recorded: Mutex<Option<Result<u64, DeviceError>>>,
}

/// Why a live session did not start.
#[derive(Debug, thiserror::Error)]
enum LiveError {
    /// The trace file to record to could not be created (the message names it).
    #[error("{0}")]
    Record(DeviceError),
    /// The loop thread could not be started.
    #[error("cannot start the input thread: {0}")]
    Spawn(std::io::Error),
}

#[derive(Debug, Clone, Default)]
struct LoopStatus {
    tracker: SourceState,
    glove: SourceState,
    last_error: Option<String>,
    finished: bool,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// A running device session.
#[derive(Debug)]
struct Session {
    describe: String,
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    started: Instant,
}

impl Session {
    /// Starts the loop on `stream`; with `record`, every frame also goes to a trace file whose
    /// header names `profile` (or, for a replay, is the replayed trace's own header) and the
    /// scene the session runs on (see [`crate::hand::scene::Scene::of_window`]).
    fn start(
        stream: HandStream,
        record: Option<(PathBuf, &Profile, Option<SceneText>)>,
    ) -> Result<Session, LiveError> {
        let describe = stream.describe();
        let shared = Arc::new(Shared::default());
        let mut writer = match record {
            Some((path, profile, scene)) => {
                // A replayed trace is recorded with its own header, not the replay profile's;
                // the scene is the window's.
                let mut header = stream.recording_header(profile);
                header.scene = scene;
                Some(TraceWriter::create(&path, header).map_err(LiveError::Record)?)
            }
            None => None,
        };
        let worker = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name("nendo live input".into())
            .spawn(move || {
                while !worker.stop.load(Ordering::Relaxed) {
                    // Read `finished` before draining: a stream sets it after its last frame,
                    // so the drain below still takes every frame sent before.
                    let finished = stream.finished();
                    let mut batch = Vec::new();
                    if let Some(first) = stream.next_timeout(Duration::from_millis(20)) {
                        batch.push(first);
                        batch.extend(stream.drain());
                    }
                    if let Some(w) = &mut writer {
                        for f in &batch {
                            if let Err(e) = w.push(f) {
                                lock(&worker.status).last_error = Some(format!("recording: {e}"));
                            }
                        }
                    }
                    worker
                        .frames
                        .fetch_add(batch.len() as u64, Ordering::Relaxed);
                    lock(&worker.inbox).extend(batch);
                    let (tracker, glove) = stream.states();
                    let mut status = lock(&worker.status);
                    status.tracker = tracker;
                    status.glove = glove;
                    if let Some(e) = stream.last_error() {
                        status.last_error = Some(e);
                    }
                    if finished {
                        status.finished = true;
                        break;
                    }
                }
                *lock(&worker.recorded) = writer.map(TraceWriter::finish);
                stream.close();
            })
            .map_err(LiveError::Spawn)?;
        Ok(Session {
            describe,
            shared,
            thread: Some(thread),
            started: Instant::now(),
        })
    }

    fn stop(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        self.stop();
    }
}

/// The device panel's state and the live session.
#[derive(Debug, Default)]
pub struct LiveInput {
    profiles: Vec<Profile>,
    selected: usize,
    inventory: Option<Inventory>,
    session: Option<Session>,
    /// The hand the session's frames drive.
    driver: Option<HandDriver>,
    /// Finger radius for the next session's hand.
    radius: f64,
    record_to: String,
    /// Frames taken by the window, and when counting started.
    rate: (u64, Option<Instant>, f64),
    message: Option<String>,
    /// A trace file to replay, chosen in the panel.
    pub(super) trace_path: String,
}

impl LiveInput {
    /// True while a session runs.
    #[must_use]
    pub fn is_connected(&self) -> bool {
        self.session.is_some()
    }

    /// Stops the session, if any (ending its hand's contact in `doc`).
    pub fn disconnect_from(&mut self, doc: &mut Document) {
        self.end_contact(doc);
        self.disconnect();
    }

    /// Ends the hand's contact in progress (before another edit of the surface).
    pub fn end_contact(&mut self, doc: &mut Document) {
        if let Some(d) = &mut self.driver {
            d.end_contact(doc);
        }
    }

    /// Stops the session, if any.
    pub fn disconnect(&mut self) {
        self.driver = None;
        if let Some(mut s) = self.session.take() {
            s.stop();
            if let Some(r) = lock(&s.shared.recorded).take() {
                self.message = Some(match r {
                    Ok(n) => format!("trace recorded: {n} frames"),
                    Err(e) => format!("trace recording failed: {e}"),
                });
            }
        }
    }

    fn record_path(&self) -> Option<PathBuf> {
        let t = self.record_to.trim();
        (!t.is_empty()).then(|| PathBuf::from(t))
    }

    /// The selected profile's mouse settings, when it is the mouse (driven by the window's
    /// Hand tool rather than opened as a stream).
    fn selected_mouse(&self) -> Option<MouseProfile> {
        match self.profiles.get(self.selected)?.input {
            Input::Mouse(m) => Some(m),
            _ => None,
        }
    }

    /// The Connect button: opens the devices of the selected profile, or, for the mouse
    /// profile, returns its settings for the Hand tool (stopping any device session).
    fn connect_or_mouse(&mut self, doc: &mut Document) -> Option<MouseProfile> {
        if let Some(mouse) = self.selected_mouse() {
            self.disconnect_from(doc);
            self.message = Some("the mouse drives the hand (Hand tool)".into());
            return Some(mouse);
        }
        self.connect(doc);
        None
    }

    /// Opens the devices of the selected profile.
    fn connect(&mut self, doc: &mut Document) {
        let Some(profile) = self.profiles.get(self.selected).cloned() else {
            return;
        };
        self.disconnect_from(doc);
        // A device that is off now is retried until it answers, as one unplugged mid-session.
        let stream = match HandStream::connect(&profile, &StreamOptions::default()) {
            Ok(stream) => stream,
            Err(e) => {
                self.message = Some(e.to_string());
                return;
            }
        };
        // A replay profile plays a trace recorded with another hand and transform: its frames
        // are read with the trace's header, as `nendo replay` reads them.
        let (driver, finger) = match stream.source_header() {
            Some(h) => {
                let finger = FingerModel::for_profile_name(h.profile.as_deref());
                (
                    HandDriver::new(h.hand, h.world_from_tracker, finger, self.radius),
                    finger,
                )
            }
            None => {
                let finger = FingerModel::for_profile(&profile);
                (
                    HandDriver::new(
                        profile.hand,
                        profile.world_from_tracker,
                        finger,
                        self.radius,
                    ),
                    finger,
                )
            }
        };
        let driver = match driver {
            Ok(d) => d,
            Err(e) => {
                self.message = Some(e.to_string());
                return;
            }
        };
        // Mismatches the devices worked around (a glove for the other hand) stay on show.
        let warnings = (!stream.warnings().is_empty()).then(|| stream.warnings().join("; "));
        // The recording names the scene it is made on: the document's model as it is now, and
        // the hand's finger and radius.
        let record = match self.record_path() {
            Some(path) => match Scene::of_window(doc.model(), finger, self.radius).to_text() {
                Ok(scene) => Some((path, &profile, Some(scene))),
                Err(e) => {
                    self.message = Some(format!("cannot record the scene: {e}"));
                    return;
                }
            },
            None => None,
        };
        match Session::start(stream, record) {
            Ok(s) => {
                self.session = Some(s);
                self.driver = Some(driver);
                self.message = warnings;
            }
            Err(e) => self.message = Some(e.to_string()),
        }
        self.rate = (0, Some(Instant::now()), 0.0);
    }

    /// Plays a recorded trace as if it came from the devices.
    fn replay(&mut self, path: &Path, doc: &mut Document) {
        self.disconnect_from(doc);
        match Trace::read(path) {
            Ok(trace) => {
                let h = &trace.header;
                let finger = FingerModel::for_profile_name(h.profile.as_deref());
                let driver =
                    match HandDriver::new(h.hand, h.world_from_tracker, finger, self.radius) {
                        Ok(d) => d,
                        Err(e) => {
                            self.message = Some(e.to_string());
                            return;
                        }
                    };
                let stream = HandStream::replay(trace, 1.0, false, 1024);
                match Session::start(stream, None) {
                    Ok(s) => {
                        self.session = Some(s);
                        self.driver = Some(driver);
                    }
                    Err(e) => self.message = Some(e.to_string()),
                }
            }
            Err(e) => self.message = Some(format!("{}: {e}", path.display())),
        }
        self.rate = (0, Some(Instant::now()), 0.0);
    }

    /// Takes every frame the loop received since the last call and runs them, in order,
    /// through the hand against `doc`; returns why the surface refused a frame, if it did.
    pub fn poll(&mut self, doc: &mut Document) -> Option<SurfaceError> {
        let Some(session) = &self.session else {
            return None;
        };
        let frames = std::mem::take(&mut *lock(&session.shared.inbox));
        let finished = lock(&session.shared.status).finished;
        let mut refused = None;
        if let Some(driver) = &mut self.driver {
            for f in &frames {
                driver.feed(doc, f);
            }
            refused = driver.take_refused();
        }
        let (count, since, _) = &mut self.rate;
        *count += frames.len() as u64;
        if let Some(t) = since {
            let secs = t.elapsed().as_secs_f64();
            if secs >= 1.0 {
                self.rate = (0, Some(Instant::now()), *count as f64 / secs);
            }
        }
        if finished {
            self.message = Some("the stream ended".into());
            self.end_contact(doc);
            if let Some(mut s) = self.session.take() {
                s.stop();
            }
        }
        refused
    }

    /// Draws the hand the frames drive (it stays in place after a trace ends, until the next
    /// session).
    pub fn draw(&self, lines: &mut LineBatch, spheres: &mut Vec<SphereInstance>) {
        if let Some(d) = &self.driver {
            d.draw(lines, spheres);
        }
    }

    /// The device panel. Returns the mouse profile's settings when the user chose the mouse
    /// as the hand (the caller selects the Hand tool).
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        radius: f64,
        doc: &mut Document,
    ) -> Option<MouseProfile> {
        let mut use_mouse = None;
        self.radius = radius;
        if self.profiles.is_empty() {
            self.profiles = profile::builtin();
        }
        let names: Vec<String> = self.profiles.iter().map(|p| p.name.clone()).collect();
        egui::ComboBox::from_label("profile")
            .selected_text(names.get(self.selected).cloned().unwrap_or_default())
            .show_ui(ui, |ui| {
                for (i, name) in names.iter().enumerate() {
                    ui.selectable_value(&mut self.selected, i, name);
                }
            });
        if let Some(p) = self.profiles.get(self.selected) {
            ui.small(&p.description);
        }
        // Fields on rows of their own, as wide as the panel: a field beside a label or a
        // button would push the button off the fixed-width panel.
        let mouse = self.selected_mouse().is_some();
        if !mouse {
            ui.label("record trace to (optional file):");
            ui.add(
                egui::TextEdit::singleline(&mut self.record_to)
                    .desired_width(ui.available_width())
                    .hint_text("trace.jsonl"),
            );
        }
        ui.horizontal_wrapped(|ui| {
            if self.session.is_none() {
                let (label, hint) = if mouse {
                    (
                        "Use the mouse hand",
                        "selects the Hand tool: the view ray is the finger",
                    )
                } else {
                    ("Connect", "opens the profile's devices")
                };
                if ui.button(label).on_hover_text(hint).clicked() {
                    use_mouse = self.connect_or_mouse(doc);
                }
            } else if ui.button("Disconnect").clicked() {
                self.disconnect_from(doc);
            }
            if ui.button("List ports").clicked() {
                self.inventory = Some(inventory(&self.profiles));
            }
        });
        ui.label("trace to replay:");
        ui.add(
            egui::TextEdit::singleline(&mut self.trace_path)
                .desired_width(ui.available_width())
                .hint_text("trace.jsonl"),
        );
        if ui
            .add_enabled(
                !self.trace_path.trim().is_empty(),
                egui::Button::new("Replay trace"),
            )
            .clicked()
        {
            let path = PathBuf::from(self.trace_path.trim());
            self.replay(&path, doc);
        }
        if let Some(inv) = &self.inventory {
            egui::CollapsingHeader::new(format!(
                "ports ({} serial, {} HID)",
                inv.serial.len(),
                inv.hid.len()
            ))
            .default_open(true)
            .show(ui, |ui| {
                for s in &inv.serial {
                    ui.small(format!("{}  {}", s.path, s.fits.join(", ")));
                }
                if let Some(e) = &inv.serial_error {
                    ui.small(format!("serial: {e}"));
                }
                for h in &inv.hid {
                    ui.small(format!(
                        "{:04x}:{:04x} {}  {}",
                        h.vid,
                        h.pid,
                        h.product,
                        h.fits.join(", ")
                    ));
                }
                if let Some(e) = &inv.hid_error {
                    ui.small(format!("HID: {e}"));
                }
            });
        }
        match &self.session {
            Some(s) => {
                let status = lock(&s.shared.status).clone();
                ui.label(format!(
                    "{} — {:.0} s",
                    s.describe,
                    s.started.elapsed().as_secs_f64()
                ));
                ui.label(format!(
                    "tracker {:?}, glove {:?}; {} frames, {:.1} frames/s",
                    status.tracker,
                    status.glove,
                    s.shared.frames.load(Ordering::Relaxed),
                    self.rate.2
                ));
                if let Some(e) = status.last_error {
                    ui.colored_label(egui::Color32::from_rgb(230, 90, 70), e);
                }
            }
            None => {
                ui.label("not connected");
            }
        }
        if let Some(m) = &self.message {
            ui.small(m);
        }
        use_mouse
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nendo_devices::{FrameStatus, Timestamp, TraceHeader};

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
        let session = Session::start(stream, None).expect("loop thread");
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
        let err = Session::start(stream, Some((missing.clone(), &profile, None)))
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
            Session::start(stream, Some((path.clone(), &profile, None))).expect("started");
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

    /// The panel fits the fixed-width tool panel: nothing (the Replay button, the record
    /// field) reaches past its right edge, whichever profile is selected.
    #[test]
    fn the_device_panel_fits_the_tool_panel() {
        let mut live = LiveInput::default();
        let mut doc = plane_doc();
        live.trace_path = "/some/rather/long/path/to/a/recorded/trace.jsonl".into();
        let ctx = egui::Context::default();
        let count = profile::builtin().len();
        for selected in 0..count {
            live.selected = selected;
            let mut overflow = None;
            for _ in 0..2 {
                let raw = egui::RawInput {
                    screen_rect: Some(egui::Rect::from_min_size(
                        egui::Pos2::ZERO,
                        egui::vec2(1280.0, 800.0),
                    )),
                    ..Default::default()
                };
                let _ = ctx.run_ui(raw, |ui| {
                    egui::Panel::left("devices test")
                        .exact_size(crate::app::panels::PANEL_WIDTH)
                        .show(ui, |ui| {
                            let right = ui.max_rect().max.x;
                            live.ui(ui, 1.25, &mut doc);
                            overflow = Some(ui.min_rect().max.x - right);
                        });
                });
            }
            let overflow = overflow.expect("the panel ran");
            assert!(
                overflow <= 0.5,
                "profile {selected}: the panel's content runs {overflow} points past its edge"
            );
        }
    }

    /// The window's recorder writes the scene it records on — the document's model embedded,
    /// the hand's finger and radius — and `nendo replay` of the recording, with no other
    /// argument, gives the window's surface.
    #[test]
    fn a_window_recording_replays_to_the_windows_surface() {
        use crate::hand::scene::{Scene, Start};
        let dir = std::env::temp_dir().join(format!("nendo-live-scene-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let source = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("devices/traces/plane-groove.trace");
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
            profiles: vec![profile],
            selected: 0,
            radius: 0.8,
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
            patches: None,
            radius: None,
            height: None,
            minor_radius: None,
            model: None,
            regulation: None,
            profile: None,
            finger: None,
            finger_radius: None,
            auto_refine: false,
            no_auto_refine: false,
            mirror: None,
            out: out.clone(),
        });
        let replayed = crate::model::Model::read(&out).expect("the replay").model;
        assert_eq!(replayed.surface.nodes(), doc.model().surface.nodes());
        assert_eq!(&replayed, doc.model());
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Connect on the mouse profile opens no stream: it hands the mouse settings to the Hand
    /// tool, with no error.
    #[test]
    fn the_mouse_profile_selects_the_mouse_hand() {
        let mut live = LiveInput {
            profiles: profile::builtin(),
            ..LiveInput::default()
        };
        let mouse = live
            .profiles
            .iter()
            .position(|p| matches!(p.input, Input::Mouse(_)))
            .expect("a built-in mouse profile");
        live.selected = mouse;
        let mut doc = plane_doc();
        let got = live.connect_or_mouse(&mut doc);
        assert!(got.is_some(), "the mouse profile's settings");
        assert!(!live.is_connected());
        assert_eq!(
            live.message.as_deref(),
            Some("the mouse drives the hand (Hand tool)")
        );
    }

    /// Connect starts even when neither device is there now (both ports missing): the stream
    /// keeps retrying them, as for a device unplugged mid-session, instead of failing with
    /// "cannot open serial port".
    #[test]
    fn connect_starts_with_absent_devices_and_retries_them() {
        let mut profiles = profile::builtin();
        let k = profiles
            .iter()
            .position(|p| {
                matches!(&p.input, Input::Devices { glove: Some(g), tracker: Some(_) } if g.port().is_some())
            })
            .expect("a built-in serial glove and tracker profile");
        if let Input::Devices {
            glove: Some(glove),
            tracker: Some(tracker),
        } = &mut profiles[k].input
        {
            glove.set_port("/nonexistent/nendo-glove");
            tracker.set_port("/nonexistent/nendo-tracker");
        }
        let mut live = LiveInput {
            profiles,
            selected: k,
            radius: crate::hand::DEFAULT_FINGER_RADIUS,
            ..LiveInput::default()
        };
        let mut doc = plane_doc();
        assert!(live.connect_or_mouse(&mut doc).is_none());
        assert!(
            live.is_connected(),
            "connected, retrying: {:?}",
            live.message
        );
        live.disconnect_from(&mut doc);
        assert!(!live.is_connected());
    }
}
