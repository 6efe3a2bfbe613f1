//! 5DT Data Glove protocols (`docs/design.md` §16 §2): the serial Data Glove 5 and Data Glove 16
//! byte streams, and the Data Glove Ultra's USB HID report.
//!
//! ## Data Glove 5 (serial, 19200 baud 8N1)
//! Commands: `A` initialise (the glove answers one byte, 0x55); `G` information (32-byte
//! answer; bit 0 of byte 4 set for a right hand); `C` send one record; `D` stream records.
//! The sources do not say outright how streaming ends; the backend takes the glove back to
//! answering requests by asking for one record (`C`, the polled mode of VRPN's driver), both
//! to stop it and, before its handshake, to make sure a glove left streaming is quiet. The
//! emulator models the glove that way.
//!
//! | byte | field |
//! |---|---|
//! | 0 | header 0x80 |
//! | 1–5 | thumb, index, middle, ring, little flexure, 0..=255 (value/255 of full bend) |
//! | 6 | pitch of the hand's tilt sensor, 180·value/255 degrees |
//! | 7 | roll, 180·value/255 degrees |
//! | 8 | checksum: XOR of bytes 1 to 7 |
//!
//! A record whose checksum does not match is rejected; the decoder drops the header and hunts
//! for the next 0x80. (Some units are said to send a tenth byte; it is not accepted here.)
//!
//! ## Data Glove 16 (serial, 19200 baud)
//! The glove streams by itself. Data packets are 36 bytes: `<`, `D`, then 16 sensor values as
//! big-endian u16 at offsets 2–33, then two trailing bytes whose meaning the sources do not give
//! (they are carried but not checked). 7-byte information packets `<`, `I` + 5 bytes (hardware
//! version major, minor, hand, wireless flag, reserved) are interleaved. The sensors digitise to
//! 12 bits, so a data packet with a value above 4095 is rejected as misframed (this is what
//! keeps the decoder from locking onto `<D` inside data). A packet whose unchecked bytes (the
//! data trailer, the information bytes) contain `<D` or `<I` is taken for a truncated packet
//! swallowing the next header and rejected; when its last byte is `<`, the decoder waits for one
//! more byte to decide.
//!
//! ## Data Glove Ultra (USB HID)
//! Vendor id 0x5D70. Product-id bit 0 set means a left-hand glove; bit 4 set means the 5-sensor
//! model. A 64-byte input report holds 16 big-endian i16 values, each ×1/4096 of full scale;
//! the 14-sensor glove uses the first 14 in the order thumb near, thumb far, thumb–index
//! abduction, index near, index far, index–middle abduction, middle near, middle far,
//! middle–ring abduction, ring near, ring far, ring–little abduction, little near, little far; the
//! 5-sensor glove uses values 0, 3, 6, 9, 12. Whether a report-id byte precedes the data is not
//! settled by the sources, so [`decode_ultra_report`] takes it as an option.

use crate::decode::{Frame, Framing, StreamDecoder};
use crate::profile::{SensorCalibration, Side};
use crate::{DeviceError, Joint};

/// Glove 5: initialise (answer 0x55).
pub const GLOVE5_INIT: u8 = b'A';
/// Glove 5: the answer to [`GLOVE5_INIT`].
pub const GLOVE5_INIT_ANSWER: u8 = 0x55;
/// Glove 5: 32-byte information block.
pub const GLOVE5_INFO: u8 = b'G';
/// Glove 5: length of the information block.
pub const GLOVE5_INFO_LEN: usize = 32;
/// Glove 5: one record (which also ends streaming).
pub const GLOVE5_ONE: u8 = b'C';
/// Glove 5: stream records.
pub const GLOVE5_STREAM: u8 = b'D';
/// Glove 5: record header.
pub const GLOVE5_HEADER: u8 = 0x80;
/// Glove 5: record length.
pub const GLOVE5_LEN: usize = 9;

/// Glove 16: data packet length.
pub const GLOVE16_DATA_LEN: usize = 36;
/// Glove 16: information packet length.
pub const GLOVE16_INFO_LEN: usize = 7;
/// Largest raw value of the 12-bit sensors.
pub const MAX_12_BIT: u16 = 4095;

/// USB vendor id of 5DT.
pub const ULTRA_VENDOR_ID: u16 = 0x5D70;
/// Length of an Ultra input report (without a report-id byte).
pub const ULTRA_REPORT_LEN: usize = 64;
/// Scale of an Ultra value: raw/4096 is the fraction of full scale.
pub const ULTRA_SCALE: f64 = 1.0 / 4096.0;

