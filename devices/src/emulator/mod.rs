//! Byte-exact emulators of the serial devices, for tests and demonstrations without hardware
//! (`nendo emulate` runs one in the foreground; see the README).
//!
//! A [`DeviceModel`] is the device's behaviour as bytes: it answers the commands the host
//! sends and, while streaming, produces a record every period, using the protocol modules'
//! encoders. [`PtyEmulator`] runs a model on a pseudo-terminal: the host side opens the pty's
//! path with the real `serialport` crate, exactly as it would open `/dev/ttyUSB0`. The emulator
//! can go silent, be unplugged and plugged back in (a new pty behind the same path), and inject
//! garbage, so the stream's watchdog and reconnection are tested against real I/O.
//!
//! The models' motion is deterministic in the record index `k`, and each model exposes its
//! ground truth (`values_at`, `pose_at`) so tests can check decoded frames exactly; a
//! [`Script`] replaces it with a motion of the caller's (a scripted hand gesture). The pty can
//! also garble the answer to a handshake command ([`PtyEmulator::garble_answer_to`]) and
//! corrupt streamed records at random ([`PtyEmulator::corrupt_randomly`]).
//!
//! Only serial devices are emulated: the 5DT Ultra on USB HID would need a virtual HID device
//! (`/dev/uhid`, root), which this crate does not create.

mod models;
#[cfg(unix)]
mod pty;

pub use models::{
    CyberGloveModel, FastrakModel, FlockModel, Glove5Model, Glove16Model, GlovePlug, Script,
};
#[cfg(unix)]
pub use pty::PtyEmulator;

use std::time::Duration;

/// A device's behaviour on the wire.
pub trait DeviceModel: Send {
    /// The device's name, for messages.
    fn name(&self) -> &'static str;
    /// Handles bytes from the host (commands may arrive split across calls) and appends the
    /// device's answers to `reply`.
    fn receive(&mut self, bytes: &[u8], reply: &mut Vec<u8>);
    /// Whether the device is streaming records.
    fn streaming(&self) -> bool;
    /// Time between streamed records.
    fn period(&self) -> Duration;
    /// Appends the next streamed record.
    fn next_record(&mut self, out: &mut Vec<u8>);
}
