//! The gate and filter on a skeleton hand ([`crate::skeleton`]): every joint of a frame's
//! skeleton is two channels, as a tracker is — its position (a 3-vector, metres) and its
//! orientation (a unit quaternion) — judged by the same gate rules with the tracker's limits
//! ([`GateLimits`](super::GateLimits): `max_speed_m_s`, `max_acceleration_m_s2`,
//! `position_noise_m` for positions; the angular ones for orientations) and smoothed by the
//! One-Euro filter with the profile's `position` and `orientation` parameters. A VMC
//! performer (or an OpenXR runtime) is a tracker of 26 points, each of which glitches on its
//! own, so each joint is gated on its own: a one-frame jump of the index's distal joint is
//! held while the rest of the hand moves on.
//!
//! - A skeleton sample is a frame whose tracker slot carries a skeleton and is `ok`, marked
//!   fresh ([`crate::FrameStatus::tracker_fresh`]) or different from the last one (or
//!   unmarked, as for the tracker); its clock is its own (`T̂` as in the module docs of
//!   [`super`]).
//! - A joint the frame does not have (missing: its bone not sent, or timed out) is forgotten:
//!   its channels start afresh, and its first sample when it comes back passes through.
//! - The filtered skeleton keeps each joint's source flag ([`JointSource`]: measured, made)
//!   and radius; a joint with no accepted value yet (its first sample rejected as out of
//!   range) is left out. Made joints (a VMC tip, the palm) are filtered like measured ones:
//!   they move with the joints they were made from, and a glitch of theirs is held the same
//!   way.
//! - A frame without a skeleton, or whose tracker is not `ok`, resets every joint.

use glam::{DQuat, DVec3};

use super::one_euro::{OneEuro, OneEuroRotation};
use super::{Channel, Clock, FilterSettings, FrameFilter, count};
use crate::frame::QUATERNION_NORM_TOLERANCE;
use crate::skeleton::{HandJoint, JointPose, Skeleton};
use crate::{HandFrame, POSITION_LIMIT_M, SourceState};

/// One joint's channels: position and orientation.
type JointChannels = (
    Channel<[f64; 3], OneEuro<3>>,
    Channel<DQuat, OneEuroRotation>,
);

/// The channels of a skeleton: one pair per joint, the sampling clock, the last raw skeleton.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct SkeletonChannels {
    clock: Clock,
    last: Option<Skeleton>,
    joints: Vec<JointChannels>,
}

fn fresh(settings: &FilterSettings) -> JointChannels {
    (
        Channel::new(OneEuro::new(settings.position)),
        Channel::new(OneEuroRotation::new(settings.orientation)),
    )
}

impl SkeletonChannels {
    pub(super) fn new(settings: &FilterSettings) -> Self {
        Self {
            clock: Clock::default(),
            last: None,
            joints: (0..HandJoint::COUNT).map(|_| fresh(settings)).collect(),
        }
    }
}

impl FrameFilter {
    pub(super) fn reset_skeleton(&mut self) {
        self.skeleton = SkeletonChannels::new(&self.settings);
    }

    /// The frame's skeleton gated and filtered joint by joint (see the module docs).
    pub(super) fn skeleton(
        &mut self,
        frame: &HandFrame,
        t: f64,
        unmarked: bool,
    ) -> Option<Skeleton> {
        let s = match (frame.status.tracker, frame.skeleton.as_ref()) {
            (SourceState::Ok, Some(s)) => *s,
            _ => {
                if self.skeleton.last.is_some() {
                    self.reset_skeleton();
                }
                return None;
            }
        };
        let new = unmarked || frame.status.tracker_fresh || self.skeleton.last != Some(s);
        self.skeleton.last = Some(s);
        if new {
            self.skeleton.clock.tick(t);
            self.stats.skeleton_samples += 1;
        }
        let at = (t, self.skeleton.clock.period);
        let (p_limits, q_limits) = (
            self.settings.position_limits(),
            self.settings.orientation_limits(),
        );
        let mut out = Skeleton::new(s.side);
        for joint in HandJoint::ALL {
            let k = joint.index();
            let Some(pose) = s.get(joint) else {
                self.skeleton.joints[k] = fresh(&self.settings);
                continue;
            };
            let (pc, qc) = &mut self.skeleton.joints[k];
            if new {
                let p = pose.position.to_array();
                let in_range = p
                    .iter()
                    .all(|x| x.is_finite() && x.abs() <= POSITION_LIMIT_M);
                let v = pc.admit(p, in_range, at, &p_limits);
                count(
                    &v,
                    &mut self.stats.skeleton_positions,
                    &mut self.stats.resyncs,
                );
                match v {
                    Ok((_, te)) => {
                        pc.filter.step(p, te);
                    }
                    Err(_) => self.held.skeleton_positions |= 1 << k,
                }
                let q = pose.orientation;
                let in_range =
                    q.is_finite() && (q.length() - 1.0).abs() <= QUATERNION_NORM_TOLERANCE;
                let v = qc.admit(q, in_range, at, &q_limits);
                count(
                    &v,
                    &mut self.stats.skeleton_orientations,
                    &mut self.stats.resyncs,
                );
                match v {
                    Ok((_, te)) => {
                        qc.filter.step(q, te);
                    }
                    Err(_) => self.held.skeleton_orientations |= 1 << k,
                }
            }
            if let (Some(p), Some(q)) = (pc.filter.value(), qc.filter.value()) {
                // Convex combinations of accepted values: finite, in range, unit quaternions.
                let filtered = JointPose {
                    position: DVec3::from_array(p),
                    orientation: q,
                    radius: pose.radius,
                };
                out.set(joint, filtered, s.source(joint));
            }
        }
        Some(out)
    }
}
