//! Skeleton hands: a hand as joint poses, in the OpenXR layout (`XR_EXT_hand_tracking`, 26
//! joints), from any source that tracks joints rather than bend angles — the VMC protocol
//! ([`crate::vmc`]) today, an OpenXR runtime later.
//!
//! ## The joints
//!
//! [`HandJoint`] lists the 26 joints in OpenXR's order: the palm (the centre of the middle
//! finger's metacarpal), the wrist, the thumb's metacarpal (its carpometacarpal joint),
//! proximal (MCP), distal (IP) and tip, and for each of the four fingers its metacarpal (the
//! base of the metacarpal bone, by the wrist), proximal (the knuckle, MCP), intermediate (PIP),
//! distal (DIP) and tip. A joint's pose is the position of the joint and the orientation of
//! the bone that starts there.
//!
//! ## Units and frames
//!
//! As for a tracker pose ([`crate::frame`]): positions in metres in the source's frame (the
//! "tracker" frame, right-handed, +Z up for the VMC receiver), orientations as unit
//! quaternions rotating the joint's frame into that frame; the profile's
//! [`WorldFromTracker`](crate::WorldFromTracker) maps them into the modeller's world. The
//! palm's orientation follows the hand sensor's convention of [`crate::frame`]: +X toward the
//! middle finger, +Y toward the thumb of a right hand (the little finger of a left one), +Z out
//! of the back of the hand; other joints carry the orientation their source gives (for VMC,
//! the sender's bone rotations), which the hand model does not read.
//!
//! ## Validity
//!
//! Each joint is [`JointSource::Measured`] (the source sent it), [`JointSource::Made`]
//! (derived here from measured joints, by the rules below) or [`JointSource::Missing`]. The
//! rules for the joints a source lacks ([`Skeleton::make_missing`]):
//!
//! - **a tip**: the distal joint `D` extended along the intermediate → distal direction (for
//!   the thumb, proximal → distal) by the hand model's distal length `l₃`:
//!   `T = D + l₃ · (D − I)/|D − I|`, oriented as the distal joint;
//! - **a finger's metacarpal**: the wrist, oriented as the wrist;
//! - **the palm**: midway between the wrist `W` and the middle finger's knuckle `K`,
//!   `(W + K)/2`, oriented by the hand frame `x̂ = (K − W)/|K − W|`,
//!   `ŷ ∝ s·(I₁ − P₁)` made orthogonal to `x̂` (`I₁`, `P₁` the index's and little finger's
//!   knuckles, `s = +1` for a right hand, `−1` for a left one), `ẑ = x̂ × ŷ`.
//!
//! Every value in a [`Skeleton`] has passed validation: positions finite and within
//! [`POSITION_LIMIT_M`], quaternions finite and normalised.

use std::fmt;
use std::time::Duration;

use glam::{DMat3, DQuat, DVec3};

use crate::DeviceError;
use crate::device::DeviceStats;
use crate::frame::{POSITION_LIMIT_M, QUATERNION_NORM_TOLERANCE};
use crate::profile::{HandSize, Side};

