//! The loop of seed 002 §2.1 (Fig. 1): at every device sample, the hand frame → the kinematic
//! hand → contact of the active finger with the surface → push / draw-a-line → Bernstein
//! inverse and regulation.
//!
//! ## Contact semantics
//!
//! Let `E` be the fingertip point of the active finger, `d̂` its direction (the distal
//! segment's, or the view ray's for the mouse), `r_f` the finger radius ([`Fingertip`]), and
//! `ℓ = max(finger length, 2·r_f)` the reach searched along the finger.
//!
//! 1. **Finger.** A frame whose tracker is not `ok`, or without a pose, has no finger; nor has
//!    a frame whose glove is silent or lost, or `ok` without joint angles; without a glove in
//!    the profile (`none`) the hand is flat. Values a frame carries for a source that is not
//!    `ok` are never used. No finger: the contact ends.
//! 2. **Activation** ([`Activation`]). The glove's finger always acts; its switch
//!    ([`nendo_devices::buttons::PRIMARY`]) is the grip. The mouse finger acts only while a
//!    button is held: the left button presses, the right one grips.
//! 3. **Penetration.** The [`Probe`] finds the first crossing `S` of the finger's axis, from
//!    `E − ℓ·d̂` to `E` (to `E + ℓ·d̂` while gripping), with a surface; the signed penetration is
//!    `p = (E − S)·d̂` (positive: the tip is past the surface).
//! 4. **A contact starts** when, on the surface as it is, `p > min_depth` (pressing) — or,
//!    with the grip held, `p ≥ −grip_distance` (the tip touching, or within a hair): the clay
//!    sticks to it.
//! 5. **During a contact** `p` is measured on the surface *as it was before the contact* (kept
//!    aside): how far the finger is in the clay. The contact is a list of placements
//!    ([`Placement`]): the first a push at `S` with `M = p·d̂` (seed 002 §5.1: "M, the virtual
//!    finger's movement vector"); whenever the tip moves across `d̂` by more than
//!    `stroke_step`, a new placement at the new tip, joined to the previous one by a
//!    draw-a-line segment (§5.2) of its own `L_f = p·d̂`. Pressing, the latest placement keeps
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
//!    (pressing: `p ≤ 0`; gripping: the grip released and `p ≤ 0`, or no surface within
//!    reach), or the finger disappears or stops acting. Its result is then the surface the next
//!    contact starts from. A contact is one operation in the paper's sense (its Fig. 15 pot
//!    took 152).
//!
//! Everything runs in a fixed order on `f64`: the outcome is a pure function of the frames,
//! the starting grid and the options.

use glam::DVec3;
use nendo_devices::{HandFrame, JointAngles, SourceState, buttons};

use super::HandError;
use super::contact::{Fingertip, Probe};
use super::kinematics::{Digit, Hand, HandPose};
use super::press::{Placement, Presser, describe};
use crate::surface::{Grid, Op, Regulation, SurfaceError};

/// Which finger touches the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FingerModel {
    /// A finger of the kinematic hand (glove + tracker): its fingertip and distal direction.
    Hand(Digit),
    /// The mouse: the frame's pose is the fingertip on the view ray, pointing along it (the
    /// hand is drawn behind it, its index finger on the ray).
    Ray,
}

impl Default for FingerModel {
    fn default() -> Self {
        FingerModel::Hand(Digit::Index)
    }
}

impl FingerModel {
    /// The finger model for frames recorded with a profile of this name: the view ray for the
    /// `mouse` profile, the index finger otherwise.
    #[must_use]
    pub fn for_profile_name(name: Option<&str>) -> Self {
        match name {
            Some("mouse") => FingerModel::Ray,
            _ => FingerModel::default(),
        }
    }

    /// The finger model of a profile: the view ray for mouse input, the index finger
    /// otherwise.
    #[must_use]
    pub fn for_profile(profile: &nendo_devices::Profile) -> Self {
        match profile.input {
            nendo_devices::profile::Input::Mouse(_) => FingerModel::Ray,
            _ => FingerModel::default(),
        }
    }

    /// How buttons act for this finger.
    #[must_use]
    pub fn activation(self) -> Activation {
        match self {
            FingerModel::Hand(_) => Activation {
                press: 0,
                grip: buttons::PRIMARY,
            },
            FingerModel::Ray => Activation {
                press: buttons::PRIMARY | buttons::SECONDARY,
                grip: buttons::SECONDARY,
            },
        }
    }

