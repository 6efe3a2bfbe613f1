//! The loop of P2 §2.1 (Fig. 1): at every device sample, the hand frame → the kinematic
//! hand → contact of the active finger with the surface → push / draw-a-line → Bernstein
//! inverse and regulation.
//!
//! Before any rule below reads a frame, it goes through the plausibility gate and the
//! One-Euro filter ([`super::filter`]): the rules see the filtered frame.
//!
//! ## Contact semantics
//!
//! The hand presses with every part in [`HandOptions::finger`] ([`Fingers`]: any of the five
//! fingers and the palm; a glove profile's default is the five fingers, the mouse is a single
//! ray). Each part is a capsule ([`Fingertip`]). For a finger, let `E` be its fingertip point,
//! `d̂` its direction (the distal segment's, or the view ray's for the mouse), `r_f` the
//! finger radius, and `ℓ = max(finger length, 2·r_f)` the reach searched along the finger.
//! **The palm** is a capsule of radius `r_palm = max(W/2, r_f)` (`W` the palm's width in
//! world units) ending at the centre of the palm's face, pointing out of the palm
//! ([`Hand::palm`]), `ℓ = 2·r_palm` long: laid flat on the clay it presses a disc about its
//! width across, with the shape functions' paraboloid profile (not a flat-bottomed print:
//! the limit of building the palm from the paper's finger).
//!
//! **All the parts of one frame are one operation.** Rules 3–8 below apply to each part on
//! its own — its own placements, its own depth — and every part that touched the clay since
//! the contact began contributes its placements (a stroke each, [`Stroke`]) to one envelope,
//! applied to the surface before the contact and regulated once. A part that leaves the clay
//! keeps what it pressed; the contact ends when no part is in the clay. Two fingers pinching a
//! wall from both sides each press their side.
//!
//! **The contact rule in one line:** the clay never moves farther than the finger penetrated
//! it — it is pressed along the surface normal by the depth of the fingertip below the
//! surface, whatever the finger's angle (rule 3). The mouse's finger ([`FingerModel::Ray`])
//! is the exception: its depth is chosen along the view ray, and it presses along it.
//!
//! 1. **Finger.** A frame whose tracker is not `ok`, or without a pose, has no finger; nor has
//!    a frame whose glove is silent or lost, or `ok` without joint angles; without a glove in
//!    the profile (`none`) the hand is flat. Values a frame carries for a source that is not
//!    `ok` are never used. No finger: the contact ends.
//! 2. **Activation** ([`Activation`](super::Activation)). The glove's finger always acts;
//!    its switch ([`nendo_devices::buttons::PRIMARY`]) is the grip. The mouse finger acts
//!    only while a button is held: the left button presses, the right one grips.
//! 3. **Penetration: as deep as the finger went.** The [`Probe`] finds the first crossing `S`
//!    of the finger's axis, from `E − ℓ·d̂` to `E` (to `E + ℓ·d̂` while gripping), with a
//!    surface. The clay is pressed along `m̂`, the surface normal at `S` turned to the
//!    finger's side (`m̂·d̂ > 0`), by `h`, the signed depth of the fingertip past the surface
//!    along `m̂` (the surface met on the line `E − t·m̂`; positive: the tip is in the clay).
//!    So a tip that pokes straight in (`d̂ = m̂`) presses along the finger by how far it went
//!    in, and a finger lying on the clay presses with its side, into the surface, by how deep
//!    its tip is — never shoving the clay along the finger: with the finger at angle `θ` to a
//!    plane, the penetration along the axis is `h / sin θ` (1 side for a tip 0.05 below at 3°),
//!    which pressed along `d̂` would move the clay that far sideways. The clay moves by at most
//!    `h` at the samples (the shape function's `(1 − r²/r_f²)·h`), its control points by at
//!    most about 1.5 `h` (tests/it/hand_contact.rs, a flat hand at 3° to 90°).
//!    **The finger's body reaches the crossing:** `S` counts only if it is no farther
//!    behind the tip than the finger's own joints reach along the axis,
//!    `(E − S)·d̂ ≤ max_k (E − p_k)·d̂` ([`Fingertip::body`]; the finger's length when it is
//!    straight). The capsule is straight and `ℓ` long (at least `2·r_f`, 2 side by default),
//!    but a curled finger is not: out of a pointing fist the ring finger's tip points back
//!    up, 1.5 side above the plane the index presses, its joints higher still, while its
//!    capsule runs 2 side straight down through the plane; without this test it "pressed"
//!    the plane from below by the tip's height (a dent 2.4 deep for the index's 0.3).
//! 4. **A contact starts** when, on the surface as it is, `h > min_depth` (pressing) — or,
//!    with the grip held, `h ≥ −grip_distance` (the tip touching, or within a hair): the clay
//!    sticks to it.
//! 5. **During a contact** `h` and `m̂` are measured on the surface *as it was before the
//!    contact* (kept aside): how far the finger is in the clay. The contact is a list of
//!    placements ([`Placement`]): the first a push ending at the fingertip with `M = h·m̂`
//!    (P2 §5.1: "M, the virtual finger's movement vector"); whenever the tip moves
//!    across `m̂` by more than `stroke_step`, a new placement at the new tip, joined to the
//!    previous one by a draw-a-line segment (§5.2) of its own `L_f = h·m̂`. Going deeper is
//!    not moving across: the tip pressed straight in along `m̂`, or poking along the finger
//!    `d̂` (a leaning finger going in or out), keeps the push; going deeper, the push follows
//!    the fingertip. Limit: a finger lying on the clay that slides along its own length is
//!    taken for poking, not for drawing a line. Pressing, the latest placement keeps
//!    the deepest `p` it reached (clay does not spring back when the finger eases off);
//!    gripping, it follows `p` both ways (withdrawing pulls; moving draws a ridge).
//! 6. **Only what the finger adds.** Every frame the surface is recomputed from the surface
//!    before the contact with all the placements so far, each sample moving by the strongest
//!    of their flows (see [`super::press`]): a finger held still changes nothing, pressing
//!    deeper applies only the additional penetration, and the clay behind a moving finger is
//!    not pressed again.
//! 7. **The clay meets the fingertip.** The Bernstein inverse reproduces the shape function
//!    at the 16 samples of each patch, not everywhere, and regulation moves the surface a
//!    little more, so a push of `p` does not put the surface exactly at the fingertip (on the
//!    paper's 8 × 4 sphere with `r_f = 1`, about half of it). While a contact is a lone push
//!    or pull, the surface is measured along its axis at the fingertip after each
//!    application, and the miss is added to a correction of the depth, until the clay meets
//!    the finger. A stroke's segments press by the penetration itself (the draw-a-line
//!    shape function as the paper has it): along a stroke the clay at the fingertip is also
//!    shaped by the earlier segments, so a miss there does not measure the live one.
//! 8. **A contact ends** when the finger goes back out of the clay as it was before the contact
//!    (pressing: `h ≤ 0`; gripping: the grip released and `h ≤ 0`, or no surface within
//!    reach), or the finger disappears or stops acting. Its result is then the surface the next
//!    contact starts from. A contact is one operation in the paper's sense (its Fig. 15 pot
//!    took 152).
//! 9. **Pinch to grab.** With thumb and index both in the set (a glove; never the mouse), when
//!    their fingertips come closer than [`HandOptions::pinch_distance`] (0.4 side by default)
//!    *on the same side of the clay* (the segment between the tips does not cross the
//!    surface) and the surface point `S` nearest the pinch point `P` (midway between the tips,
//!    [`crate::surface::nearest`]) is within `r_f` of `P`, they take hold of the clay at `S`
//!    instead of pressing (a press in progress ends first). While the tips
//!    stay within 1.5 × the pinch distance, every frame the surface is the surface before the
//!    pinch moved by `{"op":"move","at":S,"to":S + (P − P₀),"radius":r_f}` ([`Op::Move`],
//!    [`crate::surface::grab`]: the held point lands exactly on the target), `P₀` the pinch
//!    point when it took hold; nothing presses meanwhile. Opening the pinch ends it: one
//!    operation, one undo step, committed as that one `move`.
//!
//! Everything runs in a fixed order on `f64`: the outcome is a pure function of the frames,
//! the starting grid and the options.

