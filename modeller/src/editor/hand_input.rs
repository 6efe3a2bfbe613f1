//! The virtual hand in the window: device frames (a glove and tracker, a replayed trace, or the
//! mouse through [`crate::hand::MouseFinger`]) run through [`crate::hand::HandLoop`] against
//! the document's surface, and the hand is drawn with its fingers.
//!
//! A contact (from the first frame that deforms the surface to the frame the finger leaves it)
//! is one undoable edit, and its operations go into the document's recording. Before anything
//! else edits the surface (a mouse tool, undo, opening a file), [`HandDriver::end_contact`]
//! closes the contact in progress, as the hand loop requires.
//!
//! **Symmetry.** With the window's symmetry on, the mouse hand presses every contact together
//! with its images under the window's whole group — the mirrors, the radial turns, the lathe's
//! continuous turns, as the mouse tools' strokes — as one operation ([`HandDriver::set_mirror`]): the
//! hand loop's envelope takes in the mirrored fingers, and the touched control points and their
//! partners are made exactly symmetric after the regulation
//! ([`crate::surface::Presser::set_mirror`]); a pinch moves the clay with its mirror image
//! ([`crate::surface::Sculptor::apply_mirrored`]). The mirror is taken up only between
//! contacts: a contact keeps the mirror map it began with. A device session's hand (a glove and
//! tracker, a skeleton source such as VMC) presses with the window's group the same way,
//! taken up between contacts — except while it records, when it keeps the group it started
//! with (named in its trace's scene) until the recording stops; a replayed trace presses with
//! its scene's group, whatever the window's toggle says. Both so that `nendo replay` gives the
//! window's surface bit for bit (`editor::live` `symmetry` module docs).

use glam::DVec3;
use nendo_devices::profile::MouseProfile;
use nendo_devices::skeleton::{HandJoint, JointSource};
use nendo_devices::{HandFrame, HandSize, Timestamp, ViewRay, WorldFromTracker, buttons};
use std::time::Instant;

use super::document::Document;
use crate::hand::{FingerModel, Hand, HandError, HandLoop, HandOptions, MouseFinger, Touch};
use crate::mesh::Ray;
use crate::model::Model;
use crate::render::{LineBatch, Rgba, SphereInstance};
use crate::surface::{Patch, SurfaceError, Symmetry};

/// Samples per patch side the contact feedback measures the clay's displacement on.
const FEEDBACK_SAMPLES: usize = 9;

/// A patch whose clay moved by at least this fraction of the contact's largest displacement
/// is in the touched region.
const FEEDBACK_REGION: f64 = 0.1;

/// The touched region's colour.
const TOUCHED: Rgba = Rgba([1.0, 0.45, 0.1, 0.95]);

/// The contact in progress as the window shows it: where the clay moved and by how much,
/// measured on the surface itself — each changed patch sampled on a
/// [`FEEDBACK_SAMPLES`]² grid of parameters, `δ = max |S(u,v) − S₀(u,v)|` against the
/// surface before the contact `S₀` — and the part deepest in the clay.
#[derive(Debug, Clone, Default)]
pub struct Feedback {
    /// The surface before the contact.
    reference: Option<crate::surface::Grid>,
    /// Every patch the contact changed, with its largest displacement and where (on the
    /// surface now).
    moved: std::collections::BTreeMap<usize, (f64, DVec3)>,
    /// Patches changed since the last measure.
    pending: Vec<usize>,
    /// The touched region's iso-parameter lines, for drawing.
    lines: Vec<Vec<glam::Vec3>>,
    /// The part deepest in the clay and its depth (`h` of the hand loop's rule 3).
    pub deepest: Option<(crate::hand::Part, f64)>,
}

impl Feedback {
    /// The largest displacement of the clay since the contact began, and where it is.
    #[must_use]
    pub fn moved(&self) -> Option<(f64, DVec3)> {
        self.moved
            .values()
            .copied()
            .max_by(|a, b| a.0.total_cmp(&b.0))
    }

