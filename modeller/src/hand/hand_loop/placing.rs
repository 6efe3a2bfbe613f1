//! Rule 1 of [`super`]: the hand of a frame and the capsules of its pressing parts — from a
//! skeleton source's joints ([`crate::hand::skeleton`]) or a glove and tracker through the
//! kinematic hand — and the skeleton the window draws.

use nendo_devices::{HandFrame, JointAngles, SourceState};

use super::HandLoop;
use crate::hand::contact::Fingertip;
use crate::hand::kinematics::{Digit, HandPose};
use crate::hand::parts::{FingerModel, Part};

impl HandLoop {
    /// The hand's skeleton at the last frame that had a hand, in the tracker's frame (place
    /// it with [`Hand::skeleton_joints`]): a skeleton source's, gated and filtered, or the
    /// glove's through the hand model ([`Hand::skeleton`]). `None` for the mouse's ray.
    #[must_use]
    pub fn skeleton(&self) -> Option<nendo_devices::Skeleton> {
        let f = self.drawn.as_ref()?;
        if let Some(s) = f.skeleton {
            return Some(s);
        }
        if self.options.finger == FingerModel::Ray {
            return None;
        }
        let joints = match f.status.glove {
            SourceState::Ok => f.joints.as_ref(),
            _ => None,
        };
        Some(self.hand.skeleton(f.pose.as_ref()?, joints))
    }

    /// The hand and primary fingertip of a frame, if it has them (rule 1 of the module docs).
    #[must_use]
    pub fn finger_of(&self, frame: &HandFrame) -> Option<(HandPose, Fingertip)> {
        let (pose, tips) = self.parts_of(frame)?;
        let primary = Part::Digit(self.options.finger.primary());
        let tip = tips
            .iter()
            .find(|(p, _)| *p == primary)
            .or_else(|| tips.first())?
            .1;
        Some((pose, tip))
    }

    /// The hand and the capsules of every pressing part of a frame (rule 1): a fingertip for
    /// each finger of the set, the palm's for the palm.
    #[must_use]
    pub fn parts_of(&self, frame: &HandFrame) -> Option<(HandPose, Vec<(Part, Fingertip)>)> {
        // Only a delivering source acts: a pose held over from a tracker that is now silent or
        // lost (a frame built by hand, a trace from elsewhere) never reaches the surface.
        if frame.status.tracker != SourceState::Ok {
            return None;
        }
        // A skeleton source gives the hand's joints themselves (super::skeleton).
        let (placed, whole) = match &frame.skeleton {
            Some(skeleton) => (
                self.hand.skeleton_pose(skeleton)?,
                crate::hand::skeleton::whole(skeleton),
            ),
            None => (self.glove_pose(frame)?, [true; 5]),
        };
        let mut tips = Vec::new();
        for part in self.options.finger.parts().parts() {
            let tip = match part {
                // A finger the skeleton lacks a joint of does not press.
                Part::Digit(d) if !whole[d.index()] => continue,
                Part::Digit(d) => {
                    let chain = placed.finger(d);
                    Fingertip {
                        tip: chain.tip(),
                        axis: chain.direction(),
                        base: chain.points[2],
                        radius: self.options.finger_radius,
                        length: self.reach_of(part),
                        body: [
                            placed.sensor,
                            chain.points[0],
                            chain.points[1],
                            chain.points[2],
                            chain.points[3],
                        ],
                    }
                }
                Part::Palm => {
                    let palm = self.hand.palm(&placed);
                    Fingertip {
                        tip: palm.centre,
                        axis: palm.normal,
                        base: palm.centre - self.reach_of(part) * palm.normal,
                        radius: self.palm_radius(),
                        length: self.reach_of(part),
                        body: [
                            placed.sensor,
                            placed.sensor,
                            placed.sensor,
                            placed.sensor,
                            palm.centre,
                        ],
                    }
                }
            };
            if !(tip.tip.is_finite()
                && tip.axis.is_finite()
                && tip.body.iter().all(|p| p.is_finite()))
            {
                return None;
            }
            tips.push((part, tip));
        }
        (!tips.is_empty()).then_some((placed, tips))
    }

    /// The kinematic hand of a glove and tracker frame (rule 1): the tracker's pose, bent by
    /// the glove's angles (flat without a glove in the profile).
    fn glove_pose(&self, frame: &HandFrame) -> Option<HandPose> {
        let pose = frame.pose?;
        let joints: Option<&JointAngles> = match (frame.status.glove, &frame.joints) {
            (SourceState::Ok, Some(j)) => Some(j),
            (SourceState::Absent, _) => None,
            _ => return None,
        };
        Some(match self.options.finger {
            FingerModel::Hand(_) => self.hand.pose(&pose, joints),
            FingerModel::Ray => self.hand.pose_at_fingertip(&pose, joints, Digit::Index),
        })
    }
}
