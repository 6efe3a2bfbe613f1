//! Filtering as trackers do it: a plausibility gate, then a One-Euro filter, on the tracker's
//! position and orientation, on every glove joint, and on every joint of a skeleton hand
//! (its position and orientation, [`skeleton`]) ([`FrameFilter`]).
//!
//! A hand frame goes through [`FrameFilter::apply`] before anything reads it (in nendo: the
//! first thing the hand loop does with a frame, so the window and `nendo replay` filter the
//! same frames the same way). The frame keeps its time, buttons and source states; its pose
//! and joint angles are replaced by their filtered values. Recorded traces keep the raw
//! samples: the filter is a pure function of the frames and its [`FilterSettings`], so a
//! replay recomputes exactly what the window showed, and which samples the gate held.
//!
//! ## Samples and time
//!
//! Each source (tracker, glove) is filtered per *sample*, not per frame: a frame is a new
//! tracker sample when it says so ([`crate::FrameStatus::tracker_fresh`]) or its pose differs
//! from the last one; a frame with neither source marked fresh (built by hand, or by a
//! program that does not know) is a new sample of every source it carries. Other frames pass
//! the last filtered value on unchanged. Time is the frames' own timestamps, never the wall
//! clock: `T_e = max(t − t_prev, T̂)`, where `T̂` is the source's sampling period, estimated as
//! the running mean of the intervals between its samples (`T̂ ← T̂ + (Δt − T̂)/8`, `Δt`
//! clamped to [0.5 ms, 100 ms], starting at 1/120 s; intervals of zero are not counted). The
//! floor `T̂` matters because a stream timestamps samples when they are read: records that
//! arrive together in one read are microseconds apart on the clock but a period apart in
//! truth. A frame timed before the previous one starts another stream (a trace played after
//! another): every channel starts afresh, its first sample passing through as it is.
//!
//! ## The plausibility gate
//!
//! Before the filter, each channel's sample is judged against what a hand can do
//! ([`GateLimits`]); a rejected sample is not filtered — the channel holds its last good
//! value — and is counted per channel and reason ([`FilterStats`]). With `Δt = max(t −
//! t_last, T̂)` from the last accepted sample:
//!
//! 1. **Range.** Not finite, a position beyond [`POSITION_LIMIT_M`], a quaternion whose norm
//!    is off by more than [`QUATERNION_NORM_TOLERANCE`], a joint angle outside its range
//!    ([`joint_range`]): rejected (and never accepted later by rule 4).
//! 2. **Speed.** `|x − x_last| > v_max·Δt + n`: farther than the hand could have gone.
//! 3. **Acceleration.** With two samples accepted in a row, `|x − x_pred| > a_max·Δt² + n`, where
//!    `x_pred = x_last + (x_last − x_before)·Δt/Δt_before` continues the last step at
//!    constant velocity: the hand would have had to accelerate harder than `a_max` (the
//!    second difference of a motion with acceleration at most `a` is at most `a·Δt²`). As
//!    samples read in a burst carry squeezed timestamps (and the gap after the burst a
//!    stretched one) while the device samples at a fixed rate, the prediction `2·x_last −
//!    x_before` of one more equal step is also tried, and the nearer of the two counts. This is
//!    what catches a one-sample spike at any rate: a 6 cm spike at 60 Hz is only 3.6 m/s, but
//!    2.7 cm more than a hand accelerating at 10 g could add.
//! 4. **Hold limit.** A run of kinematic rejections (rules 2–3) longer than `hold_max_s` ends:
//!    the next implausible sample is accepted and the channel's history restarts from it
//!    (counted as a resync) — a jump that lasts is real (the tracker re-acquired the hand
//!    somewhere else), and holding it off forever would freeze the hand.
//!
//! `n` is the measurement noise allowed on top (it keeps jitter from tripping rules 2–3: the
//! second difference of white noise of deviation `σ` has deviation `√6·σ`). Position limits
//! are in metres per second in the tracker's frame, whatever the profile's scale (frames
//! carry metres; the scale maps them to world units afterwards): the defaults are
//! `v_max = 5 m/s` (fast reaching peaks at 2–3 m/s), `a_max = 100 m/s²` (about 10 g; a fast
//! point-to-point hand movement peaks near 20–50 m/s², a flick of the wrist swings the sensor
//! harder), `n = 5 mm` (ten times a magnetic
//! tracker's typical 0.5 mm jitter; at 240 Hz it keeps the false rejections of that jitter
//! below 10⁻⁴). Orientation: `40 rad/s`, `400 rad/s²` (a fast turn of the wrist reaches
//! 10 rad/s within 25 ms), `0.01 rad` (five times a magnetic tracker's 0.1° of noise).
//! Joints: `40 rad/s`, `500 rad/s²` (fast finger tapping, 0.5 rad at 5 Hz, peaks near
//! 500 rad/s²), `0.03 rad` (about four counts of a CyberGlove's 0.4° steps).
//! `hold_max_s = 0.25`. So at 120 Hz a tracker sample more than 12 mm off the
//! constant-velocity prediction is held (33 mm at 60 Hz, 6.7 mm at 240 Hz), an orientation
//! more than 0.038 rad off, a joint more than 0.08 rad off at 100 Hz; smaller glitches pass
//! the gate and are smoothed by the filter like jitter.
//!
//! ## The filter
//!
//! Accepted samples go through the One-Euro filter ([`one_euro`]: cutoff
//! `f_c = f_cmin + β·|Ẋ̂|`, `α = 1/(1 + τ/T_e)`, `τ = 1/(2π f_c)`, the derivative filtered at
//! `d_cutoff`). The position is one 3-vector (one cutoff from its speed), the orientation a
//! unit quaternion filtered by slerp on the short arc, each joint a scalar. Defaults
//! ([`FilterSettings::default`]), each `f_cmin = 1 Hz`, `d_cutoff = 1 Hz`:
//!
//! | channel | `β` | lag bound `1/(2πβ)` | |
//! |---|---|---|---|
//! | position | 200 per m/s | 0.8 mm | 0.5 mm RMS of jitter at rest → about 0.12 mm |
//! | orientation | 30 per rad/s | 0.0053 rad | 0.3° at the sensor, 0.8 mm at a fingertip 15 cm away |
//! | joints | 10 per rad/s | 0.016 rad | 0.6 mm at the tip of a 4 cm segment |
//!
//! (`β` was chosen by the paper's procedure: `f_cmin` for jitter at rest, then `β` up until
//! the lag at hand speeds is about a millimetre; the orientation's and the joints' are the
//! position's times the lever they act through, 15 cm and 5 cm. The lag bound holds at a
//! steady speed; a short, quick motion lags more while `Ẋ̂` catches up — the derivative's
//! own low-pass has a time constant of 0.16 s at 1 Hz.) A channel the source stops delivering
//! (not `ok`, or no value) is forgotten: when it comes back its first sample passes through.
//!
//! [`POSITION_LIMIT_M`]: crate::POSITION_LIMIT_M
//! [`QUATERNION_NORM_TOLERANCE`]: crate::frame::QUATERNION_NORM_TOLERANCE

