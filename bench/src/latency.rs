//! `nendo bench input`, second part: **device sample → frame latency** on the real path, at
//! 1 600 patches.
//!
//! Set-up: a CyberGlove II (18 sensors) and a Polhemus Fastrak emulated byte for byte on two
//! pseudo-terminals ([`PtyEmulator`], what `nendo emulate` runs), both playing the shipped
//! `press` gesture over and over (the hand comes down 0.8 side into the plane and lifts again
//! every 3 s; the glove at 100 Hz, the tracker at 120 Hz, each its own byte stream), read
//! through the shipped profile `cyberglove2-18-fastrak` placed over the plane as the window's
//! own test of a live session places it (tracker origin at the world origin, 21.5 sides per
//! metre), every finger pressing as a glove's default. The model is the 10-side plane as
//! 40 × 40 = 1 600 patches. What runs is the window's code: [`Modeller`] (the headless editor)
//! connected to the profile — the stream's device threads, the loop thread's inbox, the hand
//! driver on the document in [`Modeller::tick`] and again in [`Modeller::refresh`], the display
//! cache — and the window's upload and draw on [`Renderer`], into an offscreen target of a
//! headless device ([`Offscreen`]: on this machine Mesa's software Vulkan, lavapipe), at a
//! window's 1280 × 720 and at 320 × 180, where the rasteriser costs little. Missing beside the
//! window: egui (its panels' pass and its drawing).
//!
//! A frame starts as the window's does while devices stream: when the loop thread signals
//! samples ([`DeviceWaker`], the window's redraw request), or right after the previous frame
//! when samples came during it. Each sample is timed by the editor's own
//! [`nendo::editor::live::LatencyMeter`] (see its module for the stages): the **CPU side** from the port read
//! that completed the sample to the return of the frame's `queue.submit`; the **presented**
//! figure to the moment the device reports the frame's work done (`device.poll` waiting for
//! that submission) — the offscreen stand-in for `present()` returning, which on lavapipe
//! likewise waits for the rasteriser. Frames are drawn back to back: a frame still drawing
//! delays the samples that arrive meanwhile, and that wait is in their figure (stage `wait`);
//! the table also gives the CPU side without it, the pipeline's own work on a sample.
//!
//! Each frame size runs twice, alike but for the frame's order: **latched** — the window's: once
//! the previous frame is done (here its `device.poll`; the window's surface acquire), the frame
//! waits at most `LATCH_WAIT` for a fresh sample and takes it just before the display refresh
//! and the submission, and settles the display after the frame is done — and the **baseline**, the order before the latch (the frame takes what
//! came when it starts). The target is on each frame's newest sample, the pose it draws (the
//! latency module says why); every sample's figure is given beside it.
//!
//! The first second (connection, handshakes, the first full tessellation) is not counted.
//! Wall time throughout (this is a latency, not a CPU cost): on a shared machine other
//! processes inflate it.

use std::sync::Arc;
use std::sync::mpsc::sync_channel;
use std::time::{Duration, Instant};

use glam::Vec2;
use nendo::cli::emulate::{GESTURE_RATE_HZ, frame_at, raw_values};
use nendo::editor::live::{
    DeviceWaker, LATCH_WAIT, LatencyMeter, Quantiles, SampleLatency, Stages,
};
use nendo::editor::{Document, Modeller};
use nendo::hand::script::Gesture;
use nendo::model::Model;
use nendo::render::{
    GpuContext, LineBatch, OFFSCREEN_FORMAT, Offscreen, RenderError, Renderer, SphereInstance,
};
use nendo::surface::{Primitive, PrimitiveParams};
use nendo_devices::cyberglove::SensorCount;
use nendo_devices::emulator::{CyberGloveModel, DeviceModel, FastrakModel, PtyEmulator, Script};
use nendo_devices::{DeviceError, TrackerPose, profile};

use super::Table;

/// The offscreen frame's size (pixels): a window's.
pub const FRAME_SIZE: [u32; 2] = [1280, 720];

