#![forbid(unsafe_code)]
//! # nendo-devices: glove and tracker input for nendo
//!
//! Produces timestamped [`HandFrame`]s — tracker pose, glove joint angles, buttons, source
//! states — from real devices, a recorded trace, or the mouse. It knows nothing of geometry:
//! the application's hand model turns frames into a virtual hand and contact with the surface.
//!
//! ## Parts
//!
//! | module | what it is |
//! |---|---|
//! | [`arrival`] | [`Arrival`]: when a sample reached the host (the port read that completed it), carried beside each frame as a [`StampedFrame`] |
//! | [`frame`] | the frame types and their units: [`HandFrame`], [`TrackerPose`], [`JointAngles`], [`Joint`] |
//! | [`decode`] | the incremental, resynchronising byte-stream decoder shared by every protocol |
//! | [`cyberglove`], [`fivedt`], [`fastrak`], [`flock`] | one module per protocol: record formats, commands, framing, encoders |
//! | [`serial`] | the serial transport (`serialport`) |
//! | [`device`] | the [`Glove`] and [`Tracker`] traits and their serial and USB HID backends |
//! | [`filter`] | [`FrameFilter`]: the plausibility gate and One-Euro filter on tracker pose and glove joints, its [`FilterSettings`] (a profile's `filter`) |
//! | [`stream`] | [`HandStream`]: glove + tracker merged on background threads, watchdog, reconnection |
//! | [`skeleton`] | [`Skeleton`]: a hand as the 26 joint poses of OpenXR, the [`SkeletonSource`] trait, the joints made where a source lacks them |
//! | [`vmc`] | the VMC protocol (OSC over UDP): [`vmc::VmcReceiver`], the humanoid hierarchy composed, Unity's frame converted |
//! | [`mouse`] | [`MouseDevice`]: a hand driven by the mouse's view ray |
//! | [`trace`] | the recorded-trace text format, its reader (recovering interrupted recordings), atomic writer and recorder |
//! | [`profile`] | device profiles (JSON): ports, calibration, tracker-to-world transform, hand size |
//! | [`alignment`] | recenter and scale the tracker-to-world transform, fit the hand to the model |
//! | [`glove_calibration`] | a glove's offsets and gains from a flat hand, a fist and the thumb out |
//! | [`discover`] | serial ports and HID devices present, and which profile fits each |
//! | [`emulator`] | byte-exact device emulators on pseudo-terminals, for tests and demonstrations |
//! | [`throughput`] | decode throughput per protocol (the `nendo bench input` table) |
//!
//! ## Opening a stream
//!
//! ```no_run
//! use nendo_devices::{HandStream, StreamOptions, profile};
//! # fn main() -> Result<(), nendo_devices::DeviceError> {
//! let profile = profile::resolve("cyberglove2-18-fastrak")?;
//! let stream = HandStream::open(&profile, &StreamOptions::default())?;
//! for frame in stream.drain() {
//!     if let Some(pose) = frame.pose {
//!         let (position, orientation) = profile.world_from_tracker.apply(&pose);
//!         # let _ = (position, orientation);
//!     }
//! }
//! # Ok(()) }
//! ```
//!
//! Protocol facts come from `docs/design.md` §16; each protocol module documents every field of
//! the records it reads, in its own words.
#![warn(missing_docs)]

pub mod alignment;
pub mod arrival;
pub mod cyberglove;
pub mod decode;
pub mod device;
pub mod discover;
pub mod emulator;
mod error;
pub mod fastrak;
pub mod filter;
pub mod fivedt;
pub mod flock;
pub mod frame;
pub mod glove_calibration;
pub mod mouse;
pub mod profile;
pub mod serial;
pub mod skeleton;
pub mod stream;
pub mod throughput;
pub mod trace;
pub mod vmc;

pub use arrival::{Arrival, StampedFrame};
pub use decode::DecodeStats;
pub use device::{DeviceStats, Glove, Tracker, open_glove, open_glove_for_hand, open_tracker};
pub use error::DeviceError;
pub use filter::{FilterSettings, FilterStats, FrameFilter};
pub use frame::{
    ANGLE_LIMIT_RAD, FrameStatus, GloveSample, HandFrame, Joint, JointAngles, POSITION_LIMIT_M,
    SourceState, Timestamp, TrackerPose, buttons,
};
pub use mouse::{MouseDevice, ViewRay};
pub use profile::{HandSize, Profile, WorldFromTracker};
pub use skeleton::{HandJoint, JointPose, JointSource, Skeleton, SkeletonSource};
pub use stream::{DeviceRole, DeviceStatus, HandStream, StreamOptions, StreamStats};
pub use throughput::{ThroughputRow, VmcThroughput, decode_throughput, vmc_throughput};
pub use trace::{
    Recovered, SceneText, Trace, TraceHeader, TraceRecorder, TraceStream, TraceWriter,
};