mod gate;
pub mod one_euro;
mod skeleton;
#[cfg(test)]
mod tests;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::frame::QUATERNION_NORM_TOLERANCE;
use crate::skeleton::HandJoint;
use crate::{HandFrame, Joint, JointAngles, POSITION_LIMIT_M, SourceState, TrackerPose};
use gate::{Gate, Limits};
pub use gate::{Rejection, Verdict};
use one_euro::{OneEuro, OneEuroRotation};
pub use one_euro::{OneEuroParams, smoothing_factor};

/// The sampling period assumed before a source's first interval, seconds (120 Hz).
pub const DEFAULT_PERIOD_S: f64 = 1.0 / 120.0;
/// The shortest and longest interval counted in a source's period estimate, seconds.
pub const PERIOD_RANGE_S: [f64; 2] = [0.5e-3, 0.1];

/// The gate's limits ([`FilterSettings::gate`]); see the module docs for the rules and the
/// defaults' reasoning.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GateLimits {
    /// Largest tracker speed, metres per second (default 5).
    pub max_speed_m_s: f64,
    /// Largest tracker acceleration, metres per second² (default 100).
    pub max_acceleration_m_s2: f64,
    /// Tracker position noise allowed on top, metres (default 0.005).
    pub position_noise_m: f64,
    /// Largest angular speed of the hand sensor, radians per second (default 40).
    pub max_angular_speed_rad_s: f64,
    /// Largest angular acceleration of the hand sensor, radians per second² (default 400).
    pub max_angular_acceleration_rad_s2: f64,
    /// Orientation noise allowed on top, radians (default 0.01).
    pub orientation_noise_rad: f64,
    /// Largest joint speed, radians per second (default 40).
    pub max_joint_speed_rad_s: f64,
    /// Largest joint acceleration, radians per second² (default 500).
    pub max_joint_acceleration_rad_s2: f64,
    /// Joint angle noise allowed on top, radians (default 0.03).
    pub joint_noise_rad: f64,
    /// Longest a channel holds its last good value against implausible samples, seconds
    /// (default 0.25).
    pub hold_max_s: f64,
}