/// Full scale of an Ultra value: a report value beyond ±4096 is outside the sensor's range
/// (corrupt); the backend drops the report and counts it as invalid.
pub const ULTRA_FULL_SCALE: u16 = 4096;

/// The joints of the 14-sensor gloves, in sensor order.
pub const JOINTS_14: [Joint; 14] = [
    Joint::ThumbMcp,
    Joint::ThumbIp,
    Joint::ThumbIndexAbduction,
    Joint::IndexMcp,
    Joint::IndexPip,
    Joint::IndexMiddleAbduction,
    Joint::MiddleMcp,
    Joint::MiddlePip,
    Joint::MiddleRingAbduction,
    Joint::RingMcp,
    Joint::RingPip,
    Joint::RingPinkyAbduction,
    Joint::PinkyMcp,
    Joint::PinkyPip,
];

/// The joints the 5-sensor gloves' overall finger flexures are mapped to (the knuckle joints).
pub const JOINTS_5: [Joint; 5] = [
    Joint::ThumbMcp,
    Joint::IndexMcp,
    Joint::MiddleMcp,
    Joint::RingMcp,
    Joint::PinkyMcp,
];

/// The Ultra values used by the 5-sensor model.
pub const ULTRA_5_SENSOR_SLOTS: [usize; 5] = [0, 3, 6, 9, 12];

/// A Data Glove 5 record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Glove5Record {
    /// Thumb, index, middle, ring, little flexure (0..=255).
    pub fingers: [u8; 5],
    /// Tilt pitch byte (180·value/255 degrees).
    pub pitch: u8,
    /// Tilt roll byte (180·value/255 degrees).
    pub roll: u8,
}

impl Glove5Record {
    /// Pitch in degrees.
    pub fn pitch_degrees(&self) -> f64 {
        180.0 * f64::from(self.pitch) / 255.0
    }

    /// Roll in degrees.
    pub fn roll_degrees(&self) -> f64 {
        180.0 * f64::from(self.roll) / 255.0
    }
}

/// Framing of the Data Glove 5 stream.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Glove5Framing;

fn xor(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0, |a, b| a ^ b)
}

impl Framing for Glove5Framing {
    type Record = Glove5Record;

    fn frame(&self, w: &[u8]) -> Frame<Glove5Record> {
        if w[0] != GLOVE5_HEADER {
            return Frame::NotHeader;
        }
        if w.len() < GLOVE5_LEN {
            return Frame::NeedMore;
        }
        if xor(&w[1..8]) != w[8] {
            return Frame::Reject;
        }
        let mut fingers = [0; 5];
        fingers.copy_from_slice(&w[1..6]);
        Frame::Record(
            Glove5Record {
                fingers,
                pitch: w[6],
                roll: w[7],
            },
            GLOVE5_LEN,
        )
    }
}

/// The Data Glove 5 decoder.
pub type Glove5Decoder = StreamDecoder<Glove5Framing>;

/// Appends a Data Glove 5 record.
pub fn encode_glove5(record: &Glove5Record, out: &mut Vec<u8>) {
    let start = out.len();
    out.push(GLOVE5_HEADER);
    out.extend_from_slice(&record.fingers);
    out.push(record.pitch);
    out.push(record.roll);
    let sum = xor(&out[start + 1..]);
    out.push(sum);
}

/// A Data Glove 16 packet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Glove16Packet {
    /// `<D`: sensor values.
    Data {
        /// The 16 raw values (0..=4095).
        values: [u16; 16],
        /// The two trailing bytes, unchecked.
        trailer: [u8; 2],
    },
    /// `<I`: information.
    Info([u8; 5]),
}

/// Framing of the Data Glove 16 stream.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Glove16Framing;

/// Whether bytes `from..to` of a candidate packet hold the start of another packet (`<D` or
/// `<I`), which means the candidate is a truncated packet swallowing the next one. `None` when
/// the answer depends on the byte after the candidate, which has not arrived yet.
fn swallows_header(w: &[u8], from: usize, to: usize) -> Option<bool> {
    for i in from..to {
        if w[i] == b'<' {
            match w.get(i + 1) {
                Some(b'D' | b'I') => return Some(true),
                Some(_) => {}
                None => return None,
            }
        }
    }
    Some(false)
}

