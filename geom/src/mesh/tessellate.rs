//! Tessellation of bicubic Bezier patches into triangles within a chosen tolerance.
//!
//! A patch `S(u,v) = Σ_i Σ_j B_i³(u) B_j³(v) P[4i+j]` is sampled on a uniform `m_u × m_v` grid of
//! its parameter square and every grid cell is split into two triangles. The counts come from a
//! bound on the second derivatives, so the distance between a triangle and the surface at the
//! same parameters never exceeds the tolerance:
//!
//! - `|S_uu| ≤ 6 max|Δ²_u P|`, `|S_vv| ≤ 6 max|Δ²_v P|`, `|S_uv| ≤ 9 max|Δ_u Δ_v P|` (the
//!   derivatives are Bezier patches whose control points are these differences, and a Bezier
//!   patch lies in the convex hull of its control points);
//! - so for every direction `d`, `|S''[d,d]| ≤ A d_u² + B d_v²` with `A = M_uu + M_uv`,
//!   `B = M_vv + M_uv` (using `2|d_u d_v| ≤ d_u² + d_v²`);
//! - the linear interpolant on a triangle errs by at most `½ M R²`, `R` the radius of the
//!   smallest ball holding the triangle and `M` the second-derivative bound (Waldron, *The error
//!   in linear interpolation at the vertices of a simplex*, SIAM J. Numer. Anal. 35, 1998).
//!   Applied in the coordinates `(u√A, v√B)`, where `M = 1`, a right triangle with legs
//!   `1/m_u, 1/m_v` gives `error ≤ (A/m_u² + B/m_v²) / 8`;
//! - half of the tolerance goes to each term: `m_u = ⌈√(A / 4 tol)⌉`, `m_v = ⌈√(B / 4 tol)⌉`.
//!
//! **No cracks.** Neighbouring patches must place the same vertices on the edge they share.
//! Every patch edge belongs to one of the patch's two directions (the edges `v = 0, 1` run along
//! `u` and use `m_u`). Edges with identical control points (in either order) tie their
//! directions together, across all patches and whatever the topology, and each tied set takes
//! the largest count of its members. Edge vertices are then evaluated from the edge's own cubic
//! in a canonical orientation (de Casteljau, so a collapsed edge at a pole stays exactly one
//! point), which makes both sides bit-identical: the mesh is watertight without welding, and
//! [`TriMesh::welded`] can merge the copies exactly.

use glam::{DVec3, Vec3};
use std::collections::HashMap;

use crate::curve::bernstein;

/// A bicubic Bezier patch: 16 control points `P[4*i + j]`, `i` along `u`, `j` along `v`.
pub type PatchPoints = [DVec3; 16];

/// How finely patches are tessellated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tessellation {
    /// Largest allowed distance between a triangle and the surface at the same parameters, in
    /// model units (sides). Not a positive number: every patch gets `max_segments`.
    pub tolerance: f64,
    /// Fewest segments along each direction of a patch (at least 1).
    pub min_segments: u32,
    /// Most segments along each direction of a patch; when it binds, the tolerance is not met
    /// (see [`TriMesh::error_bound`]).
    pub max_segments: u32,
}

impl Tessellation {
    /// What the modeller draws: 1/100 side — about a pixel when ten sides fill a 1280-pixel
    /// view — with at least 4 segments per patch edge so that shading and the seam heat map
    /// stay smooth on flat patches.
    pub const DISPLAY: Self = Self {
        tolerance: 1e-2,
        min_segments: 4,
        max_segments: 32,
    };

    /// The default for exported meshes: 1/1000 side, as few triangles as the tolerance allows.
    pub const EXPORT: Self = Self {
        tolerance: 1e-3,
        min_segments: 1,
        max_segments: 256,
    };

    /// The default limit on the triangles of an exported mesh (`nendo export --max-triangles`,
    /// the window's export): 20 million triangles take about 0.5 GB as tessellated
    /// ([`MeshSize::bytes`]) and about twice that at the peak of welding and writing.
    pub const DEFAULT_MAX_TRIANGLES: u64 = 20_000_000;

