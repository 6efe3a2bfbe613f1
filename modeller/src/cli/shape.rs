//! `nendo figure shape SHAPE.json --mesh OUT.obj [--png OUT.png] [--out RESULT.json]`: a metaball
//! shape fitted to horizontal sections and deformed through them (P0 §4.3, Fig. 12).
//!
//! 1. The shape file ([`crate::figure::shape_document`]) is read: sections (contours at heights
//!    `z`), the curves laid along them, the drags (`moves`) of those curves, and optionally
//!    fitted metaballs.
//! 2. Without metaballs, the shape is fitted to the sections ([`crate::figure::shape`]).
//! 3. Each section's moves are applied to its curves in order; the section's contour follows its
//!    curves (the Beier–Neely curve warp, `--a --b --p --reach`, edges divided to
//!    `--max-edge`), and the metaballs are re-fitted to all the sections from where they were.
//!    A section whose curves did not move is left exactly as it was; when nothing moved
//!    nothing is re-fitted.
//! 4. The iso-surface is meshed by marching tetrahedra ([`crate::figure::marching`]) and
//!    written to `--mesh` (`.obj` with normals, `.stl`, `.glb`, by extension); `--png` draws it
//!    with the window's renderer, offscreen, with the sections' contours and curves as lines
//!    (feature `gui`); `--out` writes the resulting shape file (moved curves, warped contours,
//!    fitted metaballs, no moves). Every file is written atomically.
//!
//! A summary is printed as JSON: the residuals of the fit and of the re-fit (distances from the
//! contour samples to the iso-surface, per section), which sections moved, the mesh's size,
//! whether it is closed, and the times.

use anyhow::{Context, bail};
use clap::Args as ClapArgs;
use glam::DVec2;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::curve::Curve;
use crate::curve::warp::WarpParams;
use crate::figure::marching::{MeshOptions, is_closed, iso_surface};
use crate::figure::optimise::{Optimiser, Stopping};
use crate::figure::shape::{ShapeFitOptions, ShapeFitReport, deform, fit_sections};
use crate::figure::{Section, ShapeDocument};
use crate::mesh::{MeshFormat, TriMesh, save_mesh};

/// Largest shape file read: 64 MB (256 sections and 2 000 metaballs with their contours fit in
/// a few MB). A larger file, or a device or pipe that never ends, is refused after reading one
/// byte past the limit.
pub const MAX_SHAPE_FILE_BYTES: u64 = 64 << 20;

/// Arguments of `nendo figure shape`.
#[derive(Debug, Clone, ClapArgs)]
pub struct FigureShapeArgs {
    /// The shape file (`nendo-shape` JSON: sections, curves, moves, optional metaballs).
    pub shape: PathBuf,
    /// Where to write the mesh; the extension (.obj, .stl, .glb) chooses the format.
    #[arg(long, value_name = "OUT.obj")]
    pub mesh: PathBuf,
    /// Draw the mesh (and the sections' contours and curves) to this PNG, offscreen.
    #[arg(long, value_name = "OUT.png")]
    pub png: Option<PathBuf>,
    /// Write the resulting shape file (deformed sections, fitted metaballs) here.
    #[arg(long, value_name = "RESULT.json")]
    pub out: Option<PathBuf>,
    /// Mesh lattice cells along the longest side of the shape (2..=256).
    #[arg(long, default_value_t = 64)]
    pub resolution: usize,
    /// Most metaballs seeded per section.
    #[arg(long, default_value_t = 12)]
    pub balls: usize,
    /// Samples per section contour (0: four per vertex, 100 to 400).
    #[arg(long, default_value_t = 0)]
    pub samples: usize,
    /// Guard grid cells along the longer side of each section plane.
    #[arg(long, default_value_t = 24)]
    pub guard_resolution: usize,
    /// Leave out the guards between consecutive section planes.
    #[arg(long)]
    pub no_bridges: bool,
    /// Most optimiser iterations (fit and re-fit each).
    #[arg(long, default_value_t = 200)]
    pub iterations: usize,
    /// Use the seed's steepest descent instead of Levenberg–Marquardt.
    #[arg(long)]
    pub descent: bool,
    /// Fit even when the file has metaballs (they are then ignored).
    #[arg(long)]
    pub refit: bool,
    /// Beier–Neely `a` of the section warp (0: points on a curve follow it exactly).
    #[arg(long, default_value_t = WarpParams::default().a, allow_hyphen_values = true)]
    pub a: f64,
    /// Beier–Neely `b` (fall-off with distance).
    #[arg(long, default_value_t = WarpParams::default().b, allow_hyphen_values = true)]
    pub b: f64,
    /// Beier–Neely `p` (weight of curve length).
    #[arg(long, default_value_t = WarpParams::default().p, allow_hyphen_values = true)]
    pub p: f64,
    /// Distance at which a lone curve's pull on a section is halved (default: no still
    /// background).
    #[arg(long, allow_hyphen_values = true)]
    pub reach: Option<f64>,
    /// Divide a moved section's contour edges longer than this before warping (default: 1/100
    /// of the contour's diagonal).
    #[arg(long, value_name = "LENGTH", allow_hyphen_values = true)]
    pub max_edge: Option<f64>,
    /// Picture size in pixels, `WIDTHxHEIGHT`.
    #[arg(long, default_value = "800x800")]
    pub size: String,
    /// Where to look from: front, back, left, right, top, bottom, iso.
    #[arg(long, default_value = "iso")]
    pub view: String,
    /// Leave the sections' contours and curves out of the picture.
    #[arg(long)]
    pub no_lines: bool,
}