impl Default for GateLimits {
    fn default() -> Self {
        Self {
            max_speed_m_s: 5.0,
            max_acceleration_m_s2: 100.0,
            position_noise_m: 0.005,
            max_angular_speed_rad_s: 40.0,
            max_angular_acceleration_rad_s2: 400.0,
            orientation_noise_rad: 0.01,
            max_joint_speed_rad_s: 40.0,
            max_joint_acceleration_rad_s2: 500.0,
            joint_noise_rad: 0.03,
            hold_max_s: 0.25,
        }
    }
}

/// The filter of a device profile (its `filter` member) and of a recorded session's scene:
/// gate limits and the One-Euro parameters per kind of channel. Every member is optional in
/// JSON (absent: the default); a profile without `filter` has the defaults.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FilterSettings {
    /// Gate and filter on (default `true`); off, frames pass unchanged.
    pub enabled: bool,
    /// The tracker's position, metres (default `f_cmin` 1 Hz, `β` 200 per m/s, `d_cutoff`
    /// 1 Hz).
    pub position: OneEuroParams,
    /// The tracker's orientation, radians (default 1 Hz, 30 per rad/s, 1 Hz).
    pub orientation: OneEuroParams,
    /// Each glove joint, radians (default 1 Hz, 10 per rad/s, 1 Hz).
    pub joints: OneEuroParams,
    /// The plausibility gate's limits.
    pub gate: GateLimits,
}

impl Default for FilterSettings {
    fn default() -> Self {
        let params = |beta| OneEuroParams {
            min_cutoff_hz: 1.0,
            beta,
            d_cutoff_hz: 1.0,
        };
        Self {
            enabled: true,
            position: params(200.0),
            orientation: params(30.0),
            joints: params(10.0),
            gate: GateLimits::default(),
        }
    }
}

/// A filter setting out of its range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("filter.{name} is {value}; it must be {expected}")]
pub struct FilterError {
    /// The member, as `position.beta`.
    pub name: &'static str,
    /// Its value.
    pub value: f64,
    /// What it must be.
    pub expected: &'static str,
}

impl FilterSettings {
    /// No gate, no filter: frames pass unchanged (the other members at their defaults).
    #[must_use]
    pub fn off() -> Self {
        Self {
            enabled: false,
            ..Self::default()
        }
    }

