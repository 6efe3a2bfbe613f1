//! Aligning the tracker with the model: the profile's `world_from_tracker`,
//! `p_world = t + s · (R · p_tracker)` ([`WorldFromTracker`]), adjusted so the hand is where
//! and as large as the user wants it.
//!
//! - **Recenter** ([`recenter`]): the tracker's current position `p` is to appear at the world
//!   point `c`; rotation and scale stay, the translation becomes `t' = c − s · (R · p)`.
//! - **Scale** ([`rescale_about`]): `s` becomes `s'` with the hand's current world position
//!   `w = t + s · (R · p)` kept: `t' = w − s' · (R · p)`.
//! - **Fit the hand to the model** ([`fit_scale`]): `s` such that the hand's length (wrist
//!   crease to the middle fingertip, [`hand_length`], metres) is [`FIT_FRACTION`] of the
//!   model's largest extent: `s = FIT_FRACTION · extent / hand_length`. On the default 10-side
//!   plane a typical hand (0.186 m) becomes 4 sides long, 21.5 sides per metre.
//!
//! Limits: the rotation is never changed here (it is the profile's; the tracker's axes are a
//! property of its mounting); recentering uses the tracker's position, i.e. the sensor on the
//! back of the hand, not a fingertip.

use glam::DVec3;

use crate::DeviceError;
use crate::profile::{HandSize, WorldFromTracker};

/// The part of the model's largest extent that [`fit_scale`] makes the hand.
pub const FIT_FRACTION: f64 = 0.4;

/// Wrist crease to the tip of the middle finger, metres.
pub fn hand_length(hand: &HandSize) -> f64 {
    hand.palm_length + hand.middle.proximal + hand.middle.middle + hand.middle.distal
}

/// The transform with the tracker position `tracker_position` (metres) mapped to `target`
/// (world); rotation and scale unchanged.
///
/// # Errors
/// [`DeviceError::InvalidValue`] when a position is not finite or the result fails
/// [`WorldFromTracker::validate`].
pub fn recenter(
    wft: &WorldFromTracker,
    tracker_position: DVec3,
    target: DVec3,
) -> Result<WorldFromTracker, DeviceError> {
    if !(tracker_position.is_finite() && target.is_finite()) {
        return Err(DeviceError::InvalidValue(format!(
            "recenter from {tracker_position} to {target}: positions must be finite"
        )));
    }
    let t = target - wft.scale * (wft.rotation() * tracker_position);
    let out = WorldFromTracker {
        translation: t.to_array(),
        ..*wft
    };
    out.validate()?;
    Ok(out)
}

/// The transform with scale `scale` (world units per metre), the hand at `tracker_position`
/// staying where it is in the world.
///
/// # Errors
/// [`DeviceError::InvalidValue`] for a scale that is not finite and positive, or a position
/// that is not finite.
pub fn rescale_about(
    wft: &WorldFromTracker,
    tracker_position: DVec3,
    scale: f64,
) -> Result<WorldFromTracker, DeviceError> {
    if !(scale.is_finite() && scale > 0.0) {
        return Err(DeviceError::InvalidValue(format!(
            "scale {scale} world units per metre (needs a finite positive number)"
        )));
    }
    let world = wft.translation() + wft.scale * (wft.rotation() * tracker_position);
    let scaled = WorldFromTracker { scale, ..*wft };
    recenter(&scaled, tracker_position, world)
}

/// The scale (world units per metre) that makes `hand` [`FIT_FRACTION`] of `extent` (world
/// units, the model's largest extent).
///
/// # Errors
/// [`DeviceError::InvalidValue`] for an extent that is not finite and positive, or a hand that
/// fails [`HandSize::validate`].
pub fn fit_scale(hand: &HandSize, extent: f64) -> Result<f64, DeviceError> {
    hand.validate()?;
    if !(extent.is_finite() && extent > 0.0) {
        return Err(DeviceError::InvalidValue(format!(
            "model extent {extent} (needs a finite positive number)"
        )));
    }
    Ok(FIT_FRACTION * extent / hand_length(hand))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TrackerPose;
    use glam::DQuat;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random_wft(rng: &mut ChaCha8Rng) -> WorldFromTracker {
        let axis = DVec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        )
        .normalize_or(DVec3::Z);
        let q = DQuat::from_axis_angle(axis, rng.gen_range(-3.0..3.0));
        WorldFromTracker {
            translation: [
                rng.gen_range(-5.0..5.0),
                rng.gen_range(-5.0..5.0),
                rng.gen_range(-5.0..5.0),
            ],
            rotation_wxyz: [q.w, q.x, q.y, q.z],
            scale: rng.gen_range(0.5..50.0),
        }
    }

    fn at(w: &WorldFromTracker, p: DVec3) -> DVec3 {
        w.apply(&TrackerPose {
            position: p,
            orientation: DQuat::IDENTITY,
        })
        .0
    }

    #[test]
    fn recenter_maps_the_hand_to_the_target_and_keeps_the_rest() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for _ in 0..100 {
            let w = random_wft(&mut rng);
            let p = DVec3::new(
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
            );
            let c = DVec3::new(rng.gen_range(-9.0..9.0), 0.3, rng.gen_range(-9.0..9.0));
            let r = recenter(&w, p, c).expect("recentred");
            assert!((at(&r, p) - c).length() < 1e-9);
            assert_eq!((r.rotation_wxyz, r.scale), (w.rotation_wxyz, w.scale));
            // Another tracker point moves by the same displacement in both transforms.
            let q = p + DVec3::new(0.1, -0.05, 0.02);
            let d0 = at(&w, q) - at(&w, p);
            let d1 = at(&r, q) - at(&r, p);
            assert!((d0 - d1).length() < 1e-9);
        }
        assert!(recenter(&WorldFromTracker::default(), DVec3::NAN, DVec3::ZERO).is_err());
    }

    #[test]
    fn rescaling_keeps_the_hand_in_place_and_scales_its_motion() {
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        for _ in 0..100 {
            let w = random_wft(&mut rng);
            let p = DVec3::new(0.2, -0.1, 0.4);
            let s = rng.gen_range(1.0..100.0);
            let r = rescale_about(&w, p, s).expect("rescaled");
            assert!((at(&r, p) - at(&w, p)).length() < 1e-9);
            let q = p + DVec3::X * 0.01;
            let moved = (at(&r, q) - at(&r, p)).length();
            assert!((moved - 0.01 * s).abs() < 1e-9 * s);
        }
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(rescale_about(&WorldFromTracker::default(), DVec3::ZERO, bad).is_err());
        }
    }

    #[test]
    fn the_fitted_hand_is_the_fraction_of_the_model() {
        let hand = HandSize::default();
        let s = fit_scale(&hand, 10.0).expect("fits");
        assert!((s * hand_length(&hand) - FIT_FRACTION * 10.0).abs() < 1e-12);
        assert!((hand_length(&hand) - 0.186).abs() < 1e-12);
        assert!(fit_scale(&hand, 0.0).is_err());
        assert!(fit_scale(&hand, f64::NAN).is_err());
    }
}
