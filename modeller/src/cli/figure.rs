//! `nendo figure fit | render | warp | measure | shape`: figures of metacircles in 2D (P0
//! §4.1–4.2) and metaball shapes fitted to sections (§4.3), headless.
//!
//! * `nendo figure fit IN.json --out FIG.json [--png P] [--svg S]`: fits metacircles to the
//!   contour of a figure file (seeded on its medial axis, optimised) and prints the residual as
//!   JSON.
//! * `nendo figure render FIG.json [--png P] [--svg S] [--size 512x512]`.
//! * `nendo figure warp FIG.json --curves DEFORMED.json --out OUT.json [--max-edge L]
//!   [--png P] [--svg S]`: moves the figure's curves to the deformed ones; metacircles, contour
//!   and polygons follow (edges longer than `L` divided first, none when no curve moved).
//! * `nendo figure measure FIG.json`: the residual of a figure against its contour, as JSON.
//! * `nendo figure shape SHAPE.json --mesh OUT.obj [--png P] [--out RESULT.json]`: the
//!   metaball shape fitted to the horizontal sections of a `nendo-shape` file, deformed by the
//!   `moves` of the curves laid along them and re-fitted; writes the iso-surface as a mesh
//!   (OBJ/STL/GLB) and, with the `gui` feature, a PNG through the renderer
//!   ([`super::shape`]).

use anyhow::{Context, bail};
use clap::{Args as ClapArgs, Subcommand};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use super::arg_error::ArgError;
use crate::curve::warp::WarpParams;
use crate::figure::document::curves_from_json_str;
use crate::figure::fit::{FitOptions, FitReport, fit_contour, measure};
use crate::figure::optimise::{Optimiser, Stopping};
use crate::figure::warp::{WarpOptions, warp_document};
use crate::figure::{FigureDocument, Image, ImageSize, PictureOptions, Rgb, picture};

/// Arguments of `nendo figure`.
#[derive(Debug, ClapArgs)]
pub struct FigureArgs {
    /// What to do.
    #[command(subcommand)]
    pub action: Action,
}

/// The `nendo figure` actions.
#[derive(Debug, Subcommand)]
pub enum Action {
    /// Fit metacircles to the contour of a figure file; print the residual as JSON.
    Fit(FitArgs),
    /// Draw a figure file to PNG and/or SVG.
    Render(FigureRenderArgs),
    /// Warp a figure by moving its curves to deformed ones.
    Warp(WarpArgs),
    /// Print the residual of a figure against its contour as JSON.
    Measure(MeasureArgs),
    /// Fit metaballs to horizontal sections, drag the curves laid along them, re-fit, and
    /// write the iso-surface as a mesh (and a PNG through the renderer).
    Shape(super::shape::FigureShapeArgs),
}

/// Picture outputs shared by the actions.
#[derive(Debug, Clone, ClapArgs)]
pub struct PictureArgs {
    /// Write the picture as PNG here.
    #[arg(long, value_name = "OUT.png")]
    pub png: Option<PathBuf>,
    /// Write the boundary (and polygons, curves) as SVG here.
    #[arg(long, value_name = "OUT.svg")]
    pub svg: Option<PathBuf>,
    /// Picture size in pixels, `WIDTHxHEIGHT`.
    #[arg(long, default_value = "512x512", value_parser = parse_size)]
    pub size: ImageSize,
    /// Supersampling of boundary pixels per axis (1..=16).
    #[arg(long, default_value_t = 4)]
    pub samples: u32,
    /// Leave the curves out of the SVG.
    #[arg(long)]
    pub no_curves: bool,
}

