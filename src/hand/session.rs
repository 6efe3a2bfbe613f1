//! The loop of seed 002 §2.1 (Fig. 1): at every device sample, the hand frame → the kinematic
//! hand → contact of the active finger with the surface → push / draw-a-line → Bernstein
//! inverse and regulation.
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
//! 2. **Activation** ([`Activation`]). The glove's finger always acts; its switch
//!    ([`nendo_devices::buttons::PRIMARY`]) is the grip. The mouse finger acts only while a
//!    button is held: the left button presses, the right one grips.
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
//!    (seed 002 §5.1: "M, the virtual finger's movement vector"); whenever the tip moves
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
use nendo_devices::{HandFrame, JointAngles, SourceState, buttons};

use super::HandError;
use super::contact::{Fingertip, Probe};
use super::kinematics::{Digit, Hand, HandPose};

use super::press::{Placement, Presser, Stroke, describe};
use crate::surface::{Grid, Op, Regulation, Sculptor, SurfaceError};

/// A contact shape of the hand: a fingertip capsule, or the palm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Part {
    /// The fingertip capsule of a finger.
    Digit(Digit),
    /// The palm: a wide, short capsule under the palm's centre, along its normal
    /// ([`Hand::palm`]).
    Palm,
}

impl Part {
    /// Every part: the five fingers, thumb to little finger, then the palm.
    pub const ALL: [Part; 6] = [
        Part::Digit(Digit::Thumb),
        Part::Digit(Digit::Index),
        Part::Digit(Digit::Middle),
        Part::Digit(Digit::Ring),
        Part::Digit(Digit::Pinky),
        Part::Palm,
    ];

    /// The part's name on the command line (`thumb` … `pinky`, `palm`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Part::Digit(d) => d.name(),
            Part::Palm => "palm",
        }
    }

    fn bit(self) -> u8 {
        match self {
            Part::Digit(d) => 1 << d.index(),
            Part::Palm => 1 << 5,
        }
    }
}

/// Which parts of the hand press: a set of the five fingers and the palm. Written on the
/// command line as `all` (the five fingers), or a comma-separated list of `thumb`, `index`,
/// `middle`, `ring`, `pinky`, `palm` and `all` (`all,palm`: the whole hand).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Fingers(u8);

impl Fingers {
    /// The five fingers (not the palm).
    pub const ALL: Fingers = Fingers(0b1_1111);

    /// The thumb and the index finger (a pinch).
    pub const THUMB_AND_INDEX: Fingers = Fingers(0b11);

    /// One part alone.
    #[must_use]
    pub fn one(part: Part) -> Self {
        Fingers(part.bit())
    }

    /// This set and `part`.
    #[must_use]
    pub fn with(self, part: Part) -> Self {
        Fingers(self.0 | part.bit())
    }

    /// Whether `part` is in the set.
    #[must_use]
    pub fn contains(self, part: Part) -> bool {
        self.0 & part.bit() != 0
    }

    /// The parts in the set, in [`Part::ALL`]'s order.
    pub fn parts(self) -> impl Iterator<Item = Part> {
        Part::ALL.into_iter().filter(move |p| self.contains(*p))
    }

    /// The finger that stands for the set where one finger is needed (the one drawn as the
    /// fingertip, the one a mouse ray is): the index when it is in the set, else the first
    /// finger; the index for the palm alone.
    #[must_use]
    pub fn primary(self) -> Digit {
        if self.contains(Part::Digit(Digit::Index)) {
            return Digit::Index;
        }
        self.parts()
            .find_map(|p| match p {
                Part::Digit(d) => Some(d),
                Part::Palm => None,
            })
            .unwrap_or(Digit::Index)
    }
}

impl std::str::FromStr for Fingers {
    type Err = crate::surface::UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let unknown = |given: &str| crate::surface::UnknownName {
            kind: "finger",
            given: given.to_owned(),
            expected: "thumb, index, middle, ring, pinky, palm or all (a comma-separated list)",
        };
        let mut set = Fingers(0);
        for name in s.split(',').map(str::trim) {
            set = match name {
                "all" => Fingers(set.0 | Fingers::ALL.0),
                "palm" => set.with(Part::Palm),
                _ => set.with(Part::Digit(
                    name.parse::<Digit>().map_err(|_| unknown(name))?,
                )),
            };
        }
        Ok(set)
    }
}

