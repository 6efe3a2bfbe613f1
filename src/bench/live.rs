//! `nendo bench live`: what one frame of a live stroke costs, and what undo keeps per stroke.
//!
//! **Live-stroke frame.** Planes of 10 × 10 and 40 × 40 unit patches, sculpted as in
//! `nendo bench render` ([`super::render::sculpted_plane`]), under the model's default
//! regulation. A stroke is open ([`Document::begin_stroke`]) and every frame draws one more
//! segment of a line (the window's default finger: radius 1.25, depth 0.3; segments of
//! 0.25 side, going round a circle) — a frame is then:
//!
//! 1. *deform + regulate*: [`Document::apply`] of the segment (the history only notes the
//!    touched patches);
//! 2. *re-tessellate*: [`DisplayCache::refresh`] while busy — only the touched patches are
//!    tessellated again, in place, and the seam heat around them;
//! 3. *upload*: the GPU vertices of the changed ranges
//!    ([`DisplayCache::vertex_ranges_since`]) built on the CPU
//!    ([`crate::render::surface_vertices`]) — the buffer the renderer's `write_buffer`
//!    copies; the GPU copy itself is not included (it needs an adapter, and on the software
//!    renderer it is a memcpy of the same bytes).
//!
//! The same run times the full rebuild the window did before: the same deformation, then the
//! whole surface tessellated with its seam heat ([`SurfaceDisplay::new`]) and every vertex
//! built for upload. Times are medians of the measuring thread's CPU time
//! ([`super::cpu_median_ns`]), so other processes on a shared machine do not inflate them.
//!
//! **Undo memory.** Typical strokes — half live pushes or pulls (the default finger, depth up
//! to 0.3, redone three times with a growing depth as the window does), half lines of three
//! segments — at random points of planes of 10 × 10, 40 × 40 and 256 × 256 unit patches; the
//! history's bytes per stroke ([`crate::app::history::History::bytes`]), how many strokes fit
//! in its 100 MB, the base model it keeps, and the median CPU time of one undo.

use glam::DVec3;
use std::hint::black_box;

use super::{Table, cpu_median_ns, format_ns};
use crate::app::Document;
use crate::app::display_cache::DisplayCache;
use crate::app::history::History;
use crate::app::scene::SurfaceDisplay;
use crate::mesh::Tessellation;
use crate::model::Model;
use crate::render::surface_vertices;
use crate::surface::{Op, Primitive, PrimitiveParams};

/// The suite's tables.
#[must_use]
pub fn report(scale: f64) -> String {
    let batches = ((15.0 * scale).round() as usize).max(3);
    let mut out = String::new();
    out.push_str(&frames(batches));
    out.push('\n');
    out.push_str(&undo_memory(((1000.0 * scale).round() as usize).max(20)));
    out
}

/// The point of the circular stroke at frame `k` (segments of 0.25 side).
fn on_circle(k: usize, radius: f64) -> DVec3 {
    let angle = 0.25 * k as f64 / radius;
    DVec3::new(radius * angle.cos(), radius * angle.sin(), 0.0)
}

fn segment(k: usize, radius: f64) -> Op {
    Op::Drag {
        path: vec![on_circle(k, radius), on_circle(k + 1, radius)],
        dir: -DVec3::Z,
        depth: 0.3,
        radius: 1.25,
    }
}