impl Framing for Glove16Framing {
    type Record = Glove16Packet;

    fn frame(&self, w: &[u8]) -> Frame<Glove16Packet> {
        if w[0] != b'<' {
            return Frame::NotHeader;
        }
        let Some(&kind) = w.get(1) else {
            return Frame::NeedMore;
        };
        let (len, body_from) = match kind {
            b'D' => {
                // Check the high bytes as they arrive: each must be ≤ 0x0F.
                let have = w.len().min(34);
                if (2..have).step_by(2).any(|i| w[i] > (MAX_12_BIT >> 8) as u8) {
                    return Frame::Reject;
                }
                // Only the unchecked trailer can hide a following header.
                (GLOVE16_DATA_LEN, 34)
            }
            b'I' => (GLOVE16_INFO_LEN, 2),
            _ => return Frame::Reject,
        };
        if w.len() < len {
            return Frame::NeedMore;
        }
        match swallows_header(w, body_from, len) {
            None => return Frame::NeedMore,
            Some(true) => return Frame::Reject,
            Some(false) => {}
        }
        if kind == b'D' {
            let mut values = [0u16; 16];
            for (i, v) in values.iter_mut().enumerate() {
                *v = u16::from_be_bytes([w[2 + 2 * i], w[3 + 2 * i]]);
            }
            Frame::Record(
                Glove16Packet::Data {
                    values,
                    trailer: [w[34], w[35]],
                },
                len,
            )
        } else {
            let mut info = [0u8; 5];
            info.copy_from_slice(&w[2..7]);
            Frame::Record(Glove16Packet::Info(info), len)
        }
    }
}

/// The Data Glove 16 decoder.
pub type Glove16Decoder = StreamDecoder<Glove16Framing>;

/// Appends a Data Glove 16 packet.
pub fn encode_glove16(packet: &Glove16Packet, out: &mut Vec<u8>) {
    match packet {
        Glove16Packet::Data { values, trailer } => {
            out.extend_from_slice(b"<D");
            for v in values {
                out.extend_from_slice(&v.to_be_bytes());
            }
            out.extend_from_slice(trailer);
        }
        Glove16Packet::Info(info) => {
            out.extend_from_slice(b"<I");
            out.extend_from_slice(info);
        }
    }
}

/// Product-id bit of a left-hand Ultra glove.
pub const ULTRA_PID_LEFT_HAND: u16 = 0x01;
/// Product-id bit of the 5-sensor Ultra glove.
pub const ULTRA_PID_FIVE_SENSORS: u16 = 0x10;
/// The Ultra values used by the 14-sensor model.
pub const ULTRA_14_SENSOR_SLOTS: [usize; 14] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13];

/// What the product id of an Ultra USB glove says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct UltraModel {
    /// A left-hand glove (product-id bit 0).
    pub left_hand: bool,
    /// The 5-sensor model (product-id bit 4); otherwise 14 sensors.
    pub five_sensors: bool,
}

/// The calibration an Ultra glove is read with, fitted to its model by
/// [`UltraModel::fit_calibration`], and what people should be told about the fit.
#[derive(Debug, Clone, PartialEq)]
pub struct UltraFit {
    /// One entry per report value (16), mapping only the values the glove's model reports.
    pub calibration: Vec<SensorCalibration>,
    /// Mismatches between the glove and the profile that were worked around.
    pub warnings: Vec<String>,
}

impl UltraModel {
    /// The model a product id names.
    pub fn from_product_id(pid: u16) -> Self {
        UltraModel {
            left_hand: pid & ULTRA_PID_LEFT_HAND != 0,
            five_sensors: pid & ULTRA_PID_FIVE_SENSORS != 0,
        }
    }

    /// Which hand the glove is made for.
    pub fn side(&self) -> Side {
        if self.left_hand {
            Side::Left
        } else {
            Side::Right
        }
    }