    /// Checks every number: cutoffs and limits positive and finite, `β` finite and not
    /// negative.
    ///
    /// # Errors
    /// [`FilterError`] naming the first bad member.
    pub fn validate(&self) -> Result<(), FilterError> {
        let g = &self.gate;
        let mut checks: Vec<(&'static str, f64, bool)> = Vec::new();
        for (names, p) in [
            (
                [
                    "position.min_cutoff_hz",
                    "position.beta",
                    "position.d_cutoff_hz",
                ],
                &self.position,
            ),
            (
                [
                    "orientation.min_cutoff_hz",
                    "orientation.beta",
                    "orientation.d_cutoff_hz",
                ],
                &self.orientation,
            ),
            (
                ["joints.min_cutoff_hz", "joints.beta", "joints.d_cutoff_hz"],
                &self.joints,
            ),
        ] {
            checks.push((names[0], p.min_cutoff_hz, true));
            checks.push((names[1], p.beta, false));
            checks.push((names[2], p.d_cutoff_hz, true));
        }
        for (name, value) in [
            ("gate.max_speed_m_s", g.max_speed_m_s),
            ("gate.max_acceleration_m_s2", g.max_acceleration_m_s2),
            ("gate.position_noise_m", g.position_noise_m),
            ("gate.max_angular_speed_rad_s", g.max_angular_speed_rad_s),
            (
                "gate.max_angular_acceleration_rad_s2",
                g.max_angular_acceleration_rad_s2,
            ),
            ("gate.orientation_noise_rad", g.orientation_noise_rad),
            ("gate.max_joint_speed_rad_s", g.max_joint_speed_rad_s),
            (
                "gate.max_joint_acceleration_rad_s2",
                g.max_joint_acceleration_rad_s2,
            ),
            ("gate.joint_noise_rad", g.joint_noise_rad),
            ("gate.hold_max_s", g.hold_max_s),
        ] {
            checks.push((name, value, true));
        }
        for (name, value, strictly) in checks {
            let ok = value.is_finite() && if strictly { value > 0.0 } else { value >= 0.0 };
            if !ok {
                return Err(FilterError {
                    name,
                    value,
                    expected: if strictly {
                        "a positive number"
                    } else {
                        "a number not below zero"
                    },
                });
            }
        }
        Ok(())
    }

    fn position_limits(&self) -> Limits {
        let g = &self.gate;
        Limits {
            speed: g.max_speed_m_s,
            acceleration: g.max_acceleration_m_s2,
            noise: g.position_noise_m,
            hold_max: g.hold_max_s,
        }
    }

    fn orientation_limits(&self) -> Limits {
        let g = &self.gate;
        Limits {
            speed: g.max_angular_speed_rad_s,
            acceleration: g.max_angular_acceleration_rad_s2,
            noise: g.orientation_noise_rad,
            hold_max: g.hold_max_s,
        }
    }

    fn joint_limits(&self) -> Limits {
        let g = &self.gate;
        Limits {
            speed: g.max_joint_speed_rad_s,
            acceleration: g.max_joint_acceleration_rad_s2,
            noise: g.joint_noise_rad,
            hold_max: g.hold_max_s,
        }
    }
}

/// The range of angles the gate accepts for a joint, radians `[low, high]`: the hand's
/// active range (flexion of the finger joints −30° to 110°, the thumb–index spread up to
/// 90°, the other spreads ±30°, wrist flexion ±80°, wrist deviation −20° to 35°; Hume et al.,
/// "Functional range of motion of the joints of the hand", J Hand Surg 1990, and the AAOS
/// norms), widened by about 20° either way for calibration error. Every shipped profile's
/// calibration maps its sensors' whole raw range inside these (tested).
#[must_use]
pub fn joint_range(joint: Joint) -> [f64; 2] {
    use Joint::*;
    match joint {
        ThumbIndexAbduction | PalmArch => [-0.9, 1.9],
        IndexMiddleAbduction | MiddleRingAbduction | RingPinkyAbduction | WristYaw => [-0.9, 0.9],
        WristPitch => [-1.7, 1.7],
        _ => [-0.9, 2.4],
    }
}

/// Rejections of one kind of channel, by reason.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Rejections {
    /// Not finite or outside the physical range.
    pub out_of_range: u64,
    /// Beyond the speed limit.
    pub too_fast: u64,
    /// Beyond the acceleration limit.
    pub too_sudden: u64,
}

