//! `nendo bench render`: what drawing the clay costs — CPU tessellation (with the seam heat
//! map) of 100 and 1 600 sculpted patches, and a whole headless frame at 1280 × 720 on the
//! adapter wgpu finds (Mesa's lavapipe on a machine without a GPU). Target: ≤ 150 ms per frame
//! for the 10 × 10 plane on the software renderer.
//!
//! Set-up: planes of 10 × 10 and 40 × 40 unit patches with one push (depth 0.4 side, finger
//! radius 1.25 side) at the centre of every 5 × 5 block of patches, so both carry the same
//! density of dents. Tessellation at the window's settings ([`Tessellation::DISPLAY`]) and at
//! the export default ([`Tessellation::EXPORT`]). A frame is: write the uniforms, draw the
//! background, the surface (4 samples per pixel, as the window draws) and the patch
//! boundaries, resolve, copy to a buffer and map it — the full offscreen path of
//! `nendo render` with the surface already uploaded; the upload is timed apart. Times are
//! medians over batches ([`super::Stopwatch`]).

use glam::DVec3;
use std::hint::black_box;

use super::{Stopwatch, Table};
use nendo::mesh::{PatchPoints, Tessellation, seam_angles_deg, seam_bands, tessellate};
use nendo::surface::{Grid, Op, Primitive, PrimitiveParams, Sculptor};

/// A sculpted plane of `n × n` unit patches (see the module docs).
///
/// # Panics
/// Never for `n ≥ 1` (the primitive and the pushes are valid).
#[must_use]
pub fn sculpted_plane(n: usize) -> Grid {
    let mut grid = Primitive::Plane
        .build(&PrimitiveParams {
            patches: Some((n, n)),
            ..PrimitiveParams::default()
        })
        .unwrap_or_else(|e| panic!("plane {n}: {e}"));
    let mut sculptor = Sculptor::new();
    let half = n as f64 / 2.0;
    for bx in 0..n.div_ceil(5) {
        for by in 0..n.div_ceil(5) {
            let at = DVec3::new(
                5.0 * bx as f64 + 2.5 - half,
                5.0 * by as f64 + 2.5 - half,
                0.0,
            );
            let op = Op::Push {
                at,
                dir: -DVec3::Z,
                depth: 0.4,
                radius: 1.25,
            };
            sculptor
                .apply(&mut grid, &op, Default::default())
                .unwrap_or_else(|e| panic!("push: {e}"));
        }
    }
    grid
}

/// The suite's table.
#[must_use]
pub fn report(scale: f64) -> String {
    let batches = ((15.0 * scale).round() as usize).max(3);
    let planes: Vec<(usize, Vec<PatchPoints>)> = [10, 40]
        .into_iter()
        .map(|n| (n, sculpted_plane(n).patches()))
        .collect();

    let mut table = Table::new(&["case", "patches", "triangles", "median ms"]);
    for (n, patches) in &planes {
        for (label, settings) in [
            ("display", Tessellation::DISPLAY),
            ("export", Tessellation::EXPORT),
        ] {
            let triangles = tessellate(patches, &settings).triangle_count();
            let ms = Stopwatch {
                batches,
                calls_per_batch: 1,
            }
            .median_ns(|_| {
                black_box(tessellate(black_box(patches), &settings));
            }) / 1e6;
            table.row(vec![
                format!("tessellate {n}x{n} ({label}, tol {})", settings.tolerance),
                patches.len().to_string(),
                triangles.to_string(),
                format!("{ms:.2}"),
            ]);
        }
        let ms = Stopwatch {
            batches,
            calls_per_batch: 1,
        }
        .median_ns(|_| {
            let mesh = tessellate(black_box(patches), &Tessellation::DISPLAY);
            let angles = seam_angles_deg(black_box(patches), &mesh);
            black_box(seam_bands(&mesh, &angles, 0.15));
        }) / 1e6;
        table.row(vec![
            format!("tessellate + seam heat {n}x{n} (display)"),
            patches.len().to_string(),
            String::new(),
            format!("{ms:.2}"),
        ]);
    }
    let mut out = table.render();
    #[cfg(feature = "gui")]
    {
        out.push('\n');
        out.push_str(&frames(&planes, batches));
    }
    #[cfg(not(feature = "gui"))]
    out.push_str("(frame times need the `gui` feature)\n");
    out
}

/// Headless frame times at 1280 × 720.
#[cfg(feature = "gui")]
fn frames(planes: &[(usize, Vec<PatchPoints>)], batches: usize) -> String {
    use nendo::editor::scene::SurfaceDisplay;
    use nendo::editor::{OrbitCamera, ViewPreset};
    use nendo::render::{GpuContext, LineBatch, OFFSCREEN_FORMAT, Offscreen, Renderer, Style};

    let gpu = match GpuContext::headless() {
        Ok(g) => g,
        Err(e) => return format!("frame times: {e}\n"),
    };
    let size = [1280u32, 720u32];
    let aspect = size[0] as f32 / size[1] as f32;
    let mut table = Table::new(&[
        "frame 1280x720",
        "samples",
        "triangles",
        "upload ms",
        "median frame ms",
    ]);
    for samples in [4u32, 1] {
        let mut renderer = Renderer::new(&gpu.device, OFFSCREEN_FORMAT, samples);
        let offscreen = Offscreen::new(&gpu.device, size, samples);
        for (n, patches) in planes {
            let display = SurfaceDisplay::new(patches, &Tessellation::DISPLAY);
            let mut lines = LineBatch::new();
            display.patch_edges(&mut lines);
            let upload_ms = Stopwatch {
                batches: batches.min(5),
                calls_per_batch: 1,
            }
            .median_ns(|_| {
                renderer.set_surface(&gpu.device, &gpu.queue, &display.mesh, &display.seam_heat);
                renderer.set_lines(&gpu.device, &gpu.queue, &lines);
            }) / 1e6;
            let camera = OrbitCamera::framing(ViewPreset::Iso, &display.mesh.positions, aspect);
            let view = camera.view(aspect);
            let style = Style {
                heat_map: true,
                ..Style::default()
            };
            let mut failure = None;
            let ms = Stopwatch {
                batches,
                calls_per_batch: 1,
            }
            .median_ns(|_| {
                renderer.prepare(&gpu.queue, &view, &style, [size[0] as f32, size[1] as f32]);
                if let Err(e) = offscreen.render(&gpu, &renderer) {
                    failure = Some(e);
                }
            }) / 1e6;
            let frame = match failure {
                Some(e) => format!("failed: {e}"),
                None => format!("{ms:.1}"),
            };
            table.row(vec![
                format!("plane {n}x{n}"),
                samples.to_string(),
                display.mesh.triangle_count().to_string(),
                format!("{upload_ms:.2}"),
                frame,
            ]);
        }
    }
    format!("adapter: {}\n{}", gpu.describe(), table.render())
}
