//! The tessellation plan: how many segments each patch gets so that its triangles stay within
//! the tolerance, and the size of the mesh that follows, known before any vertex is made.
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
//! Each patch's own counts are then raised to those of the neighbours it shares edges with
//! ([`super::edges`]), so that the mesh has no cracks.

use super::edges::tie_shared_edges;
use super::tessellate::PatchPoints;
#[cfg(doc)]
use super::tessellate::tessellate;
#[cfg(doc)]
use super::trimesh::TriMesh;

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

    /// The default export tolerance as a fraction of the model's size:
    /// [`Tessellation::export_tolerance_for`].
    pub const RELATIVE_EXPORT_TOLERANCE: f64 = 1e-3;

    /// The default export tolerance for `patches`: a thousandth of the diagonal `D` of their
    /// control points' box, `ε = 10⁻³·D` ([`Tessellation::RELATIVE_EXPORT_TOLERANCE`]) —
    /// 0.014 side for the 10 × 10 plane, a tenth of what the display draws per pixel on a
    /// 1280-pixel view (a side is ~13 pixels there, and the display's own tolerance is
    /// 0.01 side). An absolute tolerance is wrong for every model but one size: 10⁻³ side wrote
    /// 2.5 million triangles for a face mask on the plane. Without finite points (no patch,
    /// or a NaN), the absolute [`Tessellation::EXPORT`] tolerance.
    #[must_use]
    pub fn export_tolerance_for(patches: &[PatchPoints]) -> f64 {
        let mut points = patches.iter().flatten().filter(|p| p.is_finite());
        let Some(first) = points.next() else {
            return Self::EXPORT.tolerance;
        };
        let (lo, hi) = points.fold((*first, *first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        let tolerance = Self::RELATIVE_EXPORT_TOLERANCE * (hi - lo).length();
        if tolerance.is_finite() && tolerance > 0.0 {
            tolerance
        } else {
            Self::EXPORT.tolerance
        }
    }

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
    pub(super) fn own_counts(&self, p: &PatchPoints) -> ([u32; 2], [f64; 2]) {
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

/// Segment counts of every patch for some settings: the plan [`tessellate`] follows.
#[derive(Debug, Clone)]
pub(super) struct Plan {
    /// Each patch's own counts and second-derivative bounds.
    pub(super) own: Vec<([u32; 2], [f64; 2])>,
    /// The counts after tying shared edges.
    pub(super) counts: Vec<[u32; 2]>,
    /// The tied class of each patch direction `2 · patch + direction` (a representative).
    pub(super) classes: Vec<usize>,
}

impl Plan {
    pub(super) fn new(patches: &[PatchPoints], settings: &Tessellation) -> Self {
        let own: Vec<([u32; 2], [f64; 2])> =
            patches.iter().map(|p| settings.own_counts(p)).collect();
        let (counts, classes) = tie_shared_edges(patches, &own);
        Self {
            own,
            counts,
            classes,
        }
    }

    pub(super) fn size(&self) -> MeshSize {
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
