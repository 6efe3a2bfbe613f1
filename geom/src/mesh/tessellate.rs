//! Tessellation of bicubic Bezier patches into triangles within a chosen tolerance: the entry
//! points ([`tessellate`], [`try_tessellate`]) and the evaluation of one patch's vertices.
//!
//! A patch is sampled on a uniform `m_u × m_v` grid of its parameter square and every grid cell
//! is split into two triangles. The parts: how many segments each patch gets so that the
//! triangles stay within the tolerance ([`super::plan`]); how neighbours agree on the vertices
//! of the edge they share, so that the mesh has no cracks ([`super::edges`]); the mesh type
//! ([`super::trimesh`]); keeping a mesh up to date while a few patches change
//! ([`super::live`]).

use glam::{DVec3, Vec3};

use super::edges::{canonical, edges};
#[cfg(doc)]
use super::plan::estimate;
use super::plan::{MeshSize, Plan, Tessellation};
use super::trimesh::{PatchBlock, TriMesh};
use crate::curve::bernstein;
use crate::surface::patch::{Patch, VLine, cubic_basis, cubic_basis_derivative, regular_normal};

pub use crate::surface::patch::PatchPoints;

/// Why [`try_tessellate`] refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum TessellateError {
    /// The mesh would have more triangles than the limit the caller set.
    #[error(
        "the mesh would have {} triangles ({} vertices, about {} MB), more than the limit of {limit} triangles",
        .estimate.triangles,
        .estimate.vertices,
        .estimate.bytes() / 1_000_000
    )]
    TooManyTriangles {
        /// The exact size of the mesh that was refused.
        estimate: MeshSize,
        /// The limit, triangles.
        limit: u64,
    },
    /// The mesh would have more vertices than `u32` indices can address.
    #[error(
        "the mesh would have {} vertices, more than 32-bit indices can address",
        .estimate.vertices
    )]
    TooManyVertices {
        /// The exact size of the mesh that was refused.
        estimate: MeshSize,
    },
}

/// [`tessellate`], refusing before it allocates the mesh when the mesh would have more than
/// `max_triangles` triangles (or more vertices than `u32` indices address).
///
/// # Errors
/// [`TessellateError::TooManyTriangles`] / [`TessellateError::TooManyVertices`], carrying the
/// exact size of the refused mesh.
pub fn try_tessellate(
    patches: &[PatchPoints],
    settings: &Tessellation,
    max_triangles: u64,
) -> Result<TriMesh, TessellateError> {
    let plan = Plan::new(patches, settings);
    let estimate = plan.size();
    if estimate.triangles > max_triangles {
        return Err(TessellateError::TooManyTriangles {
            estimate,
            limit: max_triangles,
        });
    }
    // Indices are u32, and so are the index offsets of the blocks.
    if estimate.vertices > u64::from(u32::MAX) || estimate.triangles * 3 > u64::from(u32::MAX) {
        return Err(TessellateError::TooManyVertices { estimate });
    }
    Ok(build(patches, &plan))
}

/// Tessellates patches into one mesh, watertight across every edge the patches share exactly.
///
/// It allocates the whole mesh ([`estimate`] tells how big beforehand); where the patches or
/// the tolerance come from a user, use [`try_tessellate`].
///
/// ```
/// use glam::DVec3;
/// use nendo_geom::mesh::{Tessellation, tessellate};
/// // A flat unit square as a bicubic patch.
/// let square: [DVec3; 16] =
///     std::array::from_fn(|k| DVec3::new((k / 4) as f64 / 3.0, (k % 4) as f64 / 3.0, 0.0));
/// let mesh = tessellate(&[square], &Tessellation::with_tolerance(1e-3));
/// assert_eq!(mesh.triangle_count(), 2); // flat: one cell is exact
/// ```
#[must_use]
pub fn tessellate(patches: &[PatchPoints], settings: &Tessellation) -> TriMesh {
    build(patches, &Plan::new(patches, settings))
}

/// Builds the mesh a plan describes.
fn build(patches: &[PatchPoints], plan: &Plan) -> TriMesh {
    build_with_bounds(patches, plan).0
}

