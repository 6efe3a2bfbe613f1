//! Shared by the corruption and fuzz suites: every decoder configuration, random valid records
//! for it, and decoding into comparable values.
#![allow(dead_code)]

use glam::{DMat3, DQuat, DVec3};
use rand::Rng;

use nendo_devices::cyberglove::{self, CyberGloveDecoder, CyberGloveFraming, SensorCount};
use nendo_devices::decode::{DecodeStats, Framing, StreamDecoder};
use nendo_devices::fastrak::{self, DataFormat, FastrakDecoder, FastrakFraming, FastrakRecord};
use nendo_devices::fivedt::{
    self, Glove5Decoder, Glove5Framing, Glove5Record, Glove16Decoder, Glove16Framing, Glove16Packet,
};
use nendo_devices::flock::{
    self, BirdOrientation, FlockDecoder, FlockFraming, FlockRecord, RecordMode,
};

/// Every decoder configuration under test.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Proto {
    CyberGlove18Status,
    CyberGlove22,
    Glove5,
    Glove16,
    FastrakAscii,
    FastrakBinary,
    FastrakAsciiEuler,
    FlockPositionQuaternion,
    FlockPositionAngles,
    FlockPositionMatrix,
}

pub const ALL: [Proto; 10] = [
    Proto::CyberGlove18Status,
    Proto::CyberGlove22,
    Proto::Glove5,
    Proto::Glove16,
    Proto::FastrakAscii,
    Proto::FastrakBinary,
    Proto::FastrakAsciiEuler,
    Proto::FlockPositionQuaternion,
    Proto::FlockPositionAngles,
    Proto::FlockPositionMatrix,
];

fn cyber(p: Proto) -> CyberGloveFraming {
    match p {
        Proto::CyberGlove18Status => CyberGloveFraming {
            sensors: SensorCount::Eighteen,
            status_byte: true,
        },
        _ => CyberGloveFraming {
            sensors: SensorCount::TwentyTwo,
            status_byte: false,
        },
    }
}

fn fastrak(p: Proto) -> FastrakFraming {
    match p {
        Proto::FastrakAscii => FastrakFraming::position_quaternion(DataFormat::Ascii),
        Proto::FastrakBinary => FastrakFraming::position_quaternion(DataFormat::Binary),
        _ => FastrakFraming {
            format: DataFormat::Ascii,
            items: vec![
                fastrak::Item::Position,
                fastrak::Item::Euler,
                fastrak::Item::CrLf,
            ],
        },
    }
}

fn flock(p: Proto) -> FlockFraming {
    let mode = match p {
        Proto::FlockPositionQuaternion => RecordMode::PositionQuaternion,
        Proto::FlockPositionAngles => RecordMode::PositionAngles,
        _ => RecordMode::PositionMatrix,
    };
    FlockFraming {
        mode,
        scale_inches: flock::DEFAULT_SCALE_INCHES,
    }
}

fn unit_quaternion(rng: &mut impl Rng) -> DQuat {
    loop {
        let v = [
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0f64),
        ];
        let q = DQuat::from_array(v);
        let n = q.length();
        if n > 0.1 && n < 1.0 {
            return q / n;
        }
    }
}

fn not_lt(b: u8) -> u8 {
    if b == b'<' { b'>' } else { b }
}