/// A frame small enough that the software rasteriser is not what the samples wait for.
pub const SMALL_FRAME: [u32; 2] = [320, 180];

/// What a latency run needs that may be missing.
#[derive(Debug)]
pub enum LatencyBenchError {
    /// No headless device, or a frame the device could not finish.
    Gpu(RenderError),
    /// An emulator's pseudo-terminal, or the profile's temporary file.
    Io(std::io::Error),
    /// The shipped profile, or connecting to the emulated devices.
    Device(DeviceError),
    /// The session ended or never pressed the plane (the message says what happened).
    Session(String),
}

impl std::fmt::Display for LatencyBenchError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Gpu(e) => write!(
                f,
                "the renderer (package nendo-modeller, headless wgpu): {e}"
            ),
            Self::Io(e) => write!(f, "the emulated devices: {e}"),
            Self::Device(e) => write!(f, "the device session: {e}"),
            Self::Session(e) => write!(f, "the device session: {e}"),
        }
    }
}

impl std::error::Error for LatencyBenchError {}

/// A latency run's samples and what it ran on.
#[derive(Debug, Clone)]
pub struct LatencyRun {
    /// Every sample shown after the warm-up, in order.
    pub samples: Vec<SampleLatency>,
    /// Frames drawn after the warm-up.
    pub frames: usize,
    /// The contacts the hand made (undoable edits).
    pub contacts: u64,
    /// The adapter.
    pub gpu: String,
    /// Seconds measured.
    pub seconds: f64,
    /// The frame's size (pixels).
    pub size: [u32; 2],
    /// The frame order: latched (the window's) or the baseline.
    pub order: FrameOrder,
}

/// How a frame takes the device input (`nendo::editor::live` latency module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameOrder {
    /// The window's: after the previous frame is done (the acquire), wait at most
    /// [`LATCH_WAIT`] for a fresh sample, then take it, refresh, encode and submit.
    Latched,
    /// The baseline, the order before the latch: take what came when the frame starts.
    Unlatched,
}

impl FrameOrder {
    fn name(self) -> &'static str {
        match self {
            Self::Latched => "latched",
            Self::Unlatched => "baseline",
        }
    }
}