    /// The report values this model fills, in sensor order.
    pub fn slots(&self) -> &'static [usize] {
        if self.five_sensors {
            &ULTRA_5_SENSOR_SLOTS
        } else {
            &ULTRA_14_SENSOR_SLOTS
        }
    }

    /// Describes the model for messages (`5-sensor right-hand`).
    pub fn describe(&self) -> String {
        format!(
            "{}-sensor {}-hand",
            self.slots().len(),
            if self.left_hand { "left" } else { "right" }
        )
    }

    /// Fits a profile's calibration table (one entry per report value) to this model: entries
    /// for report values the model does not fill are dropped (their joints would read
    /// whatever the unused values hold), with a warning naming them — so the 14-sensor table
    /// read by a 5-sensor glove keeps the five knuckle flexures at values 0, 3, 6, 9, 12. A
    /// table that then maps no joint at all is refused. When `hand` is given and differs from
    /// the glove's side, a warning says so (the glove still works; the hand model is the
    /// profile's).
    pub fn fit_calibration(
        &self,
        pid: u16,
        table: &[SensorCalibration],
        hand: Option<Side>,
    ) -> Result<UltraFit, DeviceError> {
        let slots = self.slots();
        let mut calibration = table.to_vec();
        let mut dropped = Vec::new();
        for (i, c) in calibration.iter_mut().enumerate() {
            if let Some(j) = c.joint
                && !slots.contains(&i)
            {
                dropped.push(format!("{j} (value {i})"));
                c.joint = None;
            }
        }
        let label = format!(
            "5DT Data Glove Ultra (product id {pid:#06x}, {})",
            self.describe()
        );
        if calibration.iter().all(|c| c.joint.is_none()) {
            return Err(DeviceError::Unsupported(format!(
                "{label}: the profile's calibration maps none of the report values this glove fills ({}); use a calibration table for the {}-sensor glove",
                slots
                    .iter()
                    .map(usize::to_string)
                    .collect::<Vec<_>>()
                    .join(", "),
                slots.len()
            )));
        }
        let mut warnings = Vec::new();
        if !dropped.is_empty() {
            warnings.push(format!(
                "{label}: reports only values {}; the profile's {} are not read",
                slots
                    .iter()
                    .map(usize::to_string)
                    .collect::<Vec<_>>()
                    .join(", "),
                dropped.join(", ")
            ));
        }
        if let Some(side) = hand
            && side != self.side()
        {
            warnings.push(format!(
                "{label}: the glove is for the {} hand but the profile's hand is the {} one",
                side_name(self.side()),
                side_name(side)
            ));
        }
        Ok(UltraFit {
            calibration,
            warnings,
        })
    }
}

fn side_name(side: Side) -> &'static str {
    match side {
        Side::Left => "left",
        Side::Right => "right",
    }
}

/// Decodes an Ultra input report into its 16 raw values (big-endian i16; value/4096 is the
/// fraction of full scale). With `report_id`, the first byte is a report id and is skipped.
pub fn decode_ultra_report(report: &[u8], report_id: bool) -> Result<[i16; 16], DeviceError> {
    let data = if report_id {
        report.get(1..).unwrap_or(&[])
    } else {
        report
    };
    if data.len() < 32 {
        return Err(DeviceError::InvalidValue(format!(
            "5DT Ultra report of {} bytes (at least 32 data bytes expected)",
            report.len()
        )));
    }
    let mut values = [0i16; 16];
    for (i, v) in values.iter_mut().enumerate() {
        *v = i16::from_be_bytes([data[2 * i], data[2 * i + 1]]);
    }
    Ok(values)
}