    /// A tessellation to the given tolerance with the export limits.
    #[must_use]
    pub fn with_tolerance(tolerance: f64) -> Self {
        Self {
            tolerance,
            ..Self::EXPORT
        }
    }

    /// Segments `(m_u, m_v)` one patch needs on its own, and the bound `(A, B)` of its second
    /// derivatives (see the module docs).
    fn own_counts(&self, p: &PatchPoints) -> ([u32; 2], [f64; 2]) {
        let (a, b) = second_derivative_bounds(p);
        let lo = self.min_segments.max(1);
        let hi = self.max_segments.max(lo);
        let count = |k: f64| -> u32 {
            let m = (k / (4.0 * self.tolerance)).sqrt().ceil();
            // A tolerance that is not a positive number (or a NaN patch) asks for the finest.
            if m.is_finite() && self.tolerance > 0.0 {
                (m as u32).clamp(lo, hi)
            } else {
                hi
            }
        };
        ([count(a), count(b)], [a, b])
    }
}

impl Default for Tessellation {
    fn default() -> Self {
        Self::DISPLAY
    }
}

/// `(A, B)` of the module docs: `A = M_uu + M_uv`, `B = M_vv + M_uv`.
fn second_derivative_bounds(p: &PatchPoints) -> (f64, f64) {
    let at = |i: usize, j: usize| p[4 * i + j];
    let mut m_uu = 0.0f64;
    let mut m_vv = 0.0f64;
    let mut m_uv = 0.0f64;
    for a in 0..4 {
        for k in 0..2 {
            m_uu = m_uu.max((at(k + 2, a) - 2.0 * at(k + 1, a) + at(k, a)).length());
            m_vv = m_vv.max((at(a, k + 2) - 2.0 * at(a, k + 1) + at(a, k)).length());
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            m_uv = m_uv.max((at(i + 1, j + 1) - at(i + 1, j) - at(i, j + 1) + at(i, j)).length());
        }
    }
    (6.0 * m_uu + 9.0 * m_uv, 6.0 * m_vv + 9.0 * m_uv)
}

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
    /// Unit vertex normals (`S_u × S_v` of the patch; at a collapsed edge, the limit from
    /// inside the patch).
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

/// The size of the mesh [`tessellate`] makes for some patches and settings, computed from the
/// same per-patch segment counts (after tying shared edges) without building the mesh.
///
/// The counts are exact for the mesh [`tessellate`] returns; [`TriMesh::welded`] only removes
/// vertices and triangles, so they bound an exported mesh from above.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshSize {
    /// Vertices before welding.
    pub vertices: u64,
    /// Triangles before welding.
    pub triangles: u64,
}

impl MeshSize {
    /// Bytes the tessellated mesh takes: a position and a normal (2 × 12 bytes) per vertex and
    /// three `u32` indices per triangle. Welding it (as exporters do) needs about as much again
    /// at its peak, plus a hash map entry per vertex.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        self.vertices
            .saturating_mul(24)
            .saturating_add(self.triangles.saturating_mul(12))
    }
}

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

/// Segment counts of every patch for some settings: the plan [`tessellate`] follows.
#[derive(Debug, Clone)]
struct Plan {
    /// Each patch's own counts and second-derivative bounds.
    own: Vec<([u32; 2], [f64; 2])>,
    /// The counts after tying shared edges.
    counts: Vec<[u32; 2]>,
    /// The tied class of each patch direction `2 · patch + direction` (a representative).
    classes: Vec<usize>,
}

impl Plan {
    fn new(patches: &[PatchPoints], settings: &Tessellation) -> Self {
        let own: Vec<([u32; 2], [f64; 2])> =
            patches.iter().map(|p| settings.own_counts(p)).collect();
        let (counts, classes) = tie_shared_edges(patches, &own);
        Self {
            own,
            counts,
            classes,
        }
    }

