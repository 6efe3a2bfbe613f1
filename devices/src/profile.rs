//! Device profiles: JSON files that say which devices make up the hand input, how to reach
//! them, how to calibrate them, where the tracker sits in the world and how big the hand is.
//!
//! The format (`"format": "nendo-device-profile"`, `"version": 1`) is documented field by field
//! in `devices/README.md`; the shipped profiles are in `devices/profiles/` and built into the
//! crate ([`builtin`]).

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};
use std::path::Path;

use crate::cyberglove::SensorCount;
use crate::fastrak::{DataFormat, Units};
use crate::filter::FilterSettings;
use crate::flock::RecordMode;
use crate::{DeviceError, Joint, JointAngles, TrackerPose};

/// The format name every profile carries.
pub const PROFILE_FORMAT: &str = "nendo-device-profile";
/// The profile format version this crate reads.
pub const PROFILE_VERSION: u32 = 1;
/// Largest profile file read: 1 MB (a profile is a few kB). A larger file, or a device or pipe
/// that never ends (`/dev/zero`), is refused after reading one byte past the limit.
pub const MAX_PROFILE_BYTES: u64 = 1 << 20;

/// A device profile.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Profile {
    /// Always [`PROFILE_FORMAT`].
    pub format: String,
    /// Always [`PROFILE_VERSION`].
    pub version: u32,
    /// Short name (the file stem of a shipped profile).
    pub name: String,
    /// One line for people.
    #[serde(default)]
    pub description: String,
    /// Where the hand frames come from.
    pub input: Input,
    /// Maps tracker coordinates (metres) into the modeller's world.
    #[serde(default)]
    pub world_from_tracker: WorldFromTracker,
    /// The hand's side and dimensions.
    #[serde(default)]
    pub hand: HandSize,
    /// Watchdog period: a source that sends nothing valid for this long is declared silent and
    /// restarted.
    #[serde(default = "default_watchdog_ms")]
    pub watchdog_ms: u64,
    /// The plausibility gate and One-Euro filter on the frames ([`crate::filter`]); absent:
    /// the defaults ([`FilterSettings::default`]).
    #[serde(default)]
    pub filter: FilterSettings,
}

fn default_watchdog_ms() -> u64 {
    1000
}

/// Where hand frames come from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Input {
    /// Live devices: a glove, a tracker, or both.
    Devices {
        /// The glove, if any.
        #[serde(default)]
        glove: Option<GloveProfile>,
        /// The tracker, if any.
        #[serde(default)]
        tracker: Option<TrackerProfile>,
    },
    /// The mouse-driven hand of the window ([`crate::MouseDevice`]).
    Mouse(MouseProfile),
    /// A recorded trace played back as if live (the mock backend).
    Replay(ReplayProfile),
    /// A source of joint poses: a skeleton hand ([`crate::skeleton`]), such as the VMC
    /// receiver.
    Skeleton(SkeletonProfile),
}

/// How a USB device identifies itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UsbMatch {
    /// USB vendor id.
    pub vid: u16,
    /// USB product id; absent matches any product of the vendor.
    #[serde(default)]
    pub pid: Option<u16>,
}

impl UsbMatch {
    /// Whether a device with these ids matches.
    pub fn matches(&self, vid: u16, pid: u16) -> bool {
        self.vid == vid && self.pid.is_none_or(|p| p == pid)
    }
}

/// Calibration of one glove sensor: `angle = (raw − offset) · gain` radians (the convention of
/// VR Juggler's CyberGlove driver; docs/design.md §16.1), mapped onto a named joint.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorCalibration {
    /// The joint this sensor measures; `null` ignores the sensor.
    pub joint: Option<Joint>,
    /// Raw value at zero angle.
    pub offset: f64,
    /// Radians per raw count.
    pub gain: f64,
}