    /// The patches of the touched region: moved by at least a tenth of the largest
    /// displacement ([`FEEDBACK_REGION`]), in index order.
    #[must_use]
    pub fn region(&self) -> Vec<usize> {
        let most = self.moved().map_or(0.0, |m| m.0);
        self.moved
            .iter()
            .filter(|(_, (d, _))| most > 0.0 && *d >= FEEDBACK_REGION * most)
            .map(|(k, _)| *k)
            .collect()
    }

    /// The status line's words: `index 0.31 in · clay moved 0.30 over 6 patches`.
    #[must_use]
    pub fn describe(&self) -> String {
        let part = match self.deepest {
            Some((part, h)) if h >= 0.0 => format!("{} {h:.3} in", part.name()),
            Some((part, h)) => format!("{} {:.3} out (gripping)", part.name(), -h),
            None => "holding".into(),
        };
        let moved = self.moved().map_or(0.0, |m| m.0);
        format!(
            "{part} · clay moved {moved:.3} over {} patches",
            self.region().len()
        )
    }

    /// Measures the patches changed since the last call on `grid` (the surface now) and
    /// rebuilds the region's lines.
    fn measure(&mut self, grid: &crate::surface::Grid) {
        let Some(reference) = &self.reference else {
            return;
        };
        if reference.patch_count() != grid.patch_count() {
            self.pending.clear();
            return;
        }
        self.pending.sort_unstable();
        self.pending.dedup();
        let k = FEEDBACK_SAMPLES;
        let at = |i: usize| i as f64 / (k - 1) as f64;
        for &p in &self.pending {
            let (now, before) = (
                Patch::new(grid.patch_at(p)),
                Patch::new(reference.patch_at(p)),
            );
            let mut most = (0.0, now.eval(0.5, 0.5));
            for s in 0..k * k {
                let (u, v) = (at(s / k), at(s % k));
                let x = now.eval(u, v);
                let d = (x - before.eval(u, v)).length();
                if d > most.0 {
                    most = (d, x);
                }
            }
            self.moved.insert(p, most);
        }
        self.pending.clear();
        self.lines.clear();
        for p in self.region() {
            let patch = Patch::new(grid.patch_at(p));
            for i in [0, k / 2, k - 1] {
                self.lines
                    .push((0..k).map(|j| patch.eval(at(i), at(j)).as_vec3()).collect());
                self.lines
                    .push((0..k).map(|j| patch.eval(at(j), at(i)).as_vec3()).collect());
            }
        }
    }

    fn draw(&self, lines: &mut LineBatch, spheres: &mut Vec<SphereInstance>, radius: f64) {
        for l in &self.lines {
            lines.polyline(l.iter().copied(), TOUCHED);
        }
        if let Some((d, x)) = self.moved()
            && d > 0.0
        {
            spheres.push(SphereInstance {
                center: x.as_vec3().to_array(),
                radius: (0.08 * radius) as f32,
                colour: TOUCHED.0,
            });
        }
    }
}

/// A hand loop feeding a document.
#[derive(Debug, Clone)]
pub struct HandDriver {
    hand_loop: HandLoop,
    /// The model before the contact in progress, until the contact first changes it.
    before: Option<Model>,
    /// The contact in progress has been recorded for undo.
    recorded: bool,
    /// Why the surface last refused a frame's placements (the status line shows it).
    refused: Option<SurfaceError>,
    /// Contacts that changed the surface (one undoable edit each).
    contacts: u64,
    /// The contact in progress as the window shows it.
    feedback: Option<Feedback>,
}

impl HandDriver {
    /// A driver for a hand of `size` placed by `world_from_tracker`, touching with `finger`,
    /// finger radius `radius`.
    ///
    /// # Errors
    /// [`HandError`] for a hand or radius the loop refuses.
    pub fn new(
        size: HandSize,
        world_from_tracker: WorldFromTracker,
        finger: FingerModel,
        radius: f64,
    ) -> Result<Self, HandError> {
        let options = HandOptions {
            finger_radius: radius,
            finger,
            ..HandOptions::default()
        };
        let hand_loop = HandLoop::new(Hand::new(size, world_from_tracker)?, options)?;
        Ok(Self {
            hand_loop,
            before: None,
            recorded: false,
            refused: None,
            contacts: 0,
            feedback: None,
        })
    }

