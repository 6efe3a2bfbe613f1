//! Export from the window, off the UI thread: tessellating a big grid finely takes
//! seconds (millions of triangles), and the window keeps drawing meanwhile. STEP and IGES
//! (the exact patches and curves, [`crate::cad`]) go the same way, without tessellation.
//!
//! The job owns a copy of the patches, tessellates them with the library's mesher, welds and
//! writes the file atomically ([`save_mesh`]), and reports back once through a channel; the
//! window polls it every frame. Like `nendo export`, the report warns when the largest segment
//! count could not reach the tolerance.

use std::path::PathBuf;
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::time::Instant;

use crate::cad::{CadError, CadFormat, save_cad};
use crate::mesh::{
    ExportError, MeshFormat, PatchPoints, TessellateError, Tessellation, estimate, save_mesh,
    tessellate,
};

/// The tolerances the window offers, sides: from 1/10 down to 1/10 000 of a side (finer
/// gains nothing visible and, capped by [`Tessellation::max_segments`], only adds triangles).
pub const TOLERANCE_RANGE: std::ops::RangeInclusive<f64> = 1e-4..=0.1;

/// What a mesh export will write, known before anything is tessellated: the export dialog
/// shows it under the tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExportEstimate {
    /// Triangles, exactly as the mesher will make them ([`estimate`]; welding keeps them,
    /// but for the few collapsed at a pole).
    pub triangles: u64,
    /// The file's size in bytes, estimated: see [`estimate_export`].
    pub bytes: u64,
}

/// The triangles and file size of exporting `patches` within `tolerance` to `format`.
///
/// The triangle count `T` is exact ([`estimate`], the mesher's own plan). The welded mesh of
/// a grid has about `V = T / 2` vertices (every interior vertex of a triangulated grid is
/// shared by six triangles, each triangle has three). The sizes then:
///
/// - binary STL: `84 + 50 T` bytes, exactly;
/// - GLB: a position and a normal per vertex and three `u32` indices per triangle,
///   `24 V + 12 T`, plus about 1 kB of header and JSON;
/// - OBJ: a `v` and a `vn` line per vertex (three shortest `f32` numbers each, about 36 bytes
///   a line) and an `f a//a b//b c//c` line per triangle, `6 d + 9` bytes with `d` the digits
///   of `V`: `72 V + (6 d + 9) T`.
///
/// Within 15 % of the written file on the primitives and sculpted grids
/// (`tests/it/export_size.rs`).
#[must_use]
pub fn estimate_export(
    patches: &[PatchPoints],
    tolerance: f64,
    format: MeshFormat,
) -> ExportEstimate {
    let triangles = estimate(patches, &Tessellation::with_tolerance(tolerance)).triangles;
    let vertices = triangles.div_ceil(2);
    let digits = u64::from(vertices.max(1).ilog10() + 1);
    let bytes = match format {
        MeshFormat::Stl => 84 + 50 * triangles,
        MeshFormat::Glb => 1024 + 24 * vertices + 12 * triangles,
        MeshFormat::Obj => 72 * vertices + (6 * digits + 9) * triangles,
    };
    ExportEstimate { triangles, bytes }
}

/// What a finished export did.
#[derive(Debug, Clone, PartialEq)]
pub struct Exported {
    /// The file written.
    pub path: PathBuf,
    /// Triangles written.
    pub triangles: usize,
    /// The mesh's error bound (at most the tolerance unless the segment cap bound).
    pub error_bound: f64,
    /// The tolerance asked for.
    pub tolerance: f64,
    /// The segment cap per patch edge.
    pub max_segments: u32,
    /// Wall time, milliseconds.
    pub ms: f64,
    /// For a STEP or IGES export: the format and the patches and curves written (then
    /// `triangles` is 0 and the tolerance does not apply).
    pub cad: Option<(CadFormat, usize, usize)>,
}

impl Exported {
    /// True when the cap on segments kept the mesh from the tolerance.
    #[must_use]
    pub fn missed_tolerance(&self) -> bool {
        self.error_bound > self.tolerance
    }

