//! `nendo render MODEL.json --png OUT.png [--size WxH] [--view iso] [--ortho] [--display zebra]
//! [--matcap red-wax]`: draws a model headless with the window's renderer (offscreen, on any
//! wgpu adapter — Mesa's lavapipe without a GPU), in clay (lit or with a matcap,
//! [`crate::render::matcap`]) or an analysis mode ([`crate::render::display_mode`]), in
//! perspective or orthographic projection ([`crate::editor::camera`]); a curvature map gets
//! its legend drawn into the image ([`crate::render::legend`]).

use clap::Args as ClapArgs;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use super::arg_error::ArgError;
use crate::editor::ViewPreset;
use crate::editor::scene::{Overlays, SurfaceDisplay, framing_points, model_lines};
use crate::mesh::Tessellation;
use crate::model::Model;
use crate::render::display_mode::auto_range;
use crate::render::{
    CurvatureKind, GpuContext, LineBatch, Matcap, OFFSCREEN_FORMAT, Offscreen, Renderer, Style,
    SurfaceAnalysis, SurfaceMode,
};

/// Arguments of `nendo render`.
#[derive(Debug, Clone, ClapArgs)]
pub struct RenderArgs {
    /// The model (nendo-model JSON).
    pub model: PathBuf,
    /// Where to write the image.
    #[arg(long, value_name = "OUT.png")]
    pub png: PathBuf,
    /// Image size in pixels, `WIDTHxHEIGHT`.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Where to look from: front, back, left, right, top, bottom, iso.
    #[arg(long, default_value = "iso")]
    pub view: ViewPreset,
    /// Orthographic projection (parallel rays) instead of perspective, framed to fit.
    #[arg(long)]
    pub ortho: bool,
    /// Shade the clay with a matcap instead of the lights: clay, red-wax or soft-grey.
    #[arg(long, value_name = "NAME")]
    pub matcap: Option<Matcap>,
    /// Colour the seams by their G1 error.
    #[arg(long)]
    pub heat: bool,
    /// Seam angle drawn red, degrees (with `--heat-g2`: the mismatch drawn red, percent).
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub heat_max: f32,
    /// The heat map shows the G2 (curvature) mismatch across the seams, percent, instead of
    /// the G1 angle.
    #[arg(long, requires = "heat")]
    pub heat_g2: bool,
    /// Draw the control net.
    #[arg(long)]
    pub control_net: bool,
    /// Leave out the patch boundaries.
    #[arg(long)]
    pub no_edges: bool,
    /// Samples per pixel (1 or 4).
    #[arg(long, default_value_t = 4, value_parser = parse_samples)]
    pub samples: u32,
    /// How the surface is drawn: clay, zebra, curvature or isophotes (from the patches' exact
    /// derivatives per pixel); a curvature map carries its legend (colour bar, range) at the
    /// image's top right.
    #[arg(long, default_value = "clay")]
    pub display: SurfaceMode,
    /// The curvature a `--display curvature` map shows: mean, gaussian or max.
    #[arg(long, default_value = "mean")]
    pub curvature: CurvatureKind,
    /// The curvature map's range `LO:HI` (default: the 2nd to 98th percentile on the model).
    #[arg(long, value_name = "LO:HI", value_parser = parse_range, allow_hyphen_values = true)]
    pub range: Option<[f32; 2]>,
    /// Zebra: light stripes per 180° of reflected direction.
    #[arg(long, default_value_t = 12.0)]
    pub stripes: f32,
    /// Zebra: stripe direction, degrees from the screen's vertical.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub stripe_angle: f32,
}

/// Parses a curvature range `LO:HI` (finite, `LO < HI`).
fn parse_range(s: &str) -> Result<[f32; 2], String> {
    let bad = || format!("{s:?}: expected LO:HI with LO < HI, e.g. -0.5:0.5");
    let (lo, hi) = s.split_once(':').ok_or_else(bad)?;
    let lo: f32 = lo.trim().parse().map_err(|_| bad())?;
    let hi: f32 = hi.trim().parse().map_err(|_| bad())?;
    if lo.is_finite() && hi.is_finite() && lo < hi {
        Ok([lo, hi])
    } else {
        Err(bad())
    }
}

/// Parses a sample count: 1 or 4 (what every adapter supports).
fn parse_samples(s: &str) -> Result<u32, ArgError> {
    match s.trim() {
        "1" => Ok(1),
        "4" => Ok(4),
        _ => Err(ArgError::Samples(s.to_owned())),
    }
}

/// Parses `WIDTHxHEIGHT` (each 1..=8192).
fn parse_size(s: &str) -> Result<(u32, u32), ArgError> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| ArgError::NotASize {
        value: s.to_owned(),
        example: "1280x720",
    })?;
    let parse = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=8192).contains(n))
    };
    match (parse(w), parse(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => Err(ArgError::RenderSize(s.to_owned())),
    }
}

