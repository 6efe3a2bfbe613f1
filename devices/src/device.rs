//! The device traits and the serial and USB backends behind them.
//!
//! A [`Glove`] produces calibrated [`GloveSample`]s, a [`Tracker`] validated [`TrackerPose`]s.
//! Both have the same life cycle, driven by [`HandStream`](crate::HandStream): `start` opens the
//! link, does the protocol's handshake and leaves the device streaming; `read` waits a bounded
//! time and decodes what arrived; `stop` stops streaming (best effort) and closes the link. A
//! device may be started again after `stop` — that is how the stream reconnects.
//!
//! [`open_glove`] and [`open_tracker`] build the backend a profile names.

use std::time::{Duration, Instant};

use crate::cyberglove::{
    self, CyberGloveDecoder, CyberGloveFraming, CyberRecord, GloveFault, SensorCount,
};
use crate::decode::{DecodeStats, Framing, StreamDecoder};
use crate::fastrak::{self, FastrakDecoder, FastrakFraming, Item, Units};
use crate::fivedt::{
    self, Glove5Decoder, Glove5Framing, Glove16Decoder, Glove16Framing, Glove16Packet,
};
use crate::flock::{self, FlockDecoder, FlockFraming};
use crate::profile::{
    FastrakOrientation, GloveProfile, SensorCalibration, Side, TrackerProfile, calibrate,
};
use crate::serial::SerialLink;
use crate::{DeviceError, GloveSample, Joint, TrackerPose};

/// How long a device may take to answer a handshake command.
pub const ANSWER_TIMEOUT: Duration = Duration::from_millis(300);

/// How many times a handshake is tried before the device is declared absent: a missing or
/// garbled answer to any step (a timeout, an unexpected answer) re-syncs the line and resends
/// the whole handshake, after [`HANDSHAKE_BACKOFF`] doubling at each attempt. A port that
/// cannot be opened or hangs up is not retried here (the stream reopens it every
/// [`StreamOptions::retry`](crate::StreamOptions::retry)).
pub const HANDSHAKE_ATTEMPTS: u32 = 4;

/// The pause before the second handshake attempt; it doubles for each later one (50, 100,
/// 200 ms: a device given up on has had about 2 s to answer).
pub const HANDSHAKE_BACKOFF: Duration = Duration::from_millis(50);

/// Counters of a device beyond its decoder's.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DeviceStats {
    /// The protocol decoder's counters (summed over restarts).
    pub decode: DecodeStats,
    /// Records that decoded but whose values were rejected (NaN, out of range).
    pub invalid: u64,
    /// Faults the device reported in place of a sample.
    pub faults: u64,
    /// Records that were well formed but not for us (another tracker station, glove info
    /// packets).
    pub ignored: u64,
    /// Successful starts (1 + reconnections).
    pub starts: u64,
    /// Handshake attempts that failed with a missing or garbled answer and were retried (or,
    /// the last one, given up on).
    pub handshake_retries: u64,
}

/// A data glove: joint angles per named joint.
pub trait Glove: Send {
    /// What and where the device is, for messages.
    fn describe(&self) -> String;
    /// The joints its samples carry.
    fn joints(&self) -> Vec<Joint>;
    /// Opens the link, does the handshake and starts streaming.
    fn start(&mut self) -> Result<(), DeviceError>;
    /// Waits at most `timeout` for data and appends the samples decoded from it.
    fn read(&mut self, timeout: Duration, out: &mut Vec<GloveSample>) -> Result<(), DeviceError>;
    /// Stops streaming (best effort) and closes the link.
    fn stop(&mut self);
    /// Counters.
    fn stats(&self) -> DeviceStats;
    /// When the bytes of the samples the last [`read`](Self::read) appended arrived: the
    /// moment the port read that completed them returned (see [`crate::arrival`]). `None`:
    /// the backend does not say, and the stream stamps the moment `read` returned.
    fn arrived(&self) -> Option<Instant> {
        None
    }
    /// Mismatches between the device found at the last start and its profile that were
    /// worked around (for people: printed by `nendo record`, shown by the window).
    fn warnings(&self) -> Vec<String> {
        Vec::new()
    }
}

