//! Ascension Flock of Birds serial protocol (`docs/design.md` §16 §4).
//!
//! ## Link
//! 2400–115200 baud (set by DIP switches), 8N1. One bird on the bus (stand-alone); the
//! `0xF0 + address` forwarding prefix of multi-bird flocks is not used.
//!
//! ## Commands the backend sends
//! - a record-mode byte: `V` position, `W` angles, `X` matrix, `Y` position + angles,
//!   `Z` position + matrix, `\` quaternion, `]` position + quaternion;
//! - `B` point: the bird answers one record; `@` stream records; `?` stop streaming.
//!
//! ## Record
//! A record is a sequence of 16-bit words, each sent low byte first. Only the first byte of a
//! record has bit 7 set (the phasing bit); every other byte has it clear. A word is rebuilt as
//! `value = (MSB << 9) | ((LSB & 0x7F) << 2)`, read as a signed 16-bit integer (14 significant
//! bits).
//!
//! | mode | words | content |
//! |---|---|---|
//! | `V` | 3 | position x, y, z |
//! | `W` | 3 | angles z (azimuth), y (elevation), x (roll) |
//! | `X` | 9 | rotation matrix, 9 elements |
//! | `Y` | 6 | position, then angles |
//! | `Z` | 12 | position, then matrix |
//! | `\` | 4 | quaternion q0 (scalar), q1, q2, q3 |
//! | `]` | 7 | position, then quaternion |
//!
//! Position = value·S/32768 inches with S = 36 (72 or 144 in the extended ranges);
//! angles = value·180/32768 degrees; matrix elements and quaternion parts = value/32768.
//! Matrix elements are taken column by column (this and the quaternion's handedness differ
//! between sources; the profile can conjugate the quaternion).
//!
//! ## Measuring range
//! A position is at most ±S inches per axis by construction (a 16-bit word scaled by S/32768):
//! the scale is the bird's measuring range, and the backend passes on only positions within
//! it. Orientation: angles must keep the elevation within ±90° ([`ELEVATION_LIMIT_DEG`]), a
//! matrix must be a rotation (`MᵀM` within 0.05 of the identity, determinant within 0.05 of
//! 1), a quaternion's norm within 0.02 of 1; any other record is dropped and counted as
//! invalid.
//!
//! ## Resynchronisation
//! Hunt for a byte with bit 7 set; reject the candidate when a later byte of the same record has
//! bit 7 set (a truncated record followed by the next one), or when its quaternion or matrix is
//! far from unit length.

use glam::{DMat3, DQuat, DVec3, EulerRot};

use crate::decode::{Frame, Framing, StreamDecoder};
use crate::{DeviceError, TrackerPose};

/// Point: one record.
pub const POINT: u8 = b'B';
/// Stream records.
pub const STREAM: u8 = b'@';
/// Stop streaming.
pub const STOP: u8 = b'?';
/// The phasing bit of a record's first byte.
pub const PHASE_BIT: u8 = 0x80;
/// The default position scale S, inches.
pub const DEFAULT_SCALE_INCHES: f64 = 36.0;
/// Largest elevation a bird reports, degrees (azimuth and roll span ±180°, elevation ±90°): an
/// angles record beyond it is corrupt, dropped and counted as invalid.
pub const ELEVATION_LIMIT_DEG: f64 = 90.0 + 0.02;
/// The position scales a bird can be set to, inches: 36, and 72 or 144 in the extended ranges.
pub const SCALES_INCHES: [f64; 3] = [36.0, 72.0, 144.0];

/// What a record holds, chosen by the record-mode command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RecordMode {
    /// `V`: position.
    Position,
    /// `W`: angles.
    Angles,
    /// `X`: matrix.
    Matrix,
    /// `Y`: position and angles.
    PositionAngles,
    /// `Z`: position and matrix.
    PositionMatrix,
    /// `\`: quaternion.
    Quaternion,
    /// `]`: position and quaternion.
    PositionQuaternion,
}

impl RecordMode {
    /// Every mode.
    pub const ALL: [RecordMode; 7] = [
        RecordMode::Position,
        RecordMode::Angles,
        RecordMode::Matrix,
        RecordMode::PositionAngles,
        RecordMode::PositionMatrix,
        RecordMode::Quaternion,
        RecordMode::PositionQuaternion,
    ];

    /// The command byte selecting the mode.
    pub const fn command(self) -> u8 {
        match self {
            RecordMode::Position => b'V',
            RecordMode::Angles => b'W',
            RecordMode::Matrix => b'X',
            RecordMode::PositionAngles => b'Y',
            RecordMode::PositionMatrix => b'Z',
            RecordMode::Quaternion => b'\\',
            RecordMode::PositionQuaternion => b']',
        }
    }

    /// The mode a command byte selects.
    pub fn from_command(c: u8) -> Option<Self> {
        RecordMode::ALL.into_iter().find(|m| m.command() == c)
    }

