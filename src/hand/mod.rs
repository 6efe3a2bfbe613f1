//! The hand: device frames → a kinematic hand → contact of the virtual finger with the surface
//! → push, pull and draw-a-line operations on the patch grid (seed 002 §2.1, Fig. 1; the
//! interactive system of Fig. 12–13).
//!
//! At every device sample the paper's loop reads the hand's position and orientation from the
//! tracker and the finger bend angles from the glove, computes the joint positions of the
//! virtual hand, tests the virtual finger against the surface, and — when they collide —
//! derives the shape function's parameters from the finger and deforms the patches through
//! the Bernstein inverse and regulation. Here:
//!
//! | module | what it is |
//! |---|---|
//! | [`kinematics`] | [`Hand`]: bend angles → joint positions of each [`Digit`], lengths from the profile, placed in the world by the tracker pose |
//! | [`contact`] | [`Probe`]: where a line along the finger meets the surface (patch boxes, then exact ray picking of [`crate::mesh`]); [`Fingertip`], the capsule of radius `r_f` around the finger's axis |
//! | [`session`] | [`HandLoop`]: frames → contact → the surface deformed; [`Session`]: the loop with its own grid, for replay |
//! | [`press`] | the operation of one contact: its finger [`Placement`]s applied together, as an envelope, to the surface before the contact — re-exported from the geometry crate's engine, [`crate::surface::envelope`] (the hand only builds placements) |
//! | [`mouse`] | [`MouseFinger`]: the mouse as a hand — the view ray is the finger; click depth and drag give push, pull and draw-a-line |
//! //! | [`scene`] | [`Scene`](scene::Scene): the surface a recorded session started from and its settings, the `scene` line of a trace header (`nendo replay TRACE` needs nothing else) |
//! | [`script`] | scripted hand motions written as real traces (inverse kinematics for a wanted fingertip), and the generators of the traces shipped in `devices/traces/` |
//!
//! ## Contact, in short (the rules are in [`session`])
//!
//! - The active finger (the index by default) ends in a capsule of radius `r_f` around its
//!   axis; `r_f` is also the shape function's finger radius, so the capsule is exactly the
//!   reach of the operation.
//! - The surface is searched along the finger's axis. When the axis crosses the surface at
//!   `S` before the fingertip `E`, the penetration is `p = (E − S)·d̂`, `d̂` the finger's
//!   direction, and a contact starts: a push with `M = p·d̂` at `S` (seed 002 §5.1).
//! - While the finger stays in the clay and moves across its axis, the contact grows into a
//!   draw-a-line stroke through the fingertip's path (§5.2), each segment with its own depth.
//! - Every frame the contact is recomputed from the surface as it was before it, each sample
//!   moving by the strongest of the contact's placements: only what the finger adds is
//!   applied, and clay the finger already pressed is not pressed again.
//! - While the grip is held (the glove's switch; the right mouse button) the clay sticks to
//!   the fingertip: withdrawing pulls, moving draws a ridge.
//!
//! The whole loop is a pure function of the frames, the starting surface and the options:
//! replaying a trace twice gives bit-identical surfaces.

pub mod contact;
pub mod kinematics;
pub mod mouse;
pub mod press;
pub mod scene;
pub mod script;
pub mod session;

pub use contact::{AxisHit, Fingertip, Probe};
pub use kinematics::{Digit, FingerChain, Hand, HandPose};
pub use mouse::MouseFinger;
pub use press::Placement;
pub use session::{
    Activation, DEFAULT_FINGER_RADIUS, FingerModel, FrameOutcome, HandLoop, HandOptions, LoopStats,
    Session, Touch,
};

/// What can go wrong in the hand loop.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HandError {
    /// An option is out of range (a radius that is not a positive finite number, …).
    #[error("hand options: {0}")]
    Options(String),
    /// A hand size or tracker transform that cannot place a hand (non-finite, non-positive).
    #[error("hand model: {0}")]
    Model(String),
    /// A device value the mouse hand could not turn into a frame (a zero or non-finite ray).
    #[error("mouse: {0}")]
    Mouse(String),
}