/// Applies a calibration table to raw sensor values (one entry per sensor, in sensor order).
/// Every produced angle is validated; the first bad one fails the whole sample.
pub fn calibrate(table: &[SensorCalibration], raw: &[f64]) -> Result<JointAngles, DeviceError> {
    let mut angles = JointAngles::new();
    for (cal, &r) in table.iter().zip(raw) {
        if let Some(joint) = cal.joint {
            angles.set(joint, (r - cal.offset) * cal.gain)?;
        }
    }
    Ok(angles)
}

fn default_cyber_baud() -> u32 {
    115_200
}
fn default_5dt_baud() -> u32 {
    19_200
}
fn default_tracker_baud() -> u32 {
    115_200
}

/// A glove and its link.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "protocol", deny_unknown_fields)]
pub enum GloveProfile {
    /// CyberGlove I/II/III, binary serial protocol.
    #[serde(rename = "cyberglove")]
    CyberGlove {
        /// Serial port path.
        port: String,
        /// Baud rate (default 115200).
        #[serde(default = "default_cyber_baud")]
        baud: u32,
        /// USB ids of the serial adapter, for `nendo devices`.
        #[serde(default)]
        usb: Option<UsbMatch>,
        /// 18 or 22.
        sensors: usize,
        /// Ask for the status byte (switch, glove-in) in every record.
        #[serde(default)]
        status_byte: bool,
        /// One entry per sensor, in sensor order.
        calibration: Vec<SensorCalibration>,
    },
    /// 5DT Data Glove 5, serial.
    #[serde(rename = "5dt-glove5")]
    FiveDtGlove5 {
        /// Serial port path.
        port: String,
        /// Baud rate (default 19200).
        #[serde(default = "default_5dt_baud")]
        baud: u32,
        /// USB ids of the serial adapter.
        #[serde(default)]
        usb: Option<UsbMatch>,
        /// Five entries: thumb, index, middle, ring, little (raw 0..=255).
        calibration: Vec<SensorCalibration>,
    },
    /// 5DT Data Glove 16, serial.
    #[serde(rename = "5dt-glove16")]
    FiveDtGlove16 {
        /// Serial port path.
        port: String,
        /// Baud rate (default 19200).
        #[serde(default = "default_5dt_baud")]
        baud: u32,
        /// USB ids of the serial adapter.
        #[serde(default)]
        usb: Option<UsbMatch>,
        /// Sixteen entries (raw 0..=4095).
        calibration: Vec<SensorCalibration>,
    },
    /// 5DT Data Glove Ultra over USB HID.
    #[serde(rename = "5dt-ultra-usb")]
    FiveDtUltraUsb {
        /// The glove's USB ids (vendor 0x5D70).
        usb: UsbMatch,
        /// Whether input reports start with a report-id byte.
        #[serde(default)]
        report_id: bool,
        /// Sixteen entries, one per report value (raw i16; raw/4096 is full scale).
        calibration: Vec<SensorCalibration>,
    },
}

impl GloveProfile {
    /// The serial port path, for serial gloves.
    pub fn port(&self) -> Option<&str> {
        match self {
            GloveProfile::CyberGlove { port, .. }
            | GloveProfile::FiveDtGlove5 { port, .. }
            | GloveProfile::FiveDtGlove16 { port, .. } => Some(port),
            GloveProfile::FiveDtUltraUsb { .. } => None,
        }
    }

    /// Replaces the serial port path (no effect on USB HID gloves).
    pub fn set_port(&mut self, new: &str) {
        match self {
            GloveProfile::CyberGlove { port, .. }
            | GloveProfile::FiveDtGlove5 { port, .. }
            | GloveProfile::FiveDtGlove16 { port, .. } => *port = new.to_string(),
            GloveProfile::FiveDtUltraUsb { .. } => {}
        }
    }

    /// The USB ids the device shows, if known.
    pub fn usb(&self) -> Option<UsbMatch> {
        match self {
            GloveProfile::CyberGlove { usb, .. }
            | GloveProfile::FiveDtGlove5 { usb, .. }
            | GloveProfile::FiveDtGlove16 { usb, .. } => *usb,
            GloveProfile::FiveDtUltraUsb { usb, .. } => Some(*usb),
        }
    }

