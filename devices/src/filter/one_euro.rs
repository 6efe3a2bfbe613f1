//! The One-Euro filter (Casiez, Roussel, Vogel, "1€ filter: a simple speed-based low-pass
//! filter for noisy input in interactive systems", CHI 2012): a first-order low-pass filter
//! whose cutoff rises with the signal's speed.
//!
//! For a sample `X_i` taken `T_e` seconds after the previous one (the frames' own timestamps,
//! see [`super::Clock`]):
//!
//! ```text
//! α(f_c)  = 1 / (1 + τ/T_e),   τ = 1 / (2π f_c)             smoothing factor of cutoff f_c
//! Ẋ_i     = (X_i − X_{i−1}) / T_e                           raw derivative
//! Ẋ̂_i     = Ẋ̂_{i−1} + α(d_cutoff) · (Ẋ_i − Ẋ̂_{i−1})          filtered derivative
//! f_c     = f_cmin + β · |Ẋ̂_i|                              adaptive cutoff
//! X̂_i     = X̂_{i−1} + α(f_c) · (X_i − X̂_{i−1})              filtered value
//! ```
//!
//! (the paper's §"The 1€ filter"; the derivative is the difference of the raw samples, as in
//! the authors' reference implementation, `dx = (x − lastRawValue)·rate`). The first sample
//! passes through unchanged, with `Ẋ̂ = 0`. A vector signal (the tracker's position) is
//! filtered with one cutoff for all its coordinates, from the norm `|Ẋ̂|` of its filtered
//! derivative: the filter does not depend on the tracker's axes.
//!
//! **Orientation** ([`OneEuroRotation`]) is the same filter on the rotation group: the
//! difference of two unit quaternions is the rotation vector `log(q_a⁻¹ q_b)` (axis × angle,
//! taken on the hemisphere where the angle is at most π — `q` and `−q` are the same
//! rotation), and the low-pass step is the spherical interpolation
//! `q̂_i = q̂_{i−1} · exp(α · log(q̂_{i−1}⁻¹ q_i)) = slerp(q̂_{i−1}, q_i, α)`, renormalised.
//!
//! Properties the tests check against these formulas: a constant input stays exactly
//! constant; a step is followed as `1 − Π(1 − α_k)`; the output of a monotone input never
//! overshoots it (each step is a convex combination of the previous output and the input);
//! a fast input is followed with less lag than a slow one (larger `|Ẋ̂|`, larger cutoff).

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

/// The One-Euro filter's three parameters for one kind of channel.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OneEuroParams {
    /// `f_cmin`, the cutoff at rest, in hertz: lower removes more jitter at rest.
    pub min_cutoff_hz: f64,
    /// `β`, how fast the cutoff rises with speed, in hertz per unit of speed (per m/s for
    /// the tracker's position, per rad/s for orientation and joints): higher follows fast
    /// motion with less lag. Zero: a fixed low-pass at `f_cmin`.
    pub beta: f64,
    /// The cutoff of the derivative's own low-pass, in hertz (the paper uses 1 Hz).
    pub d_cutoff_hz: f64,
}

impl OneEuroParams {
    /// The upper bound of the lag of a ramp at any speed: as `|Ẋ| → ∞` the lag `|Ẋ|·τ(f_c)`
    /// tends to `1 / (2π β)` (the continuous-time limit), in the signal's units; infinite
    /// for `β = 0`.
    #[must_use]
    pub fn lag_bound(&self) -> f64 {
        1.0 / (std::f64::consts::TAU * self.beta)
    }
}

/// `α = 1 / (1 + τ/T_e)` with `τ = 1 / (2π f_c)`: the smoothing factor of a first-order
/// low-pass of cutoff `cutoff_hz` for a sample `period_s` after the previous one.
#[must_use]
pub fn smoothing_factor(cutoff_hz: f64, period_s: f64) -> f64 {
    let tau = 1.0 / (std::f64::consts::TAU * cutoff_hz);
    1.0 / (1.0 + tau / period_s)
}

/// A One-Euro filter of an `N`-dimensional signal (one cutoff for all coordinates).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OneEuro<const N: usize> {
    params: OneEuroParams,
    /// `(X̂, X, Ẋ̂)`: the last output, the last raw sample and the filtered derivative.
    state: Option<([f64; N], [f64; N], [f64; N])>,
}