/// Runs the emulated glove and tracker for `seconds` (after a one-second warm-up) into the
/// editor and offscreen frames of `size`, each frame in `order` (see the module docs).
///
/// # Errors
/// [`LatencyBenchError`] when no headless device opens, an emulator cannot start, or the
/// session does not run.
pub fn run(
    seconds: f64,
    size: [u32; 2],
    order: FrameOrder,
) -> Result<LatencyRun, LatencyBenchError> {
    let gpu = GpuContext::headless().map_err(LatencyBenchError::Gpu)?;
    let mut profile =
        profile::resolve("cyberglove2-18-fastrak").map_err(LatencyBenchError::Device)?;
    profile.world_from_tracker.translation = [0.0; 3];
    profile.world_from_tracker.scale = 21.5;
    let gesture = Gesture::Press
        .trace(profile.world_from_tracker, GESTURE_RATE_HZ)
        .map_err(|e| LatencyBenchError::Session(e.to_string()))?;
    let frames = Arc::new(gesture.frames);
    if frames.is_empty() {
        return Err(LatencyBenchError::Session(
            "the press gesture has no frames".into(),
        ));
    }
    let tracker = FastrakModel::new();
    let period = tracker.period();
    let poses = Arc::clone(&frames);
    let tracker = PtyEmulator::spawn(tracker.with_path(Script::new(move |k| {
        frame_at(&poses, period, k)
            .pose
            .unwrap_or(TrackerPose::IDENTITY)
    })))
    .map_err(LatencyBenchError::Io)?;
    let table = profile
        .glove()
        .map(|g| g.calibration().to_vec())
        .ok_or_else(|| LatencyBenchError::Session("the profile has no glove".into()))?;
    let glove = CyberGloveModel::new(SensorCount::Eighteen);
    let period = glove.period();
    let angles = Arc::clone(&frames);
    let glove = PtyEmulator::spawn(glove.with_values(Script::new(move |k| {
        raw_values(&table, frame_at(&angles, period, k), 1)
    })))
    .map_err(LatencyBenchError::Io)?;
    if let nendo_devices::profile::Input::Devices {
        glove: Some(g),
        tracker: Some(t),
    } = &mut profile.input
    {
        g.set_port(&glove.port());
        t.set_port(&tracker.port());
    }
    let dir = std::env::temp_dir().join(format!("nendo-bench-latency-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(LatencyBenchError::Io)?;
    let path = dir.join("emulated.json");
    std::fs::write(&path, profile.to_json()).map_err(LatencyBenchError::Io)?;

    let plane = Primitive::Plane
        .build(&PrimitiveParams {
            patches: Some((40, 40)),
            ..PrimitiveParams::default()
        })
        .map_err(|e| LatencyBenchError::Session(e.to_string()))?;
    let mut modeller = Modeller::new(Document::new(Model::new(plane)), None, false);
    let (tx, rx) = sync_channel::<()>(1);
    modeller.set_device_waker(DeviceWaker(Arc::new(move || {
        let _ = tx.try_send(());
    })));
    let connected = modeller.connect_profile(&path.display().to_string());
    let _ = std::fs::remove_dir_all(&dir);
    connected.map_err(LatencyBenchError::Device)?;
    if !modeller.devices_mut().0.is_connected() {
        return Err(LatencyBenchError::Session(
            modeller
                .status()
                .map_or_else(|| "not connected".into(), |s| s.text.clone()),
        ));
    }
    *modeller.devices_mut().0.latency_mut() = LatencyMeter::with_window(usize::MAX);

    let renderer = Renderer::new(&gpu.device, OFFSCREEN_FORMAT, 1);
    let target = Offscreen::new(&gpu.device, size, 1);
    let mut frame = Frame {
        gpu: &gpu,
        renderer,
        target,
        uploaded: None,
        lines: LineBatch::new(),
        spheres: Vec::new(),
        order,
    };
    modeller.set_viewport(Vec2::new(size[0] as f32, size[1] as f32));
    let warm = Instant::now() + Duration::from_secs(1);
    while Instant::now() < warm {
        let _ = rx.recv_timeout(Duration::from_millis(20));
        frame.draw(&mut modeller)?;
    }
    modeller.devices_mut().0.latency_mut().clear();
    let contacts_before = contacts(&mut modeller);
    let begun = Instant::now();
    let end = begun + Duration::from_secs_f64(seconds);
    let mut drawn = 0;
    while Instant::now() < end {
        // The window's redraw request: samples arrived (or a frame is due anyway).
        let _ = rx.recv_timeout(Duration::from_millis(20));
        frame.draw(&mut modeller)?;
        drawn += 1;
        if !modeller.devices_mut().0.is_connected() {
            return Err(LatencyBenchError::Session(
                "the device session ended".into(),
            ));
        }
    }
    let measured = begun.elapsed().as_secs_f64();
    let contacts = contacts(&mut modeller) - contacts_before;
    let samples = modeller
        .devices_mut()
        .0
        .latency()
        .shown()
        .copied()
        .collect();
    let (live, doc) = modeller.devices_mut();
    live.disconnect_from(doc);
    drop((glove, tracker));
    Ok(LatencyRun {
        samples,
        frames: drawn,
        contacts,
        gpu: gpu.describe(),
        seconds: measured,
        size,
        order,
    })
}

/// The contacts the device hand has made so far.
fn contacts(modeller: &mut Modeller) -> u64 {
    modeller.devices_mut().0.contacts()
}

/// The window's drawing, offscreen.
struct Frame<'a> {
    gpu: &'a GpuContext,
    renderer: Renderer,
    target: Offscreen,
    /// The display generation on the GPU.
    uploaded: Option<u64>,
    lines: LineBatch,
    spheres: Vec<SphereInstance>,
    order: FrameOrder,
}

impl Frame<'_> {
    /// One frame in the window's order: the editor's per-frame work, the latch (when
    /// [`FrameOrder::Latched`]; the previous frame's wait below stands for the window's
    /// acquire), the display refresh, the surface's changed vertices uploaded, the scene, the
    /// submission, then the wait for the frame to be drawn — each marked on the editor's
    /// latency record.
    fn draw(&mut self, modeller: &mut Modeller) -> Result<(), LatencyBenchError> {
        modeller.tick(Instant::now());
        let latched = self.order == FrameOrder::Latched;
        if latched {
            modeller.latch_devices(LATCH_WAIT);
            modeller.refresh_for_frame();
        } else {
            modeller.refresh();
        }
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        if self.uploaded != Some(modeller.surface_generation()) {
            let display = modeller.surface();
            match self.uploaded.and_then(|g| modeller.surface_ranges_since(g)) {
                Some(ranges) => self.renderer.update_surface_vertices(
                    device,
                    queue,
                    &display.mesh,
                    &display.seam_heat,
                    &ranges,
                ),
                None => self
                    .renderer
                    .set_surface(device, queue, &display.mesh, &display.seam_heat),
            }
            self.uploaded = Some(modeller.surface_generation());
        }
        let style = modeller.scene(&mut self.lines, &mut self.spheres);
        self.renderer.set_lines(device, queue, &self.lines);
        self.renderer.set_spheres(device, queue, &self.spheres);
        let size = modeller.viewport();
        let view = modeller.camera().view(size.x / size.y);
        self.renderer.prepare(queue, &view, &style, size.to_array());
        let submission = self.target.submit(self.gpu, &self.renderer);
        modeller.frame_submitted(Instant::now());
        Offscreen::wait(self.gpu, submission).map_err(LatencyBenchError::Gpu)?;
        modeller.frame_presented(Instant::now());
        if latched {
            modeller.settle();
        }
        Ok(())
    }
}