    /// The same driver with its contact count starting at `contacts` (a hand rebuilt after an
    /// alignment change keeps counting).
    #[must_use]
    pub fn with_contacts(mut self, contacts: u64) -> Self {
        self.contacts = contacts;
        self
    }

    /// Contacts that have changed the surface so far.
    #[must_use]
    pub fn contacts(&self) -> u64 {
        self.contacts
    }

    /// The loop (pose, fingertip, counters).
    #[must_use]
    pub fn hand_loop(&self) -> &HandLoop {
        &self.hand_loop
    }

    /// Gates and filters the frames from now on with `settings` ([`HandLoop::set_filter`]):
    /// a device session's profile's, a replayed trace's scene's.
    #[must_use]
    pub fn with_filter(mut self, settings: nendo_devices::FilterSettings) -> Self {
        self.hand_loop.set_filter(settings);
        self
    }

    /// Presses the next contacts together with their mirror images (`None`: one-sided). Taken
    /// up only between contacts: a contact in progress keeps the mirror it began with.
    pub fn set_mirror(&mut self, mirror: Option<&Symmetry>) {
        if self.hand_loop.touch() == Touch::Free && self.hand_loop.mirror() != mirror {
            self.hand_loop.set_mirror(mirror.cloned());
        }
    }

    /// Feeds one frame: the hand moves, and deforms the document's surface where it touches.
    pub fn feed(&mut self, doc: &mut Document, frame: &HandFrame) {
        if self.hand_loop.touch() == Touch::Free {
            self.before = Some(doc.model().clone());
            self.recorded = false;
        }
        let hand_loop = &mut self.hand_loop;
        // The loop says which patches it changed: the display re-tessellates only those.
        let outcome = doc.sculpt_patches(|grid, regulation| {
            let out = hand_loop.frame(frame, grid, regulation);
            let changed = out.changed.clone();
            (out, changed)
        });
        if !outcome.changed.is_empty() && !self.recorded {
            if let Some(before) = self.before.take() {
                self.feedback = Some(Feedback {
                    reference: Some(before.surface.clone()),
                    ..Feedback::default()
                });
                doc.record_undo("hand", before);
            }
            self.recorded = true;
            self.contacts += 1;
        }
        if let Some(f) = &mut self.feedback {
            f.pending.extend_from_slice(&outcome.changed);
        }
        if self.hand_loop.touch() == Touch::Free {
            self.feedback = None;
        }
        if let Some(ops) = outcome.committed {
            doc.record_ops(&ops);
        }
        if let Some(e) = outcome.refused {
            self.refused = Some(e);
        }
    }

    /// Measures the contact's feedback on `doc`'s surface as it is now (once per window frame,
    /// after the frames are fed: [`HandDriver::feed`] only notes the changed patches).
    pub fn measure(&mut self, doc: &Document) {
        let deepest = self.hand_loop.deepest();
        if let Some(f) = &mut self.feedback {
            f.deepest = deepest;
            f.measure(&doc.model().surface);
        }
    }

    /// The contact in progress as the window shows it (after [`HandDriver::measure`]); `None`
    /// while the hand does not touch.
    #[must_use]
    pub fn feedback(&self) -> Option<&Feedback> {
        self.feedback.as_ref()
    }

    /// Why the surface refused a frame since the last call (the latest refusal), if it did: the
    /// surface kept the contact's last accepted state (see [`crate::hand::FrameOutcome`]).
    pub fn take_refused(&mut self) -> Option<SurfaceError> {
        self.refused.take()
    }

    /// Ends the contact in progress (see the module docs).
    pub fn end_contact(&mut self, doc: &mut Document) {
        if let Some(ops) = self.hand_loop.end_contact() {
            doc.record_ops(&ops);
        }
        self.before = None;
        self.recorded = false;
        self.feedback = None;
    }

