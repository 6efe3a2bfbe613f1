//! The device models: CyberGlove, 5DT Data Glove 5 and 16, Fastrak, Flock of Birds.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use glam::{DQuat, DVec3, EulerRot};

use super::DeviceModel;
use crate::TrackerPose;
use crate::cyberglove::{self, SensorCount};
use crate::fastrak::{self, DataFormat, FastrakFraming, FastrakRecord, Item, Units};
use crate::fivedt::{self, Glove5Record, Glove16Packet};
use crate::flock::{self, BirdOrientation, FlockFraming, FlockRecord, RecordMode};

/// A scripted motion: the value of record `k` (a pose for a tracker, raw sensor values for a
/// glove). Models given one ([`FastrakModel::with_path`], [`CyberGloveModel::with_values`], …)
/// move through it instead of their test motion, so a person without hardware can watch a
/// hand move (`nendo emulate`).
#[derive(Clone)]
pub struct Script<T>(Arc<dyn Fn(u64) -> T + Send + Sync>);

impl<T> Script<T> {
    /// A script from a function of the record index.
    pub fn new(f: impl Fn(u64) -> T + Send + Sync + 'static) -> Self {
        Script(Arc::new(f))
    }

    /// The value of record `k`.
    pub fn at(&self, k: u64) -> T {
        (self.0)(k)
    }
}

impl<T> std::fmt::Debug for Script<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Script")
    }
}

/// Whether a CyberGlove is plugged into its interface unit. A handle shared with a model
/// running on a [`PtyEmulator`](super::PtyEmulator), so a test can pull the glove out of the
/// unit (the serial line stays up) and plug it back in.
#[derive(Debug, Clone)]
pub struct GlovePlug(Arc<AtomicBool>);

impl GlovePlug {
    /// Plugs the glove in (`true`) or pulls it out (`false`).
    pub fn set_plugged(&self, plugged: bool) {
        self.0.store(plugged, Ordering::Relaxed);
    }