/// A 6-DoF hand tracker.
pub trait Tracker: Send {
    /// What and where the device is, for messages.
    fn describe(&self) -> String;
    /// Opens the link, does the handshake and starts streaming.
    fn start(&mut self) -> Result<(), DeviceError>;
    /// Waits at most `timeout` for data and appends the poses decoded from it.
    fn read(&mut self, timeout: Duration, out: &mut Vec<TrackerPose>) -> Result<(), DeviceError>;
    /// Stops streaming (best effort) and closes the link.
    fn stop(&mut self);
    /// Counters.
    fn stats(&self) -> DeviceStats;
    /// When the bytes of the samples the last [`read`](Self::read) appended arrived: the
    /// moment the port read that completed them returned (see [`crate::arrival`]). `None`:
    /// the backend does not say, and the stream stamps the moment `read` returned.
    fn arrived(&self) -> Option<Instant> {
        None
    }
}

/// A serial protocol: handshake, stop, and turning records into samples.
trait SerialProtocol: Send {
    type Framing: Framing<Record: Send> + Send;
    type Sample;
    fn label(&self) -> String;
    /// The handshake after opening; must leave the device streaming.
    fn start(
        &mut self,
        link: &mut SerialLink,
        decoder: &mut StreamDecoder<Self::Framing>,
    ) -> Result<(), DeviceError>;
    /// Stop streaming, best effort.
    fn stop(&mut self, link: &mut SerialLink);
    /// Converts a record; `Ok(None)` for a record that is not for us.
    fn convert(
        &self,
        record: <Self::Framing as Framing>::Record,
        stats: &mut DeviceStats,
    ) -> Result<Option<Self::Sample>, DeviceError>;
}

/// A serial device: a port, a protocol and its decoder.
struct SerialDevice<P: SerialProtocol> {
    port: String,
    baud: u32,
    link: Option<SerialLink>,
    protocol: P,
    decoder: StreamDecoder<P::Framing>,
    stats: DeviceStats,
    records: Vec<<P::Framing as Framing>::Record>,
    /// When the last read that returned bytes returned.
    arrived: Option<Instant>,
}

impl<P: SerialProtocol> SerialDevice<P> {
    fn new(port: &str, baud: u32, protocol: P, framing: P::Framing) -> Self {
        SerialDevice {
            port: port.to_string(),
            baud,
            link: None,
            protocol,
            decoder: StreamDecoder::new(framing),
            stats: DeviceStats::default(),
            records: Vec::new(),
            arrived: None,
        }
    }

    /// Opens the port and does the handshake, retrying it on a missing or garbled answer (see
    /// [`HANDSHAKE_ATTEMPTS`]): before each new attempt the line is re-synced (what is in
    /// flight is drained, the decoder forgets its bytes) and the whole handshake is resent,
    /// since every protocol's handshake begins by stopping the device.
    fn start_link(&mut self) -> Result<(), DeviceError> {
        self.link = None;
        let mut link = SerialLink::open(&self.port, self.baud)?;
        let mut backoff = HANDSHAKE_BACKOFF;
        let mut attempt = 1;
        loop {
            self.decoder.clear();
            match self.protocol.start(&mut link, &mut self.decoder) {
                Ok(()) => break,
                Err(e) if retryable(&e) => {
                    self.stats.handshake_retries += 1;
                    if attempt >= HANDSHAKE_ATTEMPTS {
                        return Err(e);
                    }
                    attempt += 1;
                    std::thread::sleep(backoff);
                    backoff *= 2;
                    link.drain(Duration::from_millis(20), ANSWER_TIMEOUT)?;
                }
                Err(e) => return Err(e),
            }
        }
        self.decoder.clear();
        self.link = Some(link);
        self.stats.starts += 1;
        Ok(())
    }

    fn read_samples(
        &mut self,
        timeout: Duration,
        out: &mut Vec<P::Sample>,
    ) -> Result<(), DeviceError> {
        let Some(link) = self.link.as_mut() else {
            return Err(DeviceError::Io {
                device: self.port.clone(),
                error: std::io::Error::new(std::io::ErrorKind::NotConnected, "not started"),
            });
        };
        let mut buf = [0u8; 1024];
        let n = link.read_some(&mut buf, timeout)?;
        if n > 0 {
            // The bytes that complete a record arrive now: its samples' arrival.
            self.arrived = Some(Instant::now());
        }
        self.records.clear();
        self.decoder.push(&buf[..n], &mut self.records);
        let mut failure = None;
        for record in self.records.drain(..) {
            match self.protocol.convert(record, &mut self.stats) {
                Ok(Some(s)) => out.push(s),
                Ok(None) => {}
                Err(e) if e.is_disconnect() || matches!(e, DeviceError::BadAnswer { .. }) => {
                    failure = Some(e)
                }
                Err(_) => self.stats.invalid += 1,
            }
        }
        failure.map_or(Ok(()), Err)
    }

