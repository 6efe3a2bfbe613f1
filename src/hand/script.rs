//! Scripted hand motions, written as real traces — and the generators of the traces shipped in
//! `devices/traces/`.
//!
//! There are no physical gloves or trackers here, so the shipped traces are hand motions
//! written by program: a [`Choreography`] moves the active fingertip along wanted paths
//! (inverse kinematics of [`Hand::pose_for_fingertip`]: the tracker pose that puts the
//! fingertip there), bends the glove's joints, presses the glove's switch, and emits one
//! frame per device period exactly as the device layer would — tracker pose in metres in the
//! tracker's frame, the 18 calibrated CyberGlove angles, buttons, source states — rounded
//! as a trace stores them ([`nendo_devices::trace::quantize_frame`]). Written with
//! [`nendo_devices::TraceWriter`] they are ordinary `nendo-hand-trace 1` files.
//!
//! The mouse trace is made the way the window makes mouse frames: a [`MouseFinger`] over the
//! real [`nendo_devices::MouseHand`], with the view rays of a fixed camera.
//!
//! Every generator is deterministic: the same code writes the same trace.

use glam::DVec3;
use nendo_devices::profile::MouseProfile;
use nendo_devices::trace::quantize_frame;
use nendo_devices::{
    FrameStatus, HandFrame, HandSize, Joint, JointAngles, SourceState, Timestamp, Trace,
    TraceHeader, TrackerPose, ViewRay, WorldFromTracker, buttons,
};
use std::f64::consts::{FRAC_PI_2, TAU};

use super::DEFAULT_FINGER_RADIUS;
use super::HandError;
use super::kinematics::{Digit, Hand};
use super::mouse::MouseFinger;
use super::scene::{Scene, SceneError, finger_name};
use super::session::{FingerModel, Fingers, Part};
use crate::surface::{Grid, Primitive, PrimitiveParams, Regulation};

/// The joints of the CyberGlove II with 18 sensors, in its sensor order (the columns of the
/// `cyberglove2-18-fastrak` profile's calibration table).
pub const CYBERGLOVE_18_JOINTS: [Joint; 18] = [
    Joint::ThumbRoll,
    Joint::ThumbMcp,
    Joint::ThumbIp,
    Joint::ThumbIndexAbduction,
    Joint::IndexMcp,
    Joint::IndexPip,
    Joint::MiddleMcp,
    Joint::MiddlePip,
    Joint::IndexMiddleAbduction,
    Joint::RingMcp,
    Joint::RingPip,
    Joint::MiddleRingAbduction,
    Joint::PinkyMcp,
    Joint::PinkyPip,
    Joint::RingPinkyAbduction,
    Joint::PalmArch,
    Joint::WristPitch,
    Joint::WristYaw,
];

/// The pointing pose of the scripted glove: index nearly straight, the other fingers curled,
/// all inside the range a CyberGlove's default calibration can report.
pub const POINTING: [(Joint, f64); 18] = [
    (Joint::ThumbRoll, 0.35),
    (Joint::ThumbMcp, 0.5),
    (Joint::ThumbIp, 0.4),
    (Joint::ThumbIndexAbduction, 0.2),
    (Joint::IndexMcp, 0.15),
    (Joint::IndexPip, 0.2),
    (Joint::MiddleMcp, 1.3),
    (Joint::MiddlePip, 1.35),
    (Joint::IndexMiddleAbduction, 0.08),
    (Joint::RingMcp, 1.35),
    (Joint::RingPip, 1.35),
    (Joint::MiddleRingAbduction, 0.05),
    (Joint::PinkyMcp, 1.35),
    (Joint::PinkyPip, 1.3),
    (Joint::RingPinkyAbduction, 0.08),
    (Joint::PalmArch, 0.1),
    (Joint::WristPitch, 0.0),
    (Joint::WristYaw, 0.0),
];

/// A scripted glove + tracker session: moves the active fingertip, bends joints, presses
/// the switch, and records one frame per device period.
#[derive(Debug, Clone)]
pub struct Choreography {
    hand: Hand,
    digit: Digit,
    angles: JointAngles,
    pose: TrackerPose,
    up: DVec3,
    buttons: u32,
    rate_hz: f64,
    frames: Vec<HandFrame>,
    error: Option<String>,
}

impl Choreography {
    /// The tracker-to-world transform of the scripted traces: 20 world units ("side") per
    /// metre, the tracker's source 6 side in front of the model (−y). A 6-side sphere is then
    /// 30 cm across — a ball of clay — and the hand's index finger 1.6 side long.
    pub const WORLD: WorldFromTracker = WorldFromTracker {
        translation: [0.0, -6.0, 0.0],
        rotation_wxyz: [1.0, 0.0, 0.0, 0.0],
        scale: 20.0,
    };

    /// A choreography of the default-sized right hand, index finger active, pointing pose,
    /// frames at `rate_hz`.
    ///
    /// # Errors
    /// [`HandError::Model`] for a transform that is not a similarity, [`HandError::Options`]
    /// for a rate that is not a positive number.
    pub fn new(world_from_tracker: WorldFromTracker, rate_hz: f64) -> Result<Self, HandError> {
        if !(rate_hz.is_finite() && rate_hz > 0.0) {
            return Err(HandError::Options(format!("frame rate {rate_hz} Hz")));
        }
        let mut angles = JointAngles::new();
        for (j, a) in POINTING {
            // In range by construction (|a| < π).
            let _ = angles.set(j, a);
        }
        Ok(Self {
            hand: Hand::new(HandSize::default(), world_from_tracker)?,
            digit: Digit::Index,
            angles,
            pose: TrackerPose::IDENTITY,
            up: DVec3::Z,
            buttons: 0,
            rate_hz,
            frames: Vec::new(),
            error: None,
        })
    }

    /// The hand model.
    #[must_use]
    pub fn hand(&self) -> &Hand {
        &self.hand
    }

    /// The glove's angles now.
    #[must_use]
    pub fn angles(&self) -> &JointAngles {
        &self.angles
    }

    /// Frames so far.
    #[must_use]
    pub fn frames(&self) -> &[HandFrame] {
        &self.frames
    }