    /// The calibration table.
    pub fn calibration(&self) -> &[SensorCalibration] {
        match self {
            GloveProfile::CyberGlove { calibration, .. }
            | GloveProfile::FiveDtGlove5 { calibration, .. }
            | GloveProfile::FiveDtGlove16 { calibration, .. }
            | GloveProfile::FiveDtUltraUsb { calibration, .. } => calibration,
        }
    }

    /// The calibration table, to replace (a glove calibration writes it; the sensor count
    /// must stay, see [`GloveProfile::validate`]).
    pub fn calibration_mut(&mut self) -> &mut Vec<SensorCalibration> {
        match self {
            GloveProfile::CyberGlove { calibration, .. }
            | GloveProfile::FiveDtGlove5 { calibration, .. }
            | GloveProfile::FiveDtGlove16 { calibration, .. }
            | GloveProfile::FiveDtUltraUsb { calibration, .. } => calibration,
        }
    }

    /// The protocol's name in profiles.
    pub fn protocol(&self) -> &'static str {
        match self {
            GloveProfile::CyberGlove { .. } => "cyberglove",
            GloveProfile::FiveDtGlove5 { .. } => "5dt-glove5",
            GloveProfile::FiveDtGlove16 { .. } => "5dt-glove16",
            GloveProfile::FiveDtUltraUsb { .. } => "5dt-ultra-usb",
        }
    }

    /// Number of raw sensors the glove sends.
    pub fn sensor_count(&self) -> usize {
        match self {
            GloveProfile::CyberGlove { sensors, .. } => *sensors,
            GloveProfile::FiveDtGlove5 { .. } => 5,
            GloveProfile::FiveDtGlove16 { .. } | GloveProfile::FiveDtUltraUsb { .. } => 16,
        }
    }

    /// The joints the glove reports (those named in the calibration table), in sensor order.
    pub fn joints(&self) -> Vec<Joint> {
        self.calibration().iter().filter_map(|c| c.joint).collect()
    }

    /// How errors about this glove name it when no profile name is at hand.
    pub fn describe_for_errors(&self) -> String {
        match (self.port(), self.usb()) {
            (Some(port), _) => format!("{} on {port}", self.protocol()),
            (None, Some(u)) => format!("{} (USB vendor {:04x})", self.protocol(), u.vid),
            (None, None) => self.protocol().to_string(),
        }
    }

    /// Checks the sensor count against the calibration table, finite calibration, joints
    /// mapped once, the baud rate; `name` labels errors.
    pub fn validate(&self, name: &str) -> Result<(), DeviceError> {
        let bad = |message: String| DeviceError::Profile {
            name: name.to_string(),
            message,
        };
        if let GloveProfile::CyberGlove { sensors, .. } = self
            && SensorCount::from_count(*sensors).is_none()
        {
            return Err(bad(format!(
                "a CyberGlove has 18 or 22 sensors, not {sensors}"
            )));
        }
        let table = self.calibration();
        if table.len() != self.sensor_count() {
            return Err(bad(format!(
                "the {} glove has {} sensors but the calibration table has {} entries",
                self.protocol(),
                self.sensor_count(),
                table.len()
            )));
        }
        let mut seen = 0u32;
        for (i, c) in table.iter().enumerate() {
            if !(c.offset.is_finite() && c.gain.is_finite()) {
                return Err(bad(format!("calibration entry {i} is not finite")));
            }
            if let Some(j) = c.joint {
                if seen & (1 << j.index()) != 0 {
                    return Err(bad(format!("joint {j} is mapped twice")));
                }
                seen |= 1 << j.index();
            }
        }
        if let Some(b) = self.baud()
            && b == 0
        {
            return Err(bad("baud rate 0".into()));
        }
        Ok(())
    }

    fn baud(&self) -> Option<u32> {
        match self {
            GloveProfile::CyberGlove { baud, .. }
            | GloveProfile::FiveDtGlove5 { baud, .. }
            | GloveProfile::FiveDtGlove16 { baud, .. } => Some(*baud),
            GloveProfile::FiveDtUltraUsb { .. } => None,
        }
    }
}

