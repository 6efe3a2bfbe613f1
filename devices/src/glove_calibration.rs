//! A short glove calibration: the user holds three poses — a flat hand, a fist, the thumb out —
//! and every sensor's offset and gain are fitted to the angles those poses are taken to have.
//!
//! ## The math
//!
//! A sensor's calibration reads `angle = (raw − offset) · gain` ([`crate::profile::calibrate`]).
//! The stream delivers calibrated angles, so the raw value of a captured sample is recovered
//! through the table the stream used: `raw = angle / gain₀ + offset₀` (a sensor whose current
//! gain is 0 cannot be inverted and is left as it is). For each sensor, the mean raw value
//! `r̄ₚ` of each pose `p` is paired with the pose's target angle `tₚ` for the sensor's joint
//! ([`target_angle`]; a pose says nothing about some joints):
//!
//! - two or more pairs whose targets span at least [`MIN_TARGET_SPAN_RAD`]: the least-squares
//!   line `t = g · (r − o)` through them gives both, `g = Σ(r − r̄)(t − t̄) / Σ(r − r̄)²` and
//!   `o = r̄ − t̄ / g`; a sensor whose raw means span less than [`MIN_RAW_SPAN`] between those
//!   poses did not move and is an error (the pose was not held, or the sensor is broken);
//! - otherwise (all its poses have one target — the finger abductions, the wrist, the palm
//!   arch and the thumb roll are 0 in every pose): the gain is kept and the offset set so the
//!   mean of those poses reads the target, `o = r̄ − t / g₀`.
//!
//! ## The poses (their target angles)
//!
//! - **Flat**: the hand flat on a table, fingers straight and together, thumb alongside the
//!   index: every joint 0.
//! - **Fist**: a loose fist, the thumb over the middle phalanges: finger MCP 80°, PIP 95°,
//!   DIP 45°; thumb MCP 40°, IP 40°; abductions 0; thumb roll, thumb abduction, palm arch and
//!   the wrist unspecified.
//! - **Thumb out**: the flat hand with the thumb spread away from the index as far as is
//!   comfortable: thumb–index abduction 60°, every other joint 0 except the thumb roll
//!   (unspecified).
//!
//! Limits: the targets are round values of a typical hand, not a measurement of the user's;
//! what the calibration fixes is each sensor's zero and span, which is what differs most
//! between wearers and between donnings. Gains of joints that no pose moves keep their old
//! value.

use crate::profile::SensorCalibration;
use crate::{Joint, JointAngles};

/// The smallest spread of target angles (radians) over which a gain is fitted.
pub const MIN_TARGET_SPAN_RAD: f64 = 0.3;
/// The smallest spread of raw means between poses of different targets for a sensor to count
/// as having moved (raw counts; every glove's range is at least 0–255).
pub const MIN_RAW_SPAN: f64 = 1e-6;

/// A pose held during calibration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CalibrationPose {
    /// Flat hand, fingers together, thumb alongside.
    Flat,
    /// A loose fist.
    Fist,
    /// Flat hand, thumb spread out.
    ThumbOut,
}

impl CalibrationPose {
    /// The three poses, in the order the user is asked for them.
    pub const ALL: [CalibrationPose; 3] = [
        CalibrationPose::Flat,
        CalibrationPose::Fist,
        CalibrationPose::ThumbOut,
    ];

    /// What the user is asked to do.
    pub const fn instruction(self) -> &'static str {
        match self {
            CalibrationPose::Flat => "hand flat, fingers straight and together, thumb alongside",
            CalibrationPose::Fist => "a loose fist, thumb over the middle finger",
            CalibrationPose::ThumbOut => "hand flat, thumb spread away from the index",
        }
    }

    /// Short name.
    pub const fn name(self) -> &'static str {
        match self {
            CalibrationPose::Flat => "flat hand",
            CalibrationPose::Fist => "fist",
            CalibrationPose::ThumbOut => "thumb out",
        }
    }
}

