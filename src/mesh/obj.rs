//! Wavefront OBJ: `v` positions, `vn` normals, `f a//a b//b c//c` triangles (1-based indices,
//! one normal per vertex).

use std::io::Write;

use super::export::ExportError;
use nendo_geom::mesh::TriMesh;

/// Writes a mesh as OBJ text.
///
/// # Errors
/// [`ExportError::Io`] when the writer fails.
pub fn write_obj<W: Write>(mesh: &TriMesh, out: &mut W) -> Result<(), ExportError> {
    writeln!(
        out,
        "# nendo mesh: {} vertices, {} triangles",
        mesh.positions.len(),
        mesh.triangle_count()
    )?;
    writeln!(out, "o nendo")?;
    for p in &mesh.positions {
        writeln!(out, "v {} {} {}", p.x, p.y, p.z)?;
    }
    for n in &mesh.normals {
        writeln!(out, "vn {} {} {}", n.x, n.y, n.z)?;
    }
    for [a, b, c] in mesh.triangles().map(|t| t.map(|i| i + 1)) {
        writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}")?;
    }
    Ok(())
}
