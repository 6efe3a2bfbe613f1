//! Polhemus Fastrak serial protocol (`docs/design.md` §16 §3).
//!
//! ## Link
//! Up to 115200 baud 8N1 (19200 and 115200 are common). 120 Hz update cycle.
//!
//! ## Commands the backend sends
//! - `c` polled mode (stops continuous output), `C` continuous mode; `P` one record (polled);
//! - `F` ASCII records, `f` binary records;
//! - `U` positions in inches, `u` in centimetres;
//! - `O<station>,<item>,<item>,…` CR: the output list of a station (items below).
//!
//! ## Record
//! | bytes | field |
//! |---|---|
//! | 1 | `0` (record type: data) |
//! | 1 | station number, ASCII `1`–`4` |
//! | 1 | error/status byte: space when all is well, else a letter (the record is flagged: the backend drops it and counts a fault) |
//! | … | the items of the output list, in its order |
//!
//! Items: 1 = CR LF (two bytes in both formats), 2 = position x y z, 4 = azimuth, elevation,
//! roll in degrees, 11 = orientation quaternion w x y z. In ASCII each value is a 7-character
//! right-aligned decimal, `Sxxx.xx` (sign or space, two decimals) for position and angles and
//! `Sx.xxxx` (four decimals) for quaternion parts; in binary each value is a little-endian IEEE
//! f32. The default ASCII record (items 2, 4, 1) is 3 + 6·7 + 2 = 47 bytes.
//!
//! Orientation by angles is R = Rz(azimuth)·Ry(elevation)·Rx(roll).
//!
//! ## Resynchronisation
//! Hunt for `0` followed by a station digit and a space-or-letter; then every field must parse
//! (ASCII: digits, one point, optional sign; binary: finite), lie in its range (positions within
//! ±1000 units, angles within ±180°, quaternion of norm within 0.02 of 1) and CR LF must sit
//! where the output list puts it. Otherwise drop one byte and hunt again.
//!
//! ## Measuring range
//! The backend passes on positions within [`POSITION_LIMIT_M`] = 3.81 m per axis: the
//! standard source's 10-foot range ([`MEASURING_RANGE_M`]) with a 25 % margin. A well-framed
//! record beyond it is a corrupt value (a flipped exponent bit of a binary f32): dropped and
//! counted as invalid. Orientations are checked by the decoder (above).

use glam::{DQuat, DVec3, EulerRot};

use crate::decode::{Frame, Framing, StreamDecoder};
use crate::{DeviceError, TrackerPose};

/// Continuous output.
pub const CONTINUOUS: u8 = b'C';
/// Polled mode (stops continuous output).
pub const POLLED: u8 = b'c';
/// Send one record.
pub const POINT: u8 = b'P';
/// ASCII records.
pub const ASCII: u8 = b'F';
/// Binary records.
pub const BINARY: u8 = b'f';
/// Positions in inches.
pub const INCHES: u8 = b'U';
/// Positions in centimetres.
pub const CENTIMETRES: u8 = b'u';

/// The error byte of a record the tracker does not flag (a space). Any other value (a letter)
/// flags the record; the backend counts it as a fault and drops it.
pub const NO_ERROR: u8 = b' ';
/// Largest position magnitude the decoder accepts as a well-formed field, in device units (the
/// ASCII field's own limit, `±999.99`): beyond it a candidate record is misframed.
pub const POSITION_RANGE: f64 = 1000.0;

/// The Fastrak's measuring range with its standard source: 10 feet (3.05 m) from the source,
/// per axis (manual Rev G: operation to 10 ft, specified accuracy to 30 in).
pub const MEASURING_RANGE_M: f64 = 3.048;

/// Largest position coordinate the backend passes on, in metres: the measuring range with a
/// 25 % margin (3.81 m, 150 in). A well-framed record beyond it (a flipped exponent bit of a
/// binary field turns 3 in into 783 in) is dropped and counted as invalid
/// ([`DeviceStats::invalid`](crate::DeviceStats::invalid)).
pub const POSITION_LIMIT_M: f64 = 1.25 * MEASURING_RANGE_M;
/// Width of an ASCII field.
pub const ASCII_FIELD: usize = 7;