    /// Whether the glove is plugged in.
    pub fn is_plugged(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// A CyberGlove: answers `G`, streams on `S`, stops on ^C, sets the status byte with `U`.
/// Power-on state: not streaming, no status byte, glove plugged in. While the glove is out of
/// its interface unit ([`CyberGloveModel::glove_plug`]), every record — the answer to a poll and
/// each streamed one — is the `e g` (glove unplugged) error record.
#[derive(Debug, Clone)]
pub struct CyberGloveModel {
    sensors: SensorCount,
    status_byte: bool,
    streaming: bool,
    awaiting_status_argument: bool,
    k: u64,
    period: Duration,
    plug: GlovePlug,
    script: Option<Script<Vec<u8>>>,
    switch: Option<Script<bool>>,
}

impl CyberGloveModel {
    /// A glove with this many sensors, streaming at 100 Hz when asked.
    pub fn new(sensors: SensorCount) -> Self {
        CyberGloveModel {
            sensors,
            status_byte: false,
            streaming: false,
            awaiting_status_argument: false,
            k: 0,
            period: Duration::from_millis(10),
            plug: GlovePlug(Arc::new(AtomicBool::new(true))),
            script: None,
            switch: None,
        }
    }

    /// The same glove moving through `script`: the raw sensor values of record `k` in sensor
    /// order (missing values read 128; 0, which would corrupt the record, reads 1).
    pub fn with_values(mut self, script: Script<Vec<u8>>) -> Self {
        self.script = Some(script);
        self
    }

    /// The same glove with its switch pressed when `script` says so (in the status byte, when
    /// the host asks for one).
    pub fn with_switch(mut self, script: Script<bool>) -> Self {
        self.switch = Some(script);
        self
    }

    /// The handle that plugs the glove into its interface unit and pulls it out.
    pub fn glove_plug(&self) -> GlovePlug {
        self.plug.clone()
    }

    /// The raw sensor values of record `k`: sensor `i` is `1 + (k + 7i) mod 255`, so sensor 0
    /// gives `k` away and no value is ever 0.
    pub fn values_at(sensors: SensorCount, k: u64) -> Vec<u8> {
        (0..sensors.count() as u64)
            .map(|i| 1 + ((k + 7 * i) % 255) as u8)
            .collect()
    }

    /// The status byte of record `k`: glove in, switch pressed during every other 50 records.
    pub fn status_at(k: u64) -> u8 {
        cyberglove::STATUS_GLOVE_IN
            | if (k / 50) % 2 == 1 {
                cyberglove::STATUS_SWITCH
            } else {
                0
            }
    }

    fn record(&mut self, header: u8, out: &mut Vec<u8>) {
        if !self.plug.is_plugged() {
            cyberglove::encode_fault(header, cyberglove::GloveFault::GloveUnplugged, out);
            return;
        }
        let values = match &self.script {
            Some(script) => {
                let mut v = script.at(self.k);
                v.resize(self.sensors.count(), 128);
                v.iter_mut().for_each(|x| *x = (*x).max(1));
                v
            }
            None => Self::values_at(self.sensors, self.k),
        };
        let status = self.status_byte.then(|| match &self.switch {
            Some(switch) if switch.at(self.k) => {
                cyberglove::STATUS_GLOVE_IN | cyberglove::STATUS_SWITCH
            }
            Some(_) => cyberglove::STATUS_GLOVE_IN,
            None => Self::status_at(self.k),
        });
        cyberglove::encode_sample(header, &values, status, out);
        self.k += 1;
    }
}

impl DeviceModel for CyberGloveModel {
    fn name(&self) -> &'static str {
        "CyberGlove"
    }

    fn receive(&mut self, bytes: &[u8], reply: &mut Vec<u8>) {
        for &b in bytes {
            if self.awaiting_status_argument {
                self.awaiting_status_argument = false;
                self.status_byte = b != 0;
                reply.extend_from_slice(&[cyberglove::SET_STATUS, 0]);
                continue;
            }
            match b {
                cyberglove::STOP => self.streaming = false,
                cyberglove::POLL => self.record(cyberglove::POLL, reply),
                cyberglove::STREAM => self.streaming = true,
                cyberglove::SET_STATUS => self.awaiting_status_argument = true,
                _ => {}
            }
        }
    }

    fn streaming(&self) -> bool {
        self.streaming
    }

    fn period(&self) -> Duration {
        self.period
    }

    fn next_record(&mut self, out: &mut Vec<u8>) {
        self.record(cyberglove::STREAM, out);
    }
}

/// A 5DT Data Glove 5: `A` → 0x55, `G` → 32-byte information, `C` one record (and stop),
/// `D` stream.
#[derive(Debug, Clone, Default)]
pub struct Glove5Model {
    streaming: bool,
    k: u64,
    script: Option<Script<[u8; 5]>>,
}

impl Glove5Model {
    /// A right-hand glove, streaming at 100 Hz when asked.
    pub fn new() -> Self {
        Glove5Model::default()
    }

    /// Record `k`: thumb flexure is `k mod 256`, the others follow at offsets of 50.
    pub fn record_at(k: u64) -> Glove5Record {
        Glove5Record {
            fingers: std::array::from_fn(|i| ((k + 50 * i as u64) % 256) as u8),
            pitch: (k % 200) as u8,
            roll: 90,
        }
    }

    /// The same glove moving through `script`: the five finger bytes of record `k`, thumb
    /// to little finger (pitch and roll level).
    pub fn with_values(mut self, script: Script<[u8; 5]>) -> Self {
        self.script = Some(script);
        self
    }

