//! Skeleton hands and the kinematic hand: one kind of hand whatever the source.
//!
//! A source of joint poses ([`nendo_devices::skeleton`]: the VMC receiver, later OpenXR)
//! gives a [`Skeleton`] in the tracker's frame; a glove and tracker give bend angles and a
//! pose, which the hand model's forward kinematics ([`super::kinematics`]) turns into the same
//! skeleton. Either way the hand loop, the contact rule and the window see a [`HandPose`]:
//!
//! - [`Hand::skeleton_pose`]: skeleton → hand. Each finger's chain is its four joints
//!   ([`HandJoint::FINGERS`]: for the thumb metacarpal, proximal, distal, tip; for a finger
//!   proximal, intermediate, distal, tip), placed in the world by `world_from_tracker`,
//!   `x ↦ t + c·R·x`. The hand's frame is the palm joint's orientation `Q_palm` (+X toward the
//!   middle finger, +Z out of the back of the hand), `R·Q_palm` in the world; the sensor (the
//!   back of the hand, where the kinematic hand's sensor sits) is half the palm's thickness
//!   `T = 0.3·W` above the palm joint: `t + c·R·(x_palm + Q_palm·(0, 0, T/2))`. A skeleton
//!   without the palm places no hand; a finger missing a joint of its chain (a bone not sent,
//!   or stale: [`nendo_devices::vmc`]) is not [`whole`]: its chain is collapsed onto the palm
//!   joint, and the hand loop leaves it out of the pressing parts — the other fingers press.
//! - [`Hand::skeleton_joints`]: the skeleton's joints placed in the world, with their sources,
//!   for drawing (wrist, metacarpals and palm too; made joints drawn apart from measured ones).
//! - [`Hand::skeleton`]: glove frame → skeleton, in the tracker's frame. With `(P, Q)` the
//!   tracker pose and `x_k` the kinematic hand's joints in its sensor frame: each finger's
//!   joints at `P + Q·x_k`; the palm at `P + Q·(0, 0, −T/2)` oriented `Q`; the wrist at
//!   `P + Q·(−L/2, 0, −T/2)` (`L` the palm's length), oriented `Q`; the finger metacarpals
//!   made at the wrist. The finger joints are measured (by the glove, through the model), the
//!   palm, wrist and metacarpals made.
//!
//! The two are inverse on the fingers: `skeleton_pose(skeleton(pose, angles))` places every
//! joint where [`Hand::pose`] does, to rounding (tests/it/hand_skeleton.rs).

use glam::DVec3;
use nendo_devices::skeleton::{HandJoint, JointPose, JointSource, Skeleton};
use nendo_devices::{JointAngles, TrackerPose};

use super::kinematics::{Digit, FingerChain, Hand, HandPose, PALM_THICKNESS};

impl Hand {
    /// The hand of a skeleton, in the world (see the module docs); `None` when the palm is
    /// missing or a value is not finite. A finger that is not [`whole`] has its chain at the
    /// palm joint.
    #[must_use]
    pub fn skeleton_pose(&self, s: &Skeleton) -> Option<HandPose> {
        let w = self.world_from_tracker();
        let (t, r, c) = (w.translation(), w.rotation(), w.scale);
        let place = |x: DVec3| t + c * (r * x);
        let palm = s.get(HandJoint::Palm)?;
        let half = 0.5 * PALM_THICKNESS * self.size().palm_width;
        let sensor = place(palm.position + palm.orientation * DVec3::new(0.0, 0.0, half));
        let mut fingers = [FingerChain {
            points: [DVec3::ZERO; 4],
        }; 5];
        let whole = whole(s);
        for ((finger, chain), ok) in fingers.iter_mut().zip(HandJoint::FINGERS).zip(whole) {
            for (point, joint) in finger.points.iter_mut().zip(chain) {
                *point = match s.get(joint) {
                    Some(j) if ok => place(j.position),
                    _ => place(palm.position),
                };
            }
        }
        let pose = HandPose {
            sensor,
            orientation: (r * palm.orientation).normalize(),
            scale: c,
            fingers,
        };
        let finite = pose.sensor.is_finite()
            && pose.orientation.is_finite()
            && fingers
                .iter()
                .all(|f| f.points.iter().all(|p| p.is_finite()));
        finite.then_some(pose)
    }

    /// Every known joint of a skeleton placed in the world (`x ↦ t + c·R·x`), with where it
    /// comes from, in OpenXR's order: what the window draws.
    #[must_use]
    pub fn skeleton_joints(&self, s: &Skeleton) -> Vec<(HandJoint, DVec3, JointSource)> {
        let w = self.world_from_tracker();
        let (t, r, c) = (w.translation(), w.rotation(), w.scale);
        s.iter()
            .map(|(j, pose, source)| (j, t + c * (r * pose.position), source))
            .collect()
    }

    /// The skeleton of a glove frame, in the tracker's frame (see the module docs).
    #[must_use]
    pub fn skeleton(&self, pose: &TrackerPose, joints: Option<&JointAngles>) -> Skeleton {
        let size = self.size();
        let (p, q) = (pose.position, pose.orientation);
        let at = |x: DVec3| JointPose {
            position: p + q * x,
            orientation: q,
            radius: None,
        };
        let mut s = Skeleton::new(size.side);
        let t = PALM_THICKNESS * size.palm_width;
        s.set(
            HandJoint::Palm,
            at(DVec3::new(0.0, 0.0, -0.5 * t)),
            JointSource::Made,
        );
        let wrist = at(DVec3::new(-0.5 * size.palm_length, 0.0, -0.5 * t));
        s.set(HandJoint::Wrist, wrist, JointSource::Made);
        for m in HandJoint::METACARPALS {
            s.set(m, wrist, JointSource::Made);
        }
        for (digit, chain) in Digit::ALL.into_iter().zip(HandJoint::FINGERS) {
            let local = self.local_finger(digit, joints);
            for (x, joint) in local.points.into_iter().zip(chain) {
                s.set(joint, at(x), JointSource::Measured);
            }
        }
        s
    }
}

/// Which of the five fingers (thumb first, [`Digit::ALL`]'s order) have every joint of their
/// chain ([`HandJoint::FINGERS`]): the fingers that may press.
#[must_use]
pub fn whole(s: &Skeleton) -> [bool; 5] {
    HandJoint::FINGERS.map(|chain| chain.iter().all(|j| s.get(*j).is_some()))
}