    /// Draws the hand: its skeleton — wrist, metacarpals, palm and the finger chains, joints
    /// and bones ([`draw_skeleton`]) — from any source (the mouse's ray: palm and fingers
    /// from its pose), then the capsule of every pressing part (the fingers and palm in the
    /// loop's set), those in the clay highlighted.
    pub fn draw(&self, lines: &mut LineBatch, spheres: &mut Vec<SphereInstance>) {
        if let Some(f) = &self.feedback {
            f.draw(lines, spheres, self.hand_loop.options().finger_radius);
        }
        let Some(pose) = self.hand_loop.pose() else {
            return;
        };
        let sphere = |p: DVec3, r: f64, colour: [f32; 4]| SphereInstance {
            center: p.as_vec3().to_array(),
            radius: r as f32,
            colour,
        };
        let touching = self.hand_loop.touch() != Touch::Free;
        let bone = if touching {
            Rgba::HIGHLIGHT
        } else {
            Rgba::HAND
        };
        let joint_radius = 0.012 * pose.scale.max(1e-6);
        if let Some(skeleton) = self.hand_loop.skeleton() {
            let joints = self.hand_loop.hand().skeleton_joints(&skeleton);
            draw_skeleton(&joints, joint_radius, bone, lines, spheres);
        } else {
            // The palm: the sensor to each knuckle, and the knuckles in a row.
            let knuckles: Vec<DVec3> = pose.fingers.iter().map(|f| f.points[0]).collect();
            for k in &knuckles {
                lines.segment(pose.sensor.as_vec3(), k.as_vec3(), Rgba::HAND);
            }
            lines.polyline(knuckles[1..].iter().map(|p| p.as_vec3()), Rgba::HAND);
            for finger in &pose.fingers {
                lines.polyline(finger.points.iter().map(|p| p.as_vec3()), bone);
                for p in &finger.points {
                    spheres.push(sphere(*p, joint_radius, MEASURED_JOINT));
                }
            }
        }
        // Every pressing part's capsule: orange while that part is in the clay (or holds it),
        // blue otherwise — which fingers touch.
        let in_clay = self.hand_loop.touching();
        for (part, tip) in self.hand_loop.fingertips() {
            let colour = if in_clay.contains(*part) {
                [1.0, 0.35, 0.15, 0.35]
            } else {
                [0.4, 0.65, 1.0, 0.3]
            };
            spheres.push(sphere(tip.tip, tip.radius, colour));
            lines.segment(tip.base.as_vec3(), tip.tip.as_vec3(), bone);
        }
    }
}

/// A measured joint's colour: opaque, light.
pub const MEASURED_JOINT: [f32; 4] = [0.92, 0.9, 0.88, 1.0];
/// A made joint's colour (derived from measured ones: a VMC tip, the palm, a glove hand's wrist
/// and metacarpals): dim and see-through, so it reads as a hollow ghost of a joint.
pub const MADE_JOINT: [f32; 4] = [0.55, 0.6, 0.7, 0.35];
/// A made joint's sphere, as a multiple of a measured one's radius: a larger shell, so a made
/// joint at a measured one's place (a glove's metacarpals at its wrist) still shows.
pub const MADE_JOINT_SCALE: f64 = 1.4;
/// A bone to or from a made joint: dimmer than [`Rgba::HAND`].
pub const MADE_BONE: Rgba = Rgba([0.6, 0.62, 0.7, 0.6]);