fn ms(d: Duration) -> String {
    format!("{:.2}", d.as_secs_f64() * 1e3)
}

/// Median and p95 of `values` as two cells (`-` for none).
fn cells(values: impl IntoIterator<Item = Duration>) -> [String; 2] {
    Quantiles::of(values).map_or_else(
        || ["-".to_string(), "-".to_string()],
        |q| [ms(q.median), ms(q.p95)],
    )
}

/// The CPU side without the `wait` stage: the pipeline's own work on a sample once a frame
/// takes it (parse, hand loop, the frame's later samples, display refresh, upload and
/// submission).
fn work(s: &SampleLatency) -> Duration {
    s.cpu() - s.stages.wait
}

/// The latency table of runs: per run, for each frame's newest sample (the pose it draws),
/// for every sample and for those that changed the surface, the CPU side, the CPU side without the wait for a frame, and the presented
/// figure, median and p95; then each stage's median and p95 per run.
#[must_use]
pub fn table(runs: &[LatencyRun]) -> String {
    let mut t = Table::new(&[
        "frame",
        "samples",
        "count",
        "CPU median (ms)",
        "CPU p95 (ms)",
        "CPU w/o wait: median",
        "p95 (ms)",
        "presented median (ms)",
        "presented p95 (ms)",
    ]);
    let mut s = Table::new(&[
        "frame",
        "stage",
        "newest: median (ms)",
        "p95 (ms)",
        "every: median (ms)",
        "p95 (ms)",
    ]);
    let mut about = Vec::new();
    let mut headline = Vec::new();
    for run in runs {
        let frame = format!("{}x{} {}", run.size[0], run.size[1], run.order.name());
        about.push(format!(
            "{frame}: {:.1} s measured, {} frames, {} samples, {} contacts",
            run.seconds,
            run.frames,
            run.samples.len(),
            run.contacts
        ));
        let sets: [(&str, Vec<&SampleLatency>); 3] = [
            (
                "frame's newest",
                run.samples.iter().filter(|s| s.newest).collect(),
            ),
            ("every sample", run.samples.iter().collect()),
            (
                "changed the surface",
                run.samples.iter().filter(|s| s.changed).collect(),
            ),
        ];
        for (name, set) in &sets {
            let [cpu_median, cpu_p95] = cells(set.iter().map(|s| s.cpu()));
            let [work_median, work_p95] = cells(set.iter().map(|s| work(s)));
            let [shown_median, shown_p95] = cells(set.iter().filter_map(|s| s.presented()));
            t.row(vec![
                frame.clone(),
                name.to_string(),
                set.len().to_string(),
                cpu_median,
                cpu_p95,
                work_median,
                work_p95,
                shown_median,
                shown_p95,
            ]);
        }
        let newest = run.samples.iter().filter(|s| s.newest);
        if let Some(c) = Quantiles::of(newest.map(SampleLatency::cpu)) {
            let met = c.median <= Duration::from_millis(2) && c.p95 <= Duration::from_millis(8);
            headline.push(format!(
                "{frame}: each frame's newest sample, CPU side median {} ms, p95 {} ms: target \
                 (median <= 2, p95 <= 8 ms) {}",
                ms(c.median),
                ms(c.p95),
                if met { "met" } else { "NOT met" }
            ));
        }
        let stage = |i: usize| {
            let of = |newest: bool| {
                cells(
                    run.samples
                        .iter()
                        .filter(|x| x.newest || !newest)
                        .map(|x| x.stages.all()[i]),
                )
            };
            let ([a, b], [c, d]) = (of(true), of(false));
            vec![a, b, c, d]
        };
        for (i, name) in Stages::NAMES.iter().enumerate() {
            s.row([vec![frame.clone(), name.to_string()], stage(i)].concat());
        }
        let present = |newest: bool| {
            cells(
                run.samples
                    .iter()
                    .filter(|x| x.newest || !newest)
                    .filter_map(|x| x.present),
            )
        };
        let ([a, b], [c, d]) = (present(true), present(false));
        s.row(vec![frame.clone(), "present".into(), a, b, c, d]);
    }
    let gpu = runs.first().map_or_else(String::new, |r| r.gpu.clone());
    format!(
        "Device sample -> frame on a 1 600-patch plane (40 x 40, side 10): emulated CyberGlove II (100 Hz) + \
         Fastrak (120 Hz) on ptys pressing every 3 s, all five fingers, through the editor into offscreen frames \
         on {gpu}, frames back to back; wall time after 1 s of warm-up. Each size twice in one run: \
         latched (the window's order: after the previous frame, wait <= {} ms for a fresh sample, take it, \
         submit) and the baseline (take what came when the frame starts).\n  {}\n\
         CPU side = port read -> queue.submit returned; w/o wait = the same less the wait for a frame to take \
         the sample (the previous frame's drawing, on a software renderer); presented = -> the device's work \
         for that frame done (lavapipe: rasterised). Not a target here.\n{}  {}\n\
         Stages (each one's own quantiles, over each frame's newest sample and over every sample; the CPU \
         side is their sum per sample):\n{}",
        LATCH_WAIT.as_millis(),
        about.join("\n  "),
        t.render(),
        headline.join("\n  "),
        s.render(),
    )
}

/// The latency part of `nendo bench input`: `6 · scale` seconds (at least 3) at each frame
/// size, the window's 1280 x 720 and a 320 x 180 one whose rasterisation is cheap, each
/// latched and then as the baseline, prepared alike (a fresh session each).
#[must_use]
pub fn report(scale: f64) -> String {
    let seconds = (6.0 * scale).max(3.0);
    let mut runs = Vec::new();
    for (size, order) in [FRAME_SIZE, SMALL_FRAME]
        .into_iter()
        .flat_map(|s| [(s, FrameOrder::Latched), (s, FrameOrder::Unlatched)])
    {
        match run(seconds, size, order) {
            Ok(r) => runs.push(r),
            Err(e) => return format!("Device sample -> frame latency: not measured: {e}\n"),
        }
    }
    table(&runs)
}
