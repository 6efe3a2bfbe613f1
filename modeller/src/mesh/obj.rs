//! Wavefront OBJ: `v` positions, `vn` normals, `s 1` (smooth shading: the normals are the
//! surface's), `f a//a b//b c//c` triangles (1-based indices, one normal per vertex).
//!
//! Y-up by default (Blender's and most tools' assumption; see [`super::up`]), Z-up on
//! request. Numbers are the shortest text that reads back to the same `f32`: positional for
//! magnitudes in `[1e-4, 1e7)`, else with an exponent (`1.06e-36`, not 36 zeros).

use std::io::Write;

use super::export::ExportError;
use super::up::UpAxis;
use nendo_geom::mesh::TriMesh;

/// `x` as the shortest text that reads back to the same `f32`.
fn number(x: f32) -> String {
    let a = x.abs();
    if a == 0.0 || (1e-4..1e7).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// Writes a mesh as OBJ text with `up` as the file's up axis.
///
/// # Errors
/// [`ExportError::Io`] when the writer fails.
pub fn write_obj<W: Write>(mesh: &TriMesh, out: &mut W, up: UpAxis) -> Result<(), ExportError> {
    writeln!(
        out,
        "# nendo mesh: {} vertices, {} triangles, +{} up",
        mesh.positions.len(),
        mesh.triangle_count(),
        up.name().to_ascii_uppercase()
    )?;
    writeln!(out, "o nendo")?;
    for p in &mesh.positions {
        let p = up.apply(*p);
        writeln!(out, "v {} {} {}", number(p.x), number(p.y), number(p.z))?;
    }
    for n in &mesh.normals {
        let n = up.apply(*n);
        writeln!(out, "vn {} {} {}", number(n.x), number(n.y), number(n.z))?;
    }
    writeln!(out, "s 1")?;
    for [a, b, c] in mesh.triangles().map(|t| t.map(|i| i + 1)) {
        writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_read_back_exactly() {
        assert_eq!(number(0.0), "0");
        assert_eq!(number(0.5), "0.5");
        assert_eq!(number(1.06e-36), "1.06e-36");
        assert_eq!(number(-3.0e9), "-3e9");
        let mut state = 0x2545_F491u32;
        for _ in 0..50_000 {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            let x = f32::from_bits(state);
            if x.is_finite() {
                let t = number(x);
                assert_eq!(t.parse::<f32>().ok(), Some(x), "{t}");
                assert!(t.len() <= 16, "{t}");
            }
        }
    }
}
