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
//! **The contact rule:** a part presses only where its tip *entered* the clay from the side
//! its hand is on, along the surface normal, and no deeper than the tip went. Entering is
//! read off the tip's motion — its path from the last frame to this one crossing the surface
//! as it was before the contact — and the side off where the part *was*: at the last frame
//! its whole body, from the back of the hand through knuckle and joints to the tip, was out
//! of the clay, so the tip came in from the hand's side; where the part is now says nothing
//! about which side of a sheet it came from. The clay is then pressed away from that side,
//! along `m̂`, by the tip's depth `h` past the surface (rule 3). Why: the hand is one body;
//! a fingertip can only reach the clay through the air the hand is in, so clay in front of a
//! moving tip is pushed away from the hand, never toward it. Every way a part could push
//! clay toward the hand comes from deciding the side from the pose alone — a curled finger
//! whose straight capsule runs back through the clay from a tip in the air (it used to raise
//! the plane 0.8 side under a fist), a tip that appears inside the clay (a hand put down in
//! it, an undo that puts clay back over a resting finger) and then comes out through the
//! sheet toward the hand. None of them entered the clay, so none presses. Clay moves toward
//! the hand only when the hand holds it: the grip (the glove's switch, rule 4) and the pinch
//! (rule 9). The mouse's finger ([`FingerModel::Ray`]) is the exception: its tip is put at
//! a depth along the view ray (click depth, wheel), so it presses along the ray by that
//! depth, always from the viewer's side.
//!
//! 1. **Finger.** A frame whose tracker is not `ok`, or without a pose, has no finger; nor has
//!    a frame whose glove is silent or lost, or `ok` without joint angles; without a glove in
//!    the profile (`none`) the hand is flat. Values a frame carries for a source that is not
//!    `ok` are never used. No finger: the contact ends, and where the parts were is
//!    forgotten (the next frame with a hand is the parts' first). A frame carrying a skeleton
//!    (a VMC source in the tracker's slot) takes the hand from its joints
//!    ([`super::skeleton`]); a skeleton without its palm has no finger, and a finger missing
//!    a joint of its chain (a bone not sent, or stale) is left out of the pressing parts.
//! 2. **Activation** ([`Activation`](super::Activation)). The glove's finger always acts;
//!    its switch ([`nendo_devices::buttons::PRIMARY`]) is the grip. The mouse finger acts
//!    only while a button is held: the left button presses, the right one grips.
//! 3. **In the clay: entered from the hand's side, as deep as the tip went** (the reasoning
//!    and the searches: `hand_loop/side.rs`). A part is *in the clay* from the frame its tip's path
//!    `E₀ → E` crosses the surface (before the contact; the grid as it is when none is in
//!    progress) while, at the frame before, its body ([`Fingertip::body`]) crossed no surface,
//!    until its tip's path crosses back or no surface is behind it; a part seen for the first
//!    time is not in the clay. While it is, the clay is pressed along `m̂` — the surface
//!    normal, at first at the crossing turned the way the tip went, then at the surface found
//!    behind the tip along the last `m̂`, turned to agree with it — by `h`, the depth of the
//!    tip past the surface along `m̂`. So a tip that pokes straight in presses along the
//!    finger by how far it went in, and a finger lying on the clay presses with its side, into
//!    the surface, by how deep its tip is — never shoving the clay along the finger: with the
//!    finger at angle `θ` to a plane, the penetration along the axis is `h / sin θ` (1 side for
//!    a tip 0.05 below at 3°), which pressed along `d̂` would move the clay that far sideways.
//!    The clay moves by at most `h` at the samples (the shape function's
//!    `(1 − r²/r_f²)·h`), its control points by at most about 1.5 `h` (tests/it/hand_contact.rs,
//!    a flat hand at 3° to 90°; the random poses of tests/it/hand_poses.rs). The capsule
//!    (`ℓ` long along `d̂`) is the reach the clay is searched behind the tip; a curled finger's
//!    straight capsule may run through the clay while its tip is in the air — the tip did not
//!    enter, so it does not press.
//! 4. **A contact starts** when, on the surface as it is, a part is in the clay by
//!    `h > min_depth` (pressing) — or, with the grip held, when it is in the clay, or the
//!    surface ahead of its tip along the finger (within `ℓ`) is within `grip_distance` of the
//!    tip along its normal (`h ≥ −grip_distance`: the tip touching, or within a hair): the
//!    clay sticks to it. A gripping part is measured along its `m̂` either way (in the clay or
//!    out of it, pulling).
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
//! 8. **A contact ends** when every part is back out of the clay as it was before the contact
//!    (pressing: out by rule 3; gripping: the grip released and out, or no surface within
//!    reach), or the hand disappears or stops acting. A contact ended from outside
//!    ([`HandLoop::end_contact`]: an undo, a mouse tool) takes every part out of the clay: a
//!    part still in it presses again only once it has come out and gone back in. Its result is then the surface the next
//!    contact starts from. A contact is one operation in the paper's sense (its Fig. 15 pot
//!    took 152).
//! 9. **Pinch to grab.** With thumb and index both in the set (a glove; never the mouse), when
//!    their fingertips come closer than the pinch distance `d` — [`HandOptions::pinch_closed`]
//!    of the hand's index finger length, a quarter by default: 2 cm of the default hand, so
//!    0.4 side at 20 sides per metre and 0.02 side at 1 (`hand_loop/pinch.rs`) — *on the same side of the
//!    clay* (the segment between the tips does not cross the surface), each tip within `d` of
//!    the surface (both within reach of it), they take hold of the clay at `S`, the surface
//!    point nearest the pinch point `P` (midway between the tips,
//!    [`crate::surface::nearest`]), instead of pressing (a press in progress ends first).
//!    While the tips stay within [`HandOptions::pinch_open`] of the index's length (three
//!    eighths: 1.5 `d`), every frame the surface is the surface before the pinch moved by
//!    `{"op":"move","at":S,"to":S + (P − P₀),"radius":r_f}` ([`Op::Move`],
//!    [`crate::surface::grab`]: the held point lands exactly on the target), `P₀` the pinch
//!    point when it took hold; nothing presses meanwhile, and no part is in the clay when it
//!    lets go. The tips must *close* on the clay: they take hold only if they were at least
//!    `d` apart at an earlier frame since the hand appeared and have not closed since (tips
//!    together already — a fist, a pinch closed in the air — press like any other part). Opening the pinch ends it: one operation, one undo step, committed as that one
//!    `move`.
//! 10. **The clutch** (`hand_loop/clutch.rs`). While the frame's buttons hold
//!     [`nendo_devices::buttons::CLUTCH`] (the window's clutch key), or — a glove's hand —
//!     while the hand makes a fist (the index, middle, ring and little fingers each flexed by
//!     at least 1.3 rad, the mean of MCP and PIP; open again when any is below 1.1 rad), the
//!     hand moves and is drawn but does not act: as rule 1 without a finger, the contact or
//!     pinch in progress ends and where the parts were is forgotten — so a part that is in the
//!     clay when the clutch lets go did not enter it, and presses only once it has come out
//!     and gone back in. The hand can be carried to another place, or back, through the clay.
//!
//! Everything runs in a fixed order on `f64`: the outcome is a pure function of the frames,
//! the starting grid and the options.

