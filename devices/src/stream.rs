//! [`HandStream`]: a tracker and a glove merged into one stream of timestamped hand frames.
//!
//! Each device runs on its own thread, so a slow or silent device never delays the other. A
//! frame is emitted at every device sample (and at every change of a source's state) holding the
//! latest value of each source. Frames go into a bounded channel with `try_send`: the device
//! threads never block on a slow consumer; when the channel is full the frame is dropped and
//! counted ([`StreamStats::overflow`]).
//!
//! Robustness, per source:
//! - **watchdog**: no valid sample for the profile's `watchdog_ms` → state
//!   [`SourceState::Silent`]; the device is stopped and started again (its handshake re-sent)
//!   until it answers;
//! - **disconnect**: an I/O error (unplugged, hung up) or a failed open → state
//!   [`SourceState::Disconnected`]; the device is reopened every [`StreamOptions::retry`] and
//!   resumes by itself when it is back;
//! - bad records and bad values are dropped and counted in [`DeviceStats`], never passed on.
//!
//! Starting: [`HandStream::open`] needs every device to answer its handshake now (an absent
//! port is an error); [`HandStream::connect`] starts whatever is present and keeps retrying
//! what is missing every [`StreamOptions::retry`], exactly as for a device unplugged mid-session
//! (the window's Connect, `nendo record`). [`HandStream::status`] gives per device what a
//! status panel shows ([`DeviceStatus`]: state, sample rate, the last error — cleared when the
//! device recovers —, faults, rejected records, watchdog trips).
//!
//! **Frames are delivered as a trace stores them**: every frame is rounded to the trace's six
//! decimals on its way into the channel ([`crate::trace::quantize_frame`], by the stream's
//! glove joints), so whatever reads a stream — the window's hand loop, `nendo record` — sees
//! exactly the numbers a recording of it keeps, and replaying the recording gives the window's
//! surface bit for bit. (One micrometre and one microradian lie far below what any of these
//! devices resolves.)
//!
//! **Every frame carries its arrival** ([`crate::arrival`]): when the port read that completed
//! its newest sample returned, and when it entered the channel. [`HandStream::drain_stamped`]
//! and [`HandStream::next_stamped_timeout`] hand it on; the other readers see frames only.
//!
//! Nothing here panics on device input; a poisoned lock is recovered, not unwrapped.

use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, SyncSender, TrySendError, sync_channel};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::device::{DeviceStats, Glove, Tracker, open_glove_for_hand, open_tracker};
use crate::profile::{Input, Profile, SkeletonProfile};
use crate::skeleton::{Skeleton, SkeletonSource};
use crate::trace::{Trace, TraceHeader, quantize_frame};
use crate::{
    Arrival, DeviceError, FrameStatus, GloveSample, HandFrame, Joint, JointAngles, SourceState,
    StampedFrame, Timestamp, TrackerPose, buttons,
};

/// How a device thread waits for data before checking its stop flag and watchdog.
const POLL: Duration = Duration::from_millis(20);

/// Options for opening a stream.
#[derive(Debug, Clone)]
pub struct StreamOptions {
    /// Replaces the glove's serial port of the profile.
    pub glove_port: Option<String>,
    /// Replaces the tracker's serial port of the profile.
    pub tracker_port: Option<String>,
    /// Frames the channel holds before new ones are dropped.
    pub capacity: usize,
    /// Replaces the profile's watchdog period.
    pub watchdog: Option<Duration>,
    /// Time between attempts to reopen a lost device.
    pub retry: Duration,
    /// Replaces the VMC receiver's listening address of the profile (`ADDR:PORT`).
    pub vmc_listen: Option<String>,
}

impl Default for StreamOptions {
    fn default() -> Self {
        StreamOptions {
            glove_port: None,
            tracker_port: None,
            capacity: 1024,
            watchdog: None,
            retry: Duration::from_millis(250),
            vmc_listen: None,
        }
    }
}

