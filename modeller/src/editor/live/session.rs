//! The device session: connecting the selected profile's devices (or replaying a trace),
//! recording, each window frame's samples run through the hand loop on the document, the
//! hand drawn, and what the panel shows of it.

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use nendo_devices::profile::{Input, MouseProfile};
use nendo_devices::{DeviceStatus, HandFrame, HandStream, Profile, StreamOptions, TrackerPose};

use crate::editor::document::Document;
use crate::editor::hand_input::HandDriver;
use crate::hand::scene::Scene;
use crate::hand::{DEFAULT_FINGER_RADIUS, FingerModel};
use crate::render::{LineBatch, SphereInstance};
use crate::surface::SurfaceError;

use super::inbox::*;
use super::*;

impl LiveInput {
    /// True while a session runs.
    #[must_use]
    pub fn is_connected(&self) -> bool {
        self.session.is_some()
    }

    /// True while the device hand is in a contact (the display then keeps its segment counts,
    /// as during a mouse gesture, and re-tessellates only the changed patches).
    #[must_use]
    pub fn in_contact(&self) -> bool {
        self.driver
            .as_ref()
            .is_some_and(|d| d.hand_loop().touch() != crate::hand::Touch::Free)
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
        self.release_symmetry();
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
    pub(super) fn record_path(&self) -> Option<PathBuf> {
        let t = self.record_to.trim();
        (self.record && !t.is_empty()).then(|| PathBuf::from(t))
    }

    /// The Connect button: opens the devices of the selected profile, or, for the mouse
    /// profile, returns its settings for the Hand tool (stopping any device session).
    pub(crate) fn connect_or_mouse(&mut self, doc: &mut Document) -> Option<MouseProfile> {
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
    pub(crate) fn connect_recording(&mut self, doc: &mut Document, record: Option<PathBuf>) {
        self.confirm_overwrite = None;
        // The first connect of a glove profile fits the hand to the model (desk.rs); the
        // fit may select the user's copy it was saved to.
        let fitted = self.fit_on_first_connect();
        let Some(profile) = self.selected_profile() else {
            return;
        };
        if let Some(e) = self.listen_error() {
            self.message = Some(e);
            return;
        }
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
        // The group the session presses with, when it is fixed: a replay's scene's, or the
        // window's now for a recording (the `symmetry` module docs).
        let plan = match self.plan_symmetry(doc, stream.source_header(), record.is_some()) {
            Ok(plan) => plan,
            Err(e) => {
                self.message = Some(e);
                return;
            }
        };
        // Mismatches the devices worked around (a glove for the other hand) stay on show.
        let warnings = (!stream.warnings().is_empty()).then(|| stream.warnings().join("; "));
        // The recording names the scene it is made on: the document's model as it is now (before
        // the group makes it invariant, as `nendo replay` does it again), the hand's finger,
        // radius and filter, and the group the session presses with.
        let mut scene = Scene {
            filter: Some(*driver.hand_loop().filter().settings()),
            ..Scene::of_window(doc.model(), finger, radius)
        };
        if let Some(plan) = &plan {
            plan.name_in(&mut scene);
        }
        // The recording marks what the hand loop's gate holds: the same settings.
        let gate = *driver.hand_loop().filter().settings();
        let record = match record {
            Some(path) => match scene.to_text() {
                Ok(scene) => Some((path, &profile, Some(scene), gate)),
                Err(e) => {
                    self.message = Some(format!("cannot record the scene: {e}"));
                    return;
                }
            },
            None => None,
        };
        match DeviceSession::start(stream, record, self.clutch) {
            Ok(mut s) => {
                *lock(&s.shared.waker) = self.waker.clone();
                self.latency.clear();
                s.replay = replay;
                self.session = Some(s);
                self.driver = Some(driver);
                self.running = Some(profile);
                self.message = match (fitted, warnings) {
                    (Some(f), Some(w)) => Some(format!("{f}; {w}")),
                    (f, w) => f.or(w),
                };
                self.set_clutch(self.clutch);
                if let Err(e) = self.fix_symmetry(doc, plan) {
                    self.disconnect();
                    self.message = Some(e);
                }
            }
            Err(e) => self.message = Some(e.to_string()),
        }
        self.rate = (0, Some(Instant::now()), 0.0);
        self.write_status(true);
    }

    /// The hand for a stream: a replay reads its frames with the trace's header (its hand
    /// and transform), as `nendo replay` does; live devices with the profile's.
    pub(super) fn driver_for(
        &mut self,
        stream: &HandStream,
        profile: &Profile,
    ) -> Option<(HandDriver, FingerModel, f64)> {
        let (driver, finger, radius) = match stream.source_header() {
            Some(h) => self.trace_driver(h),
            None => {
                let finger = self.finger_for(profile);
                let radius = self.radius(profile, false);
                (
                    HandDriver::new(profile.hand, profile.world_from_tracker, finger, radius)
                        .map(|d| d.with_filter(profile.filter)),
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

    /// The hand of a replayed trace, as `nendo replay` reads it with no other argument: the
    /// trace's hand and transform, its scene's finger ([`trace_finger`]), finger radius (unless
    /// set in the panel; without one the library's default) and filter.
    fn trace_driver(
        &self,
        h: &nendo_devices::TraceHeader,
    ) -> (Result<HandDriver, crate::hand::HandError>, FingerModel, f64) {
        let finger = trace_finger(h);
        let radius = self.radius_set.unwrap_or_else(|| {
            Scene::of_trace(h)
                .ok()
                .flatten()
                .and_then(|s| s.finger_radius)
                .unwrap_or(DEFAULT_FINGER_RADIUS)
        });
        let filter = crate::hand::filter::for_trace(h, finger);
        (
            HandDriver::new(h.hand, h.world_from_tracker, finger, radius)
                .map(|d| d.with_filter(filter)),
            finger,
            radius,
        )
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

    /// Plays a recorded trace as if it came from the devices, streamed frame by frame as
    /// `nendo replay` reads it ([`HandStream::replay_file`]): a trace of any length in the
    /// memory of one frame line. A header that does not read is refused at once with a
    /// message; a frame line that is an error (over 1 MB, or malformed before an `end` line)
    /// ends the replay there, and the message when the stream ends names the file and line
    /// (as it says what an interrupted recording dropped).
    pub(crate) fn replay(&mut self, path: &Path, doc: &mut Document) {
        self.disconnect_from(doc);
        self.rate = (0, Some(Instant::now()), 0.0);
        let stream = match HandStream::replay_file(path, 1.0, false, 1024) {
            Ok(s) => s,
            Err(e) => {
                self.message = Some(format!("{}: {e}", path.display()));
                return;
            }
        };
        let Some(h) = stream.source_header() else {
            return;
        };
        let driver = match self.trace_driver(h).0 {
            Ok(d) => d,
            Err(e) => {
                self.message = Some(e.to_string());
                return;
            }
        };
        // The trace's scene's group, whatever the window's toggle says (`symmetry` docs).
        let plan = match self.plan_symmetry(doc, Some(h), false) {
            Ok(plan) => plan,
            Err(e) => {
                self.message = Some(format!("{}: {e}", path.display()));
                return;
            }
        };
        match DeviceSession::start(stream, None, self.clutch) {
            Ok(mut s) => {
                *lock(&s.shared.waker) = self.waker.clone();
                self.latency.clear();
                s.replay = Some(path.to_path_buf());
                self.session = Some(s);
                self.driver = Some(driver);
                self.set_clutch(self.clutch);
                if let Err(e) = self.fix_symmetry(doc, plan) {
                    self.disconnect();
                    self.message = Some(e);
                }
            }
            Err(e) => self.message = Some(e.to_string()),
        }
    }

    /// Waits at most `within` for a device frame newer than those already in the inbox — the
    /// frame's latch (the `latency` module docs, step 4) — and says whether one came. Returns
    /// at once without a session or once the session has finished.
    pub fn latch(&self, within: Duration) -> bool {
        let Some(session) = &self.session else {
            return false;
        };
        if lock(&session.shared.status).finished {
            return false;
        }
        let inbox = lock(&session.shared.inbox);
        let had = inbox.len();
        let (inbox, _) = session
            .shared
            .arrived
            .wait_timeout_while(inbox, within, |i| i.len() <= had)
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        inbox.len() > had
    }

    /// Takes every frame the loop received since the last call and runs them, in order,
    /// through the hand against `doc`; returns why the surface refused a frame, if it did.
    pub fn poll(&mut self, doc: &mut Document) -> Option<SurfaceError> {
        let Some(session) = &self.session else {
            self.write_status(false);
            return None;
        };
        // `finished` first: the loop thread sets it after putting the last frames in the
        // inbox, so a session seen finished here has nothing left behind the take below.
        let (finished, ended) = {
            let status = lock(&session.shared.status);
            (status.finished, status.ended.clone())
        };
        let stamped = std::mem::take(&mut *lock(&session.shared.inbox));
        let taken = Instant::now();
        let mut refused = None;
        if let Some(driver) = &mut self.driver {
            let mut samples = Vec::with_capacity(stamped.len());
            for s in &stamped {
                // Between contacts the hand takes up the group its next contact presses with.
                self.symmetry.take_up(driver, doc);
                let revision = doc.revision();
                driver.feed(doc, &s.frame);
                samples.push((s.arrival, Instant::now(), doc.revision() != revision));
            }
            driver.measure(doc);
            self.latency.took(taken, &samples, Instant::now());
            refused = driver.take_refused();
            self.contacts = driver.contacts();
        }
        let frames: Vec<HandFrame> = stamped.iter().map(|s| s.frame).collect();
        // A skeleton source's hand is where its palm is (for Recenter).
        let palm = |f: &nendo_devices::HandFrame| {
            let s = f.skeleton.as_ref()?;
            let p = s.get(nendo_devices::HandJoint::Palm)?;
            TrackerPose::new(p.position, p.orientation).ok()
        };
        if let Some(pose) = frames.iter().rev().find_map(|f| f.pose.or_else(|| palm(f))) {
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
            // A replay's end says why it ended early, if it did.
            self.message = Some(match ended {
                Some(why) => format!("the stream ended: {why}"),
                None => "the stream ended".into(),
            });
            self.end_contact(doc);
            if let Some(mut s) = self.session.take() {
                s.stop();
            }
            self.release_symmetry();
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
    pub(crate) fn device_status(&self) -> Option<(Vec<DeviceStatus>, Option<String>, bool)> {
        let s = self.session.as_ref()?;
        let status = lock(&s.shared.status);
        Some((
            status.devices.clone(),
            status.recording_error.clone(),
            s.replay.is_some(),
        ))
    }

    /// `describe — N s; frames, rate`, the recording and a fixed symmetry group, for the panel.
    pub(crate) fn session_line(&self) -> Option<String> {
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
        let symmetry = self
            .symmetry_note()
            .map(|n| format!("; {n}"))
            .unwrap_or_default();
        Some(format!(
            "{what} — {:.0} s, {} frames, {:.1} frames/s{recording}{symmetry}",
            s.started.elapsed().as_secs_f64(),
            s.shared.frames.load(Ordering::Relaxed),
            self.rate.2
        ))
    }

    /// The running live profile (devices or a skeleton source, not a replay).
    pub(crate) fn running_devices(&self) -> Option<&Profile> {
        self.running
            .as_ref()
            .filter(|p| matches!(p.input, Input::Devices { .. } | Input::Skeleton(_)))
    }

    /// The last tracker pose.
    pub(crate) fn last_pose(&self) -> Option<TrackerPose> {
        self.last_pose
    }

    /// Calls `waker` whenever device samples arrive (the window: a redraw request), for this
    /// session and the next ones.
    pub fn set_waker(&mut self, waker: DeviceWaker) {
        if let Some(s) = &self.session {
            *lock(&s.shared.waker) = Some(waker.clone());
        }
        self.waker = Some(waker);
    }

    /// Contacts the device hand has made in this session (one undoable edit each).
    #[must_use]
    pub fn contacts(&self) -> u64 {
        self.contacts
    }

    /// The device samples' latency record (see [`LatencyMeter`]).
    #[must_use]
    pub fn latency(&self) -> &LatencyMeter {
        &self.latency
    }

    /// The latency record, for the window to mark a frame's steps (or a bench to widen it).
    pub fn latency_mut(&mut self) -> &mut LatencyMeter {
        &mut self.latency
    }
}