/// Arguments of `nendo figure fit`.
#[derive(Debug, Clone, ClapArgs)]
pub struct FitArgs {
    /// A figure file with a `contour`.
    pub input: PathBuf,
    /// Where to write the fitted figure file.
    #[arg(long, value_name = "FIG.json")]
    pub out: PathBuf,
    /// Most metacircles seeded.
    #[arg(long, default_value_t = 200)]
    pub circles: usize,
    /// Grid cells along the longer side for the medial-axis seeds.
    #[arg(long, default_value_t = 128)]
    pub seed_resolution: usize,
    /// Contour samples (0: automatic).
    #[arg(long, default_value_t = 0)]
    pub contour_samples: usize,
    /// Guard grid cells along the longer side.
    #[arg(long, default_value_t = 64)]
    pub guard_resolution: usize,
    /// Use P0's steepest descent instead of Levenberg–Marquardt.
    #[arg(long)]
    pub descent: bool,
    /// Most optimiser iterations.
    #[arg(long, default_value_t = 200)]
    pub iterations: usize,
    /// Colour of the metacircles, `#rrggbb`.
    #[arg(long, default_value = "#8a5a3c", value_parser = parse_colour)]
    pub colour: Rgb,
    /// Pictures of the result.
    #[command(flatten)]
    pub picture: PictureArgs,
}

/// Arguments of `nendo figure render`.
#[derive(Debug, Clone, ClapArgs)]
pub struct FigureRenderArgs {
    /// The figure file.
    pub figure: PathBuf,
    /// Outputs.
    #[command(flatten)]
    pub picture: PictureArgs,
}

/// Arguments of `nendo figure warp`.
#[derive(Debug, Clone, ClapArgs)]
pub struct WarpArgs {
    /// The figure file (with its curves).
    pub figure: PathBuf,
    /// The deformed curves: a JSON array of curves, `{"curves": […]}` or a figure file.
    #[arg(long, value_name = "CURVES.json")]
    pub curves: PathBuf,
    /// Where to write the warped figure file.
    #[arg(long, value_name = "OUT.json")]
    pub out: PathBuf,
    /// Beier–Neely `a` (0: points on a curve follow it exactly).
    #[arg(long, default_value_t = WarpParams::default().a, allow_hyphen_values = true)]
    pub a: f64,
    /// Beier–Neely `b` (fall-off with distance).
    #[arg(long, default_value_t = WarpParams::default().b, allow_hyphen_values = true)]
    pub b: f64,
    /// Beier–Neely `p` (weight of curve length).
    #[arg(long, default_value_t = WarpParams::default().p, allow_hyphen_values = true)]
    pub p: f64,
    /// Divide contour and polygon edges longer than this (figure units) before warping, so
    /// that they bend with the curves (default: 1/200 of the frame's diagonal; `inf`: divide
    /// none). No edge is divided when no curve moved.
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    pub max_edge: Option<f64>,
    /// Pictures of the result.
    #[command(flatten)]
    pub picture: PictureArgs,
}

/// Arguments of `nendo figure measure`.
#[derive(Debug, Clone, ClapArgs)]
pub struct MeasureArgs {
    /// The figure file (with metacircles and a contour).
    pub figure: PathBuf,
}

/// Runs `nendo figure`.
pub fn run(args: FigureArgs) -> ExitCode {
    let result = match args.action {
        Action::Fit(a) => fit(&a),
        Action::Render(a) => render(&a),
        Action::Warp(a) => warp(&a),
        Action::Measure(a) => measure_cmd(&a),
        Action::Shape(a) => super::shape::shape(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => super::output::failed("nendo figure", &e),
    }
}

/// Largest figure or curves file read: 64 MB (2 000 metacircles take about 200 kB; the rest
/// is room for contours, polygons and curves). A larger file, or a device or pipe that never
/// ends, is refused after reading one byte past the limit.
pub const MAX_FIGURE_FILE_BYTES: u64 = 64 << 20;

/// Reads a figure file.
pub(crate) fn read_document(path: &Path) -> anyhow::Result<FigureDocument> {
    let text = nendo_file::read_text_limited(path, MAX_FIGURE_FILE_BYTES, "figure file")?;
    FigureDocument::from_json(&text).with_context(|| format!("{}", path.display()))
}

/// Writes text (an SVG, a figure file) with the one safe writer.
pub(crate) fn write_text(path: &Path, text: &str) -> anyhow::Result<()> {
    Ok(nendo_file::write_bytes(path, text.as_bytes())?)
}

/// Encodes an image as PNG and writes it with the one safe writer.
pub(crate) fn write_png(path: &Path, image: &Image) -> anyhow::Result<()> {
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, image.size.width, image.size.height);
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = encoder.write_header().context("PNG header")?;
        writer.write_image_data(&image.pixels).context("PNG data")?;
        writer.finish().context("PNG end")?;
    }
    Ok(nendo_file::write_bytes(path, &bytes)?)
}

