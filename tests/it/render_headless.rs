//! Headless rendering on the software Vulkan driver (Mesa's lavapipe) or whatever adapter
//! there is, compared with stored reference images.
//!
//! One GPU device serves every scene (creating one costs ~0.3 s). With no adapter the test
//! fails with a message naming `mesa-vulkan-drivers`; it never passes silently.
//!
//! References live in `tests/data/render/`; `NENDO_BLESS_RENDER=1` rewrites them from the
//! current output (then inspect them before committing). Thresholds, per image: mean absolute
//! difference over all channels at most [`MAX_MEAN_ABS`] (of 255), and at most
//! [`MAX_BAD_FRACTION`] of the pixels with a channel off by more than [`BAD_PIXEL`] — enough
//! for rasterisation differences between Mesa versions along edges, not for a change of
//! shading, framing or geometry.
#![cfg(feature = "gui")]

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec2, Vec3};
use nendo::editor::scene::{SurfaceDisplay, control_net, curve};
use nendo::editor::{OrbitCamera, ViewPreset};
use nendo::mesh::Tessellation;
use nendo::render::{
    GpuContext, LineBatch, OFFSCREEN_FORMAT, Offscreen, RenderError, Renderer, RgbaImage,
    SphereInstance, Style, ToolFootprint,
};
use nendo::surface::{Grid, Primitive, PrimitiveParams, Topology};

const MAX_MEAN_ABS: f64 = 1.5;
const BAD_PIXEL: u8 = 32;
const MAX_BAD_FRACTION: f64 = 0.01;
const SIZE: [u32; 2] = [320, 240];
const SAMPLES: u32 = 4;

fn reference_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/render")
        .join(format!("{name}.png"))
}

/// `(mean absolute difference, fraction of pixels with a channel off by more than BAD_PIXEL)`.
fn compare(a: &RgbaImage, b: &RgbaImage) -> (f64, f64) {
    assert_eq!(
        (a.width, a.height),
        (b.width, b.height),
        "image sizes differ"
    );
    let mut sum = 0u64;
    let mut bad = 0usize;
    for (p, q) in a.pixels.chunks_exact(4).zip(b.pixels.chunks_exact(4)) {
        let d: Vec<u8> = p.iter().zip(q).map(|(x, y)| x.abs_diff(*y)).collect();
        sum += d.iter().map(|x| u64::from(*x)).sum::<u64>();
        if d.iter().any(|x| *x > BAD_PIXEL) {
            bad += 1;
        }
    }
    let n = (a.width * a.height) as f64;
    (sum as f64 / (4.0 * n), bad as f64 / n)
}

fn check_against_reference(name: &str, image: &RgbaImage) {
    let path = reference_path(name);
    if std::env::var_os("NENDO_BLESS_RENDER").is_some() {
        image.save_png(&path).expect("write reference");
    }
    let bytes = std::fs::read(&path).unwrap_or_else(|e| {
        panic!(
            "reference {} unreadable ({e}); run with NENDO_BLESS_RENDER=1",
            path.display()
        )
    });
    let reference = RgbaImage::read_png(&bytes).expect("reference decodes");
    let (mean, bad) = compare(image, &reference);
    eprintln!(
        "{name}: mean abs diff {mean:.3}, bad pixels {:.3} %",
        100.0 * bad
    );
    if mean > MAX_MEAN_ABS || bad > MAX_BAD_FRACTION {
        let out = std::env::temp_dir().join(format!("nendo-{name}-actual.png"));
        let _ = image.save_png(&out);
        panic!(
            "{name}: mean abs diff {mean:.3} (max {MAX_MEAN_ABS}), bad pixels {:.3} % (max {} %); actual image in {}",
            100.0 * bad,
            100.0 * MAX_BAD_FRACTION,
            out.display()
        );
    }
}

fn pixel(image: &RgbaImage, x: u32, y: u32) -> [u8; 4] {
    let i = 4 * (y * image.width + x) as usize;
    [
        image.pixels[i],
        image.pixels[i + 1],
        image.pixels[i + 2],
        image.pixels[i + 3],
    ]
}

/// Renders `patches` framed from `preset`, with extra lines and spheres.
fn render(
    gpu: &GpuContext,
    renderer: &mut Renderer,
    patches: &[[DVec3; 16]],
    preset: ViewPreset,
    style: Style,
    extra: impl FnOnce(&mut LineBatch, &mut Vec<SphereInstance>),
) -> RgbaImage {
    let display = SurfaceDisplay::new(patches, &Tessellation::DISPLAY);
    let mut lines = LineBatch::new();
    display.patch_edges(&mut lines);
    let mut spheres = Vec::new();
    extra(&mut lines, &mut spheres);
    renderer.set_surface(&gpu.device, &gpu.queue, &display.mesh, &display.seam_heat);
    renderer.set_lines(&gpu.device, &gpu.queue, &lines);
    renderer.set_spheres(&gpu.device, &gpu.queue, &spheres);
    let aspect = SIZE[0] as f32 / SIZE[1] as f32;
    let camera = OrbitCamera::framing(preset, &display.mesh.positions, aspect);
    renderer.prepare(
        &gpu.queue,
        &camera.view(aspect),
        &style,
        [SIZE[0] as f32, SIZE[1] as f32],
    );
    Offscreen::new(&gpu.device, SIZE, SAMPLES)
        .render(gpu, renderer)
        .expect("offscreen frame")
}

/// The 10 × 10 plane with one grid vertex lifted: a bump whose seams are not G1.
fn creased_plane() -> Vec<[DVec3; 16]> {
    let plane = Primitive::Plane
        .build(&PrimitiveParams::default())
        .expect("plane");
    let mut nodes = plane.nodes().to_vec();
    let id = plane.node_id(15, 15).expect("an interior vertex");
    nodes[id] += DVec3::new(0.0, 0.0, 1.2);
    Grid::from_net(Topology::Plane, 10, 10, nodes)
        .expect("grid")
        .patches()
}