    fn stop_link(&mut self) {
        if let Some(mut link) = self.link.take() {
            self.protocol.stop(&mut link);
        }
    }

    fn device_stats(&self) -> DeviceStats {
        DeviceStats {
            decode: self.decoder.stats(),
            ..self.stats
        }
    }
}

impl<P: SerialProtocol<Sample = GloveSample>> Glove for SerialDevice<P>
where
    P: GloveJoints,
{
    fn describe(&self) -> String {
        format!("{} on {}", self.protocol.label(), self.port)
    }
    fn joints(&self) -> Vec<Joint> {
        self.protocol.joints()
    }
    fn start(&mut self) -> Result<(), DeviceError> {
        self.start_link()
    }
    fn read(&mut self, timeout: Duration, out: &mut Vec<GloveSample>) -> Result<(), DeviceError> {
        self.read_samples(timeout, out)
    }
    fn stop(&mut self) {
        self.stop_link()
    }
    fn stats(&self) -> DeviceStats {
        self.device_stats()
    }
    fn arrived(&self) -> Option<Instant> {
        self.arrived
    }
}

impl<P: SerialProtocol<Sample = TrackerPose>> Tracker for SerialDevice<P> {
    fn describe(&self) -> String {
        format!("{} on {}", self.protocol.label(), self.port)
    }
    fn start(&mut self) -> Result<(), DeviceError> {
        self.start_link()
    }
    fn read(&mut self, timeout: Duration, out: &mut Vec<TrackerPose>) -> Result<(), DeviceError> {
        self.read_samples(timeout, out)
    }
    fn stop(&mut self) {
        self.stop_link()
    }
    fn stats(&self) -> DeviceStats {
        self.device_stats()
    }
    fn arrived(&self) -> Option<Instant> {
        self.arrived
    }
}

/// Whether a handshake failure is worth another attempt: the device did not answer in time or
/// answered something else (a garbled answer). A port that is gone, or a glove out of its
/// interface unit, is not.
fn retryable(e: &DeviceError) -> bool {
    matches!(
        e,
        DeviceError::Timeout { .. } | DeviceError::BadAnswer { .. }
    )
}

/// The joints a glove protocol reports.
trait GloveJoints {
    fn joints(&self) -> Vec<Joint>;
}

fn joints_of(table: &[SensorCalibration]) -> Vec<Joint> {
    table.iter().filter_map(|c| c.joint).collect()
}

// ---------------------------------------------------------------------------------------------
// CyberGlove

struct CyberGloveProtocol {
    /// The port, for messages.
    device: String,
    framing: CyberGloveFraming,
    calibration: Vec<SensorCalibration>,
}

impl CyberGloveProtocol {
    fn unplugged(&self) -> DeviceError {
        DeviceError::Unplugged {
            device: format!("CyberGlove on {}", self.device),
            detail: "the glove is unplugged from its interface unit".into(),
        }
    }

    /// Whether a sample's status byte (when records carry one) says the glove is plugged in.
    fn glove_in(status: Option<u8>) -> bool {
        status.is_none_or(|s| s & cyberglove::STATUS_GLOVE_IN != 0)
    }
}

impl GloveJoints for CyberGloveProtocol {
    fn joints(&self) -> Vec<Joint> {
        joints_of(&self.calibration)
    }
}

impl SerialProtocol for CyberGloveProtocol {
    type Framing = CyberGloveFraming;
    type Sample = GloveSample;

    fn label(&self) -> String {
        format!("CyberGlove ({} sensors)", self.framing.sensors.count())
    }