/// Counters of a stream.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StreamStats {
    /// Frames put into the channel.
    pub frames: u64,
    /// Frames dropped because the channel was full.
    pub overflow: u64,
    /// Times a source was declared silent by the watchdog.
    pub watchdog_trips: u64,
    /// Times a source was lost (I/O error or failed reopen after a loss).
    pub disconnects: u64,
    /// The glove's counters.
    pub glove: DeviceStats,
    /// The tracker's counters.
    pub tracker: DeviceStats,
}

#[derive(Debug, Default)]
struct Merge {
    pose: Option<TrackerPose>,
    angles: Option<JointAngles>,
    switch: bool,
    skeleton: Option<Skeleton>,
    tracker: SourceState,
    glove: SourceState,
}

struct Shared {
    merge: Mutex<Merge>,
    tx: SyncSender<StampedFrame>,
    /// The glove's joints: the columns a trace of the stream has, by which frames are rounded.
    joints: Vec<Joint>,
    stop: AtomicBool,
    finished: AtomicBool,
    frames: AtomicU64,
    overflow: AtomicU64,
    watchdog_trips: AtomicU64,
    disconnects: AtomicU64,
    glove_stats: Mutex<DeviceStats>,
    tracker_stats: Mutex<DeviceStats>,
    last_error: Mutex<Option<String>>,
    roles: Mutex<[RoleStatus; 2]>,
    start: Instant,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

impl Shared {
    /// Sends a frame as a trace stores it ([`quantize_frame`]): the one place where frames are
    /// rounded on their way to the hand loop and to a recording, so both see the same numbers.
    fn send(&self, frame: HandFrame, read: Instant) {
        let frame = quantize_frame(&frame, &self.joints);
        let stamped = StampedFrame {
            frame,
            arrival: Arrival::read_at(read),
        };
        match self.tx.try_send(stamped) {
            Ok(()) => {
                self.frames.fetch_add(1, Ordering::Relaxed);
            }
            Err(TrySendError::Full(_)) => {
                self.overflow.fetch_add(1, Ordering::Relaxed);
            }
            Err(TrySendError::Disconnected(_)) => {}
        }
    }

    fn emit(&self, m: &Merge, tracker_fresh: bool, glove_fresh: bool, read: Instant) {
        let frame = HandFrame {
            time: Timestamp::since(self.start),
            pose: if m.tracker == SourceState::Ok {
                m.pose
            } else {
                None
            },
            joints: if m.glove == SourceState::Ok {
                m.angles
            } else {
                None
            },
            buttons: if m.switch && m.glove == SourceState::Ok {
                buttons::PRIMARY
            } else {
                0
            },
            status: FrameStatus {
                tracker: m.tracker,
                glove: m.glove,
                tracker_fresh,
                glove_fresh,
            },
            skeleton: m.skeleton.filter(|_| m.tracker == SourceState::Ok),
        };
        self.send(frame, read);
    }

    fn note_error(&self, e: &DeviceError) {
        *lock(&self.last_error) = Some(e.to_string());
    }

    fn role(&self, role: DeviceRole, f: impl FnOnce(&mut RoleStatus)) {
        f(&mut lock(&self.roles)[role.index()]);
    }

    fn note_role_error(&self, role: DeviceRole, e: &DeviceError) {
        self.note_error(e);
        self.role(role, |r| r.error = Some(e.to_string()));
    }
}

/// Which source a worker thread serves.
enum Source {
    Glove(Box<dyn Glove>),
    Tracker(Box<dyn Tracker>),
    /// A skeleton source, in the tracker's slot of a frame (its state is the tracker's).
    Skeleton(Box<dyn SkeletonSource>),
}

impl Source {
    fn role(&self) -> DeviceRole {
        match self {
            Source::Glove(_) => DeviceRole::Glove,
            Source::Tracker(_) | Source::Skeleton(_) => DeviceRole::Tracker,
        }
    }

