//! Hand frames: what the device layer produces, one per device sample.
//!
//! A [`HandFrame`] is a timestamp, an optional tracker pose, optional glove joint angles, the
//! pressed buttons, and the state of each source. Units are fixed and documented here so that
//! every backend converts at the edge:
//!
//! - **time**: microseconds on the host's monotonic clock since the stream started
//!   ([`Timestamp`]);
//! - **position**: metres, in the tracker's own coordinate frame (its transmitter / source);
//!   the profile's [`WorldFromTracker`](crate::WorldFromTracker) maps it into the modeller's
//!   world;
//! - **orientation**: a unit quaternion rotating vectors from the hand sensor's frame into the
//!   tracker's frame;
//! - **joint angles**: radians of flexion (positive curls the finger toward the palm) or of
//!   abduction (positive spreads the fingers), per named [`Joint`].
//!
//! The hand sensor's frame, as the later hand model reads it: origin on the back of the hand
//! where the sensor sits, **+X along the middle finger toward its tip, +Y toward the thumb for
//! a right hand (toward the little finger for a left hand), +Z out of the back of the hand**.
//!
//! Every value in a frame has passed validation: finite, and inside the physical ranges
//! [`POSITION_LIMIT_M`] and [`ANGLE_LIMIT_RAD`]; quaternions are normalised. NaN never reaches
//! the geometry.

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};
use std::fmt;

use crate::DeviceError;

/// Largest tracker position accepted, in metres from the tracker's origin. Magnetic trackers
/// work within a few metres; anything beyond this is corrupt data.
pub const POSITION_LIMIT_M: f64 = 100.0;

/// Largest joint angle accepted, in radians either way. A finger joint never turns more than
/// half a turn; anything beyond is a bad calibration or corrupt data.
pub const ANGLE_LIMIT_RAD: f64 = std::f64::consts::PI;

/// How far a decoded quaternion's norm may be from 1 before it is rejected (device quaternions
/// carry 14 to 24 bits; a larger error means a corrupt record).
pub const QUATERNION_NORM_TOLERANCE: f64 = 0.02;

/// Microseconds on the host's monotonic clock since the stream (or recording) started.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize,
)]
pub struct Timestamp(pub u64);

impl Timestamp {
    /// A timestamp from microseconds.
    pub const fn from_micros(us: u64) -> Self {
        Timestamp(us)
    }

    /// The timestamp in microseconds.
    pub const fn as_micros(self) -> u64 {
        self.0
    }

    /// The timestamp in seconds.
    pub fn as_secs_f64(self) -> f64 {
        self.0 as f64 * 1e-6
    }

    /// Microseconds elapsed between `start` and now, on the monotonic clock.
    pub fn since(start: std::time::Instant) -> Self {
        Timestamp(u64::try_from(start.elapsed().as_micros()).unwrap_or(u64::MAX))
    }
}

