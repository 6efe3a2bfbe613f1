//! `nendo bench live`: what one frame of a live stroke costs in the window, and what undo
//! keeps per stroke.
//!
//! **Live-stroke frame.** Planes of 10 × 10 and 40 × 40 unit patches, sculpted as in
//! `nendo bench render` ([`super::render::sculpted_plane`]), under the model's default
//! regulation. Two gestures, each as the window draws it, with the window's default finger
//! (radius 1.25, depth up to 0.3) and auto-refine off (a refinement changes the grid, so its
//! frame rebuilds the whole display):
//! - *push*: a live Push whose depth grows with the drag, 16 frames per stroke (depth 0.3·f/16
//!   at frame f), then released; the next stroke starts further round a circle;
//! - *line*: a Draw-a-line (a groove pressing along the surface's normals), its path growing
//!   by 0.25 per frame round a circle, 16 frames per stroke (a path of up to 4 units,
//!   re-applied whole every frame as the window does).
//!
//! One frame is the window's path:
//! 1. *deform + regulate*: [`LiveStroke::show`] — what the previous frame's operation wrote
//!    put back from the engine's journal (the stroke's start), the operation applied to it;
//! 2. *re-tessellate*: [`DisplayCache::refresh`] while busy — only the changed patches are
//!    tessellated again, in place, and the seam heat around them;
//! 3. *upload*: the changed vertex ranges ([`DisplayCache::vertex_ranges_since`]) handed to
//!    [`Renderer::update_surface_vertices`] — their GPU vertices built and written with
//!    `queue.write_buffer` at their offsets, then a (empty) `queue.submit` — on a headless
//!    device when one opens ([`GpuContext::headless`]; the software renderer on a machine
//!    without a GPU); without one, the vertices are built only (the table says which).
//!
//! The same run times the full rebuild the window did before, on the same frames: the same
//! deformation, then the whole surface tessellated with its seam heat ([`SurfaceDisplay::new`])
//! and every vertex uploaded ([`Renderer::set_surface`]). Times are medians over frames of the
//! measuring thread's CPU time ([`super::sculpt::thread_cpu_ns`]), so other processes on a
//! shared machine do not inflate them (a driver thread's copy is not counted either).
//!
//! **Undo memory.** Typical strokes — half live pushes or pulls (the default finger, depth up
//! to 0.3, redone three times with a growing depth as the window does), half lines of three
//! segments — at random points of planes of 10 × 10, 40 × 40 and 256 × 256 unit patches; the
//! history's bytes per stroke ([`nendo::editor::history::History::bytes`]), how many strokes fit
//! in its 100 MB, the base model it keeps, and the median CPU time of one undo.

use glam::DVec3;
use std::hint::black_box;
use std::ops::Range;

use super::{Table, cpu_median_ns, format_ns};
use nendo::editor::Document;
use nendo::editor::display_cache::DisplayCache;
use nendo::editor::history::History;
use nendo::editor::scene::SurfaceDisplay;
use nendo::editor::stroke::LiveStroke;
use nendo::mesh::Tessellation;
use nendo::model::Model;
use nendo::render::{GpuContext, OFFSCREEN_FORMAT, Renderer, surface_vertices};
use nendo::surface::{Dirs, Op, Primitive, PrimitiveParams};

/// The suite's tables.
#[must_use]
pub fn report(scale: f64) -> String {
    let strokes = ((4.0 * scale).round() as usize).max(2);
    let mut out = String::new();
    out.push_str(&frames(strokes));
    out.push('\n');
    out.push_str(&undo_memory(((1000.0 * scale).round() as usize).max(20)));
    out
}

/// Frames per benched stroke.
const FRAMES_PER_STROKE: usize = 16;

/// The point of a circle of `radius` about the origin at arc length `0.25·k`.
fn on_circle(k: usize, radius: f64) -> DVec3 {
    let angle = 0.25 * k as f64 / radius;
    DVec3::new(radius * angle.cos(), radius * angle.sin(), 0.0)
}

/// A gesture the bench draws (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Gesture {
    Push,
    Line,
}

impl Gesture {
    /// The operation frame `f` (0-based) of stroke `s` shows.
    fn op(self, s: usize, f: usize, circle: f64) -> Op {
        let start = 3 * FRAMES_PER_STROKE * s;
        match self {
            Self::Push => Op::Push {
                at: on_circle(start, circle),
                dir: -DVec3::Z,
                depth: 0.3 * (f + 1) as f64 / FRAMES_PER_STROKE as f64,
                radius: 1.25,
            },
            Self::Line => Op::Groove {
                path: (start..=start + f + 1)
                    .map(|k| on_circle(k, circle))
                    .collect(),
                dirs: Dirs::Normal,
                depth: 0.3,
                radius: 1.25,
            },
        }
    }