    fn describe(&self) -> String {
        match self {
            Source::Glove(g) => g.describe(),
            Source::Tracker(t) => t.describe(),
            Source::Skeleton(s) => s.describe(),
        }
    }

    fn start(&mut self) -> Result<(), DeviceError> {
        match self {
            Source::Glove(g) => g.start(),
            Source::Tracker(t) => t.start(),
            Source::Skeleton(s) => s.start(),
        }
    }

    fn stop(&mut self) {
        match self {
            Source::Glove(g) => g.stop(),
            Source::Tracker(t) => t.stop(),
            Source::Skeleton(s) => s.stop(),
        }
    }

    fn stats(&self) -> DeviceStats {
        match self {
            Source::Glove(g) => g.stats(),
            Source::Tracker(t) => t.stats(),
            Source::Skeleton(s) => s.stats(),
        }
    }

    /// Reads and publishes; returns the number of samples.
    fn read_and_publish(
        &mut self,
        shared: &Shared,
        gloves: &mut Vec<GloveSample>,
        poses: &mut Vec<TrackerPose>,
        hands: &mut Vec<Skeleton>,
    ) -> Result<usize, DeviceError> {
        match self {
            Source::Glove(g) => {
                gloves.clear();
                let r = g.read(POLL, gloves);
                let read = g.arrived().unwrap_or_else(Instant::now);
                *lock(&shared.glove_stats) = g.stats();
                for s in gloves.iter() {
                    let mut m = lock(&shared.merge);
                    m.angles = Some(s.angles);
                    m.switch = s.switch.unwrap_or(false);
                    m.glove = SourceState::Ok;
                    shared.emit(&m, false, true, read);
                }
                r.map(|()| gloves.len())
            }
            Source::Tracker(t) => {
                poses.clear();
                let r = t.read(POLL, poses);
                let read = t.arrived().unwrap_or_else(Instant::now);
                *lock(&shared.tracker_stats) = t.stats();
                for p in poses.iter() {
                    let mut m = lock(&shared.merge);
                    m.pose = Some(*p);
                    m.tracker = SourceState::Ok;
                    shared.emit(&m, true, false, read);
                }
                r.map(|()| poses.len())
            }
            Source::Skeleton(s) => {
                hands.clear();
                let r = s.read(POLL, hands);
                // The receive that completed these hands has just returned: its arrival.
                let read = Instant::now();
                *lock(&shared.tracker_stats) = s.stats();
                let seen = s.seen();
                shared.role(DeviceRole::Tracker, |r| r.seen = seen);
                for h in hands.iter() {
                    let mut m = lock(&shared.merge);
                    m.skeleton = Some(*h);
                    m.tracker = SourceState::Ok;
                    shared.emit(&m, true, false, read);
                }
                r.map(|()| hands.len())
            }
        }
    }

    fn set_state(&self, shared: &Shared, state: SourceState) {
        let mut m = lock(&shared.merge);
        let slot = match self {
            Source::Glove(_) => &mut m.glove,
            Source::Tracker(_) | Source::Skeleton(_) => &mut m.tracker,
        };
        if *slot != state {
            *slot = state;
            shared.emit(&m, false, false, Instant::now());
        }
    }
}

/// Whether every device must start now.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Start {
    /// Every device answers now, or the stream is not opened ([`HandStream::open`]).
    AllNow,
    /// What is present starts now, the rest is retried ([`HandStream::connect`]).
    Tolerant,
}

enum Phase {
    Running { last_data: Instant },
    Restart { at: Instant },
}