impl Rejections {
    /// Every rejection.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.out_of_range + self.too_fast + self.too_sudden
    }

    fn count(&mut self, r: Rejection) {
        match r {
            Rejection::OutOfRange => self.out_of_range += 1,
            Rejection::TooFast => self.too_fast += 1,
            Rejection::TooSudden => self.too_sudden += 1,
        }
    }
}

/// What a [`FrameFilter`] has seen and rejected.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FilterStats {
    /// Tracker samples judged.
    pub tracker_samples: u64,
    /// Glove samples judged.
    pub glove_samples: u64,
    /// Tracker positions rejected (the last good one held).
    pub position: Rejections,
    /// Tracker orientations rejected.
    pub orientation: Rejections,
    /// Joint angles rejected, over every joint.
    pub joints: Rejections,
    /// Joint angles rejected, per joint ([`Joint::index`]).
    pub per_joint: [u64; Joint::COUNT],
    /// Skeleton samples judged (frames carrying a new skeleton, [`skeleton`]).
    pub skeleton_samples: u64,
    /// Skeleton joint positions rejected, over every joint.
    pub skeleton_positions: Rejections,
    /// Skeleton joint orientations rejected, over every joint.
    pub skeleton_orientations: Rejections,
    /// Holds that ended by accepting a lasting jump (rule 4 of the gate).
    pub resyncs: u64,
    /// Frames with at least one value held.
    pub frames_held: u64,
}

impl FilterStats {
    /// Every rejected value: positions, orientations and joint angles.
    #[must_use]
    pub fn rejected(&self) -> u64 {
        self.position.total()
            + self.orientation.total()
            + self.joints.total()
            + self.skeleton_positions.total()
            + self.skeleton_orientations.total()
    }
}

/// The values one frame had held by the gate.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Held {
    /// The tracker's position, and why.
    pub position: Option<Rejection>,
    /// The tracker's orientation, and why.
    pub orientation: Option<Rejection>,
    /// The joints held ([`Joint::index`] bits).
    pub joints: u32,
    /// The skeleton joints whose position was held ([`HandJoint::index`] bits).
    pub skeleton_positions: u32,
    /// The skeleton joints whose orientation was held ([`HandJoint::index`] bits).
    pub skeleton_orientations: u32,
}

impl Held {
    /// Nothing held.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.position.is_none()
            && self.orientation.is_none()
            && self.joints == 0
            && self.skeleton_positions == 0
            && self.skeleton_orientations == 0
    }

    /// The skeleton joints held, by position or orientation.
    pub fn skeleton_joints(&self) -> impl Iterator<Item = HandJoint> + '_ {
        let bits = self.skeleton_positions | self.skeleton_orientations;
        HandJoint::ALL
            .into_iter()
            .filter(move |j| bits & (1 << j.index()) != 0)
    }

    /// The joints held.
    pub fn joints(&self) -> impl Iterator<Item = Joint> + '_ {
        Joint::ALL
            .into_iter()
            .filter(|j| self.joints & (1 << j.index()) != 0)
    }
}

/// A source's sampling clock: the last sample's time and the period estimate `T̂`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Clock {
    last: Option<f64>,
    period: f64,
}

impl Default for Clock {
    fn default() -> Self {
        Self {
            last: None,
            period: DEFAULT_PERIOD_S,
        }
    }
}

impl Clock {
    /// A new sample at `t`: updates `T̂ ← T̂ + (Δt − T̂)/8` (see the module docs).
    fn tick(&mut self, t: f64) {
        if let Some(last) = self.last {
            let dt = t - last;
            if dt > 0.0 {
                let dt = dt.clamp(PERIOD_RANGE_S[0], PERIOD_RANGE_S[1]);
                self.period += (dt - self.period) / 8.0;
            }
        }
        self.last = Some(t);
    }
}

/// One channel: its gate, its filter, and when the filter last took a sample.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Channel<S, F> {
    gate: Gate<S>,
    filter: F,
    filtered_at: Option<f64>,
}

