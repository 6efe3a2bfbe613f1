//! The hand loop's settings ([`HandOptions`]): the finger radius, which parts press, and the
//! thresholds of contact, stroke, grip and pinch. Lengths are in world units ("side"), but for
//! the pinch's, which are fractions of the hand's own index finger: a pinch is a thing the
//! hand does, the same gesture at any tracker-to-world scale.

use super::HandError;
use super::parts::FingerModel;

/// The loop's settings (lengths in world units, "side").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandOptions {
    /// The finger radius `r_f`: the fingertip capsule's radius and the shape function's.
    pub finger_radius: f64,
    /// Which finger touches.
    pub finger: FingerModel,
    /// A contact starts when the tip is this far past the surface; depth changes at or below
    /// it are not applied.
    pub min_depth: f64,
    /// Motion across the finger above this, while in contact, adds a placement: the contact
    /// becomes a draw-a-line stroke.
    pub stroke_step: f64,
    /// How close to the surface the tip must be for the grip to catch.
    pub grip_distance: f64,
    /// Thumb and index fingertips closer than this fraction of the hand's index finger
    /// length ([`super::Hand::finger_length`], knuckle to tip) — both tips no farther than
    /// that from the surface, on the same side of it — take hold of the clay instead of
    /// pressing (rule 9). A fraction of the hand, not a length in sides: the same pinch takes
    /// hold whatever the tracker-to-world scale.
    pub pinch_closed: f64,
    /// A pinch lets go when its tips are farther apart than this fraction of the index
    /// finger's length (the hysteresis: at least [`HandOptions::pinch_closed`], so that a
    /// pinch held at the threshold does not flicker).
    pub pinch_open: f64,
}

/// The default [`HandOptions::pinch_closed`]: a quarter of the index finger's length — 2 cm
/// of the default hand (its index 8.1 cm long), 0.4 side at the scripted traces' 20 sides per
/// metre, 0.02 side at `cyberglove2-18-fastrak`'s 1 side per metre.
pub const DEFAULT_PINCH_CLOSED: f64 = 0.25;

/// The default [`HandOptions::pinch_open`]: 1.5 times [`DEFAULT_PINCH_CLOSED`] (3 cm of the
/// default hand).
pub const DEFAULT_PINCH_OPEN: f64 = 0.375;

/// The default finger radius `r_f`, in sides: the hand loop's in the window and in
/// `nendo replay` alike, so a trace gives the same surface in both (the shipped traces and
/// their figures are made with it).
pub const DEFAULT_FINGER_RADIUS: f64 = 1.0;

impl Default for HandOptions {
    fn default() -> Self {
        Self {
            finger_radius: DEFAULT_FINGER_RADIUS,
            finger: FingerModel::default(),
            min_depth: 1e-4,
            stroke_step: 5e-3,
            grip_distance: 0.05,
            pinch_closed: DEFAULT_PINCH_CLOSED,
            pinch_open: DEFAULT_PINCH_OPEN,
        }
    }
}

impl HandOptions {
    /// Checks every number.
    ///
    /// # Errors
    /// [`HandError::Options`] naming the first bad value.
    pub fn validate(&self) -> Result<(), HandError> {
        for (name, value) in [
            ("finger radius", self.finger_radius),
            ("grip distance", self.grip_distance),
            ("pinch closed", self.pinch_closed),
            ("pinch open", self.pinch_open),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(HandError::Options(format!(
                    "{name} must be a positive number, not {value}"
                )));
            }
        }
        for (name, value) in [
            ("min depth", self.min_depth),
            ("stroke step", self.stroke_step),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(HandError::Options(format!(
                    "{name} must be a non-negative number, not {value}"
                )));
            }
        }
        if self.pinch_open < self.pinch_closed {
            return Err(HandError::Options(format!(
                "pinch open ({}) must be at least pinch closed ({})",
                self.pinch_open, self.pinch_closed
            )));
        }
        Ok(())
    }
}
