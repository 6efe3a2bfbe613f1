//! What an operation asks of the surface: shape functions and their fingers, the nearest surface
//! point, the exact landing of a move, the smoothing dab (implicit fairing) and the thin-plate
//! energy that accepts it, the Bernstein inverse,
//! refinement, and the deviation from an operation's ideal shape. Uses the layers below; the
//! engine ([`super::engine`]) runs them.

pub mod brush;
pub mod deviation;
pub mod fairing;
pub(crate) mod grab;
pub mod inverse;
pub(crate) mod nearest;
pub mod refine;
pub mod sculpt_brush;
pub(crate) mod shape_fn;
pub(crate) mod smooth;
