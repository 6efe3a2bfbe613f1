//! What the hand loop reports: the hand's relation to the clay ([`Touch`]), what one frame
//! did ([`FrameOutcome`]) and the loop's counters ([`LoopStats`]).

use crate::surface::{Op, SurfaceError};

/// The finger's relation to the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Touch {
    /// No contact (or no finger).
    #[default]
    Free,
    /// In contact, pressing.
    Pressing,
    /// In contact with the grip held: the clay sticks to the fingertip.
    Gripping,
    /// Thumb and index pinched together on the clay hold it and move it with the hand.
    Holding,
}

/// What one frame did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameOutcome {
    /// The finger's state after the frame.
    pub touch: Touch,
    /// The signed penetration `h` of the fingertip along the pressing direction (rule 3), when
    /// a surface was found.
    pub penetration: Option<f64>,
    /// Patches whose control points changed this frame (sorted): what to redraw.
    pub changed: Vec<usize>,
    /// A contact that ended this frame, as the operations it stands for (a push, then one
    /// draw-a-line segment per further placement; see [`super::press::describe`]).
    pub committed: Option<Vec<Op>>,
    /// Why the surface refused this frame's application of the contact (a result not finite
    /// or beyond [`crate::surface::COORDINATE_LIMIT`], or a seam the regulation could not
    /// keep G1; see [`crate::surface::verify`]). The surface then stays as the contact's last
    /// accepted application; the contact goes on, and a later frame whose placements the
    /// surface accepts shows them.
    pub refused: Option<SurfaceError>,
}

/// Counters of a loop.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LoopStats {
    /// Frames fed.
    pub frames: u64,
    /// Frames that had a finger (pose, and glove data when the profile has a glove).
    pub frames_with_finger: u64,
    /// Contacts begun.
    pub contacts: u64,
    /// Contacts ended as a push (one placement, pressed in).
    pub pushes: u64,
    /// Contacts ended as a pull (one placement, the clay drawn out with the grip).
    pub pulls: u64,
    /// Contacts ended as a draw-a-line stroke (several placements).
    pub strokes: u64,
    /// Placements over all contacts (after merging straight runs).
    pub placements: u64,
    /// Frames on which the surface was recomputed.
    pub applications: u64,
    /// Applications the surface refused (a result not finite or beyond the coordinate limit,
    /// or a seam the regulation could not keep G1; see [`FrameOutcome::refused`]).
    pub rejected: u64,
    /// Sum over frames of the patches whose control points changed.
    pub patch_updates: u64,
    /// Pinches ended: the clay held between thumb and index and moved (one `move` each).
    pub holds: u64,
}

impl LoopStats {
    /// Contacts ended (pushes, pulls and strokes): operations in the paper's sense.
    #[must_use]
    pub fn operations(&self) -> u64 {
        self.pushes + self.pulls + self.strokes + self.holds
    }
}
