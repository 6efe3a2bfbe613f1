//! `nendo export MODEL.json OUT.(obj|stl|glb|step|stp|igs|iges) [--tolerance T]
//! [--max-triangles N] [--up y|z] [--scale S] [--units mm|cm|m|in] [--one-surface]`.
//!
//! - Meshes (`.obj`, `.stl`, `.glb`): the model's surface tessellated by the library's own
//!   mesher within the tolerance. Memory is bounded: the size of the mesh is computed from the
//!   per-patch segment counts before anything is allocated, and a mesh of more than
//!   `--max-triangles` triangles (default [`Tessellation::DEFAULT_MAX_TRIANGLES`]) is refused
//!   with its size. Up axes: OBJ +Y by default (`--up z` keeps Z-up), GLB always +Y (glTF),
//!   STL always +Z ([`crate::mesh::up`]).
//! - CAD (`.step`/`.stp`, `.igs`/`.iges`): the exact patches and the curves ([`crate::cad`]),
//!   in `--units` (millimetres by default), `--scale` file units per model unit (default 1);
//!   `--one-surface` writes the whole grid as one B-spline surface (refused, with the worst
//!   grid line, when the grid is not one: a model regulated other than `exact`). The STEP
//!   product and the IGES file name are the model file's stem. No tessellation, so
//!   `--tolerance` and `--max-triangles` do not apply. Z-up as the model (CAD's convention).
//!
//! The default tolerance is relative to the model's size: a thousandth of the diagonal of its
//! control points' box ([`Tessellation::export_tolerance_for`]).
//!
//! `--tolerance` and `--scale` are checked whatever the format (a positive finite number
//! each): a `--tolerance nan` given with a `.step` is refused, not silently ignored.
//!
//! `--scale` is at most [`MAX_CAD_SCALE`] = 1e4 and at least [`MIN_CAD_SCALE`] = 1e-4. Why:
//! the STEP file declares a length uncertainty of `1e-7` file units (the IGES resolution is
//! the same), and a model unit is a side of the start primitive, whose refined patches are
//! down to about `1/256` unit. At `1e-4` such a patch is `4e-7` file units across, still above
//! the uncertainty; below it the patches' edges fall inside it and a reader sees
//! degenerate edges (`1e-9` made files OpenCASCADE calls faulty). At `1e4` a model of 100
//! units is `1e6` file units (a kilometre in mm), whose uncertainty is `1e-13` of its size,
//! a thousand times the double precision's `1e-16`; beyond it, tolerances vanish into
//! rounding (`1e40` made faulty files too).
//!
//! A mesh that would be empty or degenerate (every triangle without a face normal in the
//! file's single precision, as a plane scaled by `1e-50` is) is refused, nothing written
//! ([`crate::mesh::export::check_not_degenerate`]).

use clap::Args as ClapArgs;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use crate::cad::{CadFormat, CadOptions, CadUnit, save_cad};
use crate::mesh::{MeshFormat, Tessellation, UpAxis, save_mesh_up, try_tessellate};
use crate::model::Model;

/// Smallest `--scale` (see the module docs).
pub const MIN_CAD_SCALE: f64 = 1e-4;
/// Largest `--scale` (see the module docs).
pub const MAX_CAD_SCALE: f64 = 1e4;

/// Arguments of `nendo export`.
#[derive(Debug, Clone, ClapArgs)]
pub struct ExportArgs {
    /// The model (nendo-model JSON).
    pub model: PathBuf,
    /// The output file; its extension chooses the format: .obj, .stl, .glb (meshes), .step /
    /// .stp (STEP AP214), .igs / .iges (IGES 5.3).
    pub out: PathBuf,
    /// Meshes: largest distance between the mesh and the surface, in model units (sides).
    /// Without it: a thousandth of the diagonal of the model's box (0.014 for the 10 × 10
    /// plane).
    #[arg(long, allow_hyphen_values = true)]
    pub tolerance: Option<f64>,
    /// Meshes: refuse meshes of more triangles than this (counted before welding, before
    /// anything is allocated; 20 million take about 1 GB at the peak of writing).
    #[arg(long, default_value_t = Tessellation::DEFAULT_MAX_TRIANGLES)]
    pub max_triangles: u64,
    /// Meshes: the file's up axis, y or z. OBJ: y by default (model (x, y, z) written as
    /// (x, z, -y)), z keeps the model's coordinates; GLB is always y (glTF), STL always z.
    #[arg(long)]
    pub up: Option<UpAxis>,
    /// STEP / IGES: file units (--units) per model unit.
    #[arg(long, default_value_t = 1.0, allow_hyphen_values = true)]
    pub scale: f64,
    /// STEP / IGES: the file's length unit: mm, cm, m or in.
    #[arg(long, default_value_t = CadUnit::Millimetre)]
    pub units: CadUnit,
    /// STEP / IGES: the whole grid as one B-spline surface (one face) instead of one per
    /// patch; needs a grid kept by the `exact` regulation.
    #[arg(long)]
    pub one_surface: bool,
}

