use super::*;
use crate::{FrameStatus, Timestamp};
use glam::DQuat;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{PI, TAU};

fn params(min_cutoff_hz: f64, beta: f64, d_cutoff_hz: f64) -> OneEuroParams {
    OneEuroParams {
        min_cutoff_hz,
        beta,
        d_cutoff_hz,
    }
}

/// A standard normal deviate (Box–Muller).
fn gauss(rng: &mut ChaCha8Rng) -> f64 {
    let u: f64 = rng.gen_range(f64::EPSILON..1.0);
    let v: f64 = rng.r#gen();
    (-2.0 * u.ln()).sqrt() * (TAU * v).cos()
}

/// A frame of both sources, fresh, at `k` periods of `hz`.
fn frame(k: usize, hz: f64, position: DVec3, q: DQuat, angles: JointAngles) -> HandFrame {
    HandFrame {
        time: Timestamp((k as f64 * 1e6 / hz).round() as u64),
        pose: Some(TrackerPose {
            position,
            orientation: q,
        }),
        joints: Some(angles),
        buttons: 0,
        status: FrameStatus {
            tracker: SourceState::Ok,
            glove: SourceState::Ok,
            tracker_fresh: true,
            glove_fresh: true,
        },
    }
}

fn bent(a: f64) -> JointAngles {
    JointAngles::new()
        .with(Joint::IndexMcp, a)
        .and_then(|j| j.with(Joint::IndexPip, 0.5))
        .unwrap()
}

#[test]
fn the_smoothing_factor_is_the_papers() {
    // α = 1/(1 + τ/T_e), τ = 1/(2π f_c): at 1 Hz and 100 Hz, τ = 0.159 154 9 s.
    let tau = 1.0 / (2.0 * PI);
    assert!((smoothing_factor(1.0, 0.01) - 0.01 / (0.01 + tau)).abs() < 1e-15);
    assert!((smoothing_factor(1.0, 0.01) - 0.059_117_397).abs() < 1e-9);
    // A cutoff far above the rate follows the input; far below, holds.
    assert!(smoothing_factor(1e9, 0.01) > 1.0 - 1e-6);
    assert!(smoothing_factor(1e-9, 0.01) < 1e-6);
}

#[test]
fn a_constant_input_stays_exactly_constant() {
    let mut f = OneEuro::<3>::new(params(1.0, 100.0, 1.0));
    let x = [0.123_456, -7.5, 1e-3];
    for k in 0..500 {
        let period = 0.004 + 0.004 * ((k % 3) as f64);
        assert_eq!(f.step(x, period), x);
    }
    assert_eq!(f.derivative(), [0.0; 3]);
    let mut r = OneEuroRotation::new(params(1.0, 15.0, 1.0));
    let q = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 2.0);
    for k in 0..500 {
        // The sign of a quaternion does not matter: −q is the same rotation.
        let input = if k % 2 == 0 { q } else { -q };
        let out = r.step(input, 1.0 / 120.0);
        assert!(out.dot(q).abs() > 1.0 - 1e-15, "{k}: {out}");
        assert!((out.length() - 1.0).abs() < 1e-15);
    }
}

#[test]
fn the_step_response_follows_the_recurrence() {
    // β = 0: a fixed low-pass, y_n = 1 − (1 − α)^n exactly.
    let t = 1.0 / 120.0;
    let mut f = OneEuro::<1>::new(params(2.0, 0.0, 1.0));
    f.step([0.0], t);
    let a = smoothing_factor(2.0, t);
    for n in 1..=200 {
        let [y] = f.step([1.0], t);
        let want = 1.0 - (1.0 - a).powi(n);
        assert!((y - want).abs() < 1e-12, "{n}: {y} vs {want}");
    }
    // β > 0: the derivative of a step is 1/T at the step and 0 after, so its low-pass is
    // Ẋ̂_n = α_d (1 − α_d)^(n−1) / T, the cutoff f_cmin + β Ẋ̂_n, and
    // y_n = y_{n−1} + α(f_c,n) (1 − y_{n−1}).
    let (fmin, beta, dc) = (1.0, 3.0, 1.0);
    let mut f = OneEuro::<1>::new(params(fmin, beta, dc));
    f.step([0.0], t);
    let ad = smoothing_factor(dc, t);
    let mut y = 0.0;
    for n in 1..=200 {
        let d = ad * (1.0 - ad).powi(n - 1) / t;
        y += smoothing_factor(fmin + beta * d, t) * (1.0 - y);
        let [got] = f.step([1.0], t);
        assert!((got - y).abs() < 1e-12, "{n}: {got} vs {y}");
        assert!(got <= 1.0, "no overshoot");
    }
    // The adaptive cutoff follows the step faster than the fixed one.
    let mut fixed = OneEuro::<1>::new(params(fmin, 0.0, dc));
    let mut adaptive = OneEuro::<1>::new(params(fmin, beta, dc));
    fixed.step([0.0], t);
    adaptive.step([0.0], t);
    for _ in 0..10 {
        fixed.step([1.0], t);
        adaptive.step([1.0], t);
    }
    assert!(adaptive.value().unwrap()[0] > fixed.value().unwrap()[0] + 0.1);
}

