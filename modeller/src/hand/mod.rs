//! The hand: device frames → a kinematic hand → contact of the virtual finger with the surface
//! → push, pull and draw-a-line operations on the patch grid (P2 §2.1, Fig. 1; the
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
//! | [`kinematics`] | [`Hand`]: bend angles → joint positions of each [`Digit`], lengths from the profile, placed in the world by the tracker pose; the [`Palm`] |
//! | [`contact`] | [`Probe`]: where a line along the finger meets the surface (patch boxes, then exact ray picking of [`crate::mesh`]); [`Fingertip`], the capsule of radius `r_f` around the finger's axis |
//! | [`parts`] | [`Part`]: a finger or the palm; [`Fingers`], the set that presses; [`FingerModel`], the parts a device presses with, and its [`Activation`] |
//! | [`options`] | [`HandOptions`]: finger radius, parts, thresholds of contact, stroke, grip and pinch |
//! | [`filter`] | the plausibility gate and One-Euro filter every frame goes through first ([`nendo_devices::filter`]), and which settings a loop uses |
//! | [`hand_loop`] | [`HandLoop`]: frames → contact of every pressing [`Part`] → the surface deformed, pinches held (the contact rules) |
//! | [`outcome`] | what the loop reports: [`Touch`], [`FrameOutcome`], [`LoopStats`] |
//! | [`session`] | [`HandSession`]: the loop with its own grid, for replay, tests and benches |
//! | [`press`] | the operation of one contact: every part's finger [`Placement`]s applied together, as an envelope, to the surface before the contact — re-exported from the geometry crate's engine, [`crate::surface::engine`] (the hand only builds placements) |
//! | [`mouse`] | [`MouseFinger`]: the mouse as a hand — the view ray is the finger; click depth and drag give push, pull and draw-a-line |
//! | [`scene`] | [`Scene`](scene::Scene): the surface a recorded session started from and its settings, the `scene` line of a trace header (`nendo replay TRACE` needs nothing else) |
//! | [`script`] | scripted hand motions written as real traces ([`Choreography`](script::Choreography): inverse kinematics for a wanted fingertip; gestures; pinch poses) |
//! | [`shipped`] | the generators of the traces shipped in `devices/traces/`, and their scenes |
//!
//! ## Contact, in short (the rules are in [`hand_loop`])
//!
//! - **The clay never moves farther than the finger penetrated it, whatever the finger's
//!   angle: a finger lying on the clay presses with its side, a tip pokes with its tip.**
//!   The surface is searched along the finger's axis; when the axis crosses the surface at
//!   `S` before the fingertip `E`, the clay is pressed along `m̂`, the surface normal at `S`
//!   turned to the finger's side, by `h`, the depth of `E` past the surface along `m̂`: a push
//!   ending at the fingertip with `M = h·m̂` (P2 §5.1). A tip poking straight in presses
//!   along the finger; a finger lying on the clay presses into the surface by how deep its
//!   tip is — not along the finger, which at a shallow angle `θ` would shove the clay
//!   sideways by `h / sin θ`. A flat hand 0.05 side into the plane moves no control point
//!   more than 1.5 × 0.05 at any angle from 3° to 90° (tests/it/hand_contact.rs). The mouse's
//!   ray is the exception: its depth is chosen along the ray, and it presses along it.
//! - **Only where the finger is.** A crossing counts only if the finger's own joints reach
//!   back along its axis that far: a fingertip curled back out of a fist, whose straight
//!   capsule runs on through the clay below, points out of the clay and does not press it.
//! - **Every finger presses, and the palm.** Each part of the hand in the set
//!   ([`Fingers`]; `--finger all`, the default for gloves, is the five fingers; `palm` adds
//!   the palm as a wide capsule under the palm's centre) ends in a capsule — radius `r_f`
//!   for a fingertip (also the shape function's finger radius, so the capsule is exactly the
//!   reach of the operation), half the palm's width for the palm. Every part that reaches
//!   the surface in a frame contributes, by the rule above; all of one frame are one
//!   operation (their displacement fields combined as an envelope), regulated once.
//! - While a part stays in the clay and moves across, its contact grows into a draw-a-line
//!   stroke through its path (§5.2), each segment with its own depth.
//! - Every frame the contact is recomputed from the surface as it was before it, each sample
//!   moving by the strongest of the contact's placements: only what the hand adds is
//!   applied, and clay already pressed is not pressed again.
//! - While the grip is held (the glove's switch; the right mouse button) the clay sticks to
//!   the fingertips: withdrawing pulls, moving draws a ridge.
//! - **Pinch to grab.** Thumb and index tips meeting (closer than 0.4 side) on the clay from
//!   the same side take hold of the clay nearest the pinch point and, while they stay
//!   together, move it with the pinch point (the surface's exact `move`, live from the surface
//!   before the pinch, one undo step: after letting go the surface passes through the last
//!   target to rounding); a wall pinched from both sides is pressed on both sides instead.
//!
//! - **Filtered first.** Every frame goes through a plausibility gate (a tracker sample
//!   faster or more sudden than a hand, a joint past its range, NaN: the last good value
//!   held, and counted) and a One-Euro filter on position, orientation and joints, on the
//!   frames' own timestamps ([`filter`]), before anything above reads it.
//!
//! The whole loop is a pure function of the frames, the starting surface, the options and
//! the filter's settings: replaying a trace twice gives bit-identical surfaces.

pub mod contact;
pub mod filter;
pub mod hand_loop;
pub mod kinematics;
pub mod mouse;
pub mod options;
pub mod outcome;
pub mod parts;
pub mod press;
pub mod scene;
pub mod script;
pub mod session;
pub mod shipped;

pub use contact::{AxisHit, Fingertip, Probe};
pub use hand_loop::HandLoop;
pub use kinematics::{Digit, FingerChain, Hand, HandPose, Palm};
pub use mouse::MouseFinger;
pub use options::{DEFAULT_FINGER_RADIUS, DEFAULT_PINCH_DISTANCE, HandOptions};
pub use outcome::{FrameOutcome, LoopStats, Touch};
pub use parts::{Activation, FingerModel, Fingers, Part};
pub use press::Placement;
pub use session::HandSession;

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