impl<const N: usize> OneEuro<N> {
    /// A filter that has seen nothing yet.
    #[must_use]
    pub fn new(params: OneEuroParams) -> Self {
        Self {
            params,
            state: None,
        }
    }

    /// The last output, if any sample has been seen.
    #[must_use]
    pub fn value(&self) -> Option<[f64; N]> {
        self.state.map(|(x, _, _)| x)
    }

    /// The filtered derivative `Ẋ̂` (zero before the second sample).
    #[must_use]
    pub fn derivative(&self) -> [f64; N] {
        self.state.map_or([0.0; N], |(_, _, d)| d)
    }

    /// Forgets everything: the next sample passes through.
    pub fn reset(&mut self) {
        self.state = None;
    }

    /// Filters sample `x` taken `period_s > 0` seconds after the previous one; returns `X̂`.
    pub fn step(&mut self, x: [f64; N], period_s: f64) -> [f64; N] {
        let p = self.params;
        let (out, derivative) = match self.state {
            None => (x, [0.0; N]),
            Some((prev_out, prev_raw, prev_d)) => {
                let a_d = smoothing_factor(p.d_cutoff_hz, period_s);
                let mut d = [0.0; N];
                for k in 0..N {
                    let raw = (x[k] - prev_raw[k]) / period_s;
                    d[k] = prev_d[k] + a_d * (raw - prev_d[k]);
                }
                let speed = d.iter().map(|v| v * v).sum::<f64>().sqrt();
                let a = smoothing_factor(p.min_cutoff_hz + p.beta * speed, period_s);
                let mut out = [0.0; N];
                for k in 0..N {
                    out[k] = prev_out[k] + a * (x[k] - prev_out[k]);
                }
                (out, d)
            }
        };
        self.state = Some((out, x, derivative));
        out
    }
}

/// The rotation vector (axis × angle, radians) of the rotation from `a` to `b` in `a`'s
/// frame, `log(a⁻¹ b)`, on the short arc: its length is at most π.
#[must_use]
pub fn rotation_between(a: DQuat, b: DQuat) -> DVec3 {
    let mut d = a.inverse() * b;
    if d.w < 0.0 {
        d = -d;
    }
    let s = DVec3::new(d.x, d.y, d.z);
    let sin_half = s.length();
    if sin_half < 1e-300 {
        return DVec3::ZERO;
    }
    let angle = 2.0 * sin_half.atan2(d.w);
    s * (angle / sin_half)
}

/// `q · exp(v)`: `q` turned by the rotation vector `v` in its own frame, renormalised.
#[must_use]
pub fn rotate_by(q: DQuat, v: DVec3) -> DQuat {
    (q * DQuat::from_scaled_axis(v)).normalize()
}

/// The One-Euro filter on unit quaternions (see the module docs): differences are rotation
/// vectors on the short arc, the low-pass step a slerp, every output renormalised.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OneEuroRotation {
    params: OneEuroParams,
    /// `(q̂, q, ω̂)`: the last output, the last raw sample, the filtered angular velocity
    /// (rad/s, in the previous sample's frame).
    state: Option<(DQuat, DQuat, DVec3)>,
}

impl OneEuroRotation {
    /// A filter that has seen nothing yet.
    #[must_use]
    pub fn new(params: OneEuroParams) -> Self {
        Self {
            params,
            state: None,
        }
    }

    /// The last output, if any sample has been seen.
    #[must_use]
    pub fn value(&self) -> Option<DQuat> {
        self.state.map(|(q, _, _)| q)
    }

    /// Forgets everything: the next sample passes through.
    pub fn reset(&mut self) {
        self.state = None;
    }

    /// Filters the unit quaternion `q` taken `period_s > 0` seconds after the previous
    /// sample; returns `q̂` (unit).
    pub fn step(&mut self, q: DQuat, period_s: f64) -> DQuat {
        let p = self.params;
        let q = q.normalize();
        let (out, omega) = match self.state {
            None => (q, DVec3::ZERO),
            Some((prev_out, prev_raw, prev_w)) => {
                let a_d = smoothing_factor(p.d_cutoff_hz, period_s);
                let raw = rotation_between(prev_raw, q) / period_s;
                let w = prev_w + a_d * (raw - prev_w);
                let a = smoothing_factor(p.min_cutoff_hz + p.beta * w.length(), period_s);
                (rotate_by(prev_out, a * rotation_between(prev_out, q)), w)
            }
        };
        self.state = Some((out, q, omega));
        out
    }
}
