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
//! Around the loop, [`LiveInput`] keeps what the Devices panel (`app::devices_panel`, in the window)
//! edits: the profiles listed (shipped ones, the user's profile folder, files opened), the
//! ports chosen, the recording, the alignment and the glove calibration — both written into the
//! user's profile ([`nendo_devices::alignment`], [`nendo_devices::glove_calibration`]).
//!
//! The finger radius of a device hand follows the hand's size in the world unless it is set:
//! `r = DEFAULT_FINGER_RADIUS · L · s / (FIT_FRACTION · 10)`, `L` the hand's length (metres),
//! `s` the profile's sides per metre — so a hand fitted to the default 10-side plane
//! ("Fit the hand to the model") touches with the library's default radius, and a hand half as
//! large with half of it. A replayed trace is read with its scene's finger and finger radius
//! (`DEFAULT_FINGER_RADIUS` when it names none) unless set, as `nendo replay` reads it.
//!
//! The desk's aids — the hand fitted on a profile's first connect, the pressing parts chosen,
//! the clutch key, the contact feedback — are in `desk`.
//!
//! The device hand presses with a symmetry group (`symmetry`): a session that does not record
//! follows the window's symmetry, taken up between contacts as the mouse hand does; a
//! recording keeps the window's group at Connect until it stops, and names it in its trace's
//! scene (`mirror`, `radial`, `lathe`); a replayed trace presses with its scene's group. A
//! fixed group first makes the whole surface exactly invariant, as `nendo replay` does, so the
//! window and `nendo replay` of the trace agree bit for bit.
//!
//! Each sample's latency, from its arrival on the port to the frame that shows it, is kept by
//! a [`LatencyMeter`] (see `latency`): the window marks the display refresh, the frame's GPU
//! submission and its presentation; the status bar and the status file show the figure.
//!
//! Test aid: with `NENDO_STATUS_FILE=PATH` the window rewrites PATH (atomically, at most four
//! times a second) with one JSON object: the session (`none`, `devices`, `replay`), each
//! device's status as the panel shows it, whether the hand is drawn and how many contacts it
//! has made, whether the clutch holds it (`clutched`) and how far the contact in progress has
//! moved the clay (`clay_moved`, `null` when none) — what `.ci/checks/window-devices.sh` waits
//! on.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::DVec3;
use nendo_devices::discover::Inventory;
use nendo_devices::{HandSize, Profile, SourceState, TrackerPose, WorldFromTracker, alignment};

use crate::editor::hand_input::HandDriver;
use crate::editor::settings::DevicePorts;
use crate::hand::scene::Scene;
use crate::hand::{DEFAULT_FINGER_RADIUS, FingerModel};

mod calibration;
mod desk;
#[cfg(test)]
mod desk_tests;
mod inbox;
mod latency;
mod profiles;
mod session;
mod status;
mod symmetry;
#[cfg(test)]
mod symmetry_tests;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod vmc_tests;

pub(crate) use calibration::CalibrationCapture;
use inbox::DeviceSession;
pub use inbox::DeviceWaker;
pub use latency::{
    LATCH_WAIT, LATENCY_WINDOW, LatencyMeter, LatencySummary, Quantiles, SampleLatency, Stages,
};
pub(crate) use profiles::{ProfileEntry, ProfileSource};

/// The environment variable naming the machine-readable status file (a test aid).
pub const STATUS_FILE_ENV: &str = "NENDO_STATUS_FILE";

/// The side of the model the follow-the-hand radius is referred to (the default plane's).
const REFERENCE_EXTENT: f64 = 10.0;

/// How long each calibration pose is captured.
pub const CAPTURE: Duration = Duration::from_millis(1000);

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

/// The device panel's state and the live session.
#[derive(Debug, Default)]
pub struct LiveInput {
    pub(crate) entries: Vec<ProfileEntry>,
    pub(crate) selected: usize,
    /// Ports typed or picked for the selected profile's glove and tracker.
    pub(crate) glove_port: String,
    pub(crate) tracker_port: String,
    /// Remembered ports per profile key.
    pub(crate) ports: std::collections::BTreeMap<String, DevicePorts>,
    pub(crate) inventory: Option<Inventory>,
    session: Option<DeviceSession>,
    /// The profile the session runs (ports applied).
    running: Option<Profile>,
    /// The hand the session's frames drive.
    driver: Option<HandDriver>,
    /// The finger radius set by hand (`None`: it follows the hand).
    pub(crate) radius_set: Option<f64>,
    /// Record every device session.
    pub(crate) record: bool,
    /// The trace to record to.
    pub(crate) record_to: String,
    /// Connect waits: the recording would replace this file.
    pub(crate) confirm_overwrite: Option<PathBuf>,
    /// Frames taken by the window, and when counting started.
    rate: (u64, Option<Instant>, f64),
    pub(crate) message: Option<String>,
    /// A trace file to replay, chosen in the panel.
    pub(crate) trace_path: String,
    /// The last tracker pose received (what recentering moves).
    last_pose: Option<TrackerPose>,
    pub(crate) calibration: CalibrationCapture,
    /// The hand size being edited.
    pub(crate) hand_edit: Option<HandSize>,
    /// The sides per metre being dragged.
    pub(crate) scale_edit: Option<f64>,
    /// The user's profile folder (`None`: none is listed or written; tests).
    profile_dir: Option<PathBuf>,
    /// `NENDO_STATUS_FILE` and when it was last written.
    status_file: Option<PathBuf>,
    status_written: Option<Instant>,
    /// Contacts the device hand has made (one undoable edit each).
    contacts: u64,
    /// The parts that press, chosen in the panel (`None`: every finger).
    pressing: Option<crate::hand::Fingers>,
    /// The profiles (keys) whose hand has been fitted: no automatic fit on their connect.
    fitted: std::collections::BTreeSet<String>,
    /// The view's anchor, for the automatic fit of a first connect.
    anchor: Option<ViewAnchor>,
    /// The clutch key is held.
    clutch: bool,
    /// Each sample's way from the port to the frame that shows it.
    latency: LatencyMeter,
    /// Called by the loop thread when samples arrive (the window's redraw request).
    waker: Option<DeviceWaker>,
    /// The symmetry group the device hand presses with (see `symmetry`).
    symmetry: symmetry::PressingSymmetry,
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
        .and_then(|f| f.parse::<FingerModel>().ok())
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
