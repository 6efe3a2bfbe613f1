//! Pinch to grab (rule 9 of [`super`]): thumb and index meeting on the clay take hold of it
//! and, while they stay together, move it with the pinch point — one `move` of the surface
//! before the pinch, one undo step.

use glam::DVec3;

use super::HandLoop;
use crate::hand::contact::Fingertip;
use crate::hand::kinematics::Digit;
use crate::hand::outcome::FrameOutcome;
use crate::hand::parts::Part;
use crate::surface::{Grid, Op, Regulation};

/// A pinch in progress (rule 9): the clay held between thumb and index.
#[derive(Debug, Clone)]
pub(super) struct Hold {
    /// The point of the clay taken hold of.
    pub(super) at: DVec3,
    /// The pinch point (between the two tips) when it took hold.
    pub(super) start: DVec3,
    /// The target of the last accepted move.
    pub(super) to: DVec3,
}

/// A pinch lets go when the tips are this many times the pinch distance apart (so that a
/// pinch held at the threshold does not flicker).
const PINCH_RELEASE: f64 = 1.5;

impl HandLoop {
    /// Rule 9: where thumb and index, not holding yet, take hold of `grid` — the point of the
    /// clay held and the pinch point — or `None`: their tips closer than the pinch distance on
    /// the same side of the clay, the clay within `r_f` of the pinch point.
    pub(super) fn takes_hold(
        &mut self,
        thumb: &Fingertip,
        index: &Fingertip,
        grid: &Grid,
    ) -> Option<(DVec3, DVec3)> {
        let o = self.options;
        let gap = (thumb.tip - index.tip).length();
        let mid = 0.5 * (thumb.tip + index.tip);
        if gap >= o.pinch_distance {
            return None;
        }
        // Both tips on the same side of the clay (the segment between them does not cross it:
        // a wall pinched from both sides is pressed, not held), the pinch point within a
        // finger radius of the surface: the clay nearest it is taken hold of.
        if self
            .probe
            .first_crossing(grid, thumb.tip, index.tip - thumb.tip, gap)
            .is_some()
        {
            return None;
        }
        let hit = crate::surface::nearest(grid, mid)
            .filter(|s| (s.point - mid).length() <= o.finger_radius)?;
        Some((hit.point, mid))
    }

    /// Rule 9: starts, follows or ends a pinch; `true` when the frame was a pinch's (nothing
    /// pressed).
    pub(super) fn pinch(
        &mut self,
        tips: &[(Part, Fingertip)],
        grid: &mut Grid,
        regulation: Regulation,
        out: &mut FrameOutcome,
    ) -> bool {
        let o = self.options;
        let Some((thumb, index)) = pinch_pair(tips) else {
            if self.hold.is_some() {
                out.committed = self.end_contact();
            }
            return false;
        };
        let gap = (thumb.tip - index.tip).length();
        let mid = 0.5 * (thumb.tip + index.tip);
        if let Some(mut h) = self.hold.take() {
            if gap > PINCH_RELEASE * o.pinch_distance {
                self.hold = Some(h);
                out.committed = self.end_contact();
                return false;
            }
            let to = h.at + (mid - h.start);
            if (to - h.to).length() > o.min_depth {
                self.stats.applications += 1;
                let op = Op::Move {
                    at: h.at,
                    to,
                    radius: o.finger_radius,
                };
                // The move applied afresh to the surface before the pinch (the engine's live
                // operation); with a mirror, together with its mirror image as one operation
                // (a mirror made for another grid is refused, never dropped).
                match self.live.show(grid, &op, regulation, self.presser.mirror()) {
                    Ok(changed) => {
                        out.changed = changed.to_vec();
                        self.stats.patch_updates += out.changed.len() as u64;
                        h.to = to;
                    }
                    Err(e) => {
                        self.stats.rejected += 1;
                        out.refused = Some(e);
                    }
                }
            }
            self.hold = Some(h);
            return true;
        }
        let Some((at, mid)) = self.takes_hold(&thumb, &index, grid) else {
            return false;
        };
        // A press in progress ends here; the pinch holds the surface it left.
        if self.contact.is_some() {
            out.committed = self.end_contact();
        }
        self.stats.contacts += 1;
        // The surface as it is now is the start the pinch's moves are applied to.
        self.live.settle();
        self.hold = Some(Box::new(Hold {
            at,
            start: mid,
            to: at,
        }));
        true
    }
}

/// The thumb's and the index's capsules among a frame's parts, when both press (rule 9).
pub(super) fn pinch_pair(tips: &[(Part, Fingertip)]) -> Option<(Fingertip, Fingertip)> {
    let find = |d: Digit| tips.iter().find(|(p, _)| *p == Part::Digit(d)).map(|t| t.1);
    Some((find(Digit::Thumb)?, find(Digit::Index)?))
}