    /// The status line for it.
    #[must_use]
    pub fn message(&self) -> String {
        if let Some((format, patches, curves)) = self.cad {
            return format!(
                "exported {} ({}, exact: {patches} patches, {curves} curves, millimetres) in {:.0} ms",
                self.path.display(),
                format.name(),
                self.ms
            );
        }
        let mut text = format!(
            "exported {} ({} triangles, tolerance {}, error bound {:.2e}) in {:.0} ms",
            self.path.display(),
            self.triangles,
            self.tolerance,
            self.error_bound,
            self.ms
        );
        if self.missed_tolerance() {
            text.push_str(&format!(
                "; warning: {} segments per patch edge could not reach the tolerance",
                self.max_segments
            ));
        }
        text
    }
}

/// Why an export was refused or failed. The messages are the window's status lines: complete
/// on their own, so no variant also exposes its inner error as a `source()`.
#[derive(Debug, thiserror::Error)]
pub enum ExportJobError {
    /// The file name names no mesh format.
    #[error("{0}")]
    Format(ExportError),
    /// The tolerance is not a positive number.
    #[error("the export tolerance must be a positive number, not {}", crate::num::Compact(*.0))]
    BadTolerance(f64),
    /// The mesh would exceed the triangle limit (counted before anything is allocated).
    #[error("cannot export: {0}; choose a coarser tolerance")]
    TooLarge(TessellateError),
    /// The export thread could not be started.
    #[error("cannot start the export: {0}")]
    Spawn(std::io::Error),
    /// Writing a STEP or IGES file failed.
    #[error("cannot export {}: {error}", path.display())]
    Cad {
        /// The file being written.
        path: PathBuf,
        /// What went wrong.
        error: CadError,
    },
    /// Writing the file failed.
    #[error("cannot export {}: {error}", path.display())]
    Write {
        /// The file being written.
        path: PathBuf,
        /// What went wrong.
        error: ExportError,
    },
    /// The export thread ended without reporting (it panicked).
    #[error("the export of {} stopped without finishing", .0.display())]
    Stopped(PathBuf),
}

/// An export running on its own thread.
#[derive(Debug)]
pub struct ExportJob {
    path: PathBuf,
    started: Instant,
    result: Receiver<Result<Exported, ExportJobError>>,
}

impl ExportJob {
    /// Starts exporting `patches` to `path` (the extension picks the format) with
    /// `tessellation`.
    ///
    /// # Errors
    /// An [`ExportJobError`] for an unknown extension, a tolerance that is not a positive number, a mesh
    /// of more than [`Tessellation::DEFAULT_MAX_TRIANGLES`] triangles (counted before
    /// anything is allocated), or a thread that cannot be started.
    pub fn start(
        patches: Vec<PatchPoints>,
        path: PathBuf,
        tessellation: Tessellation,
    ) -> Result<Self, ExportJobError> {
        let format = MeshFormat::from_path(&path).map_err(ExportJobError::Format)?;
        if !(tessellation.tolerance.is_finite() && tessellation.tolerance > 0.0) {
            return Err(ExportJobError::BadTolerance(tessellation.tolerance));
        }
        let size = estimate(&patches, &tessellation);
        if size.triangles > Tessellation::DEFAULT_MAX_TRIANGLES {
            let refused = TessellateError::TooManyTriangles {
                estimate: size,
                limit: Tessellation::DEFAULT_MAX_TRIANGLES,
            };
            return Err(ExportJobError::TooLarge(refused));
        }
        let (tx, result) = mpsc::channel();
        let target = path.clone();
        let started = Instant::now();
        std::thread::Builder::new()
            .name("nendo export".into())
            .spawn(move || {
                let raw = tessellate(&patches, &tessellation);
                let mesh = raw.welded();
                let outcome = save_mesh(&target, format, &mesh)
                    .map(|()| Exported {
                        path: target.clone(),
                        triangles: mesh.triangle_count(),
                        error_bound: raw.error_bound,
                        tolerance: tessellation.tolerance,
                        max_segments: tessellation.max_segments,
                        ms: started.elapsed().as_secs_f64() * 1e3,
                        cad: None,
                    })
                    .map_err(|error| ExportJobError::Write {
                        path: target.clone(),
                        error,
                    });
                // The window may have gone; nothing to tell then.
                let _ = tx.send(outcome);
            })
            .map_err(ExportJobError::Spawn)?;
        Ok(Self {
            path,
            started,
            result,
        })
    }

