//! The generators of the hand traces shipped in `devices/traces/` ([`shipped`]), each a
//! [`Choreography`] (or, for the mouse, a [`MouseFinger`] under a fixed camera) with the
//! surface and the settings it was made for ([`Shipped`], [`Shipped::scene`]).
//!
//! The mouse trace is made the way the window makes mouse frames: a [`MouseFinger`] over the
//! real [`nendo_devices::MouseDevice`], with the view rays of a fixed camera.
//!
//! Every generator is deterministic: the same code writes the same trace, byte for byte
//! (`tests/it/hand_traces.rs` checks the shipped files against them).

use glam::DVec3;
use nendo_devices::profile::MouseProfile;
use nendo_devices::trace::quantize_frame;
use nendo_devices::{
    HandFrame, HandSize, Joint, Timestamp, Trace, TraceHeader, ViewRay, WorldFromTracker, buttons,
};
use std::f64::consts::{FRAC_PI_2, TAU};

use super::DEFAULT_FINGER_RADIUS;
use super::HandError;
use super::kinematics::Digit;
use super::mouse::MouseFinger;
use super::parts::{FingerModel, Fingers, Part};
use super::scene::{Scene, SceneError, finger_name};
use super::script::{
    CYBERGLOVE_18_JOINTS, Choreography, GLOVE_PROFILE, POINTING, pinch_opened, pinch_pose,
    pinching, thumb_to,
};
use crate::surface::{Grid, Primitive, PrimitiveParams, Regulation};

/// How far outside the sphere the scripted pinch closes (side): the tips stay out of the clay
/// all the way in (at least 0.02 side off it while the fingers close).
const PINCH_GAP: f64 = 0.08;

/// How far the scripted pinch opens (radians off the index's curl, [`pinch_opened`]): the tips
/// 0.98 side apart.
const PINCH_OPEN: f64 = 0.25;

/// Pinch and pull on the paper's sphere, the way a hand pulls a nose out of a ball: the hand
/// comes in along −x with thumb and index open ([`pinch_opened`]: the tips 0.98 side apart,
/// thumb above index, side by side on the sphere, [`pinch_pose`]), stops with the pinch point
/// 0.08 side outside the equator at longitude 0, closes both fingers ([`pinching`]; the pinch
/// point stays put, the tips end 0.1 side apart and take hold of the clay as they pass within
/// the pinch distance), pulls 1 side straight out along +x, opens the fingers again (letting
/// go) and leaves along +x. Neither fingertip's capsule axis reaches the clay: nothing
/// presses, the pinch's `move` is the only operation. 120 Hz.
///
/// # Errors
/// Never for these fixed motions.
pub fn sphere_pinch_pull() -> Result<Trace, HandError> {
    let mut c = Choreography::new(Choreography::WORLD, 120.0)?;
    let hand = *c.hand();
    let closed = pinching(&hand);
    let open = pinch_opened(&hand, &closed, PINCH_OPEN);
    c.set_angles(&open);
    let at = DVec3::new(3.0 + PINCH_GAP, 0.0, 0.0);
    let Some(grab) = pinch_pose(&hand, c.angles(), at, -DVec3::X, DVec3::Z) else {
        return Err(HandError::Model("no hand pose pinches the sphere".into()));
    };
    c.set_pose(c.shifted(grab, DVec3::new(1.5, 0.0, 0.0)));
    c.hold(6);
    c.move_pose_to(grab, 60);
    c.bend_to(&closed, 30);
    c.hold(10);
    let pulled = c.shifted(grab, DVec3::new(1.0, 0.0, 0.0));
    c.move_pose_to(pulled, 90);
    c.hold(10);
    c.bend_to(&open, 30);
    let away = c.shifted(pulled, DVec3::new(1.5, 0.0, 0.0));
    c.move_pose_to(away, 30);
    c.finish(GLOVE_PROFILE)
}

/// The index fingertip of the rim pinch: inside the tube, 0.15 side past its wall at x = 2,
/// 1.6 below the rim.
pub const RIM_INDEX: DVec3 = DVec3::new(2.15, 0.0, 4.4);
/// The thumb tip of the rim pinch: outside the tube, 0.15 side past the wall, 1 side above the
/// index's press and 0.3 to its side (−y).
pub const RIM_THUMB: DVec3 = DVec3::new(1.85, -0.3, 5.4);