/// Fastrak record format in a profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FastrakFormat {
    /// ASCII records.
    Ascii,
    /// Binary records.
    Binary,
}

impl From<FastrakFormat> for DataFormat {
    fn from(f: FastrakFormat) -> DataFormat {
        match f {
            FastrakFormat::Ascii => DataFormat::Ascii,
            FastrakFormat::Binary => DataFormat::Binary,
        }
    }
}

/// Fastrak position units in a profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FastrakUnits {
    /// Inches.
    Inches,
    /// Centimetres.
    Centimetres,
}

impl From<FastrakUnits> for Units {
    fn from(u: FastrakUnits) -> Units {
        match u {
            FastrakUnits::Inches => Units::Inches,
            FastrakUnits::Centimetres => Units::Centimetres,
        }
    }
}

/// Which orientation a Fastrak sends.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FastrakOrientation {
    /// Quaternion (item 11).
    Quaternion,
    /// Azimuth, elevation, roll (item 4).
    Euler,
}

/// Flock of Birds record mode in a profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FlockRecordMode {
    /// `Y`: position and angles.
    PositionAngles,
    /// `Z`: position and matrix.
    PositionMatrix,
    /// `]`: position and quaternion.
    PositionQuaternion,
}

impl From<FlockRecordMode> for RecordMode {
    fn from(m: FlockRecordMode) -> RecordMode {
        match m {
            FlockRecordMode::PositionAngles => RecordMode::PositionAngles,
            FlockRecordMode::PositionMatrix => RecordMode::PositionMatrix,
            FlockRecordMode::PositionQuaternion => RecordMode::PositionQuaternion,
        }
    }
}

fn default_station() -> u8 {
    1
}
fn default_flock_scale() -> f64 {
    crate::flock::DEFAULT_SCALE_INCHES
}
fn default_flock_mode() -> FlockRecordMode {
    FlockRecordMode::PositionQuaternion
}

/// A tracker and its link.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "protocol", deny_unknown_fields)]
pub enum TrackerProfile {
    /// Polhemus Fastrak.
    #[serde(rename = "fastrak")]
    Fastrak {
        /// Serial port path.
        port: String,
        /// Baud rate (default 115200).
        #[serde(default = "default_tracker_baud")]
        baud: u32,
        /// USB ids of the serial adapter.
        #[serde(default)]
        usb: Option<UsbMatch>,
        /// The station the hand sensor is on (1–4).
        #[serde(default = "default_station")]
        station: u8,
        /// ASCII or binary records.
        format: FastrakFormat,
        /// Position units the tracker is set to.
        units: FastrakUnits,
        /// Quaternion or Euler angles.
        orientation: FastrakOrientation,
    },
    /// Ascension Flock of Birds (one bird).
    #[serde(rename = "flock")]
    Flock {
        /// Serial port path.
        port: String,
        /// Baud rate (default 115200; must match the unit's DIP switches).
        #[serde(default = "default_tracker_baud")]
        baud: u32,
        /// USB ids of the serial adapter.
        #[serde(default)]
        usb: Option<UsbMatch>,
        /// Record mode (default position + quaternion).
        #[serde(default = "default_flock_mode")]
        record: FlockRecordMode,
        /// Position scale S in inches: 36, or 72 or 144 for the extended ranges
        /// ([`crate::flock::SCALES_INCHES`]), as set on the unit; any other value is refused.
        #[serde(default = "default_flock_scale")]
        scale_inches: f64,
        /// Conjugate the bird's orientation (the sources disagree on its handedness).
        #[serde(default)]
        conjugate: bool,
    },
}

impl TrackerProfile {
    /// The serial port path.
    pub fn port(&self) -> &str {
        match self {
            TrackerProfile::Fastrak { port, .. } | TrackerProfile::Flock { port, .. } => port,
        }
    }

