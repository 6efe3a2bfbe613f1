//! Rule 3 of [`super`]: which side of the clay a part comes from, and how deep it is in.
//!
//! A part presses only where its tip *entered* the clay, and only from the side its hand
//! is on. Both are read off the part's motion, never off its pose alone:
//!
//! - **Entering** is the tip's path between two frames, `E₀ → E`, crossing the surface (the
//!   surface as it was before the contact). The part then goes into the clay along `m̂`, the
//!   surface normal at the crossing turned the way the tip went (`m̂·(E − E₀) > 0`): the clay
//!   is on the far side of the sheet from where the tip came.
//! - **From the hand's side**: at the frame before, the part's whole body — from the back of
//!   the hand through its knuckle and joints to the tip ([`Fingertip::body`]) — did not cross
//!   the surface. The tip was reached from the hand without passing through clay, so the
//!   side it came in from is the side the hand is on. A tip that is on the far side of the
//!   clay from its own hand (a finger whose tip was found inside the clay when the hand
//!   appeared, or after an undo put the clay back over it; a curled fingertip under a sheet
//!   its knuckles are above) does not press when it comes out: coming out through the sheet
//!   toward the hand would push the clay toward the hand.
//! - **While in the clay** the part keeps its side: every frame the surface is searched back
//!   from the tip along `−m̂` (the nearest surface behind the tip: the sheet it went
//!   through, not a wall farther back), `m̂` is updated to the normal found there (turned to
//!   agree with the last `m̂`, so it follows a curved surface along a stroke without ever
//!   flipping), and the depth `h` is the tip's distance past the surface along it. The part
//!   leaves the clay when its tip's path crosses the surface back toward its side, or when
//!   no surface is behind it any more (it slid off the sheet's edge).
//!
//! So a curled finger whose tip never crossed the surface never presses, however its
//! straight capsule would run through the clay; a part can only move the clay along `m̂`,
//! away from the side it came from, and by no more than its tip went in (`h`). Only the grip
//! and the pinch move clay toward the hand.
//!
//! The tip's path and the body are tested with the [`Probe`](crate::hand::Probe) (segments
//! against the exact patches). The body is tested only on a frame whose tip path crosses the
//! surface, so a frame costs one short segment per part, plus one or two searches along the
//! normal for a part in the clay.

use glam::DVec3;

use super::HandLoop;
use crate::hand::contact::{AxisHit, Fingertip};
use crate::hand::parts::Part;
use crate::surface::Grid;

/// How a part in the clay presses it (rule 3): along `dir`, `depth` past the surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Press {
    /// The unit direction `m̂` the clay is pressed in: the surface normal, turned away from
    /// the side the part came from.
    pub(super) dir: DVec3,
    /// The signed depth `h` of the tip past the surface along `m̂` (positive: in the clay).
    pub(super) depth: f64,
}

/// Which side of the clay a part's tip is on (rule 3), as its crossings of the surface say.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Place {
    /// Not known: the part has just appeared (or reappeared after frames without a hand)
    /// with its body across the surface — its tip may be in the clay.
    Unknown,
    /// On the hand's side: the part was seen with its body, back of the hand to tip, crossing
    /// no surface, and its tip has crossed none since (or has come back).
    Home,
    /// Past the surface: the tip crossed it along `dir` (into the clay) and has not crossed
    /// back. `pressing`: it entered from the hand's side (its body out of the clay at the
    /// frame before), so it presses; otherwise it went through with the hand (the back of
    /// the hand or a knuckle crossed first) and its coming back out is a return, not a press.
    Far {
        /// The direction the tip went in along: `m̂`, updated while it presses.
        dir: DVec3,
        /// Whether it presses.
        pressing: bool,
    },
}

/// Where a part was at the last frame with a hand, and which side of the clay it was on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Side {
    /// Its tip.
    pub(super) tip: DVec3,
    /// Its body, back of the hand to tip ([`Fingertip::body`]).
    pub(super) body: [DVec3; 5],
    /// The side of the clay its tip was on.
    pub(super) place: Place,
}