    fn name(self) -> &'static str {
        match self {
            Self::Push => "push",
            Self::Line => "line",
        }
    }
}

/// Where the frames' vertices go: a headless device's vertex buffer, or nowhere (built only).
struct Upload {
    gpu: Option<(GpuContext, Renderer)>,
}

impl Upload {
    fn open() -> (Self, String) {
        match GpuContext::headless() {
            Ok(gpu) => {
                let renderer = Renderer::new(&gpu.device, OFFSCREEN_FORMAT, 1);
                let what = format!("written to the GPU ({})", gpu.describe());
                (
                    Self {
                        gpu: Some((gpu, renderer)),
                    },
                    what,
                )
            }
            Err(e) => (
                Self { gpu: None },
                format!("built only, no GPU write (no device: {e})"),
            ),
        }
    }

    /// Uploads the whole surface; returns the vertices uploaded.
    fn all(&mut self, display: &SurfaceDisplay) -> usize {
        let count = display.mesh.positions.len();
        match &mut self.gpu {
            Some((gpu, renderer)) => {
                renderer.set_surface(&gpu.device, &gpu.queue, &display.mesh, &display.seam_heat);
                gpu.queue.submit(std::iter::empty());
            }
            None => {
                let all = 0..count as u32;
                black_box(surface_vertices(&display.mesh, &display.seam_heat, all));
            }
        }
        count
    }

    /// Uploads the given vertex ranges again; returns the vertices uploaded.
    fn ranges(&mut self, display: &SurfaceDisplay, ranges: &[Range<u32>]) -> usize {
        match &mut self.gpu {
            Some((gpu, renderer)) => {
                renderer.update_surface_vertices(
                    &gpu.device,
                    &gpu.queue,
                    &display.mesh,
                    &display.seam_heat,
                    ranges,
                );
                gpu.queue.submit(std::iter::empty());
            }
            None => {
                for r in ranges {
                    black_box(surface_vertices(
                        &display.mesh,
                        &display.seam_heat,
                        r.clone(),
                    ));
                }
            }
        }
        ranges.iter().map(|r| (r.end - r.start) as usize).sum()
    }
}

/// Per-frame times (ns) of the three phases and the vertices uploaded.
#[derive(Default)]
struct FrameTimes {
    deform: Vec<f64>,
    tessellate: Vec<f64>,
    upload: Vec<f64>,
    total: Vec<f64>,
    vertices: Vec<f64>,
    partial: usize,
}

/// Draws `strokes` strokes of `gesture` on `model`, 16 frames each, the window's way (or with
/// a full rebuild each frame), timing each frame after the first stroke's first two.
fn draw(
    model: &Model,
    gesture: Gesture,
    strokes: usize,
    full: bool,
    upload: &mut Upload,
) -> FrameTimes {
    let now = || super::sculpt::thread_cpu_ns().unwrap_or(0) as f64;
    let circle = model.surface.patches_u() as f64 / 4.0;
    let mut doc = Document::new(model.clone());
    let mut cache = DisplayCache::default();
    cache.refresh(&doc, false);
    upload.all(cache.display());
    let mut times = FrameTimes::default();
    let mut frame = 0usize;
    for s in 0..strokes {
        let mut stroke = LiveStroke::begin(&doc, cache.patches(), &cache.display().mesh, false);
        let mut last = None;
        for f in 0..FRAMES_PER_STROKE {
            let op = gesture.op(s, f, circle);
            let t0 = now();
            let generation = cache.generation();
            stroke.show(&mut doc, Some(&op));
            let t1 = now();
            let (t2, count) = if full {
                let display =
                    SurfaceDisplay::new(&doc.model().surface.patches(), &Tessellation::DISPLAY);
                let t2 = now();
                (t2, upload.all(&display))
            } else {
                cache.refresh(&doc, true);
                let t2 = now();
                let display = cache.display();
                match cache.vertex_ranges_since(generation) {
                    Some(ranges) => {
                        times.partial += 1;
                        (t2, upload.ranges(display, &ranges))
                    }
                    None => (t2, upload.all(display)),
                }
            };
            let t3 = now();
            frame += 1;
            if frame > 2 {
                times.deform.push(t1 - t0);
                times.tessellate.push(t2 - t1);
                times.upload.push(t3 - t2);
                times.total.push(t3 - t0);
                times.vertices.push(count as f64);
            }
            last = Some(op);
        }
        let _ = stroke.commit(&mut doc, last.as_ref());
        cache.refresh(&doc, false);
        upload.all(cache.display());
    }
    times
}

