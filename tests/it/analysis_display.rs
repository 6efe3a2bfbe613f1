//! The analysis display modes (zebra, curvature, isophotes) from the patches' exact
//! derivatives: the stripe phase on the CPU with the shader's formula, and the rendered image
//! on the software Vulkan driver (no adapter: the test fails naming `mesa-vulkan-drivers`).
//!
//! The surface: two bicubic patches meeting at `x = 0`, exactly the twisted plane
//! `z = k x y` over `[−1, 1]²` (G1 — in fact C∞ — across the seam), and the same with the
//! right patch's first interior column lifted so that the normals differ by 1° at the seam's
//! middle (a crease). Stripes around the screen's vertical (close to the seam's direction)
//! cross the seam, and a crease of `α` shifts them by up to `2α · s / 180°` periods.
#![cfg(feature = "gui")]

use glam::{DVec3, Vec3};
use nendo::editor::scene::SurfaceDisplay;
use nendo::mesh::Tessellation;
use nendo::render::display_mode::{AnalysisUniform, zebra_basis, zebra_phase};
use nendo::render::{
    CurvatureKind, GpuContext, OFFSCREEN_FORMAT, Offscreen, Renderer, RgbaImage, Style,
    SurfaceAnalysis, SurfaceMode, View, look_at_view,
};
use nendo::surface::{Patch, Primitive, PrimitiveParams};

const SIZE: [u32; 2] = [320, 320];
const TWIST: f64 = 0.4;
const STRIPES: f32 = 20.0;
const EYE: Vec3 = Vec3::new(0.0, -2.5, 4.5);

/// The two patches of `z = k x y`; with `crease_deg`, the right patch's column `i = 1` lifted
/// by `tan(α)/3`, which turns its slope across the seam by `α` at `y = 0`.
fn twisted_pair(crease_deg: f64) -> Vec<[DVec3; 16]> {
    let patch = |x0: f64, lift: f64| {
        let mut p = [DVec3::ZERO; 16];
        for i in 0..4 {
            for j in 0..4 {
                let x = x0 + i as f64 / 3.0;
                let y = -1.0 + 2.0 * j as f64 / 3.0;
                let extra = if i == 1 { lift } else { 0.0 };
                p[4 * i + j] = DVec3::new(x, y, TWIST * x * y + extra);
            }
        }
        p
    };
    vec![
        patch(-1.0, 0.0),
        patch(0.0, crease_deg.to_radians().tan() / 3.0),
    ]
}

fn view() -> View {
    look_at_view(EYE, Vec3::ZERO, 0.7, SIZE[0] as f32 / SIZE[1] as f32)
}

fn zebra() -> SurfaceAnalysis {
    SurfaceAnalysis {
        mode: SurfaceMode::Zebra,
        stripes: STRIPES,
        stripe_angle_deg: 0.0,
        ..SurfaceAnalysis::default()
    }
}

/// The stripe phase on both sides of the seam at `k` points along it, with the shader's
/// formula in `f64`: `(left, right)` per point.
fn phases_across_seam(patches: &[[DVec3; 16]], k: usize) -> Vec<(f64, f64)> {
    let (left, right) = (Patch::new(patches[0]), Patch::new(patches[1]));
    let basis = zebra_basis(view().world_from_view, 0.0);
    let eye = EYE.as_dvec3();
    (1..k)
        .map(|i| {
            let t = i as f64 / k as f64;
            let (pl, pr) = (left.eval(1.0, t), right.eval(0.0, t));
            assert!((pl - pr).length() < 1e-12, "the patches share the seam");
            let nl = left.normal(1.0, t).expect("regular");
            let nr = right.normal(0.0, t).expect("regular");
            (
                zebra_phase(pl, nl, eye, basis, f64::from(STRIPES)),
                zebra_phase(pr, nr, eye, basis, f64::from(STRIPES)),
            )
        })
        .collect()
}

#[test]
fn the_stripe_phase_is_continuous_across_g1_and_jumps_across_a_1_degree_crease() {
    let smooth = twisted_pair(0.0);
    let creased = twisted_pair(1.0);
    // The crease is 1° where it is made (G1 angle of the seam's middle).
    let display = SurfaceDisplay::new(&creased, &Tessellation::DISPLAY);
    assert!(
        (0.9..=1.001).contains(&display.max_seam_deg),
        "creased by {}°",
        display.max_seam_deg
    );
    let g1 = phases_across_seam(&smooth, 64);
    let worst_g1 = g1.iter().map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(worst_g1 < 1e-9, "G1 seam: phase jump {worst_g1} periods");
    // Along the seam the phase runs over several periods: the stripes cross it.
    let run = g1.last().expect("samples").0 - g1[0].0;
    assert!(run.abs() > 3.0, "the stripes cross the seam: {run} periods");
    let crease = phases_across_seam(&creased, 64);
    let jumps: Vec<f64> = crease.iter().map(|(a, b)| (a - b).abs()).collect();
    let least = jumps.iter().copied().fold(f64::INFINITY, f64::min);
    // 2α s / 180° = 0.22 periods seen along the normal with the stripe axis along the seam;
    // more under this oblique view, and everywhere well within one period.
    assert!(
        least > 0.1 && jumps.iter().all(|j| *j < 0.5),
        "creased seam: jumps {least} .. {}",
        jumps.iter().copied().fold(0.0, f64::max)
    );
}