macro_rules! hand_joints {
    ($( $(#[$doc:meta])* $variant:ident = $name:literal, )*) => {
        /// A joint of the OpenXR hand (`XrHandJointEXT`), in its order.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub enum HandJoint {
            $( $(#[$doc])* $variant, )*
        }

        impl HandJoint {
            /// Every joint, in OpenXR's order.
            pub const ALL: [HandJoint; HandJoint::COUNT] = [$(HandJoint::$variant,)*];

            /// The joint's name (snake case, OpenXR's without the prefix).
            pub const fn name(self) -> &'static str {
                match self { $(HandJoint::$variant => $name,)* }
            }

            /// The joint of a name.
            pub fn from_name(name: &str) -> Option<HandJoint> {
                match name { $($name => Some(HandJoint::$variant),)* _ => None }
            }
        }
    };
}

hand_joints! {
    /// The centre of the middle finger's metacarpal.
    Palm = "palm",
    /// The wrist.
    Wrist = "wrist",
    /// The thumb's carpometacarpal joint.
    ThumbMetacarpal = "thumb_metacarpal",
    /// The thumb's metacarpophalangeal joint.
    ThumbProximal = "thumb_proximal",
    /// The thumb's interphalangeal joint.
    ThumbDistal = "thumb_distal",
    /// The thumb's tip.
    ThumbTip = "thumb_tip",
    /// The base of the index finger's metacarpal.
    IndexMetacarpal = "index_metacarpal",
    /// The index knuckle (MCP).
    IndexProximal = "index_proximal",
    /// The index PIP joint.
    IndexIntermediate = "index_intermediate",
    /// The index DIP joint.
    IndexDistal = "index_distal",
    /// The index tip.
    IndexTip = "index_tip",
    /// The base of the middle finger's metacarpal.
    MiddleMetacarpal = "middle_metacarpal",
    /// The middle knuckle (MCP).
    MiddleProximal = "middle_proximal",
    /// The middle PIP joint.
    MiddleIntermediate = "middle_intermediate",
    /// The middle DIP joint.
    MiddleDistal = "middle_distal",
    /// The middle tip.
    MiddleTip = "middle_tip",
    /// The base of the ring finger's metacarpal.
    RingMetacarpal = "ring_metacarpal",
    /// The ring knuckle (MCP).
    RingProximal = "ring_proximal",
    /// The ring PIP joint.
    RingIntermediate = "ring_intermediate",
    /// The ring DIP joint.
    RingDistal = "ring_distal",
    /// The ring tip.
    RingTip = "ring_tip",
    /// The base of the little finger's metacarpal.
    LittleMetacarpal = "little_metacarpal",
    /// The little finger's knuckle (MCP).
    LittleProximal = "little_proximal",
    /// The little finger's PIP joint.
    LittleIntermediate = "little_intermediate",
    /// The little finger's DIP joint.
    LittleDistal = "little_distal",
    /// The little finger's tip.
    LittleTip = "little_tip",
}

impl HandJoint {
    /// Number of joints.
    pub const COUNT: usize = 26;

    /// The joint's position in [`HandJoint::ALL`] (OpenXR's index).
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The chains of the five fingers, thumb first, each from its base to its tip: for the
    /// thumb metacarpal, proximal, distal, tip; for a finger proximal (the knuckle),
    /// intermediate, distal, tip.
    pub const FINGERS: [[HandJoint; 4]; 5] = {
        use HandJoint::*;
        [
            [ThumbMetacarpal, ThumbProximal, ThumbDistal, ThumbTip],
            [IndexProximal, IndexIntermediate, IndexDistal, IndexTip],
            [MiddleProximal, MiddleIntermediate, MiddleDistal, MiddleTip],
            [RingProximal, RingIntermediate, RingDistal, RingTip],
            [LittleProximal, LittleIntermediate, LittleDistal, LittleTip],
        ]
    };

    /// The metacarpals of the four fingers, index first.
    pub const METACARPALS: [HandJoint; 4] = [
        HandJoint::IndexMetacarpal,
        HandJoint::MiddleMetacarpal,
        HandJoint::RingMetacarpal,
        HandJoint::LittleMetacarpal,
    ];
}

impl fmt::Display for HandJoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Where a joint's pose comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum JointSource {
    /// Not known in this frame.
    #[default]
    Missing,
    /// Sent by the source.
    Measured,
    /// Derived from measured joints (see the module docs).
    Made,
}

impl JointSource {
    /// Whether the joint has a pose.
    pub const fn is_valid(self) -> bool {
        !matches!(self, JointSource::Missing)
    }
}

/// One joint's pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointPose {
    /// Where the joint is, metres in the source's frame.
    pub position: DVec3,
    /// The joint's frame → the source's frame (unit quaternion).
    pub orientation: DQuat,
    /// The radius of the finger or hand at the joint, metres, where the source knows it.
    pub radius: Option<f64>,
}

impl JointPose {
    /// A validated joint pose: the position finite and within [`POSITION_LIMIT_M`], the
    /// quaternion finite with a norm within [`QUATERNION_NORM_TOLERANCE`] of 1 (normalised
    /// here), the radius finite and positive.
    pub fn new(
        position: DVec3,
        orientation: DQuat,
        radius: Option<f64>,
    ) -> Result<JointPose, DeviceError> {
        if !position.is_finite() || position.abs().max_element() > POSITION_LIMIT_M {
            return Err(DeviceError::InvalidValue(format!(
                "joint position {position} m (allowed: finite, within ±{POSITION_LIMIT_M} m)"
            )));
        }
        let norm = orientation.length();
        if !orientation.is_finite() || (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
            return Err(DeviceError::InvalidValue(format!(
                "joint quaternion {orientation} has norm {norm} (allowed: 1 ± {QUATERNION_NORM_TOLERANCE})"
            )));
        }
        if let Some(r) = radius
            && !(r.is_finite() && r > 0.0 && r < 1.0)
        {
            return Err(DeviceError::InvalidValue(format!(
                "joint radius {r} m (allowed: 0 < r < 1 m)"
            )));
        }
        Ok(JointPose {
            position,
            orientation: orientation / norm,
            radius,
        })
    }

    /// The origin with no rotation.
    pub const IDENTITY: JointPose = JointPose {
        position: DVec3::ZERO,
        orientation: DQuat::IDENTITY,
        radius: None,
    };
}