    fn record(&mut self, out: &mut Vec<u8>) {
        let record = match &self.script {
            Some(script) => Glove5Record {
                fingers: script.at(self.k),
                pitch: 128,
                roll: 128,
            },
            None => Self::record_at(self.k),
        };
        fivedt::encode_glove5(&record, out);
        self.k += 1;
    }
}

impl DeviceModel for Glove5Model {
    fn name(&self) -> &'static str {
        "5DT Data Glove 5"
    }

    fn receive(&mut self, bytes: &[u8], reply: &mut Vec<u8>) {
        for &b in bytes {
            match b {
                fivedt::GLOVE5_INIT => reply.push(fivedt::GLOVE5_INIT_ANSWER),
                fivedt::GLOVE5_INFO => {
                    let mut info = [0u8; fivedt::GLOVE5_INFO_LEN];
                    info[4] = 0x01; // right hand
                    reply.extend_from_slice(&info);
                }
                fivedt::GLOVE5_ONE => {
                    self.streaming = false;
                    self.record(reply);
                }
                fivedt::GLOVE5_STREAM => self.streaming = true,
                _ => {}
            }
        }
    }

    fn streaming(&self) -> bool {
        self.streaming
    }

    fn period(&self) -> Duration {
        Duration::from_millis(10)
    }

    fn next_record(&mut self, out: &mut Vec<u8>) {
        self.record(out);
    }
}

/// A 5DT Data Glove 16: streams by itself, an information packet after every 20 data packets.
#[derive(Debug, Clone, Default)]
pub struct Glove16Model {
    k: u64,
    since_info: u32,
}

impl Glove16Model {
    /// A glove streaming at 100 Hz.
    pub fn new() -> Self {
        Glove16Model::default()
    }

    /// The values of data packet `k`: value `i` is `(k + 100 i) mod 4096`.
    pub fn values_at(k: u64) -> [u16; 16] {
        std::array::from_fn(|i| ((k + 100 * i as u64) % 4096) as u16)
    }
}

impl DeviceModel for Glove16Model {
    fn name(&self) -> &'static str {
        "5DT Data Glove 16"
    }

    fn receive(&mut self, _: &[u8], _: &mut Vec<u8>) {}

    fn streaming(&self) -> bool {
        true
    }

    fn period(&self) -> Duration {
        Duration::from_millis(10)
    }

    fn next_record(&mut self, out: &mut Vec<u8>) {
        if self.since_info == 20 {
            self.since_info = 0;
            fivedt::encode_glove16(&Glove16Packet::Info([1, 0, 1, 1, 0]), out);
        }
        let values = Self::values_at(self.k);
        fivedt::encode_glove16(
            &Glove16Packet::Data {
                values,
                trailer: [0, 0],
            },
            out,
        );
        self.k += 1;
        self.since_info += 1;
    }
}

/// A smooth hand path, shared by the tracker models: a slow loop 20–40 cm from the source with
/// the hand turning about a tilted axis. Position in metres.
fn path_at(k: u64) -> TrackerPose {
    let t = k as f64 * 0.01;
    let position = DVec3::new(
        0.3 + 0.1 * t.sin(),
        0.05 * (1.3 * t).cos(),
        -0.2 + 0.05 * (0.7 * t).sin(),
    );
    let axis = DVec3::new(0.3, 1.0, 0.2).normalize();
    let orientation = DQuat::from_axis_angle(axis, 0.8 * (0.5 * t).sin());
    TrackerPose {
        position,
        orientation,
    }
}

/// A Fastrak: `c`/`C` polled/continuous, `P` one record, `F`/`f` ASCII/binary, `U`/`u`
/// inches/centimetres, `O<station>,<items>` CR output list. Power-on state: continuous ASCII in
/// inches with the default output list (position, angles, CR LF) on station 1.
#[derive(Debug, Clone)]
pub struct FastrakModel {
    format: DataFormat,
    units: Units,
    items: Vec<Item>,
    station: u8,
    continuous: bool,
    command: Option<Vec<u8>>,
    k: u64,
    flag_every: Option<u64>,
    script: Option<Script<TrackerPose>>,
}