impl Side {
    /// The same place, no longer pressing: a part that was in the clay stays past the surface
    /// and comes back out without pressing (rules 8 and 9).
    pub(super) fn stop_pressing(&mut self) {
        if let Place::Far { pressing, .. } = &mut self.place {
            *pressing = false;
        }
    }
}

/// The most crossings of one frame's tip path counted (a jump through a few sheets).
const MAX_CROSSINGS: usize = 8;

/// How many times the normal's foot is refined (`depth_behind`).
const FOOT_STEPS: usize = 4;

/// The slot of a part in [`HandLoop`]'s per-part memory.
pub(super) fn slot(part: Part) -> usize {
    match part {
        Part::Digit(d) => d.index(),
        Part::Palm => 5,
    }
}

impl HandLoop {
    /// Rule 3 for a part of the hand: where `finger`'s tip is now relative to `reference`,
    /// given where it was at the last frame (`was`; `None`: the part has just appeared), and
    /// how it presses the clay (`None`: it does not).
    ///
    /// A part appears [`Place::Home`] when its body crosses no surface, else
    /// [`Place::Unknown`] until it does not. The tip's path from the last frame crossing the
    /// surface moves it from one side to the other: from `Home` past the surface it enters the
    /// clay — pressing if its body crossed no surface at the last frame, else it went through
    /// with the hand (the back of the hand or a knuckle crossed first), pressing nothing; from
    /// `Unknown` it rejoins its body's side (`Home`); from [`Place::Far`] back across the
    /// surface (against `dir`) it is home again, pressing nothing. The crossings of the path
    /// are counted: an even number (a jump — a tracker glitch, two recordings joined — through
    /// the clay and out again) leaves the tip where it was, and a tip that crossed several
    /// sheets in one frame does not press.
    pub(super) fn side_press(
        &mut self,
        reference: &Grid,
        was: Option<&Side>,
        finger: &Fingertip,
    ) -> (Place, Option<Press>) {
        let Some(was) = was else {
            return (self.appearing(reference, finger), None);
        };
        let step = finger.tip - was.tip;
        let (count, last) = self.crossings(reference, was.tip, step);
        let place = match (was.place, last) {
            // No crossing, or an even number (a jump through the clay and out again in one
            // frame): still on the same side.
            (Place::Unknown, _) if count % 2 == 0 => self.appearing(reference, finger),
            (place, _) if count % 2 == 0 => place,
            (_, None) => was.place,
            (Place::Far { dir, pressing }, Some(x)) => {
                // Back through the sheet toward the side it came from: out of the clay (a
                // lone crossing onward, into a farther sheet, keeps it in).
                if count > 1 || x.normal.dot(step) * x.normal.dot(dir) < 0.0 {
                    return (Place::Home, None);
                }
                Place::Far { dir, pressing }
            }
            (from, Some(x)) => {
                let Some(n) = x.normal.try_normalize() else {
                    return (from, None);
                };
                let dir = if n.dot(step) > 0.0 { n } else { -n };
                if count == 1 && self.clear(reference, &was.body) {
                    Place::Far {
                        dir,
                        pressing: true,
                    }
                } else if from == Place::Home {
                    Place::Far {
                        dir,
                        pressing: false,
                    }
                } else {
                    Place::Home
                }
            }
        };
        match place {
            Place::Far {
                dir,
                pressing: true,
            } => match self.depth_behind(reference, finger.tip, dir, finger.length) {
                Some(p) => (
                    Place::Far {
                        dir: p.dir,
                        pressing: true,
                    },
                    Some(p),
                ),
                // No surface behind the tip any more: it slid off the sheet's edge.
                None => (Place::Home, None),
            },
            place => (place, None),
        }
    }

    /// How many times the path `from → from + step` crosses `grid` (at most
    /// [`MAX_CROSSINGS`]), and the last crossing.
    fn crossings(&mut self, grid: &Grid, from: DVec3, step: DVec3) -> (usize, Option<AxisHit>) {
        let length = step.length();
        let Some(dir) = step.try_normalize() else {
            return (0, None);
        };
        let (mut count, mut last, mut at) = (0, None, 0.0);
        while count < MAX_CROSSINGS {
            let Some(x) = self
                .probe
                .first_crossing(grid, from + at * dir, dir, length - at)
            else {
                break;
            };
            count += 1;
            at += x.t + 1e-6 * (1.0 + length);
            last = Some(AxisHit { t: at, ..x });
            if at >= length {
                break;
            }
        }
        (count, last)
    }