/// Runs `nendo export`.
pub fn run(args: ExportArgs) -> ExitCode {
    if let Some(t) = args.tolerance
        && !(t.is_finite() && t > 0.0)
    {
        eprintln!(
            "nendo export: --tolerance must be a positive number, not {}",
            crate::num::Compact(t)
        );
        return ExitCode::from(2);
    }
    if !(args.scale.is_finite() && args.scale > 0.0) {
        eprintln!(
            "nendo export: --scale must be a positive number (file units per model unit), not {}",
            crate::num::Compact(args.scale)
        );
        return ExitCode::from(2);
    }
    if !(MIN_CAD_SCALE..=MAX_CAD_SCALE).contains(&args.scale) {
        eprintln!(
            "nendo export: --scale {} is outside 1e-4 to 1e4 file units per model unit: the file's length uncertainty (1e-7) or the double precision would make the geometry faulty",
            crate::num::Compact(args.scale)
        );
        return ExitCode::from(2);
    }
    if let Err(e) =
        super::paths::check(&[("OUT", Some(&args.out))], &[("model", Some(&args.model))])
    {
        eprintln!("nendo export: {e}");
        return ExitCode::from(2);
    }
    if let Some(format) = CadFormat::from_path(&args.out) {
        return run_cad(&args, format);
    }
    let format = match MeshFormat::from_path(&args.out) {
        Ok(f) => f,
        Err(_) => {
            let ext = args
                .out
                .extension()
                .and_then(|e| e.to_str())
                .unwrap_or("")
                .to_ascii_lowercase();
            eprintln!(
                "nendo export: unknown format {ext:?}: use .obj, .stl, .glb, .step, .stp, .igs or .iges"
            );
            return ExitCode::from(2);
        }
    };
    if args.one_surface || args.units != CadUnit::Millimetre {
        eprintln!(
            "nendo export: --one-surface and --units apply to STEP and IGES; a mesh is written in model units"
        );
        return ExitCode::from(2);
    }
    let up = args.up.unwrap_or(format.default_up());
    if let Err(e) = format.check_up(up) {
        eprintln!("nendo export: --up {up}: {e}");
        return ExitCode::from(2);
    }
    let loaded = match Model::read(&args.model) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("nendo export: {}", e.in_file(&args.model));
            return ExitCode::FAILURE;
        }
    };
    let patches = loaded.model.surface.patches();
    let tolerance = args
        .tolerance
        .unwrap_or_else(|| Tessellation::export_tolerance_for(&patches));
    let settings = Tessellation::with_tolerance(tolerance);
    let raw = match try_tessellate(&patches, &settings, args.max_triangles) {
        Ok(raw) => raw,
        Err(e) => {
            eprintln!(
                "nendo export: {e}; raise --max-triangles or the --tolerance (now {})",
                crate::num::Compact(tolerance)
            );
            return ExitCode::FAILURE;
        }
    };
    let mesh = raw.welded();
    if let Err(e) = save_mesh_up(&args.out, format, &mesh, up) {
        eprintln!("nendo export: {}: {e}", args.out.display());
        return ExitCode::FAILURE;
    }
    let summary = format!(
        "{}: {} patches, {} vertices, {} triangles, error bound {:.3e} (tolerance {}), +{} up",
        args.out.display(),
        patches.len(),
        mesh.positions.len(),
        mesh.triangle_count(),
        raw.error_bound,
        crate::num::Compact(tolerance),
        up.name().to_ascii_uppercase()
    );
    if let Err(super::output::StdoutError(e)) = super::output::println(summary) {
        return super::output::stdout_failed("nendo export", &e);
    }
    if raw.error_bound > tolerance {
        eprintln!(
            "nendo export: warning: {} segments per patch edge could not reach the tolerance",
            settings.max_segments
        );
    }
    ExitCode::SUCCESS
}

/// `nendo export` to STEP or IGES.
fn run_cad(args: &ExportArgs, format: CadFormat) -> ExitCode {
    if let Some(up) = args.up.filter(|&u| u != UpAxis::Z) {
        eprintln!(
            "nendo export: --up {up}: {} is written +Z up, as the model",
            format.name()
        );
        return ExitCode::from(2);
    }
    let loaded = match Model::read(&args.model) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("nendo export: {}", e.in_file(&args.model));
            return ExitCode::FAILURE;
        }
    };
    let started = Instant::now();
    let model = &loaded.model;
    let options = CadOptions {
        scale: args.scale,
        unit: args.units,
        name: CadOptions::name_of(&args.model),
        one_surface: args.one_surface,
    };
    let bytes = match save_cad(&args.out, format, model, &options) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("nendo export: {}: {e}", args.out.display());
            return ExitCode::FAILURE;
        }
    };
    let summary = format!(
        "{}: {}, {} patches ({} surface{}), {} curves, {} bytes, scale {} {} per unit, {:.0} ms",
        args.out.display(),
        format.name(),
        model.surface.patch_count(),
        model.surface.topology(),
        if args.one_surface {
            " as one B-spline face"
        } else {
            ""
        },
        model.curves.len(),
        bytes,
        crate::num::Compact(args.scale),
        args.units,
        started.elapsed().as_secs_f64() * 1e3
    );
    if let Err(super::output::StdoutError(e)) = super::output::println(summary) {
        return super::output::stdout_failed("nendo export", &e);
    }
    ExitCode::SUCCESS
}
