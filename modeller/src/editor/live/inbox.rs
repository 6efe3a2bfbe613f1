//! The loop thread: it drains the device stream's small channel continuously into an
//! unbounded inbox (and, when recording, into a trace file that grows frame by frame, so a
//! crash keeps what was recorded: [`TraceRecorder`]), so a slow window frame never drops a
//! sample; the window takes everything in the inbox once per frame. The frames are the
//! stream's, already rounded as the trace stores them, so the hand loop and the recording see
//! the same numbers. Each frame keeps its arrival stamp ([`StampedFrame`]) for the latency
//! figure.
//!
//! The recording marks the frames the plausibility gate holds (`held=`, trace version 4): its
//! recorder runs the gate with the settings the window's hand loop filters with — the same
//! settings the recording's scene carries, which `nendo replay` filters with — over the same
//! frames, so the marks are what the hand loop held ([`TraceRecorder::create_gated`]). With
//! the gate off the trace has no marks.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use nendo_devices::trace::Existing;
use nendo_devices::{
    DeviceError, DeviceStatus, FilterSettings, HandStream, Profile, SceneText, StampedFrame,
    TraceRecorder,
};

/// What the loop thread calls when it has put samples into the inbox: the window asks for a
/// redraw, so a sample is taken by the next frame at once rather than at the next scheduled
/// one (a bench waiting for samples is woken the same way).
#[derive(Clone)]
pub struct DeviceWaker(pub Arc<dyn Fn() + Send + Sync>);

impl std::fmt::Debug for DeviceWaker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("DeviceWaker")
    }
}

/// What the loop thread shares with the window.
#[derive(Debug, Default)]
pub(super) struct Shared {
    pub(super) inbox: Mutex<Vec<StampedFrame>>,
    /// Notified after frames went into the inbox (the window's latch waits on it).
    pub(super) arrived: Condvar,
    /// Called after samples went into the inbox.
    pub(super) waker: Mutex<Option<DeviceWaker>>,
    pub(super) stop: AtomicBool,
    /// The clutch key is held: every frame taken from now on carries
    /// [`nendo_devices::buttons::CLUTCH`] (in the recording too, so a replay does what the
    /// window did).
    pub(super) clutch: AtomicBool,
    pub(super) frames: AtomicU64,
    pub(super) status: Mutex<LoopStatus>,
    /// The recording's outcome (frames written), once the loop has ended.
    pub(super) recorded: Mutex<Option<Result<u64, DeviceError>>>,
}

/// Why a live session did not start.
#[derive(Debug, thiserror::Error)]
pub(super) enum LiveError {
    /// The trace file to record to could not be created (the message names it).
    #[error("{0}")]
    Record(DeviceError),
    /// The loop thread could not be started.
    #[error("cannot start the input thread: {0}")]
    Spawn(std::io::Error),
}

#[derive(Debug, Clone, Default)]
pub(super) struct LoopStatus {
    /// Each device, as [`HandStream::status`] gives it.
    pub(super) devices: Vec<DeviceStatus>,
    /// A recording error (the device errors are per device).
    pub(super) recording_error: Option<String>,
    pub(super) finished: bool,
    /// Once finished: why the stream ended, if it says (a replayed trace's bad line, what an
    /// interrupted recording dropped: [`HandStream::last_error`]).
    pub(super) ended: Option<String>,
}

pub(super) fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// A running device session.
#[derive(Debug)]
pub(super) struct DeviceSession {
    pub(super) describe: String,
    pub(super) shared: Arc<Shared>,
    pub(super) thread: Option<JoinHandle<()>>,
    pub(super) started: Instant,
    /// The trace a replay plays.
    pub(super) replay: Option<PathBuf>,
    /// The trace the session records to.
    pub(super) recording: Option<PathBuf>,
}

impl DeviceSession {
    /// Starts the loop on `stream`; with `record`, every frame also goes to a trace file whose
    /// header names `profile` (or, for a replay, is the replayed trace's own header) and the
    /// scene the session runs on (see [`crate::hand::scene::Scene::of_window`]), marked by the
    /// gate of the hand loop's filter settings (the scene's). `clutch`
    /// says whether the clutch key is held as it starts: set before the loop thread takes its
    /// first frame, so a key held from the start marks every frame.
    pub(super) fn start(
        stream: HandStream,
        record: Option<(PathBuf, &Profile, Option<SceneText>, FilterSettings)>,
        clutch: bool,
    ) -> Result<DeviceSession, LiveError> {
        let describe = stream.describe();
        let shared = Arc::new(Shared::default());
        shared.clutch.store(clutch, Ordering::Relaxed);
        let recording = record.as_ref().map(|(p, _, _, _)| p.clone());
        let mut writer = match record {
            Some((path, profile, scene, gate)) => {
                // A replayed trace is recorded with its own header, not the replay profile's;
                // the scene is the window's.
                let mut header = stream.recording_header(profile);
                header.scene = scene;
                // Appended as frames come, so a crash keeps them; the panel has asked before
                // replacing an existing file (`LiveInput::connect`).
                Some(
                    TraceRecorder::create_gated(&path, header, Existing::Replace, gate)
                        .map_err(LiveError::Record)?,
                )
            }
            None => None,
        };
        lock(&shared.status).devices = stream.status();
        let worker = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name("nendo live input".into())
            .spawn(move || {
                while !worker.stop.load(Ordering::Relaxed) {
                    // Read `finished` before draining: a stream sets it after its last frame,
                    // so the drain below still takes every frame sent before.
                    let finished = stream.finished();
                    let mut batch = Vec::new();
                    if let Some(first) = stream.next_stamped_timeout(Duration::from_millis(20)) {
                        batch.push(first);
                        batch.extend(stream.drain_stamped());
                    }
                    if worker.clutch.load(Ordering::Relaxed) {
                        for s in &mut batch {
                            s.frame.buttons |= nendo_devices::buttons::CLUTCH;
                        }
                    }
                    if let Some(w) = &mut writer {
                        let written = batch
                            .iter()
                            .try_for_each(|f| w.push(&f.frame))
                            .and_then(|()| w.sync_if_due());
                        // A failed write (a full disk) stops the recording, keeping the frames
                        // before it; the hand goes on.
                        if let Err(e) = written {
                            lock(&worker.status).recording_error =
                                Some(format!("recording stopped: {e}"));
                            *lock(&worker.recorded) = Some(Err(e));
                            writer = None;
                        }
                    }
                    worker
                        .frames
                        .fetch_add(batch.len() as u64, Ordering::Relaxed);
                    let arrived = !batch.is_empty();
                    lock(&worker.inbox).extend(batch);
                    if arrived {
                        worker.arrived.notify_all();
                    }
                    if arrived && let Some(w) = lock(&worker.waker).clone() {
                        (w.0)();
                    }
                    let devices = stream.status();
                    let mut status = lock(&worker.status);
                    status.devices = devices;
                    if finished {
                        status.finished = true;
                        status.ended = stream.last_error();
                        break;
                    }
                }
                if let Some(w) = writer {
                    *lock(&worker.recorded) = Some(w.finish());
                }
                stream.close();
            })
            .map_err(LiveError::Spawn)?;
        Ok(DeviceSession {
            describe,
            shared,
            thread: Some(thread),
            started: Instant::now(),
            replay: None,
            recording,
        })
    }

    pub(super) fn stop(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for DeviceSession {
    fn drop(&mut self) {
        self.stop();
    }
}
