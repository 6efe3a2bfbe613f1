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
//!
//! Around the loop, [`LiveInput`] keeps what the Devices panel ([`super::devices_panel`])
//! edits: the profiles listed (shipped ones, the user's profile folder, files opened), the
//! ports chosen, the recording, the alignment and the glove calibration — both written into the
//! user's profile ([`nendo_devices::alignment`], [`nendo_devices::glove_calibration`]).
//!
//! The finger radius of a device hand follows the hand's size in the world unless it is set:
//! `r = DEFAULT_FINGER_RADIUS · L · s / (FIT_FRACTION · 10)`, `L` the hand's length (metres),
//! `s` the profile's sides per metre — so a hand fitted to the default 10-side plane
//! ("Fit the hand to the model") touches with the library's default radius, and a hand half as
//! large with half of it. A replayed trace is read with `DEFAULT_FINGER_RADIUS` unless set, as
//! `nendo replay` reads it.
//!
//! Test aid: with `NENDO_STATUS_FILE=PATH` the window rewrites PATH (atomically, at most four
//! times a second) with one JSON object: the session (`none`, `devices`, `replay`), each
//! device's status as the panel shows it, whether the hand is drawn and how many contacts it
//! has made — what `.ci/checks/window-devices.sh` waits on.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use glam::DVec3;
use nendo_devices::discover::Inventory;
use nendo_devices::glove_calibration::{CalibrationPose, PoseSamples, SensorFit, calibrate_glove};
use nendo_devices::profile::{Input, MouseProfile};
use nendo_devices::{
    DeviceError, DeviceStatus, HandFrame, HandSize, HandStream, Profile, SceneText, SourceState,
    StreamOptions, Trace, TraceWriter, TrackerPose, WorldFromTracker, alignment, profile,
};

use super::document::Document;
use super::file_dialog::{DialogPurpose, FileDialog};
use super::hand_input::HandDriver;
use super::settings::{DevicePorts, Settings};
use crate::hand::scene::Scene;
use crate::hand::{DEFAULT_FINGER_RADIUS, FingerModel};
use crate::render::{LineBatch, SphereInstance};
use crate::surface::SurfaceError;

/// The environment variable naming the machine-readable status file (a test aid).
pub const STATUS_FILE_ENV: &str = "NENDO_STATUS_FILE";

/// The side of the model the follow-the-hand radius is referred to (the default plane's).
const REFERENCE_EXTENT: f64 = 10.0;

/// How long each calibration pose is captured.
pub const CAPTURE: Duration = Duration::from_millis(1000);

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
    /// Each device, as [`HandStream::status`] gives it.
    devices: Vec<DeviceStatus>,
    /// A recording error (the device errors are per device).
    recording_error: Option<String>,
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
    /// The trace a replay plays.
    replay: Option<PathBuf>,
    /// The trace the session records to.
    recording: Option<PathBuf>,
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
        let recording = record.as_ref().map(|(p, _, _)| p.clone());
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
        lock(&shared.status).devices = stream.status();
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
                                lock(&worker.status).recording_error =
                                    Some(format!("recording: {e}"));
                            }
                        }
                    }
                    worker
                        .frames
                        .fetch_add(batch.len() as u64, Ordering::Relaxed);
                    lock(&worker.inbox).extend(batch);
                    let devices = stream.status();
                    let mut status = lock(&worker.status);
                    status.devices = devices;
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
            replay: None,
            recording,
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

/// Where a listed profile comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum ProfileSource {
    /// Shipped with nendo (read-only: changes go to a user copy).
    Builtin,
    /// A profile file (the user's folder, or opened).
    File(PathBuf),
}

/// A profile in the panel's list.
#[derive(Debug, Clone)]
pub(super) struct ProfileEntry {
    pub(super) profile: Profile,
    pub(super) source: ProfileSource,
}

impl ProfileEntry {
    /// How settings name it: a shipped profile's name, or the file's path.
    pub(super) fn key(&self) -> String {
        match &self.source {
            ProfileSource::Builtin => self.profile.name.clone(),
            ProfileSource::File(p) => p.display().to_string(),
        }
    }

    /// How the picker lists it.
    pub(super) fn label(&self) -> String {
        match &self.source {
            ProfileSource::Builtin => format!("{} (built-in)", self.profile.name),
            ProfileSource::File(p) => format!(
                "{} ({})",
                self.profile.name,
                p.file_name()
                    .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
            ),
        }
    }
}

/// The model point under the view's centre and the model's size: what recentering and fitting
/// the hand aim at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewAnchor {
    /// The surface point under the view centre (the orbit target when the centre misses).
    pub point: DVec3,
    /// The surface's unit normal there, facing the viewer.
    pub normal: DVec3,
    /// The model's largest extent, world units.
    pub extent: f64,
}