/// An output-list item.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Item {
    /// 1: CR LF.
    CrLf,
    /// 2: position x, y, z.
    Position,
    /// 4: azimuth, elevation, roll (degrees).
    Euler,
    /// 11: quaternion w, x, y, z.
    Quaternion,
}

impl Item {
    /// The item's number in the output-list command.
    pub const fn code(self) -> u8 {
        match self {
            Item::CrLf => 1,
            Item::Position => 2,
            Item::Euler => 4,
            Item::Quaternion => 11,
        }
    }

    /// The item of a number.
    pub fn from_code(code: u8) -> Option<Item> {
        Some(match code {
            1 => Item::CrLf,
            2 => Item::Position,
            4 => Item::Euler,
            11 => Item::Quaternion,
            _ => return None,
        })
    }

    const fn values(self) -> usize {
        match self {
            Item::CrLf => 0,
            Item::Position | Item::Euler => 3,
            Item::Quaternion => 4,
        }
    }

    const fn decimals(self) -> usize {
        match self {
            Item::Quaternion => 4,
            _ => 2,
        }
    }
}

/// Record encoding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DataFormat {
    /// 7-character decimal fields.
    Ascii,
    /// Little-endian f32 fields.
    Binary,
}

/// Units of positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Units {
    /// Inches (the power-on default).
    Inches,
    /// Centimetres.
    Centimetres,
}

impl Units {
    /// Metres per unit.
    pub const fn metres(self) -> f64 {
        match self {
            Units::Inches => 0.0254,
            Units::Centimetres => 0.01,
        }
    }

    /// The unit's name, for messages.
    pub const fn name(self) -> &'static str {
        match self {
            Units::Inches => "in",
            Units::Centimetres => "cm",
        }
    }
}

/// Decoder configuration: format and output list the tracker was given.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FastrakFraming {
    /// ASCII or binary.
    pub format: DataFormat,
    /// The output list.
    pub items: Vec<Item>,
}

impl FastrakFraming {
    /// The configuration the backend uses: position, quaternion, CR LF.
    pub fn position_quaternion(format: DataFormat) -> Self {
        FastrakFraming {
            format,
            items: vec![Item::Position, Item::Quaternion, Item::CrLf],
        }
    }

    fn field_len(&self) -> usize {
        match self.format {
            DataFormat::Ascii => ASCII_FIELD,
            DataFormat::Binary => 4,
        }
    }

    /// Length of a record in bytes.
    pub fn record_len(&self) -> usize {
        3 + self
            .items
            .iter()
            .map(|i| {
                if *i == Item::CrLf {
                    2
                } else {
                    i.values() * self.field_len()
                }
            })
            .sum::<usize>()
    }
}

/// A decoded record, in device units (positions in inches or centimetres, angles in degrees).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FastrakRecord {
    /// Station 1–4.
    pub station: u8,
    /// Error/status byte (space when all is well).
    pub error: u8,
    /// Position x, y, z.
    pub position: Option<[f64; 3]>,
    /// Azimuth, elevation, roll, degrees.
    pub euler: Option<[f64; 3]>,
    /// Quaternion w, x, y, z.
    pub quaternion: Option<[f64; 4]>,
}

impl FastrakRecord {
    /// The pose in metres: position × unit, orientation from the quaternion when the record has
    /// one, else from the angles. Fails (never panics) when the record lacks either part or the
    /// values are out of range.
    pub fn pose(&self, units: Units) -> Result<TrackerPose, DeviceError> {
        let Some([x, y, z]) = self.position else {
            return Err(DeviceError::InvalidValue(
                "Fastrak record without position".into(),
            ));
        };
        let orientation = match (self.quaternion, self.euler) {
            (Some([w, qx, qy, qz]), _) => DQuat::from_xyzw(qx, qy, qz, w),
            (None, Some([az, el, roll])) => DQuat::from_euler(
                EulerRot::ZYX,
                az.to_radians(),
                el.to_radians(),
                roll.to_radians(),
            ),
            (None, None) => {
                return Err(DeviceError::InvalidValue(
                    "Fastrak record without orientation".into(),
                ));
            }
        };
        TrackerPose::new(DVec3::new(x, y, z) * units.metres(), orientation)
    }
}