    fn digit(self) -> Digit {
        match self {
            FingerModel::Hand(d) => d,
            FingerModel::Ray => Digit::Index,
        }
    }
}

/// Which buttons make the finger act and grip.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Activation {
    /// The finger acts only while one of these buttons is held; `0`: always.
    pub press: u32,
    /// While one of these is held the clay sticks to the finger (pull, ridge).
    pub grip: u32,
}

/// The loop's settings (lengths in world units, "side").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandOptions {
    /// The finger radius `r_f`: the fingertip capsule's radius and the shape function's.
    pub finger_radius: f64,
    /// Which finger touches.
    pub finger: FingerModel,
    /// A contact starts when the tip is this far past the surface; depth changes at or below
    /// it are not applied.
    pub min_depth: f64,
    /// Motion across the finger above this, while in contact, adds a placement: the contact
    /// becomes a draw-a-line stroke.
    pub stroke_step: f64,
    /// How close to the surface the tip must be for the grip to catch.
    pub grip_distance: f64,
}

/// The default finger radius `r_f`, in sides: the hand loop's in the window and in
/// `nendo replay` alike, so a trace gives the same surface in both (the shipped traces and
/// their figures are made with it).
pub const DEFAULT_FINGER_RADIUS: f64 = 1.0;

impl Default for HandOptions {
    fn default() -> Self {
        Self {
            finger_radius: DEFAULT_FINGER_RADIUS,
            finger: FingerModel::default(),
            min_depth: 1e-4,
            stroke_step: 5e-3,
            grip_distance: 0.05,
        }
    }
}

impl HandOptions {
    /// Checks every number.
    ///
    /// # Errors
    /// [`HandError::Options`] naming the first bad value.
    pub fn validate(&self) -> Result<(), HandError> {
        for (name, value) in [
            ("finger radius", self.finger_radius),
            ("grip distance", self.grip_distance),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(HandError::Options(format!(
                    "{name} must be a positive number, not {value}"
                )));
            }
        }
        for (name, value) in [
            ("min depth", self.min_depth),
            ("stroke step", self.stroke_step),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(HandError::Options(format!(
                    "{name} must be a non-negative number, not {value}"
                )));
            }
        }
        Ok(())
    }
}

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
}

/// What one frame did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameOutcome {
    /// The finger's state after the frame.
    pub touch: Touch,
    /// The signed penetration `p` of the fingertip (rule 3), when a surface was found.
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
}

impl LoopStats {
    /// Contacts ended (pushes, pulls and strokes): operations in the paper's sense.
    #[must_use]
    pub fn operations(&self) -> u64 {
        self.pushes + self.pulls + self.strokes
    }
}

/// A contact in progress (rules 5–7).
#[derive(Debug, Clone)]
struct Contact {
    /// The surface before the contact.
    reference: Grid,
    /// Whether the clay sticks to the finger.
    grip: bool,
    /// Every placement so far; the last one is live.
    placements: Vec<Placement>,
    /// The live placement's point on the surface before the contact.
    anchor: DVec3,
    /// The live placement's penetration (the deepest while pressing, the current gripping).
    penetration: f64,
    /// The depth correction of rule 7.
    correction: f64,
    /// The placements changed since the last application.
    dirty: bool,
}

impl Contact {
    fn live(&mut self) -> &mut Placement {
        let last = self.placements.len() - 1;
        &mut self.placements[last]
    }