    /// Where a part is whose side is not known yet (it has just appeared): on the hand's side
    /// when its body, from the back of the hand to the tip, crosses no surface; not known
    /// while it does (its tip may be in the clay).
    fn appearing(&mut self, reference: &Grid, finger: &Fingertip) -> Place {
        if self.clear(reference, &finger.body) {
            Place::Home
        } else {
            Place::Unknown
        }
    }

    /// Whether no segment of `body` crosses `grid`.
    fn clear(&mut self, grid: &Grid, body: &[DVec3; 5]) -> bool {
        body.windows(2).all(|w| {
            let d = w[1] - w[0];
            let l = d.length();
            l == 0.0 || self.probe.first_crossing(grid, w[0], d, l).is_none()
        })
    }

    /// The press of a tip in the clay along (about) `m`: the nearest surface behind the tip
    /// along `−m` (searched `reach` back, then as far as the grid goes), its normal turned to
    /// agree with `m`, and the tip's depth along that normal. `None`: no surface behind.
    fn depth_behind(&mut self, grid: &Grid, tip: DVec3, m: DVec3, reach: f64) -> Option<Press> {
        let far = 2.0 * grid.bounds().half_extents().length() + reach;
        let mut hit = self
            .probe
            .first_crossing(grid, tip, -m, reach)
            .or_else(|| self.probe.first_crossing(grid, tip, -m, far))?;
        let mut dir = m;
        // The foot of the normal through the tip: the normal where the line `tip − t·dir` meets
        // the surface becomes the next line's direction (each turned to agree with `m`), a few
        // times — exact at once on a plane, a fixed point on a curved surface.
        for _ in 0..FOOT_STEPS {
            let n = hit.normal.try_normalize()?;
            let next = if n.dot(m) >= 0.0 { n } else { -n };
            if next.dot(dir) >= 1.0 - 1e-12 {
                dir = next;
                break;
            }
            dir = next;
            match self
                .probe
                .first_crossing(grid, tip, -dir, hit.t.mul_add(2.0, reach))
            {
                Some(h) => hit = h,
                None => break,
            }
        }
        Some(Press { dir, depth: hit.t })
    }

    /// Where a gripping part is: the surface nearest its tip along `±m` (within `reach`
    /// either way), the normal there turned to agree with `m`, and the tip's signed depth
    /// past it (negative: the tip is out of the clay, pulling). `None`: no surface within
    /// reach.
    pub(super) fn grip_press(
        &mut self,
        grid: &Grid,
        tip: DVec3,
        m: DVec3,
        reach: f64,
    ) -> Option<Press> {
        let behind = self.probe.first_crossing(grid, tip, -m, reach);
        let ahead = self.probe.first_crossing(grid, tip, m, reach);
        let (hit, sign) = match (behind, ahead) {
            (Some(b), Some(a)) if a.t < b.t => (a, -1.0),
            (Some(b), _) => (b, 1.0),
            (None, Some(a)) => (a, -1.0),
            (None, None) => return None,
        };
        let n = hit.normal.try_normalize()?;
        let dir = if n.dot(m) >= 0.0 { n } else { -n };
        Some(Press {
            dir,
            depth: sign * hit.t * dir.dot(m),
        })
    }

    /// Where the grip catches a part that is not in the clay: the surface ahead of its tip
    /// along the finger (within its reach), the normal there turned along the finger, and the
    /// tip's (negative) depth before it along that normal.
    pub(super) fn grip_start(&mut self, grid: &Grid, finger: &Fingertip) -> Option<Press> {
        let hit = self
            .probe
            .first_crossing(grid, finger.tip, finger.axis, finger.length)?;
        let n = hit.normal.try_normalize()?;
        let dir = if n.dot(finger.axis) >= 0.0 { n } else { -n };
        let along = self
            .probe
            .first_crossing(grid, finger.tip, dir, hit.t + finger.length)
            .map_or(hit.t * dir.dot(finger.axis), |h| h.t);
        Some(Press { dir, depth: -along })
    }
}