/// A two-finger pinch of the paper's test tube's wall near its rim (the tube is one sheet of
/// clay: radius 2, its rim at z = 6): the hand comes down over the rim with the index inside
/// the tube (pointing down, leaning 30° out toward the wall), the thumb open outside, 0.4 side
/// in from where it will press; it moves out until the index tip is 0.15 side past the wall
/// ([`RIM_INDEX`]: pressing it out), the thumb closes on the outside until its tip is 0.15
/// side past the wall ([`RIM_THUMB`]: pressing it in), holds, opens, and the hand moves back
/// in and rises out of the tube. Both tips press the one wall from its two sides, at spots
/// along it, as fingers side by side do a sheet (on one sheet two tips at the same spot
/// from both sides would have to pass through each other); their tips never come within the
/// pinch distance, so nothing is held. One contact of both fingers. 60 Hz.
///
/// # Errors
/// Never for these fixed motions.
pub fn tube_rim_pinch() -> Result<Trace, HandError> {
    let mut c = Choreography::new(Choreography::WORLD, 60.0)?;
    let hand = *c.hand();
    let lean = 30f64.to_radians();
    let (s, k) = (lean.sin(), lean.cos());
    let axis = DVec3::new(s * k, s * s, -k);
    // The back of the hand toward −y: the thumb reaches over the rim to the outside.
    c.place(RIM_INDEX, axis, DVec3::new(-0.55, -0.83, 0.0));
    let press = c.pose();
    let placed = hand.pose(&press, Some(c.angles()));
    let local = |w: DVec3| placed.orientation.inverse() * (w - placed.sensor) / placed.scale;
    let (squeeze, _) = thumb_to(&hand, c.angles(), local(RIM_THUMB));
    let (open, _) = thumb_to(&hand, c.angles(), local(DVec3::new(2.5, -0.3, 5.8)));
    c.set_angles(&open);
    let inside = c.shifted(press, DVec3::new(-0.4, 0.0, 0.0));
    let above = c.shifted(inside, DVec3::new(0.0, 0.0, 2.5));
    c.set_pose(above);
    c.hold(6);
    c.move_pose_to(inside, 48);
    c.move_pose_to(press, 24);
    c.bend_to(&squeeze, 24);
    c.hold(12);
    c.bend_to(&open, 24);
    c.move_pose_to(inside, 24);
    c.move_pose_to(above, 36);
    c.finish(GLOVE_PROFILE)
}

/// A flat hand (every joint straight) laid palm down on the default plane: the palm's face
/// comes down from 0.5 above to `depth` below the plane at (0, 0), the fingers along +x,
/// holds, and lifts. The fingers stay above the clay (their axes 0.255 side over the palm's
/// face, level with it); only the palm presses. 120 Hz.
///
/// # Errors
/// Never for these fixed motions.
pub fn plane_palm(depth: f64) -> Result<Trace, HandError> {
    let mut c = Choreography::new(Choreography::WORLD, 120.0)?;
    let flat: Vec<(Joint, f64)> = CYBERGLOVE_18_JOINTS.iter().map(|&j| (j, 0.0)).collect();
    c.set_angles(&flat);
    c.place(DVec3::new(1.0, 0.0, 1.0), DVec3::X, DVec3::Z);
    let hand = *c.hand();
    let palm = hand.palm(&hand.pose(&c.pose(), Some(c.angles()))).centre;
    let lower = |z: f64| c.shifted(c.pose(), DVec3::new(-palm.x, -palm.y, z - palm.z));
    let (above, pressed) = (lower(0.5), lower(-depth));
    c.set_pose(above);
    c.hold(6);
    c.move_pose_to(pressed, 60);
    c.hold(20);
    c.move_pose_to(above, 40);
    c.finish(GLOVE_PROFILE)
}

/// A trace shipped in `devices/traces/`, with the surface it was made for.
#[derive(Debug, Clone)]
pub struct Shipped {
    /// File name without `.trace`.
    pub name: &'static str,
    /// One line for people.
    pub about: &'static str,
    /// The starting surface.
    pub primitive: Primitive,
    /// Its parameters.
    pub params: PrimitiveParams,
    /// The parts of the hand it was made for (`--finger`): the index alone for the traces
    /// made before the whole hand pressed, the ray for the mouse.
    pub finger: FingerModel,
    /// The frames.
    pub trace: Trace,
}

