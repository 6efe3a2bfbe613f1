//! The view's modes rendered headless (Mesa's lavapipe, or whatever adapter there is; with no
//! adapter the tests fail naming `mesa-vulkan-drivers`): the orthographic view of the plane
//! from the top, and the matcaps against their CPU formulas.
#![cfg(feature = "gui")]

use glam::{Vec2, Vec3};
use nendo::editor::scene::SurfaceDisplay;
use nendo::editor::{OrbitCamera, Projection, ViewPreset};
use nendo::mesh::Tessellation;
use nendo::render::matcap::srgb8;
use nendo::render::{
    GpuContext, LineBatch, Matcap, OFFSCREEN_FORMAT, Offscreen, Renderer, RgbaImage, Style,
};
use nendo::surface::{PatchPoints, Primitive, PrimitiveParams};

const SIZE: [u32; 2] = [320, 240];

fn pixel(image: &RgbaImage, x: u32, y: u32) -> [u8; 3] {
    let i = 4 * (y * image.width + x) as usize;
    [image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]]
}

fn draw(
    gpu: &GpuContext,
    patches: &[PatchPoints],
    camera: &OrbitCamera,
    style: &Style,
) -> RgbaImage {
    let display = SurfaceDisplay::new(patches, &Tessellation::DISPLAY);
    let mut renderer = Renderer::new(&gpu.device, OFFSCREEN_FORMAT, 1);
    renderer.set_surface(&gpu.device, &gpu.queue, &display.mesh, &display.seam_heat);
    renderer.set_lines(&gpu.device, &gpu.queue, &LineBatch::new());
    let aspect = SIZE[0] as f32 / SIZE[1] as f32;
    renderer.prepare(
        &gpu.queue,
        &camera.view(aspect),
        style,
        [SIZE[0] as f32, SIZE[1] as f32],
    );
    Offscreen::new(&gpu.device, SIZE, 1)
        .render(gpu, &renderer)
        .expect("offscreen frame")
}

/// The flat plane seen from the top in orthographic projection is a uniform silhouette
/// square of the size the half height `h = d tan(φ/2)` gives: `10 / 2h` of the image's height.
#[test]
fn the_plane_from_the_top_in_orthographic_is_a_uniform_square() {
    let gpu = GpuContext::headless().unwrap_or_else(|e| panic!("{e}"));
    let plane = Primitive::Plane
        .build(&PrimitiveParams::default())
        .expect("plane")
        .patches();
    let display = SurfaceDisplay::new(&plane, &Tessellation::DISPLAY);
    let aspect = SIZE[0] as f32 / SIZE[1] as f32;
    let mut camera = OrbitCamera::framing(ViewPreset::Top, &display.mesh.positions, aspect);
    camera.projection = Projection::Orthographic;
    camera.frame(&display.mesh.positions, aspect);
    let image = draw(&gpu, &plane, &camera, &Style::default());
    // Clay: pixels unlike the background's (a vertical gradient: column 0 of the same row).
    let mut clay = Vec::new();
    for y in 0..SIZE[1] {
        let background = pixel(&image, 0, y);
        for x in 0..SIZE[0] {
            let p = pixel(&image, x, y);
            if p.iter().zip(background).any(|(a, b)| a.abs_diff(b) > 12) {
                clay.push((x, y, p));
            }
        }
    }
    let (x0, x1) = clay
        .iter()
        .fold((u32::MAX, 0), |(a, b), c| (a.min(c.0), b.max(c.0)));
    let (y0, y1) = clay
        .iter()
        .fold((u32::MAX, 0), |(a, b), c| (a.min(c.1), b.max(c.1)));
    let (w, h) = (x1 - x0 + 1, y1 - y0 + 1);
    let expected = 10.0 / (2.0 * camera.half_height()) * SIZE[1] as f32;
    eprintln!("ortho plane: {w} x {h} pixels, expected {expected:.1}");
    assert!((w as f32 - expected).abs() <= 1.5 && (h as f32 - expected).abs() <= 1.5);
    assert_eq!(clay.len() as u32, w * h, "a full square, no holes");
    let first = clay[0].2;
    let spread = clay
        .iter()
        .map(|c| {
            c.2.iter()
                .zip(first)
                .map(|(a, b)| a.abs_diff(b))
                .max()
                .unwrap_or(0)
        })
        .max()
        .unwrap_or(0);
    assert!(spread <= 1, "uniform: channels differ by up to {spread}");
}

