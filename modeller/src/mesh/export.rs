//! Mesh export: the formats, their errors, and saving to a file with the one safe writer.

use std::io::Write;
use std::path::Path;

use super::glb::write_glb;
use super::obj::write_obj;
use super::stl::write_stl;
use super::up::UpAxis;
use nendo_geom::mesh::TriMesh;

/// What can go wrong when exporting a mesh.
#[derive(Debug, thiserror::Error)]
pub enum ExportError {
    /// Writing the encoded mesh failed.
    #[error("cannot write the mesh: {0}")]
    Io(#[from] std::io::Error),
    /// The file could not be created, replaced or synced (the message does not name it, as
    /// for [`ExportError::Io`]: callers do).
    #[error("cannot write the mesh: {}", .0.reason())]
    Write(#[from] nendo_file::WriteError),
    /// A vertex position or normal is NaN or infinite.
    #[error("vertex {vertex} has a coordinate that is not finite; nothing written")]
    NonFinite {
        /// The first such vertex.
        vertex: usize,
    },
    /// The mesh has no triangles, which the format cannot express.
    #[error("the mesh has no triangles")]
    Empty,
    /// Every triangle is degenerate in the file's single precision: its face normal (the
    /// normalised cross product of its edges in `f32`, as STL writes it) is zero — a model
    /// scaled so small (or so large) that the written coordinates no longer make a surface.
    #[error(
        "all {triangles} triangles of the mesh are degenerate in the file's single precision (no face normal; the model is too small or too large to write as a mesh, e.g. scaled by 1e-13); nothing written"
    )]
    Degenerate {
        /// The triangles.
        triangles: usize,
    },
    /// The mesh is too large for the format (more than `u32::MAX` triangles, or a GLB over 4 GiB).
    #[error("the mesh is too large for the format")]
    TooLarge,
    /// The file name's extension names no known format.
    #[error("unknown mesh format {0:?}: use .obj, .stl or .glb")]
    UnknownFormat(String),
    /// The format fixes its up axis and another was asked for.
    #[error("{format} is always +{} up", fixed.name().to_ascii_uppercase())]
    FixedUp {
        /// The format's name.
        format: &'static str,
        /// Its only up axis.
        fixed: UpAxis,
    },
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

    /// The up axis a file of this format gets unless asked otherwise: +Y for OBJ (Blender's
    /// and most tools' assumption) and GLB (glTF requires it), +Z for STL (the 3D-printing
    /// convention). See [`super::up`].
    #[must_use]
    pub fn default_up(self) -> UpAxis {
        match self {
            MeshFormat::Obj | MeshFormat::Glb => UpAxis::Y,
            MeshFormat::Stl => UpAxis::Z,
        }
    }

    /// Checks that this format can be written with `up`: any for OBJ, only +Y for GLB, only
    /// +Z for STL.
    ///
    /// # Errors
    /// [`ExportError::FixedUp`].
    pub fn check_up(self, up: UpAxis) -> Result<(), ExportError> {
        match self {
            MeshFormat::Obj => Ok(()),
            _ if up == self.default_up() => Ok(()),
            MeshFormat::Glb => Err(ExportError::FixedUp {
                format: "glTF",
                fixed: UpAxis::Y,
            }),
            MeshFormat::Stl => Err(ExportError::FixedUp {
                format: "STL",
                fixed: UpAxis::Z,
            }),
        }
    }

    /// Writes `mesh` in this format with its default up axis ([`MeshFormat::default_up`]).
    ///
    /// # Errors
    /// As the format's writer.
    pub fn write<W: Write>(self, mesh: &TriMesh, out: &mut W) -> Result<(), ExportError> {
        self.write_up(mesh, out, self.default_up())
    }

    /// Writes `mesh` in this format with `up` as the file's up axis.
    ///
    /// # Errors
    /// [`ExportError::FixedUp`] when the format fixes another axis; as the format's writer.
    pub fn write_up<W: Write>(
        self,
        mesh: &TriMesh,
        out: &mut W,
        up: UpAxis,
    ) -> Result<(), ExportError> {
        self.check_up(up)?;
        match self {
            MeshFormat::Obj => write_obj(mesh, out, up),
            MeshFormat::Stl => write_stl(mesh, out),
            MeshFormat::Glb => write_glb(mesh, out),
        }
    }
}

/// Writes `mesh` to `path` with the one safe writer ([`nendo_file`]): atomically, through a
/// symbolic link to its file, keeping the replaced file's permissions; on failure `path` is
/// untouched and no temporary file is left.
///
/// A mesh with a NaN or infinite position or normal is refused before anything is written.
/// The file gets the format's default up axis ([`MeshFormat::default_up`]).
///
/// # Errors
/// [`ExportError::NonFinite`], as [`MeshFormat::write`], or [`ExportError::Write`] from the file
/// system.
pub fn save_mesh(path: &Path, format: MeshFormat, mesh: &TriMesh) -> Result<(), ExportError> {
    save_mesh_up(path, format, mesh, format.default_up())
}

/// As [`save_mesh`], with `up` as the file's up axis.
///
/// # Errors
/// [`ExportError::FixedUp`] (before anything is written) and as [`save_mesh`].
pub fn save_mesh_up(
    path: &Path,
    format: MeshFormat,
    mesh: &TriMesh,
    up: UpAxis,
) -> Result<(), ExportError> {
    format.check_up(up)?;
    if let Some(vertex) = first_non_finite(mesh) {
        return Err(ExportError::NonFinite { vertex });
    }
    check_not_degenerate(mesh)?;
    nendo_file::write_atomic(path, |file| {
        format.write_up(mesh, file, up)?;
        Ok(())
    })
}

/// The first vertex of `mesh` whose position or normal has a NaN or infinite coordinate.
#[must_use]
pub fn first_non_finite(mesh: &TriMesh) -> Option<usize> {
    mesh.positions
        .iter()
        .zip(mesh.normals.iter().map(Some).chain(std::iter::repeat(None)))
        .position(|(p, n)| !p.is_finite() || n.is_some_and(|n| !n.is_finite()))
}

/// Refuses a mesh that would be written empty or degenerate: no triangles
/// ([`ExportError::Empty`]), or no triangle with a face normal in `f32`
/// ([`ExportError::Degenerate`]). A mesh with some degenerate triangles (a sphere's poles) is
/// written.
///
/// # Errors
/// As above.
pub fn check_not_degenerate(mesh: &TriMesh) -> Result<(), ExportError> {
    if mesh.triangle_count() == 0 {
        return Err(ExportError::Empty);
    }
    let has_normal = mesh.triangles().any(|t| {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        (b - a).cross(c - a).try_normalize().is_some()
    });
    if has_normal {
        Ok(())
    } else {
        Err(ExportError::Degenerate {
            triangles: mesh.triangle_count(),
        })
    }
}
