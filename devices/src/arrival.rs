//! When a sample reached the host: the first link of the latency chain from a device to the
//! frame that shows it.
//!
//! Every frame of a [`HandStream`](crate::HandStream) travels with an [`Arrival`] on the
//! host's monotonic clock ([`std::time::Instant`]):
//!
//! - `read`: the moment the port read that completed the sample's bytes returned — a record
//!   split over several reads arrives with its last byte (`Glove::arrived`,
//!   `Tracker::arrived`; a backend that does not say is stamped when its `read` returns);
//! - `sent`: the moment the sample, decoded, validated and merged into a frame, was put into
//!   the stream's channel.
//!
//! `sent − read` is the **parse** stage (decode, calibration, merge, the trace's rounding).
//! Whatever reads the stream carries the stamp on (the window's device loop measures from it
//! up to the frame's GPU submission and presentation). A replayed trace has no port: its
//! frames arrive when the replay thread sends them (`read = sent`). A frame emitted for a
//! change of a source's state (no sample) is stamped when it is emitted.
//!
//! The stamp is not part of a [`HandFrame`]: a trace keeps the frames, not the host's clock,
//! and two frames compare equal whatever their arrival.

use std::time::{Duration, Instant};

use crate::HandFrame;

/// When a frame's newest sample reached the host (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Arrival {
    /// When the port read that completed the sample's bytes returned.
    pub read: Instant,
    /// When the frame was put into the stream's channel (`read ≤ sent`).
    pub sent: Instant,
}

impl Arrival {
    /// An arrival read at `read` and sent now (never before `read`).
    #[must_use]
    pub fn read_at(read: Instant) -> Self {
        let now = Instant::now();
        Arrival {
            read: read.min(now),
            sent: now,
        }
    }

    /// An arrival read and sent now (a replayed frame, a change of state).
    #[must_use]
    pub fn now() -> Self {
        let now = Instant::now();
        Arrival {
            read: now,
            sent: now,
        }
    }

    /// The parse stage: from the bytes' arrival to the frame in the channel.
    #[must_use]
    pub fn parse(&self) -> Duration {
        self.sent.saturating_duration_since(self.read)
    }
}

/// A frame and when its newest sample arrived.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StampedFrame {
    /// The frame, as a trace stores it.
    pub frame: HandFrame,
    /// When it arrived.
    pub arrival: Arrival,
}