/// Live-stroke frame times against the full rebuild.
fn frames(batches: usize) -> String {
    let mut table = Table::new(&[
        "live-stroke frame",
        "patches",
        "deform+regulate",
        "re-tessellate",
        "upload build",
        "frame (median)",
        "full rebuild frame",
        "full / live",
        "vertices uploaded",
    ]);
    for n in [10usize, 40] {
        let model = Model::new(super::render::sculpted_plane(n));
        let circle = n as f64 / 4.0;
        // Live: the phases timed apart, then whole frames.
        let mut doc = Document::new(model.clone());
        let mut cache = DisplayCache::default();
        cache.refresh(&doc, false);
        doc.begin_stroke("draw a line");
        let mut k = 0usize;
        let mut uploaded = Vec::new();
        let mut phases = [Vec::new(), Vec::new(), Vec::new()];
        for _ in 0..batches * 4 {
            let t0 = super::sculpt::thread_cpu_ns().unwrap_or(0);
            let _ = black_box(doc.apply(&segment(k, circle)));
            let t1 = super::sculpt::thread_cpu_ns().unwrap_or(0);
            let generation = cache.generation();
            cache.refresh(&doc, true);
            let t2 = super::sculpt::thread_cpu_ns().unwrap_or(0);
            let display = cache.display();
            let mut count = 0usize;
            match cache.vertex_ranges_since(generation) {
                Some(ranges) => {
                    for r in ranges {
                        count +=
                            black_box(surface_vertices(&display.mesh, &display.seam_heat, r)).len();
                    }
                }
                None => {
                    let all = 0..display.mesh.positions.len() as u32;
                    count +=
                        black_box(surface_vertices(&display.mesh, &display.seam_heat, all)).len();
                }
            }
            let t3 = super::sculpt::thread_cpu_ns().unwrap_or(0);
            uploaded.push(count as f64);
            for (p, t) in phases.iter_mut().zip([t1 - t0, t2 - t1, t3 - t2]) {
                p.push(t as f64);
            }
            k += 1;
        }
        let live_frame = cpu_median_ns(batches, 2, |_| {
            let _ = black_box(doc.apply(&segment(k, circle)));
            let generation = cache.generation();
            cache.refresh(&doc, true);
            let display = cache.display();
            let all = 0..display.mesh.positions.len() as u32;
            match cache.vertex_ranges_since(generation) {
                Some(ranges) => {
                    for r in ranges {
                        black_box(surface_vertices(&display.mesh, &display.seam_heat, r));
                    }
                }
                None => {
                    black_box(surface_vertices(&display.mesh, &display.seam_heat, all));
                }
            }
            k += 1;
        });
        doc.end_stroke();
        // Full: the same deformation, everything rebuilt.
        let mut doc = Document::new(model);
        doc.begin_stroke("draw a line");
        let mut j = 0usize;
        let full_frame = cpu_median_ns(batches.min(9), 1, |_| {
            let _ = black_box(doc.apply(&segment(j, circle)));
            let display =
                SurfaceDisplay::new(&doc.model().surface.patches(), &Tessellation::DISPLAY);
            let all = 0..display.mesh.positions.len() as u32;
            black_box(surface_vertices(&display.mesh, &display.seam_heat, all));
            j += 1;
        });
        let [mut deform, mut tess, mut upload] = phases;
        table.row(vec![
            format!("plane {n}x{n}"),
            (n * n).to_string(),
            format_ns(super::median(&mut deform)),
            format_ns(super::median(&mut tess)),
            format_ns(super::median(&mut upload)),
            format_ns(live_frame),
            format_ns(full_frame),
            format!("{:.1}", full_frame / live_frame),
            format!("{:.0}", super::median(&mut uploaded)),
        ]);
    }
    format!(
        "Live-stroke frames (CPU time; upload = building the changed vertices for the GPU, no adapter needed):\n{}",
        table.render()
    )
}

/// Uniform numbers from a seed (SplitMix64): the same strokes in every run.
#[derive(Debug, Clone)]
pub struct Strokes(u64);

impl Strokes {
    /// A sequence from `seed`.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// A number in `lo..hi`.
    pub fn gen_range(&mut self, range: std::ops::Range<f64>) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        let unit = (z >> 11) as f64 / (1u64 << 53) as f64;
        range.start + (range.end - range.start) * unit
    }
}

/// A typical stroke at a random point of the `n × n` plane (see the module docs).
pub fn typical_stroke(doc: &mut Document, rng: &mut Strokes, n: usize) {
    let h = n as f64 / 2.0;
    let at = DVec3::new(rng.gen_range(-h..h), rng.gen_range(-h..h), 0.0);
    let depth = rng.gen_range(-0.3..0.3);
    if rng.gen_range(0.0..1.0) < 0.5 {
        doc.begin_stroke(if depth < 0.0 { "pull" } else { "push" });
        for k in 1..=3 {
            doc.rewind_stroke();
            let op = Op::Push {
                at,
                dir: -DVec3::Z,
                depth: depth * f64::from(k) / 3.0,
                radius: 1.25,
            };
            let _ = doc.apply(&op);
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
        let snapshot = crate::app::history::model_bytes(&model);
        let mut doc = Document::new(model);
        let mut rng = Strokes::new(n as u64);
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