    /// The active fingertip and its direction now (forward kinematics of the current pose).
    #[must_use]
    pub fn fingertip(&self) -> (DVec3, DVec3) {
        let f = *self
            .hand
            .pose(&self.pose, Some(&self.angles))
            .finger(self.digit);
        (f.tip(), f.direction())
    }

    fn solve(&mut self, tip: DVec3, axis: DVec3) -> Option<TrackerPose> {
        let pose = self
            .hand
            .pose_for_fingertip(self.digit, Some(&self.angles), tip, axis, self.up);
        if pose.is_none() && self.error.is_none() {
            self.error = Some(format!(
                "no hand pose puts the fingertip at {tip} along {axis}"
            ));
        }
        pose
    }

    /// Puts the fingertip at `tip` pointing along `axis`, the back of the hand toward `up`,
    /// without a frame (the starting pose).
    pub fn place(&mut self, tip: DVec3, axis: DVec3, up: DVec3) -> &mut Self {
        self.up = up;
        if let Some(p) = self.solve(tip, axis) {
            self.pose = p;
        }
        self
    }

    /// Turns the back of the hand toward `up` for the following motions.
    pub fn set_up(&mut self, up: DVec3) -> &mut Self {
        self.up = up;
        self
    }

    /// Moves the fingertip to `tip`, pointing along `axis`, in `frames` frames, easing in and
    /// out (smoothstep): the position along the straight line, the direction turning at a
    /// steady rate in the plane of the two directions (about `up` when they are opposite).
    pub fn move_to(&mut self, tip: DVec3, axis: DVec3, frames: usize) -> &mut Self {
        let (from, from_axis) = self.fingertip();
        let up = self.up;
        self.path(frames, |s| {
            let e = s * s * (3.0 - 2.0 * s);
            (from.lerp(tip, e), turn(from_axis, axis, up, e))
        })
    }

    /// The tracker pose now.
    #[must_use]
    pub fn pose(&self) -> TrackerPose {
        self.pose
    }

    /// Sets the tracker pose, without a frame.
    pub fn set_pose(&mut self, pose: TrackerPose) -> &mut Self {
        self.pose = pose;
        self
    }

    /// Sets glove angles at once, without a frame.
    pub fn set_angles(&mut self, targets: &[(Joint, f64)]) -> &mut Self {
        for &(j, a) in targets {
            if self.angles.set(j, a).is_err() && self.error.is_none() {
                self.error = Some(format!("angle {a} of {j} is out of range"));
            }
        }
        self
    }

    /// The tracker pose of the hand moved by `offset` (world units), same orientation.
    #[must_use]
    pub fn shifted(&self, pose: TrackerPose, offset: DVec3) -> TrackerPose {
        let w = self.hand.world_from_tracker();
        let delta = w.rotation().inverse() * offset / w.scale;
        TrackerPose {
            position: pose.position + delta,
            orientation: pose.orientation,
        }
    }

    /// Moves the whole hand to a tracker pose in `frames` frames (smoothstep; position along a
    /// line, orientation by spherical interpolation); the glove's angles stay.
    pub fn move_pose_to(&mut self, target: TrackerPose, frames: usize) -> &mut Self {
        let from = self.pose;
        for k in 1..=frames {
            let s = k as f64 / frames as f64;
            let e = s * s * (3.0 - 2.0 * s);
            self.pose = TrackerPose {
                position: from.position.lerp(target.position, e),
                orientation: from.orientation.slerp(target.orientation, e).normalize(),
            };
            self.emit();
        }
        self
    }

    /// Moves the fingertip along `at(s)` (position, direction) for `s` in `(0, 1]`, one frame
    /// per step, `frames` frames.
    pub fn path(&mut self, frames: usize, at: impl Fn(f64) -> (DVec3, DVec3)) -> &mut Self {
        for k in 1..=frames {
            let (tip, axis) = at(k as f64 / frames as f64);
            if let Some(p) = self.solve(tip, axis) {
                self.pose = p;
            }
            self.emit();
        }
        self
    }

    /// Bends glove joints to new angles in `frames` frames (linearly) while the tracker stays
    /// where it is: the fingertip moves by the kinematic chain alone.
    pub fn bend_to(&mut self, targets: &[(Joint, f64)], frames: usize) -> &mut Self {
        let start: Vec<(Joint, f64, f64)> = targets
            .iter()
            .map(|&(j, a)| (j, self.angles.get(j).unwrap_or(0.0), a))
            .collect();
        for k in 1..=frames {
            let s = k as f64 / frames as f64;
            for &(j, a0, a1) in &start {
                if self.angles.set(j, a0 + (a1 - a0) * s).is_err() && self.error.is_none() {
                    self.error = Some(format!("angle {a1} of {j} is out of range"));
                }
            }
            self.emit();
        }
        self
    }

    /// Holds still for `frames` frames.
    pub fn hold(&mut self, frames: usize) -> &mut Self {
        for _ in 0..frames {
            self.emit();
        }
        self
    }

    /// Sets the buttons (the glove's switch is [`buttons::PRIMARY`]) from the next frame on.
    pub fn press(&mut self, mask: u32) -> &mut Self {
        self.buttons = mask;
        self
    }

    fn emit(&mut self) {
        let k = self.frames.len() as f64;
        let frame = HandFrame {
            time: Timestamp((k * 1e6 / self.rate_hz).round() as u64),
            pose: Some(self.pose),
            joints: Some(self.angles),
            buttons: self.buttons,
            status: FrameStatus {
                tracker: SourceState::Ok,
                glove: SourceState::Ok,
                tracker_fresh: true,
                glove_fresh: true,
            },
        };
        self.frames
            .push(quantize_frame(&frame, &CYBERGLOVE_18_JOINTS));
    }

    /// The trace: header (profile name, transform, hand, the 18 glove columns) and frames.
    ///
    /// # Errors
    /// [`HandError::Model`] when a wanted fingertip placement had no solution (a zero
    /// direction, or one parallel to `up`) or an angle was out of range.
    pub fn finish(self, profile: &str) -> Result<Trace, HandError> {
        if let Some(e) = self.error {
            return Err(HandError::Model(e));
        }
        Ok(Trace {
            header: TraceHeader {
                profile: Some(profile.to_string()),
                world_from_tracker: *self.hand.world_from_tracker(),
                hand: *self.hand.size(),
                joints: CYBERGLOVE_18_JOINTS.to_vec(),
                scene: None,
            },
            frames: self.frames,
        })
    }
}