use glam::DVec3;
use nendo_devices::{FrameFilter, HandFrame, JointAngles, SourceState};

use super::HandError;
use super::contact::{Fingertip, Probe};
use super::kinematics::{Digit, Hand, HandPose};
use super::options::HandOptions;
use super::outcome::{FrameOutcome, LoopStats, Touch};
use super::parts::{FingerModel, Fingers, Part};
use super::press::{Placement, Presser, Stroke, describe};
use crate::surface::{Grid, LiveOperation, Op, Regulation};

mod pinch;
mod track;

use pinch::{Hold, pinch_pair};
use track::{Contact, Track, extend};

/// How the fingertip presses the clay (rule 3): along `dir`, `depth` past the surface.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Press {
    /// The unit direction `m̂` the clay is pressed in: the surface normal, turned to the
    /// finger's side.
    dir: DVec3,
    /// The signed depth `h` of the fingertip past the surface along `m̂` (positive: in the
    /// clay).
    depth: f64,
}

/// Frames → contact → operations on a grid (see the module docs).
#[derive(Debug, Clone)]
pub struct HandLoop {
    hand: Hand,
    options: HandOptions,
    probe: Probe,
    presser: Presser,
    /// The pinch's move, shown live on the surface before the pinch.
    live: LiveOperation,
    contact: Option<Box<Contact>>,
    hold: Option<Box<Hold>>,
    pose: Option<HandPose>,
    fingertip: Option<Fingertip>,
    tips: Vec<(Part, Fingertip)>,
    stats: LoopStats,
    /// The plausibility gate and One-Euro filter every frame goes through first
    /// ([`super::filter`]).
    pub(super) filter: FrameFilter,
}