macro_rules! joints {
    ($( $(#[$doc:meta])* $variant:ident = $name:literal, )*) => {
        /// A named hand joint measured by a glove sensor. The set is the union of what the
        /// CyberGlove (18 and 22 sensors) and the 5DT gloves (5 and 14 sensors) measure
        /// (`docs/design.md` §16 §1, §2); each glove maps its sensors onto these names through
        /// the profile's calibration table.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub enum Joint {
            $( $(#[$doc])* $variant, )*
        }

        impl Joint {
            /// Every joint, in index order.
            pub const ALL: [Joint; Joint::COUNT] = [$(Joint::$variant,)*];

            /// The joint's name in profiles and traces (snake case).
            pub const fn name(self) -> &'static str {
                match self { $(Joint::$variant => $name,)* }
            }

            /// The joint of a name used in profiles and traces.
            pub fn from_name(name: &str) -> Option<Joint> {
                match name { $($name => Some(Joint::$variant),)* _ => None }
            }
        }
    };
}

joints! {
    /// Rotation of the thumb across the palm (CyberGlove "thumb rotation").
    ThumbRoll = "thumb_roll",
    /// Thumb metacarpophalangeal flexion (5DT "thumb near").
    ThumbMcp = "thumb_mcp",
    /// Thumb interphalangeal flexion (5DT "thumb far").
    ThumbIp = "thumb_ip",
    /// Abduction between thumb and index finger.
    ThumbIndexAbduction = "thumb_index_abduction",
    /// Index metacarpophalangeal flexion.
    IndexMcp = "index_mcp",
    /// Index proximal interphalangeal flexion.
    IndexPip = "index_pip",
    /// Index distal interphalangeal flexion (22-sensor CyberGlove only).
    IndexDip = "index_dip",
    /// Middle metacarpophalangeal flexion.
    MiddleMcp = "middle_mcp",
    /// Middle proximal interphalangeal flexion.
    MiddlePip = "middle_pip",
    /// Middle distal interphalangeal flexion.
    MiddleDip = "middle_dip",
    /// Abduction between index and middle fingers.
    IndexMiddleAbduction = "index_middle_abduction",
    /// Ring metacarpophalangeal flexion.
    RingMcp = "ring_mcp",
    /// Ring proximal interphalangeal flexion.
    RingPip = "ring_pip",
    /// Ring distal interphalangeal flexion.
    RingDip = "ring_dip",
    /// Abduction between middle and ring fingers.
    MiddleRingAbduction = "middle_ring_abduction",
    /// Little-finger metacarpophalangeal flexion.
    PinkyMcp = "pinky_mcp",
    /// Little-finger proximal interphalangeal flexion.
    PinkyPip = "pinky_pip",
    /// Little-finger distal interphalangeal flexion.
    PinkyDip = "pinky_dip",
    /// Abduction between ring and little fingers.
    RingPinkyAbduction = "ring_pinky_abduction",
    /// Arching of the palm.
    PalmArch = "palm_arch",
    /// Wrist flexion (pitch).
    WristPitch = "wrist_pitch",
    /// Wrist abduction (yaw).
    WristYaw = "wrist_yaw",
}

impl Joint {
    /// Number of named joints.
    pub const COUNT: usize = 22;

    /// The joint's position in [`Joint::ALL`].
    pub const fn index(self) -> usize {
        self as usize
    }
}

impl fmt::Display for Joint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl Serialize for Joint {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for Joint {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        Joint::from_name(&name)
            .ok_or_else(|| serde::de::Error::custom(format!("unknown joint name `{name}`")))
    }
}

/// Glove joint angles in radians, for the joints the glove measures.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointAngles {
    angles: [f64; Joint::COUNT],
    present: u32,
}

impl JointAngles {
    /// No joint measured.
    pub const fn new() -> Self {
        JointAngles {
            angles: [0.0; Joint::COUNT],
            present: 0,
        }
    }

    /// Sets one joint's angle after checking it is finite and within [`ANGLE_LIMIT_RAD`].
    pub fn set(&mut self, joint: Joint, radians: f64) -> Result<(), DeviceError> {
        if !radians.is_finite() || radians.abs() > ANGLE_LIMIT_RAD {
            return Err(DeviceError::InvalidValue(format!(
                "angle of {joint} is {radians} rad (allowed: finite, within ±π)"
            )));
        }
        self.angles[joint.index()] = radians;
        self.present |= 1 << joint.index();
        Ok(())
    }

    /// Builder form of [`JointAngles::set`].
    pub fn with(mut self, joint: Joint, radians: f64) -> Result<Self, DeviceError> {
        self.set(joint, radians)?;
        Ok(self)
    }

    /// The angle of a joint, if the glove measures it.
    pub fn get(&self, joint: Joint) -> Option<f64> {
        (self.present & (1 << joint.index()) != 0).then(|| self.angles[joint.index()])
    }

    /// Whether no joint is measured.
    pub fn is_empty(&self) -> bool {
        self.present == 0
    }

    /// Number of measured joints.
    pub fn len(&self) -> usize {
        self.present.count_ones() as usize
    }

    /// The measured joints and their angles, in [`Joint::ALL`] order.
    pub fn iter(&self) -> impl Iterator<Item = (Joint, f64)> + '_ {
        Joint::ALL
            .into_iter()
            .filter_map(|j| self.get(j).map(|a| (j, a)))
    }
}

/// A 6-DoF tracker pose: position in metres and a unit orientation quaternion, both in the
/// tracker's frame (see the module docs for the conventions).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackerPose {
    /// Position of the hand sensor, metres.
    pub position: DVec3,
    /// Rotation from the hand sensor's frame to the tracker's frame (unit quaternion).
    pub orientation: DQuat,
}

impl TrackerPose {
    /// A validated pose: the position must be finite and within [`POSITION_LIMIT_M`], the
    /// quaternion finite with a norm within [`QUATERNION_NORM_TOLERANCE`] of 1; the quaternion
    /// is normalised.
    pub fn new(position: DVec3, orientation: DQuat) -> Result<Self, DeviceError> {
        if !position.is_finite() || position.abs().max_element() > POSITION_LIMIT_M {
            return Err(DeviceError::InvalidValue(format!(
                "tracker position {position} m (allowed: finite, within ±{POSITION_LIMIT_M} m)"
            )));
        }
        let norm = orientation.length();
        if !orientation.is_finite() || (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
            return Err(DeviceError::InvalidValue(format!(
                "tracker quaternion {orientation} has norm {norm} (allowed: 1 ± {QUATERNION_NORM_TOLERANCE})"
            )));
        }
        Ok(TrackerPose {
            position,
            orientation: orientation / norm,
        })
    }

    /// The identity pose at the tracker's origin.
    pub const IDENTITY: TrackerPose = TrackerPose {
        position: DVec3::ZERO,
        orientation: DQuat::IDENTITY,
    };
}

/// A glove sample: calibrated angles and the glove's switch, if it reports one.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GloveSample {
    /// Calibrated joint angles.
    pub angles: JointAngles,
    /// The glove's push switch (CyberGlove status byte), when the glove reports it.
    pub switch: Option<bool>,
}