/// Runs `nendo render`.
pub fn run(args: RenderArgs) -> ExitCode {
    match render(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("nendo render: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn render(args: &RenderArgs) -> anyhow::Result<()> {
    if !(args.heat_max.is_finite() && args.heat_max > 0.0) {
        anyhow::bail!(
            "--heat-max must be a positive angle in degrees, not {}",
            crate::num::Compact(f64::from(args.heat_max))
        );
    }
    super::paths::check(
        &[("--png", Some(&args.png))],
        &[("model", Some(&args.model))],
    )?;
    let loaded = Model::read(&args.model).map_err(|e| anyhow::anyhow!(e.in_file(&args.model)))?;
    let model = loaded.model;
    let patches = model.surface.patches();
    let display = SurfaceDisplay::new(&patches, &Tessellation::DISPLAY);
    let overlays = Overlays {
        patch_edges: !args.no_edges,
        control_net: args.control_net,
        heat_map: args.heat,
        heat_max_deg: args.heat_max,
        control_polygons: true,
    };
    let mut lines = LineBatch::new();
    model_lines(&model, &patches, &display, &overlays, &mut lines);

    let start = Instant::now();
    let gpu = GpuContext::headless()?;
    let mut renderer = Renderer::new(&gpu.device, OFFSCREEN_FORMAT, args.samples);
    if args.heat_g2 {
        let g2 = crate::mesh::seam_g2_percent(&patches, &display.mesh);
        eprintln!(
            "largest G2 seam mismatch {}%",
            crate::num::Compact(f64::from(g2.iter().copied().fold(0.0, f32::max)))
        );
        let heat = crate::mesh::seam_bands(&display.mesh, &g2, SurfaceDisplay::HEAT_BAND);
        renderer.set_surface(&gpu.device, &gpu.queue, &display.mesh, &heat);
    } else {
        renderer.set_surface(&gpu.device, &gpu.queue, &display.mesh, &display.seam_heat);
    }
    renderer.set_lines(&gpu.device, &gpu.queue, &lines);
    if !(args.stripes.is_finite() && args.stripes > 0.0 && args.stripe_angle.is_finite()) {
        anyhow::bail!("--stripes must be a positive number and --stripe-angle a finite angle");
    }
    let range = match args.range {
        Some(r) => r,
        None => auto_range(&patches, args.curvature).unwrap_or([-1.0, 1.0]),
    };
    let analysis = SurfaceAnalysis {
        mode: args.display,
        kind: args.curvature,
        range,
        stripes: args.stripes,
        stripe_angle_deg: args.stripe_angle,
        ..SurfaceAnalysis::default()
    };
    if analysis.mode != SurfaceMode::Clay {
        renderer.set_analysis_patches(&gpu.device, &gpu.queue, &patches, &display.mesh);
    }
    let (w, h) = args.size;
    let aspect = w as f32 / h as f32;
    let points = framing_points(&model, &patches, &display, &overlays);
    let mut camera = crate::editor::OrbitCamera::framing(args.view, &points, aspect);
    if args.ortho {
        camera.projection = crate::editor::Projection::Orthographic;
        camera.frame(&points, aspect);
    }
    let style = Style {
        heat_map: args.heat,
        heat_max_deg: args.heat_max,
        matcap: args.matcap,
        ..Style::default()
    };
    let view = camera.view(aspect);
    renderer.set_analysis(&gpu.queue, &analysis, &view);
    renderer.prepare(&gpu.queue, &view, &style, [w as f32, h as f32]);
    let mut image = Offscreen::new(&gpu.device, [w, h], args.samples).render(&gpu, &renderer)?;
    let legend = if analysis.mode == SurfaceMode::Curvature {
        let drawn = crate::render::legend::draw_legend(
            &mut image.pixels,
            image.width,
            image.height,
            range,
            analysis.kind,
        );
        if drawn.is_none() {
            eprintln!("the image is too small for the curvature legend: none drawn");
        }
        drawn
    } else {
        None
    };
    image.save_png(&args.png)?;
    eprintln!(
        "{}: {}x{} from {}{}, {} patches, {} triangles, on {} in {:.0} ms",
        args.png.display(),
        w,
        h,
        args.view,
        if args.ortho { " (orthographic)" } else { "" },
        patches.len(),
        display.mesh.triangle_count(),
        gpu.describe(),
        start.elapsed().as_secs_f64() * 1e3
    );
    if analysis.mode == SurfaceMode::Curvature {
        eprintln!(
            "{} curvature map: blue {} .. red {}",
            analysis.kind,
            crate::num::Compact(f64::from(range[0])),
            crate::num::Compact(f64::from(range[1]))
        );
    }
    if let Some(l) = legend {
        eprintln!(
            "legend: bar {}x{} at ({}, {}), labels {}",
            l.bar.width,
            l.bar.height,
            l.bar.x,
            l.bar.y,
            l.labels
                .iter()
                .map(|(t, _)| t.as_str())
                .collect::<Vec<_>>()
                .join(" | ")
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn size_and_samples_fail_with_typed_errors_and_the_same_messages() {
        let e = parse_samples("2").unwrap_err();
        assert!(matches!(e, ArgError::Samples(_)), "{e:?}");
        assert_eq!(e.to_string(), "\"2\": samples per pixel must be 1 or 4");
        assert_eq!(parse_samples("4").ok(), Some(4));
        let e = parse_size("1280").unwrap_err();
        assert!(matches!(e, ArgError::NotASize { .. }), "{e:?}");
        assert_eq!(
            e.to_string(),
            "\"1280\": expected WIDTHxHEIGHT, e.g. 1280x720"
        );
        let e = parse_size("9000x10").unwrap_err();
        assert!(matches!(e, ArgError::RenderSize(_)), "{e:?}");
        assert_eq!(
            e.to_string(),
            "\"9000x10\": width and height must be whole numbers from 1 to 8192"
        );
        assert_eq!(parse_size("640x480").ok(), Some((640, 480)));
    }
}