/// One random valid record of the protocol, encoded.
pub fn random_record(p: Proto, rng: &mut impl Rng) -> Vec<u8> {
    let mut out = Vec::new();
    match p {
        Proto::CyberGlove18Status | Proto::CyberGlove22 => {
            let f = cyber(p);
            let values: Vec<u8> = (0..f.sensors.count())
                .map(|_| rng.gen_range(1..=255))
                .collect();
            let status = f.status_byte.then(|| rng.gen_range(0..8u8));
            let header = if rng.gen_bool(0.9) { b'S' } else { b'G' };
            cyberglove::encode_sample(header, &values, status, &mut out);
        }
        Proto::Glove5 => {
            let mut b = [0u8; 7];
            rng.fill_bytes(&mut b);
            let rec = Glove5Record {
                fingers: [b[0], b[1], b[2], b[3], b[4]],
                pitch: b[5],
                roll: b[6],
            };
            fivedt::encode_glove5(&rec, &mut out);
        }
        Proto::Glove16 => {
            if rng.gen_bool(0.1) {
                // Unchecked bytes are random, but never `<` (a packet start; see fivedt docs).
                let info = std::array::from_fn(|_| not_lt(rng.r#gen()));
                fivedt::encode_glove16(&Glove16Packet::Info(info), &mut out);
            } else {
                let values = std::array::from_fn(|_| rng.gen_range(0..=4095u16));
                fivedt::encode_glove16(
                    &Glove16Packet::Data {
                        values,
                        trailer: [not_lt(rng.r#gen()), not_lt(rng.r#gen())],
                    },
                    &mut out,
                );
            }
        }
        Proto::FastrakAscii | Proto::FastrakBinary | Proto::FastrakAsciiEuler => {
            let q = unit_quaternion(rng);
            let (az, el, roll) = q.to_euler(glam::EulerRot::ZYX);
            let rec = FastrakRecord {
                station: rng.gen_range(1..=4),
                error: if rng.gen_bool(0.95) { b' ' } else { b'E' },
                position: Some(std::array::from_fn(|_| rng.gen_range(-99.0..99.0))),
                euler: Some([az.to_degrees(), el.to_degrees(), roll.to_degrees()]),
                quaternion: Some([q.w, q.x, q.y, q.z]),
            };
            fastrak::encode_record(&fastrak(p), &rec, &mut out).unwrap();
        }
        Proto::FlockPositionQuaternion
        | Proto::FlockPositionAngles
        | Proto::FlockPositionMatrix => {
            let q = unit_quaternion(rng);
            let (z, y, x) = q.to_euler(glam::EulerRot::ZYX);
            let orientation = match p {
                Proto::FlockPositionQuaternion => BirdOrientation::Quaternion([q.w, q.x, q.y, q.z]),
                Proto::FlockPositionAngles => {
                    BirdOrientation::Angles([z.to_degrees(), y.to_degrees(), x.to_degrees()])
                }
                _ => BirdOrientation::Matrix(DMat3::from_quat(q).to_cols_array()),
            };
            let position = DVec3::new(
                rng.gen_range(-35.0..35.0),
                rng.gen_range(-35.0..35.0),
                rng.gen_range(-35.0..35.0),
            );
            let rec = FlockRecord {
                position: Some(position.to_array()),
                orientation: Some(orientation),
            };
            flock::encode_record(&flock(p), &rec, &mut out);
        }
    }
    out
}

/// What a decoder run produced: records as comparable strings, counters, bytes left pending.
#[derive(Debug, Clone, PartialEq)]
pub struct Decoded {
    pub records: Vec<String>,
    pub stats: DecodeStats,
    pub pending: usize,
}

fn run<F: Framing>(mut d: StreamDecoder<F>, bytes: &[u8], chunks: &[usize]) -> Decoded
where
    F::Record: std::fmt::Debug,
{
    let mut out = Vec::new();
    let mut at = 0;
    let mut i = 0;
    while at < bytes.len() {
        let n = chunks
            .get(i % chunks.len().max(1))
            .copied()
            .unwrap_or(bytes.len())
            .max(1);
        let end = (at + n).min(bytes.len());
        d.push(&bytes[at..end], &mut out);
        at = end;
        i += 1;
    }
    Decoded {
        records: out.iter().map(|r| format!("{r:?}")).collect(),
        stats: d.stats(),
        pending: d.pending(),
    }
}

/// Decodes `bytes` pushed in pieces whose sizes cycle through `chunks` (empty: all at once).
pub fn decode(p: Proto, bytes: &[u8], chunks: &[usize]) -> Decoded {
    match p {
        Proto::CyberGlove18Status | Proto::CyberGlove22 => {
            run(CyberGloveDecoder::new(cyber(p)), bytes, chunks)
        }
        Proto::Glove5 => run(Glove5Decoder::new(Glove5Framing), bytes, chunks),
        Proto::Glove16 => run(Glove16Decoder::new(Glove16Framing), bytes, chunks),
        Proto::FastrakAscii | Proto::FastrakBinary | Proto::FastrakAsciiEuler => {
            run(FastrakDecoder::new(fastrak(p)), bytes, chunks)
        }
        _ => run(FlockDecoder::new(flock(p)), bytes, chunks),
    }
}

/// The canonical decoded form of one clean record.
pub fn canonical(p: Proto, record: &[u8]) -> String {
    let d = decode(p, record, &[]);
    assert_eq!(
        d.records.len(),
        1,
        "{p:?}: a clean record must decode alone: {record:02x?}"
    );
    d.records[0].clone()
}

/// The accounting every decoder must keep: each byte pushed is in a record, skipped, or pending.
pub fn accounted(d: &Decoded) -> bool {
    d.stats.bytes_in == d.stats.record_bytes + d.stats.skipped_bytes + d.pending as u64
}