impl<S: gate::Sample, F> Channel<S, F> {
    fn new(filter: F) -> Self {
        Self {
            gate: Gate::default(),
            filter,
            filtered_at: None,
        }
    }

    /// Judges `x` at `t` (`period`: the source's `T̂`); when it passes, returns the
    /// verdict and the filter's `T_e` for it.
    fn admit(
        &mut self,
        x: S,
        in_range: bool,
        (t, period): (f64, f64),
        limits: &Limits,
    ) -> Result<(Verdict, f64), Rejection> {
        match self.gate.judge(x, in_range, t, period, limits) {
            Verdict::Reject(r) => Err(r),
            v => {
                let te = self.filtered_at.map_or(period, |t0| (t - t0).max(period));
                self.filtered_at = Some(t);
                Ok((v, te))
            }
        }
    }
}

/// Counts a gate's verdict: a rejection by reason, a resync.
fn count(
    verdict: &Result<(Verdict, f64), Rejection>,
    rejections: &mut Rejections,
    resyncs: &mut u64,
) {
    match verdict {
        Err(r) => rejections.count(*r),
        Ok((Verdict::Resync, _)) => *resyncs += 1,
        Ok(_) => {}
    }
}

/// The gate and filter of a frame stream (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct FrameFilter {
    settings: FilterSettings,
    tracker_clock: Clock,
    glove_clock: Clock,
    last_time: Option<f64>,
    last_pose: Option<TrackerPose>,
    last_angles: Option<JointAngles>,
    position: Channel<[f64; 3], OneEuro<3>>,
    orientation: Channel<glam::DQuat, OneEuroRotation>,
    joints: Vec<Channel<[f64; 1], OneEuro<1>>>,
    skeleton: skeleton::SkeletonChannels,
    stats: FilterStats,
    held: Held,
}

impl Default for FrameFilter {
    fn default() -> Self {
        Self::new(FilterSettings::default())
    }
}

impl FrameFilter {
    /// A filter with these settings (they are not checked here: see
    /// [`FilterSettings::validate`]).
    #[must_use]
    pub fn new(settings: FilterSettings) -> Self {
        Self {
            settings,
            tracker_clock: Clock::default(),
            glove_clock: Clock::default(),
            last_time: None,
            last_pose: None,
            last_angles: None,
            position: Channel::new(OneEuro::new(settings.position)),
            orientation: Channel::new(OneEuroRotation::new(settings.orientation)),
            joints: (0..Joint::COUNT)
                .map(|_| Channel::new(OneEuro::new(settings.joints)))
                .collect(),
            skeleton: skeleton::SkeletonChannels::new(&settings),
            stats: FilterStats::default(),
            held: Held::default(),
        }
    }

    /// The settings.
    #[must_use]
    pub fn settings(&self) -> &FilterSettings {
        &self.settings
    }

    /// The counters so far.
    #[must_use]
    pub fn stats(&self) -> &FilterStats {
        &self.stats
    }

    /// What the last frame had held.
    #[must_use]
    pub fn held(&self) -> Held {
        self.held
    }

    /// What [`FrameFilter::apply`] would return for `frame`, without taking it in.
    #[must_use]
    pub fn peek(&self, frame: &HandFrame) -> HandFrame {
        self.clone().apply(frame)
    }

    /// Gates and filters one frame: the frame with its pose and joint angles replaced by
    /// their filtered values (a value the gate rejected holds the last good one; a channel
    /// with no good value yet is left out). Off ([`FilterSettings::enabled`]), the frame
    /// unchanged.
    pub fn apply(&mut self, frame: &HandFrame) -> HandFrame {
        self.held = Held::default();
        if !self.settings.enabled {
            return *frame;
        }
        let t = frame.time.as_secs_f64();
        if self.last_time.is_some_and(|last| t < last) {
            // Time went back: another stream (a trace played after another).
            self.reset_tracker();
            self.reset_glove();
            self.reset_skeleton();
        }
        self.last_time = Some(t);
        let unmarked = !frame.status.tracker_fresh && !frame.status.glove_fresh;
        let mut out = *frame;
        out.pose = self.tracker(frame, t, unmarked);
        out.joints = self.glove(frame, t, unmarked);
        out.skeleton = self.skeleton(frame, t, unmarked);
        if !self.held.is_empty() {
            self.stats.frames_held += 1;
        }
        out
    }