fn render(
    gpu: &GpuContext,
    renderer: &mut Renderer,
    patches: &[[DVec3; 16]],
    analysis: &SurfaceAnalysis,
) -> RgbaImage {
    let display = SurfaceDisplay::new(patches, &Tessellation::DISPLAY);
    renderer.set_surface(&gpu.device, &gpu.queue, &display.mesh, &display.seam_heat);
    renderer.set_analysis_patches(&gpu.device, &gpu.queue, patches, &display.mesh);
    let view = view();
    renderer.set_analysis(&gpu.queue, analysis, &view);
    renderer.prepare(
        &gpu.queue,
        &view,
        &Style::default(),
        [SIZE[0] as f32, SIZE[1] as f32],
    );
    Offscreen::new(&gpu.device, SIZE, 1)
        .render(gpu, renderer)
        .expect("offscreen frame")
}

fn luma(image: &RgbaImage, x: u32, y: u32) -> u32 {
    let i = 4 * (y * image.width + x) as usize;
    (u32::from(image.pixels[i]) + u32::from(image.pixels[i + 1]) + u32::from(image.pixels[i + 2]))
        / 3
}

/// The rows the seam covers (projected seam points `y = ±0.9`), and how many of them have
/// the pixels of columns `c − 1` and `c` in stripes of different brightness. The seam
/// (`x = 0`; the eye is at `x = 0`) runs between the image's two middle columns.
fn breaks_between(image: &RgbaImage, c: u32) -> (usize, usize) {
    let clip = view().clip_from_world;
    let row = |y: f32| {
        let p = clip * Vec3::new(0.0, y, 0.0).extend(1.0);
        ((1.0 - p.y / p.w) * 0.5 * SIZE[1] as f32) as u32
    };
    let (a, b) = (row(0.9), row(-0.9));
    let (top, bottom) = (a.min(b), a.max(b));
    let differing = (top..=bottom)
        .filter(|&y| (luma(image, c - 1, y) > 128) != (luma(image, c, y) > 128))
        .count();
    (differing, (bottom - top + 1) as usize)
}

/// `(rows broken across the seam, mean rows broken between two neighbouring columns away
/// from it, rows)`: the stripes change from one column to the next anyway (they run
/// obliquely); a break is what exceeds that.
fn stripe_breaks(image: &RgbaImage) -> (usize, f64, usize) {
    let mid = SIZE[0] / 2;
    let (seam, rows) = breaks_between(image, mid);
    let controls = [mid - 24, mid - 12, mid + 12, mid + 24];
    let control = controls
        .iter()
        .map(|&c| breaks_between(image, c).0 as f64)
        .sum::<f64>()
        / controls.len() as f64;
    (seam, control, rows)
}

#[test]
fn rendered_zebra_stripes_are_continuous_across_g1_and_broken_across_a_crease() {
    let gpu = GpuContext::headless().unwrap_or_else(|e| panic!("{e}"));
    eprintln!("rendering on {}", gpu.describe());
    let mut renderer = Renderer::new(&gpu.device, OFFSCREEN_FORMAT, 1);
    let smooth = render(&gpu, &mut renderer, &twisted_pair(0.0), &zebra());
    let creased = render(&gpu, &mut renderer, &twisted_pair(1.0), &zebra());
    if std::env::var_os("NENDO_KEEP_RENDER").is_some() {
        let dir = std::env::temp_dir();
        smooth
            .save_png(&dir.join("nendo-zebra-g1.png"))
            .expect("save");
        creased
            .save_png(&dir.join("nendo-zebra-crease.png"))
            .expect("save");
    }
    let (g1, g1_elsewhere, rows) = stripe_breaks(&smooth);
    let (crease, crease_elsewhere, _) = stripe_breaks(&creased);
    eprintln!(
        "rows with the stripes broken, of {rows}: G1 seam {g1} (neighbouring columns elsewhere \
         {g1_elsewhere:.1}), 1° crease {crease} (elsewhere {crease_elsewhere:.1})"
    );
    assert!(rows > 100, "the seam spans {rows} rows");
    // Both images are stripes: light and dark pixels in fair shares along the seam.
    for image in [&smooth, &creased] {
        let light = (0..SIZE[1])
            .filter(|&y| luma(image, SIZE[0] / 2, y) > 128)
            .count();
        assert!(
            light > 40 && light < 280,
            "{light} light pixels in the column"
        );
    }
    // G1: the seam is like any other pair of neighbouring columns.
    assert!(
        (g1 as f64) <= g1_elsewhere + rows as f64 / 20.0,
        "G1 seam: {g1} of {rows} rows broken, {g1_elsewhere:.1} elsewhere"
    );
    // A jump of 0.2 to 0.4 periods: light meets dark on a good share of the rows.
    assert!(
        crease as f64 >= crease_elsewhere + rows as f64 / 5.0 && crease >= 2 * g1.max(1),
        "creased seam: only {crease} of {rows} rows broken ({crease_elsewhere:.1} elsewhere)"
    );
}