fn report_json(r: &ShapeFitReport, seconds: f64) -> Value {
    let finite = |v: f64| if v.is_finite() { json!(v) } else { json!(null) };
    json!({
        "metaballs": r.balls,
        "samples": r.samples,
        "guards": r.guards,
        "guards_violated": r.guards_violated,
        "iterations": r.iterations,
        "initial_cost": r.initial_cost,
        "final_cost": r.final_cost,
        "rms_distance": r.rms_distance,
        "max_distance": finite(r.max_distance),
        "size": r.size,
        "seconds": seconds,
        "sections": r.sections.iter().map(|s| json!({
            "z": s.z,
            "samples": s.samples,
            "rms_distance": s.rms_distance,
            "max_distance": finite(s.max_distance),
            "rms_density": s.rms_density,
            "max_density": s.max_density,
        })).collect::<Vec<_>>(),
    })
}

/// Runs `nendo figure shape`.
///
/// # Errors
/// What went wrong, with the file it concerns.
pub fn shape(args: &FigureShapeArgs) -> anyhow::Result<()> {
    // `--out` may replace the shape file read (a shape file either way); the mesh and the
    // picture may not.
    super::paths::check(
        &[("--mesh", Some(&args.mesh)), ("--png", args.png.as_deref())],
        &[("shape file", Some(&args.shape))],
    )?;
    super::paths::check(
        &[
            ("--mesh", Some(&args.mesh)),
            ("--png", args.png.as_deref()),
            ("--out", args.out.as_deref()),
        ],
        &[],
    )?;
    let format = MeshFormat::from_path(&args.mesh)?;
    if !(2..=256).contains(&args.resolution) {
        bail!("--resolution must be 2 to 256, got {}", args.resolution);
    }
    super::figure::at_most("--balls", args.balls, 500)?;
    super::figure::at_most("--samples", args.samples, 100_000)?;
    super::figure::at_most("--guard-resolution", args.guard_resolution, 512)?;
    super::figure::at_most("--iterations", args.iterations, 100_000)?;
    // Check the picture's settings before any work.
    if args.png.is_some() {
        picture_settings(args)?;
    }
    let text = nendo_file::read_text_limited(&args.shape, MAX_SHAPE_FILE_BYTES, "shape file")?;
    let doc =
        ShapeDocument::from_json(&text).with_context(|| format!("{}", args.shape.display()))?;
    let mut options = ShapeFitOptions {
        samples: args.samples,
        guard_resolution: args.guard_resolution,
        bridges: !args.no_bridges,
        optimiser: if args.descent {
            Optimiser::SteepestDescent
        } else {
            Optimiser::LevenbergMarquardt
        },
        stopping: Stopping {
            max_iterations: args.iterations,
            ..Stopping::default()
        },
        threshold: doc.threshold,
        ..ShapeFitOptions::default()
    };
    options.seeds.max_seeds = args.balls;
    let params = WarpParams {
        a: args.a,
        b: args.b,
        p: args.p,
        reach: args.reach.unwrap_or(f64::INFINITY),
    };
    params.check().map_err(|e| anyhow::anyhow!("{e}"))?;

    // 2. The shape before the drags.
    let mut fit_json = Value::Null;
    let start = match (&doc.shape, args.refit) {
        (Some(s), false) => s.clone(),
        _ => {
            let t = Instant::now();
            let (s, r) = fit_sections(&doc.sections, &options)?;
            fit_json = report_json(&r, t.elapsed().as_secs_f64());
            s
        }
    };
    // 3. The drags: curves moved, sections warped, the shape re-fitted.
    let deformed: Vec<Vec<Curve<DVec2>>> = doc
        .sections
        .iter()
        .zip(&doc.moves)
        .enumerate()
        .map(|(i, (s, m))| {
            s.moved_curves(m)
                .with_context(|| format!("{}: section {i}", args.shape.display()))
        })
        .collect::<anyhow::Result<_>>()?;
    let t = Instant::now();
    let result = deform(
        &start,
        &doc.sections,
        &deformed,
        params,
        args.max_edge,
        &options,
    )?;
    let refit_json = result
        .report
        .as_ref()
        .map_or(Value::Null, |r| report_json(r, t.elapsed().as_secs_f64()));
    let moved: Vec<usize> = (0..result.moved.len())
        .filter(|&i| result.moved[i])
        .collect();

    // 4. The mesh and the pictures.
    let t = Instant::now();
    let mesh = iso_surface(
        &result.shape,
        &MeshOptions {
            resolution: args.resolution,
            ..MeshOptions::default()
        },
    )?;
    let mesh_seconds = t.elapsed().as_secs_f64();
    // The error's own message says what failed; its source repeats the path and the reason,
    // so it is not chained (as `nendo export` prints it).
    save_mesh(&args.mesh, format, &mesh)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.mesh.display()))?;
    if let Some(png) = &args.png {
        draw_png(png, &mesh, &result.sections, &moved, args)?;
    }
    if let Some(out) = &args.out {
        let written = ShapeDocument {
            name: doc.name.clone(),
            threshold: doc.threshold,
            sections: result.sections.clone(),
            moves: vec![Vec::new(); result.sections.len()],
            shape: Some(result.shape.clone()),
        };
        super::figure::write_text(out, &written.to_json())?;
    }
    super::output::println(json!({
        "sections": doc.sections.len(),
        "metaballs": result.shape.balls.len(),
        "fit": fit_json,
        "moved_sections": moved,
        "refit": refit_json,
        "mesh": {
            "path": args.mesh.display().to_string(),
            "vertices": mesh.positions.len(),
            "triangles": mesh.triangle_count(),
            "closed": is_closed(&mesh),
            "resolution": args.resolution,
            "sag": mesh.error_bound,
            "seconds": mesh_seconds,
        },
        "png": args.png.as_ref().map(|p| p.display().to_string()),
        "out": args.out.as_ref().map(|p| p.display().to_string()),
    }))?;
    Ok(())
}

