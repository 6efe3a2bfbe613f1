//! CyberGlove I/II/III binary serial protocol (`docs/design.md` §16 §1).
//!
//! ## Link
//! 115200 baud 8N1 for the CyberGlove II and III (older VTI units up to 38400).
//!
//! ## Commands the backend sends (binary mode, upper-case letters)
//! - `0x03` (^C): stop streaming. No answer.
//! - `G`: poll one record; the glove answers with one `G` record (below).
//! - `S`: start streaming `S` records at the glove's sample period.
//! - `U` + one byte (0 or 1): include the status byte in records or not. A set command is
//!   answered by echoing the command letter followed by NUL (`U` `0x00`).
//!
//! ## Record (binary)
//! | bytes | field |
//! |---|---|
//! | 1 | header: `G` (answer to a poll) or `S` (streamed) |
//! | N | sensor values, one byte each, N = 18 or 22, in sensor-mask bit order; each 1..=255 — 0 never occurs in a good record and marks a corrupt one |
//! | 0 or 1 | status byte, when enabled with `U`: bit 0 glove plugged in, bit 1 switch pressed, bit 2 light on |
//! | 1 | terminator NUL (0x00) |
//!
//! The glove's own 5-byte timestamp (`D` command) is never enabled: the host clock stamps
//! samples, so this decoder does not accept it.
//!
//! Error records replace the sensor bytes: header, `e`, a code (`s` sample error, `g` glove
//! unplugged), NUL. They are unambiguous because a data record of 18 or 22 sensors cannot have a
//! NUL at its fourth byte.
//!
//! ## Sensor order
//! Sensors are addressed as 6 groups (thumb, index, middle, ring, pinky, carpus) × 4 slots
//! (MCP, PIP, DIP, ABD); bit `4·group + slot` of the sensor mask says whether the sensor is
//! present, and values arrive in mask-bit order. The 18-sensor mask is `0x7BBB3F`, the 22-sensor
//! mask `0x7FFF7F`. The thumb's slots are rotation, MCP, IP and thumb–index abduction; a finger's
//! ABD slot is its abduction from the finger on its thumb side; the carpus slots are palm arch,
//! wrist pitch, wrist yaw.
//!
//! ## Resynchronisation
//! A candidate record is rejected when a sensor byte is 0 or the terminator is not NUL; the
//! decoder then drops one byte and hunts for the next `G`/`S`. A false header inside a record
//! always sees that record's NUL terminator among its sensor bytes, so it is rejected too.

use crate::Joint;
use crate::decode::{Frame, Framing, StreamDecoder};

/// Stop streaming (^C).
pub const STOP: u8 = 0x03;
/// Poll one record.
pub const POLL: u8 = b'G';
/// Start streaming.
pub const STREAM: u8 = b'S';
/// Set the status-byte option (followed by one byte, 0 or 1).
pub const SET_STATUS: u8 = b'U';
/// Record terminator.
pub const TERMINATOR: u8 = 0x00;

/// Sensor mask of the 18-sensor glove.
pub const MASK_18: u32 = 0x7B_BB_3F;
/// Sensor mask of the 22-sensor glove.
pub const MASK_22: u32 = 0x7F_FF_7F;

/// Status byte: glove plugged in.
pub const STATUS_GLOVE_IN: u8 = 0x01;
/// Status byte: switch pressed.
pub const STATUS_SWITCH: u8 = 0x02;
/// Status byte: light on.
pub const STATUS_LIGHT: u8 = 0x04;

/// The joint measured by each group × slot of the sensor mask (`None`: no such sensor).
const SLOT_JOINTS: [Option<Joint>; 24] = [
    Some(Joint::ThumbRoll),
    Some(Joint::ThumbMcp),
    Some(Joint::ThumbIp),
    Some(Joint::ThumbIndexAbduction),
    Some(Joint::IndexMcp),
    Some(Joint::IndexPip),
    Some(Joint::IndexDip),
    None,
    Some(Joint::MiddleMcp),
    Some(Joint::MiddlePip),
    Some(Joint::MiddleDip),
    Some(Joint::IndexMiddleAbduction),
    Some(Joint::RingMcp),
    Some(Joint::RingPip),
    Some(Joint::RingDip),
    Some(Joint::MiddleRingAbduction),
    Some(Joint::PinkyMcp),
    Some(Joint::PinkyPip),
    Some(Joint::PinkyDip),
    Some(Joint::RingPinkyAbduction),
    Some(Joint::PalmArch),
    Some(Joint::WristPitch),
    Some(Joint::WristYaw),
    None,
];

