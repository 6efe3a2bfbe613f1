//! What a glove user needs at the desk, around the live session:
//!
//! - **The hand fitted on the first connect.** The first time a glove profile's devices are
//!   connected (its key not yet in [`Settings::fitted`]), the hand is fitted to the model
//!   ([`nendo_devices::alignment::fit_scale`]: sides per metre so that the hand is
//!   [`nendo_devices::alignment::FIT_FRACTION`] of the model's size) before the devices
//!   start; the fit is saved into the user's copy of the profile (a shipped profile gets
//!   `NAME-mine.json`, selected from then on) and the profile is remembered as fitted, so the
//!   next connects reuse it (and a scale set by hand afterwards is kept).
//! - **The pressing parts** chosen in the Devices panel by name (`thumb`, `index`, `middle`,
//!   `ring`, `pinky`, `palm`, [`Part::name`]); every finger by default. Remembered in the
//!   settings ([`Settings::pressing`], written as `--finger` reads it) and used by the hand
//!   loop of every device session (a replayed trace presses with the parts its scene names).
//! - **The clutch key** ([`LiveInput::set_clutch`]): held, every frame taken carries
//!   [`nendo_devices::buttons::CLUTCH`] and the hand moves without touching (rule 10 of
//!   [`crate::hand::hand_loop`], which also takes a fist as the clutch).
//! - **Contact feedback** ([`LiveInput::feedback`]): while the hand presses, the patches it
//!   changed, how far the clay moved, and the part deepest in the clay
//!   ([`crate::editor::hand_input::Feedback`]).

use nendo_devices::profile::Input;
use nendo_devices::{Profile, alignment};

use crate::editor::document::Document;
use crate::editor::hand_input::Feedback;
use crate::editor::settings::Settings;
use crate::hand::{FingerModel, Fingers, Part};

use super::*;

impl LiveInput {
    /// The parts that press in device sessions (every finger unless chosen).
    #[must_use]
    pub fn pressing(&self) -> Fingers {
        self.pressing.unwrap_or(Fingers::ALL)
    }

    /// Chooses the parts that press (at least one), and rebuilds the running hand with them
    /// (ending its contact).
    pub fn set_pressing(&mut self, doc: &mut Document, parts: Fingers) {
        if parts.parts().next().is_none() {
            self.message = Some("at least one part of the hand must press".into());
            return;
        }
        self.pressing = Some(parts);
        self.rebuild_hand(doc);
    }

    /// Adds `part` to the pressing parts or takes it out (the panel's checkboxes).
    pub fn toggle_pressing(&mut self, doc: &mut Document, part: Part) {
        let now = self.pressing();
        let next = Part::ALL
            .into_iter()
            .filter(|p| (*p == part) != now.contains(*p))
            .fold(None::<Fingers>, |set, p| {
                Some(set.map_or_else(|| Fingers::one(p), |s| s.with(p)))
            });
        match next {
            Some(set) => self.set_pressing(doc, set),
            None => self.message = Some("at least one part of the hand must press".into()),
        }
    }

    /// The finger model of a live profile's hand: the view ray for the mouse, else the parts
    /// chosen.
    #[must_use]
    pub fn finger_for(&self, profile: &Profile) -> FingerModel {
        match FingerModel::for_profile(profile) {
            FingerModel::Hand(_) => FingerModel::Hand(self.pressing()),
            ray => ray,
        }
    }

    /// Whether the profile of `key` has had its hand fitted (automatically or by hand).
    #[must_use]
    pub fn is_fitted(&self, key: &str) -> bool {
        self.fitted.contains(key)
    }

    /// The model point under the view centre and the model's size, for the next connect's
    /// automatic fit (the panel and the modeller keep it current).
    pub fn set_view_anchor(&mut self, anchor: ViewAnchor) {
        self.anchor = Some(anchor);
    }

    /// Before the first connect of a glove profile: fits the hand to the model, saves the
    /// fit into the user's profile and remembers the profile as fitted (see the module docs).
    /// Returns what it did, for the panel's message.
    pub(super) fn fit_on_first_connect(&mut self) -> Option<String> {
        let entry = self.entries.get(self.selected)?;
        if !matches!(entry.profile.input, Input::Devices { .. }) || self.is_fitted(&entry.key()) {
            return None;
        }
        let anchor = self.anchor?;
        let key = entry.key();
        let wft = entry.profile.world_from_tracker;
        let fitted = alignment::fit_scale(&entry.profile.hand, anchor.extent)
            .and_then(|s| alignment::rescale_about(&wft, glam::DVec3::ZERO, s));
        let w = match fitted {
            Ok(w) => w,
            Err(e) => return Some(format!("fit the hand: {e}")),
        };
        if let Some(e) = self.entries.get_mut(self.selected) {
            e.profile.world_from_tracker = w;
        }
        let what = format!(
            "the hand fitted to the model ({:.2} sides per metre)",
            w.scale
        );
        self.save_profile(&what);
        self.fitted.insert(key);
        if let Some(e) = self.entries.get(self.selected) {
            self.fitted.insert(e.key());
        }
        self.message.clone()
    }

    /// Holds the clutch (the window's clutch key) or lets it go: see the module docs.
    pub fn set_clutch(&mut self, held: bool) {
        self.clutch = held;
        if let Some(s) = &self.session {
            s.shared
                .clutch
                .store(held, std::sync::atomic::Ordering::Relaxed);
        }
    }

    /// Whether the clutch key is held.
    #[must_use]
    pub fn clutch_key(&self) -> bool {
        self.clutch
    }

    /// Whether the clutch holds the hand off the clay: the key, or the glove's fist at the
    /// last frame.
    #[must_use]
    pub fn clutched(&self) -> bool {
        self.driver
            .as_ref()
            .is_some_and(|d| self.clutch || d.hand_loop().fist())
    }

    /// The contact in progress as the window shows it, if the device hand presses.
    #[must_use]
    pub fn feedback(&self) -> Option<&Feedback> {
        self.driver.as_ref().and_then(HandDriver::feedback)
    }

    /// The desk's part of the settings, into `settings`.
    pub(super) fn store_desk(&self, settings: &mut Settings) {
        settings.pressing = self.pressing.map(|f| f.to_string());
        settings.fitted = self.fitted.iter().cloned().collect();
    }

    /// The desk's part of the remembered settings (a pressing set that does not parse is
    /// dropped with a message).
    pub(super) fn apply_desk(&mut self, settings: &Settings) {
        self.fitted = settings.fitted.iter().cloned().collect();
        self.pressing = match settings.pressing.as_deref().map(str::parse::<Fingers>) {
            Some(Ok(f)) if f.parts().next().is_some() => Some(f),
            Some(Ok(_)) | None => None,
            Some(Err(e)) => {
                self.message = Some(format!("the remembered pressing parts: {e}"));
                None
            }
        };
    }
}