/// The glove calibration in progress: the samples captured per pose.
#[derive(Debug, Default)]
pub(super) struct CalibrationCapture {
    pub(super) samples: PoseSamples,
    /// The pose being captured and when the capture ends.
    pub(super) capturing: Option<(CalibrationPose, Instant)>,
    /// The last result, for the panel.
    pub(super) result: Option<String>,
}

/// The device panel's state and the live session.
#[derive(Debug, Default)]
pub struct LiveInput {
    pub(super) entries: Vec<ProfileEntry>,
    pub(super) selected: usize,
    /// Ports typed or picked for the selected profile's glove and tracker.
    pub(super) glove_port: String,
    pub(super) tracker_port: String,
    /// Remembered ports per profile key.
    pub(super) ports: std::collections::BTreeMap<String, DevicePorts>,
    pub(super) inventory: Option<Inventory>,
    session: Option<Session>,
    /// The profile the session runs (ports applied).
    running: Option<Profile>,
    /// The hand the session's frames drive.
    driver: Option<HandDriver>,
    /// The finger radius set by hand (`None`: it follows the hand).
    pub(super) radius_set: Option<f64>,
    /// Record every device session.
    pub(super) record: bool,
    /// The trace to record to.
    pub(super) record_to: String,
    /// Connect waits: the recording would replace this file.
    pub(super) confirm_overwrite: Option<PathBuf>,
    /// Frames taken by the window, and when counting started.
    rate: (u64, Option<Instant>, f64),
    pub(super) message: Option<String>,
    /// A trace file to replay, chosen in the panel.
    pub(super) trace_path: String,
    /// The last tracker pose received (what recentering moves).
    last_pose: Option<TrackerPose>,
    pub(super) calibration: CalibrationCapture,
    /// The hand size being edited.
    pub(super) hand_edit: Option<HandSize>,
    /// The sides per metre being dragged.
    pub(super) scale_edit: Option<f64>,
    /// The user's profile folder (`None`: none is listed or written; tests).
    profile_dir: Option<PathBuf>,
    /// `NENDO_STATUS_FILE` and when it was last written.
    status_file: Option<PathBuf>,
    status_written: Option<Instant>,
    /// Contacts the device hand has made (one undoable edit each).
    contacts: u64,
}

/// The fingers a replayed trace presses with: those its scene names, else those of the
/// profile it was recorded with (the view ray for the mouse, every finger for a glove) — as
/// `nendo replay` takes them.
#[must_use]
pub fn trace_finger(header: &nendo_devices::TraceHeader) -> FingerModel {
    Scene::of_trace(header)
        .ok()
        .flatten()
        .and_then(|scene| scene.finger)
        .and_then(|f| crate::cli::replay::parse_finger(&f).ok())
        .unwrap_or_else(|| FingerModel::for_profile_name(header.profile.as_deref()))
}

/// `stem-2.trace`, `stem-3.trace`, …: the first name beside `path` that is free.
#[must_use]
pub fn fresh_name(path: &Path) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(|| "session".into(), |s| s.to_string_lossy().into_owned());
    let ext = path
        .extension()
        .map_or_else(|| "trace".into(), |e| e.to_string_lossy().into_owned());
    let dir = path.parent().unwrap_or_else(|| Path::new(""));
    (2u32..)
        .map(|k| dir.join(format!("{stem}-{k}.{ext}")))
        .find(|p| std::fs::symlink_metadata(p).is_err())
        .unwrap_or_else(|| path.to_path_buf())
}

/// The finger radius that follows a hand (see the module docs).
#[must_use]
pub fn following_radius(hand: &HandSize, world_from_tracker: &WorldFromTracker) -> f64 {
    DEFAULT_FINGER_RADIUS * alignment::hand_length(hand) * world_from_tracker.scale
        / (alignment::FIT_FRACTION * REFERENCE_EXTENT)
}

impl LiveInput {
    /// A panel listing the shipped profiles and those in `profile_dir` (the user's folder,
    /// where user copies of changed shipped profiles go), writing its status file when the
    /// environment asks ([`STATUS_FILE_ENV`]).
    #[must_use]
    pub fn with_profile_dir(profile_dir: Option<PathBuf>) -> Self {
        let mut live = LiveInput {
            profile_dir,
            status_file: std::env::var_os(STATUS_FILE_ENV).map(PathBuf::from),
            ..LiveInput::default()
        };
        live.rescan();
        live
    }

