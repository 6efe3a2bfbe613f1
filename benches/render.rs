#![forbid(unsafe_code)]
//! Tessellating 100 and 1 600 sculpted patches, and one headless 1280 × 720 frame of the
//! 10 × 10 plane.
//!
//! `cargo bench --bench render` first prints the table of `nendo bench render`, then runs the
//! criterion groups. The frame group needs a GPU adapter (Mesa's lavapipe:
//! `apt-get install mesa-vulkan-drivers`).

use criterion::{BenchmarkId, Criterion, criterion_group};
use nendo::editor::scene::SurfaceDisplay;
use nendo::editor::{OrbitCamera, ViewPreset};
use nendo::mesh::{Tessellation, tessellate};
use nendo::render::{GpuContext, LineBatch, OFFSCREEN_FORMAT, Offscreen, Renderer, Style};
use nendo_bench::render::sculpted_plane;
use std::hint::black_box;

fn benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("tessellate");
    for n in [10, 40] {
        let patches = sculpted_plane(n).patches();
        g.bench_function(BenchmarkId::new("display", n * n), |b| {
            b.iter(|| black_box(tessellate(black_box(&patches), &Tessellation::DISPLAY)))
        });
    }
    g.finish();

    let gpu = GpuContext::headless().unwrap_or_else(|e| panic!("{e}"));
    let patches = sculpted_plane(10).patches();
    let display = SurfaceDisplay::new(&patches, &Tessellation::DISPLAY);
    let mut lines = LineBatch::new();
    display.patch_edges(&mut lines);
    let mut renderer = Renderer::new(&gpu.device, OFFSCREEN_FORMAT, 4);
    renderer.set_surface(&gpu.device, &gpu.queue, &display.mesh, &display.seam_heat);
    renderer.set_lines(&gpu.device, &gpu.queue, &lines);
    let aspect = 1280.0 / 720.0;
    let view = OrbitCamera::framing(ViewPreset::Iso, &display.mesh.positions, aspect).view(aspect);
    renderer.prepare(&gpu.queue, &view, &Style::default(), [1280.0, 720.0]);
    let offscreen = Offscreen::new(&gpu.device, [1280, 720], 4);
    let mut g = c.benchmark_group("frame");
    g.sample_size(20);
    g.bench_function("plane 10x10 1280x720 msaa4", |b| {
        b.iter(|| {
            black_box(
                offscreen
                    .render(&gpu, &renderer)
                    .unwrap_or_else(|e| panic!("{e}")),
            )
        })
    });
    g.finish();
}

criterion_group!(group, benches);

fn main() {
    print!("{}", nendo_bench::render::report(0.5));
    group();
    Criterion::default().configure_from_args().final_summary();
}