/// The angle (radians) `joint` is taken to have in `pose`, if the pose fixes it (see the module
/// docs).
pub fn target_angle(pose: CalibrationPose, joint: Joint) -> Option<f64> {
    use Joint::*;
    let deg = f64::to_radians;
    match pose {
        CalibrationPose::Flat => Some(0.0),
        CalibrationPose::Fist => match joint {
            IndexMcp | MiddleMcp | RingMcp | PinkyMcp => Some(deg(80.0)),
            IndexPip | MiddlePip | RingPip | PinkyPip => Some(deg(95.0)),
            IndexDip | MiddleDip | RingDip | PinkyDip => Some(deg(45.0)),
            ThumbMcp | ThumbIp => Some(deg(40.0)),
            IndexMiddleAbduction | MiddleRingAbduction | RingPinkyAbduction => Some(0.0),
            ThumbRoll | ThumbIndexAbduction | PalmArch | WristPitch | WristYaw => None,
        },
        CalibrationPose::ThumbOut => match joint {
            ThumbIndexAbduction => Some(deg(60.0)),
            ThumbRoll => None,
            _ => Some(0.0),
        },
    }
}

/// Why a calibration could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CalibrationError {
    /// No glove sample was captured for a pose.
    #[error("no glove samples for the {0} pose")]
    NoSamples(&'static str),
    /// A sensor read the same between poses that should differ.
    #[error(
        "sensor {sensor} ({joint}) did not move between the poses (raw spread {spread}); hold each pose while it is captured"
    )]
    DidNotMove {
        /// Sensor index.
        sensor: usize,
        /// Its joint.
        joint: Joint,
        /// The spread of its raw means.
        spread: f64,
    },
    /// The fit gave a value that is not finite.
    #[error("sensor {sensor} ({joint}): the fitted calibration is not finite")]
    NotFinite {
        /// Sensor index.
        sensor: usize,
        /// Its joint.
        joint: Joint,
    },
}

/// How one sensor was calibrated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SensorFit {
    /// Offset and gain fitted.
    OffsetAndGain,
    /// Offset fitted, gain kept (no pose moves its joint).
    OffsetOnly,
    /// Left as it was (no joint, no samples of its joint, or a current gain of 0).
    Unchanged,
}

/// Samples captured per pose: the calibrated joint angles the stream delivered while the pose
/// was held.
#[derive(Debug, Clone, Default)]
pub struct PoseSamples {
    flat: Vec<JointAngles>,
    fist: Vec<JointAngles>,
    thumb_out: Vec<JointAngles>,
}

impl PoseSamples {
    /// The samples of one pose.
    pub fn of(&self, pose: CalibrationPose) -> &[JointAngles] {
        match pose {
            CalibrationPose::Flat => &self.flat,
            CalibrationPose::Fist => &self.fist,
            CalibrationPose::ThumbOut => &self.thumb_out,
        }
    }

    /// Adds a sample to a pose.
    pub fn push(&mut self, pose: CalibrationPose, angles: JointAngles) {
        match pose {
            CalibrationPose::Flat => self.flat.push(angles),
            CalibrationPose::Fist => self.fist.push(angles),
            CalibrationPose::ThumbOut => self.thumb_out.push(angles),
        }
    }

    /// Forgets a pose's samples (to capture it again).
    pub fn clear(&mut self, pose: CalibrationPose) {
        match pose {
            CalibrationPose::Flat => self.flat.clear(),
            CalibrationPose::Fist => self.fist.clear(),
            CalibrationPose::ThumbOut => self.thumb_out.clear(),
        }
    }
}

/// The mean raw value of `sensor` over a pose's samples, through the table they were read with.
fn mean_raw(cal: &SensorCalibration, joint: Joint, samples: &[JointAngles]) -> Option<f64> {
    let raws: Vec<f64> = samples
        .iter()
        .filter_map(|a| a.get(joint))
        .map(|angle| angle / cal.gain + cal.offset)
        .collect();
    (!raws.is_empty()).then(|| raws.iter().sum::<f64>() / raws.len() as f64)
}