/// Parses a 7-character ASCII field: optional leading spaces, optional `-` or `+`, digits with
/// exactly one decimal point. Anything else is `None`.
fn parse_ascii_field(field: &[u8]) -> Option<f64> {
    let s = std::str::from_utf8(field).ok()?;
    let t = s.trim_start_matches(' ');
    let body = t.strip_prefix(['-', '+']).unwrap_or(t);
    let mut points = 0;
    let mut digits = 0;
    for c in body.bytes() {
        match c {
            b'0'..=b'9' => digits += 1,
            b'.' => points += 1,
            _ => return None,
        }
    }
    if points != 1 || digits == 0 {
        return None;
    }
    t.parse().ok()
}

fn in_range(item: Item, v: &[f64]) -> bool {
    match item {
        Item::CrLf => true,
        Item::Position => v.iter().all(|x| x.is_finite() && x.abs() <= POSITION_RANGE),
        Item::Euler => v.iter().all(|x| x.is_finite() && x.abs() <= 180.0 + 1e-3),
        Item::Quaternion => {
            let n2: f64 = v.iter().map(|x| x * x).sum();
            v.iter().all(|x| x.is_finite()) && (n2.sqrt() - 1.0).abs() <= 0.02
        }
    }
}

impl Framing for FastrakFraming {
    type Record = FastrakRecord;

    fn frame(&self, w: &[u8]) -> Frame<FastrakRecord> {
        if w[0] != b'0' {
            return Frame::NotHeader;
        }
        if w.len() >= 2 && !(b'1'..=b'4').contains(&w[1]) {
            return Frame::Reject;
        }
        if w.len() >= 3 && !(w[2] == b' ' || w[2].is_ascii_alphabetic()) {
            return Frame::Reject;
        }
        let len = self.record_len();
        if w.len() < len {
            return Frame::NeedMore;
        }
        let mut record = FastrakRecord {
            station: w[1] - b'0',
            error: w[2],
            ..Default::default()
        };
        let mut at = 3;
        let field = self.field_len();
        for &item in &self.items {
            if item == Item::CrLf {
                if &w[at..at + 2] != b"\r\n" {
                    return Frame::Reject;
                }
                at += 2;
                continue;
            }
            let mut v = [0.0f64; 4];
            for slot in v.iter_mut().take(item.values()) {
                let bytes = &w[at..at + field];
                let parsed = match self.format {
                    DataFormat::Ascii => parse_ascii_field(bytes),
                    DataFormat::Binary => {
                        let x = f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
                        x.is_finite().then_some(f64::from(x))
                    }
                };
                let Some(x) = parsed else {
                    return Frame::Reject;
                };
                *slot = x;
                at += field;
            }
            if !in_range(item, &v[..item.values()]) {
                return Frame::Reject;
            }
            match item {
                Item::Position => record.position = Some([v[0], v[1], v[2]]),
                Item::Euler => record.euler = Some([v[0], v[1], v[2]]),
                Item::Quaternion => record.quaternion = Some(v),
                Item::CrLf => {}
            }
        }
        Frame::Record(record, len)
    }
}

/// The Fastrak stream decoder.
pub type FastrakDecoder = StreamDecoder<FastrakFraming>;

/// Appends a record in the framing's format. Fails when a value does not fit its ASCII field
/// or an item the output list names is missing from the record.
pub fn encode_record(
    framing: &FastrakFraming,
    record: &FastrakRecord,
    out: &mut Vec<u8>,
) -> Result<(), DeviceError> {
    out.push(b'0');
    out.push(b'0' + record.station);
    out.push(record.error);
    for &item in &framing.items {
        let values: &[f64] = match item {
            Item::CrLf => {
                out.extend_from_slice(b"\r\n");
                continue;
            }
            Item::Position => record.position.as_ref().map(|v| &v[..]),
            Item::Euler => record.euler.as_ref().map(|v| &v[..]),
            Item::Quaternion => record.quaternion.as_ref().map(|v| &v[..]),
        }
        .ok_or_else(|| DeviceError::InvalidValue(format!("record lacks item {}", item.code())))?;
        for &x in values {
            match framing.format {
                DataFormat::Ascii => {
                    let s = format!(
                        "{:>width$.prec$}",
                        x,
                        width = ASCII_FIELD,
                        prec = item.decimals()
                    );
                    if s.len() != ASCII_FIELD {
                        return Err(DeviceError::InvalidValue(format!(
                            "{x} does not fit a {ASCII_FIELD}-character Fastrak field"
                        )));
                    }
                    out.extend_from_slice(s.as_bytes());
                }
                DataFormat::Binary => out.extend_from_slice(&(x as f32).to_le_bytes()),
            }
        }
    }
    Ok(())
}

