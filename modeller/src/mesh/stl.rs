//! Binary STL: an 80-byte header, a little-endian `u32` triangle count, then per triangle its
//! unit face normal, three vertices (`f32` each) and a zero `u16` attribute. Z-up, the model's
//! coordinates as they are (the 3D-printing convention; see [`super::up`]).

use glam::Vec3;
use std::io::Write;

use super::export::ExportError;
use nendo_geom::mesh::TriMesh;

/// Writes a mesh as binary STL. The face normal is the normalised cross product of the
/// triangle's edges (zero for a degenerate triangle).
///
/// # Errors
/// [`ExportError::TooLarge`] beyond `u32::MAX` triangles; [`ExportError::Io`] when the writer
/// fails.
pub fn write_stl<W: Write>(mesh: &TriMesh, out: &mut W) -> Result<(), ExportError> {
    let count = u32::try_from(mesh.triangle_count()).map_err(|_| ExportError::TooLarge)?;
    let mut header = [b' '; 80];
    let title = b"nendo binary STL";
    header[..title.len()].copy_from_slice(title);
    out.write_all(&header)?;
    out.write_all(&count.to_le_bytes())?;
    let mut record = [0u8; 50];
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let n = (b - a).cross(c - a).try_normalize().unwrap_or(Vec3::ZERO);
        for (k, v) in [n, a, b, c].iter().enumerate() {
            for (m, x) in v.to_array().iter().enumerate() {
                let at = 12 * k + 4 * m;
                record[at..at + 4].copy_from_slice(&x.to_le_bytes());
            }
        }
        out.write_all(&record)?;
    }
    Ok(())
}