impl Default for FastrakModel {
    fn default() -> Self {
        Self::new()
    }
}

impl FastrakModel {
    /// A tracker with one sensor on `station` 1, at 120 Hz.
    pub fn new() -> Self {
        FastrakModel {
            format: DataFormat::Ascii,
            units: Units::Inches,
            items: vec![Item::Position, Item::Euler, Item::CrLf],
            station: 1,
            continuous: true,
            command: None,
            k: 0,
            flag_every: None,
            script: None,
        }
    }

    /// The same tracker moving through `script` (poses in metres in the tracker's frame;
    /// positions are kept within the ASCII field, ±999.99 units).
    pub fn with_path(mut self, script: Script<TrackerPose>) -> Self {
        self.script = Some(script);
        self
    }

    /// The same tracker powered on in another record format (the host may change it).
    pub fn with_format(mut self, format: DataFormat) -> Self {
        self.format = format;
        self
    }

    /// The same tracker, flagging every `n`-th record (those with `k mod n = n − 1`) with the
    /// letter [`FastrakModel::FLAG`] in its error byte.
    pub fn flagging_every(mut self, n: u64) -> Self {
        self.flag_every = Some(n.max(1));
        self
    }

    /// The error byte of a flagged record.
    pub const FLAG: u8 = b'E';

    /// Whether record `k` is flagged by a tracker made with [`FastrakModel::flagging_every`]`(n)`.
    pub fn is_flagged(n: u64, k: u64) -> bool {
        k % n.max(1) == n.max(1) - 1
    }

    /// The true pose of record `k`, metres.
    pub fn pose_at(k: u64) -> TrackerPose {
        path_at(k)
    }

    /// The output list in force.
    pub fn items(&self) -> &[Item] {
        &self.items
    }

    fn record(&mut self, out: &mut Vec<u8>) {
        let pose = match &self.script {
            Some(script) => script.at(self.k),
            None => Self::pose_at(self.k),
        };
        let p =
            (pose.position / self.units.metres()).clamp(DVec3::splat(-999.0), DVec3::splat(999.0));
        let q = pose.orientation;
        let (az, el, roll) = q.to_euler(EulerRot::ZYX);
        let flagged = self.flag_every.is_some_and(|n| Self::is_flagged(n, self.k));
        let record = FastrakRecord {
            station: self.station,
            error: if flagged {
                Self::FLAG
            } else {
                fastrak::NO_ERROR
            },
            position: Some(p.to_array()),
            euler: Some([az.to_degrees(), el.to_degrees(), roll.to_degrees()]),
            quaternion: Some([q.w, q.x, q.y, q.z]),
        };
        let framing = FastrakFraming {
            format: self.format,
            items: self.items.clone(),
        };
        // The path stays well inside the ASCII field widths, so this cannot fail.
        let _ = fastrak::encode_record(&framing, &record, out);
        self.k += 1;
    }
}

impl DeviceModel for FastrakModel {
    fn name(&self) -> &'static str {
        "Fastrak"
    }

    fn receive(&mut self, bytes: &[u8], reply: &mut Vec<u8>) {
        for &b in bytes {
            if let Some(cmd) = &mut self.command {
                if b == b'\r' {
                    if let Some((station, items)) = fastrak::parse_output_list(cmd)
                        && station == self.station
                    {
                        self.items = items;
                    }
                    self.command = None;
                } else if cmd.len() < 64 {
                    cmd.push(b);
                }
                continue;
            }
            match b {
                fastrak::POLLED => self.continuous = false,
                fastrak::CONTINUOUS => self.continuous = true,
                fastrak::POINT => self.record(reply),
                fastrak::ASCII => self.format = DataFormat::Ascii,
                fastrak::BINARY => self.format = DataFormat::Binary,
                fastrak::INCHES => self.units = Units::Inches,
                fastrak::CENTIMETRES => self.units = Units::Centimetres,
                b'O' => self.command = Some(Vec::new()),
                _ => {}
            }
        }
    }

    fn streaming(&self) -> bool {
        self.continuous
    }

    fn period(&self) -> Duration {
        Duration::from_micros(8333)
    }

    fn next_record(&mut self, out: &mut Vec<u8>) {
        self.record(out);
    }
}