    /// Replaces the serial port path.
    pub fn set_port(&mut self, new: &str) {
        match self {
            TrackerProfile::Fastrak { port, .. } | TrackerProfile::Flock { port, .. } => {
                *port = new.to_string()
            }
        }
    }

    /// The USB ids of the serial adapter, if known.
    pub fn usb(&self) -> Option<UsbMatch> {
        match self {
            TrackerProfile::Fastrak { usb, .. } | TrackerProfile::Flock { usb, .. } => *usb,
        }
    }

    /// The protocol's name in profiles.
    pub fn protocol(&self) -> &'static str {
        match self {
            TrackerProfile::Fastrak { .. } => "fastrak",
            TrackerProfile::Flock { .. } => "flock",
        }
    }

    /// Checks the station, the baud rate and the Flock's scale; `name` labels errors.
    pub fn validate(&self, name: &str) -> Result<(), DeviceError> {
        let bad = |message: String| DeviceError::Profile {
            name: name.to_string(),
            message,
        };
        match self {
            TrackerProfile::Fastrak { station, baud, .. } => {
                if !(1..=4).contains(station) {
                    return Err(bad(format!("Fastrak station {station} (1–4)")));
                }
                if *baud == 0 {
                    return Err(bad("baud rate 0".into()));
                }
            }
            TrackerProfile::Flock {
                scale_inches, baud, ..
            } => {
                if !crate::flock::SCALES_INCHES.contains(scale_inches) {
                    return Err(bad(format!(
                        "Flock scale_inches {scale_inches}: the bird's position scale is 36, or 72 or 144 in the extended ranges"
                    )));
                }
                if *baud == 0 {
                    return Err(bad("baud rate 0".into()));
                }
            }
        }
        Ok(())
    }
}

fn default_mouse_depth() -> f64 {
    0.5
}
fn default_mouse_depth_range() -> [f64; 2] {
    [0.05, 5.0]
}
fn default_wheel_step() -> f64 {
    0.02
}
fn default_curl() -> f64 {
    1.2
}

/// The mouse-driven hand.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MouseProfile {
    /// Starting distance of the hand along the view ray, world units.
    #[serde(default = "default_mouse_depth")]
    pub depth: f64,
    /// Nearest and farthest depth the wheel can reach.
    #[serde(default = "default_mouse_depth_range")]
    pub depth_range: [f64; 2],
    /// Depth change per wheel step.
    #[serde(default = "default_wheel_step")]
    pub wheel_step: f64,
    /// Flexion (radians) of the curled fingers of the pointing pose.
    #[serde(default = "default_curl")]
    pub curl: f64,
}

impl Default for MouseProfile {
    fn default() -> Self {
        MouseProfile {
            depth: default_mouse_depth(),
            depth_range: default_mouse_depth_range(),
            wheel_step: default_wheel_step(),
            curl: default_curl(),
        }
    }
}

/// Slowest replay speed a profile may ask for (a thousandth of real time).
pub const MIN_REPLAY_SPEED: f64 = 1e-3;
/// Fastest replay speed a profile may ask for.
pub const MAX_REPLAY_SPEED: f64 = 1e3;

fn default_speed() -> f64 {
    1.0
}

/// A recorded trace played back as a device.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReplayProfile {
    /// The trace file (relative paths are relative to the profile file).
    pub trace: String,
    /// Playback speed (1 = as recorded).
    #[serde(default = "default_speed")]
    pub speed: f64,
    /// Start again at the end.
    #[serde(default)]
    pub repeat: bool,
}