/// Writes the pictures a [`PictureArgs`] asks for.
fn write_pictures(doc: &FigureDocument, args: &PictureArgs) -> anyhow::Result<()> {
    if args.png.is_none() && args.svg.is_none() {
        return Ok(());
    }
    let options = PictureOptions {
        size: args.size,
        samples: args.samples,
        curves: !args.no_curves,
        ..Default::default()
    };
    let pic = picture(doc, &options)?;
    if let Some(p) = &args.png {
        write_png(p, &pic.image)?;
    }
    if let Some(p) = &args.svg {
        write_text(p, &pic.svg)?;
    }
    Ok(())
}

/// The report as JSON.
pub(crate) fn report_json(r: &FitReport) -> serde_json::Value {
    json!({
        "metacircles": r.metacircles,
        "samples": r.samples,
        "iterations": r.iterations,
        "initial_cost": r.initial_cost,
        "final_cost": r.final_cost,
        "rms_density": r.rms_density,
        "max_density": r.max_density,
        "rms_distance": r.rms_distance,
        "max_distance": if r.max_distance.is_finite() { json!(r.max_distance) } else { json!(null) },
        "boundary_distance": if r.boundary_distance.is_finite() { json!(r.boundary_distance) } else { json!(null) },
        "size": r.size,
        "guards_violated": r.guards_violated,
    })
}

/// Refuses an option beyond what a fit can use: a mistyped count is an error, not an
/// allocation failure or an hour of work.
pub(crate) fn at_most(name: &str, value: usize, max: usize) -> anyhow::Result<()> {
    if value > max {
        bail!("{name} must be at most {max}, got {value}");
    }
    Ok(())
}