impl std::fmt::Display for Fingers {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut names = Vec::new();
        if self.0 & Fingers::ALL.0 == Fingers::ALL.0 {
            names.push("all");
        } else {
            names.extend(self.parts().filter(|p| *p != Part::Palm).map(Part::name));
        }
        if self.contains(Part::Palm) {
            names.push("palm");
        }
        f.write_str(&names.join(","))
    }
}

/// Which parts of the hand touch the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FingerModel {
    /// Parts of the kinematic hand (glove + tracker): fingertips (their tip and distal
    /// direction) and the palm.
    Hand(Fingers),
    /// The mouse: the frame's pose is the fingertip on the view ray, pointing along it (the
    /// hand is drawn behind it, its index finger on the ray). A single ray.
    Ray,
}

impl Default for FingerModel {
    /// The index finger alone (the library's one-finger default; a glove profile presses
    /// with every finger, see [`FingerModel::for_profile`]).
    fn default() -> Self {
        FingerModel::Hand(Fingers::one(Part::Digit(Digit::Index)))
    }
}

impl FingerModel {
    /// The finger model for frames recorded with a profile of this name: the view ray for the
    /// `mouse` profile, every finger otherwise.
    #[must_use]
    pub fn for_profile_name(name: Option<&str>) -> Self {
        match name {
            Some("mouse") => FingerModel::Ray,
            _ => FingerModel::Hand(Fingers::ALL),
        }
    }

    /// The finger model of a profile: the view ray for mouse input, every finger otherwise.
    #[must_use]
    pub fn for_profile(profile: &nendo_devices::Profile) -> Self {
        match profile.input {
            nendo_devices::profile::Input::Mouse(_) => FingerModel::Ray,
            _ => FingerModel::Hand(Fingers::ALL),
        }
    }

