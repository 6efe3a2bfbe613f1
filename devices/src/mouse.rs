//! The mouse-driven hand, for modelling with the mouse alone.
//!
//! The window turns the cursor into a view ray (camera position and direction through the
//! cursor, in world coordinates) and passes it with the buttons and wheel; the hand sits on the
//! ray at an adjustable depth, pointing along it, in the pointing pose: index finger straight,
//! the other fingers and the thumb curled. Frames come out in world coordinates, so the mouse
//! profile's `world_from_tracker` is the identity.
//!
//! Orientation: the hand's +X (along the fingers) is the ray direction; its +Z (back of the
//! hand) is as close to the world's +Y (up) as the ray allows, so the palm faces down when
//! pointing at the horizon.

use glam::{DMat3, DQuat, DVec3};

use crate::profile::MouseProfile;
use crate::{
    DeviceError, FrameStatus, HandFrame, Joint, JointAngles, SourceState, Timestamp, TrackerPose,
};

/// A view ray through the cursor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewRay {
    /// Where the ray starts (the camera), world coordinates.
    pub origin: DVec3,
    /// Its direction (any non-zero length).
    pub direction: DVec3,
}

/// Mouse buttons, as [`crate::buttons`] bits.
pub type MouseButtons = u32;

/// The mouse-driven hand (see the module docs).
#[derive(Debug, Clone)]
pub struct MouseDevice {
    config: MouseProfile,
    depth: f64,
}

const CURLED: [Joint; 12] = [
    Joint::ThumbMcp,
    Joint::ThumbIp,
    Joint::MiddleMcp,
    Joint::MiddlePip,
    Joint::MiddleDip,
    Joint::RingMcp,
    Joint::RingPip,
    Joint::RingDip,
    Joint::PinkyMcp,
    Joint::PinkyPip,
    Joint::PinkyDip,
    Joint::PalmArch,
];

const STRAIGHT: [Joint; 3] = [Joint::IndexMcp, Joint::IndexPip, Joint::IndexDip];

impl MouseDevice {
    /// A hand at the profile's starting depth.
    pub fn new(config: MouseProfile) -> Self {
        MouseDevice {
            depth: config.depth,
            config,
        }
    }

    /// Current depth along the ray.
    pub fn depth(&self) -> f64 {
        self.depth
    }

    /// Moves the hand along the ray by wheel steps (positive = away), within the profile's range.
    pub fn wheel(&mut self, steps: f64) {
        if steps.is_finite() {
            let [near, far] = self.config.depth_range;
            self.depth = (self.depth + steps * self.config.wheel_step).clamp(near, far);
        }
    }

    /// The joint angles of the pointing pose.
    pub fn pointing_pose(&self) -> JointAngles {
        let mut a = JointAngles::new();
        let curl = self
            .config
            .curl
            .clamp(-crate::ANGLE_LIMIT_RAD, crate::ANGLE_LIMIT_RAD);
        for j in CURLED {
            // In range by the clamp above.
            let _ = a.set(j, curl);
        }
        for j in STRAIGHT {
            let _ = a.set(j, 0.0);
        }
        a
    }

    /// The hand frame for a cursor ray and buttons at `time`. A non-finite or zero-length ray
    /// is an error (and no frame).
    pub fn frame(
        &self,
        time: Timestamp,
        ray: ViewRay,
        buttons: MouseButtons,
    ) -> Result<HandFrame, DeviceError> {
        let Some(dir) = ray.direction.try_normalize() else {
            return Err(DeviceError::InvalidValue(format!(
                "view ray direction {}",
                ray.direction
            )));
        };
        if !ray.origin.is_finite() {
            return Err(DeviceError::InvalidValue(format!(
                "view ray origin {}",
                ray.origin
            )));
        }
        // Back of the hand toward world up, unless the ray is (nearly) vertical.
        let up = if dir.cross(DVec3::Y).length_squared() > 1e-12 {
            DVec3::Y
        } else {
            DVec3::Z
        };
        let y = up.cross(dir).normalize();
        let z = dir.cross(y);
        let orientation = DQuat::from_mat3(&DMat3::from_cols(dir, y, z));
        let pose = TrackerPose::new(ray.origin + self.depth * dir, orientation)?;
        Ok(HandFrame {
            time,
            pose: Some(pose),
            joints: Some(self.pointing_pose()),
            buttons,
            skeleton: None,
            status: FrameStatus {
                tracker: SourceState::Ok,
                glove: SourceState::Ok,
                tracker_fresh: true,
                glove_fresh: true,
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hand_rides_the_ray_and_points_along_it() {
        let mut hand = MouseDevice::new(MouseProfile::default());
        let ray = ViewRay {
            origin: DVec3::new(0.0, 1.0, 2.0),
            direction: DVec3::new(0.0, 0.0, -3.0),
        };
        let f = hand
            .frame(Timestamp(5), ray, crate::buttons::PRIMARY)
            .unwrap();
        let p = f.pose.unwrap();
        assert!((p.position - DVec3::new(0.0, 1.0, 1.5)).length() < 1e-12);
        assert!((p.orientation * DVec3::X - DVec3::NEG_Z).length() < 1e-12);
        assert!((p.orientation * DVec3::Z - DVec3::Y).length() < 1e-12);
        assert_eq!(f.joints.unwrap().get(Joint::IndexMcp), Some(0.0));
        hand.wheel(1000.0);
        assert_eq!(hand.depth(), 5.0);
        let down = ViewRay {
            origin: DVec3::ZERO,
            direction: DVec3::NEG_Y,
        };
        assert!(hand.frame(Timestamp(6), down, 0).is_ok());
        let bad = ViewRay {
            origin: DVec3::ZERO,
            direction: DVec3::ZERO,
        };
        assert!(hand.frame(Timestamp(7), bad, 0).is_err());
        let nan = ViewRay {
            origin: DVec3::NAN,
            direction: DVec3::X,
        };
        assert!(hand.frame(Timestamp(7), nan, 0).is_err());
    }
}