    /// Sets the live placement's depth from its penetration and the correction (pressing,
    /// never below zero: a press does not pull).
    fn update_live(&mut self, min_depth: f64) {
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

/// Largest angle between the directions of two placements merged into one segment (2°).
const MERGE_COS: f64 = 0.999_390_827_019_095_8;
/// Largest distance (in finger radii) of a merged placement from the merged segment.
const MERGE_DISTANCE: f64 = 5e-3;
/// Longest merged segment, in finger radii: the live segment is recomputed every frame, so
/// it is kept short (a frame costs what the live segment reaches).
const MERGE_LENGTH: f64 = 0.5;

/// Frames → contact → operations on a grid (see the module docs).
#[derive(Debug, Clone)]
pub struct HandLoop {
    hand: Hand,
    options: HandOptions,
    probe: Probe,
    presser: Presser,
    contact: Option<Box<Contact>>,
    pose: Option<HandPose>,
    fingertip: Option<Fingertip>,
    stats: LoopStats,
}

impl HandLoop {
    /// Presses every contact together with its mirror image (see
    /// [`crate::surface::Presser::set_mirror`]); `None`: no mirror.
    pub fn set_mirror(&mut self, symmetry: Option<crate::surface::Symmetry>) {
        self.presser.set_mirror(symmetry);
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
            contact: None,
            pose: None,
            fingertip: None,
            stats: LoopStats::default(),
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

    /// The active fingertip at the last frame that had one.
    #[must_use]
    pub fn fingertip(&self) -> Option<&Fingertip> {
        self.fingertip.as_ref()
    }

    /// The finger's state.
    #[must_use]
    pub fn touch(&self) -> Touch {
        match &self.contact {
            None => Touch::Free,
            Some(c) if c.grip => Touch::Gripping,
            Some(_) => Touch::Pressing,
        }
    }

    /// The counters.
    #[must_use]
    pub fn stats(&self) -> &LoopStats {
        &self.stats
    }

    /// The placements of the contact in progress.
    #[must_use]
    pub fn placements(&self) -> &[Placement] {
        self.contact.as_ref().map_or(&[], |c| &c.placements)
    }

    /// How far along the finger the surface is searched: `max(finger length, 2·r_f)`.
    #[must_use]
    pub fn reach(&self) -> f64 {
        self.hand
            .finger_length(self.options.finger.digit())
            .max(2.0 * self.options.finger_radius)
    }

    /// Ends the contact in progress, keeping what it did; returns the operations it stands
    /// for. Call it before the grid is changed by anything else (an undo, a mouse tool): a
    /// contact recomputes the patches it touches from the surface before it.
    pub fn end_contact(&mut self) -> Option<Vec<Op>> {
        let c = self.contact.take()?;
        let ops = describe(&c.placements, self.options.finger_radius);
        match (c.placements.len(), c.placements[0].depth > 0.0) {
            (1, true) => self.stats.pushes += 1,
            (1, false) => self.stats.pulls += 1,
            _ => self.stats.strokes += 1,
        }
        self.stats.placements += c.placements.len() as u64;
        Some(ops)
    }

    /// The hand and active fingertip of a frame, if it has them (rule 1 of the module docs).
    #[must_use]
    pub fn finger_of(&self, frame: &HandFrame) -> Option<(HandPose, Fingertip)> {
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
        let digit = self.options.finger.digit();
        let placed = match self.options.finger {
            FingerModel::Hand(_) => self.hand.pose(&pose, joints),
            FingerModel::Ray => self.hand.pose_at_fingertip(&pose, joints, digit),
        };
        let chain = placed.finger(digit);
        let tip = Fingertip {
            tip: chain.tip(),
            axis: chain.direction(),
            base: chain.points[2],
            radius: self.options.finger_radius,
            length: self.reach(),
        };
        (tip.tip.is_finite() && tip.axis.is_finite()).then_some((placed, tip))
    }

    /// Signed penetration of a fingertip into `grid` along its axis (rule 3): `ahead` is how
    /// far past the tip the surface may be.
    fn penetration(&mut self, grid: &Grid, tip: DVec3, axis: DVec3, ahead: f64) -> Option<f64> {
        let reach = self.reach();
        let hit = self
            .probe
            .first_crossing(grid, tip - reach * axis, axis, reach + ahead)?;
        Some(reach - hit.t)
    }

    /// Feeds one frame: finds the contact and deforms `grid` by it.
    pub fn frame(
        &mut self,
        frame: &HandFrame,
        grid: &mut Grid,
        regulation: Regulation,
    ) -> FrameOutcome {
        self.stats.frames += 1;
        let mut out = FrameOutcome::default();
        let finger = self.finger_of(frame);
        self.pose = finger.map(|(p, _)| p);
        self.fingertip = finger.map(|(_, f)| f);
        let act = self.options.finger.activation();
        let Some((_, finger)) = finger.filter(|_| act.press == 0 || frame.buttons & act.press != 0)
        else {
            out.committed = self.end_contact();
            return out;
        };
        self.stats.frames_with_finger += 1;
        let grip = frame.buttons & act.grip != 0;
        let (e, axis) = (finger.tip, finger.axis);
        let o = self.options;
        let reach = self.reach();

        if let Some(mut c) = self.contact.take() {
            // Rule 5: how far the finger is in the clay as it was before the contact.
            let p0 = self.penetration(&c.reference, e, axis, reach);
            if c.grip && !grip {
                c.grip = false;
            } else if !c.grip && grip && p0.is_some_and(|p| p >= -o.grip_distance) {
                c.grip = true;
            }
            out.penetration = p0;
            match p0 {
                Some(p) if c.grip || p > 0.0 => {
                    self.extend(&mut c, e, axis, p);
                    self.contact = Some(c);
                }
                _ => {
                    // Rule 8: the finger is out of the clay.
                    self.contact = Some(c);
                    out.committed = self.end_contact();
                }
            }
        }
        if self.contact.is_none() {
            // Rule 4: a new contact?
            let ahead = if grip { reach } else { 0.0 };
            let Some(p) = self.penetration(grid, e, axis, ahead) else {
                return out;
            };
            out.penetration = Some(p);
            let starts = if grip {
                p >= -o.grip_distance
            } else {
                p > o.min_depth
            };
            if !starts {
                return out;
            }
            self.stats.contacts += 1;
            self.presser.begin(grid);
            let anchor = e - p * axis;
            self.contact = Some(Box::new(Contact {
                reference: grid.clone(),
                grip,
                placements: vec![Placement {
                    tip: e,
                    dir: axis,
                    depth: p,
                }],
                anchor,
                penetration: p,
                correction: 0.0,
                dirty: true,
            }));
        }
        self.apply(grid, regulation, &mut out);
        out.touch = self.touch();
        out
    }

    /// Rule 5: the finger at `e` with penetration `p` moves the live placement or adds one.
    fn extend(&self, c: &mut Contact, e: DVec3, axis: DVec3, p: f64) {
        let o = self.options;
        let live = *c.live();
        // How far the fingertip moved across the finger since the live placement.
        let target = c.anchor + c.penetration * live.dir;
        let across = (e - target) - (e - target).dot(live.dir) * live.dir;
        if across.length() > o.stroke_step {
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
                if mergeable(&prev, &live, &next, o.finger_radius) {
                    c.placements.pop();
                }
            }
            c.placements.push(next);
            c.anchor = anchor;
            c.penetration = p;
            c.dirty = true;
        } else if c.grip {
            c.penetration = p;
        } else {
            c.penetration = c.penetration.max(p);
        }
        c.update_live(o.min_depth);
    }

    /// Applies the contact's placements if they changed, then measures the clay at the live
    /// fingertip for the correction of rule 7.
    fn apply(&mut self, grid: &mut Grid, regulation: Regulation, out: &mut FrameOutcome) {
        let Some(mut c) = self.contact.take() else {
            return;
        };
        let o = self.options;
        if c.dirty {
            c.dirty = false;
            self.stats.applications += 1;
            let length = self.reach();
            match self.presser.apply(
                &c.reference,
                grid,
                &c.placements,
                o.finger_radius,
                length,
                regulation,
            ) {
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
            // Rule 7: where is the clay along the live placement's axis, at the fingertip?
            let dir = c.live().dir;
            let target = c.anchor + c.penetration * dir;
            let reach = self.reach();
            // Only a lone push or pull is corrected: along a stroke the clay at the live
            // fingertip is also shaped by the earlier placements, so a miss there does not
            // measure the live one.
            let miss = self.penetration(grid, target, dir, reach);
            if let Some(miss) = miss.filter(|_| c.placements.len() == 1) {
                let limit = 2.0 * o.finger_radius;
                c.correction = (c.correction + miss).clamp(-limit, limit);
                c.update_live(o.min_depth);
            }
        }
        self.contact = Some(c);
    }
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

/// A [`HandLoop`] with its own grid and regulation: `nendo replay`, tests, benches.
#[derive(Debug, Clone)]
pub struct Session {
    grid: Grid,
    regulation: Regulation,
    hand_loop: HandLoop,
    log: Option<Vec<Vec<Op>>>,
}

impl Session {
    /// A session sculpting `grid`.
    ///
    /// # Errors
    /// [`HandError::Options`] for bad options.
    pub fn new(
        grid: Grid,
        regulation: Regulation,
        hand: Hand,
        options: HandOptions,
    ) -> Result<Self, HandError> {
        Ok(Self {
            grid,
            regulation,
            hand_loop: HandLoop::new(hand, options)?,
            log: None,
        })
    }

    /// Keeps the operations of every contact (see [`Session::contacts`]).
    #[must_use]
    pub fn logging_contacts(mut self) -> Self {
        self.log = Some(Vec::new());
        self
    }

    /// Feeds one frame.
    pub fn feed(&mut self, frame: &HandFrame) -> FrameOutcome {
        let out = self.hand_loop.frame(frame, &mut self.grid, self.regulation);
        if let (Some(log), Some(ops)) = (&mut self.log, &out.committed) {
            log.push(ops.clone());
        }
        out
    }

    /// Ends a contact still in progress (the end of a trace).
    pub fn finish(&mut self) {
        if let Some(ops) = self.hand_loop.end_contact()
            && let Some(log) = &mut self.log
        {
            log.push(ops);
        }
    }

    /// The surface now.
    #[must_use]
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The surface, taking the session apart (a contact in progress is kept as it is).
    #[must_use]
    pub fn into_grid(self) -> Grid {
        self.grid
    }

    /// The regulation method.
    #[must_use]
    pub fn regulation(&self) -> Regulation {
        self.regulation
    }

    /// Presses every contact together with its mirror image ([`HandLoop::set_mirror`]).
    pub fn set_mirror(&mut self, symmetry: Option<crate::surface::Symmetry>) {
        self.hand_loop.set_mirror(symmetry);
    }

    /// The loop (pose, fingertip, touch, counters).
    #[must_use]
    pub fn hand_loop(&self) -> &HandLoop {
        &self.hand_loop
    }

    /// The operations of every ended contact, when logging ([`Session::logging_contacts`]).
    #[must_use]
    pub fn contacts(&self) -> Option<&[Vec<Op>]> {
        self.log.as_deref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hand::script::Choreography;
    use crate::surface::{Primitive, PrimitiveParams};
    use nendo_devices::{HandSize, WorldFromTracker};

    fn plane_session(regulation: Regulation) -> Session {
        let grid = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
        let hand = Hand::new(HandSize::default(), Choreography::WORLD).unwrap();
        Session::new(grid, regulation, hand, HandOptions::default()).unwrap()
    }

    fn z_at(grid: &Grid, x: f64, y: f64) -> f64 {
        let mut probe = Probe::new();
        probe
            .first_crossing(grid, DVec3::new(x, y, 10.0), -DVec3::Z, 20.0)
            .unwrap()
            .point
            .z
    }

    #[test]
    fn a_press_meets_the_fingertip_and_stops_when_the_finger_stops() {
        let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
        let down = -DVec3::Z;
        c.place(DVec3::new(0.5, 0.5, 0.5), down, DVec3::Y);
        c.move_to(DVec3::new(0.5, 0.5, -0.3), down, 24);
        c.hold(36);
        c.move_to(DVec3::new(0.5, 0.5, 0.5), down, 24);
        let trace = c.finish("test").unwrap();
        for regulation in Regulation::ALL {
            let mut s = plane_session(regulation);
            let mut last_change = 0;
            let mut committed = Vec::new();
            for (k, f) in trace.frames.iter().enumerate() {
                let out = s.feed(f);
                if !out.changed.is_empty() {
                    last_change = k;
                }
                if k == 59 {
                    let z = z_at(s.grid(), 0.5, 0.5);
                    assert!(
                        (z + 0.3).abs() < 2e-3,
                        "{regulation}: the clay meets the fingertip: {z}"
                    );
                }
                committed.extend(out.committed);
            }
            assert!(
                last_change < 55,
                "{regulation}: a finger held still stops deforming"
            );
            let st = s.hand_loop().stats();
            assert_eq!(
                (st.contacts, st.pushes, st.strokes, st.pulls),
                (1, 1, 0, 0),
                "{regulation}"
            );
            assert_eq!(committed.len(), 1);
            assert!(matches!(committed[0][..], [Op::Push { .. }]));
            // Withdrawing leaves the dent; far away nothing moved.
            assert!((z_at(s.grid(), 0.5, 0.5) + 0.3).abs() < 2e-3);
            assert_eq!(z_at(s.grid(), 4.0, 4.0), 0.0);
        }
    }

    #[test]
    fn a_stroke_cuts_a_groove_as_deep_as_the_finger_not_deeper() {
        let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
        let down = -DVec3::Z;
        c.place(DVec3::new(-3.0, 0.5, 0.3), down, DVec3::X);
        c.move_to(DVec3::new(-3.0, 0.5, -0.25), down, 20);
        c.move_to(DVec3::new(3.0, 0.5, -0.25), down, 300);
        c.move_to(DVec3::new(3.0, 0.5, 0.3), down, 20);
        let trace = c.finish("test").unwrap();
        let mut s = plane_session(Regulation::default());
        for f in &trace.frames {
            s.feed(f);
        }
        let st = *s.hand_loop().stats();
        assert_eq!((st.contacts, st.strokes), (1, 1), "{st:?}");
        assert!(st.placements < 100, "straight runs merge: {st:?}");
        for x in [-2.0, -1.0, 0.0, 1.0, 2.0] {
            let z = z_at(s.grid(), x, 0.5);
            assert!((z + 0.25).abs() < 0.02, "x = {x}: {z}");
        }
    }

    #[test]
    fn no_pose_or_a_silent_glove_means_no_finger() {
        let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
        c.place(DVec3::new(0.0, 0.0, -0.2), -DVec3::Z, DVec3::Y);
        c.hold(1);
        let mut frame = c.finish("test").unwrap().frames[0];
        let mut s = plane_session(Regulation::default());
        let mut lost = frame;
        lost.pose = None;
        assert_eq!(s.feed(&lost).touch, Touch::Free);
        let mut silent = frame;
        silent.joints = None;
        silent.status.glove = SourceState::Silent;
        assert!(s.feed(&silent).changed.is_empty());
        assert_eq!(s.grid(), plane_session(Regulation::default()).grid());
        frame.time.0 += 1;
        let out = s.feed(&frame);
        assert!(!out.changed.is_empty());
        assert_eq!(out.touch, Touch::Pressing);
        assert_eq!(s.hand_loop().stats().frames_with_finger, 1);
        // The glove going silent mid-contact ends the contact.
        assert!(s.feed(&silent).committed.is_some());
    }

    #[test]
    fn values_of_a_source_that_is_not_ok_never_act() {
        let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
        c.place(DVec3::new(0.0, 0.0, -0.2), -DVec3::Z, DVec3::Y);
        c.hold(1);
        let frame = c.finish("test").unwrap().frames[0];
        let untouched = plane_session(Regulation::default());
        // The pressing frame with its pose and angles kept, but a source not delivering.
        let mut stale = Vec::new();
        for state in [
            SourceState::Silent,
            SourceState::Disconnected,
            SourceState::Absent,
        ] {
            let mut f = frame;
            f.status.tracker = state;
            stale.push(f);
        }
        for state in [SourceState::Silent, SourceState::Disconnected] {
            let mut f = frame;
            f.status.glove = state;
            stale.push(f);
        }
        for f in &stale {
            let mut s = plane_session(Regulation::default());
            assert!(s.hand_loop().finger_of(f).is_none(), "{:?}", f.status);
            let out = s.feed(f);
            assert_eq!(out.touch, Touch::Free, "{:?}", f.status);
            assert!(out.changed.is_empty(), "{:?}", f.status);
            assert_eq!(s.grid(), untouched.grid());
        }
        // The same frame from delivering sources presses.
        let mut s = plane_session(Regulation::default());
        assert_eq!(s.feed(&frame).touch, Touch::Pressing);
    }

    #[test]
    fn bad_options_are_refused() {
        let hand = Hand::new(HandSize::default(), WorldFromTracker::default()).unwrap();
        for o in [
            HandOptions {
                finger_radius: 0.0,
                ..HandOptions::default()
            },
            HandOptions {
                min_depth: f64::NAN,
                ..HandOptions::default()
            },
            HandOptions {
                grip_distance: -1.0,
                ..HandOptions::default()
            },
        ] {
            assert!(HandLoop::new(hand, o).is_err(), "{o:?}");
        }
    }
}