#[test]
fn a_faster_ramp_lags_less_in_time_and_never_more_than_the_bound() {
    // At steady state on a ramp x = v·t the filtered derivative is v, α is constant, and the
    // lag L satisfies L = (1 − α)(L + vT), so L = vT(1 − α)/α = v·τ = v / (2π (f_cmin + βv)).
    let p = params(1.0, 100.0, 1.0);
    let t = 1.0 / 120.0;
    let mut lags = Vec::new();
    for v in [0.01, 0.1, 1.0, 10.0] {
        let mut f = OneEuro::<1>::new(p);
        let mut lag = 0.0;
        for k in 0..4000 {
            let x = v * t * k as f64;
            lag = x - f.step([x], t)[0];
        }
        let want = v / (TAU * (p.min_cutoff_hz + p.beta * v));
        assert!(
            (lag - want).abs() < 1e-9 * v.max(1.0),
            "{v}: {lag} vs {want}"
        );
        assert!(lag < p.lag_bound());
        lags.push((v, lag));
    }
    for w in lags.windows(2) {
        let ((v0, l0), (v1, l1)) = (w[0], w[1]);
        assert!(l1 / v1 < l0 / v0, "time lag shrinks with speed: {lags:?}");
    }
    // The same on rotations: a steady turn at ω lags by ω·τ in angle.
    let p = params(1.0, 15.0, 1.0);
    let axis = DVec3::new(0.3, -0.2, 0.9).normalize();
    for w in [0.5, 5.0] {
        let mut r = OneEuroRotation::new(p);
        let mut lag = 0.0;
        for k in 0..4000 {
            let q = DQuat::from_axis_angle(axis, w * t * k as f64);
            lag = rotation_between_len(r.step(q, t), q);
        }
        let want = w / (TAU * (p.min_cutoff_hz + p.beta * w));
        assert!((lag - want).abs() < 1e-6, "{w}: {lag} vs {want}");
    }
}

fn rotation_between_len(a: DQuat, b: DQuat) -> f64 {
    one_euro::rotation_between(a, b).length()
}

#[test]
fn a_one_sample_spike_is_held_and_counted() {
    let mut f = FrameFilter::default();
    let q = DQuat::IDENTITY;
    let rest = DVec3::new(0.1, 0.2, 0.3);
    let mut rejected_at = Vec::new();
    for k in 0..240 {
        let mut p = rest;
        if k == 100 {
            p.z -= 0.06;
        }
        let out = f.apply(&frame(k, 120.0, p, q, bent(0.3)));
        if !f.held().is_empty() {
            rejected_at.push(k);
            assert_eq!(f.held().position, Some(Rejection::TooFast));
        }
        // The output never leaves the resting point: the spike is held off entirely.
        assert!((out.pose.unwrap().position - rest).length() < 1e-12, "{k}");
    }
    assert_eq!(rejected_at, [100]);
    assert_eq!(f.stats().position.total(), 1);
    assert_eq!(f.stats().rejected(), 1);
    assert_eq!(f.stats().frames_held, 1);
    assert_eq!(f.stats().tracker_samples, 240);
}

#[test]
fn a_spike_during_motion_is_caught_by_the_acceleration_limit() {
    // 60 Hz, moving at 1 m/s: a 6 cm spike is within the speed limit (3.6 m/s from the
    // last sample) but beyond what 100 m/s² could add to the constant-velocity step.
    let mut f = FrameFilter::default();
    let v = DVec3::new(1.0, 0.0, 0.0);
    let mut held = 0;
    for k in 0..120 {
        let mut p = v * (k as f64 / 60.0);
        if k == 60 {
            p.z += 0.06;
        }
        let out = f.apply(&frame(k, 60.0, p, DQuat::IDENTITY, bent(0.3)));
        if f.held().position.is_some() {
            held += 1;
            assert_eq!(f.held().position, Some(Rejection::TooSudden));
        }
        assert!(out.pose.unwrap().position.z.abs() < 1e-12, "{k}");
    }
    assert_eq!(held, 1);
}