/// Draws a skeleton placed in the world ([`crate::hand::Hand::skeleton_joints`]): a sphere
/// per joint of radius `radius` — measured joints opaque ([`MEASURED_JOINT`]), made ones a
/// larger see-through shell ([`MADE_JOINT`]) — and the bones: the wrist to every metacarpal
/// (the thumb's included) and to the palm, each metacarpal to its knuckle, the knuckles of
/// the four fingers in a row, and every finger's chain to its tip, in `bone` where both ends
/// are measured and [`MADE_BONE`] where one is made. Joints the skeleton lacks, and bones to
/// them, are not drawn.
pub fn draw_skeleton(
    joints: &[(HandJoint, DVec3, JointSource)],
    radius: f64,
    bone: Rgba,
    lines: &mut LineBatch,
    spheres: &mut Vec<SphereInstance>,
) {
    let at = |j: HandJoint| {
        joints
            .iter()
            .find(|(k, ..)| *k == j)
            .map(|(_, p, s)| (*p, *s))
    };
    let mut segment = |a: HandJoint, b: HandJoint| {
        if let (Some((pa, sa)), Some((pb, sb))) = (at(a), at(b)) {
            let made = sa == JointSource::Made || sb == JointSource::Made;
            lines.segment(
                pa.as_vec3(),
                pb.as_vec3(),
                if made { MADE_BONE } else { bone },
            );
        }
    };
    use HandJoint::*;
    segment(Wrist, Palm);
    for (metacarpal, chain) in [ThumbMetacarpal]
        .into_iter()
        .chain(HandJoint::METACARPALS)
        .zip(HandJoint::FINGERS)
    {
        segment(Wrist, metacarpal);
        if metacarpal != chain[0] {
            segment(metacarpal, chain[0]);
        }
        for pair in chain.windows(2) {
            segment(pair[0], pair[1]);
        }
    }
    for pair in [IndexProximal, MiddleProximal, RingProximal, LittleProximal].windows(2) {
        segment(pair[0], pair[1]);
    }
    for (_, p, source) in joints {
        let (r, colour) = match source {
            JointSource::Made => (MADE_JOINT_SCALE * radius, MADE_JOINT),
            _ => (radius, MEASURED_JOINT),
        };
        spheres.push(SphereInstance {
            center: p.as_vec3().to_array(),
            radius: r as f32,
            colour,
        });
    }
}

/// The mouse as a hand (the "Hand" tool): the view ray is the finger (see
/// [`crate::hand::mouse`]); the primary button pushes and draws grooves, the secondary grips
/// and pulls (draws ridges).
///
/// The hand is drawn at a size that reads at the model's scale: a real hand (metres) would be
/// a speck on a model ten sides wide, so its lengths are scaled so that the index finger is as
/// long as the finger radius. The fingertip stays exactly where the mouse finger puts it (the
/// frames are handed to the hand loop in units of that scale), and the capsule the loop
/// searches along, `max(finger length, 2 r_f)`, is `2 r_f` either way.
#[derive(Debug, Clone)]
pub struct MouseHandTool {
    finger: MouseFinger,
    driver: HandDriver,
    start: Instant,
    held: u32,
    /// World units per metre of the drawn hand.
    scale: f64,
    /// Where along the ray the mouse hand's fingertip sits while hovering (the profile's depth).
    hover_depth: f64,
}

impl MouseHandTool {
    /// Why the surface refused a frame since the last call, if it did (see
    /// [`HandDriver::take_refused`]).
    pub fn take_refused(&mut self) -> Option<SurfaceError> {
        self.driver.take_refused()
    }

    /// A mouse hand with finger radius `radius` and click depth `depth`.
    ///
    /// # Errors
    /// [`HandError`] for a radius or depth the hand refuses.
    pub fn new(radius: f64, depth: f64) -> Result<Self, HandError> {
        Self::with_profile(MouseProfile::default(), radius, depth)
    }

    /// A mouse hand of a mouse profile (its depth range, wheel step and finger curl).
    ///
    /// # Errors
    /// [`HandError`] for a radius or depth the hand refuses.
    pub fn with_profile(profile: MouseProfile, radius: f64, depth: f64) -> Result<Self, HandError> {
        let size = HandSize::default();
        let index = size.index.proximal + size.index.middle + size.index.distal;
        let scale = radius / index;
        let scale = if scale.is_finite() && scale > 0.0 {
            scale
        } else {
            1.0
        };
        let world_from_tracker = WorldFromTracker {
            scale,
            ..WorldFromTracker::default()
        };
        Ok(Self {
            finger: MouseFinger::new(profile, depth)?,
            driver: HandDriver::new(size, world_from_tracker, FingerModel::Ray, radius)?,
            start: Instant::now(),
            held: 0,
            scale,
            hover_depth: profile.depth,
        })
    }

    /// The finger radius the tool was made with.
    #[must_use]
    pub fn radius(&self) -> f64 {
        self.driver.hand_loop().options().finger_radius
    }

    /// True while a button holds the finger on the surface.
    #[must_use]
    pub fn is_pressed(&self) -> bool {
        self.held != 0
    }

    /// Sets the depth of the next clicks.
    pub fn set_click_depth(&mut self, depth: f64) {
        self.finger.set_click_depth(depth);
    }