fn run_source(
    mut source: Source,
    shared: Arc<Shared>,
    watchdog: Duration,
    retry: Duration,
    mut phase: Phase,
) {
    let role = source.role();
    let mut gloves = Vec::new();
    let mut poses = Vec::new();
    let mut hands = Vec::new();
    while !shared.stop.load(Ordering::Relaxed) {
        match phase {
            Phase::Running { last_data } => {
                match source.read_and_publish(&shared, &mut gloves, &mut poses, &mut hands) {
                    Ok(0) if last_data.elapsed() > watchdog => {
                        shared.watchdog_trips.fetch_add(1, Ordering::Relaxed);
                        shared.role(role, |r| {
                            r.watchdog_trips += 1;
                            r.error = Some(format!(
                                "{}: no valid sample for {} ms (watchdog): restarting",
                                r.description,
                                watchdog.as_millis()
                            ));
                        });
                        source.set_state(&shared, SourceState::Silent);
                        source.stop();
                        phase = Phase::Restart { at: Instant::now() };
                    }
                    Ok(0) => {}
                    Ok(n) => {
                        shared.role(role, |r| r.samples(n as u64));
                        phase = Phase::Running {
                            last_data: Instant::now(),
                        }
                    }
                    Err(e) => {
                        shared.note_role_error(role, &e);
                        let state = if e.is_disconnect() {
                            shared.disconnects.fetch_add(1, Ordering::Relaxed);
                            shared.role(role, |r| r.disconnects += 1);
                            SourceState::Disconnected
                        } else {
                            SourceState::Silent
                        };
                        source.set_state(&shared, state);
                        source.stop();
                        phase = Phase::Restart {
                            at: Instant::now() + retry,
                        };
                    }
                }
            }
            Phase::Restart { at } => {
                let now = Instant::now();
                if now < at {
                    std::thread::sleep((at - now).min(POLL));
                    continue;
                }
                match source.start() {
                    Ok(()) => {
                        phase = Phase::Running {
                            last_data: Instant::now(),
                        }
                    }
                    Err(e) => {
                        shared.note_role_error(role, &e);
                        if e.is_disconnect() {
                            source.set_state(&shared, SourceState::Disconnected);
                        }
                        phase = Phase::Restart {
                            at: Instant::now() + retry,
                        };
                    }
                }
            }
        }
    }
    source.stop();
    let stats = source.stats();
    match source {
        Source::Glove(_) => *lock(&shared.glove_stats) = stats,
        Source::Tracker(_) | Source::Skeleton(_) => *lock(&shared.tracker_stats) = stats,
    }
}

/// A running stream of hand frames (see the module docs). Dropping it stops the device threads
/// and closes the devices.
pub struct HandStream {
    rx: Receiver<StampedFrame>,
    shared: Arc<Shared>,
    threads: Vec<JoinHandle<()>>,
    joints: Vec<Joint>,
    description: Vec<String>,
    /// The header of the trace a replay plays.
    source_header: Option<TraceHeader>,
    /// What the glove said about itself at open (see [`Glove::warnings`]).
    warnings: Vec<String>,
}

impl std::fmt::Debug for HandStream {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HandStream")
            .field("sources", &self.description)
            .finish()
    }
}

impl HandStream {
    /// Opens the devices (or the trace) a profile names and starts streaming. Each device must
    /// answer its handshake now: an absent port or a mute device is an error here, not a
    /// silent stream. The mouse profile is refused: its hand is driven by the window through
    /// [`MouseDevice`](crate::MouseDevice).
    pub fn open(profile: &Profile, options: &StreamOptions) -> Result<HandStream, DeviceError> {
        Self::open_with(profile, options, Start::AllNow)
    }

    /// Like [`HandStream::open`], but a device that is absent or does not answer now is not an
    /// error: the stream starts with whatever is present and keeps retrying the rest every
    /// [`StreamOptions::retry`] (its state `Disconnected` or `Silent` until it answers, its
    /// error in [`HandStream::status`]), as for a device unplugged mid-session. Errors are
    /// only those of the profile itself (a bad glove or tracker entry, an unreadable replay
    /// trace, the mouse profile).
    pub fn connect(profile: &Profile, options: &StreamOptions) -> Result<HandStream, DeviceError> {
        Self::open_with(profile, options, Start::Tolerant)
    }

