//! The hand loop's settings ([`HandOptions`]): the finger radius, which parts press, and the
//! thresholds of contact, stroke, grip and pinch.

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
    /// Thumb and index fingertips closer than this (and on the same side of the clay, near
    /// it) take hold of the clay instead of pressing (rule 9); they let go beyond 1.5 times
    /// it.
    pub pinch_distance: f64,
}

/// The default pinch distance, in sides: 0.4 (2 cm of a hand at the scripted traces' 20 sides
/// per metre).
pub const DEFAULT_PINCH_DISTANCE: f64 = 0.4;

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
            pinch_distance: DEFAULT_PINCH_DISTANCE,
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
            ("pinch distance", self.pinch_distance),
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
        Ok(())
    }
}