    /// Presses the next contacts with their mirror images ([`HandDriver::set_mirror`]).
    pub fn set_mirror(&mut self, mirror: Option<&Symmetry>) {
        self.driver.set_mirror(mirror);
    }

    /// The cursor's view ray with the left (`left`) and right (`right`) buttons as held.
    ///
    /// # Errors
    /// [`HandError`] for a ray with a zero or non-finite direction or a non-finite origin.
    pub fn event(
        &mut self,
        doc: &mut Document,
        ray: &Ray,
        left: bool,
        right: bool,
    ) -> Result<(), HandError> {
        let held =
            if left { buttons::PRIMARY } else { 0 } | if right { buttons::SECONDARY } else { 0 };
        self.held = held;
        let time = Timestamp::from_micros(self.start.elapsed().as_micros() as u64);
        let view = ViewRay {
            origin: ray.origin,
            direction: ray.direction,
        };
        let mut frames = self.finger.frames(time, view, held, &doc.model().surface)?;
        for f in &mut frames {
            // World positions in the units of the hand's `world_from_tracker` (see the type).
            if let Some(pose) = &mut f.pose {
                pose.position /= self.scale;
            }
            self.driver.feed(doc, f);
        }
        self.driver.measure(doc);
        Ok(())
    }

    /// The cursor's view ray with no button held, the fingertip hovering `distance` along it
    /// (just in front of the surface under the cursor, say).
    ///
    /// # Errors
    /// As [`MouseHandTool::event`].
    pub fn hover_at(
        &mut self,
        doc: &mut Document,
        ray: &Ray,
        distance: f64,
    ) -> Result<(), HandError> {
        let dir = ray.direction.normalize_or_zero();
        let shift = if distance.is_finite() {
            distance - self.hover_depth
        } else {
            0.0
        };
        let shifted = Ray {
            origin: ray.origin + shift * dir,
            direction: ray.direction,
        };
        self.event(doc, &shifted, false, false)
    }

    /// Wheel steps: deeper (or, negative, shallower) while pressed, nearer or farther otherwise.
    pub fn wheel(&mut self, steps: f64) {
        self.finger.wheel(steps);
    }

    /// Ends the contact in progress.
    pub fn end_contact(&mut self, doc: &mut Document) {
        self.driver.end_contact(doc);
    }

    /// Draws the hand.
    pub fn draw(&self, lines: &mut LineBatch, spheres: &mut Vec<SphereInstance>) {
        self.driver.draw(lines, spheres);
    }

    /// The hand's fingertip, if the hand has had a frame.
    #[must_use]
    pub fn fingertip(&self) -> Option<DVec3> {
        self.driver.hand_loop().fingertip().map(|t| t.tip)
    }
}

/// The Hand tool's state: the mouse hand (made when the tool is first used, again when the
/// finger radius changes between presses), the profile it is made with, and the press.
#[derive(Debug, Clone, Default)]
pub struct HandToolState {
    /// The hand, once made.
    hand: Option<MouseHandTool>,
    /// The mouse profile the hand is made with (the Devices panel's "mouse" profile).
    profile: MouseProfile,
    /// The view ray of the last event (for a wheel step while pressed).
    last_ray: Option<Ray>,
    /// The press grips and pulls (Shift, or "ridges", at the press).
    pull: bool,
    /// The mirror the next contact presses with ([`HandToolState::set_mirror`]).
    mirror: Option<Symmetry>,
}

impl HandToolState {
    /// Why the surface refused a frame of the hand since the last call, if it did.
    pub fn take_refused(&mut self) -> Option<SurfaceError> {
        self.hand.as_mut().and_then(MouseHandTool::take_refused)
    }

    /// Uses `profile` from now on (the next event makes a new hand). End the contact first.
    pub fn use_profile(&mut self, profile: MouseProfile) {
        self.profile = profile;
        self.hand = None;
    }

    /// The hand, if made.
    #[must_use]
    pub fn hand(&self) -> Option<&MouseHandTool> {
        self.hand.as_ref()
    }

    /// True while a button holds the finger on the surface.
    #[must_use]
    pub fn is_pressed(&self) -> bool {
        self.hand.as_ref().is_some_and(MouseHandTool::is_pressed)
    }