    /// One finger of the kinematic hand.
    #[must_use]
    pub fn digit(digit: Digit) -> Self {
        FingerModel::Hand(Fingers::one(Part::Digit(digit)))
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

    /// The finger that stands for the model where one is needed ([`Fingers::primary`]; the
    /// index for the mouse's ray).
    #[must_use]
    pub fn primary(self) -> Digit {
        match self {
            FingerModel::Hand(f) => f.primary(),
            FingerModel::Ray => Digit::Index,
        }
    }

    fn parts(self) -> Fingers {
        match self {
            FingerModel::Hand(f) => f,
            FingerModel::Ray => Fingers::one(Part::Digit(Digit::Index)),
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
    /// Thumb and index fingertips closer than this (and on the same side of the clay, near
    /// it) take hold of the clay instead of pressing (rule 9); they let go beyond 1.5 times
    /// it.
    pub pinch_distance: f64,
}

/// The default pinch distance, in sides: 0.4 (2 cm of a hand at the scripted traces' 20 sides
/// per metre).
pub const DEFAULT_PINCH_DISTANCE: f64 = 0.4;

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
            pinch_distance: DEFAULT_PINCH_DISTANCE,
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
            ("pinch distance", self.pinch_distance),
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

/// One part's share of a contact in progress (rules 5–7): its placements, a stroke of the
/// envelope.
#[derive(Debug, Clone)]
struct Track {
    /// The part pressing.
    part: Part,
    /// Its capsule radius (the shape function's finger radius).
    radius: f64,
    /// How far along its axis the surface is searched, and the capsule's length.
    reach: f64,
    /// Whether the clay sticks to it.
    grip: bool,
    /// Every placement so far; the last one is live.
    placements: Vec<Placement>,
    /// The live placement's point on the surface before the contact.
    anchor: DVec3,
    /// The live placement's penetration (the deepest while pressing, the current gripping).
    penetration: f64,
    /// The depth correction of rule 7.
    correction: f64,
    /// Whether the part is still in the clay; a part that left keeps its placements and
    /// takes no more (coming back, it starts a new track).
    active: bool,
    /// The placements changed since the last application.
    dirty: bool,
}

impl Track {
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

/// A contact in progress: every part that pressed the clay since it began, applied together
/// to the surface before it.
#[derive(Debug, Clone)]
struct Contact {
    /// The surface before the contact.
    reference: Grid,
    /// One track per part that touched, in the order they touched.
    tracks: Vec<Track>,
}

impl Contact {
    fn active(&self, part: Part) -> Option<usize> {
        self.tracks.iter().position(|t| t.part == part && t.active)
    }
}

/// A pinch in progress (rule 9): the clay held between thumb and index.
#[derive(Debug, Clone)]
struct Hold {
    /// The surface before the pinch.
    reference: Grid,
    /// The point of the clay taken hold of.
    at: DVec3,
    /// The pinch point (between the two tips) when it took hold.
    start: DVec3,
    /// The target of the last accepted move.
    to: DVec3,
}

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

/// Largest angle between the directions of two placements merged into one segment (2°).
const MERGE_COS: f64 = 0.999_390_827_019_095_8;
/// Largest distance (in finger radii) of a merged placement from the merged segment.
const MERGE_DISTANCE: f64 = 5e-3;
/// Longest merged segment, in finger radii: the live segment is recomputed every frame, so
/// it is kept short (a frame costs what the live segment reaches).
const MERGE_LENGTH: f64 = 0.5;
/// A pinch lets go when the tips are this many times the pinch distance apart (so that a
/// pinch held at the threshold does not flicker).
const PINCH_RELEASE: f64 = 1.5;

/// Frames → contact → operations on a grid (see the module docs).
#[derive(Debug, Clone)]
pub struct HandLoop {
    hand: Hand,
    options: HandOptions,
    probe: Probe,
    presser: Presser,
    sculptor: Sculptor,
    contact: Option<Box<Contact>>,
    hold: Option<Box<Hold>>,
    pose: Option<HandPose>,
    fingertip: Option<Fingertip>,
    tips: Vec<(Part, Fingertip)>,
    stats: LoopStats,
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
            sculptor: Sculptor::new(),
            contact: None,
            hold: None,
            pose: None,
            fingertip: None,
            tips: Vec::new(),
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

    /// Rule 9: where thumb and index, not holding yet, take hold of `grid` — the point of the
    /// clay held and the pinch point — or `None`: their tips closer than the pinch distance on
    /// the same side of the clay, the clay within `r_f` of the pinch point.
    fn takes_hold(
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

    /// Rule 9: starts, follows or ends a pinch; `true` when the frame was a pinch's (nothing
    /// pressed).
    fn pinch(
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
                let mut moved = h.reference.clone();
                let op = Op::Move {
                    at: h.at,
                    to,
                    radius: o.finger_radius,
                };
                // With a mirror, the move and its mirror image as one operation.
                let applied = match self.presser.mirror().filter(|s| s.fits(&moved)) {
                    Some(s) => self.sculptor.apply_mirrored(&mut moved, &op, regulation, s),
                    None => self.sculptor.apply(&mut moved, &op, regulation),
                };
                match applied {
                    Ok(_) => {
                        out.changed = changed_patches(grid, &moved);
                        self.stats.patch_updates += out.changed.len() as u64;
                        *grid = moved;
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
        self.hold = Some(Box::new(Hold {
            reference: grid.clone(),
            at,
            start: mid,
            to: at,
        }));
        true
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

/// Rule 5: the part at `e`, its finger along `finger`, pressing along `axis` (the rule-3
/// direction `m̂`) with penetration `p`, moves the live placement or adds one.
fn extend(o: &HandOptions, c: &mut Track, e: DVec3, finger: DVec3, axis: DVec3, p: f64) {
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

/// The thumb's and the index's capsules among a frame's parts, when both press (rule 9).
fn pinch_pair(tips: &[(Part, Fingertip)]) -> Option<(Fingertip, Fingertip)> {
    let find = |d: Digit| tips.iter().find(|(p, _)| *p == Part::Digit(d)).map(|t| t.1);
    Some((find(Digit::Thumb)?, find(Digit::Index)?))
}

/// The patches whose control points differ between two grids of the same size (sorted).
fn changed_patches(before: &Grid, after: &Grid) -> Vec<usize> {
    let (m, n) = (after.patches_u(), after.patches_v());
    if before.nodes().len() != after.nodes().len() {
        return (0..m * n).collect();
    }
    (0..m * n)
        .filter(|&p| {
            after
                .patch_node_ids(p % m, p / m)
                .iter()
                .any(|&id| before.nodes()[id] != after.nodes()[id])
        })
        .collect()
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
    #[test]
    fn thumb_and_index_is_the_pinch_pair() {
        assert_eq!(Fingers::THUMB_AND_INDEX.to_string(), "thumb,index");
        assert_eq!(
            "thumb,index".parse::<super::Fingers>().ok(),
            Some(Fingers::THUMB_AND_INDEX)
        );
    }

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
