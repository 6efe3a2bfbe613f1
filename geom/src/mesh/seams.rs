//! The G1 error along patch seams, per mesh vertex, for the heat map.
//!
//! Where patches meet, the tessellation puts bit-identical vertices on both sides of the seam
//! (see [`super::tessellate()`]). At each such vertex the angle between the two patches' exact
//! normals — evaluated again in `f64` from the patches at the vertex's parameters, not the
//! single-precision normals the mesh carries — is the G1 error of docs/design.md §14 sampled at the mesh's
//! seam vertices; at a pole the largest angle among all the patches around it is the spread of
//! their tangent planes. The angle is `atan2(|n₁ × n₂|, |n₁·n₂|)`, accurate down to rounding
//! (an `acos` of a dot product is not: `acos(1 − ε)` in `f32` reads hundredths of a degree on
//! a G1 seam). Normals are compared as lines, so neighbouring patches parametrised in opposite
//! orientations still read 0° where they are tangent-continuous.

use std::collections::HashMap;

use glam::DVec3;

use super::tessellate::{PatchPoints, patch_normal};
use super::trimesh::{TriMesh, position_key};

/// Per-vertex seam angle in degrees: for a vertex on a patch boundary, the largest angle
/// between its patch's exact normal and the exact normal of any coincident vertex of another
/// patch; 0 elsewhere. `patches` are the ones `mesh` was tessellated from; the mesh needs its
/// blocks (an empty result for a welded mesh, or one whose blocks do not match `patches`).
#[must_use]
pub fn seam_angles_deg(patches: &[PatchPoints], mesh: &TriMesh) -> Vec<f32> {
    if mesh.blocks.is_empty()
        || mesh
            .blocks
            .iter()
            .any(|b| b.patch as usize >= patches.len())
    {
        return Vec::new();
    }
    let mut angles = vec![0.0f32; mesh.positions.len()];
    let all: Vec<usize> = (0..mesh.blocks.len()).collect();
    angles_among(patches, mesh, &all, &all, &mut angles);
    angles
}

/// [`seam_angles_deg`] again at the vertices of some blocks only, after their patches (or
/// their neighbours') changed: `targets` (block indices) get their angles recomputed in
/// `angles`, from the boundary vertices of `context` (block indices, a superset of `targets`
/// holding every block that shares a boundary point with a target). Gives the values
/// [`seam_angles_deg`] gives, bit for bit, when no vertex of a target coincides with one
/// outside `context`; costs what the context's boundary costs. Does nothing when the mesh
/// and `angles` do not match (see [`seam_angles_deg`]).
pub fn update_seam_angles_deg(
    patches: &[PatchPoints],
    mesh: &TriMesh,
    context: &[usize],
    targets: &[usize],
    angles: &mut [f32],
) {
    if angles.len() != mesh.positions.len()
        || context.iter().chain(targets).any(|&b| {
            mesh.blocks
                .get(b)
                .is_none_or(|b| b.patch as usize >= patches.len())
        })
    {
        return;
    }
    angles_among(patches, mesh, context, targets, angles);
}

/// Sets the angles of the vertices of the `targets` blocks from the coincidences among the
/// boundary vertices of the `context` blocks.
fn angles_among(
    patches: &[PatchPoints],
    mesh: &TriMesh,
    context: &[usize],
    targets: &[usize],
    angles: &mut [f32],
) {
    let mut is_target = vec![false; mesh.blocks.len()];
    for &t in targets {
        is_target[t] = true;
        let b = mesh.blocks[t];
        angles[b.first_vertex as usize..(b.first_vertex + b.vertex_count()) as usize].fill(0.0);
    }
    // Position → every boundary vertex there: (patch, vertex, target?), exact normal.
    type Coincident = Vec<((u32, u32, bool), DVec3)>;
    let mut at: HashMap<[u32; 3], Coincident> = HashMap::new();
    for &index in context {
        let block = &mesh.blocks[index];
        let target = is_target[index];
        let patch = &patches[block.patch as usize];
        for k in 0..=block.m_u {
            for l in 0..=block.m_v {
                if k == 0 || l == 0 || k == block.m_u || l == block.m_v {
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
                        .push(((block.patch, v, target), patch_normal(patch, u, w)));
                }
            }
        }
    }
    for group in at.values() {
        for (i, &((patch_a, a, target_a), na)) in group.iter().enumerate() {
            for &((patch_b, b, target_b), nb) in &group[i + 1..] {
                if patch_a == patch_b || !(target_a || target_b) {
                    continue;
                }
                let deg = line_angle_deg(na, nb) as f32;
                if target_a {
                    angles[a as usize] = angles[a as usize].max(deg);
                }
                if target_b {
                    angles[b as usize] = angles[b as usize].max(deg);
                }
            }
        }
    }
}

/// The angle between the lines along two unit vectors, degrees: `atan2(|a × b|, |a·b|)`.
fn line_angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b).abs()).to_degrees()
}

/// Spreads the seam angles of [`seam_angles_deg`] into bands for a heat map: for each vertex,
/// `[angle, weight]` of the strongest nearby seam, where a vertex at parameter distance `d`
/// from a patch edge gets that edge's angle (at the same position along the edge) with weight
/// `max(0, 1 − d / width)`. The band is `width` of the patch wide on each side whatever the
/// tessellation density.
#[must_use]
pub fn seam_bands(mesh: &TriMesh, angles_deg: &[f32], width: f32) -> Vec<[f32; 2]> {
    let mut bands = vec![[0.0f32; 2]; mesh.positions.len()];
    let all: Vec<usize> = (0..mesh.blocks.len()).collect();
    update_seam_bands(mesh, angles_deg, width, &all, &mut bands);
    bands
}