    fn open_with(
        profile: &Profile,
        options: &StreamOptions,
        start: Start,
    ) -> Result<HandStream, DeviceError> {
        let watchdog = options
            .watchdog
            .unwrap_or(Duration::from_millis(profile.watchdog_ms));
        match &profile.input {
            Input::Devices { glove, tracker } => {
                let glove = match glove {
                    Some(g) => {
                        let mut g = g.clone();
                        if let Some(p) = &options.glove_port {
                            g.set_port(p);
                        }
                        Some(open_glove_for_hand(&g, Some(profile.hand.side))?)
                    }
                    None => None,
                };
                let tracker = match tracker {
                    Some(t) => {
                        let mut t = t.clone();
                        if let Some(p) = &options.tracker_port {
                            t.set_port(p);
                        }
                        Some(open_tracker(&t)?)
                    }
                    None => None,
                };
                let sources = [glove.map(Source::Glove), tracker.map(Source::Tracker)];
                HandStream::start_sources(sources, watchdog, options, start)
            }
            Input::Skeleton(SkeletonProfile::Vmc {
                listen,
                bone_timeout_s,
            }) => {
                let listen = options.vmc_listen.as_deref().unwrap_or(listen);
                let mut receiver = crate::vmc::VmcReceiver::new(listen, profile.hand)?;
                receiver.set_bone_timeout(*bone_timeout_s);
                let sources = [None, Some(Source::Skeleton(Box::new(receiver)))];
                HandStream::start_sources(sources, watchdog, options, start)
            }
            // Streamed frame by frame: an interrupted recording plays its complete frames,
            // and the stream's last error says what was dropped.
            Input::Replay(r) => {
                HandStream::replay_file(Path::new(&r.trace), r.speed, r.repeat, options.capacity)
            }
            Input::Mouse(_) => Err(DeviceError::Unsupported(
                "the mouse hand is driven by the window (MouseDevice), not opened as a stream"
                    .into(),
            )),
        }
    }

    /// Starts a stream over device backends (started here; the first failure is returned and
    /// every device already started is stopped again).
    pub fn from_devices(
        glove: Option<Box<dyn Glove>>,
        tracker: Option<Box<dyn Tracker>>,
        watchdog: Duration,
        options: &StreamOptions,
    ) -> Result<HandStream, DeviceError> {
        let sources = [glove.map(Source::Glove), tracker.map(Source::Tracker)];
        Self::start_sources(sources, watchdog, options, Start::AllNow)
    }

    /// Starts a stream over device backends; those that do not start now are retried by
    /// their threads (see [`HandStream::connect`]).
    pub fn connect_devices(
        glove: Option<Box<dyn Glove>>,
        tracker: Option<Box<dyn Tracker>>,
        watchdog: Duration,
        options: &StreamOptions,
    ) -> Result<HandStream, DeviceError> {
        let sources = [glove.map(Source::Glove), tracker.map(Source::Tracker)];
        Self::start_sources(sources, watchdog, options, Start::Tolerant)
    }

