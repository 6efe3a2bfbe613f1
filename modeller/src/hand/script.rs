//! Scripted hand motions, written as real traces: the [`Choreography`] of a glove and tracker,
//! the named [`Gesture`]s of `nendo emulate`, and the thumb and pinch poses. The traces shipped
//! in `devices/traces/` are made from them in [`super::shipped`].
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
//! Every motion is deterministic: the same code writes the same trace.

use glam::DVec3;
use nendo_devices::trace::quantize_frame;
use nendo_devices::{
    FrameStatus, HandFrame, HandSize, Joint, JointAngles, SourceState, Timestamp, Trace,
    TraceHeader, TrackerPose, WorldFromTracker, buttons,
};
use std::f64::consts::TAU;

use super::HandError;
use super::kinematics::{Digit, Hand};

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
            skeleton: None,
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
                skeleton: None,
                marks_held: false,
            },
            frames: self.frames,
            held: Vec::new(),
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

/// The profile name in the headers of the glove traces.
pub const GLOVE_PROFILE: &str = "cyberglove2-18-fastrak";

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