impl Profile {
    /// Parses and validates a profile from JSON text; `name` labels errors.
    ///
    /// Unknown and repeated members are refused; a syntax or member error names the member's
    /// path (`input.glove.calibration[3]`), line and column; a text starting with a UTF-8
    /// byte-order mark is refused as such.
    pub fn from_json(text: &str, name: &str) -> Result<Profile, DeviceError> {
        let bad = |message: String| DeviceError::Profile {
            name: name.to_string(),
            message,
        };
        if text.starts_with('\u{feff}') {
            return Err(bad(
                "the file starts with a UTF-8 byte-order mark (BOM); save it without one".into(),
            ));
        }
        let mut de = serde_json::Deserializer::from_str(text);
        let p: Profile = serde_path_to_error::deserialize(&mut de)
            .map_err(|e| {
                let path = e.path().to_string();
                // Member names in JSON's double quotes, as nendo's other documents name them.
                let inner = e.into_inner().to_string().replace('`', "\"");
                if path == "." {
                    inner
                } else {
                    format!("{path}: {inner}")
                }
            })
            .and_then(|p| de.end().map(|()| p).map_err(|e| e.to_string()))
            .map_err(bad)?;
        p.validate(name)?;
        Ok(p)
    }

    /// Reads and validates a profile file. A relative replay trace path is resolved against
    /// the profile's directory.
    pub fn load(path: &Path) -> Result<Profile, DeviceError> {
        let text = nendo_file::read_text_limited(path, MAX_PROFILE_BYTES, "device profile")
            .map_err(|e| match e {
                nendo_file::ReadError::Io { path, error } => DeviceError::File { path, error },
                other => DeviceError::InvalidValue(other.to_string()),
            })?;
        let mut p = Profile::from_json(&text, &path.display().to_string())?;
        if let Input::Replay(r) = &mut p.input
            && Path::new(&r.trace).is_relative()
            && let Some(dir) = path.parent()
        {
            r.trace = dir.join(&r.trace).display().to_string();
        }
        Ok(p)
    }

    /// The profile as pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Validates the profile and writes it to `path` as pretty JSON, atomically (the one safe
    /// writer, `nendo_file`): a failed write leaves any earlier file as it was.
    ///
    /// # Errors
    /// [`DeviceError::Profile`] for a profile that does not validate, [`DeviceError::File`]
    /// when the file cannot be written.
    pub fn save(&self, path: &Path) -> Result<(), DeviceError> {
        self.validate(&path.display().to_string())?;
        let mut text = self.to_json();
        text.push('\n');
        nendo_file::write_bytes(path, text.as_bytes()).map_err(|e| DeviceError::File {
            path: path.to_path_buf(),
            error: e.into_io(),
        })
    }

    /// The glove, to change (its port, its calibration).
    pub fn glove_mut(&mut self) -> Option<&mut GloveProfile> {
        match &mut self.input {
            Input::Devices { glove, .. } => glove.as_mut(),
            _ => None,
        }
    }

    /// The tracker, to change (its port).
    pub fn tracker_mut(&mut self) -> Option<&mut TrackerProfile> {
        match &mut self.input {
            Input::Devices { tracker, .. } => tracker.as_mut(),
            _ => None,
        }
    }

    /// Checks everything serde cannot: format and version, sensor counts against calibration
    /// tables, ranges.
    pub fn validate(&self, name: &str) -> Result<(), DeviceError> {
        let bad = |message: String| DeviceError::Profile {
            name: name.to_string(),
            message,
        };
        if self.format != PROFILE_FORMAT {
            return Err(bad(format!(
                "format is `{}`, expected `{PROFILE_FORMAT}`",
                self.format
            )));
        }
        if self.version != PROFILE_VERSION {
            return Err(bad(format!(
                "version {} (this nendo reads version {PROFILE_VERSION})",
                self.version
            )));
        }
        if self.watchdog_ms == 0 {
            return Err(bad("watchdog_ms must be positive".into()));
        }
        self.filter.validate().map_err(|e| bad(e.to_string()))?;
        self.world_from_tracker
            .validate()
            .map_err(|e| bad(e.to_string()))?;
        self.hand.validate().map_err(|e| bad(e.to_string()))?;
        match &self.input {
            Input::Devices { glove, tracker } => {
                if glove.is_none() && tracker.is_none() {
                    return Err(bad(
                        "`devices` input names neither a glove nor a tracker".into()
                    ));
                }
                if let Some(g) = glove {
                    g.validate(name)?;
                }
                if let Some(t) = tracker {
                    t.validate(name)?;
                }
            }
            Input::Mouse(m) => {
                let [lo, hi] = m.depth_range;
                let ok = [m.depth, lo, hi, m.wheel_step, m.curl]
                    .iter()
                    .all(|x| x.is_finite())
                    && 0.0 < lo
                    && lo <= m.depth
                    && m.depth <= hi
                    && m.curl.abs() <= crate::ANGLE_LIMIT_RAD;
                if !ok {
                    return Err(bad("mouse depth must satisfy 0 < near ≤ depth ≤ far".into()));
                }
            }
            Input::Skeleton(s) => s.validate(name)?,
            Input::Replay(r) => {
                if !(MIN_REPLAY_SPEED..=MAX_REPLAY_SPEED).contains(&r.speed) {
                    return Err(bad(format!(
                        "replay speed {} (expected {MIN_REPLAY_SPEED} to {MAX_REPLAY_SPEED})",
                        r.speed
                    )));
                }
            }
        }
        Ok(())
    }