impl HandLoop {
    /// Presses every contact together with its mirror image (see
    /// [`crate::surface::Presser::set_mirror`]); `None`: no mirror.
    pub fn set_mirror(&mut self, symmetry: Option<crate::surface::Symmetry>) {
        self.presser.set_mirror(symmetry);
    }

    /// The mirror set by [`HandLoop::set_mirror`].
    #[must_use]
    pub fn mirror(&self) -> Option<&crate::surface::Symmetry> {
        self.presser.mirror()
    }

    /// A loop for this hand.
    ///
    /// # Errors
    /// [`HandError::Options`] for bad options.
    pub fn new(hand: Hand, options: HandOptions) -> Result<Self, HandError> {
        options.validate()?;
        Ok(Self {
            hand,
            options,
            probe: Probe::new(),
            presser: Presser::default(),
            live: LiveOperation::new(),
            contact: None,
            hold: None,
            pose: None,
            fingertip: None,
            tips: Vec::new(),
            stats: LoopStats::default(),
            filter: FrameFilter::new(super::filter::default_for(options.finger)),
        })
    }

    /// The options.
    #[must_use]
    pub fn options(&self) -> &HandOptions {
        &self.options
    }

    /// The hand model.
    #[must_use]
    pub fn hand(&self) -> &Hand {
        &self.hand
    }

    /// The hand at the last frame that had one (for drawing).
    #[must_use]
    pub fn pose(&self) -> Option<&HandPose> {
        self.pose.as_ref()
    }

    /// The primary fingertip ([`FingerModel::primary`]) at the last frame that had one.
    #[must_use]
    pub fn fingertip(&self) -> Option<&Fingertip> {
        self.fingertip.as_ref()
    }

    /// Every pressing part's capsule at the last frame that had a hand (for drawing).
    #[must_use]
    pub fn fingertips(&self) -> &[(Part, Fingertip)] {
        &self.tips
    }

    /// The parts in the clay now: those of the contact in progress still pressing, or thumb
    /// and index while they hold the clay.
    #[must_use]
    pub fn touching(&self) -> Fingers {
        let mut set = Fingers(0);
        if self.hold.is_some() {
            set = set
                .with(Part::Digit(Digit::Thumb))
                .with(Part::Digit(Digit::Index));
        }
        if let Some(c) = &self.contact {
            for t in c.tracks.iter().filter(|t| t.active) {
                set = set.with(t.part);
            }
        }
        set
    }

    /// The hand's state.
    #[must_use]
    pub fn touch(&self) -> Touch {
        if self.hold.is_some() {
            return Touch::Holding;
        }
        match &self.contact {
            None => Touch::Free,
            Some(c) if c.tracks.iter().any(|t| t.active && t.grip) => Touch::Gripping,
            Some(_) => Touch::Pressing,
        }
    }