/// Parses `WIDTHxHEIGHT` (each 1..=8192).
fn parse_size(s: &str) -> anyhow::Result<(u32, u32)> {
    let parse = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=8192).contains(n))
    };
    match s.split_once(['x', 'X']).map(|(w, h)| (parse(w), parse(h))) {
        Some((Some(w), Some(h))) => Ok((w, h)),
        _ => bail!("--size {s:?}: expected WIDTHxHEIGHT, each 1 to 8192"),
    }
}

/// The picture's size and view, checked.
#[cfg(feature = "gui")]
fn picture_settings(
    args: &FigureShapeArgs,
) -> anyhow::Result<((u32, u32), crate::editor::ViewPreset)> {
    let size = parse_size(&args.size)?;
    let view = args
        .view
        .parse()
        .map_err(|e: crate::surface::UnknownName| anyhow::anyhow!("--view: {e}"))?;
    Ok((size, view))
}

#[cfg(not(feature = "gui"))]
fn picture_settings(args: &FigureShapeArgs) -> anyhow::Result<()> {
    parse_size(&args.size)?;
    bail!("--png needs the renderer: build nendo with the `gui` feature")
}

#[cfg(feature = "gui")]
fn draw_png(
    path: &Path,
    mesh: &TriMesh,
    sections: &[Section],
    moved: &[usize],
    args: &FigureShapeArgs,
) -> anyhow::Result<()> {
    use crate::editor::OrbitCamera;
    use crate::render::{
        GpuContext, LineBatch, OFFSCREEN_FORMAT, Offscreen, Renderer, Rgba, Style,
    };
    use glam::Vec3;

    let ((w, h), view) = picture_settings(args)?;
    let mut lines = LineBatch::new();
    if !args.no_lines {
        for (i, s) in sections.iter().enumerate() {
            let z = s.z as f32;
            let at = |p: DVec2| Vec3::new(p.x as f32, p.y as f32, z);
            let pts = s.contour.points();
            lines.polyline(
                pts.iter().chain(pts.first()).map(|&p| at(p)),
                Rgba::PATCH_EDGE,
            );
            let colour = if moved.contains(&i) {
                Rgba::HIGHLIGHT
            } else {
                Rgba::CURVE
            };
            for c in &s.curves {
                let (a, b) = c.domain();
                lines.polyline(
                    (0..=64).map(|k| at(c.eval(a + (b - a) * k as f64 / 64.0))),
                    colour,
                );
            }
        }
    }
    let gpu = GpuContext::headless()?;
    let mut renderer = Renderer::new(&gpu.device, OFFSCREEN_FORMAT, 4);
    renderer.set_surface(&gpu.device, &gpu.queue, mesh, &[]);
    renderer.set_lines(&gpu.device, &gpu.queue, &lines);
    let aspect = w as f32 / h as f32;
    let camera = OrbitCamera::framing(view, &mesh.positions, aspect);
    renderer.prepare(
        &gpu.queue,
        &camera.view(aspect),
        &Style::default(),
        [w as f32, h as f32],
    );
    let image = Offscreen::new(&gpu.device, [w, h], 4).render(&gpu, &renderer)?;
    // The error names the file.
    image.save_png(path)?;
    Ok(())
}

#[cfg(not(feature = "gui"))]
fn draw_png(
    _path: &Path,
    _mesh: &TriMesh,
    _sections: &[Section],
    _moved: &[usize],
    args: &FigureShapeArgs,
) -> anyhow::Result<()> {
    picture_settings(args)
}