/// The output-list command `O<station>,<code>,…` CR.
pub fn output_list_command(station: u8, items: &[Item]) -> Vec<u8> {
    let mut s = format!("O{station}");
    for i in items {
        s.push_str(&format!(",{}", i.code()));
    }
    s.push('\r');
    s.into_bytes()
}

/// Parses the body of an output-list command (between `O` and CR): station and items.
pub fn parse_output_list(body: &[u8]) -> Option<(u8, Vec<Item>)> {
    let s = std::str::from_utf8(body).ok()?;
    let mut parts = s.split(',');
    let station: u8 = parts.next()?.trim().parse().ok()?;
    let items = parts
        .map(|p| p.trim().parse().ok().and_then(Item::from_code))
        .collect::<Option<Vec<_>>>()?;
    ((1..=4).contains(&station) && !items.is_empty()).then_some((station, items))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_ascii_record_is_47_bytes_and_byte_exact() {
        let framing = FastrakFraming {
            format: DataFormat::Ascii,
            items: vec![Item::Position, Item::Euler, Item::CrLf],
        };
        assert_eq!(framing.record_len(), 47);
        let rec = FastrakRecord {
            station: 1,
            error: b' ',
            position: Some([12.34, -5.5, 0.0]),
            euler: Some([-179.99, 45.0, 3.25]),
            quaternion: None,
        };
        let mut b = Vec::new();
        encode_record(&framing, &rec, &mut b).unwrap();
        assert_eq!(
            &b[..],
            &b"01   12.34  -5.50   0.00-179.99  45.00   3.25\r\n"[..]
        );
        let mut d = FastrakDecoder::new(framing);
        assert_eq!(d.decode(&b), vec![rec]);
    }

    #[test]
    fn binary_position_quaternion_round_trips() {
        let framing = FastrakFraming::position_quaternion(DataFormat::Binary);
        assert_eq!(framing.record_len(), 3 + 28 + 2);
        let rec = FastrakRecord {
            station: 2,
            error: b' ',
            position: Some([1.5, -2.25, 30.0]),
            euler: None,
            quaternion: Some([0.5, 0.5, -0.5, 0.5]),
        };
        let mut b = Vec::new();
        encode_record(&framing, &rec, &mut b).unwrap();
        let mut d = FastrakDecoder::new(framing);
        assert_eq!(d.decode(&b), vec![rec]);
        let pose = rec.pose(Units::Inches).unwrap();
        assert!((pose.position - DVec3::new(1.5, -2.25, 30.0) * 0.0254).length() < 1e-12);
    }

    #[test]
    fn euler_orientation_is_rz_ry_rx() {
        let rec = FastrakRecord {
            station: 1,
            error: b' ',
            position: Some([0.0; 3]),
            euler: Some([90.0, 0.0, 0.0]),
            quaternion: None,
        };
        let q = rec.pose(Units::Centimetres).unwrap().orientation;
        assert!((q * DVec3::X - DVec3::Y).length() < 1e-12);
    }

    #[test]
    fn output_list_command_round_trips() {
        let items = [Item::Position, Item::Quaternion, Item::CrLf];
        let c = output_list_command(1, &items);
        assert_eq!(c, b"O1,2,11,1\r");
        assert_eq!(
            parse_output_list(&c[1..c.len() - 1]),
            Some((1, items.to_vec()))
        );
        assert_eq!(parse_output_list(b"9,2"), None);
    }
}