    /// The counters.
    #[must_use]
    pub fn stats(&self) -> &LoopStats {
        &self.stats
    }

    /// The placements of the contact in progress, every part's one after the other.
    #[must_use]
    pub fn placements(&self) -> Vec<Placement> {
        self.contact.as_ref().map_or_else(Vec::new, |c| {
            c.tracks
                .iter()
                .flat_map(|t| t.placements.iter().copied())
                .collect()
        })
    }

    /// How far along the primary finger the surface is searched: `max(finger length, 2·r_f)`.
    #[must_use]
    pub fn reach(&self) -> f64 {
        self.reach_of(Part::Digit(self.options.finger.primary()))
    }

    /// How far along a part the surface is searched: `max(finger length, 2·r_f)` for a
    /// finger, `2·r_palm` for the palm.
    fn reach_of(&self, part: Part) -> f64 {
        match part {
            Part::Digit(d) => self
                .hand
                .finger_length(d)
                .max(2.0 * self.options.finger_radius),
            Part::Palm => 2.0 * self.palm_radius(),
        }
    }

    /// The palm's capsule radius: half the palm's width, at least `r_f`.
    fn palm_radius(&self) -> f64 {
        (0.5 * self.hand.size().palm_width * self.hand.scale()).max(self.options.finger_radius)
    }

    /// Ends the contact or the pinch in progress, keeping what it did; returns the operations
    /// it stands for. Call it before the grid is changed by anything else (an undo, a mouse
    /// tool): a contact recomputes the patches it touches from the surface before it.
    pub fn end_contact(&mut self) -> Option<Vec<Op>> {
        if let Some(h) = self.hold.take() {
            self.stats.holds += 1;
            return Some(vec![Op::Move {
                at: h.at,
                to: h.to,
                radius: self.options.finger_radius,
            }]);
        }
        let c = self.contact.take()?;
        let mut ops = Vec::new();
        let mut count = 0;
        for t in &c.tracks {
            ops.extend(describe(&t.placements, t.radius));
            count += t.placements.len();
        }
        let lone = c.tracks.iter().all(|t| t.placements.len() == 1);
        match (count, c.tracks[0].placements[0].depth > 0.0) {
            (1, true) => self.stats.pushes += 1,
            (1, false) => self.stats.pulls += 1,
            _ if lone && c.tracks.iter().all(|t| t.placements[0].depth > 0.0) => {
                self.stats.pushes += 1;
            }
            _ => self.stats.strokes += 1,
        }
        self.stats.placements += count as u64;
        Some(ops)
    }

    /// The hand and primary fingertip of a frame, if it has them (rule 1 of the module docs).
    #[must_use]
    pub fn finger_of(&self, frame: &HandFrame) -> Option<(HandPose, Fingertip)> {
        let (pose, tips) = self.parts_of(frame)?;
        let primary = Part::Digit(self.options.finger.primary());
        let tip = tips
            .iter()
            .find(|(p, _)| *p == primary)
            .or_else(|| tips.first())?
            .1;
        Some((pose, tip))
    }

