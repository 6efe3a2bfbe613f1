//! The errors of the surface part.

use crate::surface::topology::Topology;

/// What can go wrong when building, reading or deforming a patch grid.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SurfaceError {
    /// A patch count is zero, or too small for the topology (a closed direction needs at least
    /// 2 patches, 6 around a pole; a sphere needs 2 patches from pole to pole).
    #[error("{topology} topology needs at least {min} patches along {direction}, got {got}")]
    TooFewPatches {
        /// The topology being built.
        topology: Topology,
        /// `"u"` or `"v"`.
        direction: &'static str,
        /// The smallest count allowed.
        min: usize,
        /// The count asked for.
        got: usize,
    },
    /// A patch count around a closed direction is odd; every meridian at a pole needs an
    /// opposite one, so closed directions always have an even count.
    #[error(
        "{topology} needs an even number of patches around its closed {direction} direction, got {got}"
    )]
    OddClosedCount {
        /// The topology being built.
        topology: Topology,
        /// `"u"` or `"v"`.
        direction: &'static str,
        /// The count asked for.
        got: usize,
    },
    /// The grid would hold more control points than this build can index.
    #[error(
        "a {patches_u} x {patches_v} grid is too large (at most {} patches)",
        crate::surface::limits::MAX_PATCHES
    )]
    TooLarge {
        /// Patches along u.
        patches_u: usize,
        /// Patches along v.
        patches_v: usize,
    },
    /// A shape parameter (radius, height, …) is not a positive finite number.
    #[error("{name} must be a positive finite number, got {}", crate::num::Compact(*.value))]
    BadParameter {
        /// Which parameter.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// The number of control points or patches given does not match the grid's counts.
    #[error("expected {expected} {what}, got {got}")]
    WrongCount {
        /// What was counted (`"control points"`, `"patches"`).
        what: &'static str,
        /// The count the topology and patch counts require.
        expected: usize,
        /// The count given.
        got: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("patch {patch}, control point {point}: coordinate is not finite")]
    NotFinite {
        /// Patch index `iv * patches_u + iu` (or the node index for a raw net).
        patch: usize,
        /// Control point index `4 * i + j` in the patch.
        point: usize,
    },
    /// Two patches disagree about a control point they must share (a common edge, a closed
    /// seam, a pole).
    #[error(
        "patch {patch}, control point {point} should coincide with patch {other}, control point \
         {other_point} ({what}), but they are {distance:e} apart"
    )]
    NotCoincident {
        /// The patch whose point disagrees.
        patch: usize,
        /// Its control point index.
        point: usize,
        /// The patch holding the first copy of the shared point.
        other: usize,
        /// That copy's control point index.
        other_point: usize,
        /// Which kind of sharing (`"shared edge"`, `"closed seam"`, `"pole"`).
        what: &'static str,
        /// How far apart they are.
        distance: f64,
    },
    /// An operation's parameter is invalid (not finite, zero direction, radius not positive,
    /// a path too short).
    #[error("invalid operation: {0}")]
    BadOp(String),
    /// An operation would move a control point to a coordinate that is not finite or beyond
    /// [`crate::surface::COORDINATE_LIMIT`] (the grid is then left as it was), or a
    /// net read has one beyond it.
    #[error(
        "patch {patch}, control point {point}: coordinate not finite or beyond the coordinate limit {limit:e}; refused"
    )]
    OutOfRange {
        /// The first patch (in increasing index) holding such a point.
        patch: usize,
        /// Its control point index `4 * i + j`.
        point: usize,
        /// The limit, [`crate::surface::COORDINATE_LIMIT`].
        limit: f64,
    },
    /// The regulation could not bring the touched edges to G1 within
    /// [`crate::surface::G1_TOLERANCE_DEG`]; the grid is left as it was.
    #[error(
        "regulation {regulation} could not keep the surface G1: the edge between patches {patch} and {other} creases by {angle_deg:.3e} degrees (tolerance {tolerance_deg:e}); refused"
    )]
    NotG1 {
        /// The regulation method that promised G1.
        regulation: crate::surface::Regulation,
        /// One patch of the worst edge.
        patch: usize,
        /// The patch on the other side.
        other: usize,
        /// The largest angle between the normals of the two sides found along it (degrees).
        angle_deg: f64,
        /// The tolerance, [`crate::surface::G1_TOLERANCE_DEG`].
        tolerance_deg: f64,
    },
    /// The `g2` regulation left a seam of a touched patch with a curvature mismatch above
    /// [`crate::surface::G2_TOLERANCE`]; the grid is left as it was.
    #[error(
        "regulation g2 could not keep the surface curvature-continuous: across the edge between patches {patch} and {other} the normal curvatures differ by {relative:.3e} relative ({absolute:.3e} absolute; tolerance {tolerance:e} relative); refused"
    )]
    NotG2 {
        /// One patch of the worst edge.
        patch: usize,
        /// The patch on the other side.
        other: usize,
        /// The largest relative mismatch `|κ₁ − κ₂| / (|κ₁| + |κ₂|)` found along it.
        relative: f64,
        /// The largest absolute mismatch `|κ₁ − κ₂|` found along it.
        absolute: f64,
        /// The tolerance, [`crate::surface::G2_TOLERANCE`].
        tolerance: f64,
    },
    /// The `g2` regulation found no curvature-continuous net in its window (not expected:
    /// the window always admits the net before the operation); the grid is left as it was.
    #[error(
        "regulation g2 found no curvature-continuous net in its window of {patches} patches; refused"
    )]
    G2Singular {
        /// Patches in the window.
        patches: usize,
    },
    /// The grids compared by a measure do not have the same topology and patch counts.
    #[error("the grids differ in topology or patch counts")]
    Mismatch,
}

/// A name that is not one of a fixed set (a primitive, a regulation method, …), as read from
/// a command line or a panel.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown {kind} {given:?}: expected {expected}")]
pub struct UnknownName {
    /// What was named ("primitive", "regulation", …).
    pub kind: &'static str,
    /// The name as given.
    pub given: String,
    /// The names accepted, in words.
    pub expected: &'static str,
}