#[test]
fn no_adapter_fails_naming_the_package() {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::empty(),
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    let err = GpuContext::with_instance(instance, None).expect_err("no backend, no adapter");
    assert!(matches!(err, RenderError::NoAdapter(_)));
    assert!(err.to_string().contains("mesa-vulkan-drivers"), "{err}");
}

#[test]
fn scenes_match_their_references() {
    let gpu = GpuContext::headless().unwrap_or_else(|e| panic!("{e}"));
    eprintln!("rendering on {}", gpu.describe());
    let mut renderer = Renderer::new(&gpu.device, OFFSCREEN_FORMAT, SAMPLES);

    // The paper's sphere: 8 × 4 patches of radius 3, two poles.
    let sphere = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .expect("sphere")
        .patches();
    let image = render(
        &gpu,
        &mut renderer,
        &sphere,
        ViewPreset::Iso,
        Style::default(),
        |_, _| {},
    );
    // Clay in the middle, background in the corner.
    let [r, g, b, _] = pixel(&image, SIZE[0] / 2, SIZE[1] / 2);
    assert!(
        r > g && g > b && r > 100,
        "the centre is clay-coloured: {r} {g} {b}"
    );
    let [r, g, b, _] = pixel(&image, 2, 2);
    assert!(
        r.abs_diff(b) < 40 && r < 200,
        "the corner is background: {r} {g} {b}"
    );
    check_against_reference("sphere_iso", &image);

    // The exact sphere is G1 along every seam and at its poles: the seam readout is zero up to
    // rounding, and the heat map — even at its most sensitive (0.01° drawn red) — leaves the
    // clay exactly as it is without the heat map.
    let display = SurfaceDisplay::new(&sphere, &Tessellation::DISPLAY);
    assert!(
        display.max_seam_deg < 1e-6,
        "seam readout of an exact sphere: {}°",
        display.max_seam_deg
    );
    let heat = render(
        &gpu,
        &mut renderer,
        &sphere,
        ViewPreset::Iso,
        Style {
            heat_map: true,
            heat_max_deg: 0.01,
            ..Style::default()
        },
        |_, _| {},
    );
    let worst = heat
        .pixels
        .iter()
        .zip(&image.pixels)
        .map(|(a, b)| a.abs_diff(*b))
        .max()
        .unwrap_or(0);
    assert!(
        worst <= 1,
        "the heat map colours an exact sphere (a channel differs by {worst})"
    );

    // A creased plane with the heat map, the tool footprint, the control net, a curve and a
    // translucent probe sphere.
    let plane = creased_plane();
    let style = Style {
        heat_map: true,
        heat_max_deg: 30.0,
        tool: Some(ToolFootprint {
            center: Vec3::new(-2.0, -2.0, 0.0),
            axis: Vec3::Z,
            radius: 1.25,
        }),
        ..Style::default()
    };
    let image = render(
        &gpu,
        &mut renderer,
        &plane,
        ViewPreset::Iso,
        style,
        |lines, spheres| {
            control_net(&plane[..10], lines);
            let samples: Vec<DVec3> = (0..=32)
                .map(|k| {
                    DVec3::new(
                        -4.0 + 8.0 * k as f64 / 32.0,
                        3.0,
                        0.5 + (k as f64 * 0.3).sin() * 0.3,
                    )
                })
                .collect();
            curve(
                &samples,
                Some(&[samples[0], DVec3::new(0.0, 3.5, 1.5), samples[32]]),
                false,
                lines,
            );
            spheres.push(SphereInstance {
                center: [2.5, -1.5, 0.6],
                radius: 0.8,
                colour: [0.3, 0.6, 1.0, 0.35],
            });
            spheres.push(SphereInstance {
                center: [-4.0, 3.0, 0.5],
                radius: 0.15,
                colour: [0.9, 0.2, 0.1, 1.0],
            });
        },
    );
    check_against_reference("plane_heat_iso", &image);

    // Framing and orientation: from the top, the plane fills the view symmetrically.
    let flat = Primitive::Plane
        .build(&PrimitiveParams::default())
        .expect("plane")
        .patches();
    let image = render(
        &gpu,
        &mut renderer,
        &flat,
        ViewPreset::Top,
        Style::default(),
        |_, _| {},
    );
    let centre = pixel(&image, SIZE[0] / 2, SIZE[1] / 2);
    let left = pixel(&image, SIZE[0] / 2 - 60, SIZE[1] / 2);
    let right = pixel(&image, SIZE[0] / 2 + 60, SIZE[1] / 2);
    assert!(
        centre[0] > 100 && left[0] > 100 && right[0] > 100,
        "clay across the middle"
    );
    check_against_reference("plane_top", &image);

    // Picking through the same camera lands where the plane is drawn.
    let aspect = SIZE[0] as f32 / SIZE[1] as f32;
    let display = SurfaceDisplay::new(&flat, &Tessellation::DISPLAY);
    let camera = OrbitCamera::framing(ViewPreset::Top, &display.mesh.positions, aspect);
    let ray = camera.ray(
        Vec2::new(SIZE[0] as f32 / 2.0, SIZE[1] as f32 / 2.0),
        Vec2::new(SIZE[0] as f32, SIZE[1] as f32),
    );
    let hit = nendo::mesh::pick(&flat, &display.mesh, &ray).expect("the centre ray hits the plane");
    assert!(hit.point.truncate().length() < 1e-3, "{:?}", hit.point);
}