impl Shipped {
    /// The starting surface.
    ///
    /// # Errors
    /// Never for the shipped parameters; a bad parameter is reported as the surface's error.
    pub fn grid(&self) -> Result<Grid, crate::surface::SurfaceError> {
        self.primitive.build(&self.params)
    }

    /// The scene the trace's header carries: the primitive with every parameter it is built
    /// from, the default regulation, the fingers it was made for ([`Shipped::finger`]: the view
    /// ray for the mouse; the index finger, every finger, the palm or a pinch's two fingers for
    /// the glove) and the default finger radius; no mirror, no refinement. `nendo replay` of the trace then needs only `--out`.
    ///
    /// # Errors
    /// Never for the shipped parameters; a bad parameter is reported as the scene's error.
    pub fn scene(&self) -> Result<Scene, SceneError> {
        let mut scene = Scene::primitive(self.primitive, &self.params)?;
        scene.regulation = Some(Regulation::default());
        scene.finger = Some(finger_name(self.finger));
        scene.finger_radius = Some(DEFAULT_FINGER_RADIUS);
        Ok(scene)
    }
}

/// A push straight down on the north pole of the paper's sphere (8 × 4 patches, radius 3)
/// 0.6 side deep, then a pull on the equator at longitude 0 (a grid vertex): touch, grip with
/// the glove's switch, withdraw 0.6 side, let go. 120 Hz.
///
/// # Errors
/// Never for these fixed motions (see [`Choreography::finish`]).
pub fn sphere_push_pull() -> Result<Trace, HandError> {
    let mut c = Choreography::new(Choreography::WORLD, 120.0)?;
    let down = -DVec3::Z;
    c.place(DVec3::new(0.0, 0.0, 4.4), down, DVec3::Y);
    c.hold(12);
    c.move_to(DVec3::new(0.0, 0.0, 3.15), down, 30);
    c.move_to(DVec3::new(0.0, 0.0, 2.4), down, 48);
    c.hold(24);
    c.move_to(DVec3::new(0.0, 0.0, 4.0), down, 36);
    // Around to the equator at a safe distance, the finger always pointing at the centre.
    c.set_up(DVec3::Y);
    c.path(60, |s| {
        let beta = FRAC_PI_2 * s * s * (3.0 - 2.0 * s);
        let out = DVec3::new(beta.sin(), 0.0, beta.cos());
        (4.0 * out, -out)
    });
    let inward = -DVec3::X;
    c.move_to(DVec3::new(3.01, 0.0, 0.0), inward, 30);
    c.press(buttons::PRIMARY).hold(6);
    c.move_to(DVec3::new(3.6, 0.0, 0.0), inward, 48);
    c.hold(12);
    c.press(0).hold(6);
    c.move_to(DVec3::new(4.5, 0.0, 0.0), inward, 24);
    c.finish(GLOVE_PROFILE)
}

/// The index angles of the groove: curled to press into the plane, straightened to lift.
const GROOVE_CURL: f64 = 0.5;
const GROOVE_LIFT: f64 = -0.25;

/// A groove drawn across the 10 × 10 plane: the hand hovers at `x = −3.5`, the index curls
/// into the plane (the press comes from the glove's bend alone), the hand draws the finger
/// 7 side along +x with the fingertip 0.3 side below the plane, the finger straightens to lift
/// out, and the hand leaves. The finger leans 20° forward along the stroke. 120 Hz.
///
/// # Errors
/// Never for these fixed motions (see [`Choreography::finish`]).
pub fn plane_groove() -> Result<Trace, HandError> {
    let mut c = Choreography::new(Choreography::WORLD, 120.0)?;
    let lean = 20f64.to_radians();
    let axis = DVec3::new(lean.sin(), 0.0, -lean.cos());
    let (start, end) = (DVec3::new(-3.5, 0.0, -0.3), DVec3::new(3.5, 0.0, -0.3));
    // The pose that puts the curled fingertip at the start of the stroke; with the finger
    // straight, the same pose holds the fingertip above the plane.
    let curled = [(Joint::IndexMcp, GROOVE_CURL)];
    let straight = [(Joint::IndexMcp, POINTING[4].1)];
    c.set_angles(&curled);
    c.place(start, axis, DVec3::X);
    let pressing = c.pose();
    c.set_angles(&straight);
    let above = c.shifted(pressing, DVec3::new(-1.0, 0.0, 1.5));
    c.set_pose(above);
    c.hold(12);
    c.move_pose_to(pressing, 36);
    c.bend_to(&curled, 30);
    c.hold(6);
    c.move_to(end, axis, 420);
    c.hold(6);
    c.bend_to(&[(Joint::IndexMcp, GROOVE_LIFT)], 30);
    let away = c.shifted(c.pose(), DVec3::new(1.0, 0.0, 1.5));
    c.move_pose_to(away, 30);
    c.finish(GLOVE_PROFILE)
}