    /// The glove, if the profile has live devices with a glove.
    pub fn glove(&self) -> Option<&GloveProfile> {
        match &self.input {
            Input::Devices { glove, .. } => glove.as_ref(),
            _ => None,
        }
    }

    /// The tracker, if the profile has live devices with a tracker.
    pub fn tracker(&self) -> Option<&TrackerProfile> {
        match &self.input {
            Input::Devices { tracker, .. } => tracker.as_ref(),
            _ => None,
        }
    }
}

/// The shipped profiles, as (file stem, JSON text).
const BUILTIN: [(&str, &str); 9] = [
    (
        "cyberglove2-18",
        include_str!("../profiles/cyberglove2-18.json"),
    ),
    (
        "cyberglove2-22",
        include_str!("../profiles/cyberglove2-22.json"),
    ),
    (
        "5dt-glove5-serial",
        include_str!("../profiles/5dt-glove5-serial.json"),
    ),
    (
        "5dt-ultra14-usb",
        include_str!("../profiles/5dt-ultra14-usb.json"),
    ),
    ("fastrak", include_str!("../profiles/fastrak.json")),
    ("flock", include_str!("../profiles/flock.json")),
    (
        "cyberglove2-18-fastrak",
        include_str!("../profiles/cyberglove2-18-fastrak.json"),
    ),
    ("mouse", include_str!("../profiles/mouse.json")),
    ("vmc", include_str!("../profiles/vmc.json")),
];

/// The profiles shipped in `devices/profiles/`, parsed. A shipped profile that failed to parse
/// would be a build defect; the crate's tests parse every one.
pub fn builtin() -> Vec<Profile> {
    BUILTIN
        .iter()
        .filter_map(|(name, text)| Profile::from_json(text, name).ok())
        .collect()
}

/// Whether `name` is a shipped profile's name.
pub fn is_builtin(name: &str) -> bool {
    BUILTIN.iter().any(|(n, _)| *n == name)
}

/// A profile by shipped name (`cyberglove2-18`) or by path to a JSON file.
pub fn resolve(name_or_path: &str) -> Result<Profile, DeviceError> {
    if let Some((name, text)) = BUILTIN.iter().find(|(n, _)| *n == name_or_path) {
        return Profile::from_json(text, name);
    }
    let path = Path::new(name_or_path);
    if path.exists() {
        return Profile::load(path);
    }
    let names: Vec<&str> = BUILTIN.iter().map(|(n, _)| *n).collect();
    Err(DeviceError::Profile {
        name: name_or_path.to_string(),
        message: format!(
            "no such file, and not a shipped profile ({})",
            names.join(", ")
        ),
    })
}

mod hand;
pub use hand::{FingerLengths, HandSize, Side, WorldFromTracker};
mod skeleton;
pub use skeleton::SkeletonProfile;

#[cfg(test)]
mod tests;