/// Live-stroke frame times against the full rebuild.
fn frames(strokes: usize) -> String {
    let (mut upload, uploaded) = Upload::open();
    let mut table = Table::new(&[
        "live-stroke frame",
        "patches",
        "deform+regulate",
        "re-tessellate",
        "upload",
        "frame (median)",
        "partial frames",
        "full rebuild frame",
        "full / live",
        "vertices uploaded",
    ]);
    for n in [10usize, 40] {
        let model = Model::new(super::render::sculpted_plane(n));
        for gesture in [Gesture::Push, Gesture::Line] {
            let mut live = draw(&model, gesture, strokes, false, &mut upload);
            let mut full = draw(&model, gesture, strokes.div_ceil(2), true, &mut upload);
            let frame = super::median(&mut live.total);
            let full_frame = super::median(&mut full.total);
            table.row(vec![
                format!("plane {n}x{n} {}", gesture.name()),
                (n * n).to_string(),
                format_ns(super::median(&mut live.deform)),
                format_ns(super::median(&mut live.tessellate)),
                format_ns(super::median(&mut live.upload)),
                format_ns(frame),
                format!("{}/{}", live.partial, strokes * FRAMES_PER_STROKE),
                format_ns(full_frame),
                format!("{:.1}", full_frame / frame),
                format!(
                    "{:.0} of {:.0}",
                    super::median(&mut live.vertices),
                    super::median(&mut full.vertices)
                ),
            ]);
        }
    }
    format!(
        "Live-stroke frames (CPU time of the measuring thread; upload = vertices {uploaded}):\n{}",
        table.render()
    )
}

/// Uniform numbers from a seed, drawn from the suites' one generator ([`super::rng::Seeded`]):
/// the same strokes in every run.
#[derive(Debug, Clone)]
pub struct LiveStrokes(super::rng::Seeded);

impl LiveStrokes {
    /// A sequence from `seed`.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        Self(super::rng::Seeded::new(seed))
    }

    /// A number in `lo..hi`.
    pub fn gen_range(&mut self, range: std::ops::Range<f64>) -> f64 {
        self.0.range(range.start, range.end)
    }
}

/// A typical stroke at a random point of the `n × n` plane (see the module docs).
pub fn typical_stroke(doc: &mut Document, rng: &mut LiveStrokes, n: usize) {
    let h = n as f64 / 2.0;
    let at = DVec3::new(rng.gen_range(-h..h), rng.gen_range(-h..h), 0.0);
    let depth = rng.gen_range(-0.3..0.3);
    if rng.gen_range(0.0..1.0) < 0.5 {
        doc.begin_stroke(if depth < 0.0 { "pull" } else { "push" });
        for k in 1..=3 {
            let op = Op::Push {
                at,
                dir: -DVec3::Z,
                depth: depth * f64::from(k) / 3.0,
                radius: 1.25,
            };
            let _ = doc.show_in_stroke(Some(&op), |_| (None, None));
        }
    } else {
        doc.begin_stroke("draw a line");
        let mut last = at;
        for _ in 0..3 {
            let next = last + DVec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), 0.0);
            let op = Op::Drag {
                path: vec![last, next],
                dir: -DVec3::Z,
                depth,
                radius: 1.25,
            };
            let _ = doc.apply(&op);
            last = next;
        }
    }
    doc.end_stroke();
}

/// Undo memory per typical stroke.
fn undo_memory(strokes: usize) -> String {
    let mut table = Table::new(&[
        "undo",
        "strokes",
        "bytes / stroke",
        "strokes in 100 MB",
        "base model MB",
        "undo (median)",
        "whole snapshot / stroke",
    ]);
    for n in [10usize, 40, 256] {
        let model = Model::new(
            Primitive::Plane
                .build(&PrimitiveParams {
                    patches: Some((n, n)),
                    ..PrimitiveParams::default()
                })
                .unwrap_or_else(|e| panic!("plane {n}: {e}")),
        );
        let snapshot = nendo::editor::history::model_bytes(&model);
        let mut doc = Document::new(model);
        let mut rng = LiveStrokes::new(n as u64);
        for _ in 0..strokes {
            typical_stroke(&mut doc, &mut rng, n);
        }
        let history = doc.history();
        let kept = history.undo_len();
        let per = history.bytes() as f64 / kept.max(1) as f64;
        let base = history.base_bytes();
        let undo = cpu_median_ns(9, 5, |_| {
            doc.undo();
        });
        table.row(vec![
            format!("plane {n}x{n}"),
            kept.to_string(),
            format!("{per:.0}"),
            format!("{:.0}", History::DEFAULT_LIMIT_BYTES as f64 / per),
            format!("{:.1}", base as f64 / 1e6),
            format_ns(undo),
            snapshot.to_string(),
        ]);
    }
    format!(
        "Undo memory (typical strokes; the old history kept a whole snapshot per stroke):\n{}",
        table.render()
    )
}