/// One ring of pushes around the tube's axis at height `z`, at `count` azimuths starting at
/// `phase`: from inside (`outward`, the finger pointing away from the axis) to radius
/// `radius`, or from outside (pointing at the axis). Between pushes the fingertip withdraws
/// to `clear` (a radius away from the wall) and turns to the next azimuth there.
#[allow(clippy::too_many_arguments)]
fn ring(
    c: &mut Choreography,
    z: f64,
    radius: f64,
    clear: f64,
    outward: bool,
    count: usize,
    phase: f64,
    ops: &mut usize,
) {
    let radial = |phi: f64| DVec3::new(phi.cos(), phi.sin(), 0.0);
    let axis = |phi: f64| if outward { radial(phi) } else { -radial(phi) };
    let at = |phi: f64, r: f64| radial(phi) * r + DVec3::new(0.0, 0.0, z);
    c.set_up(DVec3::Z);
    c.move_to(at(phase, clear), axis(phase), 12);
    for k in 0..count {
        let phi = phase + TAU * k as f64 / count as f64;
        c.move_to(at(phi, radius), axis(phi), 8);
        c.hold(2);
        c.move_to(at(phi, clear), axis(phi), 5);
        *ops += 1;
        if k + 1 < count {
            let next = phase + TAU * (k + 1) as f64 / count as f64;
            c.path(4, |s| {
                let p = phi + (next - phi) * s;
                (at(p, clear), axis(p))
            });
        }
    }
}

/// Goes from wherever the finger is to above the tube's open top, then down into it (inside)
/// or down its outside, ending at radius `clear`, height `z`, azimuth `phi`.
fn enter(c: &mut Choreography, inside: bool, z: f64, clear: f64, phi: f64) {
    let radial = DVec3::new(phi.cos(), phi.sin(), 0.0);
    let axis = if inside { radial } else { -radial };
    let (tip, now) = c.fingertip();
    let top = 8.0;
    let over = if inside { 0.6 } else { clear };
    c.set_up(DVec3::Z);
    c.move_to(DVec3::new(tip.x, tip.y, top), now, 24);
    // Turn the finger horizontally (about the vertical) to its new direction.
    let level = DVec3::new(now.x, now.y, 0.0)
        .try_normalize()
        .unwrap_or(radial);
    c.move_to(DVec3::new(tip.x, tip.y, top), level, 12);
    c.move_to(DVec3::new(tip.x, tip.y, top), axis, 18);
    c.move_to(radial * over + DVec3::new(0.0, 0.0, top), axis, 24);
    c.move_to(radial * over + DVec3::new(0.0, 0.0, z), axis, 24);
    c.move_to(radial * clear + DVec3::new(0.0, 0.0, z), axis, 8);
}