    fn reset_tracker(&mut self) {
        self.tracker_clock = Clock::default();
        self.last_pose = None;
        self.position = Channel::new(OneEuro::new(self.settings.position));
        self.orientation = Channel::new(OneEuroRotation::new(self.settings.orientation));
    }

    fn tracker(&mut self, frame: &HandFrame, t: f64, unmarked: bool) -> Option<TrackerPose> {
        let pose = match (frame.status.tracker, frame.pose) {
            (SourceState::Ok, Some(p)) => p,
            _ => {
                self.reset_tracker();
                return None;
            }
        };
        let new = unmarked || frame.status.tracker_fresh || self.last_pose != Some(pose);
        self.last_pose = Some(pose);
        if new {
            self.tracker_clock.tick(t);
            self.stats.tracker_samples += 1;
            let at = (t, self.tracker_clock.period);
            let limits = self.settings.position_limits();
            let p = pose.position.to_array();
            let in_range = p
                .iter()
                .all(|x| x.is_finite() && x.abs() <= POSITION_LIMIT_M);
            let v = self.position.admit(p, in_range, at, &limits);
            count(&v, &mut self.stats.position, &mut self.stats.resyncs);
            match v {
                Ok((_, te)) => {
                    self.position.filter.step(p, te);
                }
                Err(r) => self.held.position = Some(r),
            }
            let limits = self.settings.orientation_limits();
            let q = pose.orientation;
            let in_range = q.is_finite() && (q.length() - 1.0).abs() <= QUATERNION_NORM_TOLERANCE;
            let v = self.orientation.admit(q, in_range, at, &limits);
            count(&v, &mut self.stats.orientation, &mut self.stats.resyncs);
            match v {
                Ok((_, te)) => {
                    self.orientation.filter.step(q, te);
                }
                Err(r) => self.held.orientation = Some(r),
            }
        }
        let position = self.position.filter.value()?;
        let orientation = self.orientation.filter.value()?;
        Some(TrackerPose {
            position: DVec3::from_array(position),
            orientation,
        })
    }

    fn reset_glove(&mut self) {
        self.glove_clock = Clock::default();
        self.last_angles = None;
        for c in &mut self.joints {
            *c = Channel::new(OneEuro::new(self.settings.joints));
        }
    }

    fn glove(&mut self, frame: &HandFrame, t: f64, unmarked: bool) -> Option<JointAngles> {
        let angles = match (frame.status.glove, frame.joints) {
            (SourceState::Ok, Some(a)) => a,
            _ => {
                self.reset_glove();
                return None;
            }
        };
        let new = unmarked || frame.status.glove_fresh || self.last_angles != Some(angles);
        self.last_angles = Some(angles);
        if new {
            self.glove_clock.tick(t);
            self.stats.glove_samples += 1;
        }
        let period = self.glove_clock.period;
        let limits = self.settings.joint_limits();
        let mut out = JointAngles::new();
        for (joint, a) in angles.iter() {
            let k = joint.index();
            let c = &mut self.joints[k];
            if new {
                let [lo, hi] = joint_range(joint);
                let in_range = a.is_finite() && (lo..=hi).contains(&a);
                let v = c.admit([a], in_range, (t, period), &limits);
                count(&v, &mut self.stats.joints, &mut self.stats.resyncs);
                match v {
                    Ok((_, te)) => {
                        c.filter.step([a], te);
                    }
                    Err(_) => {
                        self.stats.per_joint[k] += 1;
                        self.held.joints |= 1 << k;
                    }
                }
            }
            if let Some([v]) = c.filter.value() {
                // A convex combination of accepted angles, all inside the joint's range:
                // always a valid angle; a value that were not is left out.
                let _ = out.set(joint, v);
            }
        }
        Some(out)
    }
}
