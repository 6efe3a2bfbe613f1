//! `nendo export MODEL.json OUT.(obj|stl|glb) [--tolerance T] [--max-triangles N]`: the model's
//! surface as a mesh, tessellated by the library's own mesher within the tolerance.
//!
//! Memory is bounded: the size of the mesh is computed from the per-patch segment counts before
//! anything is allocated, and a mesh of more than `--max-triangles` triangles (default
//! [`Tessellation::DEFAULT_MAX_TRIANGLES`]) is refused with its size.

use clap::Args as ClapArgs;
use std::path::PathBuf;
use std::process::ExitCode;

use crate::mesh::{MeshFormat, Tessellation, save_mesh, try_tessellate};
use crate::model::Model;

/// Arguments of `nendo export`.
#[derive(Debug, Clone, ClapArgs)]
pub struct Args {
    /// The model (nendo-model JSON).
    pub model: PathBuf,
    /// The mesh file; its extension (.obj, .stl, .glb) chooses the format.
    pub out: PathBuf,
    /// Largest distance between the mesh and the surface, in model units (sides).
    #[arg(long, default_value_t = Tessellation::EXPORT.tolerance)]
    pub tolerance: f64,
    /// Refuse meshes of more triangles than this (counted before welding, before anything is
    /// allocated; 20 million take about 1 GB at the peak of writing).
    #[arg(long, default_value_t = Tessellation::DEFAULT_MAX_TRIANGLES)]
    pub max_triangles: u64,
}

/// Runs `nendo export`.
pub fn run(args: Args) -> ExitCode {
    if !(args.tolerance.is_finite() && args.tolerance > 0.0) {
        eprintln!("nendo export: --tolerance must be a positive number");
        return ExitCode::from(2);
    }
    let format = match MeshFormat::from_path(&args.out) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("nendo export: {e}");
            return ExitCode::from(2);
        }
    };
    let loaded = match Model::read(&args.model) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("nendo export: {}: {e}", args.model.display());
            return ExitCode::FAILURE;
        }
    };
    let patches = loaded.model.surface.patches();
    let settings = Tessellation::with_tolerance(args.tolerance);
    let raw = match try_tessellate(&patches, &settings, args.max_triangles) {
        Ok(raw) => raw,
        Err(e) => {
            eprintln!(
                "nendo export: {e}; raise --max-triangles or the --tolerance (now {})",
                args.tolerance
            );
            return ExitCode::FAILURE;
        }
    };
    let mesh = raw.welded();
    if let Err(e) = save_mesh(&args.out, format, &mesh) {
        eprintln!("nendo export: {}: {e}", args.out.display());
        return ExitCode::FAILURE;
    }
    let summary = format!(
        "{}: {} patches, {} vertices, {} triangles, error bound {:.3e} (tolerance {})",
        args.out.display(),
        patches.len(),
        mesh.positions.len(),
        mesh.triangle_count(),
        raw.error_bound,
        args.tolerance
    );
    if let Err(super::output::StdoutError(e)) = super::output::println(summary) {
        return super::output::stdout_failed("nendo export", &e);
    }
    if raw.error_bound > args.tolerance {
        eprintln!(
            "nendo export: warning: {} segments per patch edge could not reach the tolerance",
            settings.max_segments
        );
    }
    ExitCode::SUCCESS
}