    /// Starts writing `model` to `path` as STEP or IGES (`format`), the exact patches and
    /// curves, one model unit to the millimetre.
    ///
    /// # Errors
    /// [`ExportJobError::Spawn`] when the thread cannot be started.
    pub fn start_cad(
        model: crate::model::Model,
        path: PathBuf,
        format: CadFormat,
    ) -> Result<Self, ExportJobError> {
        let (tx, result) = mpsc::channel();
        let target = path.clone();
        let started = Instant::now();
        std::thread::Builder::new()
            .name("nendo export".into())
            .spawn(move || {
                let options =
                    crate::cad::CadOptions::named(&crate::cad::CadOptions::name_of(&target));
                let outcome = save_cad(&target, format, &model, &options)
                    .map(|_| Exported {
                        path: target.clone(),
                        triangles: 0,
                        error_bound: 0.0,
                        tolerance: 0.0,
                        max_segments: 0,
                        ms: started.elapsed().as_secs_f64() * 1e3,
                        cad: Some((format, model.surface.patch_count(), model.curves.len())),
                    })
                    .map_err(|error| ExportJobError::Cad {
                        path: target.clone(),
                        error,
                    });
                let _ = tx.send(outcome);
            })
            .map_err(ExportJobError::Spawn)?;
        Ok(Self {
            path,
            started,
            result,
        })
    }

    /// The file being written.
    #[must_use]
    pub fn path(&self) -> &std::path::Path {
        &self.path
    }