/// The state of one input source (tracker or glove) as the stream sees it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum SourceState {
    /// The profile has no such source.
    #[default]
    Absent,
    /// Samples are arriving.
    Ok,
    /// The watchdog fired: the device is open but has sent nothing valid for longer than the
    /// profile's watchdog period. Its last value is withdrawn from frames.
    Silent,
    /// The device is gone (unplugged, port closed, open failed); the stream retries opening it
    /// and resumes when it is back.
    Disconnected,
}

impl SourceState {
    /// The state's token in traces.
    pub const fn token(self) -> &'static str {
        match self {
            SourceState::Absent => "none",
            SourceState::Ok => "ok",
            SourceState::Silent => "silent",
            SourceState::Disconnected => "lost",
        }
    }

    /// The state of a trace token.
    pub fn from_token(token: &str) -> Option<Self> {
        Some(match token {
            "none" => SourceState::Absent,
            "ok" => SourceState::Ok,
            "silent" => SourceState::Silent,
            "lost" => SourceState::Disconnected,
            _ => return None,
        })
    }
}

/// Per-source state of a frame, and which source produced it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct FrameStatus {
    /// State of the tracker.
    pub tracker: SourceState,
    /// State of the glove.
    pub glove: SourceState,
    /// The frame carries a new tracker sample (otherwise its pose, if any, is the last one held).
    pub tracker_fresh: bool,
    /// The frame carries a new glove sample (otherwise its angles, if any, are held).
    pub glove_fresh: bool,
}

/// Button bits of a [`HandFrame`].
pub mod buttons {
    /// Primary button: left mouse button, or the glove's switch.
    pub const PRIMARY: u32 = 1;
    /// Secondary button: right mouse button.
    pub const SECONDARY: u32 = 2;
    /// Middle mouse button.
    pub const MIDDLE: u32 = 4;
    /// The clutch: while held, the hand moves without touching the clay (the window's
    /// clutch key, stamped on the samples as they arrive so that a recording carries it).
    pub const CLUTCH: u32 = 8;
}

/// One hand frame: emitted at every device sample, holding the latest value of each source.
///
/// `pose` is `Some` only while the tracker is [`SourceState::Ok`]; `joints` only while the glove
/// is. A frame with a source in another state carries `None` for it, so a silent or unplugged
/// device can never leave a stale hand acting on the surface.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HandFrame {
    /// When the newest sample in the frame was read.
    pub time: Timestamp,
    /// The tracker pose, when the tracker is delivering.
    pub pose: Option<TrackerPose>,
    /// The glove's joint angles, when the glove is delivering.
    pub joints: Option<JointAngles>,
    /// Pressed buttons ([`buttons`] bits).
    pub buttons: u32,
    /// Source states and freshness.
    pub status: FrameStatus,
    /// The hand as joint poses, when the tracker slot is a skeleton source (a VMC receiver,
    /// [`crate::skeleton`]) and it is delivering; such a frame has no `pose` and no `joints`.
    pub skeleton: Option<crate::skeleton::Skeleton>,
}

impl HandFrame {
    /// Whether every source present in the profile is delivering.
    pub fn is_complete(&self) -> bool {
        let ok = |s: SourceState| matches!(s, SourceState::Ok | SourceState::Absent);
        ok(self.status.tracker) && ok(self.status.glove)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joint_names_round_trip_and_indices_match_all() {
        for (i, j) in Joint::ALL.into_iter().enumerate() {
            assert_eq!(j.index(), i);
            assert_eq!(Joint::from_name(j.name()), Some(j));
        }
        assert_eq!(Joint::from_name("elbow"), None);
    }

    #[test]
    fn nan_and_out_of_range_angles_are_rejected() {
        let mut a = JointAngles::new();
        assert!(a.set(Joint::IndexMcp, f64::NAN).is_err());
        assert!(a.set(Joint::IndexMcp, 4.0).is_err());
        assert!(a.is_empty());
        a.set(Joint::IndexMcp, 1.0).unwrap();
        assert_eq!(a.get(Joint::IndexMcp), Some(1.0));
        assert_eq!(a.get(Joint::IndexPip), None);
        assert_eq!(a.len(), 1);
    }

    #[test]
    fn poses_are_validated_and_normalised() {
        assert!(TrackerPose::new(DVec3::new(f64::NAN, 0.0, 0.0), DQuat::IDENTITY).is_err());
        assert!(TrackerPose::new(DVec3::splat(200.0), DQuat::IDENTITY).is_err());
        assert!(TrackerPose::new(DVec3::ZERO, DQuat::from_xyzw(0.0, 0.0, 0.0, 0.5)).is_err());
        let p = TrackerPose::new(DVec3::ONE, DQuat::from_xyzw(0.0, 0.0, 0.0, 1.01)).unwrap();
        assert!((p.orientation.length() - 1.0).abs() < 1e-15);
    }
}