    fn start(
        &mut self,
        link: &mut SerialLink,
        decoder: &mut CyberGloveDecoder,
    ) -> Result<(), DeviceError> {
        link.send(&[cyberglove::STOP])?;
        link.drain(Duration::from_millis(30), ANSWER_TIMEOUT)?;
        link.send(&[cyberglove::SET_STATUS, u8::from(self.framing.status_byte)])?;
        link.expect(
            &[cyberglove::SET_STATUS, 0],
            ANSWER_TIMEOUT,
            "U (status byte)",
        )?;
        link.send(&[cyberglove::POLL])?;
        let record = link.await_record(decoder, ANSWER_TIMEOUT, "G (poll)", |r| match r {
            CyberRecord::Sample { header, .. } | CyberRecord::Fault { header, .. } => {
                *header == cyberglove::POLL
            }
        })?;
        match record {
            // The interface unit answers, but its glove is out: the device is not there yet,
            // and the stream keeps retrying as for any disconnected device.
            CyberRecord::Fault {
                fault: GloveFault::GloveUnplugged,
                ..
            } => return Err(self.unplugged()),
            CyberRecord::Sample { status, .. } if !Self::glove_in(status) => {
                return Err(self.unplugged());
            }
            CyberRecord::Fault { fault, .. } => {
                return Err(DeviceError::BadAnswer {
                    device: link.name().to_string(),
                    command: "G (poll)".into(),
                    detail: format!("the glove reports {fault:?}"),
                });
            }
            CyberRecord::Sample { .. } => {}
        }
        link.send(&[cyberglove::STREAM])
    }

    fn stop(&mut self, link: &mut SerialLink) {
        let _ = link.send(&[cyberglove::STOP]);
    }

