//! Pinch to grab (rule 9 of [`super`]): thumb and index meeting on the clay take hold of it
//! and, while they stay together, move it with the pinch point — one `move` of the surface
//! before the pinch, one undo step.
//!
//! The distances are the hand's own: the tips take hold closer than
//! [`HandOptions::pinch_closed`] (a quarter) of the index finger's length apart, both within
//! that of the surface, and let go beyond [`HandOptions::pinch_open`] (three eighths) of it.
//! A tracker-to-world scale makes the hand, its gestures and these distances alike larger or
//! smaller, so the same gesture pinches, or does not, at any scale: at 1 side per metre the
//! default hand's index is 0.081 side long and pinches within 0.02 side; at 20 sides per metre
//! within 0.4 side. A fixed distance in sides would be 5 times the whole hand at the first
//! scale — every touch a pinch.
//!
//! A pinch is a closing: the tips take hold only when they come together within reach of the
//! clay, having been apart since the hand appeared. Tips that are together already — a hand
//! that appears pinched, a fist (the thumb folded over the index), fingers closed in the air
//! and then brought to the clay — take hold of nothing and press like any other part, so a
//! fist pushed into the clay dents it instead of drawing it out as it withdraws.
//!
//! [`HandOptions::pinch_closed`]: crate::hand::HandOptions::pinch_closed
//! [`HandOptions::pinch_open`]: crate::hand::HandOptions::pinch_open

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

impl HandLoop {
    /// The pinch distance in world units: [`HandOptions::pinch_closed`] of the index finger's
    /// length.
    ///
    /// [`HandOptions::pinch_closed`]: crate::hand::HandOptions::pinch_closed
    #[must_use]
    pub fn pinch_distance(&self) -> f64 {
        self.options.pinch_closed * self.hand.finger_length(Digit::Index)
    }

    /// The distance at which a pinch lets go, in world units: [`HandOptions::pinch_open`] of
    /// the index finger's length.
    ///
    /// [`HandOptions::pinch_open`]: crate::hand::HandOptions::pinch_open
    #[must_use]
    pub fn pinch_release_distance(&self) -> f64 {
        self.options.pinch_open * self.hand.finger_length(Digit::Index)
    }

    /// Rule 9: where thumb and index, not holding yet, take hold of `grid` — the point of the
    /// clay held and the pinch point — or `None`. They take hold when their tips *close* to
    /// less than the pinch distance `d` ([`HandLoop::pinch_distance`]) — they were at least
    /// `d` apart at a frame since the hand appeared, and have not closed since — on the same
    /// side of the clay, each tip within `d` of the surface (both within reach of it); the
    /// clay nearest the pinch point is taken hold of.
    pub(super) fn takes_hold(
        &mut self,
        thumb: &Fingertip,
        index: &Fingertip,
        grid: &Grid,
    ) -> Option<(DVec3, DVec3)> {
        let d = self.pinch_distance();
        let gap = (thumb.tip - index.tip).length();
        let mid = 0.5 * (thumb.tip + index.tip);
        if gap >= d || !self.pinch_armed {
            return None;
        }
        // Both tips on the same side of the clay (the segment between them does not cross it:
        // a wall pinched from both sides is pressed, not held).
        if self
            .probe
            .first_crossing(grid, thumb.tip, index.tip - thumb.tip, gap)
            .is_some()
        {
            return None;
        }
        // Both tips within reach of the surface: first a patch box within `d` of each (the
        // box pyramid: cheap when the hand is away from the clay), then the nearest point.
        for tip in [thumb.tip, index.tip] {
            let mut near = std::mem::take(&mut self.near);
            near.clear();
            grid.patches_where(
                |b| {
                    let b = b.inflated(d);
                    tip.cmpge(b.min).all() && tip.cmple(b.max).all()
                },
                &mut near,
            );
            let any = !near.is_empty();
            self.near = near;
            if !any {
                return None;
            }
            let s = crate::surface::nearest(grid, tip)?;
            if (s.point - tip).length() > d {
                return None;
            }
        }
        let hit = crate::surface::nearest(grid, mid)?;
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
                out.committed = self.close();
            }
            return false;
        };
        let gap = (thumb.tip - index.tip).length();
        let mid = 0.5 * (thumb.tip + index.tip);
        if let Some(mut h) = self.hold.take() {
            if gap > self.pinch_release_distance() {
                self.hold = Some(h);
                out.committed = self.close();
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
        if gap >= self.pinch_distance() {
            // Open: the next closing of the tips may take hold.
            self.pinch_armed = true;
            return false;
        }
        let Some((at, mid)) = self.takes_hold(&thumb, &index, grid) else {
            // Closed without taking hold (away from the clay, or across it): the tips must
            // open again before they can.
            self.pinch_armed = false;
            return false;
        };
        self.pinch_armed = false;
        // A press in progress ends here; the pinch holds the surface it left.
        if self.contact.is_some() {
            out.committed = self.close();
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