/// A named hand gesture over the default plane (`--primitive plane`, z = 0), for the device
/// emulators of `nendo emulate`: each is one loop of a few seconds, in world units ("side")
/// through the profile's tracker-to-world transform, so the hand does the same over the model
/// whatever the transform. The glove holds the pointing pose ([`POINTING`]) except where said.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Gesture {
    /// 3.0 s: the index fingertip comes straight down at (0.5, 0.5), 0.3 side into the plane,
    /// holds, and lifts out again: a dent.
    Press,
    /// 5.5 s: the fingertip dips 0.15 side into the plane at x = −0.8 and draws a wave to
    /// x = 0.8 (y = 0.3·sin 2πs), then lifts and goes back: a wavy groove.
    Wave,
    /// 3.5 s: the fingertip touches the plane at (−0.5, −0.5), the thumb closes on the index
    /// and the glove's switch is pressed (the grip), the hand rises 0.4 side pulling the clay
    /// up, then the switch is released and the thumb opens: a bump.
    Pinch,
}

impl Gesture {
    /// Every gesture.
    pub const ALL: [Gesture; 3] = [Gesture::Press, Gesture::Wave, Gesture::Pinch];

    /// The gesture's name on the command line.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Gesture::Press => "press",
            Gesture::Wave => "wave",
            Gesture::Pinch => "pinch",
        }
    }

    /// The gesture of a name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Gesture> {
        Gesture::ALL.into_iter().find(|g| g.name() == name)
    }

    /// One loop of the gesture as frames at `rate_hz`, for a hand placed by
    /// `world_from_tracker` (the default hand size; tracker poses in metres, the 18 CyberGlove
    /// angles, the switch as [`buttons::PRIMARY`]).
    ///
    /// # Errors
    /// [`HandError`] for a transform that is not a similarity or a rate that is not positive.
    pub fn trace(
        self,
        world_from_tracker: WorldFromTracker,
        rate_hz: f64,
    ) -> Result<Trace, HandError> {
        let mut c = Choreography::new(world_from_tracker, rate_hz)?;
        let down = -DVec3::Z;
        // Frames for a duration in seconds.
        let n = |seconds: f64| ((seconds * rate_hz).round() as usize).max(1);
        match self {
            Gesture::Press => {
                let above = DVec3::new(0.5, 0.5, 0.5);
                c.place(above, down, DVec3::Y);
                c.hold(n(0.25));
                c.move_to(DVec3::new(0.5, 0.5, -0.3), down, n(1.0));
                c.hold(n(0.5));
                c.move_to(above, down, n(1.0));
                c.hold(n(0.25));
            }
            Gesture::Wave => {
                let start = DVec3::new(-0.8, 0.0, 0.4);
                c.place(start, down, DVec3::X);
                c.move_to(DVec3::new(-0.8, 0.0, -0.15), down, n(0.5));
                c.path(n(3.0), |s| {
                    (
                        DVec3::new(-0.8 + 1.6 * s, 0.3 * (TAU * s).sin(), -0.15),
                        down,
                    )
                });
                c.move_to(DVec3::new(0.8, 0.0, 0.4), down, n(0.5));
                c.move_to(start, down, n(1.5));
            }
            Gesture::Pinch => {
                let above = DVec3::new(-0.5, -0.5, 0.4);
                c.place(above, down, DVec3::Y);
                c.move_to(DVec3::new(-0.5, -0.5, 0.0), down, n(0.75));
                c.bend_to(&[(Joint::ThumbMcp, 0.9), (Joint::ThumbIp, 0.8)], n(0.25));
                c.press(buttons::PRIMARY);
                c.hold(n(0.25));
                c.move_to(above, down, n(1.25));
                c.press(0);
                c.bend_to(&[(Joint::ThumbMcp, 0.5), (Joint::ThumbIp, 0.4)], n(0.25));
                c.hold(n(0.75));
            }
        }
        c.finish(self.name())
    }
}

/// The thumb joints a scripted pinch bends.
pub const THUMB_JOINTS: [Joint; 4] = [
    Joint::ThumbRoll,
    Joint::ThumbMcp,
    Joint::ThumbIp,
    Joint::ThumbIndexAbduction,
];

/// The thumb angles ([`THUMB_JOINTS`]) that bring the thumb's tip nearest `target` (a point in
/// the hand's sensor frame, metres), the other joints as in `angles`; and how far from
/// `target` the tip then is (metres). Each angle within [−0.3, 1.5] rad (inside a
/// CyberGlove's default range). A coarse grid of 9⁴ poses, then coordinate descent with
/// halving steps: deterministic.
#[must_use]
pub fn thumb_to(hand: &Hand, angles: &JointAngles, target: DVec3) -> ([(Joint, f64); 4], f64) {
    let (lo, hi) = (-0.3, 1.5);
    let miss = |x: &[f64; 4]| {
        let mut a = *angles;
        for (j, v) in THUMB_JOINTS.iter().zip(x) {
            // In range by construction.
            let _ = a.set(*j, *v);
        }
        (hand.local_finger(Digit::Thumb, Some(&a)).tip() - target).length()
    };
    let mut best = [0.0; 4];
    let mut best_miss = f64::INFINITY;
    let step = (hi - lo) / 8.0;
    for k in 0..9usize.pow(4) {
        let x = [0, 1, 2, 3].map(|i| lo + step * ((k / 9usize.pow(i)) % 9) as f64);
        let m = miss(&x);
        if m < best_miss {
            (best, best_miss) = (x, m);
        }
    }
    let mut h = step / 2.0;
    while h > 1e-5 {
        let mut improved = false;
        for i in 0..4 {
            for sign in [-1.0, 1.0] {
                let mut x = best;
                x[i] = (x[i] + sign * h).clamp(lo, hi);
                let m = miss(&x);
                if m < best_miss {
                    (best, best_miss) = (x, m);
                    improved = true;
                }
            }
        }
        if !improved {
            h /= 2.0;
        }
    }
    let mut out = [(Joint::ThumbRoll, 0.0); 4];
    for (o, (j, v)) in out.iter_mut().zip(THUMB_JOINTS.iter().zip(best)) {
        *o = (*j, v);
    }
    (out, best_miss)
}