/// A Flock of Birds (one bird): record-mode bytes, `B` point, `@` stream, `?` stop. Power-on
/// state: position + angles, not streaming, 36-inch scale.
#[derive(Debug, Clone)]
pub struct FlockModel {
    framing: FlockFraming,
    streaming: bool,
    k: u64,
    script: Option<Script<TrackerPose>>,
}

impl Default for FlockModel {
    fn default() -> Self {
        Self::new()
    }
}

impl FlockModel {
    /// A bird at 100 Hz.
    pub fn new() -> Self {
        FlockModel {
            framing: FlockFraming {
                mode: RecordMode::PositionAngles,
                scale_inches: flock::DEFAULT_SCALE_INCHES,
            },
            streaming: false,
            k: 0,
            script: None,
        }
    }

    /// The same bird moving through `script` (poses in metres in the transmitter's frame;
    /// positions are kept within the scale).
    pub fn with_path(mut self, script: Script<TrackerPose>) -> Self {
        self.script = Some(script);
        self
    }

    /// The same bird with another position scale, inches (36, 72 or 144).
    pub fn with_scale(mut self, inches: f64) -> Self {
        self.framing.scale_inches = inches;
        self
    }

    /// The true pose of record `k`, metres.
    pub fn pose_at(k: u64) -> TrackerPose {
        path_at(k)
    }

    /// The record mode in force.
    pub fn mode(&self) -> RecordMode {
        self.framing.mode
    }

    fn record(&mut self, out: &mut Vec<u8>) {
        let pose = match &self.script {
            Some(script) => script.at(self.k),
            None => Self::pose_at(self.k),
        };
        let q = pose.orientation;
        let (z, y, x) = q.to_euler(EulerRot::ZYX);
        let orientation = match self.framing.mode {
            RecordMode::Position => None,
            RecordMode::Angles | RecordMode::PositionAngles => Some(BirdOrientation::Angles([
                z.to_degrees(),
                y.to_degrees(),
                x.to_degrees(),
            ])),
            RecordMode::Matrix | RecordMode::PositionMatrix => Some(BirdOrientation::Matrix(
                glam::DMat3::from_quat(q).to_cols_array(),
            )),
            RecordMode::Quaternion | RecordMode::PositionQuaternion => {
                Some(BirdOrientation::Quaternion([q.w, q.x, q.y, q.z]))
            }
        };
        let record = FlockRecord {
            position: Some({
                // Within the scale, one step short of the word's end (32767/32768).
                let s = self.framing.scale_inches * 0.999;
                (pose.position / 0.0254)
                    .clamp(DVec3::splat(-s), DVec3::splat(s))
                    .to_array()
            }),
            orientation,
        };
        flock::encode_record(&self.framing, &record, out);
        self.k += 1;
    }
}

impl DeviceModel for FlockModel {
    fn name(&self) -> &'static str {
        "Flock of Birds"
    }

    fn receive(&mut self, bytes: &[u8], reply: &mut Vec<u8>) {
        for &b in bytes {
            if let Some(mode) = RecordMode::from_command(b) {
                self.framing.mode = mode;
                continue;
            }
            match b {
                flock::POINT => self.record(reply),
                flock::STREAM => self.streaming = true,
                flock::STOP => self.streaming = false,
                _ => {}
            }
        }
    }

    fn streaming(&self) -> bool {
        self.streaming
    }

    fn period(&self) -> Duration {
        Duration::from_millis(10)
    }

    fn next_record(&mut self, out: &mut Vec<u8>) {
        self.record(out);
    }
}
