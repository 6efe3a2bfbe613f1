//! The limits every surface result is held to: how large a coordinate may grow, how much
//! crease the exact regulation may leave, how many patches a grid may have. The bottom of the surface module: the grid refuses
//! nets beyond the first and grids of more patches than the last, the verification refuses
//! operations beyond either.

/// The largest absolute value a control-point coordinate may take (10³⁰).
///
/// Every surface point is a convex combination of control points, so the whole surface lies
/// within it, and every mesh a surface is written as (OBJ, STL and GLB are made from the
/// tessellation's `f32` vertices, whose largest value is ≈ 3.4 · 10³⁸) stays finite, with eight
/// orders of magnitude to spare for scaling on export. Every product the geometry forms in
/// `f64` stays finite far below `f64::MAX` ≈ 1.8 · 10³⁰⁸: the mesher's and the measures'
/// normals are cross products of derivative differences (≈ 10⁶² · small constants) whose
/// squared lengths reach ≈ 10¹²⁵; the pole regulation's plane fit and its eigen solve square
/// ring offsets' outer products (≈ 10¹²³). Operations whose result would exceed it are refused
/// ([`SurfaceError::OutOfRange`](crate::surface::SurfaceError::OutOfRange)); grids read from files beyond it are refused by
/// [`Grid::from_net`](crate::surface::Grid::from_net) / [`Grid::from_patches`](crate::surface::Grid::from_patches).
pub const COORDINATE_LIMIT: f64 = 1e30;

/// The largest crease (degrees) [`Regulation::Exact`](crate::surface::Regulation::Exact) may leave along an edge of a touched
/// patch: exact regulation holds G1 to rounding (≈ 10⁻¹²°), so anything above 10⁻⁶° means the
/// construction failed (e.g. a pole's tangent plane folded the first ring) and the operation
/// is refused ([`SurfaceError::NotG1`](crate::surface::SurfaceError::NotG1)).
pub const G1_TOLERANCE_DEG: f64 = 1e-6;

/// The largest relative curvature mismatch `|κ₁ − κ₂| / (|κ₁| + |κ₂|)` (Rhino's
/// `(R₁ − R₂) / (R₁ + R₂)`) [`Regulation::G2`](crate::surface::Regulation::G2) may leave across a
/// seam of a touched patch: 1 %. Counted only where the absolute mismatch is above
/// [`G2_FLAT`] / the model's size (two nearly flat sides whose tiny curvatures differ in sign
/// are not a curvature jump). The construction holds G2 to rounding; above this the
/// operation is refused ([`SurfaceError::NotG2`](crate::surface::SurfaceError::NotG2)).
pub const G2_TOLERANCE: f64 = 0.01;

/// The absolute curvature mismatch, times the model's size, below which a seam counts as
/// G2 whatever its relative mismatch (see [`G2_TOLERANCE`]).
pub const G2_FLAT: f64 = 1e-7;

/// Largest number of patches a grid may have: 65 536 (256 × 256), about 0.5 GB with its
/// samples and groups — far past any interactive model (the paper's largest is 128), and a
/// clear error rather than an allocation failure for a mistyped count.
pub const MAX_PATCHES: usize = 1 << 16;