    /// The mirror the next contacts press with (`None`: one-sided); a contact in progress keeps
    /// its own ([`HandDriver::set_mirror`]).
    pub fn set_mirror(&mut self, mirror: Option<&Symmetry>) {
        if self.mirror.as_ref() != mirror {
            self.mirror = mirror.cloned();
        }
    }

    /// A press starts: it pulls when `pull`, else pushes.
    pub fn press(&mut self, pull: bool) {
        self.pull = pull;
    }

    /// The view ray of the last event.
    #[must_use]
    pub fn last_ray(&self) -> Option<Ray> {
        self.last_ray
    }

    /// Ends the contact in progress, if any.
    pub fn end_contact(&mut self, doc: &mut Document) {
        if let Some(h) = &mut self.hand {
            h.end_contact(doc);
        }
    }

    /// Feeds the hand the view ray `ray` (left button held or not; hovering, the fingertip sits
    /// `hover` along the ray), making the hand first for `radius` and click `depth` when it is
    /// missing or stale (not held, another radius). A contact begun here presses with the mirror
    /// last set ([`HandToolState::set_mirror`]).
    ///
    /// # Errors
    /// [`HandError`] when the hand refuses the settings or the ray; a refused hand is dropped.
    pub fn feed(
        &mut self,
        doc: &mut Document,
        ray: Ray,
        left: bool,
        hover: f64,
        radius: f64,
        depth: f64,
    ) -> Result<(), HandError> {
        self.last_ray = Some(ray);
        let stale = self
            .hand
            .as_ref()
            .is_none_or(|h| !h.is_pressed() && h.radius() != radius);
        if stale {
            self.end_contact(doc);
            self.hand = None;
            self.hand = Some(MouseHandTool::with_profile(self.profile, radius, depth)?);
        }
        let Some(hand) = &mut self.hand else {
            return Ok(());
        };
        if !hand.is_pressed() {
            hand.set_click_depth(depth);
            hand.set_mirror(self.mirror.as_ref());
        }
        if left {
            hand.event(doc, &ray, !self.pull, self.pull)
        } else {
            hand.hover_at(doc, &ray, hover)
        }
    }

    /// Wheel steps while pressed: deeper or shallower.
    pub fn wheel(&mut self, steps: f64) {
        if let Some(h) = &mut self.hand {
            h.wheel(steps);
        }
    }

    /// Draws the hand, if made.
    pub fn draw(&self, lines: &mut LineBatch, spheres: &mut Vec<SphereInstance>) {
        if let Some(h) = &self.hand {
            h.draw(lines, spheres);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Primitive, PrimitiveParams};

    #[test]
    fn a_mouse_hand_click_is_one_undoable_push() {
        let plane = Primitive::Plane
            .build(&PrimitiveParams::default())
            .expect("plane");
        let mut doc = Document::new(Model::new(plane));
        let original = doc.model().clone();
        let mut tool = MouseHandTool::new(1.25, 0.3).expect("mouse hand");
        let ray = Ray {
            origin: DVec3::new(0.5, 0.5, 10.0),
            direction: -DVec3::Z,
        };
        tool.event(&mut doc, &ray, false, false).expect("hover");
        assert_eq!(doc.model(), &original, "hovering does not sculpt");
        tool.event(&mut doc, &ray, true, false).expect("press");
        tool.event(&mut doc, &ray, true, false).expect("hold");
        tool.event(&mut doc, &ray, false, false).expect("release");
        assert_ne!(doc.model(), &original, "the click pushed");
        let dented = doc
            .model()
            .surface
            .patches()
            .iter()
            .flatten()
            .map(|p| p.z)
            .fold(0.0, f64::min);
        assert!(dented < -0.1, "a dent into the plane: {dented}");
        assert_eq!(doc.history().undo_name(), Some("hand"));
        assert!(doc.undo());
        assert_eq!(doc.model(), &original, "one undo removes the whole contact");
        let mut lines = LineBatch::new();
        let mut spheres = Vec::new();
        tool.draw(&mut lines, &mut spheres);
        assert!(
            lines.len() >= 15 && spheres.len() >= 20,
            "a hand with five fingers is drawn"
        );
    }
}