/// Encodes an Ultra input report (64 bytes, with a leading report id when given).
pub fn encode_ultra_report(values: &[i16; 16], report_id: Option<u8>) -> Vec<u8> {
    let mut out = Vec::with_capacity(ULTRA_REPORT_LEN + 1);
    out.extend(report_id);
    for v in values {
        out.extend_from_slice(&v.to_be_bytes());
    }
    out.resize(report_id.is_some() as usize + ULTRA_REPORT_LEN, 0);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glove5_record_is_byte_exact_with_its_checksum() {
        let rec = Glove5Record {
            fingers: [1, 2, 4, 8, 16],
            pitch: 32,
            roll: 64,
        };
        let mut b = Vec::new();
        encode_glove5(&rec, &mut b);
        assert_eq!(b, [0x80, 1, 2, 4, 8, 16, 32, 64, 127]);
        let mut d = Glove5Decoder::new(Glove5Framing);
        assert_eq!(d.decode(&b), vec![rec]);
        b[3] ^= 1;
        assert!(d.decode(&b).is_empty());
        assert_eq!(d.stats().rejected, 1);
    }

    #[test]
    fn glove16_skips_info_packets_and_rejects_13_bit_values() {
        let mut b = Vec::new();
        let values: [u16; 16] = std::array::from_fn(|i| (i as u16) * 200);
        encode_glove16(&Glove16Packet::Info([1, 2, 1, 1, 0]), &mut b);
        encode_glove16(
            &Glove16Packet::Data {
                values,
                trailer: [0, 0],
            },
            &mut b,
        );
        let mut d = Glove16Decoder::new(Glove16Framing);
        let recs = d.decode(&b);
        assert_eq!(recs.len(), 2);
        assert_eq!(
            recs[1],
            Glove16Packet::Data {
                values,
                trailer: [0, 0]
            }
        );
        let mut bad = Vec::new();
        encode_glove16(
            &Glove16Packet::Data {
                values: [0x1000; 16],
                trailer: [0, 0],
            },
            &mut bad,
        );
        assert!(d.decode(&bad).is_empty());
    }

    #[test]
    fn ultra_reports_round_trip_with_and_without_report_id() {
        let values: [i16; 16] = std::array::from_fn(|i| (i as i16 - 8) * 300);
        for id in [None, Some(1)] {
            let r = encode_ultra_report(&values, id);
            assert_eq!(r.len(), 64 + id.is_some() as usize);
            assert_eq!(decode_ultra_report(&r, id.is_some()).unwrap(), values);
        }
        assert!(decode_ultra_report(&[0; 10], false).is_err());
        let m = UltraModel::from_product_id(0x0011);
        assert!(m.left_hand && m.five_sensors);
    }

    /// The shipped 14-sensor table (thumb near, far, abduction, …; values 14, 15 unused).
    fn table_14() -> Vec<SensorCalibration> {
        (0..16)
            .map(|i| SensorCalibration {
                joint: JOINTS_14.get(i).copied(),
                offset: 0.0,
                gain: 0.0003834952,
            })
            .collect()
    }

    #[test]
    fn a_five_sensor_ultra_reads_only_its_five_values_with_a_14_sensor_table() {
        let pid = ULTRA_PID_FIVE_SENSORS;
        let m = UltraModel::from_product_id(pid);
        assert_eq!(m.slots(), &ULTRA_5_SENSOR_SLOTS);
        let fit = m
            .fit_calibration(pid, &table_14(), Some(Side::Right))
            .unwrap();
        let mapped: Vec<Joint> = fit.calibration.iter().filter_map(|c| c.joint).collect();
        assert_eq!(mapped, JOINTS_5);
        for (i, c) in fit.calibration.iter().enumerate() {
            assert_eq!(c.joint.is_some(), ULTRA_5_SENSOR_SLOTS.contains(&i), "{i}");
        }
        assert_eq!(fit.warnings.len(), 1, "{:?}", fit.warnings);
        assert!(
            fit.warnings[0].contains("0, 3, 6, 9, 12") && fit.warnings[0].contains("thumb_ip"),
            "{}",
            fit.warnings[0]
        );
        // The 14-sensor glove keeps the whole table, silently.
        let fit = UltraModel::from_product_id(0)
            .fit_calibration(0, &table_14(), Some(Side::Right))
            .unwrap();
        assert_eq!(fit.calibration, table_14());
        assert!(fit.warnings.is_empty());
    }

    #[test]
    fn a_table_the_glove_cannot_fill_is_refused_and_the_other_hand_is_reported() {
        // Only far joints and abductions: nothing at 0, 3, 6, 9, 12.
        let mut table = table_14();
        for i in ULTRA_5_SENSOR_SLOTS {
            table[i].joint = None;
        }
        let pid = ULTRA_PID_FIVE_SENSORS;
        let e = UltraModel::from_product_id(pid)
            .fit_calibration(pid, &table, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("5-sensor") && e.contains("0x0010"), "{e}");
        assert!(e.contains("maps none"), "{e}");
        let pid = ULTRA_PID_LEFT_HAND;
        let fit = UltraModel::from_product_id(pid)
            .fit_calibration(pid, &table_14(), Some(Side::Right))
            .unwrap();
        assert_eq!(fit.warnings.len(), 1);
        assert!(
            fit.warnings[0].contains("left hand") && fit.warnings[0].contains("right one"),
            "{}",
            fit.warnings[0]
        );
        // No hand to check against: no warning.
        let fit = UltraModel::from_product_id(pid)
            .fit_calibration(pid, &table_14(), None)
            .unwrap();
        assert!(fit.warnings.is_empty());
    }
}