use glam::DVec3;
use nendo_devices::{FrameFilter, HandFrame, SourceState};

use super::HandError;
use super::contact::{Fingertip, Probe};
use super::kinematics::{Digit, Hand, HandPose};
use super::options::HandOptions;
use super::outcome::{FrameOutcome, LoopStats, Touch};
use super::parts::{FingerModel, Fingers, Part};
use super::press::{Placement, Presser, Stroke, describe};
use crate::surface::{Grid, LiveOperation, Op, Regulation};

pub mod clutch;
mod pinch;
mod placing;
mod side;
mod track;

use pinch::{Hold, pinch_pair};
use side::{Place, Press, Side, slot};
use track::{Contact, Track, extend};

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
    /// The filtered frame of the last frame that had a hand (for drawing its skeleton).
    drawn: Option<Box<HandFrame>>,
    fingertip: Option<Fingertip>,
    tips: Vec<(Part, Fingertip)>,
    /// Every part's place at the last frame with a hand, and whether it is in the clay
    /// (rule 3), by [`slot`].
    sides: [Option<Side>; 6],
    /// Scratch: patches near a pinching tip (rule 9).
    near: Vec<usize>,
    /// Whether thumb and index have been apart since the hand appeared or they last closed:
    /// the next closing may take hold (rule 9).
    pinch_armed: bool,
    /// Whether the hand made a fist at the last frame (rule 10's hysteresis).
    fist: bool,
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
            drawn: None,
            fingertip: None,
            tips: Vec::new(),
            sides: [None; 6],
            near: Vec::new(),
            pinch_armed: false,
            fist: false,
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

    /// The part deepest in the clay now and how deep its tip is past the surface before the
    /// contact (`h` of rule 3; a gripping part's may be negative), among the parts of the
    /// contact in progress still in it. `None` when no part is in the clay.
    #[must_use]
    pub fn deepest(&self) -> Option<(Part, f64)> {
        let c = self.contact.as_ref()?;
        c.tracks
            .iter()
            .filter(|t| t.active)
            .map(|t| (t.part, t.penetration))
            .max_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// Whether the hand made a fist at the last frame (rule 10's gesture: the clutch).
    #[must_use]
    pub fn fist(&self) -> bool {
        self.fist
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
    /// tool): a contact recomputes the patches it touches from the surface before it. A part
    /// still in the clay is then taken to be out of it: it presses again only after it has
    /// come out and gone back in (rule 3: the clay it is in may not be there any more).
    pub fn end_contact(&mut self) -> Option<Vec<Op>> {
        for s in self.sides.iter_mut().flatten() {
            s.stop_pressing();
        }
        self.close()
    }

    /// Ends the contact or the pinch in progress (rules 8 and 9), keeping what it did; the
    /// operations it stands for.
    fn close(&mut self) -> Option<Vec<Op>> {
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

    /// The mouse's finger ([`FingerModel::Ray`]): the view ray, its depth chosen along it
    /// (click depth, wheel), pressing along it — the depth `h` of the tip past the first
    /// crossing of the ray, from `E − ℓ·d̂` (the viewer's side) to `E + ahead·d̂`.
    fn ray_press(&mut self, grid: &Grid, finger: &Fingertip, ahead: f64) -> Option<Press> {
        let (tip, axis, reach) = (finger.tip, finger.axis, finger.length);
        let hit = self
            .probe
            .first_crossing(grid, tip - reach * axis, axis, reach + ahead)?;
        Some(Press {
            dir: axis,
            depth: reach - hit.t,
        })
    }

    /// Rule 3 for every part of a frame, on the surface before the contact (the grid itself
    /// when none is in progress): where each part is and how it presses, by [`slot`]. Reads
    /// where the parts were at the last frame; changes nothing but the probe's buffers. The
    /// mouse's ray has no sides (it is measured along the ray, [`HandLoop::ray_press`]).
    fn sides_now(
        &mut self,
        tips: &[(Part, Fingertip)],
        grid: &Grid,
    ) -> ([Place; 6], [Option<Press>; 6]) {
        let mut places = [Place::Unknown; 6];
        let mut now = [None; 6];
        if self.options.finger == FingerModel::Ray {
            return (places, now);
        }
        let contact = self.contact.take();
        let reference = contact.as_ref().map_or(grid, |c| &c.reference);
        for (part, finger) in tips {
            let k = slot(*part);
            let was = self.sides[k];
            (places[k], now[k]) = self.side_press(reference, was.as_ref(), finger);
        }
        self.contact = contact;
        (places, now)
    }

    /// Keeps where every part is now and which side of the clay it is on (`places`, by
    /// [`slot`]), for the next frame's rule 3.
    fn remember(&mut self, tips: &[(Part, Fingertip)], places: &[Place; 6]) {
        let mut sides = [None; 6];
        for (part, finger) in tips {
            let k = slot(*part);
            sides[k] = Some(Side {
                tip: finger.tip,
                body: finger.body,
                place: places[k],
            });
        }
        self.sides = sides;
    }

    /// How a part that is not in the contact yet would start one on `grid` (rule 4): in the
    /// clay (rule 3, `side`), or — with the grip held — the surface just ahead of its tip.
    /// The mouse's ray is measured along the ray, looking `reach` past the tip while
    /// gripping.
    fn joining(
        &mut self,
        grid: &Grid,
        finger: &Fingertip,
        side: Option<Press>,
        grip: bool,
    ) -> Option<Press> {
        if self.options.finger == FingerModel::Ray {
            let ahead = if grip { finger.length } else { 0.0 };
            return self.ray_press(grid, finger, ahead);
        }
        match side {
            Some(p) => Some(p),
            None if grip => self.grip_start(grid, finger),
            None => None,
        }
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
        self.drawn = parts.as_ref().map(|_| Box::new(*frame));
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
        let (clutched, fist) = self.clutch(frame);
        self.fist = fist;
        if clutched && parts.is_some() {
            self.stats.clutched += 1;
        }
        let acting = self.acting(frame).filter(|_| !clutched);
        let Some(((_, tips), grip)) = parts.zip(acting) else {
            // No hand, or the clutch held (rule 10): where the parts were is not known any
            // more (rule 3), nor whether the pinch was open (rule 9).
            self.sides = [None; 6];
            self.pinch_armed = false;
            out.committed = self.close();
            return out;
        };
        self.stats.frames_with_finger += 1;

        // Rule 9: thumb and index together on the clay hold it.
        if self.pinch(&tips, grid, regulation, &mut out) {
            // Nothing presses while the pinch holds the clay; where the parts go is followed
            // on the surface the pinch moves.
            let (mut places, _) = self.sides_now(&tips, grid);
            for place in &mut places {
                if let Place::Far { pressing, .. } = place {
                    *pressing = false;
                }
            }
            self.remember(&tips, &places);
            out.touch = self.touch();
            return out;
        }

        // Rule 3: where every part is, relative to the clay before the contact.
        let (places, now) = self.sides_now(&tips, grid);
        self.remember(&tips, &places);

        let o = self.options;
        let ray = o.finger == FingerModel::Ray;
        if let Some(mut c) = self.contact.take() {
            let mut seen = Fingers(0);
            for &(part, finger) in &tips {
                seen = seen.with(part);
                let (e, axis) = (finger.tip, finger.axis);
                let reach = finger.length;
                let side = now[slot(part)];
                if let Some(k) = c.active(part) {
                    // Rule 5: how far the part is in the clay as it was before the contact.
                    let (held, live) = {
                        let t = &c.tracks[k];
                        (t.grip, t.placements[t.placements.len() - 1].dir)
                    };
                    let p0 = if ray {
                        self.ray_press(&c.reference, &finger, reach)
                    } else if held && grip {
                        // The clay sticks to a gripping part, in the clay or out of it.
                        self.grip_press(&c.reference, e, live, reach)
                    } else {
                        side
                    };
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
                    let press = self.joining(&c.reference, &finger, side, grip);
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
                out.committed = self.close();
            }
        }
        if self.contact.is_none() {
            // Rule 4: a new contact?
            let tracks = self.new_tracks(&tips, grid, grip, &now, &mut out.penetration);
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

    /// Rule 4 for every part of a frame, on `grid` as it is (`now`: rule 3's presses, by
    /// [`slot`]): the tracks of the parts that start a contact (none: no contact starts).
    /// Sets `penetration` to the primary part's depth when it is in the clay (or, gripping,
    /// when the grip finds the surface).
    fn new_tracks(
        &mut self,
        tips: &[(Part, Fingertip)],
        grid: &Grid,
        grip: bool,
        now: &[Option<Press>; 6],
        penetration: &mut Option<f64>,
    ) -> Vec<Track> {
        let primary = Part::Digit(self.options.finger.primary());
        let mut tracks = Vec::new();
        for &(part, finger) in tips {
            let Some(press) = self.joining(grid, &finger, now[slot(part)], grip) else {
                continue;
            };
            if part == primary {
                *penetration = Some(press.depth);
            }
            tracks.extend(self.start(part, &finger, press, grip));
        }
        tracks
    }

    /// Rule 10: whether the clutch holds the hand off the clay in `frame`, and whether the
    /// hand makes a fist (from the fist at the last frame). Changes nothing.
    fn clutch(&self, frame: &HandFrame) -> (bool, bool) {
        let joints = match (self.options.finger, frame.status.glove) {
            (FingerModel::Hand(_), SourceState::Ok) => frame.joints.as_ref(),
            _ => None,
        };
        let fist = clutch::fist(self.fist, joints);
        (fist || clutch::key(frame.buttons), fist)
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
    /// part that starts pressing (rule 4: a part whose tip entered the clay from its hand's
    /// side, by `h` along `m̂`) as a push each ([`super::press::describe`]). `None` when a
    /// contact or a pinch is in progress, the frame has no acting finger, or nothing starts.
    /// The loop itself is not changed. `nendo replay --auto-refine` refines the grid for these
    /// operations before the frame.
    pub fn starting(&mut self, frame: &HandFrame, grid: &Grid) -> Option<Vec<Op>> {
        if self.touch() != Touch::Free {
            return None;
        }
        // The frame as HandLoop::frame will see it (super::filter), the filter untouched.
        let frame = &self.filter.peek(frame);
        let (_, tips) = self.parts_of(frame)?;
        let grip = self.acting(frame).filter(|_| !self.clutch(frame).0)?;
        if let Some((thumb, index)) = pinch_pair(&tips)
            && let Some((at, _)) = self.takes_hold(&thumb, &index, grid)
        {
            return Some(vec![Op::Move {
                at,
                to: at,
                radius: self.options.finger_radius,
            }]);
        }
        let (_, now) = self.sides_now(&tips, grid);
        let tracks = self.new_tracks(&tips, grid, grip, &now, &mut None);
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
