//! Clean shading along creases and groove bottoms (issue 27): the shipped crease cases built
//! with `nendo sculpt`, rendered headless close up from several directions, show no isolated
//! dark pixels.
//!
//! The cause of the specks was the shader: it turned each pixel's interpolated normal towards
//! the eye by the sign of `n · (eye − x)`, so along a rim seen edge-on single pixels of a
//! visible triangle flipped to face away (ground light, no key light). The side seen is now the
//! triangle's own (`front_facing`, see `clay.wgsl`). What a close look still finds are faint
//! one-pixel shades of the relief itself — the crinkles of a groove drawn as dabs, 8 to 21
//! levels (of 255) darker than their neighbours, on a mesh whose vertex normals all agree with
//! their triangles — so a speck here is a pixel more than [`SPECK`] levels darker than all but
//! one of its eight neighbours.
#![cfg(feature = "gui")]

use glam::Vec3;
use nendo::editor::OrbitCamera;
use nendo::editor::scene::SurfaceDisplay;
use nendo::mesh::Tessellation;
use nendo::model::Model;
use nendo::render::{
    GpuContext, LineBatch, OFFSCREEN_FORMAT, Offscreen, Renderer, RgbaImage, Style,
};

use crate::support::{run_with_input, temp_dir};

const SIZE: [u32; 2] = [400, 300];
/// Samples per pixel, as the window draws.
const SAMPLES: u32 = 4;
/// How much darker than its neighbours a pixel is to count as a speck (of 255, mean of r, g, b).
const SPECK: f32 = 25.0;

/// The model `nendo sculpt` makes from `ops` on the default plane.
fn sculpted(name: &str, ops: &str, extra: &[&str]) -> Model {
    let dir = temp_dir(&format!("shading-{name}"));
    let out = dir.join(format!("{name}.json"));
    let out_s = out.to_str().expect("utf-8");
    let mut args = vec![
        "sculpt",
        "--primitive",
        "plane",
        "--ops",
        "-",
        "--out",
        out_s,
    ];
    args.extend_from_slice(extra);
    let o = run_with_input(&args, ops);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    Model::read(&out).expect("the model reads").model
}

/// A zig-zag path on the plane z = 0 through `corners`, a point every `step`.
fn path(corners: &[[f64; 2]], step: f64) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    for w in corners.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        let n = (len / step).ceil() as usize;
        for k in 0..n {
            let t = k as f64 / n as f64;
            out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), 0.0]);
        }
    }
    let last = corners[corners.len() - 1];
    out.push([last[0], last[1], 0.0]);
    out
}

/// The crease cases: the zig-zag groove of radius 0.375 and a deep fold pressed by two
/// overlapping pushes.
fn cases() -> Vec<(&'static str, Model, [Vec3; 2])> {
    let zig = path(
        &[
            [-3.0, 1.5],
            [-1.5, -1.5],
            [0.0, 1.5],
            [1.5, -1.5],
            [3.0, 1.5],
        ],
        0.075,
    );
    let groove = serde_json::json!({
        "op": "drag", "path": zig, "dir": [0, 0, -1], "depth": 0.33, "radius": 0.375
    });
    // Two fingertips of the hand pressed side by side, deep, with the clay between them
    // folded into a crease (as the Hand tool's index and middle fingers leave it).
    let mut fingers = String::new();
    for (x, y) in [(-2.65, -0.3), (-1.85, 0.3), (0.35, -0.2), (1.15, 0.2)] {
        let push = serde_json::json!({
            "op": "push", "at": [x, y, 0.0], "dir": [0, 0, -1], "depth": 0.45, "radius": 0.375
        });
        fingers.push_str(&format!("{push}\n"));
    }
    vec![
        (
            "zigzag",
            sculpted("zigzag", &format!("{groove}\n"), &["--auto-refine"]),
            // A leg, and a corner of the zig-zag.
            [Vec3::new(-2.25, 0.0, -0.2), Vec3::new(0.0, 1.2, -0.2)],
        ),
        (
            "fingers",
            sculpted("fingers", &fingers, &["--auto-refine"]),
            [Vec3::new(-2.25, 0.0, -0.2), Vec3::new(0.75, 0.0, -0.2)],
        ),
    ]
}

/// Pixels darker by more than `threshold` (of 255, mean of r, g, b) than all but one of
/// their eight neighbours: one-pixel (or two-pixel) dark specks.
fn specks(image: &RgbaImage, threshold: f32) -> Vec<(u32, u32, f32)> {
    let lum = |x: u32, y: u32| {
        let i = 4 * (y * image.width + x) as usize;
        (f32::from(image.pixels[i])
            + f32::from(image.pixels[i + 1])
            + f32::from(image.pixels[i + 2]))
            / 3.0
    };
    let mut out = Vec::new();
    for y in 1..image.height - 1 {
        for x in 1..image.width - 1 {
            let mut n: Vec<f32> = (0..9)
                .filter(|k| *k != 4)
                .map(|k| lum(x + k % 3 - 1, y + k / 3 - 1))
                .collect();
            n.sort_by(f32::total_cmp);
            if n[1] - lum(x, y) > threshold {
                out.push((x, y, n[1] - lum(x, y)));
            }
        }
    }
    out
}

#[test]
fn crease_cases_render_without_dark_specks() {
    let gpu = GpuContext::headless().unwrap_or_else(|e| panic!("{e}"));
    let mut renderer = Renderer::new(&gpu.device, OFFSCREEN_FORMAT, SAMPLES);
    let mut failures = Vec::new();
    for (name, model, targets) in cases() {
        let patches = model.surface.patches();
        let display = SurfaceDisplay::new(&patches, &Tessellation::DISPLAY);
        renderer.set_surface(&gpu.device, &gpu.queue, &display.mesh, &display.seam_heat);
        renderer.set_lines(&gpu.device, &gpu.queue, &LineBatch::new());
        let aspect = SIZE[0] as f32 / SIZE[1] as f32;
        let mut views = 0;
        for target in targets {
            for yaw in [0.0f32, 90.0, 200.0, 300.0] {
                for pitch in [25.0f32, 60.0] {
                    let camera = OrbitCamera {
                        target,
                        distance: 3.5,
                        yaw: yaw.to_radians(),
                        pitch: pitch.to_radians(),
                        ..OrbitCamera::default()
                    };
                    renderer.prepare(
                        &gpu.queue,
                        &camera.view(aspect),
                        &Style::default(),
                        [SIZE[0] as f32, SIZE[1] as f32],
                    );
                    let image = Offscreen::new(&gpu.device, SIZE, SAMPLES)
                        .render(&gpu, &renderer)
                        .expect("offscreen frame");
                    let found = specks(&image, SPECK);
                    if std::env::var_os("NENDO_SHADING_DUMP").is_some() {
                        let _ = image.save_png(
                            &std::env::temp_dir().join(format!("nendo-shading-{name}-{views}.png")),
                        );
                        eprintln!(
                            "{name} view {views}: {} specks {:?}",
                            found.len(),
                            &found[..found.len().min(10)]
                        );
                    }
                    if !found.is_empty() {
                        failures.push(format!(
                            "{name}, view {views} (yaw {yaw}, pitch {pitch}): {} specks, e.g. {:?}",
                            found.len(),
                            &found[..found.len().min(5)]
                        ));
                    }
                    views += 1;
                }
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