    /// The hand and the capsules of every pressing part of a frame (rule 1): a fingertip for
    /// each finger of the set, the palm's for the palm.
    #[must_use]
    pub fn parts_of(&self, frame: &HandFrame) -> Option<(HandPose, Vec<(Part, Fingertip)>)> {
        // Only a delivering source acts: a pose held over from a tracker that is now silent or
        // lost (a frame built by hand, a trace from elsewhere) never reaches the surface.
        if frame.status.tracker != SourceState::Ok {
            return None;
        }
        let pose = frame.pose?;
        let joints: Option<&JointAngles> = match (frame.status.glove, &frame.joints) {
            (SourceState::Ok, Some(j)) => Some(j),
            (SourceState::Absent, _) => None,
            _ => return None,
        };
        let placed = match self.options.finger {
            FingerModel::Hand(_) => self.hand.pose(&pose, joints),
            FingerModel::Ray => self.hand.pose_at_fingertip(&pose, joints, Digit::Index),
        };
        let mut tips = Vec::new();
        for part in self.options.finger.parts().parts() {
            let tip = match part {
                Part::Digit(d) => {
                    let chain = placed.finger(d);
                    Fingertip {
                        tip: chain.tip(),
                        axis: chain.direction(),
                        base: chain.points[2],
                        radius: self.options.finger_radius,
                        length: self.reach_of(part),
                        body: chain.points[..3]
                            .iter()
                            .map(|&p| (chain.tip() - p).dot(chain.direction()))
                            .fold(0.0, f64::max),
                    }
                }
                Part::Palm => {
                    let palm = self.hand.palm(&placed);
                    Fingertip {
                        tip: palm.centre,
                        axis: palm.normal,
                        base: palm.centre - self.reach_of(part) * palm.normal,
                        radius: self.palm_radius(),
                        length: self.reach_of(part),
                        body: self.reach_of(part),
                    }
                }
            };
            if !(tip.tip.is_finite() && tip.axis.is_finite()) {
                return None;
            }
            tips.push((part, tip));
        }
        (!tips.is_empty()).then_some((placed, tips))
    }

    /// Signed penetration of a fingertip into `grid` along its axis: `ahead` is how far past
    /// the tip the surface may be.
    fn penetration(
        &mut self,
        grid: &Grid,
        tip: DVec3,
        axis: DVec3,
        reach: f64,
        ahead: f64,
    ) -> Option<f64> {
        let hit = self
            .probe
            .first_crossing(grid, tip - reach * axis, axis, reach + ahead)?;
        Some(reach - hit.t)
    }

    /// Rule 3: how the capsule of `finger` (ending at its tip, pointing along its axis, its
    /// `length` long) presses `grid` — the direction `m̂` (the surface normal at the axis's
    /// crossing, turned to the finger's side) and the signed depth `h` of the tip past the
    /// surface along it. `ahead` is how far past the tip the surface may be. `None` when the
    /// axis does not reach the surface, or meets it farther behind the tip than the finger's
    /// `body` reaches.
    fn press(&mut self, grid: &Grid, finger: &Fingertip, ahead: f64) -> Option<Press> {
        let (tip, axis, reach, body) = (finger.tip, finger.axis, finger.length, finger.body);
        let hit = self
            .probe
            .first_crossing(grid, tip - reach * axis, axis, reach + ahead)?;
        let along_axis = reach - hit.t;
        if self.options.finger == FingerModel::Ray {
            // The mouse's finger is the view ray, its depth chosen along it (click depth, wheel):
            // it presses along the ray.
            return Some(Press {
                dir: axis,
                depth: along_axis,
            });
        }
        let n = hit.normal.try_normalize().unwrap_or(axis);
        let dir = if n.dot(axis) < 0.0 { -n } else { n };
        // The finger's own body reaches the crossing: past it the straight capsule runs on
        // where a curled finger is not (a fingertip curled back out of a fist points out of
        // the clay its capsule crosses).
        if along_axis > body {
            return None;
        }
        // Below the tangent plane at the crossing: exact on a plane, the fallback elsewhere.
        let tangent_depth = along_axis * dir.dot(axis);
        // Along m̂ through the tip itself, searched a little beyond that depth either way, so
        // a wall further behind (the far side of a pot) is not taken for this one.
        let back = 2.0 * tangent_depth.abs() + self.options.grip_distance;
        let depth = self
            .probe
            .first_crossing(grid, tip - back * dir, dir, back + ahead.min(back))
            .map_or(tangent_depth, |h| back - h.t);
        Some(Press { dir, depth })
    }