/// The pinch of the scripted glove: the pointing pose with the index curled (its MCP and PIP,
/// searched on a grid of 0.3 to 1.2 rad) and the thumb closed on the index fingertip
/// ([`thumb_to`] the index tip, half a centimetre short of it along the thumb's approach, so
/// the tips meet without passing) — the index and thumb angles of the curl that lets the
/// thumb come closest.
#[must_use]
pub fn pinching(hand: &Hand) -> Vec<(Joint, f64)> {
    let mut best: Option<(f64, Vec<(Joint, f64)>)> = None;
    for mcp in [0.3, 0.6, 0.9, 1.2] {
        for pip in [0.3, 0.6, 0.9, 1.2] {
            let mut angles = JointAngles::new();
            for (j, a) in POINTING {
                let _ = angles.set(j, a);
            }
            let _ = angles.set(Joint::IndexMcp, mcp);
            let _ = angles.set(Joint::IndexPip, pip);
            let index = hand.local_finger(Digit::Index, Some(&angles)).tip();
            let thumb = hand.local_finger(Digit::Thumb, Some(&angles)).tip();
            let toward = (index - thumb).try_normalize().unwrap_or(DVec3::ZERO);
            let (joints, miss) = thumb_to(hand, &angles, index - 0.005 * toward);
            if best.as_ref().is_none_or(|(m, _)| miss < *m) {
                let mut all = vec![(Joint::IndexMcp, mcp), (Joint::IndexPip, pip)];
                all.extend(joints);
                best = Some((miss, all));
            }
        }
    }
    best.map(|(_, j)| j).unwrap_or_default()
}

/// The pinch of [`pinching`] opened: the index uncurled by `open` radians at its MCP and PIP,
/// and the thumb ([`thumb_to`]) at the point mirror of the opened index tip through the closed
/// pinch point (midway between the closed tips), so that the pinch point stays where it is
/// when the two fingers open or close together. The index and thumb angles.
#[must_use]
pub fn pinch_opened(hand: &Hand, pinch: &[(Joint, f64)], open: f64) -> Vec<(Joint, f64)> {
    let mut angles = JointAngles::new();
    for &(j, a) in POINTING.iter().chain(pinch) {
        let _ = angles.set(j, a);
    }
    let closed_mid = 0.5
        * (hand.local_finger(Digit::Index, Some(&angles)).tip()
            + hand.local_finger(Digit::Thumb, Some(&angles)).tip());
    let mut out = Vec::new();
    for j in [Joint::IndexMcp, Joint::IndexPip] {
        let a = angles.get(j).unwrap_or(0.0) - open;
        let _ = angles.set(j, a);
        out.push((j, a));
    }
    let index = hand.local_finger(Digit::Index, Some(&angles)).tip();
    let (thumb, _) = thumb_to(hand, &angles, 2.0 * closed_mid - index);
    out.extend(thumb);
    out
}

/// The tracker pose that puts the pinch of `angles` (the point midway between the thumb and
/// index tips) at `at`, the line from the index tip to the thumb tip along `across`, and the
/// two fingers' mean direction as near `into` as that allows (its part square to `across`):
/// the fingertips side by side on the clay, pointing into it. `None` when the directions are
/// zero or parallel.
#[must_use]
pub fn pinch_pose(
    hand: &Hand,
    angles: &JointAngles,
    at: DVec3,
    into: DVec3,
    across: DVec3,
) -> Option<TrackerPose> {
    // Any pose, then the rotation R taking its (tip line, mean direction) to (across, into).
    let start =
        hand.pose_for_fingertip(Digit::Index, Some(angles), DVec3::ZERO, DVec3::X, DVec3::Z)?;
    let placed = hand.pose(&start, Some(angles));
    let (index, thumb) = (placed.finger(Digit::Index), placed.finger(Digit::Thumb));
    let mid = 0.5 * (index.tip() + thumb.tip());
    let from = frame_of(
        thumb.tip() - index.tip(),
        index.direction() + thumb.direction(),
    )?;
    let to = frame_of(across, into)?;
    let r = to * from.transpose();
    let back = placed.orientation * DVec3::Z;
    hand.pose_for_fingertip(
        Digit::Index,
        Some(angles),
        at + r * (index.tip() - mid),
        r * index.direction(),
        r * back,
    )
}

/// The rotation whose columns are `x̂`, `ŷ = ẑ × x̂`, `ẑ` (`ẑ` the part of `z` square to `x`).
fn frame_of(x: DVec3, z: DVec3) -> Option<glam::DMat3> {
    let x = x.try_normalize()?;
    let z = (z - z.dot(x) * x).try_normalize()?;
    Some(glam::DMat3::from_cols(x, z.cross(x), z))
}

/// How far outside the sphere the scripted pinch closes (side): the tips stay out of the clay
/// all the way in (at least 0.02 side off it while the fingers close).
const PINCH_GAP: f64 = 0.08;

/// How far the scripted pinch opens (radians off the index's curl, [`pinch_opened`]): the tips
/// 0.98 side apart.
const PINCH_OPEN: f64 = 0.25;

/// Pinch and pull on the paper's sphere, the way a hand pulls a nose out of a ball: the hand
/// comes in along −x with thumb and index open ([`pinch_opened`]: the tips 0.98 side apart,
/// thumb above index, side by side on the sphere, [`pinch_pose`]), stops with the pinch point
/// 0.08 side outside the equator at longitude 0, closes both fingers ([`pinching`]; the pinch
/// point stays put, the tips end 0.1 side apart and take hold of the clay as they pass within
/// the pinch distance), pulls 1 side straight out along +x, opens the fingers again (letting
/// go) and leaves along +x. Neither fingertip's capsule axis reaches the clay: nothing
/// presses, the pinch's `move` is the only operation. 120 Hz.
///
/// # Errors
/// Never for these fixed motions.
pub fn sphere_pinch_pull() -> Result<Trace, HandError> {
    let mut c = Choreography::new(Choreography::WORLD, 120.0)?;
    let hand = *c.hand();
    let closed = pinching(&hand);
    let open = pinch_opened(&hand, &closed, PINCH_OPEN);
    c.set_angles(&open);
    let at = DVec3::new(3.0 + PINCH_GAP, 0.0, 0.0);
    let Some(grab) = pinch_pose(&hand, c.angles(), at, -DVec3::X, DVec3::Z) else {
        return Err(HandError::Model("no hand pose pinches the sphere".into()));
    };
    c.set_pose(c.shifted(grab, DVec3::new(1.5, 0.0, 0.0)));
    c.hold(6);
    c.move_pose_to(grab, 60);
    c.bend_to(&closed, 30);
    c.hold(10);
    let pulled = c.shifted(grab, DVec3::new(1.0, 0.0, 0.0));
    c.move_pose_to(pulled, 90);
    c.hold(10);
    c.bend_to(&open, 30);
    let away = c.shifted(pulled, DVec3::new(1.5, 0.0, 0.0));
    c.move_pose_to(away, 30);
    c.finish(GLOVE_PROFILE)
}