/// A hand as joint poses, for one instant (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Skeleton {
    /// Which hand.
    pub side: Side,
    joints: [JointPose; HandJoint::COUNT],
    sources: [JointSource; HandJoint::COUNT],
}

impl Skeleton {
    /// A hand with no joint known.
    pub const fn new(side: Side) -> Skeleton {
        Skeleton {
            side,
            joints: [JointPose::IDENTITY; HandJoint::COUNT],
            sources: [JointSource::Missing; HandJoint::COUNT],
        }
    }

    /// Sets a joint (its pose already validated by [`JointPose::new`]).
    pub fn set(&mut self, joint: HandJoint, pose: JointPose, source: JointSource) {
        self.joints[joint.index()] = pose;
        self.sources[joint.index()] = source;
    }

    /// Forgets a joint.
    pub fn clear(&mut self, joint: HandJoint) {
        self.joints[joint.index()] = JointPose::IDENTITY;
        self.sources[joint.index()] = JointSource::Missing;
    }

    /// A joint's pose, if known.
    pub fn get(&self, joint: HandJoint) -> Option<&JointPose> {
        self.sources[joint.index()]
            .is_valid()
            .then(|| &self.joints[joint.index()])
    }

    /// Where a joint's pose comes from.
    pub fn source(&self, joint: HandJoint) -> JointSource {
        self.sources[joint.index()]
    }

    /// The known joints with their poses and sources, in OpenXR's order.
    pub fn iter(&self) -> impl Iterator<Item = (HandJoint, &JointPose, JointSource)> + '_ {
        HandJoint::ALL.into_iter().filter_map(|j| {
            let s = self.sources[j.index()];
            s.is_valid().then(|| (j, &self.joints[j.index()], s))
        })
    }

    /// Number of known joints.
    pub fn len(&self) -> usize {
        self.sources.iter().filter(|s| s.is_valid()).count()
    }

    /// Whether no joint is known.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether every joint of the five finger chains, and the palm, is known: what the hand
    /// model needs to place a hand.
    pub fn is_complete(&self) -> bool {
        self.sources[HandJoint::Palm.index()].is_valid()
            && HandJoint::FINGERS
                .iter()
                .flatten()
                .all(|j| self.sources[j.index()].is_valid())
    }

    /// Makes the joints a source lacks from those it has, by the rules of the module docs:
    /// tips from the distal joints and the hand's distal lengths, metacarpals at the wrist,
    /// the palm between the wrist and the middle knuckle. A joint already known is kept; a
    /// joint whose ingredients are missing stays missing.
    pub fn make_missing(&mut self, hand: &HandSize) {
        let distal = [
            hand.thumb.distal,
            hand.index.distal,
            hand.middle.distal,
            hand.ring.distal,
            hand.pinky.distal,
        ];
        for (chain, length) in HandJoint::FINGERS.iter().zip(distal) {
            let [_, before, last, tip] = *chain;
            if self.source(tip).is_valid() {
                continue;
            }
            let (Some(b), Some(d)) = (self.get(before).copied(), self.get(last).copied()) else {
                continue;
            };
            let Some(dir) = (d.position - b.position).try_normalize() else {
                continue;
            };
            if let Ok(pose) = JointPose::new(d.position + length * dir, d.orientation, None) {
                self.set(tip, pose, JointSource::Made);
            }
        }
        if let Some(wrist) = self.get(HandJoint::Wrist).copied() {
            for m in HandJoint::METACARPALS {
                if !self.source(m).is_valid() {
                    self.set(m, wrist, JointSource::Made);
                }
            }
        }
        if !self.source(HandJoint::Palm).is_valid()
            && let Some(palm) = self.made_palm()
        {
            self.set(HandJoint::Palm, palm, JointSource::Made);
        }
    }

    /// The palm by the rule of the module docs, if the wrist and the index, middle and little
    /// knuckles are known and not degenerate.
    fn made_palm(&self) -> Option<JointPose> {
        let w = self.get(HandJoint::Wrist)?.position;
        let k = self.get(HandJoint::MiddleProximal)?.position;
        let i = self.get(HandJoint::IndexProximal)?.position;
        let p = self.get(HandJoint::LittleProximal)?.position;
        let s = match self.side {
            Side::Right => 1.0,
            Side::Left => -1.0,
        };
        let x = (k - w).try_normalize()?;
        let across = s * (i - p);
        let y = (across - across.dot(x) * x).try_normalize()?;
        let z = x.cross(y);
        let q = DQuat::from_mat3(&DMat3::from_cols(x, y, z)).normalize();
        JointPose::new(0.5 * (w + k), q, None).ok()
    }
}