    /// Feeds one frame: finds the contact and deforms `grid` by it.
    pub fn frame(
        &mut self,
        frame: &HandFrame,
        grid: &mut Grid,
        regulation: Regulation,
    ) -> FrameOutcome {
        // The device's samples are gated and filtered before anything reads them
        // (super::filter): every rule below sees the filtered frame.
        let filtered = self.filter.apply(frame);
        let frame = &filtered;
        self.stats.frames += 1;
        let mut out = FrameOutcome::default();
        let parts = self.parts_of(frame);
        self.pose = parts.as_ref().map(|(p, _)| *p);
        self.tips.clear();
        if let Some((_, tips)) = &parts {
            self.tips.extend_from_slice(tips);
        }
        let primary = Part::Digit(self.options.finger.primary());
        self.fingertip = self
            .tips
            .iter()
            .find(|(p, _)| *p == primary)
            .or_else(|| self.tips.first())
            .map(|(_, t)| *t);
        let Some(((_, tips), grip)) = parts.zip(self.acting(frame)) else {
            out.committed = self.end_contact();
            return out;
        };
        self.stats.frames_with_finger += 1;

        // Rule 9: thumb and index together on the clay hold it.
        if self.pinch(&tips, grid, regulation, &mut out) {
            out.touch = self.touch();
            return out;
        }

        let o = self.options;
        if let Some(mut c) = self.contact.take() {
            let mut seen = Fingers(0);
            for &(part, finger) in &tips {
                seen = seen.with(part);
                let (e, axis) = (finger.tip, finger.axis);
                let reach = finger.length;
                if let Some(k) = c.active(part) {
                    // Rule 5: how far the part is in the clay as it was before the contact.
                    let p0 = self.press(&c.reference, &finger, reach);
                    let t = &mut c.tracks[k];
                    if t.grip && !grip {
                        t.grip = false;
                    } else if !t.grip && grip && p0.is_some_and(|p| p.depth >= -o.grip_distance) {
                        t.grip = true;
                    }
                    if part == primary {
                        out.penetration = p0.map(|p| p.depth);
                    }
                    match p0 {
                        Some(p) if t.grip || p.depth > 0.0 => {
                            extend(&o, t, e, axis, p.dir, p.depth);
                        }
                        // Rule 8: the part is out of the clay.
                        _ => t.active = false,
                    }
                } else {
                    // A part joining the contact (rule 4, on the surface before it).
                    let ahead = if grip { reach } else { 0.0 };
                    let press = self.press(&c.reference, &finger, ahead);
                    if part == primary {
                        out.penetration = press.map(|p| p.depth);
                    }
                    if let Some(t) = press.and_then(|p| self.start(part, &finger, p, grip)) {
                        c.tracks.push(t);
                    }
                }
            }
            for t in &mut c.tracks {
                if !seen.contains(t.part) {
                    t.active = false;
                }
            }
            self.contact = Some(c);
            if self
                .contact
                .as_ref()
                .is_some_and(|c| c.tracks.iter().all(|t| !t.active))
            {
                // Rule 8: every part is out of the clay.
                out.committed = self.end_contact();
            }
        }
        if self.contact.is_none() {
            // Rule 4: a new contact?
            let tracks = self.new_tracks(&tips, grid, grip, &mut out.penetration);
            if tracks.is_empty() {
                return out;
            }
            self.stats.contacts += 1;
            self.presser.begin(grid);
            self.contact = Some(Box::new(Contact {
                reference: grid.clone(),
                tracks,
            }));
        }
        self.apply(grid, regulation, &mut out);
        out.touch = self.touch();
        out
    }

    /// Rule 4 for every part of a frame, on `grid` as it is: the tracks of the parts that
    /// start a contact (none: no contact starts). Sets `penetration` to the primary part's
    /// depth when its axis meets the surface.
    fn new_tracks(
        &mut self,
        tips: &[(Part, Fingertip)],
        grid: &Grid,
        grip: bool,
        penetration: &mut Option<f64>,
    ) -> Vec<Track> {
        let primary = Part::Digit(self.options.finger.primary());
        let mut tracks = Vec::new();
        for &(part, finger) in tips {
            let reach = finger.length;
            let ahead = if grip { reach } else { 0.0 };
            let Some(press) = self.press(grid, &finger, ahead) else {
                continue;
            };
            if part == primary {
                *penetration = Some(press.depth);
            }
            tracks.extend(self.start(part, &finger, press, grip));
        }
        tracks
    }

    /// Rule 2: whether the finger acts in `frame` (`None`: it does not), and whether the grip
    /// is held.
    fn acting(&self, frame: &HandFrame) -> Option<bool> {
        let act = self.options.finger.activation();
        (act.press == 0 || frame.buttons & act.press != 0).then_some(frame.buttons & act.grip != 0)
    }