/// The index fingertip of the rim pinch: inside the tube, 0.15 side past its wall at x = 2,
/// 1.6 below the rim.
pub const RIM_INDEX: DVec3 = DVec3::new(2.15, 0.0, 4.4);
/// The thumb tip of the rim pinch: outside the tube, 0.15 side past the wall, 1 side above the
/// index's press and 0.3 to its side (−y).
pub const RIM_THUMB: DVec3 = DVec3::new(1.85, -0.3, 5.4);

/// A two-finger pinch of the paper's test tube's wall near its rim (the tube is one sheet of
/// clay: radius 2, its rim at z = 6): the hand comes down over the rim with the index inside
/// the tube (pointing down, leaning 30° out toward the wall), the thumb open outside, 0.4 side
/// in from where it will press; it moves out until the index tip is 0.15 side past the wall
/// ([`RIM_INDEX`]: pressing it out), the thumb closes on the outside until its tip is 0.15
/// side past the wall ([`RIM_THUMB`]: pressing it in), holds, opens, and the hand moves back
/// in and rises out of the tube. Both tips press the one wall from its two sides, at spots
/// along it, as fingers side by side do a sheet (on one sheet two tips at the same spot
/// from both sides would have to pass through each other); their tips never come within the
/// pinch distance, so nothing is held. One contact of both fingers. 60 Hz.
///
/// # Errors
/// Never for these fixed motions.
pub fn tube_rim_pinch() -> Result<Trace, HandError> {
    let mut c = Choreography::new(Choreography::WORLD, 60.0)?;
    let hand = *c.hand();
    let lean = 30f64.to_radians();
    let (s, k) = (lean.sin(), lean.cos());
    let axis = DVec3::new(s * k, s * s, -k);
    // The back of the hand toward −y: the thumb reaches over the rim to the outside.
    c.place(RIM_INDEX, axis, DVec3::new(-0.55, -0.83, 0.0));
    let press = c.pose();
    let placed = hand.pose(&press, Some(c.angles()));
    let local = |w: DVec3| placed.orientation.inverse() * (w - placed.sensor) / placed.scale;
    let (squeeze, _) = thumb_to(&hand, c.angles(), local(RIM_THUMB));
    let (open, _) = thumb_to(&hand, c.angles(), local(DVec3::new(2.5, -0.3, 5.8)));
    c.set_angles(&open);
    let inside = c.shifted(press, DVec3::new(-0.4, 0.0, 0.0));
    let above = c.shifted(inside, DVec3::new(0.0, 0.0, 2.5));
    c.set_pose(above);
    c.hold(6);
    c.move_pose_to(inside, 48);
    c.move_pose_to(press, 24);
    c.bend_to(&squeeze, 24);
    c.hold(12);
    c.bend_to(&open, 24);
    c.move_pose_to(inside, 24);
    c.move_pose_to(above, 36);
    c.finish(GLOVE_PROFILE)
}

/// A flat hand (every joint straight) laid palm down on the default plane: the palm's face
/// comes down from 0.5 above to `depth` below the plane at (0, 0), the fingers along +x,
/// holds, and lifts. The fingers stay above the clay (their axes 0.255 side over the palm's
/// face, level with it); only the palm presses. 120 Hz.
///
/// # Errors
/// Never for these fixed motions.
pub fn plane_palm(depth: f64) -> Result<Trace, HandError> {
    let mut c = Choreography::new(Choreography::WORLD, 120.0)?;
    let flat: Vec<(Joint, f64)> = CYBERGLOVE_18_JOINTS.iter().map(|&j| (j, 0.0)).collect();
    c.set_angles(&flat);
    c.place(DVec3::new(1.0, 0.0, 1.0), DVec3::X, DVec3::Z);
    let hand = *c.hand();
    let palm = hand.palm(&hand.pose(&c.pose(), Some(c.angles()))).centre;
    let lower = |z: f64| c.shifted(c.pose(), DVec3::new(-palm.x, -palm.y, z - palm.z));
    let (above, pressed) = (lower(0.5), lower(-depth));
    c.set_pose(above);
    c.hold(6);
    c.move_pose_to(pressed, 60);
    c.hold(20);
    c.move_pose_to(above, 40);
    c.finish(GLOVE_PROFILE)
}

/// A trace shipped in `devices/traces/`, with the surface it was made for.
#[derive(Debug, Clone)]
pub struct Shipped {
    /// File name without `.trace`.
    pub name: &'static str,
    /// One line for people.
    pub about: &'static str,
    /// The starting surface.
    pub primitive: Primitive,
    /// Its parameters.
    pub params: PrimitiveParams,
    /// The parts of the hand it was made for (`--finger`): the index alone for the traces
    /// made before the whole hand pressed, the ray for the mouse.
    pub finger: FingerModel,
    /// The frames.
    pub trace: Trace,
}

impl Shipped {
    /// The starting surface.
    ///
    /// # Errors
    /// Never for the shipped parameters; a bad parameter is reported as the surface's error.
    pub fn grid(&self) -> Result<Grid, crate::surface::SurfaceError> {
        self.primitive.build(&self.params)
    }

    /// The scene the trace's header carries: the primitive with every parameter it is built
    /// from, the default regulation, the fingers it was made for ([`Shipped::finger`]: the view
    /// ray for the mouse; the index finger, every finger, the palm or a pinch's two fingers for
    /// the glove) and the default finger radius; no mirror, no refinement. `nendo replay` of the trace then needs only `--out`.
    ///
    /// # Errors
    /// Never for the shipped parameters; a bad parameter is reported as the scene's error.
    pub fn scene(&self) -> Result<Scene, SceneError> {
        let mut scene = Scene::primitive(self.primitive, &self.params)?;
        scene.regulation = Some(Regulation::default());
        scene.finger = Some(finger_name(self.finger));
        scene.finger_radius = Some(DEFAULT_FINGER_RADIUS);
        Ok(scene)
    }
}