/// Builds the mesh a plan describes, with each patch's error bound.
pub(super) fn build_with_bounds(patches: &[PatchPoints], plan: &Plan) -> (TriMesh, Vec<f64>) {
    let mut bounds = Vec::with_capacity(patches.len());
    let size = plan.size();
    let mut mesh = TriMesh {
        positions: Vec::with_capacity(size.vertices as usize),
        normals: Vec::with_capacity(size.vertices as usize),
        indices: Vec::with_capacity(3 * size.triangles as usize),
        blocks: Vec::with_capacity(patches.len()),
        error_bound: 0.0,
    };
    for (index, (p, [m_u, m_v])) in patches.iter().zip(&plan.counts).enumerate() {
        let [a, b] = plan.own[index].1;
        let (fu, fv) = (f64::from(*m_u), f64::from(*m_v));
        let bound = (a / (fu * fu) + b / (fv * fv)) / 8.0;
        bounds.push(bound);
        mesh.error_bound = mesh.error_bound.max(bound);
        let block = PatchBlock {
            patch: index as u32,
            first_vertex: mesh.positions.len() as u32,
            first_index: mesh.indices.len() as u32,
            m_u: *m_u,
            m_v: *m_v,
        };
        push_patch(&mut mesh, p, &block);
        mesh.blocks.push(block);
    }
    (mesh, bounds)
}

/// Point and partial derivatives `(S, S_u, S_v)` of a patch at `(u, v)`: [`Patch::frame`].
#[must_use]
pub fn eval_patch(p: &PatchPoints, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
    let f = Patch::new(*p).frame(u, v);
    (f.point, f.du, f.dv)
}

/// Unit normal of a patch at `(u, v)`: [`Patch::normal`] (on a collapsed boundary, a pole, the
/// limit from inside the patch), and where the patch has no normal the mesh's fallback,
/// the normal at the patch centre, else `+Z`.
#[must_use]
pub fn patch_normal(p: &PatchPoints, u: f64, v: f64) -> DVec3 {
    let patch = Patch::new(*p);
    patch
        .normal(u, v)
        .unwrap_or_else(|| fallback_normal(&patch))
}

/// The normal a mesh vertex takes where its patch has none ([`Patch::normal`] is `None`: the
/// patch is degenerate there beyond a collapsed edge, folded onto itself or shrunk to a
/// curve): the normal at the patch's centre, or `+Z` when the patch has none there either
/// (a patch that is a curve or a point). A vertex needs some unit vector; this one is
/// never used where the surface has a tangent plane.
fn fallback_normal(patch: &Patch) -> DVec3 {
    patch.normal(0.5, 0.5).unwrap_or(DVec3::Z)
}

/// Appends one patch's vertices and triangles.
fn push_patch(mesh: &mut TriMesh, p: &PatchPoints, block: &PatchBlock) {
    let count = block.vertex_count() as usize;
    let first = mesh.positions.len();
    mesh.positions.resize(first + count, Vec3::ZERO);
    mesh.normals.resize(first + count, Vec3::ZERO);
    write_patch_vertices(
        p,
        block,
        &mut mesh.positions[first..],
        &mut mesh.normals[first..],
    );
    let (m_u, m_v) = (block.m_u, block.m_v);
    for k in 0..m_u {
        for l in 0..m_v {
            let a = block.vertex(k, l);
            let b = block.vertex(k + 1, l);
            let c = block.vertex(k + 1, l + 1);
            let d = block.vertex(k, l + 1);
            // Counter-clockwise seen from S_u × S_v: u is "right", v is "up".
            mesh.indices.extend([a, b, c, a, c, d]);
        }
    }
}

