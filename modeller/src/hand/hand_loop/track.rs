//! A contact in progress, part by part (rules 5–7 of [`super`]): each part's [`Track`] of
//! placements — a push that grows into a draw-a-line stroke as the fingertip moves across,
//! straight runs merged into one segment — and the [`Contact`] they make together.

use glam::DVec3;

use crate::hand::options::HandOptions;
use crate::hand::parts::Part;
use crate::hand::press::Placement;
use crate::surface::Grid;

/// One part's share of a contact in progress (rules 5–7): its placements, a stroke of the
/// envelope.
#[derive(Debug, Clone)]
pub(super) struct Track {
    /// The part pressing.
    pub(super) part: Part,
    /// Its capsule radius (the shape function's finger radius).
    pub(super) radius: f64,
    /// How far along its axis the surface is searched, and the capsule's length.
    pub(super) reach: f64,
    /// Whether the clay sticks to it.
    pub(super) grip: bool,
    /// Every placement so far; the last one is live.
    pub(super) placements: Vec<Placement>,
    /// The live placement's point on the surface before the contact.
    pub(super) anchor: DVec3,
    /// The live placement's penetration (the deepest while pressing, the current gripping).
    pub(super) penetration: f64,
    /// The depth correction of rule 7.
    pub(super) correction: f64,
    /// Whether the part is still in the clay; a part that left keeps its placements and
    /// takes no more (coming back, it starts a new track).
    pub(super) active: bool,
    /// The placements changed since the last application.
    pub(super) dirty: bool,
}

impl Track {
    pub(super) fn live(&mut self) -> &mut Placement {
        let last = self.placements.len() - 1;
        &mut self.placements[last]
    }

    /// Sets the live placement's depth from its penetration and the correction (pressing,
    /// never below zero: a press does not pull).
    pub(super) fn update_live(&mut self, min_depth: f64) {
        let mut depth = self.penetration + self.correction;
        if !self.grip {
            depth = depth.max(0.0);
        }
        let anchor = self.anchor;
        let live = self.live();
        if (depth - live.depth).abs() > min_depth {
            live.depth = depth;
            live.tip = anchor + depth * live.dir;
            self.dirty = true;
        }
    }
}

/// A contact in progress: every part that pressed the clay since it began, applied together
/// to the surface before it.
#[derive(Debug, Clone)]
pub(super) struct Contact {
    /// The surface before the contact.
    pub(super) reference: Grid,
    /// One track per part that touched, in the order they touched.
    pub(super) tracks: Vec<Track>,
}

impl Contact {
    pub(super) fn active(&self, part: Part) -> Option<usize> {
        self.tracks.iter().position(|t| t.part == part && t.active)
    }
}

/// Largest angle between the directions of two placements merged into one segment (2°).
const MERGE_COS: f64 = 0.999_390_827_019_095_8;
/// Largest distance (in finger radii) of a merged placement from the merged segment.
const MERGE_DISTANCE: f64 = 5e-3;
/// Longest merged segment, in finger radii: the live segment is recomputed every frame, so
/// it is kept short (a frame costs what the live segment reaches).
const MERGE_LENGTH: f64 = 0.5;

/// Rule 5: the part at `e`, its finger along `finger`, pressing along `axis` (the rule-3
/// direction `m̂`) with penetration `p`, moves the live placement or adds one.
pub(super) fn extend(o: &HandOptions, c: &mut Track, e: DVec3, finger: DVec3, axis: DVec3, p: f64) {
    let live = *c.live();
    // How far the fingertip moved across the pressing direction since the live placement,
    // beyond what pressing explains: straight in or out along `m̂`, or poking in or out
    // along the finger `d̂` (a leaning finger going in moves its foot on the surface; that
    // is still the same push).
    let target = c.anchor + c.penetration * live.dir;
    let v = e - target;
    let tangential = |w: DVec3| w - w.dot(live.dir) * live.dir;
    let gained = p - c.penetration;
    let across = tangential(v)
        .length()
        .min(tangential(v - v.dot(finger) * finger).length());
    if across > o.stroke_step {
        // A push turning into a stroke: the push's correction made up for how a lone
        // paraboloid fits the patches; the stroke's segments press by the penetration.
        c.correction = 0.0;
        let depth = if c.grip { p } else { p.max(0.0) };
        let anchor = e - p * axis;
        let next = Placement {
            tip: anchor + depth * axis,
            dir: axis,
            depth,
        };
        let n = c.placements.len();
        // Merge a straight run into one segment (not the first placement: the push).
        if n >= 2 {
            let prev = c.placements[n - 2];
            if mergeable(&prev, &live, &next, c.radius) {
                c.placements.pop();
            }
        }
        c.placements.push(next);
        c.anchor = anchor;
        c.penetration = p;
        c.dirty = true;
    } else if c.grip {
        c.penetration = p;
    } else if gained > 0.0 {
        // Pressing deeper: the live placement follows the fingertip.
        c.anchor = e - p * axis;
        c.penetration = p;
        let depth = (p + c.correction).max(0.0);
        let anchor = c.anchor;
        let live = c.live();
        live.dir = axis;
        live.depth = depth;
        live.tip = anchor + depth * axis;
        c.dirty = true;
    }
    c.update_live(o.min_depth);
}

/// Whether `live` lies on the segment `prev → next` closely enough, with the same direction
/// and depth, to be dropped from the polyline.
fn mergeable(prev: &Placement, live: &Placement, next: &Placement, radius: f64) -> bool {
    let same_dir = live.dir.dot(next.dir) >= MERGE_COS && prev.dir.dot(next.dir) >= MERGE_COS;
    let tolerance = MERGE_DISTANCE * radius;
    let same_depth = (live.depth - next.depth).abs() <= tolerance
        && (prev.depth - next.depth).abs() <= tolerance;
    let seg = next.tip - prev.tip;
    let t = if seg.length_squared() > 0.0 {
        ((live.tip - prev.tip).dot(seg) / seg.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let off = (prev.tip + t * seg - live.tip).length();
    same_dir && same_depth && off <= tolerance && seg.length() <= MERGE_LENGTH * radius
}