/// The curvature map of the sphere primitive (radius 3) on the GPU reads `1/R` to the
/// patches' approximation of the sphere: with the range `1/R ± 20 %`, every pixel of the
/// sphere is the ramp's middle (cyan to yellow), none blue or red.
#[test]
fn the_rendered_curvature_map_of_a_sphere_reads_one_over_r() {
    let gpu = GpuContext::headless().unwrap_or_else(|e| panic!("{e}"));
    let mut renderer = Renderer::new(&gpu.device, OFFSCREEN_FORMAT, 1);
    let radius = 3.0f32;
    let sphere = Primitive::Sphere
        .build(&PrimitiveParams {
            radius: Some(f64::from(radius)),
            ..PrimitiveParams::default()
        })
        .expect("sphere")
        .patches();
    for kind in CurvatureKind::ALL {
        let expected = if kind == CurvatureKind::Gaussian {
            1.0 / (radius * radius)
        } else {
            1.0 / radius
        };
        let analysis = SurfaceAnalysis {
            mode: SurfaceMode::Curvature,
            kind,
            range: [0.8 * expected, 1.2 * expected],
            ..SurfaceAnalysis::default()
        };
        let display = SurfaceDisplay::new(&sphere, &Tessellation::DISPLAY);
        renderer.set_surface(&gpu.device, &gpu.queue, &display.mesh, &display.seam_heat);
        renderer.set_analysis_patches(&gpu.device, &gpu.queue, &sphere, &display.mesh);
        let view = look_at_view(Vec3::new(0.0, -12.0, 3.0), Vec3::ZERO, 0.6, 1.0);
        renderer.set_analysis(&gpu.queue, &analysis, &view);
        renderer.prepare(
            &gpu.queue,
            &view,
            &Style::default(),
            [SIZE[0] as f32, SIZE[1] as f32],
        );
        let image = Offscreen::new(&gpu.device, SIZE, 1)
            .render(&gpu, &renderer)
            .expect("offscreen frame");
        // The disc of the sphere inside 80 % of its projected radius.
        let centre = (SIZE[0] / 2, SIZE[1] / 2);
        let mut checked = 0;
        for y in 0..SIZE[1] {
            for x in 0..SIZE[0] {
                let (dx, dy) = (x as f32 - centre.0 as f32, y as f32 - centre.1 as f32);
                if dx.hypot(dy) > 0.8 * 0.5 * SIZE[0] as f32 * 0.45 {
                    continue;
                }
                let i = 4 * (y * SIZE[0] + x) as usize;
                let [r, g, b] = [image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]];
                // Blue end: b ≫ r, g; red end: r ≫ g, b. The middle has green above both.
                assert!(
                    g > 60 && g >= r / 2 && g >= b / 2,
                    "{kind}: pixel ({x}, {y}) reads {r} {g} {b}, not the middle of the range"
                );
                checked += 1;
            }
        }
        assert!(checked > 1000, "{kind}: {checked} pixels checked");
    }
}

#[test]
fn the_analysis_uniform_matches_the_shader() {
    let source = nendo::render::ANALYSIS_WGSL;
    let module = naga::front::wgsl::parse_str(source).expect("analysis.wgsl parses");
    let (_, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some("Analysis"))
        .expect("struct Analysis");
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("Analysis is not a struct");
    };
    let wgsl: Vec<(String, usize)> = members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize))
        .collect();
    use std::mem::offset_of;
    let rust: Vec<(String, usize)> = [
        ("e1", offset_of!(AnalysisUniform, e1)),
        ("mode", offset_of!(AnalysisUniform, mode)),
        ("e2", offset_of!(AnalysisUniform, e2)),
        ("kind", offset_of!(AnalysisUniform, kind)),
        ("stripes", offset_of!(AnalysisUniform, stripes)),
        ("range_lo", offset_of!(AnalysisUniform, range_lo)),
        ("range_hi", offset_of!(AnalysisUniform, range_hi)),
        ("isophotes", offset_of!(AnalysisUniform, isophotes)),
    ]
    .into_iter()
    .map(|(n, o)| (n.to_string(), o))
    .collect();
    assert_eq!(wgsl, rust);
    assert_eq!(*span as usize, std::mem::size_of::<AnalysisUniform>());
}
