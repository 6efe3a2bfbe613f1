//! The G2 error along patch seams, per mesh vertex, for the heat map's G2 mode: the relative
//! curvature mismatch across the seam of [`crate::surface::curvature`] (Rhino's
//! `|κ₁ − κ₂| / (|κ₁| + |κ₂|)`, as `nendo check` reports it), in percent.
//!
//! At a boundary vertex of patch A with a coincident vertex of patch B on the same edge, the
//! seam's tangent `T` is A's derivative along the edge (`S_v` on a `u = 0, 1` edge, `S_u` on a
//! `v = 0, 1` edge), each side's normal curvature is taken in the direction `d = N × T`
//! across the seam (B's normal turned to agree with A's), and the vertex gets the largest
//! mismatch over its coincident vertices. Patch corners (where two edges meet and a
//! coincident vertex may lie on either) and poles (no tangent plane) read 0; the heat bands
//! ([`super::seam_bands`]) spread the edge values over them. Both sides flat (`|κ₁| + |κ₂|`
//! below `1e-9` / the model's size) reads 0.

use std::collections::HashMap;

use glam::DVec3;

use super::tessellate::PatchPoints;
use super::trimesh::{TriMesh, position_key};
use crate::surface::curvature::normal_curvature;
use crate::surface::patch::Patch;

/// Per-vertex relative G2 mismatch across the seam, percent (0 off the seams, at corners and
/// at poles); empty for a mesh without blocks or whose blocks do not match `patches`.
#[must_use]
pub fn seam_g2_percent(patches: &[PatchPoints], mesh: &TriMesh) -> Vec<f32> {
    if mesh.blocks.is_empty()
        || mesh
            .blocks
            .iter()
            .any(|b| b.patch as usize >= patches.len())
    {
        return Vec::new();
    }
    let size = mesh
        .bounds()
        .map_or(1.0, |(lo, hi)| f64::from((hi - lo).length()))
        .max(f64::MIN_POSITIVE);
    let flat = 1e-9 / size;
    let mut out = vec![0.0f32; mesh.positions.len()];
    // Position → boundary vertices there that are not corners: (patch, vertex, u, v).
    type Edge = Vec<(u32, u32, f64, f64)>;
    let mut at: HashMap<[u32; 3], Edge> = HashMap::new();
    for block in &mesh.blocks {
        for k in 0..=block.m_u {
            for l in 0..=block.m_v {
                let on_u = k == 0 || k == block.m_u;
                let on_v = l == 0 || l == block.m_v;
                if on_u == on_v {
                    continue;
                }
                let v = block.vertex(k, l);
                let Some(position) = mesh.positions.get(v as usize) else {
                    continue;
                };
                let (u, w) = (
                    f64::from(k) / f64::from(block.m_u),
                    f64::from(l) / f64::from(block.m_v),
                );
                at.entry(position_key(*position))
                    .or_default()
                    .push((block.patch, v, u, w));
            }
        }
    }
    for group in at.values() {
        for (i, &(pa, va, ua, wa)) in group.iter().enumerate() {
            for &(pb, vb, ub, wb) in &group[i + 1..] {
                if pa == pb {
                    continue;
                }
                let (a, b) = (
                    Patch::new(patches[pa as usize]),
                    Patch::new(patches[pb as usize]),
                );
                let Some(mismatch) = mismatch_at(&a, ua, wa, &b, ub, wb, flat) else {
                    continue;
                };
                let percent = (100.0 * mismatch) as f32;
                out[va as usize] = out[va as usize].max(percent);
                out[vb as usize] = out[vb as usize].max(percent);
            }
        }
    }
    out
}

/// The relative mismatch of the normal curvatures across the seam at a point shared by
/// `a (ua, va)` (on an edge of `a`) and `b (ub, vb)`; `None` without a tangent plane.
fn mismatch_at(a: &Patch, ua: f64, va: f64, b: &Patch, ub: f64, vb: f64, flat: f64) -> Option<f64> {
    let na = a.normal(ua, va)?;
    let nb = b.normal(ub, vb)?;
    let nb = if nb.dot(na) < 0.0 { -nb } else { nb };
    let frame = a.frame(ua, va);
    let along_v_edge = ua == 0.0 || ua == 1.0;
    let tangent: DVec3 = if along_v_edge { frame.dv } else { frame.du }.try_normalize()?;
    let ka = normal_curvature(a, ua, va, na, na.cross(tangent))?;
    let kb = normal_curvature(b, ub, vb, nb, nb.cross(tangent))?;
    let sum = ka.abs() + kb.abs();
    Some(if sum > flat {
        (ka - kb).abs() / sum
    } else {
        0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Tessellation, tessellate};

    /// Two patches of `z = x² + c(x) y`-like height fields meeting at `x = 0`: the parabola
    /// `z = x²` (G2 across the seam), and the same with the right patch's second column
    /// lifted, which keeps G1 and changes the right side's curvature.
    #[test]
    fn a_curvature_jump_reads_on_its_seam_and_a_smooth_seam_reads_zero() {
        // Control heights of x² on [x0, x0 + 1] from its blossom.
        let heights = |x0: f64| {
            let x1 = x0 + 1.0;
            [
                x0 * x0,
                (x0 * x0 + 2.0 * x0 * x1) / 3.0,
                (2.0 * x0 * x1 + x1 * x1) / 3.0,
                x1 * x1,
            ]
        };
        let patch = |x0: f64, bump: f64| {
            let z = heights(x0);
            let mut p = [DVec3::ZERO; 16];
            for i in 0..4 {
                for j in 0..4 {
                    let extra = if i == 2 { bump } else { 0.0 };
                    p[4 * i + j] = DVec3::new(x0 + i as f64 / 3.0, j as f64 / 3.0, z[i] + extra);
                }
            }
            p
        };
        for (bump, expect_zero) in [(0.0, true), (0.1, false)] {
            let patches = [patch(-1.0, 0.0), patch(0.0, bump)];
            let mesh = tessellate(&patches, &Tessellation::DISPLAY);
            let g2 = seam_g2_percent(&patches, &mesh);
            let worst = g2.iter().copied().fold(0.0, f32::max);
            if expect_zero {
                assert!(worst < 1e-6, "G2 seam reads {worst} %");
            } else {
                // κ = 2 on the left; on the right S_uu·N changes by 6·0.1·3²·…: a clear jump.
                assert!(worst > 5.0, "curvature jump reads {worst} %");
            }
        }
    }
}
