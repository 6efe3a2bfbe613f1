//! The one error type of the device layer.

use std::path::PathBuf;

/// Everything that can go wrong in the device layer: opening and talking to devices, reading
/// profiles and traces, and values that fail validation. No device error ever panics; the
/// stream reports errors as a source state and keeps running.
///
/// Every message is complete on its own: it already carries the text of the underlying error
/// (the OS's, the serial layer's), because the stream and the window show errors with
/// `to_string`. So no variant also exposes that error as its `source()`: a chain printer
/// (anyhow's `{:#}`) would repeat it.
#[derive(Debug, thiserror::Error)]
pub enum DeviceError {
    /// A serial port could not be opened (absent, busy, or no permission).
    #[error("cannot open serial port {port}: {error}")]
    Open {
        /// The port path as given (for example `/dev/ttyUSB0`).
        port: String,
        /// What the serial-port layer said (part of the message, not a `source()`).
        error: serialport::Error,
    },
    /// Reading from or writing to an open device failed (unplugged, hung up).
    #[error("I/O error on {device}: {error}")]
    Io {
        /// The port path or device name.
        device: String,
        /// The underlying error (part of the message, not a `source()`).
        error: std::io::Error,
    },
    /// The device did not answer a command within the time allowed.
    #[error("{device} did not answer {command} within {millis} ms")]
    Timeout {
        /// The port path or device name.
        device: String,
        /// The command that went unanswered, in readable form.
        command: String,
        /// How long we waited.
        millis: u64,
    },
    /// The device answered, but not what the protocol says it should.
    #[error("{device} answered {command} unexpectedly: {detail}")]
    BadAnswer {
        /// The port path or device name.
        device: String,
        /// The command, in readable form.
        command: String,
        /// What was wrong with the answer.
        detail: String,
    },
    /// The device itself reports that the sensor is not connected (a CyberGlove's interface
    /// unit saying its glove is unplugged): the link is fine, but there is nothing to read
    /// until the glove is plugged back in.
    #[error("{device}: {detail}")]
    Unplugged {
        /// The port path or device name.
        device: String,
        /// What the device reported.
        detail: String,
    },
    /// The USB HID layer failed (no permission, device gone, no HID support).
    #[error("HID error: {0}")]
    Hid(String),
    /// A device profile is malformed or inconsistent.
    #[error("profile {name}: {message}")]
    Profile {
        /// The profile's file path or name.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// A trace file is malformed; `line` is 1-based.
    #[error("trace line {line}: {message}")]
    TraceSyntax {
        /// 1-based line number of the offending line.
        line: usize,
        /// What is wrong with it.
        message: String,
    },
    /// A file could not be read or written.
    #[error("{}: {error}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// The underlying error (part of the message, not a `source()`).
        error: std::io::Error,
    },
    /// A recording stopped because its file could not be written (a full disk, an I/O
    /// error): the file keeps the frames recorded before, as an interrupted trace that a
    /// recovering read ([`crate::Trace::read_recovering`]) reads.
    #[error(
        "{}: {error}: the recording stopped; the file keeps the {frames} frames recorded before (an interrupted trace, which replay reads)",
        path.display()
    )]
    RecordingStopped {
        /// The trace file.
        path: PathBuf,
        /// The frames the file keeps.
        frames: u64,
        /// The file system's error (part of the message, not a `source()`).
        error: std::io::Error,
    },
    /// A value is not a finite number or lies outside its physical range; it is never passed on.
    #[error("invalid value: {0}")]
    InvalidValue(String),
    /// The request cannot be served by this kind of input (for example opening a device stream
    /// from the mouse profile, whose hand is driven by the window).
    #[error("unsupported: {0}")]
    Unsupported(String),
}

impl DeviceError {
    /// Whether the error means the device is gone (closed, hung up, unplugged) rather than
    /// merely slow or misbehaving.
    pub fn is_disconnect(&self) -> bool {
        matches!(
            self,
            DeviceError::Open { .. }
                | DeviceError::Io { .. }
                | DeviceError::Unplugged { .. }
                | DeviceError::Hid(_)
        )
    }
}