#[test]
fn nan_and_huge_values_never_pass() {
    let mut f = FrameFilter::default();
    let rest = DVec3::new(0.0, 0.1, 0.2);
    let good = frame(0, 120.0, rest, DQuat::IDENTITY, bent(0.3));
    f.apply(&good);
    // Frames are validated by the device layer, but their fields are public: a frame built
    // elsewhere may carry anything.
    let bad = [
        DVec3::new(f64::NAN, 0.0, 0.0),
        DVec3::new(1e308, 0.0, 0.0),
        DVec3::splat(f64::INFINITY),
    ];
    for (k, p) in bad.into_iter().enumerate() {
        let mut fr = frame(k + 1, 120.0, p, DQuat::IDENTITY, bent(0.3));
        if let Some(pose) = &mut fr.pose
            && k == 2
        {
            pose.orientation = DQuat::from_xyzw(f64::NAN, 0.0, 0.0, 1.0);
        }
        let out = f.apply(&fr);
        assert_eq!(out.pose.unwrap().position, rest);
        assert!(out.pose.unwrap().orientation.is_finite());
        assert_eq!(f.held().position, Some(Rejection::OutOfRange));
    }
    assert_eq!(f.stats().position.out_of_range, 3);
    assert_eq!(f.stats().orientation.out_of_range, 1);
    // Out-of-range values are never accepted by the hold limit: seconds of NaN hold.
    for k in 4..400 {
        let fr = frame(k, 120.0, DVec3::splat(f64::NAN), DQuat::IDENTITY, bent(0.3));
        assert_eq!(f.apply(&fr).pose.unwrap().position, rest);
    }
    assert_eq!(f.stats().resyncs, 0);
    // A NaN first sample leaves the tracker without a value.
    let mut f = FrameFilter::default();
    let fr = frame(0, 120.0, DVec3::splat(f64::NAN), DQuat::IDENTITY, bent(0.3));
    assert!(f.apply(&fr).pose.is_none());
}

#[test]
fn joints_jumping_past_their_range_or_too_fast_are_held() {
    let mut f = FrameFilter::default();
    let q = DQuat::IDENTITY;
    for k in 0..50 {
        f.apply(&frame(k, 100.0, DVec3::ZERO, q, bent(0.3)));
    }
    // A flipped high bit of a CyberGlove sensor: 64 counts of 0.4° = 0.45 rad for one sample.
    let out = f.apply(&frame(50, 100.0, DVec3::ZERO, q, bent(0.75)));
    assert_eq!(out.joints.unwrap().get(Joint::IndexMcp), Some(0.3));
    assert_eq!(out.joints.unwrap().get(Joint::IndexPip), Some(0.5));
    assert_eq!(f.held().joints().collect::<Vec<_>>(), [Joint::IndexMcp]);
    // Past its range (−0.9 to 2.4 rad of flexion): held, whatever the speed.
    let out = f.apply(&frame(51, 100.0, DVec3::ZERO, q, bent(-1.5)));
    assert_eq!(out.joints.unwrap().get(Joint::IndexMcp), Some(0.3));
    assert_eq!(f.stats().joints.too_fast + f.stats().joints.too_sudden, 1);
    assert_eq!(f.stats().joints.out_of_range, 1);
    assert_eq!(f.stats().per_joint[Joint::IndexMcp.index()], 2);
    assert_eq!(f.stats().position.total(), 0);
    // A real, fast curl (6 rad/s, well within a finger's speed) passes.
    for k in 52..80 {
        let a = 0.3 + 6.0 * (k - 52) as f64 / 100.0;
        f.apply(&frame(k, 100.0, DVec3::ZERO, q, bent(a.min(1.5))));
    }
    assert_eq!(f.stats().joints.total(), 2);
}

