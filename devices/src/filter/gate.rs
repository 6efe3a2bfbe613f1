//! The plausibility gate of one channel: a sample a hand cannot have produced is rejected and
//! the last good value held (see the parent module's docs for the rules and the limits).

use glam::DQuat;

use super::one_euro::{rotate_by, rotation_between};

/// Why the gate rejected a sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Rejection {
    /// Not finite, outside the physical range (a position beyond
    /// [`crate::POSITION_LIMIT_M`], a quaternion that is not of unit norm, a joint angle
    /// outside its range).
    OutOfRange,
    /// Farther from the last good sample than the speed limit allows.
    TooFast,
    /// Farther from the constant-velocity prediction than the acceleration limit allows.
    TooSudden,
}

/// What the gate says of one sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Plausible: pass it on.
    Accept,
    /// Implausible, but every sample has been rejected for longer than the hold limit: the
    /// jump is real (the tracker re-acquired the hand elsewhere); accepted, history restarted.
    Resync,
    /// Implausible: hold the last good value.
    Reject(Rejection),
}

/// One channel's kinematic limits, in its own units (metres or radians, per second).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Limits {
    /// Largest speed `v_max`.
    pub speed: f64,
    /// Largest acceleration `a_max`.
    pub acceleration: f64,
    /// The measurement noise allowed on top of both, `n`.
    pub noise: f64,
    /// Longest run of rejections (seconds) before the gate gives in ([`Verdict::Resync`]).
    pub hold_max: f64,
}

/// A sample as the gate sees it: a point of `ℝᴺ` or a rotation.
pub(super) trait Sample: Copy {
    /// The distance from `self` to `other` (metres, or the rotation angle in radians).
    fn distance(self, other: Self) -> f64;
    /// Where the channel would be `dt` after `last` moving as it did from `before` to `last`
    /// in `dt_before`.
    fn predict(before: Self, last: Self, dt_before: f64, dt: f64) -> Self;
}

impl<const N: usize> Sample for [f64; N] {
    fn distance(self, other: Self) -> f64 {
        self.iter()
            .zip(other)
            .map(|(a, b)| (a - b) * (a - b))
            .sum::<f64>()
            .sqrt()
    }

    fn predict(before: Self, last: Self, dt_before: f64, dt: f64) -> Self {
        std::array::from_fn(|k| last[k] + (last[k] - before[k]) * (dt / dt_before))
    }
}

impl Sample for DQuat {
    fn distance(self, other: Self) -> f64 {
        rotation_between(self, other).length()
    }

    fn predict(before: Self, last: Self, dt_before: f64, dt: f64) -> Self {
        rotate_by(last, rotation_between(before, last) * (dt / dt_before))
    }
}

/// The gate of one channel: the last two accepted samples and their times, and how long it
/// has been rejecting.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Gate<S> {
    last: Option<(S, f64)>,
    before: Option<(S, f64)>,
    /// Consecutive kinematic rejections since the last accepted sample.
    held: u32,
}

impl<S: Sample> Default for Gate<S> {
    fn default() -> Self {
        Self {
            last: None,
            before: None,
            held: 0,
        }
    }
}

impl<S: Sample> Gate<S> {
    /// Judges sample `x` at time `t` (seconds); `in_range` says whether it passed the
    /// range checks; `period` is the source's sampling period estimate, the shortest
    /// interval the kinematic checks assume between two samples.
    ///
    /// With `Δt = max(t − t_last, period)`: rejected when
    /// `|x − x_last| > v_max·Δt + n`, or, with two accepted samples in a row, when
    /// `|x − x_pred| > a_max·Δt² + n` where `x_pred` continues the last step, as the
    /// timestamps space it (`x_last + (x_last − x_before)·Δt/Δt_before`) or as one more equal
    /// step (`2·x_last − x_before`), whichever is nearer `x`. A kinematic rejection that would make
    /// the hold longer than `hold_max` — `max(t − t_last, (k + 1)·period)` for the `k`-th
    /// rejection in a row, so frames without a usable clock end a hold too — becomes
    /// [`Verdict::Resync`].
    pub fn judge(&mut self, x: S, in_range: bool, t: f64, period: f64, l: &Limits) -> Verdict {
        if !in_range {
            return Verdict::Reject(Rejection::OutOfRange);
        }
        let Some((last, t_last)) = self.last else {
            self.accept(x, t);
            return Verdict::Accept;
        };
        let dt = (t - t_last).max(period);
        let mut why = None;
        if x.distance(last) > l.speed * dt + l.noise {
            why = Some(Rejection::TooFast);
        } else if let Some((before, t_before)) = self.before {
            let dt_before = (t_last - t_before).max(period);
            // The last step continued as the timestamps space the samples, or as one more
            // equal step: the nearer counts.
            let stamped = S::predict(before, last, dt_before, dt);
            let regular = S::predict(before, last, 1.0, 1.0);
            let miss = x.distance(stamped).min(x.distance(regular));
            if miss > l.acceleration * dt * dt + l.noise {
                why = Some(Rejection::TooSudden);
            }
        }
        match why {
            None => {
                self.accept(x, t);
                Verdict::Accept
            }
            Some(_) if dt.max(f64::from(self.held + 1) * period) > l.hold_max => {
                self.before = None;
                self.last = Some((x, t));
                self.held = 0;
                Verdict::Resync
            }
            Some(r) => {
                self.held += 1;
                Verdict::Reject(r)
            }
        }
    }

    /// Takes `x` as the last good sample. After a run of rejections the step from the held
    /// sample spans the gap and says nothing of the velocity: the acceleration check waits
    /// for the next step.
    fn accept(&mut self, x: S, t: f64) {
        self.before = if self.held == 0 { self.last } else { None };
        self.last = Some((x, t));
        self.held = 0;
    }
}