    fn size(&self) -> MeshSize {
        let mut size = MeshSize {
            vertices: 0,
            triangles: 0,
        };
        for [a, b] in &self.counts {
            let (a, b) = (u64::from(*a), u64::from(*b));
            size.vertices += (a + 1) * (b + 1);
            size.triangles += 2 * a * b;
        }
        size
    }
}

/// The size of the mesh [`tessellate`] would make, without making it: memory proportional to
/// the number of patches only (the counts and the shared-edge map).
///
/// ```
/// use glam::DVec3;
/// use nendo_geom::mesh::{Tessellation, estimate, tessellate};
/// let square: [DVec3; 16] =
///     std::array::from_fn(|k| DVec3::new((k / 4) as f64 / 3.0, (k % 4) as f64 / 3.0, 0.0));
/// let size = estimate(&[square], &Tessellation::with_tolerance(1e-3));
/// assert_eq!(size.triangles, 2);
/// assert_eq!(size.vertices, 4);
/// ```
#[must_use]
pub fn estimate(patches: &[PatchPoints], settings: &Tessellation) -> MeshSize {
    Plan::new(patches, settings).size()
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

/// What it takes to keep a tessellation up to date patch by patch while a few patches change
/// (a live stroke): only the changed patches are evaluated again, in place in the mesh, as
/// long as the segment counts stay what they were. The mesh itself stays the caller's (it is
/// what the display draws); it must be the one [`LiveTessellation::new`] returned, as the
/// updates since left it.
///
/// The counts of a patch come from the largest own count of its tied class (a row or column
/// of the grid, see the module docs). After an update the own counts of the changed patches
/// are measured again and the maxima of their classes recomputed; if any class's count
/// changes, the block layout changes with it: the whole mesh is rebuilt
/// ([`MeshUpdate::Rebuilt`]) — or, when the caller asks to keep the counts (a live stroke,
/// where a dent deepening frame by frame would otherwise rebuild at every step), the changed
/// patches are evaluated again with the counts they had and the mesh is marked
/// [`LiveTessellation::counts_stale`]: its vertices lie on the exact surface but the
/// tolerance may be exceeded there ([`TriMesh::error_bound`] says by how much) until the
/// next update that does not keep counts rebuilds it. No capacity is reserved per patch:
/// a changed count changes every patch of the row or column anyway. The classes themselves
/// are those of the last full build: they follow from which edges the patches share, which
/// sculpting does not change (a rebuild re-derives them).
///
/// An update in place that did not keep stale counts gives the mesh [`tessellate`] would
/// give for the same patches, bit for bit: the same per-patch evaluation writes the same
/// vertices.
#[derive(Debug, Clone)]
pub struct LiveTessellation {
    settings: Tessellation,
    plan: Plan,
    /// Members of each class, by class representative (CSR: `members[starts[r]..starts[r+1]]`
    /// for the representative's position `r` in `representatives`).
    class_index: HashMap<usize, (usize, usize)>,
    class_members: Vec<usize>,
    /// The error bound of every patch.
    bounds: Vec<f64>,
    /// Some counts are not those the patches need (kept during a live stroke).
    stale: bool,
}

/// What [`LiveTessellation::update`] did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MeshUpdate {
    /// The vertices of these blocks (patch indices, sorted) were written again in place;
    /// the indices and every other block are unchanged.
    InPlace(Vec<usize>),
    /// The segment counts changed: the whole mesh was rebuilt (new block layout).
    Rebuilt,
}

impl LiveTessellation {
    /// Tessellates `patches` (the mesh [`tessellate`] makes) and keeps what updating needs.
    #[must_use]
    pub fn new(patches: &[PatchPoints], settings: &Tessellation) -> (Self, TriMesh) {
        let plan = Plan::new(patches, settings);
        let (mesh, bounds) = build_with_bounds(patches, &plan);
        let mut live = Self {
            settings: *settings,
            plan,
            class_index: HashMap::new(),
            class_members: Vec::new(),
            bounds,
            stale: false,
        };
        live.index_classes();
        (live, mesh)
    }