#[test]
fn a_jump_that_lasts_is_taken_after_the_hold_limit() {
    // At 90 Hz (0.25 s is 22.5 periods, no sample on the boundary).
    let mut f = FrameFilter::default();
    let q = DQuat::IDENTITY;
    for k in 0..20 {
        f.apply(&frame(k, 90.0, DVec3::ZERO, q, bent(0.3)));
    }
    // 30 cm away: after 5 samples held (67 ms), the hand could have got there at 5 m/s, and
    // the sample is plausible again.
    let mut first_moved = None;
    for k in 20..120 {
        let out = f.apply(&frame(k, 90.0, DVec3::new(0.3, 0.0, 0.0), q, bent(0.3)));
        if first_moved.is_none() && out.pose.unwrap().position.x > 0.0 {
            first_moved = Some(k);
        }
    }
    assert_eq!(first_moved, Some(25));
    assert_eq!(f.stats().resyncs, 0);
    // 2 m away, out of reach for 0.4 s: held for 0.25 s (22 samples), then taken in.
    let there = DVec3::new(2.3, 0.0, 0.0);
    let mut first_moved = None;
    for k in 120..220 {
        let out = f.apply(&frame(k, 90.0, there, q, bent(0.3)));
        if first_moved.is_none() && out.pose.unwrap().position.x > 1.0 {
            first_moved = Some(k);
        }
    }
    assert_eq!(first_moved, Some(142));
    assert_eq!(f.stats().resyncs, 1);
    assert_eq!(f.stats().position.total(), 5 + 22);
    // Frames without a clock (every one at time 0) end a hold too, by counting periods
    // (1/120 s before any interval is seen): a 0.104 s hold is 12 of them.
    let mut settings = FilterSettings::default();
    settings.gate.hold_max_s = 0.104;
    let mut f = FrameFilter::new(settings);
    let mut at_zero = |p: DVec3| {
        let mut fr = frame(0, 120.0, p, q, bent(0.3));
        fr.status.tracker_fresh = false;
        fr.status.glove_fresh = false;
        f.apply(&fr).pose.unwrap().position
    };
    at_zero(DVec3::ZERO);
    let moved = (0..100).position(|_| at_zero(there).x > 0.0);
    assert_eq!(moved, Some(12));
}

#[test]
fn jitter_at_rest_passes_the_gate_and_is_smoothed() {
    // 0.5 mm RMS per axis, 0.05° in orientation, 1 count in the joints, at 120 Hz.
    let mut rng = ChaCha8Rng::seed_from_u64(0x0e5e);
    let mut f = FrameFilter::default();
    let rest = DVec3::new(0.05, -0.2, 0.1);
    let (mut raw_max, mut out_max) = (0.0f64, 0.0f64);
    for k in 0..6000 {
        let noise = DVec3::new(gauss(&mut rng), gauss(&mut rng), gauss(&mut rng)) * 0.5e-3;
        let turn = DVec3::new(gauss(&mut rng), gauss(&mut rng), gauss(&mut rng)) * 8.7e-4;
        let q = DQuat::from_scaled_axis(turn);
        let a = 0.3 + 0.007 * (gauss(&mut rng)).round();
        let out = f.apply(&frame(k, 120.0, rest + noise, q, bent(a)));
        if k >= 240 {
            raw_max = raw_max.max(noise.length());
            out_max = out_max.max((out.pose.unwrap().position - rest).length());
        }
    }
    assert_eq!(f.stats().rejected(), 0, "{:?}", f.stats());
    assert!(raw_max > 2e-3, "{raw_max}");
    assert!(out_max < 0.8e-3, "{out_max}");
    assert!(out_max * 3.0 < raw_max, "{out_max} vs {raw_max}");
}

#[test]
fn samples_read_in_bursts_are_a_period_apart() {
    // A 120 Hz tracker read in bursts of three: three samples within microseconds, then a
    // 25 ms gap. Moving at 1.5 m/s, none is rejected, and the filter's lag stays that of a
    // regular stream.
    let mut f = FrameFilter::default();
    let v = 1.5;
    for k in 0..600 {
        let burst = (k / 3) as f64 * 3.0 / 120.0;
        let mut fr = frame(
            0,
            120.0,
            DVec3::new(v * k as f64 / 120.0, 0.0, 0.0),
            DQuat::IDENTITY,
            bent(0.3),
        );
        fr.time = Timestamp((burst * 1e6).round() as u64 + (k % 3) as u64 * 5);
        let out = f.apply(&fr);
        if k == 599 {
            let lag = v * k as f64 / 120.0 - out.pose.unwrap().position.x;
            assert!(
                lag > 0.0 && lag < 2.0 * FilterSettings::default().position.lag_bound(),
                "{lag}"
            );
        }
    }
    assert_eq!(f.stats().rejected(), 0, "{:?}", f.stats());
}