/// Shapes the paper's test tube (128 patches: 16 around × 8 along, radius 2, walls 4 high,
/// the closed bottom a hemisphere) into a pot (Fig. 15): pushes from inside widen the belly
/// in passes, pushes from inside flare the lip, pushes from outside pull in the neck, and a
/// stroke drawn around the neck smooths it. 60 Hz. Returns the trace and the number of
/// gestures (pushes and strokes).
///
/// # Errors
/// Never for these fixed motions (see [`Choreography::finish`]).
pub fn tube_pot() -> Result<(Trace, usize), HandError> {
    let mut c = Choreography::new(Choreography::WORLD, 60.0)?;
    let mut ops = 0;
    let step = TAU / 16.0;
    c.place(
        DVec3::new(0.0, -4.0, 9.0),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::Z,
    );
    c.hold(6);
    // The belly, from inside: a lower ring, two passes at the widest height, the shoulder.
    enter(&mut c, true, 3.2, 1.2, 0.0);
    for (z, r, phase) in [
        (3.2, 2.3, 0.0),
        (2.5, 2.25, 0.5 * step),
        (3.2, 2.55, 0.5 * step),
        (3.9, 2.35, 0.0),
        (3.2, 2.7, 0.0),
    ] {
        ring(&mut c, z, r, 1.2, true, 16, phase, &mut ops);
    }
    // The lip, from inside, while the wall above the belly is still straight: pressed along
    // the wall's normal (the contact rule), a push on the straight wall flares it outward and
    // leaves the rim at its height; pressed after the neck, on the wall sloping out from the
    // neck, the normal would carry the rim down below the lip's height.
    ring(&mut c, 5.85, 2.45, 1.2, true, 16, 0.0, &mut ops);
    // The neck, from outside: two passes, then a stroke drawn once around.
    enter(&mut c, false, 5.0, 2.9, 0.0);
    for (z, r, phase) in [
        (5.0, 1.75, 0.0),
        (4.6, 1.95, 0.5 * step),
        (5.0, 1.5, 0.5 * step),
    ] {
        ring(&mut c, z, r, 2.9, false, 16, phase, &mut ops);
    }
    let radial = |phi: f64| DVec3::new(phi.cos(), phi.sin(), 0.0);
    let neck = |phi: f64, r: f64| radial(phi) * r + DVec3::new(0.0, 0.0, 5.0);
    c.move_to(neck(0.0, 1.3), -radial(0.0), 10);
    c.path(150, |s| {
        let phi = TAU * s;
        (neck(phi, 1.3), -radial(phi))
    });
    c.move_to(neck(0.0, 2.9), -radial(0.0), 8);
    ops += 1;
    let (tip, axis) = c.fingertip();
    c.move_to(DVec3::new(tip.x, tip.y, 9.0), axis, 30);
    Ok((c.finish(GLOVE_PROFILE)?, ops))
}

/// The camera of the mouse trace: 12 side in front of the sphere (−y), 5 above.
pub const MOUSE_CAMERA: DVec3 = DVec3::new(0.0, -12.0, 5.0);

/// Mouse gestures on the paper's sphere, through [`MouseFinger`] and the real mouse hand of
/// `nendo_devices`, seen from [`MOUSE_CAMERA`]: a left click (push by the click depth 0.3), a
/// left drag (a groove drawn along a parallel), a right click (pull by 0.3), and a left press
/// deepened by five wheel steps. 60 Hz.
///
/// Each press anchors on the surface under the cursor. The script anchors on the sphere as it
/// was at the start, so that the trace does not depend on how the loop deforms the surface:
/// the depths are measured from the starting sphere (the clay under the right click had
/// moved by 0.014 side, well inside the grip's reach of 0.05).
///
/// # Errors
/// Never for these fixed motions.
pub fn mouse_sphere() -> Result<Trace, HandError> {
    let sphere = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .map_err(|e| HandError::Model(e.to_string()))?;
    let mut finger = MouseFinger::new(MouseProfile::default(), 0.3)?;
    let joints: Vec<Joint> = finger.pointing_joints();
    let on_sphere = |lat: f64, lon: f64| {
        let (lat, lon) = (lat.to_radians(), lon.to_radians());
        3.0 * DVec3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin())
    };
    // (cursor target on the sphere, buttons, wheel steps) per event.
    let mut events: Vec<(DVec3, u32, f64)> = Vec::new();
    // Hover in from the left.
    for i in 0..20 {
        events.push((on_sphere(10.0, -150.0 + 1.5 * i as f64), 0, 0.0));
    }
    // A left click: push.
    let a = on_sphere(25.0, -120.0);
    for b in [buttons::PRIMARY; 12].into_iter().chain([0; 4]) {
        events.push((a, b, 0.0));
    }
    // A left drag along the parallel −20° from longitude −125° to −55°: a groove.
    for i in 0..=70 {
        events.push((on_sphere(-20.0, -125.0 + i as f64), buttons::PRIMARY, 0.0));
    }
    events.push((on_sphere(-20.0, -55.0), 0, 0.0));
    // A right click: pull.
    let d = on_sphere(30.0, -60.0);
    for b in [buttons::SECONDARY; 12].into_iter().chain([0; 4]) {
        events.push((d, b, 0.0));
    }
    // A left press deepened by the wheel.
    let e = on_sphere(5.0, -90.0);
    for i in 0..16 {
        events.push((
            e,
            buttons::PRIMARY,
            if (4..9).contains(&i) { 1.0 } else { 0.0 },
        ));
    }
    for _ in 0..6 {
        events.push((e, 0, 0.0));
    }
    let mut frames: Vec<HandFrame> = Vec::new();
    for (k, (target, held, wheel)) in events.into_iter().enumerate() {
        if wheel != 0.0 {
            finger.wheel(wheel);
        }
        let time = Timestamp((k as f64 * 1e6 / 60.0).round() as u64);
        let ray = ViewRay {
            origin: MOUSE_CAMERA,
            direction: target - MOUSE_CAMERA,
        };
        for f in finger.frames(time, ray, held, &sphere)? {
            frames.push(quantize_frame(&f, &joints));
        }
    }
    Ok(Trace {
        header: TraceHeader {
            profile: Some("mouse".into()),
            world_from_tracker: WorldFromTracker::default(),
            hand: HandSize::default(),
            joints,
            scene: None,
            skeleton: None,
            marks_held: false,
        },
        frames,
        held: Vec::new(),
    })
}

