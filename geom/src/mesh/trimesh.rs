//! The triangle mesh the tessellation makes ([`TriMesh`]): single-precision positions and
//! normals, indices, and where each patch's block of vertices sits ([`PatchBlock`]); welding
//! for the exporters.

use glam::Vec3;
use std::collections::HashMap;

/// Where one patch's vertices and triangles sit in a [`TriMesh`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PatchBlock {
    /// Index of the patch in the input slice.
    pub patch: u32,
    /// First vertex of the patch; vertex `(k, l)` (at `u = k/m_u`, `v = l/m_v`) is
    /// `first_vertex + k (m_v + 1) + l`.
    pub first_vertex: u32,
    /// First index (into [`TriMesh::indices`]) of the patch's triangles.
    pub first_index: u32,
    /// Segments along `u`.
    pub m_u: u32,
    /// Segments along `v`.
    pub m_v: u32,
}

impl PatchBlock {
    /// Number of vertices of the block.
    #[must_use]
    pub fn vertex_count(&self) -> u32 {
        (self.m_u + 1) * (self.m_v + 1)
    }

    /// Number of indices of the block (three per triangle).
    #[must_use]
    pub fn index_count(&self) -> u32 {
        6 * self.m_u * self.m_v
    }

    /// Vertex index of grid vertex `(k, l)`.
    #[must_use]
    pub fn vertex(&self, k: u32, l: u32) -> u32 {
        self.first_vertex + k * (self.m_v + 1) + l
    }

    /// Parameters `(u, v)` of a vertex of this block.
    #[must_use]
    pub fn uv_of(&self, vertex: u32) -> (f64, f64) {
        let local = vertex - self.first_vertex;
        let (k, l) = (local / (self.m_v + 1), local % (self.m_v + 1));
        (
            f64::from(k) / f64::from(self.m_u),
            f64::from(l) / f64::from(self.m_v),
        )
    }
}

/// A triangle mesh in single precision, as every consumer of a mesh (GPU, STL, GLB) takes it;
/// the geometry it came from stays in `f64`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals: [`crate::surface::Patch::normal`] (`S_u × S_v` of the patch; at a
    /// collapsed edge, the limit from inside the patch), and where the patch has none, the
    /// normal at its centre, else `+Z`.
    pub normals: Vec<Vec3>,
    /// Triangles, three vertex indices each, counter-clockwise around `S_u × S_v`.
    pub indices: Vec<u32>,
    /// One block per patch while the mesh is as tessellated; empty after [`TriMesh::welded`].
    pub blocks: Vec<PatchBlock>,
    /// Largest error bound `(A/m_u² + B/m_v²)/8` over the patches: at most the tolerance unless
    /// `max_segments` capped a patch.
    pub error_bound: f64,
}

impl TriMesh {
    /// Number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// The triangles as vertex index triples.
    pub fn triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        self.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]])
    }

    /// The block holding a vertex, by binary search over [`TriMesh::blocks`].
    #[must_use]
    pub fn block_of_vertex(&self, vertex: u32) -> Option<&PatchBlock> {
        let i = self.blocks.partition_point(|b| b.first_vertex <= vertex);
        let b = self.blocks.get(i.checked_sub(1)?)?;
        (vertex < b.first_vertex + b.vertex_count()).then_some(b)
    }

    /// The mesh with bit-identical positions merged into one vertex (normals summed and
    /// renormalised) and triangles that collapsed (at poles) dropped: what an exporter writes.
    #[must_use]
    pub fn welded(&self) -> TriMesh {
        let mut index_of: HashMap<[u32; 3], u32> = HashMap::with_capacity(self.positions.len());
        let mut remap = Vec::with_capacity(self.positions.len());
        let mut positions = Vec::new();
        let mut normal_sums: Vec<Vec3> = Vec::new();
        for (p, n) in self.positions.iter().zip(&self.normals) {
            let key = position_key(*p);
            let next = positions.len() as u32;
            let id = *index_of.entry(key).or_insert(next);
            if id == next {
                positions.push(*p);
                normal_sums.push(Vec3::ZERO);
            }
            normal_sums[id as usize] += *n;
            remap.push(id);
        }
        let normals = normal_sums
            .iter()
            .zip(&remap_first_normals(&remap, &self.normals, positions.len()))
            .map(|(sum, first)| sum.try_normalize().unwrap_or(*first))
            .collect();
        let mut indices = Vec::with_capacity(self.indices.len());
        for t in self.triangles() {
            let [a, b, c] = t.map(|i| remap[i as usize]);
            if a != b && b != c && a != c {
                indices.extend([a, b, c]);
            }
        }
        TriMesh {
            positions,
            normals,
            indices,
            blocks: Vec::new(),
            error_bound: self.error_bound,
        }
    }

    /// Axis-aligned bounds `(min, max)` of the positions; `None` for an empty mesh.
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))),
        )
    }
}

/// The first normal seen for each welded vertex: the fallback when opposite normals cancel.
fn remap_first_normals(remap: &[u32], normals: &[Vec3], count: usize) -> Vec<Vec3> {
    let mut first = vec![None; count];
    for (id, n) in remap.iter().zip(normals) {
        first[*id as usize].get_or_insert(*n);
    }
    first.into_iter().map(|n| n.unwrap_or(Vec3::Z)).collect()
}

/// A hash key of a position's exact bits (`-0.0` and `0.0` are the same point).
pub(crate) fn position_key(p: Vec3) -> [u32; 3] {
    [p.x, p.y, p.z].map(|c| if c == 0.0 { 0 } else { c.to_bits() })
}