/// The outputs of a figure subcommand against its inputs ([`super::paths::check`]): `--out`
/// (a figure file) may replace the figure read, the pictures may not; no output may replace
/// another or one of the `others` inputs.
fn check_outputs(
    picture: &PictureArgs,
    figure: &Path,
    out: Option<&Path>,
    others: &[(&'static str, Option<&Path>)],
) -> Result<(), super::paths::PathClash> {
    let pictures = [
        ("--png", picture.png.as_deref()),
        ("--svg", picture.svg.as_deref()),
    ];
    super::paths::check(&pictures, &[("figure", Some(figure))])?;
    super::paths::check(&[("--out", out), pictures[0], pictures[1]], others)
}

fn fit(args: &FitArgs) -> anyhow::Result<()> {
    at_most("--circles", args.circles, 5_000)?;
    at_most("--seed-resolution", args.seed_resolution, 2_048)?;
    at_most("--contour-samples", args.contour_samples, 100_000)?;
    at_most("--guard-resolution", args.guard_resolution, 1_024)?;
    at_most("--iterations", args.iterations, 100_000)?;
    check_outputs(&args.picture, &args.input, Some(&args.out), &[])?;
    let mut doc = read_document(&args.input)?;
    let Some(contour) = doc.contour.clone() else {
        bail!(
            "{}: the figure file has no \"contour\" to fit",
            args.input.display()
        );
    };
    let mut options = FitOptions {
        samples: args.contour_samples,
        guard_resolution: args.guard_resolution,
        optimiser: if args.descent {
            Optimiser::SteepestDescent
        } else {
            Optimiser::LevenbergMarquardt
        },
        stopping: Stopping {
            max_iterations: args.iterations,
            ..Stopping::default()
        },
        colour: args.colour,
        threshold: doc.figure.threshold,
        ..FitOptions::default()
    };
    options.seeds.max_seeds = args.circles;
    options.seeds.resolution = args.seed_resolution;
    let (figure, report) = fit_contour(&contour, &options)?;
    doc.figure = figure;
    write_text(&args.out, &doc.to_json())?;
    write_pictures(&doc, &args.picture)?;
    super::output::println(report_json(&report))?;
    Ok(())
}

fn render(args: &FigureRenderArgs) -> anyhow::Result<()> {
    if args.picture.png.is_none() && args.picture.svg.is_none() {
        bail!("nothing to write: give --png and/or --svg");
    }
    check_outputs(&args.picture, &args.figure, None, &[])?;
    let doc = read_document(&args.figure)?;
    write_pictures(&doc, &args.picture)
}

fn warp(args: &WarpArgs) -> anyhow::Result<()> {
    check_outputs(
        &args.picture,
        &args.figure,
        Some(&args.out),
        &[("--curves file", Some(&args.curves))],
    )?;
    let doc = read_document(&args.figure)?;
    let text = nendo_file::read_text_limited(&args.curves, MAX_FIGURE_FILE_BYTES, "curves file")?;
    let deformed =
        curves_from_json_str(&text).with_context(|| format!("{}", args.curves.display()))?;
    let params = WarpParams {
        a: args.a,
        b: args.b,
        p: args.p,
        ..WarpParams::default()
    };
    let out = warp_document(
        &doc,
        &deformed,
        &WarpOptions {
            params,
            max_edge: args.max_edge,
        },
    )?;
    write_text(&args.out, &out.to_json())?;
    write_pictures(&out, &args.picture)?;
    let moved = doc
        .figure
        .metacircles
        .iter()
        .zip(&out.figure.metacircles)
        .map(|(a, b)| a.centre.distance(b.centre))
        .fold(0.0, f64::max);
    super::output::println(
        json!({"metacircles": out.figure.metacircles.len(), "largest_move": moved}),
    )?;
    Ok(())
}

fn measure_cmd(args: &MeasureArgs) -> anyhow::Result<()> {
    let doc = read_document(&args.figure)?;
    let Some(contour) = &doc.contour else {
        bail!(
            "{}: the figure file has no \"contour\" to measure against",
            args.figure.display()
        );
    };
    let d = FitOptions::default();
    super::output::println(report_json(&measure(
        &doc.figure,
        contour,
        d.samples,
        d.guard_resolution,
    )))?;
    Ok(())
}

/// Parses `WIDTHxHEIGHT`.
pub(crate) fn parse_size(s: &str) -> Result<ImageSize, ArgError> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| ArgError::NotASize {
        value: s.to_owned(),
        example: "512x512",
    })?;
    let number = |v: &str| {
        v.trim()
            .parse::<u32>()
            .map_err(|error| ArgError::NotAWholeNumber {
                value: s.to_owned(),
                error,
            })
    };
    let (w, h) = (number(w)?, number(h)?);
    ImageSize::new(w, h).map_err(ArgError::ImageSize)
}

/// Parses `#rrggbb`.
fn parse_colour(s: &str) -> Result<Rgb, ArgError> {
    Rgb::parse_hex(s).ok_or_else(|| ArgError::NotAColour(s.to_owned()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn size_and_colour_values_fail_with_typed_errors_and_the_same_messages() {
        let e = parse_size("512").unwrap_err();
        assert!(matches!(e, ArgError::NotASize { .. }), "{e:?}");
        assert_eq!(
            e.to_string(),
            "\"512\": expected WIDTHxHEIGHT, e.g. 512x512"
        );
        let e = parse_size("12xab").unwrap_err();
        assert!(matches!(e, ArgError::NotAWholeNumber { .. }), "{e:?}");
        assert_eq!(e.to_string(), "\"12xab\": invalid digit found in string");
        let e = parse_size("0x10").unwrap_err();
        assert!(matches!(e, ArgError::ImageSize(_)), "{e:?}");
        assert_eq!(
            e.to_string(),
            ImageSize::new(0, 10).unwrap_err().to_string()
        );
        assert!(parse_size("64x32").is_ok());
        let e = parse_colour("red").unwrap_err();
        assert!(matches!(e, ArgError::NotAColour(_)), "{e:?}");
        assert_eq!(e.to_string(), "\"red\": expected a colour #rrggbb");
        assert_eq!(parse_colour("#ff8000").ok(), Some(Rgb([255, 128, 0])));
    }
}