#[test]
fn only_fresh_samples_move_a_channel_and_a_lost_source_starts_over() {
    let mut f = FrameFilter::default();
    let q = DQuat::IDENTITY;
    for k in 0..10 {
        f.apply(&frame(k, 120.0, DVec3::ZERO, q, bent(0.3)));
    }
    // Glove-only frames carry the tracker's last pose: the tracker's filter does not move.
    let mut fr = frame(10, 120.0, DVec3::ZERO, q, bent(0.35));
    fr.status.tracker_fresh = false;
    f.apply(&fr);
    assert_eq!(f.stats().tracker_samples, 10);
    assert_eq!(f.stats().glove_samples, 11);
    // The tracker lost: its values are withdrawn, and when it is back its first sample
    // passes through as it is.
    let mut lost = frame(11, 120.0, DVec3::ZERO, q, bent(0.35));
    lost.status.tracker = SourceState::Silent;
    lost.pose = None;
    assert!(f.apply(&lost).pose.is_none());
    let back = DVec3::new(0.4, 0.0, 0.0);
    let out = f.apply(&frame(12, 120.0, back, q, bent(0.35)));
    assert_eq!(out.pose.unwrap().position, back);
    assert_eq!(f.stats().rejected(), 0);
    // Time going back starts another stream: a hand elsewhere is taken at once.
    let elsewhere = DVec3::new(-0.5, 0.2, 0.1);
    let out = f.apply(&frame(0, 120.0, elsewhere, q, bent(0.9)));
    assert_eq!(out.pose.unwrap().position, elsewhere);
    assert_eq!(out.joints.unwrap().get(Joint::IndexMcp), Some(0.9));
    assert_eq!(f.stats().rejected(), 0);
    // A stale pose on a frame whose tracker is not `ok` is never used.
    let mut stale = frame(1, 120.0, DVec3::ONE, q, bent(0.35));
    stale.status.tracker = SourceState::Disconnected;
    assert!(f.apply(&stale).pose.is_none());
}

#[test]
fn off_passes_frames_unchanged_and_peek_takes_nothing_in() {
    let mut f = FrameFilter::new(FilterSettings::off());
    let fr = frame(3, 120.0, DVec3::splat(f64::NAN), DQuat::IDENTITY, bent(0.3));
    let out = f.apply(&fr);
    assert!(out.pose.unwrap().position.x.is_nan());
    let mut f = FrameFilter::default();
    f.apply(&frame(0, 120.0, DVec3::ZERO, DQuat::IDENTITY, bent(0.3)));
    let before = f.clone();
    let next = frame(
        1,
        120.0,
        DVec3::new(0.001, 0.0, 0.0),
        DQuat::IDENTITY,
        bent(0.3),
    );
    let peeked = f.peek(&next);
    assert_eq!(f, before);
    assert_eq!(f.apply(&next), peeked);
}

#[test]
fn settings_read_with_defaults_and_refuse_bad_values() {
    let d = FilterSettings::default();
    let text = serde_json::to_string(&d).unwrap();
    assert_eq!(serde_json::from_str::<FilterSettings>(&text).unwrap(), d);
    assert_eq!(serde_json::from_str::<FilterSettings>("{}").unwrap(), d);
    let partial: FilterSettings =
        serde_json::from_str(r#"{"gate":{"max_speed_m_s":3.0}}"#).unwrap();
    assert_eq!(partial.gate.max_speed_m_s, 3.0);
    assert_eq!(partial.gate.hold_max_s, 0.25);
    assert!(serde_json::from_str::<FilterSettings>(r#"{"smoothing":1}"#).is_err());
    assert!(d.validate().is_ok());
    let mut bad = d;
    bad.position.beta = -1.0;
    assert_eq!(
        bad.validate().unwrap_err().to_string(),
        "filter.position.beta is -1; it must be a number not below zero"
    );
    let mut bad = d;
    bad.gate.hold_max_s = f64::NAN;
    assert_eq!(bad.validate().unwrap_err().name, "gate.hold_max_s");
    let mut bad = d;
    bad.joints.min_cutoff_hz = 0.0;
    assert_eq!(bad.validate().unwrap_err().name, "joints.min_cutoff_hz");
}

#[test]
fn every_shipped_gloves_raw_range_is_inside_the_joint_ranges() {
    use crate::profile::{GloveProfile, builtin};
    for p in builtin() {
        let Some(g) = p.glove() else { continue };
        let raw: [f64; 2] = match g {
            GloveProfile::CyberGlove { .. } => [1.0, 255.0],
            GloveProfile::FiveDtGlove5 { .. } => [0.0, 255.0],
            GloveProfile::FiveDtGlove16 { .. } => [0.0, 4095.0],
            GloveProfile::FiveDtUltraUsb { .. } => [0.0, 4096.0],
        };
        for c in g.calibration() {
            let Some(j) = c.joint else { continue };
            let [lo, hi] = joint_range(j);
            for r in raw {
                let a = (r - c.offset) * c.gain;
                assert!(lo <= a && a <= hi, "{}: {j} at raw {r} is {a}", p.name);
            }
        }
    }
}