/// A device that tracks a hand's joints (the VMC receiver). As [`crate::Tracker`]: started,
/// read with a timeout, stopped; a stream runs it on its own thread, with the watchdog and
/// reconnection of every device.
pub trait SkeletonSource: Send {
    /// What and where the source is, for messages.
    fn describe(&self) -> String;
    /// Opens the link (binds the socket) and starts receiving.
    fn start(&mut self) -> Result<(), DeviceError>;
    /// Waits at most `timeout` for data and appends the hands it completed.
    fn read(&mut self, timeout: Duration, out: &mut Vec<Skeleton>) -> Result<(), DeviceError>;
    /// Stops receiving and closes the link.
    fn stop(&mut self);
    /// Counters (a malformed packet counts as a rejected record).
    fn stats(&self) -> DeviceStats;
    /// The names of the bones (or joints) it has received so far, for a status panel.
    fn seen(&self) -> Vec<String>;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(x: f64, y: f64, z: f64) -> JointPose {
        JointPose::new(DVec3::new(x, y, z), DQuat::IDENTITY, None).unwrap()
    }

    #[test]
    fn names_round_trip_and_follow_openxr_order() {
        for (i, j) in HandJoint::ALL.into_iter().enumerate() {
            assert_eq!(j.index(), i);
            assert_eq!(HandJoint::from_name(j.name()), Some(j));
        }
        // XR_HAND_JOINT_INDEX_TIP_EXT = 10, XR_HAND_JOINT_LITTLE_TIP_EXT = 25.
        assert_eq!(HandJoint::IndexTip.index(), 10);
        assert_eq!(HandJoint::LittleTip.index(), 25);
    }

    #[test]
    fn bad_poses_are_refused() {
        assert!(JointPose::new(DVec3::new(f64::NAN, 0.0, 0.0), DQuat::IDENTITY, None).is_err());
        assert!(JointPose::new(DVec3::splat(1e3), DQuat::IDENTITY, None).is_err());
        assert!(JointPose::new(DVec3::ZERO, DQuat::from_xyzw(0.0, 0.0, 0.0, 0.5), None).is_err());
        assert!(JointPose::new(DVec3::ZERO, DQuat::IDENTITY, Some(-1.0)).is_err());
    }

    #[test]
    fn tips_metacarpals_and_palm_are_made_and_marked() {
        let hand = HandSize::default();
        let mut s = Skeleton::new(Side::Right);
        s.set(HandJoint::Wrist, pose(0.0, 0.0, 0.0), JointSource::Measured);
        s.set(
            HandJoint::IndexProximal,
            pose(0.09, 0.02, 0.0),
            JointSource::Measured,
        );
        s.set(
            HandJoint::MiddleProximal,
            pose(0.09, 0.0, 0.0),
            JointSource::Measured,
        );
        s.set(
            HandJoint::LittleProximal,
            pose(0.08, -0.04, 0.0),
            JointSource::Measured,
        );
        s.set(
            HandJoint::IndexIntermediate,
            pose(0.13, 0.02, 0.0),
            JointSource::Measured,
        );
        s.set(
            HandJoint::IndexDistal,
            pose(0.13, 0.02, -0.02),
            JointSource::Measured,
        );
        s.make_missing(&hand);
        let tip = s.get(HandJoint::IndexTip).unwrap().position;
        assert!((tip - DVec3::new(0.13, 0.02, -0.02 - hand.index.distal)).length() < 1e-15);
        assert_eq!(s.source(HandJoint::IndexTip), JointSource::Made);
        assert_eq!(s.source(HandJoint::IndexDistal), JointSource::Measured);
        assert_eq!(s.source(HandJoint::MiddleTip), JointSource::Missing);
        assert_eq!(s.source(HandJoint::RingMetacarpal), JointSource::Made);
        let palm = s.get(HandJoint::Palm).unwrap();
        assert!((palm.position - DVec3::new(0.045, 0.0, 0.0)).length() < 1e-15);
        // Right hand: +X to the middle knuckle, +Y toward the index (thumb side), +Z up.
        assert!((palm.orientation * DVec3::X - DVec3::X).length() < 1e-12);
        assert!((palm.orientation * DVec3::Z - DVec3::Z).length() < 1e-12);
        assert!(!s.is_complete());
        let mut left = s;
        left.side = Side::Left;
        left.clear(HandJoint::Palm);
        left.make_missing(&hand);
        let q = left.get(HandJoint::Palm).unwrap().orientation;
        assert!(
            (q * DVec3::Z + DVec3::Z).length() < 1e-12,
            "a left hand's back faces -Z here"
        );
    }
}