/// Every shipped trace, generated (see `devices/README.md` and `examples/hand_traces.rs`).
///
/// # Errors
/// Never for the fixed motions; a [`HandError`] would name what failed.
pub fn shipped() -> Result<Vec<Shipped>, HandError> {
    let sphere = PrimitiveParams::default();
    let (pot, _) = tube_pot()?;
    let mut shipped = vec![
        Shipped {
            name: "sphere-push-pull",
            about: "push 0.6 at the north pole, then grip and pull 0.6 at the equator (glove + tracker, 120 Hz)",
            primitive: Primitive::Sphere,
            params: sphere,
            finger: FingerModel::digit(Digit::Index),
            trace: sphere_push_pull()?,
        },
        Shipped {
            name: "plane-groove",
            about: "a groove 0.3 deep drawn 7 side across the plane; the finger curls in and straightens out (glove + tracker, 120 Hz)",
            primitive: Primitive::Plane,
            params: PrimitiveParams::default(),
            finger: FingerModel::digit(Digit::Index),
            trace: plane_groove()?,
        },
        Shipped {
            name: "tube-pot",
            about: "the test tube shaped into a pot: belly pushed out from inside, neck pushed in and stroked, lip flared (glove + tracker, 60 Hz)",
            primitive: Primitive::Tube,
            params: PrimitiveParams::default(),
            finger: FingerModel::digit(Digit::Index),
            trace: pot,
        },
        Shipped {
            name: "mouse-sphere",
            about: "mouse: click push, drag groove, right-click pull, wheel-deepened press on the sphere (60 Hz)",
            primitive: Primitive::Sphere,
            params: sphere,
            finger: FingerModel::Ray,
            trace: mouse_sphere()?,
        },
        Shipped {
            name: "sphere-pinch-pull",
            about: "thumb and index pinch the sphere's clay at the equator and pull a nose 1 side out (glove + tracker, 120 Hz)",
            primitive: Primitive::Sphere,
            params: sphere,
            // The pinch's two fingers: curled, the others would brush the sphere on the way in.
            finger: FingerModel::Hand(Fingers::THUMB_AND_INDEX),
            trace: sphere_pinch_pull()?,
        },
        Shipped {
            name: "tube-rim-pinch",
            about: "thumb outside and index inside press the tube's wall near the rim from both sides (glove + tracker, 60 Hz)",
            primitive: Primitive::Tube,
            params: PrimitiveParams::default(),
            finger: FingerModel::Hand(Fingers::THUMB_AND_INDEX),
            trace: tube_rim_pinch()?,
        },
        Shipped {
            name: "plane-palm",
            about: "a flat hand laid palm down 0.1 into the plane and lifted (glove + tracker, 120 Hz)",
            primitive: Primitive::Plane,
            params: PrimitiveParams::default(),
            finger: FingerModel::Hand(Fingers::ALL.with(Part::Palm)),
            trace: plane_palm(0.1)?,
        },
    ];
    // Every header names the scene it was made on.
    for s in &mut shipped {
        let scene = s
            .scene()
            .and_then(|scene| scene.to_text())
            .map_err(|e| HandError::Model(format!("{}: {e}", s.name)))?;
        s.trace.header.scene = Some(scene);
    }
    Ok(shipped)
}