    /// Starts the sources: a glove (first) and a tracker or skeleton source (second).
    fn start_sources(
        given: [Option<Source>; 2],
        watchdog: Duration,
        options: &StreamOptions,
        start: Start,
    ) -> Result<HandStream, DeviceError> {
        let mut sources: Vec<Source> = given.into_iter().flatten().collect();
        if sources.is_empty() {
            return Err(DeviceError::Unsupported(
                "a stream needs a glove or a tracker".into(),
            ));
        }
        let description: Vec<String> = sources.iter().map(Source::describe).collect();
        let mut failures: Vec<Option<DeviceError>> = Vec::new();
        for i in 0..sources.len() {
            match sources[i].start() {
                Ok(()) => failures.push(None),
                Err(e) if start == Start::Tolerant => failures.push(Some(e)),
                Err(e) => {
                    for s in &mut sources[..i] {
                        s.stop();
                    }
                    return Err(e);
                }
            }
        }
        // After the start: a glove may fit its joints to the model it found (the 5DT Ultra).
        let mut joints = Vec::new();
        let mut warnings = Vec::new();
        for s in &sources {
            if let Source::Glove(g) = s {
                joints = g.joints();
                warnings.extend(g.warnings());
            }
        }
        let (tx, rx) = sync_channel(options.capacity.max(1));
        let mut merge = Merge::default();
        for (s, failure) in sources.iter().zip(&failures) {
            let state = match failure {
                None => SourceState::Ok,
                Some(e) if e.is_disconnect() => SourceState::Disconnected,
                Some(_) => SourceState::Silent,
            };
            match s {
                Source::Glove(_) => merge.glove = state,
                Source::Tracker(_) | Source::Skeleton(_) => merge.tracker = state,
            }
        }
        let shared = Arc::new(Shared::new(tx, merge, joints.clone()));
        for (s, failure) in sources.iter().zip(&failures) {
            let description = s.describe();
            shared.role(s.role(), |r| {
                r.present = true;
                r.description = description;
            });
            if let Some(e) = failure {
                shared.note_role_error(s.role(), e);
            }
        }
        let threads = sources
            .into_iter()
            .zip(failures)
            .map(|(s, failure)| {
                let shared = Arc::clone(&shared);
                let retry = options.retry;
                let phase = match failure {
                    None => Phase::Running {
                        last_data: Instant::now(),
                    },
                    Some(_) => Phase::Restart {
                        at: Instant::now() + retry,
                    },
                };
                std::thread::Builder::new()
                    .name("nendo-device".into())
                    .spawn(move || run_source(s, shared, watchdog, retry, phase))
                    .map_err(|e| DeviceError::Io {
                        device: "device thread".into(),
                        error: e,
                    })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(HandStream {
            rx,
            shared,
            threads,
            joints,
            description,
            source_header: None,
            warnings,
        })
    }

    /// The header of the trace a replay stream plays (`None` for live devices).
    pub fn source_header(&self) -> Option<&TraceHeader> {
        self.source_header.as_ref()
    }

    /// The header a recording of this stream must carry. A replay passes its trace's header
    /// on unchanged — its profile name, tracker-to-world transform and hand are the recording's,
    /// not those of the replay profile that plays it, and its scene; live devices get
    /// `profile`'s, with no scene (the recorder names it).
    pub fn recording_header(&self, profile: &Profile) -> TraceHeader {
        match &self.source_header {
            Some(h) => h.clone(),
            None => TraceHeader {
                profile: Some(profile.name.clone()),
                world_from_tracker: profile.world_from_tracker,
                hand: profile.hand,
                joints: self.joints.clone(),
                scene: None,
                skeleton: match profile.input {
                    Input::Skeleton(_) => Some(profile.hand.side),
                    _ => None,
                },
                marks_held: false,
            },
        }
    }

    /// What the glove reported about itself at open: mismatches with the profile that were
    /// worked around (a 5DT Ultra of another model or hand than the profile's).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The next frame, if one is waiting.
    pub fn try_next(&self) -> Option<HandFrame> {
        self.rx.try_recv().ok().map(|s| s.frame)
    }

    /// The next frame, waiting at most `timeout`.
    pub fn next_timeout(&self, timeout: Duration) -> Option<HandFrame> {
        self.next_stamped_timeout(timeout).map(|s| s.frame)
    }

    /// Every frame waiting now (call once per UI frame).
    pub fn drain(&self) -> Vec<HandFrame> {
        self.rx.try_iter().map(|s| s.frame).collect()
    }

    /// The next frame with its arrival ([`crate::arrival`]), waiting at most `timeout`.
    pub fn next_stamped_timeout(&self, timeout: Duration) -> Option<StampedFrame> {
        self.rx.recv_timeout(timeout).ok()
    }

    /// Every frame waiting now, with its arrival.
    pub fn drain_stamped(&self) -> Vec<StampedFrame> {
        self.rx.try_iter().collect()
    }

    /// The glove's joints (the columns of a trace recorded from this stream).
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// The sources, described for people.
    pub fn describe(&self) -> String {
        self.description.join(" + ")
    }

    /// Current tracker and glove states.
    pub fn states(&self) -> (SourceState, SourceState) {
        let m = lock(&self.shared.merge);
        (m.tracker, m.glove)
    }

    /// The last device error of the stream's whole life (also after the device recovered; a
    /// status panel wants [`HandStream::status`], whose errors clear on recovery).
    pub fn last_error(&self) -> Option<String> {
        lock(&self.shared.last_error).clone()
    }

    /// Each device of the stream, glove first: state, rate, last error (cleared once the
    /// device delivers again), counters. A replay lists the trace's glove and tracker with the
    /// states recorded in it.
    pub fn status(&self) -> Vec<DeviceStatus> {
        let (tracker_state, glove_state) = self.states();
        let stats = self.stats();
        let roles = lock(&self.shared.roles);
        [DeviceRole::Glove, DeviceRole::Tracker]
            .into_iter()
            .filter(|role| roles[role.index()].present)
            .map(|role| {
                let r = &roles[role.index()];
                let (state, device) = match role {
                    DeviceRole::Glove => (glove_state, stats.glove),
                    DeviceRole::Tracker => (tracker_state, stats.tracker),
                };
                DeviceStatus {
                    role,
                    description: r.description.clone(),
                    state,
                    rate_hz: r.rate_now(),
                    last_error: r.error.clone(),
                    samples: r.samples,
                    faults: device.faults,
                    rejected: device.decode.rejected + device.invalid,
                    watchdog_trips: r.watchdog_trips,
                    disconnects: r.disconnects,
                    stats: device,
                    seen: r.seen.clone(),
                }
            })
            .collect()
    }

    /// Whether a replayed trace has played to its end (always false for live devices).
    pub fn finished(&self) -> bool {
        self.shared.finished.load(Ordering::Relaxed)
    }

    /// Counters so far.
    pub fn stats(&self) -> StreamStats {
        let s = &self.shared;
        StreamStats {
            frames: s.frames.load(Ordering::Relaxed),
            overflow: s.overflow.load(Ordering::Relaxed),
            watchdog_trips: s.watchdog_trips.load(Ordering::Relaxed),
            disconnects: s.disconnects.load(Ordering::Relaxed),
            glove: *lock(&s.glove_stats),
            tracker: *lock(&s.tracker_stats),
        }
    }

    /// Stops the device threads, closes the devices and returns the final counters.
    pub fn close(mut self) -> StreamStats {
        self.shutdown();
        self.stats()
    }

    fn shutdown(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }
}

impl Shared {
    fn new(tx: SyncSender<StampedFrame>, merge: Merge, joints: Vec<Joint>) -> Shared {
        Shared {
            merge: Mutex::new(merge),
            tx,
            joints,
            stop: AtomicBool::new(false),
            finished: AtomicBool::new(false),
            frames: AtomicU64::new(0),
            overflow: AtomicU64::new(0),
            watchdog_trips: AtomicU64::new(0),
            disconnects: AtomicU64::new(0),
            glove_stats: Mutex::new(DeviceStats::default()),
            tracker_stats: Mutex::new(DeviceStats::default()),
            last_error: Mutex::new(None),
            roles: Mutex::new([RoleStatus::default(), RoleStatus::default()]),
            start: Instant::now(),
        }
    }
}

impl Drop for HandStream {
    fn drop(&mut self) {
        self.shutdown();
    }
}

mod replay;
mod status;
use status::RoleStatus;
pub use status::{DeviceRole, DeviceStatus};