/// The direction a fraction `s` of the way from `from` to `to`, turning at a steady rate in
/// their plane (about `up` when they are opposite).
fn turn(from: DVec3, to: DVec3, up: DVec3, s: f64) -> DVec3 {
    let (Some(a), Some(b)) = (from.try_normalize(), to.try_normalize()) else {
        return to;
    };
    let angle = a.dot(b).clamp(-1.0, 1.0).acos();
    let k = a
        .cross(b)
        .try_normalize()
        .or_else(|| up.cross(a).try_normalize());
    match k {
        Some(k) if angle > 1e-12 => glam::DQuat::from_axis_angle(k, angle * s) * a,
        _ => b,
    }
}

/// The profile name in the headers of the glove traces.
pub const GLOVE_PROFILE: &str = "cyberglove2-18-fastrak";

/// A push straight down on the north pole of the paper's sphere (8 × 4 patches, radius 3)
/// 0.6 side deep, then a pull on the equator at longitude 0 (a grid vertex): touch, grip with
/// the glove's switch, withdraw 0.6 side, let go. 120 Hz.
///
/// # Errors
/// Never for these fixed motions (see [`Choreography::finish`]).
pub fn sphere_push_pull() -> Result<Trace, HandError> {
    let mut c = Choreography::new(Choreography::WORLD, 120.0)?;
    let down = -DVec3::Z;
    c.place(DVec3::new(0.0, 0.0, 4.4), down, DVec3::Y);
    c.hold(12);
    c.move_to(DVec3::new(0.0, 0.0, 3.15), down, 30);
    c.move_to(DVec3::new(0.0, 0.0, 2.4), down, 48);
    c.hold(24);
    c.move_to(DVec3::new(0.0, 0.0, 4.0), down, 36);
    // Around to the equator at a safe distance, the finger always pointing at the centre.
    c.set_up(DVec3::Y);
    c.path(60, |s| {
        let beta = FRAC_PI_2 * s * s * (3.0 - 2.0 * s);
        let out = DVec3::new(beta.sin(), 0.0, beta.cos());
        (4.0 * out, -out)
    });
    let inward = -DVec3::X;
    c.move_to(DVec3::new(3.01, 0.0, 0.0), inward, 30);
    c.press(buttons::PRIMARY).hold(6);
    c.move_to(DVec3::new(3.6, 0.0, 0.0), inward, 48);
    c.hold(12);
    c.press(0).hold(6);
    c.move_to(DVec3::new(4.5, 0.0, 0.0), inward, 24);
    c.finish(GLOVE_PROFILE)
}

/// The index angles of the groove: curled to press into the plane, straightened to lift.
const GROOVE_CURL: f64 = 0.5;
const GROOVE_LIFT: f64 = -0.25;

/// A groove drawn across the 10 × 10 plane: the hand hovers at `x = −3.5`, the index curls
/// into the plane (the press comes from the glove's bend alone), the hand draws the finger
/// 7 side along +x with the fingertip 0.3 side below the plane, the finger straightens to lift
/// out, and the hand leaves. The finger leans 20° forward along the stroke. 120 Hz.
///
/// # Errors
/// Never for these fixed motions (see [`Choreography::finish`]).
pub fn plane_groove() -> Result<Trace, HandError> {
    let mut c = Choreography::new(Choreography::WORLD, 120.0)?;
    let lean = 20f64.to_radians();
    let axis = DVec3::new(lean.sin(), 0.0, -lean.cos());
    let (start, end) = (DVec3::new(-3.5, 0.0, -0.3), DVec3::new(3.5, 0.0, -0.3));
    // The pose that puts the curled fingertip at the start of the stroke; with the finger
    // straight, the same pose holds the fingertip above the plane.
    let curled = [(Joint::IndexMcp, GROOVE_CURL)];
    let straight = [(Joint::IndexMcp, POINTING[4].1)];
    c.set_angles(&curled);
    c.place(start, axis, DVec3::X);
    let pressing = c.pose();
    c.set_angles(&straight);
    let above = c.shifted(pressing, DVec3::new(-1.0, 0.0, 1.5));
    c.set_pose(above);
    c.hold(12);
    c.move_pose_to(pressing, 36);
    c.bend_to(&curled, 30);
    c.hold(6);
    c.move_to(end, axis, 420);
    c.hold(6);
    c.bend_to(&[(Joint::IndexMcp, GROOVE_LIFT)], 30);
    let away = c.shifted(c.pose(), DVec3::new(1.0, 0.0, 1.5));
    c.move_pose_to(away, 30);
    c.finish(GLOVE_PROFILE)
}

/// One ring of pushes around the tube's axis at height `z`, at `count` azimuths starting at
/// `phase`: from inside (`outward`, the finger pointing away from the axis) to radius
/// `radius`, or from outside (pointing at the axis). Between pushes the fingertip withdraws
/// to `clear` (a radius away from the wall) and turns to the next azimuth there.
#[allow(clippy::too_many_arguments)]
fn ring(
    c: &mut Choreography,
    z: f64,
    radius: f64,
    clear: f64,
    outward: bool,
    count: usize,
    phase: f64,
    ops: &mut usize,
) {
    let radial = |phi: f64| DVec3::new(phi.cos(), phi.sin(), 0.0);
    let axis = |phi: f64| if outward { radial(phi) } else { -radial(phi) };
    let at = |phi: f64, r: f64| radial(phi) * r + DVec3::new(0.0, 0.0, z);
    c.set_up(DVec3::Z);
    c.move_to(at(phase, clear), axis(phase), 12);
    for k in 0..count {
        let phi = phase + TAU * k as f64 / count as f64;
        c.move_to(at(phi, radius), axis(phi), 8);
        c.hold(2);
        c.move_to(at(phi, clear), axis(phi), 5);
        *ops += 1;
        if k + 1 < count {
            let next = phase + TAU * (k + 1) as f64 / count as f64;
            c.path(4, |s| {
                let p = phi + (next - phi) * s;
                (at(p, clear), axis(p))
            });
        }
    }
}