/// Fits a new calibration table (see the module docs) from samples read through `table`.
/// Returns the table and how each sensor was fitted, in sensor order.
///
/// # Errors
/// [`CalibrationError`] when a pose has no sample, a sensor did not move between poses of
/// different targets, or a fit is not finite.
pub fn calibrate_glove(
    table: &[SensorCalibration],
    samples: &PoseSamples,
) -> Result<(Vec<SensorCalibration>, Vec<SensorFit>), CalibrationError> {
    for pose in CalibrationPose::ALL {
        if samples.of(pose).is_empty() {
            return Err(CalibrationError::NoSamples(pose.name()));
        }
    }
    let mut out = Vec::with_capacity(table.len());
    let mut fits = Vec::with_capacity(table.len());
    for (sensor, cal) in table.iter().enumerate() {
        let Some(joint) = cal.joint else {
            out.push(*cal);
            fits.push(SensorFit::Unchanged);
            continue;
        };
        if cal.gain == 0.0 || !cal.gain.is_finite() {
            out.push(*cal);
            fits.push(SensorFit::Unchanged);
            continue;
        }
        let pairs: Vec<(f64, f64)> = CalibrationPose::ALL
            .iter()
            .filter_map(|&pose| {
                let t = target_angle(pose, joint)?;
                let r = mean_raw(cal, joint, samples.of(pose))?;
                Some((r, t))
            })
            .collect();
        if pairs.is_empty() {
            out.push(*cal);
            fits.push(SensorFit::Unchanged);
            continue;
        }
        let n = pairs.len() as f64;
        let r_mean = pairs.iter().map(|p| p.0).sum::<f64>() / n;
        let t_mean = pairs.iter().map(|p| p.1).sum::<f64>() / n;
        let t_lo = pairs.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
        let t_hi = pairs.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
        let (fitted, fit) = if t_hi - t_lo >= MIN_TARGET_SPAN_RAD {
            let r_lo = pairs.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
            let r_hi = pairs.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max);
            if r_hi - r_lo < MIN_RAW_SPAN {
                return Err(CalibrationError::DidNotMove {
                    sensor,
                    joint,
                    spread: r_hi - r_lo,
                });
            }
            let sxy: f64 = pairs.iter().map(|(r, t)| (r - r_mean) * (t - t_mean)).sum();
            let sxx: f64 = pairs.iter().map(|(r, _)| (r - r_mean) * (r - r_mean)).sum();
            let gain = sxy / sxx;
            let offset = r_mean - t_mean / gain;
            (
                SensorCalibration {
                    joint: Some(joint),
                    offset,
                    gain,
                },
                SensorFit::OffsetAndGain,
            )
        } else {
            (
                SensorCalibration {
                    joint: Some(joint),
                    offset: r_mean - t_mean / cal.gain,
                    gain: cal.gain,
                },
                SensorFit::OffsetOnly,
            )
        };
        if !(fitted.offset.is_finite() && fitted.gain.is_finite() && fitted.gain != 0.0) {
            return Err(CalibrationError::NotFinite { sensor, joint });
        }
        out.push(fitted);
        fits.push(fit);
    }
    Ok((out, fits))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A CyberGlove-like table: every joint but the wrist, in order.
    fn joints() -> Vec<Joint> {
        Joint::ALL
            .iter()
            .copied()
            .filter(|j| !matches!(j, Joint::WristPitch | Joint::WristYaw))
            .collect()
    }

    /// The angles a glove with the `truth` table reads, through `table`, for a hand whose
    /// joint `j` is at `angle(j)` (raw = angle / g_true + o_true, plus noise).
    fn sample(
        truth: &[SensorCalibration],
        table: &[SensorCalibration],
        angle: impl Fn(Joint) -> f64,
        noise: f64,
        rng: &mut ChaCha8Rng,
    ) -> JointAngles {
        let raw: Vec<f64> = truth
            .iter()
            .map(|c| {
                let j = c.joint.expect("mapped");
                angle(j) / c.gain + c.offset + rng.gen_range(-noise..=noise)
            })
            .collect();
        crate::profile::calibrate(table, &raw).expect("in range")
    }

    /// The angle the synthetic hand really has in a pose: the target where the pose fixes
    /// one, something else (here, arbitrary) where it does not.
    fn held(pose: CalibrationPose, j: Joint) -> f64 {
        target_angle(pose, j).unwrap_or(0.1 + 0.01 * j.index() as f64)
    }

    #[test]
    fn synthetic_flat_fist_thumb_samples_recover_known_offsets_and_gains() {
        let mut rng = ChaCha8Rng::seed_from_u64(16);
        for _case in 0..20 {
            let joints = joints();
            // The truth: offsets 20..200 counts, gains ±(0.005..0.02) rad per count.
            let truth: Vec<SensorCalibration> = joints
                .iter()
                .map(|&j| SensorCalibration {
                    joint: Some(j),
                    offset: rng.gen_range(20.0..200.0),
                    gain: rng.gen_range(0.005..0.02) * if rng.gen_bool(0.3) { -1.0 } else { 1.0 },
                })
                .collect();
            // The table in use: wrong by up to 20 counts and 25 %, same sign (the angles it
            // reads stay within the sensor range the frames accept).
            let table: Vec<SensorCalibration> = truth
                .iter()
                .map(|c| SensorCalibration {
                    joint: c.joint,
                    offset: c.offset + rng.gen_range(-20.0..20.0),
                    gain: c.gain * rng.gen_range(0.8..1.25),
                })
                .collect();
            let mut samples = PoseSamples::default();
            for pose in CalibrationPose::ALL {
                for _ in 0..30 {
                    let a = sample(&truth, &table, |j| held(pose, j), 0.0, &mut rng);
                    samples.push(pose, a);
                }
            }
            let (fitted, fits) = calibrate_glove(&table, &samples).expect("calibrates");
            for ((f, t), (old, how)) in fitted.iter().zip(&truth).zip(table.iter().zip(&fits)) {
                let j = t.joint.expect("mapped");
                assert!(
                    (f.offset - t.offset).abs() < 1e-6,
                    "{j}: offset {} vs {}",
                    f.offset,
                    t.offset
                );
                match how {
                    SensorFit::OffsetAndGain => assert!(
                        (f.gain - t.gain).abs() < 1e-9 * t.gain.abs().max(1.0),
                        "{j}: gain {} vs {}",
                        f.gain,
                        t.gain
                    ),
                    SensorFit::OffsetOnly => assert_eq!(f.gain, old.gain, "{j}: gain kept"),
                    SensorFit::Unchanged => panic!("{j} left unchanged"),
                }
            }
            // Every flexion joint of the fingers and the thumb, and the thumb abduction, got
            // a gain.
            for (c, how) in fitted.iter().zip(&fits) {
                let j = c.joint.expect("mapped");
                let spans = CalibrationPose::ALL
                    .iter()
                    .filter_map(|&p| target_angle(p, j))
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| {
                        (lo.min(t), hi.max(t))
                    });
                let moved = spans.1 - spans.0 >= MIN_TARGET_SPAN_RAD;
                assert_eq!(*how == SensorFit::OffsetAndGain, moved, "{j}");
            }
        }
    }

    #[test]
    fn noisy_samples_give_a_close_fit() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let truth: Vec<SensorCalibration> = joints()
            .iter()
            .map(|&j| SensorCalibration {
                joint: Some(j),
                offset: 100.0,
                gain: 0.01,
            })
            .collect();
        let mut samples = PoseSamples::default();
        for pose in CalibrationPose::ALL {
            for _ in 0..200 {
                samples.push(
                    pose,
                    sample(&truth, &truth, |j| held(pose, j), 1.0, &mut rng),
                );
            }
        }
        let (fitted, _) = calibrate_glove(&truth, &samples).expect("calibrates");
        for (f, t) in fitted.iter().zip(&truth) {
            assert!((f.offset - t.offset).abs() < 1.0, "{f:?}");
            assert!((f.gain - t.gain).abs() < 0.01 * t.gain, "{f:?}");
        }
    }

    #[test]
    fn a_missing_pose_or_a_sensor_that_never_moved_is_an_error() {
        let table = vec![SensorCalibration {
            joint: Some(Joint::IndexMcp),
            offset: 50.0,
            gain: 0.01,
        }];
        let mut samples = PoseSamples::default();
        let still = JointAngles::new()
            .with(Joint::IndexMcp, 0.2)
            .expect("angle");
        samples.push(CalibrationPose::Flat, still);
        samples.push(CalibrationPose::Fist, still);
        assert_eq!(
            calibrate_glove(&table, &samples).unwrap_err(),
            CalibrationError::NoSamples("thumb out")
        );
        samples.push(CalibrationPose::ThumbOut, still);
        assert!(matches!(
            calibrate_glove(&table, &samples),
            Err(CalibrationError::DidNotMove { sensor: 0, .. })
        ));
        // An unmapped sensor and a sensor of gain 0 are left as they are.
        let table = vec![
            SensorCalibration {
                joint: None,
                offset: 1.0,
                gain: 2.0,
            },
            SensorCalibration {
                joint: Some(Joint::IndexMcp),
                offset: 3.0,
                gain: 0.0,
            },
        ];
        let (out, fits) = calibrate_glove(&table, &samples).expect("nothing to fit");
        assert_eq!(out, table);
        assert_eq!(fits, vec![SensorFit::Unchanged; 2]);
    }
}
