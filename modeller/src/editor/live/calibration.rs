//! Alignment and glove calibration: the tracker's frame set to the model (recentred, scaled,
//! the hand fitted), the calibration poses captured and fitted, both written into the user's
//! profile ([`nendo_devices::alignment`], [`nendo_devices::glove_calibration`]).

use std::time::Instant;

use glam::DVec3;
use nendo_devices::glove_calibration::{CalibrationPose, PoseSamples, SensorFit, calibrate_glove};
use nendo_devices::{HandFrame, HandSize, WorldFromTracker, alignment, profile};

use crate::editor::document::Document;
use crate::editor::hand_input::HandDriver;
use crate::hand::FingerModel;

use super::*;

/// The glove calibration in progress: the samples captured per pose.
#[derive(Debug, Default)]
pub(crate) struct CalibrationCapture {
    pub(crate) samples: PoseSamples,
    /// The pose being captured and when the capture ends.
    pub(crate) capturing: Option<(CalibrationPose, Instant)>,
    /// The last result, for the panel.
    pub(crate) result: Option<String>,
}

impl LiveInput {
    // --- Alignment and calibration -----------------------------------------------------

    /// Replaces the selected profile's transform (and the running session's hand), and saves
    /// the profile into the user's folder.
    pub(super) fn set_alignment(&mut self, doc: &mut Document, wft: WorldFromTracker, what: &str) {
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
    pub(crate) fn rebuild_hand(&mut self, doc: &mut Document) {
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
    pub(crate) fn recenter(&mut self, doc: &mut Document, anchor: &ViewAnchor) {
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
    pub(crate) fn set_scale(&mut self, doc: &mut Document, scale: f64) {
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
    pub(crate) fn fit_hand(&mut self, doc: &mut Document, anchor: &ViewAnchor) {
        let Some(entry) = self.entries.get(self.selected) else {
            return;
        };
        match alignment::fit_scale(&entry.profile.hand, anchor.extent) {
            Ok(s) => self.set_scale(doc, s),
            Err(e) => self.message = Some(format!("fit the hand: {e}")),
        }
    }

    /// Applies the edited hand size.
    pub(crate) fn apply_hand(&mut self, doc: &mut Document, hand: HandSize) {
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
    pub(crate) fn capture_pose(&mut self, pose: CalibrationPose) {
        self.calibration.samples.clear(pose);
        self.calibration.capturing = Some((pose, Instant::now() + CAPTURE));
        self.calibration.result = None;
    }

    pub(super) fn capture(&mut self, frames: &[HandFrame]) {
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
    pub(crate) fn finish_calibration(&mut self, doc: &mut Document) {
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
    pub(super) fn save_profile(&mut self, what: &str) -> bool {
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
}