    fn index_classes(&mut self) {
        let mut by_class: HashMap<usize, Vec<usize>> = HashMap::new();
        for (x, &c) in self.plan.classes.iter().enumerate() {
            by_class.entry(c).or_default().push(x);
        }
        self.class_index.clear();
        self.class_members.clear();
        for (c, members) in by_class {
            let start = self.class_members.len();
            self.class_members.extend(members);
            self.class_index
                .insert(c, (start, self.class_members.len()));
        }
    }

    /// Brings `mesh` up to `patches`, of which only those listed in `changed` differ from
    /// the patches last given (the same number of patches; otherwise, or when the segment
    /// counts change, everything is rebuilt). Afterwards `mesh` is what [`tessellate`] makes
    /// of `patches`. Costs what the changed patches and their rows and columns cost when the
    /// counts hold.
    ///
    /// With `keep_counts`, a change of segment counts does not rebuild: see the type's docs.
    pub fn update(
        &mut self,
        mesh: &mut TriMesh,
        patches: &[PatchPoints],
        changed: &[usize],
        keep_counts: bool,
    ) -> MeshUpdate {
        if self.stale && !keep_counts {
            return self.rebuild(mesh, patches);
        }
        if patches.len() != self.plan.own.len()
            || mesh.blocks.len() != patches.len()
            || changed.iter().any(|&p| p >= patches.len())
        {
            return self.rebuild(mesh, patches);
        }
        for &p in changed {
            self.plan.own[p] = self.settings.own_counts(&patches[p]);
        }
        // The classes of the changed patches' directions, each once.
        let mut classes: Vec<usize> = changed
            .iter()
            .flat_map(|&p| [self.plan.classes[2 * p], self.plan.classes[2 * p + 1]])
            .collect();
        classes.sort_unstable();
        classes.dedup();
        for c in classes {
            let Some(&(a, b)) = self.class_index.get(&c) else {
                return self.rebuild(mesh, patches);
            };
            let members = &self.class_members[a..b];
            let max = members
                .iter()
                .map(|&x| self.plan.own[x / 2].0[x % 2])
                .max()
                .unwrap_or(0);
            if members
                .iter()
                .any(|&x| self.plan.counts[x / 2][x % 2] != max)
            {
                if keep_counts {
                    self.stale = true;
                } else {
                    return self.rebuild(mesh, patches);
                }
            }
        }
        let mut blocks: Vec<usize> = changed.to_vec();
        blocks.sort_unstable();
        blocks.dedup();
        for &p in &blocks {
            let block = mesh.blocks[p];
            let [a, b] = self.plan.own[p].1;
            let (m_u, m_v) = (f64::from(block.m_u), f64::from(block.m_v));
            self.bounds[p] = (a / (m_u * m_u) + b / (m_v * m_v)) / 8.0;
            let range =
                block.first_vertex as usize..(block.first_vertex + block.vertex_count()) as usize;
            write_patch_vertices(
                &patches[p],
                &block,
                &mut mesh.positions[range.clone()],
                &mut mesh.normals[range],
            );
        }
        mesh.error_bound = self.bounds.iter().fold(0.0, |m: f64, b| m.max(*b));
        MeshUpdate::InPlace(blocks)
    }

    /// True when some segment counts were kept that the patches no longer need (see the
    /// type's docs): the mesh is on the surface but may miss the tolerance.
    #[must_use]
    pub fn counts_stale(&self) -> bool {
        self.stale
    }

    fn rebuild(&mut self, mesh: &mut TriMesh, patches: &[PatchPoints]) -> MeshUpdate {
        (*self, *mesh) = Self::new(patches, &self.settings);
        MeshUpdate::Rebuilt
    }
}

/// Builds the mesh a plan describes.
fn build(patches: &[PatchPoints], plan: &Plan) -> TriMesh {
    build_with_bounds(patches, plan).0
}

