//! Mesh export: the formats, their errors, and atomic saving to a file.

use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use super::glb::write_glb;
use super::obj::write_obj;
use super::stl::write_stl;
use nendo_geom::mesh::TriMesh;

/// What can go wrong when exporting a mesh.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// Writing (or renaming the temporary file) failed.
    #[error("cannot write the mesh: {0}")]
    Io(#[from] std::io::Error),
    /// The mesh has no triangles, which the format cannot express.
    #[error("the mesh has no triangles")]
    Empty,
    /// The mesh is too large for the format (more than `u32::MAX` triangles, or a GLB over 4 GiB).
    #[error("the mesh is too large for the format")]
    TooLarge,
    /// The file name's extension names no known format.
    #[error("unknown mesh format {0:?}: use .obj, .stl or .glb")]
    UnknownFormat(String),
}

/// A mesh file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    /// Wavefront OBJ with normals.
    Obj,
    /// Binary STL.
    Stl,
    /// Binary glTF 2.0.
    Glb,
}

impl MeshFormat {
    /// Every format, in menu order.
    pub const ALL: [MeshFormat; 3] = [MeshFormat::Obj, MeshFormat::Stl, MeshFormat::Glb];

    /// The usual file extension (lower case, no dot).
    #[must_use]
    pub fn extension(self) -> &'static str {
        match self {
            MeshFormat::Obj => "obj",
            MeshFormat::Stl => "stl",
            MeshFormat::Glb => "glb",
        }
    }

    /// The format a path's extension names (case-insensitive).
    ///
    /// # Errors
    /// [`ExportError::UnknownFormat`] for any other extension.
    pub fn from_path(path: &Path) -> Result<Self, ExportError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        Self::ALL
            .into_iter()
            .find(|f| f.extension() == ext)
            .ok_or(ExportError::UnknownFormat(ext))
    }

    /// Writes `mesh` in this format.
    ///
    /// # Errors
    /// As the format's writer.
    pub fn write<W: Write>(self, mesh: &TriMesh, out: &mut W) -> Result<(), ExportError> {
        match self {
            MeshFormat::Obj => write_obj(mesh, out),
            MeshFormat::Stl => write_stl(mesh, out),
            MeshFormat::Glb => write_glb(mesh, out),
        }
    }
}

/// Writes `mesh` to `path` atomically: into a temporary file beside it, flushed and synced, then
/// renamed over `path`; on failure the temporary file is removed and `path` is untouched.
///
/// # Errors
/// As [`MeshFormat::write`], or [`ExportError::Io`] from the file system.
pub fn save_mesh(path: &Path, format: MeshFormat, mesh: &TriMesh) -> Result<(), ExportError> {
    crate::model::check_replaceable(path)?;
    let tmp = temporary_beside(path);
    let result = (|| {
        let mut out = BufWriter::new(File::create(&tmp)?);
        format.write(mesh, &mut out)?;
        let file = out.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        fs::rename(&tmp, path)?;
        Ok(())
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// `dir/.name.tmp-<pid>` beside `path`.
fn temporary_beside(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}