/// Writes one patch's vertices (`block.vertex_count()` of them, in block order) into
/// `positions` and `normals`.
pub(super) fn write_patch_vertices(
    p: &PatchPoints,
    block: &PatchBlock,
    positions: &mut [Vec3],
    normals: &mut [Vec3],
) {
    let (m_u, m_v) = (block.m_u, block.m_v);
    let mut slot = 0usize;
    let [e_v0, e_v1, e_u0, e_u1] = edges(p).map(|(e, _)| canonical(&e));
    let on_edge = |(edge, reversed): &([DVec3; 4], bool), k: u32, m: u32| -> DVec3 {
        let k = if *reversed { m - k } else { k };
        // The ends are the corner control points themselves: `a + (b − a)·1` need not be `b`.
        match k {
            0 => edge[0],
            k if k == m => edge[3],
            k => bernstein::eval(edge, f64::from(k) / f64::from(m)),
        }
    };
    let patch = Patch::new(*p);
    let size = patch.size();
    // The patch along each grid line v = l / m_v: half of every vertex's evaluation, shared
    // by the vertices of the line (the same bits as `Patch::frame`).
    let lines: Vec<VLine> = (0..=m_v)
        .map(|l| patch.v_line(f64::from(l) / f64::from(m_v)))
        .collect();
    for k in 0..=m_u {
        let u = f64::from(k) / f64::from(m_u);
        let (bu, du) = (cubic_basis(u), cubic_basis_derivative(u));
        for (l, line) in lines.iter().enumerate() {
            let l = l as u32;
            let v = f64::from(l) / f64::from(m_v);
            let (point, su, sv) = line.tangents(&bu, &du);
            let position = if l == 0 {
                on_edge(&e_v0, k, m_u)
            } else if l == m_v {
                on_edge(&e_v1, k, m_u)
            } else if k == 0 {
                on_edge(&e_u0, l, m_v)
            } else if k == m_u {
                on_edge(&e_u1, l, m_v)
            } else {
                point
            };
            // `Patch::normal`, its regular case taken from the derivatives at hand.
            let normal = regular_normal(su, sv, size)
                .or_else(|| patch.normal(u, v))
                .unwrap_or_else(|| fallback_normal(&patch));
            positions[slot] = position.as_vec3();
            normals[slot] = normal.as_vec3();
            slot += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::estimate;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use std::collections::HashMap;

    fn grid_patch(f: impl Fn(f64, f64) -> DVec3, origin: (f64, f64)) -> PatchPoints {
        std::array::from_fn(|k| {
            let (i, j) = ((k / 4) as f64 / 3.0, (k % 4) as f64 / 3.0);
            f(origin.0 + i, origin.1 + j)
        })
    }

    fn random_patch(rng: &mut ChaCha8Rng) -> PatchPoints {
        std::array::from_fn(|k| {
            let (i, j) = ((k / 4) as f64, (k % 4) as f64);
            DVec3::new(i, j, 0.0)
                + DVec3::new(
                    rng.gen_range(-0.6..0.6),
                    rng.gen_range(-0.6..0.6),
                    rng.gen_range(-1.5..1.5),
                )
        })
    }

    /// Largest distance between the mesh and the surface at the same parameters, sampled at
    /// barycentric points of every triangle.
    fn measured_error(patch: &PatchPoints, mesh: &TriMesh) -> f64 {
        let block = mesh.blocks[0];
        let mut worst = 0.0f64;
        for t in mesh.triangles() {
            let uv = t.map(|i| block.uv_of(i));
            let pos = t.map(|i| mesh.positions[i as usize].as_dvec3());
            for a in 0..=6 {
                for b in 0..=(6 - a) {
                    let (wa, wb) = (a as f64 / 6.0, b as f64 / 6.0);
                    let wc = 1.0 - wa - wb;
                    let u = wa * uv[0].0 + wb * uv[1].0 + wc * uv[2].0;
                    let v = wa * uv[0].1 + wb * uv[1].1 + wc * uv[2].1;
                    let on_mesh = pos[0] * wa + pos[1] * wb + pos[2] * wc;
                    worst = worst.max((eval_patch(patch, u, v).0 - on_mesh).length());
                }
            }
        }
        worst
    }

    #[test]
    fn error_stays_under_the_tolerance_on_random_patches() {
        let mut rng = ChaCha8Rng::seed_from_u64(6);
        for tol in [1e-1, 1e-2, 1e-3] {
            for _ in 0..20 {
                let p = random_patch(&mut rng);
                let mesh = tessellate(&[p], &Tessellation::with_tolerance(tol));
                assert!(
                    mesh.error_bound <= tol,
                    "bound {} > {tol}",
                    mesh.error_bound
                );
                // f32 positions add ~1e-7 of rounding at this scale.
                let e = measured_error(&p, &mesh);
                assert!(e <= tol + 1e-6, "error {e} > tolerance {tol}");
            }
        }
    }

    #[test]
    fn estimate_is_the_size_of_the_mesh_and_try_refuses_over_the_limit() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for tol in [1e-1, 1e-3, 1e-5] {
            // Neighbours sharing edges, so the tie between them is part of the count.
            let patches: Vec<PatchPoints> = (0..4)
                .map(|k| {
                    let mut p = random_patch(&mut rng);
                    for q in &mut p {
                        q.x += 3.0 * f64::from(k);
                    }
                    p
                })
                .collect();
            let mut shared = patches.clone();
            for k in 1..shared.len() {
                for j in 0..4 {
                    shared[k][j] = shared[k - 1][12 + j];
                }
            }
            let settings = Tessellation::with_tolerance(tol);
            let size = estimate(&shared, &settings);
            let mesh = tessellate(&shared, &settings);
            assert_eq!(size.triangles, mesh.triangle_count() as u64);
            assert_eq!(size.vertices, mesh.positions.len() as u64);
            assert!(mesh.welded().triangle_count() as u64 <= size.triangles);
            assert_eq!(
                try_tessellate(&shared, &settings, size.triangles).as_ref(),
                Ok(&mesh)
            );
            assert_eq!(
                try_tessellate(&shared, &settings, size.triangles - 1),
                Err(TessellateError::TooManyTriangles {
                    estimate: size,
                    limit: size.triangles - 1
                })
            );
        }
    }

    #[test]
    fn flat_bilinear_patch_needs_one_cell() {
        let p = grid_patch(|u, v| DVec3::new(2.0 * u, v, 0.5), (0.0, 0.0));
        let mesh = tessellate(&[p], &Tessellation::with_tolerance(1e-6));
        assert_eq!((mesh.blocks[0].m_u, mesh.blocks[0].m_v), (1, 1));
        assert_eq!(mesh.triangle_count(), 2);
        for n in &mesh.normals {
            assert!((*n - Vec3::Z).length() < 1e-6);
        }
    }

    #[test]
    fn neighbours_with_different_curvature_share_edge_vertices() {
        // Two patches side by side along u; the right one is strongly curved, the left flat.
        let bump = |x: f64, y: f64| {
            DVec3::new(
                x,
                y,
                if x > 1.0 {
                    (3.0 * (x - 1.0)).sin() * y
                } else {
                    0.0
                },
            )
        };
        let left = grid_patch(bump, (0.0, 0.0));
        let right = grid_patch(bump, (1.0, 0.0));
        // Present the right patch transposed (its u along the left one's v) to test the tie
        // across differently oriented neighbours.
        let right_t: PatchPoints = std::array::from_fn(|k| right[4 * (k % 4) + k / 4]);
        let mesh = tessellate(&[left, right_t], &Tessellation::with_tolerance(1e-4));
        let welded = mesh.welded();
        // Boundary edges (used by one triangle) must only lie on the outer square [0,2]×[0,1].
        let mut edge_use: HashMap<(u32, u32), u32> = HashMap::new();
        for t in welded.triangles() {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *edge_use.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        for ((a, b), uses) in edge_use {
            assert!(uses <= 2);
            if uses == 1 {
                let (pa, pb) = (welded.positions[a as usize], welded.positions[b as usize]);
                let outer = |p: Vec3| {
                    p.x.abs() < 1e-6
                        || (p.x - 2.0).abs() < 1e-6
                        || p.y.abs() < 1e-6
                        || (p.y - 1.0).abs() < 1e-6
                };
                let inner_seam = (pa.x - 1.0).abs() < 1e-6 && (pb.x - 1.0).abs() < 1e-6;
                assert!(
                    outer(pa) && outer(pb) && !inner_seam,
                    "crack at {pa} – {pb}"
                );
            }
        }
    }

    #[test]
    fn collapsed_edge_keeps_one_point_and_a_finite_normal() {
        // A quarter of a cone: the v = 0 edge collapses to the apex.
        let p: PatchPoints = std::array::from_fn(|k| {
            let (i, j) = ((k / 4) as f64 / 3.0, (k % 4) as f64 / 3.0);
            let a = i * std::f64::consts::FRAC_PI_2;
            DVec3::new(j * a.cos(), j * a.sin(), 1.0 - j)
        });
        let mesh = tessellate(&[p], &Tessellation::DISPLAY);
        let b = mesh.blocks[0];
        let apex: Vec<Vec3> = (0..=b.m_u)
            .map(|k| mesh.positions[b.vertex(k, 0) as usize])
            .collect();
        assert!(apex.iter().all(|q| *q == Vec3::new(0.0, 0.0, 1.0)));
        assert!(
            mesh.normals
                .iter()
                .all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-5)
        );
        let welded = mesh.welded();
        assert_eq!(
            welded.triangle_count(),
            mesh.triangle_count() - b.m_u as usize
        );
    }

    #[test]
    fn every_vertex_normal_is_the_patch_normal() {
        use crate::surface::{Primitive, PrimitiveParams};
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut sets: Vec<Vec<PatchPoints>> =
            (0..5).map(|_| vec![random_patch(&mut rng)]).collect();
        for primitive in [Primitive::Sphere, Primitive::Tube] {
            sets.push(
                primitive
                    .build(&PrimitiveParams::default())
                    .unwrap()
                    .patches(),
            );
        }
        for patches in &sets {
            let mesh = tessellate(patches, &Tessellation::DISPLAY);
            for b in &mesh.blocks {
                let patch = Patch::new(patches[b.patch as usize]);
                for v in b.first_vertex..b.first_vertex + b.vertex_count() {
                    let (u, w) = b.uv_of(v);
                    let want = patch.normal(u, w).expect("a normal").as_vec3();
                    assert_eq!(mesh.normals[v as usize], want, "({u}, {w})");
                }
            }
        }
    }

    #[test]
    fn a_patch_shrunk_to_a_curve_takes_the_explicit_fallback_normal() {
        let p: PatchPoints = std::array::from_fn(|k| DVec3::new((k / 4 + k % 4) as f64, 0.0, 1.0));
        assert_eq!(Patch::new(p).normal(0.3, 0.6), None);
        let mesh = tessellate(&[p], &Tessellation::DISPLAY);
        assert!(mesh.normals.iter().all(|n| *n == Vec3::Z));
        assert_eq!(patch_normal(&p, 0.3, 0.6), DVec3::Z);
    }
}