    fn convert(
        &self,
        record: CyberRecord,
        stats: &mut DeviceStats,
    ) -> Result<Option<GloveSample>, DeviceError> {
        match record {
            CyberRecord::Sample { status, .. } if !Self::glove_in(status) => {
                // The status byte's glove-in bit is clear: the sensor values mean nothing.
                stats.faults += 1;
                Err(self.unplugged())
            }
            CyberRecord::Sample { status, .. } => {
                let raw: Vec<f64> = record.values().iter().map(|&v| f64::from(v)).collect();
                let angles = calibrate(&self.calibration, &raw)?;
                Ok(Some(GloveSample {
                    angles,
                    switch: status.map(|s| s & cyberglove::STATUS_SWITCH != 0),
                }))
            }
            CyberRecord::Fault { fault, .. } => {
                stats.faults += 1;
                match fault {
                    GloveFault::SampleError => Ok(None),
                    GloveFault::GloveUnplugged => Err(self.unplugged()),
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 5DT serial gloves

struct Glove5Protocol {
    calibration: Vec<SensorCalibration>,
}

impl GloveJoints for Glove5Protocol {
    fn joints(&self) -> Vec<Joint> {
        joints_of(&self.calibration)
    }
}

impl SerialProtocol for Glove5Protocol {
    type Framing = Glove5Framing;
    type Sample = GloveSample;

    fn label(&self) -> String {
        "5DT Data Glove 5".into()
    }

    fn start(&mut self, link: &mut SerialLink, _: &mut Glove5Decoder) -> Result<(), DeviceError> {
        // A glove still streaming (a restart, a host that died) would bury the answers below in
        // records: ask for one record, which ends streaming, and discard what comes.
        link.send(&[fivedt::GLOVE5_ONE])?;
        link.drain(Duration::from_millis(30), ANSWER_TIMEOUT)?;
        link.send(&[fivedt::GLOVE5_INIT])?;
        link.expect(
            &[fivedt::GLOVE5_INIT_ANSWER],
            ANSWER_TIMEOUT,
            "A (initialise)",
        )?;
        link.send(&[fivedt::GLOVE5_INFO])?;
        link.read_exact(fivedt::GLOVE5_INFO_LEN, ANSWER_TIMEOUT, "G (information)")?;
        link.send(&[fivedt::GLOVE5_STREAM])
    }

    fn stop(&mut self, link: &mut SerialLink) {
        // `C` asks for one record and ends streaming mode (the glove then sends only what it
        // is asked for); the record it answers is discarded by the next start.
        let _ = link.send(&[fivedt::GLOVE5_ONE]);
    }

    fn convert(
        &self,
        r: fivedt::Glove5Record,
        _: &mut DeviceStats,
    ) -> Result<Option<GloveSample>, DeviceError> {
        let raw = r.fingers.map(f64::from);
        Ok(Some(GloveSample {
            angles: calibrate(&self.calibration, &raw)?,
            switch: None,
        }))
    }
}

struct Glove16Protocol {
    calibration: Vec<SensorCalibration>,
}

impl GloveJoints for Glove16Protocol {
    fn joints(&self) -> Vec<Joint> {
        joints_of(&self.calibration)
    }
}

impl SerialProtocol for Glove16Protocol {
    type Framing = Glove16Framing;
    type Sample = GloveSample;

    fn label(&self) -> String {
        "5DT Data Glove 16".into()
    }

    fn start(
        &mut self,
        link: &mut SerialLink,
        decoder: &mut Glove16Decoder,
    ) -> Result<(), DeviceError> {
        // The glove streams by itself: wait for one data packet.
        link.await_record(decoder, ANSWER_TIMEOUT, "(stream)", |p| {
            matches!(p, Glove16Packet::Data { .. })
        })?;
        Ok(())
    }

    fn stop(&mut self, _: &mut SerialLink) {}

    fn convert(
        &self,
        p: Glove16Packet,
        stats: &mut DeviceStats,
    ) -> Result<Option<GloveSample>, DeviceError> {
        match p {
            Glove16Packet::Data { values, .. } => {
                let raw = values.map(f64::from);
                Ok(Some(GloveSample {
                    angles: calibrate(&self.calibration, &raw)?,
                    switch: None,
                }))
            }
            Glove16Packet::Info(_) => {
                stats.ignored += 1;
                Ok(None)
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Fastrak

struct FastrakProtocol {
    station: u8,
    units: Units,
    framing: FastrakFraming,
}

impl SerialProtocol for FastrakProtocol {
    type Framing = FastrakFraming;
    type Sample = TrackerPose;

    fn label(&self) -> String {
        format!("Fastrak station {}", self.station)
    }

    fn start(
        &mut self,
        link: &mut SerialLink,
        decoder: &mut FastrakDecoder,
    ) -> Result<(), DeviceError> {
        link.send(&[fastrak::POLLED])?;
        link.drain(Duration::from_millis(30), ANSWER_TIMEOUT)?;
        let units = match self.units {
            Units::Inches => fastrak::INCHES,
            Units::Centimetres => fastrak::CENTIMETRES,
        };
        let format = match self.framing.format {
            fastrak::DataFormat::Ascii => fastrak::ASCII,
            fastrak::DataFormat::Binary => fastrak::BINARY,
        };
        link.send(&[units, format])?;
        link.send(&fastrak::output_list_command(
            self.station,
            &self.framing.items,
        ))?;
        link.send(&[fastrak::POINT])?;
        let station = self.station;
        link.await_record(decoder, ANSWER_TIMEOUT, "P (one record)", |r| {
            r.station == station
        })?;
        link.send(&[fastrak::CONTINUOUS])
    }

    fn stop(&mut self, link: &mut SerialLink) {
        let _ = link.send(&[fastrak::POLLED]);
    }

    fn convert(
        &self,
        r: fastrak::FastrakRecord,
        stats: &mut DeviceStats,
    ) -> Result<Option<TrackerPose>, DeviceError> {
        if r.station != self.station {
            stats.ignored += 1;
            return Ok(None);
        }
        if r.error != fastrak::NO_ERROR {
            // The tracker flags this record (a letter in the error byte): its values are not
            // to be trusted. Counted as a fault and dropped.
            stats.faults += 1;
            return Ok(None);
        }
        // Beyond the tracker's measuring range (with a margin): a corrupt value (a flipped
        // exponent bit of a binary field), dropped and counted as invalid.
        if let Some(p) = r.position {
            let limit = fastrak::POSITION_LIMIT_M / self.units.metres();
            if p.iter().any(|x| !x.is_finite() || x.abs() > limit) {
                return Err(DeviceError::InvalidValue(format!(
                    "Fastrak position {p:?} beyond the measuring range (±{limit:.1} {})",
                    self.units.name()
                )));
            }
        }
        r.pose(self.units).map(Some)
    }
}

// ---------------------------------------------------------------------------------------------
// Flock of Birds

struct FlockProtocol {
    framing: FlockFraming,
    conjugate: bool,
}

impl SerialProtocol for FlockProtocol {
    type Framing = FlockFraming;
    type Sample = TrackerPose;

    fn label(&self) -> String {
        "Flock of Birds".into()
    }

    fn start(
        &mut self,
        link: &mut SerialLink,
        decoder: &mut FlockDecoder,
    ) -> Result<(), DeviceError> {
        link.send(&[flock::STOP])?;
        link.drain(Duration::from_millis(30), ANSWER_TIMEOUT)?;
        link.send(&[self.framing.mode.command(), flock::POINT])?;
        link.await_record(decoder, ANSWER_TIMEOUT, "B (point)", |_| true)?;
        link.send(&[flock::STREAM])
    }

    fn stop(&mut self, link: &mut SerialLink) {
        let _ = link.send(&[flock::STOP]);
    }

    fn convert(
        &self,
        r: flock::FlockRecord,
        _: &mut DeviceStats,
    ) -> Result<Option<TrackerPose>, DeviceError> {
        // The scale is the bird's measuring range (positions cannot exceed it as encoded; a
        // record built otherwise is refused all the same).
        let scale = self.framing.scale_inches;
        if let Some(p) = r.position
            && p.iter().any(|x| !x.is_finite() || x.abs() > scale)
        {
            return Err(DeviceError::InvalidValue(format!(
                "bird position {p:?} in beyond its scale ±{scale} in"
            )));
        }
        r.pose(self.conjugate).map(Some)
    }
}

// ---------------------------------------------------------------------------------------------
// ---------------------------------------------------------------------------------------------
// Construction from profiles

/// The glove backend a profile names (not yet started), without a hand to check the glove
/// against (see [`open_glove_for_hand`]).
pub fn open_glove(profile: &GloveProfile) -> Result<Box<dyn Glove>, DeviceError> {
    open_glove_for_hand(profile, None)
}

/// The glove backend a profile names (not yet started). A glove that says which hand it is
/// made for (the 5DT Ultra's product id) is checked against `hand`, the profile's hand; a
/// mismatch is reported in [`Glove::warnings`]. The glove profile is validated first.
pub fn open_glove_for_hand(
    profile: &GloveProfile,
    hand: Option<Side>,
) -> Result<Box<dyn Glove>, DeviceError> {
    profile.validate(&profile.describe_for_errors())?;
    Ok(match profile {
        GloveProfile::CyberGlove {
            port,
            baud,
            sensors,
            status_byte,
            calibration,
            ..
        } => {
            let sensors =
                SensorCount::from_count(*sensors).ok_or_else(|| DeviceError::Profile {
                    name: port.clone(),
                    message: format!("a CyberGlove has 18 or 22 sensors, not {sensors}"),
                })?;
            let framing = CyberGloveFraming {
                sensors,
                status_byte: *status_byte,
            };
            let protocol = CyberGloveProtocol {
                device: port.clone(),
                framing,
                calibration: calibration.clone(),
            };
            Box::new(SerialDevice::new(port, *baud, protocol, framing))
        }
        GloveProfile::FiveDtGlove5 {
            port,
            baud,
            calibration,
            ..
        } => Box::new(SerialDevice::new(
            port,
            *baud,
            Glove5Protocol {
                calibration: calibration.clone(),
            },
            Glove5Framing,
        )),
        GloveProfile::FiveDtGlove16 {
            port,
            baud,
            calibration,
            ..
        } => Box::new(SerialDevice::new(
            port,
            *baud,
            Glove16Protocol {
                calibration: calibration.clone(),
            },
            Glove16Framing,
        )),
        GloveProfile::FiveDtUltraUsb {
            usb,
            report_id,
            calibration,
        } => Box::new(UltraUsbGlove::new(
            *usb,
            *report_id,
            calibration.clone(),
            hand,
        )),
    })
}

/// The tracker backend a profile names (not yet started). The tracker profile is validated
/// first (station, baud rate, the Flock's scale).
pub fn open_tracker(profile: &TrackerProfile) -> Result<Box<dyn Tracker>, DeviceError> {
    profile.validate(&format!("{} on {}", profile.protocol(), profile.port()))?;
    Ok(match profile {
        TrackerProfile::Fastrak {
            port,
            baud,
            station,
            format,
            units,
            orientation,
            ..
        } => {
            let orientation_item = match orientation {
                FastrakOrientation::Quaternion => Item::Quaternion,
                FastrakOrientation::Euler => Item::Euler,
            };
            let framing = FastrakFraming {
                format: (*format).into(),
                items: vec![Item::Position, orientation_item, Item::CrLf],
            };
            let protocol = FastrakProtocol {
                station: *station,
                units: (*units).into(),
                framing: framing.clone(),
            };
            Box::new(SerialDevice::new(port, *baud, protocol, framing))
        }
        TrackerProfile::Flock {
            port,
            baud,
            record,
            scale_inches,
            conjugate,
            ..
        } => {
            let framing = FlockFraming {
                mode: (*record).into(),
                scale_inches: *scale_inches,
            };
            Box::new(SerialDevice::new(
                port,
                *baud,
                FlockProtocol {
                    framing,
                    conjugate: *conjugate,
                },
                framing,
            ))
        }
    })
}

mod ultra_usb;
pub use ultra_usb::UltraUsbGlove;

#[cfg(test)]
mod tests;