    /// What `frame` would start on `grid` if fed to this loop now, decided by the very rules
    /// [`HandLoop::frame`] follows (rules 1–4 and 9, the same code) without feeding it: the
    /// operations the new contact's first frame stands for — a pinch taking hold of the clay
    /// (rule 9) as a `move` of its held point to itself, else the first placement of every
    /// part that starts pressing (rule 4: only where the part's own joints reach, by `h`
    /// along `m̂`) as a push each ([`super::press::describe`]). `None` when a contact or a
    /// pinch is in progress, the frame has no acting finger, or nothing starts. The loop
    /// itself is not changed. `nendo replay --auto-refine` refines the grid for these
    /// operations before the frame.
    pub fn starting(&mut self, frame: &HandFrame, grid: &Grid) -> Option<Vec<Op>> {
        if self.touch() != Touch::Free {
            return None;
        }
        // The frame as HandLoop::frame will see it (super::filter), the filter untouched.
        let frame = &self.filter.peek(frame);
        let (_, tips) = self.parts_of(frame)?;
        let grip = self.acting(frame)?;
        if let Some((thumb, index)) = pinch_pair(&tips)
            && let Some((at, _)) = self.takes_hold(&thumb, &index, grid)
        {
            return Some(vec![Op::Move {
                at,
                to: at,
                radius: self.options.finger_radius,
            }]);
        }
        let tracks = self.new_tracks(&tips, grid, grip, &mut None);
        (!tracks.is_empty()).then(|| {
            tracks
                .iter()
                .flat_map(|t| describe(&t.placements, t.radius))
                .collect()
        })
    }

    /// Rule 4: the track a part starts when it presses (or grips) the clay.
    fn start(&self, part: Part, finger: &Fingertip, press: Press, grip: bool) -> Option<Track> {
        let o = self.options;
        let p = press.depth;
        let starts = if grip {
            p >= -o.grip_distance
        } else {
            p > o.min_depth
        };
        starts.then(|| {
            let anchor = finger.tip - p * press.dir;
            Track {
                part,
                radius: finger.radius,
                reach: finger.length,
                grip,
                placements: vec![Placement {
                    tip: finger.tip,
                    dir: press.dir,
                    depth: p,
                }],
                anchor,
                penetration: p,
                correction: 0.0,
                active: true,
                dirty: true,
            }
        })
    }

    /// Applies the contact's placements if they changed, then measures the clay at each live
    /// fingertip for the correction of rule 7.
    fn apply(&mut self, grid: &mut Grid, regulation: Regulation, out: &mut FrameOutcome) {
        let Some(mut c) = self.contact.take() else {
            return;
        };
        let o = self.options;
        if c.tracks.iter().any(|t| t.dirty) {
            for t in &mut c.tracks {
                t.dirty = false;
            }
            self.stats.applications += 1;
            let strokes: Vec<Stroke<'_>> = c
                .tracks
                .iter()
                .map(|t| Stroke {
                    placements: &t.placements,
                    radius: t.radius,
                    length: t.reach,
                })
                .collect();
            match self
                .presser
                .apply_strokes(&c.reference, grid, &strokes, regulation)
            {
                Ok(changed) => {
                    out.changed.clear();
                    out.changed.extend_from_slice(changed);
                    self.stats.patch_updates += changed.len() as u64;
                }
                Err(e) => {
                    self.stats.rejected += 1;
                    out.refused = Some(e);
                }
            }
            // Rule 7: where is the clay along each lone push's axis, at its fingertip? Only a
            // lone push or pull is corrected: along a stroke the clay at the live fingertip is
            // also shaped by the earlier placements, so a miss there does not measure the live
            // one.
            for k in 0..c.tracks.len() {
                let t = &c.tracks[k];
                if t.placements.len() != 1 || !t.active {
                    continue;
                }
                let dir = t.placements[0].dir;
                let target = t.anchor + t.penetration * dir;
                let reach = t.reach;
                let miss = self.penetration(grid, target, dir, reach, reach);
                if let Some(miss) = miss {
                    let t = &mut c.tracks[k];
                    let limit = 2.0 * t.radius;
                    t.correction = (t.correction + miss).clamp(-limit, limit);
                    t.update_live(o.min_depth);
                }
            }
        }
        self.contact = Some(c);
    }
}
