//! The user's side of a profile: where the tracker sits in the world, which hand, how long its fingers and how large the hand are.

#[allow(unused_imports)] // The parent's imports, as the code had them there.
use super::*;

/// A similarity transform from tracker coordinates (metres) to world coordinates:
/// `p_world = translation + scale · (rotation · p_tracker)`, `q_world = rotation · q_tracker`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldFromTracker {
    /// Translation, world units.
    pub translation: [f64; 3],
    /// Rotation as a unit quaternion, scalar first: w, x, y, z.
    pub rotation_wxyz: [f64; 4],
    /// World units per metre.
    pub scale: f64,
}

impl Default for WorldFromTracker {
    fn default() -> Self {
        WorldFromTracker {
            translation: [0.0; 3],
            rotation_wxyz: [1.0, 0.0, 0.0, 0.0],
            scale: 1.0,
        }
    }
}

impl WorldFromTracker {
    /// The rotation as a glam quaternion.
    pub fn rotation(&self) -> DQuat {
        let [w, x, y, z] = self.rotation_wxyz;
        DQuat::from_xyzw(x, y, z, w)
    }

    /// The translation as a vector.
    pub fn translation(&self) -> DVec3 {
        DVec3::from_array(self.translation)
    }

    /// Maps a pose from tracker into world coordinates.
    pub fn apply(&self, pose: &TrackerPose) -> (DVec3, DQuat) {
        let r = self.rotation();
        (
            self.translation() + self.scale * (r * pose.position),
            r * pose.orientation,
        )
    }

    /// Checks that every number is finite, the rotation has unit norm and the scale is positive.
    pub fn validate(&self) -> Result<(), DeviceError> {
        let r = self.rotation();
        let ok = self.translation().is_finite()
            && r.is_finite()
            && (r.length() - 1.0).abs() < 1e-6
            && self.scale.is_finite()
            && self.scale > 0.0;
        if ok {
            Ok(())
        } else {
            Err(DeviceError::InvalidValue(format!(
                "world_from_tracker {self:?} (needs finite values, unit rotation, positive scale)"
            )))
        }
    }
}

/// Which hand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// Left hand.
    Left,
    /// Right hand.
    #[default]
    Right,
}

/// Segment lengths of one finger, metres, from the knuckle outward.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FingerLengths {
    /// Proximal phalanx (for the thumb: metacarpal).
    pub proximal: f64,
    /// Middle phalanx (for the thumb: proximal phalanx).
    pub middle: f64,
    /// Distal phalanx.
    pub distal: f64,
}

impl FingerLengths {
    const fn new(proximal: f64, middle: f64, distal: f64) -> Self {
        FingerLengths {
            proximal,
            middle,
            distal,
        }
    }
}

/// The hand's side and dimensions, metres. The defaults are typical adult values (rounded
/// anthropometric means), to be replaced by measuring the user's hand.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HandSize {
    /// Left or right.
    pub side: Side,
    /// Wrist crease to the middle finger's knuckle.
    pub palm_length: f64,
    /// Across the knuckles.
    pub palm_width: f64,
    /// Thumb (metacarpal, proximal, distal).
    pub thumb: FingerLengths,
    /// Index finger.
    pub index: FingerLengths,
    /// Middle finger.
    pub middle: FingerLengths,
    /// Ring finger.
    pub ring: FingerLengths,
    /// Little finger.
    pub pinky: FingerLengths,
}

impl Default for HandSize {
    fn default() -> Self {
        HandSize {
            side: Side::Right,
            palm_length: 0.095,
            palm_width: 0.085,
            thumb: FingerLengths::new(0.046, 0.032, 0.027),
            index: FingerLengths::new(0.040, 0.023, 0.018),
            middle: FingerLengths::new(0.045, 0.027, 0.019),
            ring: FingerLengths::new(0.042, 0.026, 0.019),
            pinky: FingerLengths::new(0.033, 0.019, 0.017),
        }
    }
}

impl HandSize {
    /// Checks every length: finite and 0 < length < 0.5 m (the rule for profiles and trace
    /// headers alike).
    pub fn validate(&self) -> Result<(), DeviceError> {
        let all = [self.thumb, self.index, self.middle, self.ring, self.pinky];
        let lengths = all
            .iter()
            .flat_map(|f| [f.proximal, f.middle, f.distal])
            .chain([self.palm_length, self.palm_width]);
        for l in lengths {
            if !(l.is_finite() && l > 0.0 && l < 0.5) {
                return Err(DeviceError::InvalidValue(format!(
                    "hand length {l} m (needs 0 < length < 0.5 m)"
                )));
            }
        }
        Ok(())
    }
}
