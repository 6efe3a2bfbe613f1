//! What a stream's devices are doing, as a status panel shows it: the role of each device and its counters.

#[allow(unused_imports)] // The parent's imports, as the code had them there.
use super::*;

/// Which device of a stream.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DeviceRole {
    /// The data glove.
    Glove,
    /// The hand tracker.
    Tracker,
}

impl DeviceRole {
    pub(super) fn index(self) -> usize {
        match self {
            DeviceRole::Glove => 0,
            DeviceRole::Tracker => 1,
        }
    }

    /// `glove` or `tracker`, for people.
    pub const fn name(self) -> &'static str {
        match self {
            DeviceRole::Glove => "glove",
            DeviceRole::Tracker => "tracker",
        }
    }
}

/// One device of a stream as a status panel shows it ([`HandStream::status`]).
#[derive(Debug, Clone, PartialEq)]
pub struct DeviceStatus {
    /// Glove or tracker.
    pub role: DeviceRole,
    /// What and where the device is (`Fastrak station 1 on /dev/ttyS0`; for a replay, the
    /// trace).
    pub description: String,
    /// The source's state now: `Ok` while samples arrive, `Silent` after the watchdog tripped
    /// (the handshake is being resent), `Disconnected` while the port is absent or lost (being
    /// reopened), `Absent` for a source a replayed trace does not have.
    pub state: SourceState,
    /// Samples per second over the last half second or so (0 when none came for a second).
    pub rate_hz: f64,
    /// The device's last error, `None` once it has started again and delivers samples.
    pub last_error: Option<String>,
    /// Samples delivered.
    pub samples: u64,
    /// Faults the device reported in place of a sample ([`DeviceStats::faults`]).
    pub faults: u64,
    /// Records dropped: misframed or failing a check in the decoder, plus well-formed records
    /// whose values were out of range ([`DecodeStats::rejected`](crate::DecodeStats) +
    /// [`DeviceStats::invalid`]).
    pub rejected: u64,
    /// Times the watchdog declared the device silent and restarted it.
    pub watchdog_trips: u64,
    /// Times the device was lost (I/O error, failed reopen).
    pub disconnects: u64,
    /// All of the device's counters.
    pub stats: DeviceStats,
    /// The bones (or joints) a skeleton source has received, by name (empty for a glove or
    /// tracker).
    pub seen: Vec<String>,
}

/// A device's status as the worker keeps it.
#[derive(Debug, Default)]
pub(super) struct RoleStatus {
    pub(super) present: bool,
    pub(super) description: String,
    pub(super) error: Option<String>,
    pub(super) samples: u64,
    pub(super) watchdog_trips: u64,
    pub(super) disconnects: u64,
    pub(super) window_start: Option<Instant>,
    pub(super) window_count: u64,
    pub(super) rate: f64,
    pub(super) last_sample: Option<Instant>,
    pub(super) seen: Vec<String>,
}

impl RoleStatus {
    /// Counts `n` samples arriving now.
    pub(super) fn samples(&mut self, n: u64) {
        let now = Instant::now();
        self.samples += n;
        self.last_sample = Some(now);
        self.error = None;
        let start = *self.window_start.get_or_insert(now);
        self.window_count += n;
        let elapsed = now.duration_since(start).as_secs_f64();
        if elapsed >= 0.5 {
            self.rate = self.window_count as f64 / elapsed;
            self.window_start = Some(now);
            self.window_count = 0;
        }
    }

    pub(super) fn rate_now(&self) -> f64 {
        match self.last_sample {
            Some(t) if t.elapsed() < Duration::from_secs(1) => self.rate,
            _ => 0.0,
        }
    }
}