/// The joints of a sensor mask, in the order their values arrive.
pub fn joints_of_mask(mask: u32) -> Vec<Joint> {
    (0..24)
        .filter(|bit| mask & (1 << bit) != 0)
        .filter_map(|bit| SLOT_JOINTS[bit])
        .collect()
}

/// Number of sensors of a glove model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SensorCount {
    /// 18-sensor glove.
    Eighteen,
    /// 22-sensor glove.
    TwentyTwo,
}

impl SensorCount {
    /// From a number of sensors (18 or 22).
    pub fn from_count(n: usize) -> Option<Self> {
        match n {
            18 => Some(SensorCount::Eighteen),
            22 => Some(SensorCount::TwentyTwo),
            _ => None,
        }
    }

    /// The number of sensors.
    pub const fn count(self) -> usize {
        match self {
            SensorCount::Eighteen => 18,
            SensorCount::TwentyTwo => 22,
        }
    }

    /// The sensor mask.
    pub const fn mask(self) -> u32 {
        match self {
            SensorCount::Eighteen => MASK_18,
            SensorCount::TwentyTwo => MASK_22,
        }
    }

    /// The joints, in the order their values arrive.
    pub fn joints(self) -> Vec<Joint> {
        joints_of_mask(self.mask())
    }
}

/// Decoder configuration: what the glove was told to send.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CyberGloveFraming {
    /// Number of sensors.
    pub sensors: SensorCount,
    /// Whether records carry the status byte.
    pub status_byte: bool,
}

impl CyberGloveFraming {
    /// Length of a data record in bytes.
    pub const fn record_len(&self) -> usize {
        1 + self.sensors.count() + self.status_byte as usize + 1
    }
}

/// An error the glove reports in place of a sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GloveFault {
    /// `e s`: the glove could not take the sample.
    SampleError,
    /// `e g`: the glove is unplugged from its interface unit.
    GloveUnplugged,
}

/// A decoded CyberGlove record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CyberRecord {
    /// A sample.
    Sample {
        /// `G` or `S`.
        header: u8,
        /// Number of valid entries in `values`.
        count: u8,
        /// Raw sensor values (1..=255) in mask-bit order; entries past `count` are 0.
        values: [u8; 22],
        /// The status byte, when enabled.
        status: Option<u8>,
    },
    /// The glove reported a fault instead of a sample.
    Fault {
        /// `G` or `S`.
        header: u8,
        /// Which fault.
        fault: GloveFault,
    },
}

impl CyberRecord {
    /// The raw sensor values of a sample (empty for a fault).
    pub fn values(&self) -> &[u8] {
        match self {
            CyberRecord::Sample { count, values, .. } => &values[..*count as usize],
            CyberRecord::Fault { .. } => &[],
        }
    }
}

impl Framing for CyberGloveFraming {
    type Record = CyberRecord;

    fn frame(&self, w: &[u8]) -> Frame<CyberRecord> {
        let header = w[0];
        if header != POLL && header != STREAM {
            return Frame::NotHeader;
        }
        // Error record: header 'e' code NUL.
        if w.len() >= 2 && w[1] == b'e' {
            if w.len() < 4 {
                return Frame::NeedMore;
            }
            let fault = match w[2] {
                b's' => Some(GloveFault::SampleError),
                b'g' => Some(GloveFault::GloveUnplugged),
                _ => None,
            };
            if let (Some(fault), TERMINATOR) = (fault, w[3]) {
                return Frame::Record(CyberRecord::Fault { header, fault }, 4);
            }
            // Otherwise 'e' is just a sensor value (101); fall through.
        }
        let n = self.sensors.count();
        // A NUL among the sensor bytes rejects early, before the whole record is in.
        let available = (w.len() - 1).min(n);
        if w[1..1 + available].contains(&0) {
            return Frame::Reject;
        }
        let len = self.record_len();
        if w.len() < len {
            return Frame::NeedMore;
        }
        if w[len - 1] != TERMINATOR {
            return Frame::Reject;
        }
        let mut values = [0u8; 22];
        values[..n].copy_from_slice(&w[1..1 + n]);
        let status = self.status_byte.then(|| w[1 + n]);
        Frame::Record(
            CyberRecord::Sample {
                header,
                count: n as u8,
                values,
                status,
            },
            len,
        )
    }
}