/// Goes from wherever the finger is to above the tube's open top, then down into it (inside)
/// or down its outside, ending at radius `clear`, height `z`, azimuth `phi`.
fn enter(c: &mut Choreography, inside: bool, z: f64, clear: f64, phi: f64) {
    let radial = DVec3::new(phi.cos(), phi.sin(), 0.0);
    let axis = if inside { radial } else { -radial };
    let (tip, now) = c.fingertip();
    let top = 8.0;
    let over = if inside { 0.6 } else { clear };
    c.set_up(DVec3::Z);
    c.move_to(DVec3::new(tip.x, tip.y, top), now, 24);
    // Turn the finger horizontally (about the vertical) to its new direction.
    let level = DVec3::new(now.x, now.y, 0.0)
        .try_normalize()
        .unwrap_or(radial);
    c.move_to(DVec3::new(tip.x, tip.y, top), level, 12);
    c.move_to(DVec3::new(tip.x, tip.y, top), axis, 18);
    c.move_to(radial * over + DVec3::new(0.0, 0.0, top), axis, 24);
    c.move_to(radial * over + DVec3::new(0.0, 0.0, z), axis, 24);
    c.move_to(radial * clear + DVec3::new(0.0, 0.0, z), axis, 8);
}

/// Shapes the paper's test tube (128 patches: 16 around × 8 along, radius 2, walls 4 high,
/// the closed bottom a hemisphere) into a pot (Fig. 15): pushes from inside widen the belly
/// in passes, pushes from inside flare the lip, pushes from outside pull in the neck, and a
/// stroke drawn around the neck smooths it. 60 Hz. Returns the trace and the number of
/// gestures (pushes and strokes).
///
/// # Errors
/// Never for these fixed motions (see [`Choreography::finish`]).
pub fn tube_pot() -> Result<(Trace, usize), HandError> {
    let mut c = Choreography::new(Choreography::WORLD, 60.0)?;
    let mut ops = 0;
    let step = TAU / 16.0;
    c.place(
        DVec3::new(0.0, -4.0, 9.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::Z,
    );
    c.hold(6);
    // The belly, from inside: a lower ring, two passes at the widest height, the shoulder.
    enter(&mut c, true, 3.2, 1.2, 0.0);
    for (z, r, phase) in [
        (3.2, 2.3, 0.0),
        (2.5, 2.25, 0.5 * step),
        (3.2, 2.55, 0.5 * step),
        (3.9, 2.35, 0.0),
        (3.2, 2.7, 0.0),
    ] {
        ring(&mut c, z, r, 1.2, true, 16, phase, &mut ops);
    }
    // The lip, from inside, while the wall above the belly is still straight: pressed along
    // the wall's normal (the contact rule), a push on the straight wall flares it outward and
    // leaves the rim at its height; pressed after the neck, on the wall sloping out from the
    // neck, the normal would carry the rim down below the lip's height.
    ring(&mut c, 5.85, 2.45, 1.2, true, 16, 0.0, &mut ops);
    // The neck, from outside: two passes, then a stroke drawn once around.
    enter(&mut c, false, 5.0, 2.9, 0.0);
    for (z, r, phase) in [
        (5.0, 1.75, 0.0),
        (4.6, 1.95, 0.5 * step),
        (5.0, 1.5, 0.5 * step),
    ] {
        ring(&mut c, z, r, 2.9, false, 16, phase, &mut ops);
    }
    let radial = |phi: f64| DVec3::new(phi.cos(), phi.sin(), 0.0);
    let neck = |phi: f64, r: f64| radial(phi) * r + DVec3::new(0.0, 0.0, 5.0);
    c.move_to(neck(0.0, 1.3), -radial(0.0), 10);
    c.path(150, |s| {
        let phi = TAU * s;
        (neck(phi, 1.3), -radial(phi))
    });
    c.move_to(neck(0.0, 2.9), -radial(0.0), 8);
    ops += 1;
    let (tip, axis) = c.fingertip();
    c.move_to(DVec3::new(tip.x, tip.y, 9.0), axis, 30);
    Ok((c.finish(GLOVE_PROFILE)?, ops))
}

/// The camera of the mouse trace: 12 side in front of the sphere (−y), 5 above.
pub const MOUSE_CAMERA: DVec3 = DVec3::new(0.0, -12.0, 5.0);

/// Mouse gestures on the paper's sphere, through [`MouseFinger`] and the real mouse hand of
/// `nendo_devices`, seen from [`MOUSE_CAMERA`]: a left click (push by the click depth 0.3), a
/// left drag (a groove drawn along a parallel), a right click (pull by 0.3), and a left press
/// deepened by five wheel steps. 60 Hz.
///
/// Each press anchors on the surface under the cursor. The script anchors on the sphere as it
/// was at the start, so that the trace does not depend on how the loop deforms the surface:
/// the depths are measured from the starting sphere (the clay under the right click had
/// moved by 0.014 side, well inside the grip's reach of 0.05).
///
/// # Errors
/// Never for these fixed motions.
pub fn mouse_sphere() -> Result<Trace, HandError> {
    let sphere = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .map_err(|e| HandError::Model(e.to_string()))?;
    let mut finger = MouseFinger::new(MouseProfile::default(), 0.3)?;
    let joints: Vec<Joint> = finger.pointing_joints();
    let on_sphere = |lat: f64, lon: f64| {
        let (lat, lon) = (lat.to_radians(), lon.to_radians());
        3.0 * DVec3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin())
    };
    // (cursor target on the sphere, buttons, wheel steps) per event.
    let mut events: Vec<(DVec3, u32, f64)> = Vec::new();
    // Hover in from the left.
    for i in 0..20 {
        events.push((on_sphere(10.0, -150.0 + 1.5 * i as f64), 0, 0.0));
    }
    // A left click: push.
    let a = on_sphere(25.0, -120.0);
    for b in [buttons::PRIMARY; 12].into_iter().chain([0; 4]) {
        events.push((a, b, 0.0));
    }
    // A left drag along the parallel −20° from longitude −125° to −55°: a groove.
    for i in 0..=70 {
        events.push((on_sphere(-20.0, -125.0 + i as f64), buttons::PRIMARY, 0.0));
    }
    events.push((on_sphere(-20.0, -55.0), 0, 0.0));
    // A right click: pull.
    let d = on_sphere(30.0, -60.0);
    for b in [buttons::SECONDARY; 12].into_iter().chain([0; 4]) {
        events.push((d, b, 0.0));
    }
    // A left press deepened by the wheel.
    let e = on_sphere(5.0, -90.0);
    for i in 0..16 {
        events.push((
            e,
            buttons::PRIMARY,
            if (4..9).contains(&i) { 1.0 } else { 0.0 },
        ));
    }
    for _ in 0..6 {
        events.push((e, 0, 0.0));
    }
    let mut frames: Vec<HandFrame> = Vec::new();
    for (k, (target, held, wheel)) in events.into_iter().enumerate() {
        if wheel != 0.0 {
            finger.wheel(wheel);
        }
        let time = Timestamp((k as f64 * 1e6 / 60.0).round() as u64);
        let ray = ViewRay {
            origin: MOUSE_CAMERA,
            direction: target - MOUSE_CAMERA,
        };
        for f in finger.frames(time, ray, held, &sphere)? {
            frames.push(quantize_frame(&f, &joints));
        }
    }
    Ok(Trace {
        header: TraceHeader {
            profile: Some("mouse".into()),
            world_from_tracker: WorldFromTracker::default(),
            hand: HandSize::default(),
            joints,
            scene: None,
        },
        frames,
    })
}