/// Each matcap drawn on a sculpted sphere is its CPU formula of the view-space normal: at
/// pixels picked through the camera (the surface's exact normal there), in both projections;
/// the three matcaps and the lit shading differ.
#[test]
fn matcaps_render_their_formulas() {
    let gpu = GpuContext::headless().unwrap_or_else(|e| panic!("{e}"));
    let sphere = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .expect("sphere")
        .patches();
    let display = SurfaceDisplay::new(&sphere, &Tessellation::DISPLAY);
    let aspect = SIZE[0] as f32 / SIZE[1] as f32;
    let size = Vec2::new(SIZE[0] as f32, SIZE[1] as f32);
    let mut centre = Vec::new();
    for projection in [Projection::Orthographic, Projection::Perspective] {
        let mut camera = OrbitCamera::framing(ViewPreset::Iso, &display.mesh.positions, aspect);
        camera.projection = projection;
        camera.frame(&display.mesh.positions, aspect);
        let (r, u, e) = (camera.right(), camera.up(), camera.to_eye());
        for matcap in Matcap::ALL {
            let style = Style {
                matcap: Some(matcap),
                ..Style::default()
            };
            let image = draw(&gpu, &sphere, &camera, &style);
            let (mut checked, mut worst) = (0, 0u8);
            for y in (8..SIZE[1]).step_by(9) {
                for x in (8..SIZE[0]).step_by(9) {
                    let centre_ray = camera.ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), size);
                    let Some(hit) = nendo::mesh::pick(&sphere, &display.mesh, &centre_ray) else {
                        continue;
                    };
                    let mut n = hit.normal.as_vec3();
                    if n.dot(centre_ray.direction.as_vec3()) > 0.0 {
                        n = -n;
                    }
                    let view = Vec3::new(n.dot(r), n.dot(u), n.dot(e));
                    if view.z < 0.35 {
                        continue; // near the silhouette the pixel mixes tessellation error
                    }
                    let want = matcap.colour(view).to_array().map(srgb8);
                    let got = pixel(&image, x, y);
                    let d = want
                        .iter()
                        .zip(got)
                        .map(|(a, b)| a.abs_diff(b))
                        .max()
                        .unwrap_or(0);
                    worst = worst.max(d);
                    checked += 1;
                }
            }
            eprintln!(
                "{projection:?} {matcap}: {checked} pixels, largest channel difference {worst}/255"
            );
            assert!(checked > 100, "{checked}");
            assert!(worst <= 6, "{matcap}: {worst}/255 off its formula");
            if projection == Projection::Orthographic {
                centre.push(pixel(&image, SIZE[0] / 2, SIZE[1] / 2));
            }
        }
    }
    let lit = {
        let mut camera = OrbitCamera::framing(ViewPreset::Iso, &display.mesh.positions, aspect);
        camera.projection = Projection::Orthographic;
        camera.frame(&display.mesh.positions, aspect);
        draw(&gpu, &sphere, &camera, &Style::default())
    };
    centre.push(pixel(&lit, SIZE[0] / 2, SIZE[1] / 2));
    for (i, a) in centre.iter().enumerate() {
        for b in &centre[i + 1..] {
            let d = a
                .iter()
                .zip(b)
                .map(|(x, y)| x.abs_diff(*y))
                .max()
                .unwrap_or(0);
            assert!(d > 8, "shadings differ: {a:?} {b:?}");
        }
    }
}

/// `nendo render --ortho --matcap NAME` draws headless and says it was orthographic; a name
/// that is no matcap is refused, naming the ones there are.
#[test]
fn render_draws_orthographic_with_a_matcap() {
    let dir = crate::support::temp_dir("render-ortho-matcap");
    let model = dir.join("plane.json");
    let plane = Primitive::Plane
        .build(&PrimitiveParams::default())
        .expect("plane");
    std::fs::write(&model, nendo::model::Model::new(plane).to_json_string()).expect("model");
    let png = dir.join("out.png");
    let (model_s, png_s) = (model.display().to_string(), png.display().to_string());
    let out = crate::support::run(&[
        "render",
        &model_s,
        "--png",
        &png_s,
        "--size",
        "160x120",
        "--ortho",
        "--matcap",
        "red-wax",
        "--view",
        "top",
        "--no-edges",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("from top (orthographic)"), "{stderr}");
    let image = RgbaImage::read_png(&std::fs::read(&png).expect("png")).expect("decodes");
    let centre = pixel(&image, 80, 60);
    // The plane faces the viewer: the matcap's colour at the view-space normal (0, 0, 1).
    let want = Matcap::RedWax.colour(Vec3::Z).to_array().map(srgb8);
    let d = want.iter().zip(centre).map(|(a, b)| a.abs_diff(b)).max();
    assert!(d <= Some(1), "red wax: {centre:?}, its formula {want:?}");
    let out = crate::support::run(&["render", &model_s, "--png", &png_s, "--matcap", "chrome"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("expected clay, red-wax or soft-grey"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