    /// Lists the shipped profiles, the user's folder and the files opened before (kept).
    pub(super) fn rescan(&mut self) {
        let key = self.entries.get(self.selected).map(ProfileEntry::key);
        let opened: Vec<ProfileEntry> = self
            .entries
            .iter()
            .filter(|e| match &e.source {
                ProfileSource::File(p) => self
                    .profile_dir
                    .as_deref()
                    .is_none_or(|d| p.parent() != Some(d)),
                ProfileSource::Builtin => false,
            })
            .cloned()
            .collect();
        let mut entries: Vec<ProfileEntry> = profile::builtin()
            .into_iter()
            .map(|profile| ProfileEntry {
                profile,
                source: ProfileSource::Builtin,
            })
            .collect();
        let mut problems = Vec::new();
        if let Some(dir) = &self.profile_dir
            && let Ok(read) = std::fs::read_dir(dir)
        {
            let mut files: Vec<PathBuf> = read
                .filter_map(Result::ok)
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|e| e == "json"))
                .collect();
            files.sort();
            for path in files {
                match Profile::load(&path) {
                    Ok(profile) => entries.push(ProfileEntry {
                        profile,
                        source: ProfileSource::File(path),
                    }),
                    Err(e) => problems.push(e.to_string()),
                }
            }
        }
        entries.extend(opened);
        self.entries = entries;
        if !problems.is_empty() {
            self.message = Some(problems.join("; "));
        }
        let found = key.and_then(|k| self.entries.iter().position(|e| e.key() == k));
        self.select(found.unwrap_or(self.selected.min(self.entries.len().saturating_sub(1))));
    }

    /// Selects an entry (keeping the ports typed for the one selected before); its ports are
    /// the remembered ones, or the profile's own.
    pub(super) fn select(&mut self, index: usize) {
        self.remember_ports();
        self.show_entry(index);
    }

    /// Selects an entry with its remembered ports, or the profile's own.
    fn show_entry(&mut self, index: usize) {
        self.selected = index;
        let Some(entry) = self.entries.get(index) else {
            return;
        };
        let remembered = self.ports.get(&entry.key()).cloned().unwrap_or_default();
        self.glove_port = remembered
            .glove
            .or_else(|| {
                entry
                    .profile
                    .glove()
                    .and_then(|g| g.port())
                    .map(String::from)
            })
            .unwrap_or_default();
        self.tracker_port = remembered
            .tracker
            .or_else(|| entry.profile.tracker().map(|t| t.port().to_string()))
            .unwrap_or_default();
        self.hand_edit = None;
    }

    /// Keeps the selected profile's ports, when they differ from the profile's own.
    fn remember_ports(&mut self) {
        if let Some(entry) = self.entries.get(self.selected) {
            note_ports(&mut self.ports, entry, &self.glove_port, &self.tracker_port);
        }
    }

    /// Adds (or finds) a profile file in the list and selects it.
    pub(super) fn open_profile_file(&mut self, path: &Path) -> Result<(), DeviceError> {
        let profile = Profile::load(path)?;
        let path = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
        let source = ProfileSource::File(path);
        let index = match self.entries.iter().position(|e| e.source == source) {
            Some(k) => {
                self.entries[k].profile = profile;
                k
            }
            None => {
                self.entries.push(ProfileEntry { profile, source });
                self.entries.len() - 1
            }
        };
        self.select(index);
        Ok(())
    }

    /// Selects a profile by shipped name or file path (`nendo --profile`), with the profile's
    /// own ports (not remembered ones).
    ///
    /// # Errors
    /// When it is neither a shipped profile nor a readable profile file.
    pub fn select_profile(&mut self, name_or_path: &str) -> Result<(), DeviceError> {
        if profile::is_builtin(name_or_path) {
            let k = self
                .entries
                .iter()
                .position(|e| e.source == ProfileSource::Builtin && e.profile.name == name_or_path);
            if let Some(k) = k {
                self.ports.remove(name_or_path);
                self.select(k);
                return Ok(());
            }
        }
        // Through `resolve` for its error message on a name that is neither.
        profile::resolve(name_or_path)?;
        let path = Path::new(name_or_path);
        let key = path
            .canonicalize()
            .unwrap_or_else(|_| path.to_path_buf())
            .display()
            .to_string();
        self.ports.remove(&key);
        self.open_profile_file(path)
    }

    /// The remembered part of the panel, into `settings`.
    pub fn store_settings(&self, settings: &mut Settings) {
        let mut ports = self.ports.clone();
        if let Some(entry) = self.entries.get(self.selected) {
            note_ports(&mut ports, entry, &self.glove_port, &self.tracker_port);
            settings.profile = Some(entry.key());
        }
        settings.ports = ports;
        settings.record = self.record;
        settings.record_folder = Path::new(self.record_to.trim())
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map(Path::to_path_buf);
        settings.trace_folder = Path::new(self.trace_path.trim())
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map(Path::to_path_buf);
        settings.finger_radius = self.radius_set;
    }

    /// Takes the remembered settings (before the first frame).
    pub fn apply_settings(&mut self, settings: &Settings) {
        self.ports = settings.ports.clone();
        self.record = settings.record;
        if let Some(dir) = &settings.record_folder {
            self.record_to = dir.join("session.trace").display().to_string();
        }
        if let Some(dir) = &settings.trace_folder {
            self.trace_path = dir.display().to_string();
        }
        self.radius_set = settings.finger_radius.filter(|r| r.is_finite() && *r > 0.0);
        let wanted = settings.profile.as_deref();
        let found = wanted.and_then(|k| self.entries.iter().position(|e| e.key() == k));
        // The ports shown so far are the defaults, not the user's: nothing to keep.
        match (found, wanted) {
            (Some(k), _) => self.show_entry(k),
            (None, Some(path)) if Path::new(path).is_file() => {
                self.show_entry(self.selected);
                if let Err(e) = self.open_profile_file(Path::new(path)) {
                    self.message = Some(format!("the remembered profile: {e}"));
                }
            }
            _ => self.show_entry(self.selected),
        }
    }

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
        self.running = None;
        self.calibration.capturing = None;
        if let Some(mut s) = self.session.take() {
            s.stop();
            if let Some(r) = lock(&s.shared.recorded).take() {
                let to = s
                    .recording
                    .as_ref()
                    .map(|p| format!(" to {}", p.display()))
                    .unwrap_or_default();
                self.message = Some(match r {
                    Ok(n) => format!("trace recorded{to}: {n} frames"),
                    Err(e) => format!("trace recording failed: {e}"),
                });
            }
        }
        self.write_status(true);
    }

    /// The trace to record to, if recording is on and a path is given.
    fn record_path(&self) -> Option<PathBuf> {
        let t = self.record_to.trim();
        (self.record && !t.is_empty()).then(|| PathBuf::from(t))
    }

    /// The selected profile, with the ports of the panel.
    #[must_use]
    pub(super) fn selected_profile(&self) -> Option<Profile> {
        let mut p = self.entries.get(self.selected)?.profile.clone();
        if let Some(g) = p.glove_mut()
            && !self.glove_port.trim().is_empty()
        {
            g.set_port(self.glove_port.trim());
        }
        if let Some(t) = p.tracker_mut()
            && !self.tracker_port.trim().is_empty()
        {
            t.set_port(self.tracker_port.trim());
        }
        Some(p)
    }

    /// The selected profile's mouse settings, when it is the mouse (driven by the window's
    /// Hand tool rather than opened as a stream).
    pub(super) fn selected_mouse(&self) -> Option<MouseProfile> {
        match self.entries.get(self.selected)?.profile.input {
            Input::Mouse(m) => Some(m),
            _ => None,
        }
    }

    /// The Connect button: opens the devices of the selected profile, or, for the mouse
    /// profile, returns its settings for the Hand tool (stopping any device session).
    pub(super) fn connect_or_mouse(&mut self, doc: &mut Document) -> Option<MouseProfile> {
        if let Some(mouse) = self.selected_mouse() {
            self.disconnect_from(doc);
            self.message = Some("the mouse drives the hand (Hand tool)".into());
            return Some(mouse);
        }
        self.connect(doc);
        None
    }

    /// Opens the devices of the selected profile — unless the recording would replace an
    /// existing file: then the panel asks first ([`LiveInput::confirm_overwrite`]).
    pub fn connect(&mut self, doc: &mut Document) {
        let record = self.record_path();
        if let Some(path) = &record
            && std::fs::symlink_metadata(path).is_ok()
        {
            self.confirm_overwrite = Some(path.clone());
            return;
        }
        self.connect_recording(doc, record);
    }

    /// Connects recording to `record` (an answer to the overwrite question, or no question).
    pub(super) fn connect_recording(&mut self, doc: &mut Document, record: Option<PathBuf>) {
        self.confirm_overwrite = None;
        let Some(profile) = self.selected_profile() else {
            return;
        };
        self.disconnect_from(doc);
        if let Some(path) = &record {
            self.record_to = path.display().to_string();
        }
        // A device that is off now is retried until it answers, as one unplugged mid-session.
        let stream = match HandStream::connect(&profile, &StreamOptions::default()) {
            Ok(stream) => stream,
            Err(e) => {
                self.message = Some(e.to_string());
                return;
            }
        };
        let replay = match &profile.input {
            Input::Replay(r) => Some(PathBuf::from(&r.trace)),
            _ => None,
        };
        let Some((driver, finger, radius)) = self.driver_for(&stream, &profile) else {
            return;
        };
        // Mismatches the devices worked around (a glove for the other hand) stay on show.
        let warnings = (!stream.warnings().is_empty()).then(|| stream.warnings().join("; "));
        // The recording names the scene it is made on: the document's model as it is now, and
        // the hand's finger and radius.
        let record = match record {
            Some(path) => match Scene::of_window(doc.model(), finger, radius).to_text() {
                Ok(scene) => Some((path, &profile, Some(scene))),
                Err(e) => {
                    self.message = Some(format!("cannot record the scene: {e}"));
                    return;
                }
            },
            None => None,
        };
        match Session::start(stream, record) {
            Ok(mut s) => {
                s.replay = replay;
                self.session = Some(s);
                self.driver = Some(driver);
                self.running = Some(profile);
                self.message = warnings;
            }
            Err(e) => self.message = Some(e.to_string()),
        }
        self.rate = (0, Some(Instant::now()), 0.0);
        self.write_status(true);
    }

    /// The hand for a stream: a replay reads its frames with the trace's header (its hand
    /// and transform), as `nendo replay` does; live devices with the profile's.
    fn driver_for(
        &mut self,
        stream: &HandStream,
        profile: &Profile,
    ) -> Option<(HandDriver, FingerModel, f64)> {
        let (driver, finger, radius) = match stream.source_header() {
            Some(h) => {
                let finger = trace_finger(h);
                let radius = self.radius_set.unwrap_or(DEFAULT_FINGER_RADIUS);
                (
                    HandDriver::new(h.hand, h.world_from_tracker, finger, radius),
                    finger,
                    radius,
                )
            }
            None => {
                let finger = FingerModel::for_profile(profile);
                let radius = self.radius(profile, false);
                (
                    HandDriver::new(profile.hand, profile.world_from_tracker, finger, radius),
                    finger,
                    radius,
                )
            }
        };
        match driver {
            Ok(d) => Some((d, finger, radius)),
            Err(e) => {
                self.message = Some(e.to_string());
                None
            }
        }
    }

    /// The finger radius of a session: set, or following the hand (a replay: the default).
    #[must_use]
    pub fn radius(&self, profile: &Profile, replay: bool) -> f64 {
        self.radius_set.unwrap_or_else(|| {
            if replay {
                DEFAULT_FINGER_RADIUS
            } else {
                following_radius(&profile.hand, &profile.world_from_tracker)
            }
        })
    }

    /// Plays a recorded trace as if it came from the devices.
    pub(super) fn replay(&mut self, path: &Path, doc: &mut Document) {
        self.disconnect_from(doc);
        match Trace::read(path) {
            Ok(trace) => {
                let h = &trace.header;
                let driver = HandDriver::new(
                    h.hand,
                    h.world_from_tracker,
                    FingerModel::for_profile_name(h.profile.as_deref()),
                    self.radius_set.unwrap_or(DEFAULT_FINGER_RADIUS),
                );
                let driver = match driver {
                    Ok(d) => d,
                    Err(e) => {
                        self.message = Some(e.to_string());
                        return;
                    }
                };
                let stream = HandStream::replay(trace, 1.0, false, 1024);
                match Session::start(stream, None) {
                    Ok(mut s) => {
                        s.replay = Some(path.to_path_buf());
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
            self.write_status(false);
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
            self.contacts = driver.contacts();
        }
        if let Some(pose) = frames.iter().rev().find_map(|f| f.pose) {
            self.last_pose = Some(pose);
        }
        self.capture(&frames);
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
        self.write_status(finished);
        refused
    }

    /// Draws the hand the frames drive (it stays in place after a trace ends, until the next
    /// session).
    pub fn draw(&self, lines: &mut LineBatch, spheres: &mut Vec<SphereInstance>) {
        if let Some(d) = &self.driver {
            d.draw(lines, spheres);
        }
    }

    /// The session's devices as the panel shows them, and whether it is a replay.
    pub(super) fn device_status(&self) -> Option<(Vec<DeviceStatus>, Option<String>, bool)> {
        let s = self.session.as_ref()?;
        let status = lock(&s.shared.status);
        Some((
            status.devices.clone(),
            status.recording_error.clone(),
            s.replay.is_some(),
        ))
    }

    /// `describe — N s; frames, rate`, for the panel.
    pub(super) fn session_line(&self) -> Option<String> {
        let s = self.session.as_ref()?;
        let what = match &s.replay {
            Some(p) => format!("replaying {}", p.display()),
            None => s.describe.clone(),
        };
        let recording = s
            .recording
            .as_ref()
            .map(|p| format!("; recording to {}", p.display()))
            .unwrap_or_default();
        Some(format!(
            "{what} — {:.0} s, {} frames, {:.1} frames/s{recording}",
            s.started.elapsed().as_secs_f64(),
            s.shared.frames.load(Ordering::Relaxed),
            self.rate.2
        ))
    }

    /// The running live profile (devices, not a replay).
    pub(super) fn running_devices(&self) -> Option<&Profile> {
        self.running
            .as_ref()
            .filter(|p| matches!(p.input, Input::Devices { .. }))
    }

    /// The last tracker pose.
    pub(super) fn last_pose(&self) -> Option<TrackerPose> {
        self.last_pose
    }

    /// A file dialog for the panel's purposes, opening where its file is.
    #[must_use]
    pub fn new_dialog(&self, purpose: DialogPurpose) -> Option<FileDialog> {
        let (current, default) = match purpose {
            DialogPurpose::OpenProfile => (
                self.entries
                    .get(self.selected)
                    .and_then(|e| match &e.source {
                        ProfileSource::File(p) => Some(p.clone()),
                        ProfileSource::Builtin => None,
                    })
                    .or_else(|| self.profile_dir.as_ref().map(|d| d.join("profile.json"))),
                "profile.json",
            ),
            DialogPurpose::RecordTrace => (
                Some(PathBuf::from(self.record_to.trim())).filter(|p| !p.as_os_str().is_empty()),
                "session.trace",
            ),
            DialogPurpose::ReplayTrace => {
                let t = PathBuf::from(self.trace_path.trim());
                let inside = if t.is_dir() { t.join("x.trace") } else { t };
                (Some(inside).filter(|p| !p.as_os_str().is_empty()), "")
            }
            _ => return None,
        };
        let current = current.filter(|p| p.parent().is_some_and(Path::is_dir));
        Some(FileDialog::beside(purpose, current.as_deref(), default))
    }

    /// A file dialog of the panel picked `path`.
    pub fn dialog_chosen(&mut self, purpose: DialogPurpose, path: &Path) {
        match purpose {
            DialogPurpose::OpenProfile => {
                if let Err(e) = self.open_profile_file(path) {
                    self.message = Some(e.to_string());
                }
            }
            DialogPurpose::RecordTrace => {
                let mut path = path.to_path_buf();
                if path.extension().is_none() {
                    path.set_extension("trace");
                }
                self.record_to = path.display().to_string();
                self.record = true;
            }
            DialogPurpose::ReplayTrace => self.trace_path = path.display().to_string(),
            _ => {}
        }
    }

    // --- Alignment and calibration -----------------------------------------------------

    /// Replaces the selected profile's transform (and the running session's hand), and saves
    /// the profile into the user's folder.
    fn set_alignment(&mut self, doc: &mut Document, wft: WorldFromTracker, what: &str) {
        let Some(entry) = self.entries.get_mut(self.selected) else {
            return;
        };
        entry.profile.world_from_tracker = wft;
        if let Some(r) = &mut self.running {
            r.world_from_tracker = wft;
        }
        self.rebuild_hand(doc);
        self.save_profile(what);
    }

    /// Builds the session's hand again from the running profile (after an alignment or
    /// radius change), ending the contact in progress.
    pub(super) fn rebuild_hand(&mut self, doc: &mut Document) {
        let Some(profile) = self.running_devices().cloned() else {
            return;
        };
        self.end_contact(doc);
        let driver = HandDriver::new(
            profile.hand,
            profile.world_from_tracker,
            FingerModel::for_profile(&profile),
            self.radius(&profile, false),
        );
        match driver {
            Ok(d) => self.driver = Some(d.with_contacts(self.contacts)),
            Err(e) => self.message = Some(e.to_string()),
        }
    }

    /// Recenter: the hand, where it is now, appears half a hand above the model point under
    /// the view centre (above, along the normal: placed on it, the fingers would be in the
    /// clay at once).
    pub(super) fn recenter(&mut self, doc: &mut Document, anchor: &ViewAnchor) {
        let (Some(pose), Some(entry)) = (self.last_pose, self.entries.get(self.selected)) else {
            self.message = Some("recenter: no tracker pose yet (connect a tracker)".into());
            return;
        };
        let p = &entry.profile;
        let lift = 0.5 * alignment::hand_length(&p.hand) * p.world_from_tracker.scale;
        let target = anchor.point + anchor.normal * lift;
        match alignment::recenter(&p.world_from_tracker, pose.position, target) {
            Ok(w) => self.set_alignment(doc, w, "recentred"),
            Err(e) => self.message = Some(format!("recenter: {e}")),
        }
    }

    /// Sets the sides per metre, the hand staying where it is.
    pub(super) fn set_scale(&mut self, doc: &mut Document, scale: f64) {
        let Some(entry) = self.entries.get(self.selected) else {
            return;
        };
        let at = self.last_pose.map_or(DVec3::ZERO, |p| p.position);
        match alignment::rescale_about(&entry.profile.world_from_tracker, at, scale) {
            Ok(w) => self.set_alignment(doc, w, &format!("{scale:.3} sides per metre")),
            Err(e) => self.message = Some(format!("scale: {e}")),
        }
    }

    /// Fits the hand to the model ([`alignment::fit_scale`]).
    pub(super) fn fit_hand(&mut self, doc: &mut Document, anchor: &ViewAnchor) {
        let Some(entry) = self.entries.get(self.selected) else {
            return;
        };
        match alignment::fit_scale(&entry.profile.hand, anchor.extent) {
            Ok(s) => self.set_scale(doc, s),
            Err(e) => self.message = Some(format!("fit the hand: {e}")),
        }
    }

    /// Applies the edited hand size.
    pub(super) fn apply_hand(&mut self, doc: &mut Document, hand: HandSize) {
        if let Err(e) = hand.validate() {
            self.message = Some(format!("hand size: {e}"));
            return;
        }
        let Some(entry) = self.entries.get_mut(self.selected) else {
            return;
        };
        entry.profile.hand = hand;
        if let Some(r) = &mut self.running {
            r.hand = hand;
        }
        self.hand_edit = None;
        self.rebuild_hand(doc);
        self.save_profile("hand size");
    }

    /// Starts capturing a calibration pose for [`CAPTURE`].
    pub(super) fn capture_pose(&mut self, pose: CalibrationPose) {
        self.calibration.samples.clear(pose);
        self.calibration.capturing = Some((pose, Instant::now() + CAPTURE));
        self.calibration.result = None;
    }

    fn capture(&mut self, frames: &[HandFrame]) {
        let Some((pose, until)) = self.calibration.capturing else {
            return;
        };
        for f in frames {
            if f.status.glove_fresh
                && let Some(j) = f.joints
            {
                self.calibration.samples.push(pose, j);
            }
        }
        if Instant::now() >= until {
            self.calibration.capturing = None;
        }
    }

    /// Fits the glove's offsets and gains from the captured poses, writes them into the user's
    /// profile and reconnects with them.
    pub(super) fn finish_calibration(&mut self, doc: &mut Document) {
        let Some(table) = self
            .running_devices()
            .and_then(|p| p.glove())
            .map(|g| g.calibration().to_vec())
        else {
            self.calibration.result = Some("connect the glove first".into());
            return;
        };
        match calibrate_glove(&table, &self.calibration.samples) {
            Ok((fitted, fits)) => {
                let both = fits
                    .iter()
                    .filter(|f| **f == SensorFit::OffsetAndGain)
                    .count();
                let offset = fits.iter().filter(|f| **f == SensorFit::OffsetOnly).count();
                if let Some(g) = self
                    .entries
                    .get_mut(self.selected)
                    .and_then(|e| e.profile.glove_mut())
                {
                    *g.calibration_mut() = fitted;
                }
                self.calibration.result = Some(format!(
                    "{both} sensors: offset and gain; {offset}: offset (gain kept)"
                ));
                self.calibration.samples = PoseSamples::default();
                if self.save_profile("glove calibration") {
                    // The stream calibrates in the device thread: start it with the new table.
                    self.connect_recording(doc, None);
                }
            }
            Err(e) => self.calibration.result = Some(e.to_string()),
        }
    }

    /// Writes the selected profile (ports of the panel applied) into the user's folder: back
    /// to its file, or — a shipped profile — to a new user copy `NAME-mine.json`, which is
    /// then selected. Returns whether it was written.
    fn save_profile(&mut self, what: &str) -> bool {
        let Some(mut profile) = self.selected_profile() else {
            return false;
        };
        let Some(entry) = self.entries.get(self.selected) else {
            return false;
        };
        let path = match &entry.source {
            ProfileSource::File(p) => p.clone(),
            ProfileSource::Builtin => {
                let Some(dir) = &self.profile_dir else {
                    self.message = Some(format!("{what}: applied (no profile folder to save to)"));
                    return false;
                };
                if let Err(e) = std::fs::create_dir_all(dir) {
                    self.message = Some(format!("{what}: cannot create {}: {e}", dir.display()));
                    return false;
                }
                profile.name = format!("{}-mine", profile.name);
                let first = dir.join(format!("{}.json", profile.name));
                if std::fs::symlink_metadata(&first).is_ok() {
                    let fresh = fresh_name(&first);
                    if let Some(stem) = fresh.file_stem() {
                        profile.name = stem.to_string_lossy().into_owned();
                    }
                    fresh
                } else {
                    first
                }
            }
        };
        match profile.save(&path) {
            Ok(()) => {
                let builtin = entry.source == ProfileSource::Builtin;
                if builtin {
                    // The shipped entry goes back to shipped values; the copy is selected.
                    let name = entry.profile.name.clone();
                    if let Some(original) = profile::builtin().into_iter().find(|p| p.name == name)
                        && let Some(e) = self.entries.get_mut(self.selected)
                    {
                        e.profile = original;
                    }
                    let (glove, tracker) = (self.glove_port.clone(), self.tracker_port.clone());
                    self.entries.push(ProfileEntry {
                        profile,
                        source: ProfileSource::File(path.clone()),
                    });
                    self.select(self.entries.len() - 1);
                    (self.glove_port, self.tracker_port) = (glove, tracker);
                } else if let Some(e) = self.entries.get_mut(self.selected) {
                    e.profile = profile;
                }
                self.message = Some(format!("{what}: saved to {}", path.display()));
                true
            }
            Err(e) => {
                self.message = Some(format!("{what}: {e}"));
                false
            }
        }
    }

    // --- The status file ------------------------------------------------------------------

    /// Rewrites the status file ([`STATUS_FILE_ENV`]): at most four times a second, or now
    /// with `force`.
    fn write_status(&mut self, force: bool) {
        let Some(path) = self.status_file.clone() else {
            return;
        };
        let due = self
            .status_written
            .is_none_or(|t| t.elapsed() >= Duration::from_millis(250));
        if !(force || due) {
            return;
        }
        self.status_written = Some(Instant::now());
        let session = match &self.session {
            None => "none",
            Some(s) if s.replay.is_some() => "replay",
            Some(_) => "devices",
        };
        let devices: Vec<serde_json::Value> = self
            .device_status()
            .map(|(d, _, _)| d)
            .unwrap_or_default()
            .iter()
            .map(|d| {
                serde_json::json!({
                    "role": d.role.name(),
                    "state": state_name(d.state),
                    "rate_hz": (d.rate_hz * 10.0).round() / 10.0,
                    "samples": d.samples,
                    "last_error": d.last_error,
                    "faults": d.faults,
                    "rejected": d.rejected,
                    "watchdog_trips": d.watchdog_trips,
                    "disconnects": d.disconnects,
                })
            })
            .collect();
        let hand_drawn = self
            .driver
            .as_ref()
            .is_some_and(|d| d.hand_loop().pose().is_some());
        let line = serde_json::json!({
            "session": session,
            "devices": devices,
            "hand_drawn": hand_drawn,
            "contacts": self.contacts,
        });
        let text = format!("{line}\n");
        if let Err(e) = nendo_file::write_bytes(&path, text.as_bytes()) {
            self.message = Some(format!("{STATUS_FILE_ENV}: {}", e.reason()));
            self.status_file = None;
        }
    }
}

/// Notes in `ports` the ports typed for `entry`, where they differ from the profile's own
/// (none noted: the entry is dropped).
fn note_ports(
    ports: &mut std::collections::BTreeMap<String, DevicePorts>,
    entry: &ProfileEntry,
    glove: &str,
    tracker: &str,
) {
    let own_glove = entry.profile.glove().and_then(|g| g.port());
    let own_tracker = entry.profile.tracker().map(|t| t.port());
    let differs = |typed: &str, own: Option<&str>| {
        let typed = typed.trim();
        (!typed.is_empty() && Some(typed) != own).then(|| typed.to_string())
    };
    let noted = DevicePorts {
        glove: differs(glove, own_glove),
        tracker: differs(tracker, own_tracker),
    };
    if noted == DevicePorts::default() {
        ports.remove(&entry.key());
    } else {
        ports.insert(entry.key(), noted);
    }
}

/// A source state's name in the panel and the status file.
#[must_use]
pub fn state_name(state: SourceState) -> &'static str {
    match state {
        SourceState::Absent => "absent",
        SourceState::Ok => "ok",
        SourceState::Silent => "silent",
        SourceState::Disconnected => "disconnected",
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

    /// The Devices panel fits its width: nothing (the Replay button, the record field, the
    /// port fields) reaches past its right edge, whichever profile is selected.
    #[test]
    fn the_device_panel_fits_its_width() {
        let mut live = LiveInput::default();
        let mut doc = plane_doc();
        live.trace_path = "/some/rather/long/path/to/a/recorded/session.trace".into();
        live.record = true;
        live.record_to = "/another/rather/long/path/to/a/recording/session.trace".into();
        let anchor = ViewAnchor {
            point: DVec3::ZERO,
            normal: DVec3::Z,
            extent: 10.0,
        };
        let ctx = egui::Context::default();
        let count = profile::builtin().len();
        for selected in 0..count {
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
                    egui::Panel::right("devices test")
                        .exact_size(crate::app::devices_panel::DEVICES_PANEL_WIDTH)
                        .show(ui, |ui| {
                            let right = ui.max_rect().max.x;
                            let _ = live.ui(ui, &mut doc, &anchor);
                            if live.selected != selected {
                                live.select(selected);
                            }
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
}