    /// Seconds since the export started.
    #[must_use]
    pub fn elapsed_s(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// Waits for the job to end (the window closing: the file is finished, not cut off).
    pub fn wait(self) -> Result<Exported, ExportJobError> {
        self.result
            .recv()
            .map_err(|_| ExportJobError::Stopped(self.path.clone()))?
    }

    /// The outcome once the job is done (`None` while it runs).
    pub fn poll(&self) -> Option<Result<Exported, ExportJobError>> {
        match self.result.try_recv() {
            Ok(outcome) => Some(outcome),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => {
                Some(Err(ExportJobError::Stopped(self.path.clone())))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Primitive, PrimitiveParams};
    use std::time::Duration;

    fn wait(job: &ExportJob) -> Result<Exported, ExportJobError> {
        let deadline = Instant::now() + Duration::from_secs(30);
        loop {
            if let Some(outcome) = job.poll() {
                return outcome;
            }
            assert!(Instant::now() < deadline, "the export never finished");
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    #[test]
    fn exports_off_the_calling_thread_and_warns_when_the_tolerance_is_out_of_reach() {
        let dir = std::env::temp_dir().join(format!("nendo-export-job-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let patches = Primitive::Sphere
            .build(&PrimitiveParams::default())
            .expect("sphere")
            .patches();
        let path = dir.join("sphere.stl");
        let job = ExportJob::start(
            patches.clone(),
            path.clone(),
            Tessellation::with_tolerance(1e-2),
        )
        .expect("started");
        let done = wait(&job).expect("exported");
        assert!(path.is_file() && done.triangles > 0 && !done.missed_tolerance());
        assert!(!done.message().contains("warning"), "{}", done.message());
        // A cap of 4 segments cannot reach 1e-6 on a sphere: the CLI's warning.
        let capped = Tessellation {
            tolerance: 1e-6,
            min_segments: 1,
            max_segments: 4,
        };
        let job =
            ExportJob::start(patches.clone(), dir.join("coarse.obj"), capped).expect("started");
        let done = job.wait().expect("exported");
        assert!(done.missed_tolerance());
        assert!(
            done.message()
                .contains("warning: 4 segments per patch edge could not reach the tolerance"),
            "{}",
            done.message()
        );
        // Refused up front: an unknown format, a tolerance that is no positive number; a
        // write that fails is reported with the path.
        let err = ExportJob::start(patches.clone(), dir.join("x.ply"), Tessellation::EXPORT)
            .expect_err("unknown format");
        assert!(
            matches!(&err, ExportJobError::Format(ExportError::UnknownFormat(e)) if e == "ply"),
            "{err:?}"
        );
        assert_eq!(
            err.to_string(),
            "unknown mesh format \"ply\": use .obj, .stl or .glb"
        );
        let err = ExportJob::start(
            patches.clone(),
            dir.join("x.obj"),
            Tessellation::with_tolerance(0.0),
        )
        .expect_err("no positive tolerance");
        assert!(
            matches!(err, ExportJobError::BadTolerance(t) if t == 0.0),
            "{err:?}"
        );
        assert_eq!(
            err.to_string(),
            "the export tolerance must be a positive number, not 0"
        );
        let missing = dir.join("no-such-folder").join("x.glb");
        let job =
            ExportJob::start(patches, missing.clone(), Tessellation::EXPORT).expect("started");
        let err = wait(&job).expect_err("no folder");
        assert!(
            matches!(&err, ExportJobError::Write { path, .. } if *path == missing),
            "{err:?}"
        );
        let text = err.to_string();
        assert!(
            text.starts_with(&format!(
                "cannot export {}: cannot write the mesh: ",
                missing.display()
            )),
            "{text}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn exports_step_and_iges_off_the_calling_thread() {
        let dir = std::env::temp_dir().join(format!("nendo-export-cad-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let model = crate::model::Model::new(
            Primitive::Torus
                .build(&PrimitiveParams::default())
                .expect("torus"),
        );
        for (name, format) in [("t.step", CadFormat::Step), ("t.igs", CadFormat::Iges)] {
            let path = dir.join(name);
            let job = ExportJob::start_cad(model.clone(), path.clone(), format).expect("started");
            let done = wait(&job).expect("exported");
            let text = std::fs::read_to_string(&path).expect("written");
            assert!(text.starts_with(match format {
                CadFormat::Step => "ISO-10303-21;",
                CadFormat::Iges => "nendo exact surface",
            }));
            assert!(
                done.message()
                    .contains(&format!("{}, exact: 32 patches, 0 curves", format.name())),
                "{}",
                done.message()
            );
        }
        let missing = dir.join("no-such-folder").join("t.step");
        let job = ExportJob::start_cad(model, missing.clone(), CadFormat::Step).expect("started");
        let err = wait(&job).expect_err("no folder");
        assert!(
            matches!(&err, ExportJobError::Cad { path, .. } if *path == missing),
            "{err:?}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn refuses_a_mesh_over_the_triangle_limit_before_tessellating() {
        // 32 × 16 patches at 1e-9 all take 256 × 256 cells: 67 million triangles.
        let patches = Primitive::Sphere
            .build(&PrimitiveParams {
                patches: Some((32, 16)),
                ..PrimitiveParams::default()
            })
            .expect("sphere")
            .patches();
        let path = std::env::temp_dir().join(format!("nendo-refused-{}.stl", std::process::id()));
        let err = ExportJob::start(patches, path.clone(), Tessellation::with_tolerance(1e-9))
            .expect_err("over the limit");
        assert!(
            matches!(
                err,
                ExportJobError::TooLarge(TessellateError::TooManyTriangles { .. })
            ),
            "{err:?}"
        );
        let text = err.to_string();
        assert!(
            text.starts_with("cannot export: ")
                && text.contains("67108864 triangles")
                && text.ends_with("; choose a coarser tolerance"),
            "{text}"
        );
        assert!(!path.exists());
    }
}