/// Builds the mesh a plan describes, with each patch's error bound.
fn build_with_bounds(patches: &[PatchPoints], plan: &Plan) -> (TriMesh, Vec<f64>) {
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

/// The four boundary edges of a patch as cubics, with the direction whose count they use:
/// `(v = 0, along u)`, `(v = 1, along u)`, `(u = 0, along v)`, `(u = 1, along v)`.
fn edges(p: &PatchPoints) -> [([DVec3; 4], usize); 4] {
    [
        ([p[0], p[4], p[8], p[12]], 0),
        ([p[3], p[7], p[11], p[15]], 0),
        ([p[0], p[1], p[2], p[3]], 1),
        ([p[12], p[13], p[14], p[15]], 1),
    ]
}

/// The edge in canonical orientation (the lexicographically smaller of the two orders of its
/// control points' bits) and whether that is the reverse of the given order.
fn canonical(edge: &[DVec3; 4]) -> ([DVec3; 4], bool) {
    let key = |e: &[DVec3; 4]| e.map(|p| [p.x, p.y, p.z].map(f64::to_bits));
    let rev = [edge[3], edge[2], edge[1], edge[0]];
    if key(&rev) < key(edge) {
        (rev, true)
    } else {
        (*edge, false)
    }
}

/// Segment counts per patch after tying shared edges together (union–find over the `2 n`
/// patch directions; collapsed edges tie nothing, a point has no vertices to disagree on).
fn tie_shared_edges(
    patches: &[PatchPoints],
    own: &[([u32; 2], [f64; 2])],
) -> (Vec<[u32; 2]>, Vec<usize>) {
    let mut parent: Vec<usize> = (0..2 * patches.len()).collect();
    fn find(parent: &mut [usize], mut x: usize) -> usize {
        while parent[x] != x {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        x
    }
    let mut owner: HashMap<[[u64; 3]; 4], usize> = HashMap::with_capacity(2 * patches.len());
    for (index, p) in patches.iter().enumerate() {
        for (edge, dir) in edges(p) {
            if edge.iter().all(|q| *q == edge[0]) {
                continue;
            }
            let (c, _) = canonical(&edge);
            let key = c.map(|p| [p.x, p.y, p.z].map(f64::to_bits));
            let node = 2 * index + dir;
            match owner.get(&key) {
                Some(&other) => {
                    let (ra, rb) = (find(&mut parent, node), find(&mut parent, other));
                    parent[ra] = rb;
                }
                None => {
                    owner.insert(key, node);
                }
            }
        }
    }
    let mut class_max = vec![0u32; parent.len()];
    for node in 0..parent.len() {
        let root = find(&mut parent, node);
        class_max[root] = class_max[root].max(own[node / 2].0[node % 2]);
    }
    let classes: Vec<usize> = (0..parent.len()).map(|x| find(&mut parent, x)).collect();
    let counts = (0..patches.len())
        .map(|i| [class_max[classes[2 * i]], class_max[classes[2 * i + 1]]])
        .collect();
    (counts, classes)
}

/// Cubic Bernstein basis values and derivatives at `t`.
#[inline]
fn cubic_basis(t: f64) -> ([f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    let b = [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t];
    let d = [
        -3.0 * s * s,
        3.0 * s * s - 6.0 * t * s,
        6.0 * t * s - 3.0 * t * t,
        3.0 * t * t,
    ];
    (b, d)
}

/// Point and partial derivatives `(S, S_u, S_v)` of a patch at `(u, v)`.
#[must_use]
pub fn eval_patch(p: &PatchPoints, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
    let (bu, du) = cubic_basis(u);
    let (bv, dv) = cubic_basis(v);
    let mut s = DVec3::ZERO;
    let mut su = DVec3::ZERO;
    let mut sv = DVec3::ZERO;
    for i in 0..4 {
        for j in 0..4 {
            let q = p[4 * i + j];
            s += q * (bu[i] * bv[j]);
            su += q * (du[i] * bv[j]);
            sv += q * (bu[i] * dv[j]);
        }
    }
    (s, su, sv)
}

/// The mixed derivative `S_uv` of a patch at `(u, v)`.
fn eval_twist(p: &PatchPoints, u: f64, v: f64) -> DVec3 {
    let (_, du) = cubic_basis(u);
    let (_, dv) = cubic_basis(v);
    let mut suv = DVec3::ZERO;
    for i in 0..4 {
        for j in 0..4 {
            suv += p[4 * i + j] * (du[i] * dv[j]);
        }
    }
    suv
}

/// Unit normal of a patch at `(u, v)`. On a collapsed boundary (a pole, where `S_u` or `S_v`
/// vanishes) it is the exact limit from inside the patch: there `S_u ≈ (v − v₀) S_uv`, so the
/// normal is along `±S_uv × S_v` (and likewise for a collapsed column). At any other singular
/// point, the normal of a point nudged towards the patch centre.
#[must_use]
pub fn patch_normal(p: &PatchPoints, u: f64, v: f64) -> DVec3 {
    let (_, su, sv) = eval_patch(p, u, v);
    let n = su.cross(sv);
    let scale = su.length_squared().max(sv.length_squared());
    if n.length_squared() > 1e-20 * scale * scale && scale > 0.0 {
        return n.normalize();
    }
    let size = p
        .iter()
        .fold(0.0f64, |m, q| m.max((*q - p[0]).length_squared()));
    let tiny = 1e-18 * size;
    let limit = if su.length_squared() <= tiny && sv.length_squared() > tiny {
        let sign = if v < 0.5 { 1.0 } else { -1.0 };
        eval_twist(p, u, v).cross(sv) * sign
    } else if sv.length_squared() <= tiny && su.length_squared() > tiny {
        let sign = if u < 0.5 { 1.0 } else { -1.0 };
        su.cross(eval_twist(p, u, v)) * sign
    } else {
        DVec3::ZERO
    };
    if let Some(n) = limit.try_normalize() {
        return n;
    }
    for nudge in [1e-6, 1e-4, 1e-2] {
        let (_, su, sv) = eval_patch(p, u + nudge * (0.5 - u), v + nudge * (0.5 - v));
        if let Some(n) = su.cross(sv).try_normalize() {
            return n;
        }
    }
    DVec3::Z
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
fn write_patch_vertices(
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
    let bv: Vec<([f64; 4], [f64; 4])> = (0..=m_v)
        .map(|l| cubic_basis(f64::from(l) / f64::from(m_v)))
        .collect();
    for k in 0..=m_u {
        let u = f64::from(k) / f64::from(m_u);
        let (bu, du) = cubic_basis(u);
        // Rows of the patch restricted to this u: C_j(u) and their u-derivatives.
        let mut c = [DVec3::ZERO; 4];
        let mut d = [DVec3::ZERO; 4];
        for j in 0..4 {
            for i in 0..4 {
                c[j] += p[4 * i + j] * bu[i];
                d[j] += p[4 * i + j] * du[i];
            }
        }
        for (l, (bvl, dvl)) in bv.iter().enumerate() {
            let l = l as u32;
            let position = if l == 0 {
                on_edge(&e_v0, k, m_u)
            } else if l == m_v {
                on_edge(&e_v1, k, m_u)
            } else if k == 0 {
                on_edge(&e_u0, l, m_v)
            } else if k == m_u {
                on_edge(&e_u1, l, m_v)
            } else {
                c[0] * bvl[0] + c[1] * bvl[1] + c[2] * bvl[2] + c[3] * bvl[3]
            };
            let su = d[0] * bvl[0] + d[1] * bvl[1] + d[2] * bvl[2] + d[3] * bvl[3];
            let sv = c[0] * dvl[0] + c[1] * dvl[1] + c[2] * dvl[2] + c[3] * dvl[3];
            let n = su.cross(sv);
            let scale = su.length_squared().max(sv.length_squared());
            let normal = if scale > 0.0 && n.length_squared() > 1e-20 * scale * scale {
                n.normalize()
            } else {
                patch_normal(p, u, f64::from(l) / f64::from(m_v))
            };
            positions[slot] = position.as_vec3();
            normals[slot] = normal.as_vec3();
            slot += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

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
    fn a_live_update_gives_the_full_tessellation_bit_for_bit() {
        use crate::mesh::{seam_angles_deg, update_seam_angles_deg};
        use crate::surface::{Op, Primitive, PrimitiveParams, Regulation, Sculptor};
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        let (mut in_place, mut rebuilt) = (0, 0);
        for primitive in [Primitive::Plane, Primitive::Sphere, Primitive::Torus] {
            let mut grid = primitive.build(&PrimitiveParams::default()).unwrap();
            let (mut live, mut mesh) =
                LiveTessellation::new(&grid.patches(), &Tessellation::DISPLAY);
            let mut sculptor = Sculptor::new();
            let nodes = grid.nodes().to_vec();
            for _ in 0..25 {
                let at = nodes[rng.gen_range(0..nodes.len())];
                let op = Op::Push {
                    at,
                    dir: DVec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), 1.0),
                    depth: rng.gen_range(-0.3..0.3),
                    radius: rng.gen_range(0.4..1.5),
                };
                let Ok(touched) = sculptor.apply(&mut grid, &op, Regulation::Exact) else {
                    continue;
                };
                let patches = grid.patches();
                match live.update(&mut mesh, &patches, &touched.patches, false) {
                    MeshUpdate::InPlace(blocks) => {
                        in_place += 1;
                        assert_eq!(blocks, touched.patches);
                    }
                    MeshUpdate::Rebuilt => rebuilt += 1,
                }
                let full = tessellate(&patches, &Tessellation::DISPLAY);
                assert_eq!(mesh, full, "{primitive:?}");
                // Seam angles recomputed on a few blocks, in the context of all of them.
                let want = seam_angles_deg(&patches, &full);
                let mut got = want.clone();
                let targets: Vec<usize> = touched.patches.clone();
                for &t in &targets {
                    let b = full.blocks[t];
                    got[b.first_vertex as usize..(b.first_vertex + b.vertex_count()) as usize]
                        .fill(-1.0);
                }
                let all: Vec<usize> = (0..full.blocks.len()).collect();
                update_seam_angles_deg(&patches, &full, &all, &targets, &mut got);
                assert_eq!(got, want);
            }
        }
        assert!(
            in_place > 10 && rebuilt > 0,
            "{in_place} in place, {rebuilt} rebuilt"
        );
    }

    #[test]
    fn kept_counts_stay_on_the_surface_until_the_next_full_update() {
        use crate::surface::{Op, Primitive, PrimitiveParams, Regulation, Sculptor};
        let mut grid = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
        let (mut live, mut mesh) = LiveTessellation::new(&grid.patches(), &Tessellation::DISPLAY);
        let blocks = mesh.blocks.clone();
        let mut sculptor = Sculptor::new();
        for k in 1..=4 {
            let op = Op::Push {
                at: DVec3::new(0.2, 0.1, 0.0),
                dir: -DVec3::Z,
                depth: 0.3 * f64::from(k),
                radius: 1.25,
            };
            let touched = sculptor.apply(&mut grid, &op, Regulation::Exact).unwrap();
            let patches = grid.patches();
            let update = live.update(&mut mesh, &patches, &touched.patches, true);
            assert!(matches!(update, MeshUpdate::InPlace(_)));
            assert_eq!(mesh.blocks, blocks, "the layout is kept");
            for b in &mesh.blocks {
                for v in b.first_vertex..b.first_vertex + b.vertex_count() {
                    let (u, w) = b.uv_of(v);
                    let exact = eval_patch(&patches[b.patch as usize], u, w).0;
                    assert!((mesh.positions[v as usize].as_dvec3() - exact).length() < 1e-5);
                }
            }
        }
        assert!(live.counts_stale(), "a deepening dent needs more segments");
        let patches = grid.patches();
        assert_eq!(
            live.update(&mut mesh, &patches, &[], false),
            MeshUpdate::Rebuilt
        );
        assert!(!live.counts_stale());
        assert_eq!(mesh, tessellate(&patches, &Tessellation::DISPLAY));
    }
}