    const fn has_position(self) -> bool {
        matches!(
            self,
            RecordMode::Position
                | RecordMode::PositionAngles
                | RecordMode::PositionMatrix
                | RecordMode::PositionQuaternion
        )
    }

    const fn orientation_words(self) -> usize {
        match self {
            RecordMode::Position => 0,
            RecordMode::Angles | RecordMode::PositionAngles => 3,
            RecordMode::Matrix | RecordMode::PositionMatrix => 9,
            RecordMode::Quaternion | RecordMode::PositionQuaternion => 4,
        }
    }

    /// Number of words in a record.
    pub const fn words(self) -> usize {
        3 * self.has_position() as usize + self.orientation_words()
    }

    /// Number of bytes in a record.
    pub const fn record_len(self) -> usize {
        2 * self.words()
    }
}

/// An orientation as the bird reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BirdOrientation {
    /// Angles z, y, x in degrees.
    Angles([f64; 3]),
    /// Matrix elements, column by column.
    Matrix([f64; 9]),
    /// Quaternion q0 (scalar), q1, q2, q3.
    Quaternion([f64; 4]),
}

/// A decoded record (position in inches, angles in degrees).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FlockRecord {
    /// Position x, y, z in inches.
    pub position: Option<[f64; 3]>,
    /// Orientation, when the mode has one.
    pub orientation: Option<BirdOrientation>,
}

impl FlockRecord {
    /// The pose in metres. A record without a position is placed at the origin and one without
    /// an orientation gets the identity; with `conjugate`, the quaternion (or matrix) is
    /// inverted to match the other handedness convention.
    pub fn pose(&self, conjugate: bool) -> Result<TrackerPose, DeviceError> {
        let position = self
            .position
            .map_or(DVec3::ZERO, |p| DVec3::from_array(p) * 0.0254);
        let q = match self.orientation {
            None => DQuat::IDENTITY,
            Some(BirdOrientation::Angles([_, y, _]))
                if !y.is_finite() || y.abs() > ELEVATION_LIMIT_DEG =>
            {
                return Err(DeviceError::InvalidValue(format!(
                    "bird elevation {y}° beyond ±90°"
                )));
            }
            Some(BirdOrientation::Angles([z, y, x])) => DQuat::from_euler(
                EulerRot::ZYX,
                z.to_radians(),
                y.to_radians(),
                x.to_radians(),
            ),
            Some(BirdOrientation::Quaternion([w, x, y, z])) => DQuat::from_xyzw(x, y, z, w),
            Some(BirdOrientation::Matrix(m)) => {
                let m = DMat3::from_cols_array(&m);
                let gram = m.transpose() * m - DMat3::IDENTITY;
                let skew = gram
                    .to_cols_array()
                    .iter()
                    .fold(0.0f64, |a, x| a.max(x.abs()));
                if !m.is_finite() || (m.determinant() - 1.0).abs() > 0.05 || skew > 0.05 {
                    return Err(DeviceError::InvalidValue(
                        "bird matrix is not a rotation".into(),
                    ));
                }
                DQuat::from_mat3(&m)
            }
        };
        let q = if conjugate { q.conjugate() } else { q };
        TrackerPose::new(position, q)
    }
}

/// Rebuilds a word from its low and high bytes.
pub fn word(lsb: u8, msb: u8) -> i16 {
    ((u16::from(msb & 0x7F) << 9) | (u16::from(lsb & 0x7F) << 2)) as i16
}

/// Splits a word into its low and high bytes (both with bit 7 clear; the two lowest bits of
/// the value are lost, as on the wire).
pub fn split_word(value: i16) -> (u8, u8) {
    let u = value as u16;
    (((u >> 2) & 0x7F) as u8, ((u >> 9) & 0x7F) as u8)
}

/// Decoder configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlockFraming {
    /// What the records hold.
    pub mode: RecordMode,
    /// Position scale S in inches (36, 72 or 144).
    pub scale_inches: f64,
}

impl Framing for FlockFraming {
    type Record = FlockRecord;