/// [`seam_bands`] again for the vertices of some blocks only (block indices), in `bands`
/// (after [`update_seam_angles_deg`] changed their angles): a block's bands depend only on
/// the angles along its own boundary. Does nothing when the lengths do not match the mesh.
pub fn update_seam_bands(
    mesh: &TriMesh,
    angles_deg: &[f32],
    width: f32,
    blocks: &[usize],
    bands: &mut [[f32; 2]],
) {
    if angles_deg.len() != mesh.positions.len() || bands.len() != mesh.positions.len() {
        return;
    }
    let width = width.max(1e-6);
    let fall = |d: f32| (1.0 - d / width).max(0.0);
    for b in blocks.iter().filter_map(|&i| mesh.blocks.get(i)) {
        let (mu, mv) = (b.m_u as f32, b.m_v as f32);
        for k in 0..=b.m_u {
            for l in 0..=b.m_v {
                let (u, v) = (k as f32 / mu, l as f32 / mv);
                let candidates = [
                    (angles_deg[b.vertex(k, 0) as usize], fall(v)),
                    (angles_deg[b.vertex(k, b.m_v) as usize], fall(1.0 - v)),
                    (angles_deg[b.vertex(0, l) as usize], fall(u)),
                    (angles_deg[b.vertex(b.m_u, l) as usize], fall(1.0 - u)),
                ];
                let best = candidates
                    .into_iter()
                    .filter(|(a, w)| *a > 0.0 && *w > 0.0)
                    .max_by(|x, y| (x.0 * x.1).total_cmp(&(y.0 * y.1)));
                bands[b.vertex(k, l) as usize] = best.map_or([0.0, 0.0], |(a, w)| [a, w]);
            }
        }
    }
}

/// Largest seam angle in degrees (0 for a single patch or a welded mesh).
#[must_use]
pub fn max_seam_angle_deg(patches: &[PatchPoints], mesh: &TriMesh) -> f32 {
    seam_angles_deg(patches, mesh)
        .into_iter()
        .fold(0.0, f32::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Tessellation, tessellate};
    use glam::DVec3;

    fn patch(f: impl Fn(f64, f64) -> DVec3, x0: f64) -> [DVec3; 16] {
        std::array::from_fn(|k| f(x0 + (k / 4) as f64 / 3.0, (k % 4) as f64 / 3.0))
    }

    #[test]
    fn a_smooth_join_reads_zero_and_a_fold_reads_its_angle() {
        let flat = |x: f64, y: f64| DVec3::new(x, y, 0.0);
        let flat_patches = [patch(flat, 0.0), patch(flat, 1.0)];
        let smooth = tessellate(&flat_patches, &Tessellation::DISPLAY);
        assert_eq!(max_seam_angle_deg(&flat_patches, &smooth), 0.0);
        // The right patch rises at 30° from the seam x = 1: a crease of 30°.
        let t = 30f64.to_radians().tan();
        let folded = |x: f64, y: f64| DVec3::new(x, y, if x > 1.0 { (x - 1.0) * t } else { 0.0 });
        let folded_patches = [patch(folded, 0.0), patch(folded, 1.0)];
        let mesh = tessellate(
            &folded_patches,
            &Tessellation {
                min_segments: 10,
                ..Tessellation::DISPLAY
            },
        );
        let a = max_seam_angle_deg(&folded_patches, &mesh);
        assert!((a - 30.0).abs() < 1e-4, "{a}");
        let angles = seam_angles_deg(&folded_patches, &mesh);
        let b = mesh.blocks[0];
        assert_eq!(
            angles[b.vertex(0, 1) as usize],
            0.0,
            "the outer edge is no seam"
        );
        assert!((angles[b.vertex(b.m_u, 1) as usize] - 30.0).abs() < 1e-3);
        // The band reaches a fifth into each patch (the vertex 1/10 in gets half the weight),
        // carrying the seam's angle.
        let bands = seam_bands(&mesh, &angles, 0.2);
        let inside = bands[b.vertex(b.m_u - 1, 1) as usize];
        assert!(
            (inside[0] - 30.0).abs() < 1e-3 && (inside[1] - 0.5).abs() < 1e-5,
            "{inside:?}"
        );
        assert_eq!(bands[b.vertex(0, 1) as usize], [0.0, 0.0]);
    }

    /// Every primitive is G1 along its seams and has a tangent plane at its poles: the exact
    /// normals read 0° up to rounding (an `f32` `acos` read up to ~0.03°).
    #[test]
    fn exact_primitives_read_no_seam_error() {
        use crate::surface::{Primitive, PrimitiveParams};
        for p in Primitive::ALL {
            let patches = p
                .build(&PrimitiveParams::default())
                .expect("primitive")
                .patches();
            let mesh = tessellate(&patches, &Tessellation::DISPLAY);
            let angles = seam_angles_deg(&patches, &mesh);
            assert_eq!(angles.len(), mesh.positions.len());
            let max = angles.iter().copied().fold(0.0, f32::max);
            assert!(max < 1e-6, "{p}: seam max {max}°");
        }
        // A welded mesh has no blocks, and blocks that do not match the patches are refused.
        let patches = Primitive::Sphere
            .build(&PrimitiveParams::default())
            .expect("sphere")
            .patches();
        let mesh = tessellate(&patches, &Tessellation::DISPLAY);
        assert!(seam_angles_deg(&patches, &mesh.welded()).is_empty());
        assert!(seam_angles_deg(&patches[..3], &mesh).is_empty());
    }
}