/// The CyberGlove stream decoder.
pub type CyberGloveDecoder = StreamDecoder<CyberGloveFraming>;

/// Appends a sample record. `values` must be 1..=255 each (0 would make the record corrupt; the
/// encoder writes what it is given, so tests can build bad records on purpose).
pub fn encode_sample(header: u8, values: &[u8], status: Option<u8>, out: &mut Vec<u8>) {
    out.push(header);
    out.extend_from_slice(values);
    if let Some(s) = status {
        out.push(s);
    }
    out.push(TERMINATOR);
}

/// Appends a fault record.
pub fn encode_fault(header: u8, fault: GloveFault, out: &mut Vec<u8>) {
    let code = match fault {
        GloveFault::SampleError => b's',
        GloveFault::GloveUnplugged => b'g',
    };
    out.extend_from_slice(&[header, b'e', code, TERMINATOR]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masks_give_the_documented_sensor_orders() {
        let j18 = joints_of_mask(MASK_18);
        assert_eq!(j18.len(), 18);
        use Joint::*;
        assert_eq!(
            j18,
            vec![
                ThumbRoll,
                ThumbMcp,
                ThumbIp,
                ThumbIndexAbduction,
                IndexMcp,
                IndexPip,
                MiddleMcp,
                MiddlePip,
                IndexMiddleAbduction,
                RingMcp,
                RingPip,
                MiddleRingAbduction,
                PinkyMcp,
                PinkyPip,
                RingPinkyAbduction,
                PalmArch,
                WristPitch,
                WristYaw
            ]
        );
        assert_eq!(joints_of_mask(MASK_22).len(), 22);
    }

    #[test]
    fn a_record_is_byte_exact() {
        let mut bytes = Vec::new();
        let values: Vec<u8> = (1..=18).collect();
        encode_sample(
            b'S',
            &values,
            Some(STATUS_GLOVE_IN | STATUS_SWITCH),
            &mut bytes,
        );
        let mut expected = vec![b'S'];
        expected.extend(1..=18u8);
        expected.extend([0x03, 0x00]);
        assert_eq!(bytes, expected);
        let framing = CyberGloveFraming {
            sensors: SensorCount::Eighteen,
            status_byte: true,
        };
        let mut d = CyberGloveDecoder::new(framing);
        let recs = d.decode(&bytes);
        assert_eq!(recs.len(), 1);
        assert_eq!(recs[0].values(), &values[..]);
    }

    #[test]
    fn error_records_decode_and_zero_bytes_reject() {
        let framing = CyberGloveFraming {
            sensors: SensorCount::Eighteen,
            status_byte: false,
        };
        let mut d = CyberGloveDecoder::new(framing);
        let mut bytes = Vec::new();
        encode_fault(b'S', GloveFault::GloveUnplugged, &mut bytes);
        let mut bad: Vec<u8> = (1..=18).collect();
        bad[5] = 0;
        encode_sample(b'S', &bad, None, &mut bytes);
        encode_sample(b'S', &[7; 18], None, &mut bytes);
        let recs = d.decode(&bytes);
        assert_eq!(recs.len(), 2);
        assert_eq!(
            recs[0],
            CyberRecord::Fault {
                header: b'S',
                fault: GloveFault::GloveUnplugged
            }
        );
        assert_eq!(recs[1].values(), &[7; 18]);
        assert!(d.stats().rejected >= 1);
    }
}
