//! Binary glTF 2.0 (GLB): one mesh with one triangle primitive (`POSITION`, `NORMAL`, `u32`
//! indices) in one buffer. Units are the model's (sides). glTF is +Y up: model `(x, y, z)` is
//! written as `(x, z, −y)`, positions and normals (see [`super::up`]).
//!
//! Layout (glTF 2.0 §4.4): a 12-byte header (`glTF`, version 2, total length), a JSON chunk
//! padded with spaces to 4 bytes, and a BIN chunk padded with zeros.

use serde_json::json;
use std::io::Write;

use super::export::ExportError;
use super::up::UpAxis;
use nendo_geom::mesh::TriMesh;

const MAGIC: u32 = 0x4654_6C67; // "glTF"
const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// Writes a mesh as GLB, +Y up.
///
/// # Errors
/// [`ExportError::Empty`] for a mesh without triangles (glTF requires bounds of the positions);
/// [`ExportError::TooLarge`] beyond the 4 GiB a GLB can hold; [`ExportError::Io`] when the
/// writer fails.
pub fn write_glb<W: Write>(mesh: &TriMesh, out: &mut W) -> Result<(), ExportError> {
    let up = UpAxis::Y;
    let Some((lo, hi)) = mesh.bounds().filter(|_| !mesh.indices.is_empty()) else {
        return Err(ExportError::Empty);
    };
    // The box turned: each of its corners maps to a corner, so the bounds are the min and max
    // of the two images (exact: only a sign changes).
    let (a, b) = (up.apply(lo), up.apply(hi));
    let (lo, hi) = (a.min(b), a.max(b));
    let mut bin: Vec<u8> = Vec::with_capacity(24 * mesh.positions.len() + 4 * mesh.indices.len());
    for p in &mesh.positions {
        bin.extend(up.apply(*p).to_array().iter().flat_map(|x| x.to_le_bytes()));
    }
    let normals_at = bin.len();
    for n in &mesh.normals {
        bin.extend(up.apply(*n).to_array().iter().flat_map(|x| x.to_le_bytes()));
    }
    let indices_at = bin.len();
    bin.extend(mesh.indices.iter().flat_map(|i| i.to_le_bytes()));
    let bin_len = bin.len();

    let doc = json!({
        "asset": { "version": "2.0", "generator": "nendo" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0, "name": "nendo" }],
        "meshes": [{ "primitives": [{
            "attributes": { "POSITION": 0, "NORMAL": 1 },
            "indices": 2,
            "mode": 4
        }]}],
        "buffers": [{ "byteLength": bin_len }],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": normals_at, "target": ARRAY_BUFFER },
            { "buffer": 0, "byteOffset": normals_at, "byteLength": indices_at - normals_at, "target": ARRAY_BUFFER },
            { "buffer": 0, "byteOffset": indices_at, "byteLength": bin_len - indices_at, "target": ELEMENT_ARRAY_BUFFER }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": FLOAT, "count": mesh.positions.len(), "type": "VEC3",
              "min": lo.to_array(), "max": hi.to_array() },
            { "bufferView": 1, "componentType": FLOAT, "count": mesh.normals.len(), "type": "VEC3" },
            { "bufferView": 2, "componentType": UNSIGNED_INT, "count": mesh.indices.len(), "type": "SCALAR" }
        ]
    });
    let mut json_bytes = serde_json::to_vec(&doc).map_err(|e| ExportError::Io(e.into()))?;
    while !json_bytes.len().is_multiple_of(4) {
        json_bytes.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json_bytes.len() + 8 + bin.len();
    let total = u32::try_from(total).map_err(|_| ExportError::TooLarge)?;
    out.write_all(&MAGIC.to_le_bytes())?;
    out.write_all(&2u32.to_le_bytes())?;
    out.write_all(&total.to_le_bytes())?;
    out.write_all(&(json_bytes.len() as u32).to_le_bytes())?;
    out.write_all(&CHUNK_JSON.to_le_bytes())?;
    out.write_all(&json_bytes)?;
    out.write_all(&(bin.len() as u32).to_le_bytes())?;
    out.write_all(&CHUNK_BIN.to_le_bytes())?;
    out.write_all(&bin)?;
    Ok(())
}