    fn frame(&self, w: &[u8]) -> Frame<FlockRecord> {
        if w[0] & PHASE_BIT == 0 {
            return Frame::NotHeader;
        }
        let len = self.mode.record_len();
        let have = w.len().min(len);
        if w[1..have].iter().any(|b| b & PHASE_BIT != 0) {
            return Frame::Reject;
        }
        if w.len() < len {
            return Frame::NeedMore;
        }
        let mut words = [0i16; 12];
        for (i, v) in words.iter_mut().take(self.mode.words()).enumerate() {
            *v = word(w[2 * i], w[2 * i + 1]);
        }
        let mut at = 0;
        let mut record = FlockRecord::default();
        if self.mode.has_position() {
            let s = self.scale_inches / 32768.0;
            record.position = Some([
                f64::from(words[0]) * s,
                f64::from(words[1]) * s,
                f64::from(words[2]) * s,
            ]);
            at = 3;
        }
        let o = &words[at..at + self.mode.orientation_words()];
        let unit = |k: usize| f64::from(o[k]) / 32768.0;
        record.orientation = match self.mode.orientation_words() {
            3 => Some(BirdOrientation::Angles(std::array::from_fn(|k| {
                f64::from(o[k]) * 180.0 / 32768.0
            }))),
            9 => {
                let m: [f64; 9] = std::array::from_fn(unit);
                // Each column of a rotation is a unit vector.
                if (0..3).any(|c| {
                    let n: f64 = m[3 * c..3 * c + 3].iter().map(|x| x * x).sum();
                    (n.sqrt() - 1.0).abs() > 0.02
                }) {
                    return Frame::Reject;
                }
                Some(BirdOrientation::Matrix(m))
            }
            4 => {
                let q: [f64; 4] = std::array::from_fn(unit);
                let n: f64 = q.iter().map(|x| x * x).sum();
                if (n.sqrt() - 1.0).abs() > 0.02 {
                    return Frame::Reject;
                }
                Some(BirdOrientation::Quaternion(q))
            }
            _ => None,
        };
        Frame::Record(record, len)
    }
}

/// The Flock of Birds stream decoder.
pub type FlockDecoder = StreamDecoder<FlockFraming>;

fn to_word(x: f64) -> i16 {
    (x * 32768.0).round().clamp(-32768.0, 32767.0) as i16
}

/// Appends a record of the framing's mode. Missing parts are sent as zeros; values are
/// quantised as on the wire.
pub fn encode_record(framing: &FlockFraming, record: &FlockRecord, out: &mut Vec<u8>) {
    let mut words: Vec<i16> = Vec::with_capacity(12);
    if framing.mode.has_position() {
        let p = record.position.unwrap_or_default();
        words.extend(p.iter().map(|x| to_word(x / framing.scale_inches)));
    }
    let n = framing.mode.orientation_words();
    match (n, record.orientation) {
        (3, Some(BirdOrientation::Angles(a))) => words.extend(a.iter().map(|d| to_word(d / 180.0))),
        (9, Some(BirdOrientation::Matrix(m))) => words.extend(m.iter().map(|x| to_word(*x))),
        (4, Some(BirdOrientation::Quaternion(q))) => words.extend(q.iter().map(|x| to_word(*x))),
        _ => words.extend(std::iter::repeat_n(0, n)),
    }
    let start = out.len();
    for w in words {
        let (lsb, msb) = split_word(w);
        out.push(lsb);
        out.push(msb);
    }
    if let Some(first) = out.get_mut(start) {
        *first |= PHASE_BIT;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_follow_the_documented_packing() {
        // value = (MSB << 9) | ((LSB & 0x7F) << 2)
        assert_eq!(word(0x01, 0x00), 4);
        assert_eq!(word(0x81, 0x00), 4); // the phasing bit is not data
        assert_eq!(word(0x00, 0x40), i16::MIN);
        assert_eq!(word(0x7F, 0x7F), -4);
        for v in [-32768i16, -4, 0, 4, 16380, 32764] {
            let (l, m) = split_word(v);
            assert_eq!(word(l, m), v);
        }
    }

    #[test]
    fn position_quaternion_record_is_14_bytes_with_one_phasing_bit() {
        let framing = FlockFraming {
            mode: RecordMode::PositionQuaternion,
            scale_inches: 36.0,
        };
        let rec = FlockRecord {
            position: Some([9.0, -18.0, 4.5]),
            orientation: Some(BirdOrientation::Quaternion([0.5, -0.5, 0.5, 0.5])),
        };
        let mut b = Vec::new();
        encode_record(&framing, &rec, &mut b);
        assert_eq!(b.len(), 14);
        assert_eq!(b.iter().filter(|x| *x & 0x80 != 0).count(), 1);
        assert!(b[0] & 0x80 != 0);
        // 9 in at S = 36 is a quarter of full scale: 8192 = (0x10 << 9) | (0x00 << 2).
        assert_eq!(&b[..2], &[0x80, 0x10]);
        let mut d = FlockDecoder::new(framing);
        assert_eq!(d.decode(&b), vec![rec]);
    }

    #[test]
    fn a_truncated_record_is_rejected_by_the_next_phasing_bit() {
        let framing = FlockFraming {
            mode: RecordMode::PositionAngles,
            scale_inches: 36.0,
        };
        let rec = FlockRecord {
            position: Some([1.0, 2.0, 3.0]),
            orientation: Some(BirdOrientation::Angles([10.0, 20.0, 30.0])),
        };
        let mut one = Vec::new();
        encode_record(&framing, &rec, &mut one);
        let mut b = one[..7].to_vec();
        b.extend_from_slice(&one);
        let mut d = FlockDecoder::new(framing);
        let out = d.decode(&b);
        assert_eq!(out.len(), 1);
        assert_eq!(d.stats().rejected, 1);
        assert_eq!(d.stats().skipped_bytes, 7);
    }
}