/// Every shipped trace, generated (see `devices/README.md` and `examples/hand_traces.rs`).
///
/// # Errors
/// Never for the fixed motions; a [`HandError`] would name what failed.
pub fn shipped() -> Result<Vec<Shipped>, HandError> {
    let sphere = PrimitiveParams::default();
    let (pot, _) = tube_pot()?;
    let mut shipped = vec![
        Shipped {
            name: "sphere-push-pull",
            about: "push 0.6 at the north pole, then grip and pull 0.6 at the equator (glove + tracker, 120 Hz)",
            primitive: Primitive::Sphere,
            params: sphere,
            finger: FingerModel::digit(Digit::Index),
            trace: sphere_push_pull()?,
        },
        Shipped {
            name: "plane-groove",
            about: "a groove 0.3 deep drawn 7 side across the plane; the finger curls in and straightens out (glove + tracker, 120 Hz)",
            primitive: Primitive::Plane,
            params: PrimitiveParams::default(),
            finger: FingerModel::digit(Digit::Index),
            trace: plane_groove()?,
        },
        Shipped {
            name: "tube-pot",
            about: "the test tube shaped into a pot: belly pushed out from inside, neck pushed in and stroked, lip flared (glove + tracker, 60 Hz)",
            primitive: Primitive::Tube,
            params: PrimitiveParams::default(),
            finger: FingerModel::digit(Digit::Index),
            trace: pot,
        },
        Shipped {
            name: "mouse-sphere",
            about: "mouse: click push, drag groove, right-click pull, wheel-deepened press on the sphere (60 Hz)",
            primitive: Primitive::Sphere,
            params: sphere,
            finger: FingerModel::Ray,
            trace: mouse_sphere()?,
        },
        Shipped {
            name: "sphere-pinch-pull",
            about: "thumb and index pinch the sphere's clay at the equator and pull a nose 1 side out (glove + tracker, 120 Hz)",
            primitive: Primitive::Sphere,
            params: sphere,
            // The pinch's two fingers: curled, the others would brush the sphere on the way in.
            finger: FingerModel::Hand(Fingers::THUMB_AND_INDEX),
            trace: sphere_pinch_pull()?,
        },
        Shipped {
            name: "tube-rim-pinch",
            about: "thumb outside and index inside press the tube's wall near the rim from both sides (glove + tracker, 60 Hz)",
            primitive: Primitive::Tube,
            params: PrimitiveParams::default(),
            finger: FingerModel::Hand(Fingers::THUMB_AND_INDEX),
            trace: tube_rim_pinch()?,
        },
        Shipped {
            name: "plane-palm",
            about: "a flat hand laid palm down 0.1 into the plane and lifted (glove + tracker, 120 Hz)",
            primitive: Primitive::Plane,
            params: PrimitiveParams::default(),
            finger: FingerModel::Hand(Fingers::ALL.with(Part::Palm)),
            trace: plane_palm(0.1)?,
        },
    ];
    // Every header names the scene it was made on.
    for s in &mut shipped {
        let scene = s
            .scene()
            .and_then(|scene| scene.to_text())
            .map_err(|e| HandError::Model(format!("{}: {e}", s.name)))?;
        s.trace.header.scene = Some(scene);
    }
    Ok(shipped)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scripted_glove_reports_the_profiles_joints() {
        let p = nendo_devices::profile::resolve(GLOVE_PROFILE).unwrap();
        assert_eq!(p.glove().unwrap().joints(), CYBERGLOVE_18_JOINTS.to_vec());
        for (k, (j, _)) in POINTING.iter().enumerate() {
            assert_eq!(*j, CYBERGLOVE_18_JOINTS[k]);
        }
    }

    #[test]
    fn a_choreography_puts_the_fingertip_where_it_is_told() {
        let mut c = Choreography::new(Choreography::WORLD, 100.0).unwrap();
        c.place(DVec3::new(0.0, 0.0, 1.0), -DVec3::Z, DVec3::Y);
        c.move_to(
            DVec3::new(1.0, 2.0, 0.5),
            DVec3::new(0.0, 0.3, -1.0).normalize(),
            10,
        );
        let (tip, axis) = c.fingertip();
        assert!((tip - DVec3::new(1.0, 2.0, 0.5)).length() < 1e-12);
        assert!((axis - DVec3::new(0.0, 0.3, -1.0).normalize()).length() < 1e-12);
        let t = c.finish("x").unwrap();
        assert_eq!(t.frames.len(), 10);
        assert_eq!(t.frames[9].time.as_micros(), 90_000);
        // The frames hold the trace's rounded values: the fingertip within rounding.
        let hand = Hand::new(HandSize::default(), Choreography::WORLD).unwrap();
        let f = t.frames[9];
        let placed = hand.pose(&f.pose.unwrap(), f.joints.as_ref());
        assert!((placed.finger(Digit::Index).tip() - DVec3::new(1.0, 2.0, 0.5)).length() < 1e-4);
    }
}
