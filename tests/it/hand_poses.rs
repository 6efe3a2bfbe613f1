//! Issue 25: the contact rule over random hand poses. Random wrist orientations and joint
//! angles (flat, spread, curled, a fist, anything), at the tracker scales of the shipped
//! profiles (1, 5, 10 and 20 sides per metre), on every primitive — from above and below the
//! plane, from inside and outside the tube, from outside the others — each fed to the hand
//! loop with its product defaults (every finger presses; in a quarter of the cases the palm
//! too) as a short press sequence: the hand comes straight in until its deepest fingertip is a
//! chosen depth past the surface (or a joint 1 side past it), holds, in a third of the cases
//! slides along it, and goes back out.
//!
//! Each result is measured on the surface itself — every patch evaluated on a 10 × 10 grid,
//! before and after, at the same parameters — against an independent reference: the
//! primitive's own equations give every fingertip's penetration at every frame and the side
//! of the clay the hand is on.
//!
//! - **No point moves more than 1.5 times the deepest penetration of the parts that touched
//!   near it** — "near": within `r_f` (the shape function's reach) plus one patch (the
//!   regulation's) of a fingertip while it was past the surface — give or take 5 % of the
//!   deepest penetration anywhere (the exact regulation spreads a little of every dent over
//!   the grid).
//! - **No point moves toward the hand** unless a pinch held the clay: not by more than the
//!   paper's own press bulges. A straight push of the index alone bulges the surface beside
//!   its dent — the Bernstein inverse and the regulation fit the shape function's kinked
//!   paraboloid with whole patches — by a fraction `κ` of its depth that depends on the
//!   patches (about 0.12 on the plane's unit squares, 0.25 on the hemisphere's 8 × 2,
//!   measured here per primitive, [`overshoot`]); a sample may move toward the hand by at
//!   most 1.35 `κ` times the deepest penetration of the parts within `r_f` plus two patches
//!   (several dents side by side bulge a little more than one). Before the rule, curled
//!   fingers raised the plane by 2.6 times the depth pressed (20 times `κ`).
//! - **A tip that went past the surface without pressing went in after its own body**: a case
//!   that leaves the surface as it was, although a fingertip went past it, is one where every
//!   such fingertip crossed after a point of its own body (the back of the hand, a knuckle, a
//!   joint) — the hand met the clay knuckles or back first (checked on the equations too).
//!
//! The counts are printed (`cargo test --release --test it hand_poses -- --nocapture`).

use glam::{DQuat, DVec3};
use nendo::hand::script::{CYBERGLOVE_18_JOINTS, Choreography};
use nendo::hand::{FingerModel, Fingers, Hand, HandOptions, HandPose, HandSession, Part};
use nendo::surface::{Grid, Primitive, PrimitiveParams, Regulation, deviation};
use nendo_devices::{HandSize, Joint, JointAngles, Trace, TrackerPose, WorldFromTracker};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{PI, TAU};

/// The starting surfaces: the primitives, the open ones tall or wide enough that a hand
/// pressing their middle cannot reach around an edge (up to 3.8 side long at 20 sides per
/// metre).
fn surface(p: Primitive) -> Grid {
    let params = match p {
        Primitive::Plane => PrimitiveParams {
            patches: Some((14, 14)),
            ..PrimitiveParams::default()
        },
        Primitive::Cylinder => PrimitiveParams {
            patches: Some((8, 6)),
            height: Some(12.0),
            ..PrimitiveParams::default()
        },
        Primitive::Tube => PrimitiveParams {
            height: Some(12.0),
            ..PrimitiveParams::default()
        },
        _ => PrimitiveParams::default(),
    };
    p.build(&params).unwrap()
}

/// Which side of the primitive's sheet the hand works from.
#[derive(Debug, Clone, Copy, PartialEq)]
enum From {
    /// Above the plane, outside a closed or open shape.
    Outside,
    /// Below the plane, inside the cylinder or the tube.
    Inside,
}

/// The primitive's equations: the signed distance of `x` from its ideal surface, positive on
/// the hand's side, and the unit normal there turned to the hand's side (for a point on or
/// near the surface).
fn sided(p: Primitive, from: From, x: DVec3) -> (f64, DVec3) {
    let sign = if from == From::Outside { 1.0 } else { -1.0 };
    let radial = DVec3::new(x.x, x.y, 0.0);
    let (d, n) = match p {
        Primitive::Plane => (x.z, DVec3::Z),
        Primitive::Sphere | Primitive::Hemisphere => (x.length() - 3.0, x.normalize_or(DVec3::Z)),
        Primitive::Cylinder => (radial.length() - 3.0, radial.normalize_or(DVec3::X)),
        Primitive::Torus => {
            let core = 3.0 * radial.normalize_or(DVec3::X);
            ((x - core).length() - 1.0, (x - core).normalize_or(DVec3::Z))
        }
        Primitive::Tube => {
            if x.z > 2.0 {
                (radial.length() - 2.0, radial.normalize_or(DVec3::X))
            } else {
                let c = DVec3::new(0.0, 0.0, 2.0);
                ((x - c).length() - 2.0, (x - c).normalize_or(-DVec3::Z))
            }
        }
    };
    (sign * d, sign * n)
}

/// A point of the primitive's middle to press at, with the approach side.
fn target(p: Primitive, rng: &mut ChaCha8Rng) -> (DVec3, From) {
    let phi = rng.gen_range(0.0..TAU);
    let around = DVec3::new(phi.cos(), phi.sin(), 0.0);
    match p {
        Primitive::Plane => {
            let from = if rng.gen_bool(0.75) {
                From::Outside
            } else {
                From::Inside
            };
            (
                DVec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), 0.0),
                from,
            )
        }
        Primitive::Sphere => {
            let z: f64 = rng.gen_range(-1.0..1.0);
            let r = (1.0 - z * z).sqrt();
            (
                3.0 * DVec3::new(r * phi.cos(), r * phi.sin(), z),
                From::Outside,
            )
        }
        Primitive::Hemisphere => {
            // Near the pole: the rim is farther than a hand.
            let polar: f64 = rng.gen_range(0.0..0.25);
            (
                3.0 * (polar.sin() * around + polar.cos() * DVec3::Z),
                From::Outside,
            )
        }
        Primitive::Torus => {
            let theta: f64 = rng.gen_range(-PI..PI);
            (
                3.0 * around + (theta.cos() * around + theta.sin() * DVec3::Z),
                From::Outside,
            )
        }
        Primitive::Cylinder => (3.0 * around + DVec3::new(0.0, 0.0, 6.0), From::Outside),
        Primitive::Tube => {
            let from = if rng.gen_bool(0.5) {
                From::Outside
            } else {
                From::Inside
            };
            (
                2.0 * around + DVec3::new(0.0, 0.0, rng.gen_range(6.0..8.0)),
                from,
            )
        }
    }
}

/// The poses a hand takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Shape {
    Flat,
    Spread,
    Curled,
    Fist,
    Any,
}

const SHAPES: [Shape; 5] = [
    Shape::Flat,
    Shape::Spread,
    Shape::Curled,
    Shape::Fist,
    Shape::Any,
];

fn angles(shape: Shape, rng: &mut ChaCha8Rng) -> Vec<(Joint, f64)> {
    CYBERGLOVE_18_JOINTS
        .iter()
        .map(|&j| {
            let abduction = matches!(
                j,
                Joint::ThumbIndexAbduction
                    | Joint::IndexMiddleAbduction
                    | Joint::MiddleRingAbduction
                    | Joint::RingPinkyAbduction
            );
            let a = match (shape, abduction) {
                (_, _) if matches!(j, Joint::PalmArch | Joint::WristPitch | Joint::WristYaw) => 0.0,
                (Shape::Flat, _) => 0.0,
                (Shape::Spread, true) => rng.gen_range(0.25..0.45),
                (Shape::Spread, false) => rng.gen_range(-0.1..0.15),
                (Shape::Curled, true) => rng.gen_range(0.0..0.2),
                (Shape::Curled, false) => rng.gen_range(0.4..1.2),
                (Shape::Fist, true) => 0.0,
                (Shape::Fist, false) => rng.gen_range(1.2..1.6),
                (Shape::Any, true) => rng.gen_range(-0.1..0.45),
                (Shape::Any, false) => rng.gen_range(-0.2..1.6),
            };
            (j, a)
        })
        .collect()
}

fn random_rotation(rng: &mut ChaCha8Rng) -> DQuat {
    loop {
        let q = DQuat::from_xyzw(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        );
        let l = q.length();
        if l > 0.1 && l <= 1.0 {
            return q / l;
        }
    }
}

/// The fingertips (and the palm's centre) and every joint of a frame's hand, in the world.
fn hand_points(
    hand: &Hand,
    pose: &TrackerPose,
    joints: &JointAngles,
) -> (Vec<(Part, DVec3)>, Vec<DVec3>) {
    let placed = hand.pose(pose, Some(joints));
    let mut tips = Vec::new();
    let mut body = vec![placed.sensor];
    for (k, chain) in placed.fingers.iter().enumerate() {
        tips.push((Part::ALL[k], chain.tip()));
        body.extend_from_slice(&chain.points);
    }
    let palm = hand.palm(&placed).centre;
    tips.push((Part::Palm, palm));
    body.push(palm);
    (tips, body)
}

/// One case: the trace, the parts pressing, and what the reference says.
struct Case {
    primitive: Primitive,
    from: From,
    shape: Shape,
    scale: f64,
    finger: Fingers,
    trace: Trace,
}

/// Builds a press sequence: the hand, turned at random, starts clear of the clay on its
/// side, comes in along a direction within 60° of the surface normal until its deepest
/// fingertip is `depth` past the surface (or a joint 1 side past it: a hand that meets the
/// clay with its knuckles), holds, in a third of the cases slides 0.4 side along the surface,
/// and goes back out. `None` when no start clear of the clay was found.
fn case(rng: &mut ChaCha8Rng, primitive: Primitive, shape: Shape) -> Option<Case> {
    let (at, from) = target(primitive, rng);
    let (_, normal) = sided(primitive, from, at);
    // The scale: the profiles' 1 and 20 sides per metre, and between; inside the tube (4
    // side across) a hand of at most 1 side.
    let scale = if primitive == Primitive::Tube && from == From::Inside {
        [1.0, 5.0][rng.gen_range(0..2)]
    } else {
        [1.0, 5.0, 10.0, 20.0][rng.gen_range(0..4)]
    };
    let world = WorldFromTracker {
        translation: [0.0, 0.0, 0.0],
        rotation_wxyz: [1.0, 0.0, 0.0, 0.0],
        scale,
    };
    let hand = Hand::new(HandSize::default(), world).unwrap();
    let set = angles(shape, rng);
    let mut joints = JointAngles::new();
    for (j, a) in &set {
        joints.set(*j, *a).unwrap();
    }
    let orientation = random_rotation(rng);
    // The approach: against the normal, tilted up to 60°.
    let tilt = rng.gen_range(0.0..60f64.to_radians());
    let side = normal.any_orthonormal_vector();
    let turn = DQuat::from_axis_angle(normal, rng.gen_range(0.0..TAU));
    let approach = -(tilt.cos() * normal + tilt.sin() * (turn * side));
    let pose_at = |position: DVec3| TrackerPose {
        position,
        orientation,
    };
    // The leading fingertip (farthest along the approach) put `back` before the target.
    let (tips, _) = hand_points(&hand, &pose_at(DVec3::ZERO), &joints);
    let lead = tips[..5]
        .iter()
        .map(|(_, t)| *t)
        .max_by(|a, b| a.dot(approach).total_cmp(&b.dot(approach)))?;
    let clear = |position: DVec3| {
        let (tips, body) = hand_points(&hand, &pose_at(position), &joints);
        tips.iter()
            .map(|(_, t)| *t)
            .chain(body)
            .all(|x| sided(primitive, from, x).0 > 0.1)
    };
    let mut back = 0.3;
    let start = loop {
        let p = (at - back * approach - lead) / scale;
        if clear(p) {
            break p;
        }
        back += 0.3;
        if back > 8.0 {
            return None;
        }
    };
    // Come in until the deepest fingertip is `depth` in (or a joint 1 side in).
    let depth = rng.gen_range(0.03..0.6);
    let mut s = 0.0;
    let end = loop {
        let p = start + s * approach / scale;
        let (tips, body) = hand_points(&hand, &pose_at(p), &joints);
        let tip_in = tips[..5]
            .iter()
            .map(|(_, t)| -sided(primitive, from, *t).0)
            .fold(f64::MIN, f64::max);
        let body_in = body
            .iter()
            .map(|x| -sided(primitive, from, *x).0)
            .fold(f64::MIN, f64::max);
        if tip_in >= depth || body_in >= 1.0 || s > back + 4.0 {
            break p;
        }
        s += 0.01;
    };
    let finger = if rng.gen_bool(0.25) {
        Fingers::ALL.with(Part::Palm)
    } else {
        Fingers::ALL
    };
    let mut c = Choreography::new(world, 120.0).unwrap();
    c.set_angles(&set);
    c.set_pose(pose_at(start));
    c.hold(3);
    c.move_pose_to(pose_at(end), 30);
    c.hold(6);
    if rng.gen_bool(1.0 / 3.0) {
        let along = normal.any_orthonormal_vector();
        c.move_pose_to(pose_at(end + 0.4 * along / scale), 20);
    }
    let last = c.pose();
    c.move_pose_to(pose_at(last.position + (start - end)), 30);
    c.hold(2);
    Some(Case {
        primitive,
        from,
        shape,
        scale,
        finger,
        trace: c.finish("test").unwrap(),
    })
}

/// What the reference says of a case's frames: for every part, its deepest penetration past
/// the ideal surface, and where its tip was while past it.
fn penetrations(case: &Case) -> Vec<(Part, f64, Vec<DVec3>)> {
    let hand = Hand::new(case.trace.header.hand, case.trace.header.world_from_tracker).unwrap();
    let mut out: Vec<(Part, f64, Vec<DVec3>)> =
        case.finger.parts().map(|p| (p, 0.0, Vec::new())).collect();
    for f in &case.trace.frames {
        let (Some(pose), Some(joints)) = (f.pose, f.joints.as_ref()) else {
            continue;
        };
        let (tips, _) = hand_points(&hand, &pose, joints);
        for (part, deepest, at) in &mut out {
            let tip = tips.iter().find(|(p, _)| p == part).unwrap().1;
            let pen = -sided(case.primitive, case.from, tip).0;
            if pen > 0.0 {
                *deepest = deepest.max(pen);
                at.push(tip);
            }
        }
    }
    out
}

/// Where a finger's tip went past the ideal surface between two frames: the digit, and
/// whether a point of its body (back of the hand, knuckle, inner joints) was past it already
/// at the frame before.
fn entries(case: &Case) -> Vec<(usize, bool)> {
    let hand = Hand::new(case.trace.header.hand, case.trace.header.world_from_tracker).unwrap();
    let past = |x: DVec3| sided(case.primitive, case.from, x).0 < 0.0;
    let mut out = Vec::new();
    let mut before: Option<HandPose> = None;
    for f in &case.trace.frames {
        let (Some(pose), Some(joints)) = (f.pose, f.joints.as_ref()) else {
            continue;
        };
        let now = hand.pose(&pose, Some(joints));
        if let Some(was) = &before {
            for d in 0..5 {
                if past(now.fingers[d].tip()) && !past(was.fingers[d].tip()) {
                    let body = was.fingers[d].points[..3]
                        .iter()
                        .chain([&was.sensor])
                        .any(|x| past(*x));
                    out.push((d, body));
                }
            }
        }
        before = Some(now);
    }
    out
}

/// The largest extent of a patch (its corners' box diagonal).
fn patch_size(g: &Grid) -> f64 {
    (0..g.patch_count())
        .map(|k| {
            let p = g.patch_at(k);
            let (lo, hi) = [p[0], p[3], p[12], p[15]]
                .iter()
                .fold((p[0], p[0]), |(lo, hi), q| (lo.min(*q), hi.max(*q)));
            (hi - lo).length()
        })
        .fold(0.0, f64::max)
}

/// The overshoot of the paper's own press on `start`: straight pushes of the index alone (a
/// pointing hand, 20 sides per metre) 0.2 side into the middle of the primitive at a few
/// places; the largest move of the surface toward the hand, as a fraction of the depth. The
/// Bernstein inverse and the regulation fit the shape function's paraboloid (kinked at its
/// rim) with whole patches, so the surface bulges beside a dent: by about a tenth of its depth
/// on the plane's unit patches, by nearly a third on the hemisphere's 8 × 2.
fn overshoot(primitive: Primitive, start: &Grid, rng: &mut ChaCha8Rng) -> f64 {
    let before = deviation::samples(start, 10);
    let depth = 0.2;
    let mut worst = 0.0f64;
    for _ in 0..4 {
        let (at, from) = target(primitive, rng);
        let (_, n) = sided(primitive, from, at);
        let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
        c.place(at + n, -n, n.any_orthonormal_vector());
        c.move_to(at - depth * n, -n, 40);
        c.hold(10);
        c.move_to(at + n, -n, 40);
        let t = c.finish("test").unwrap();
        let hand = Hand::new(t.header.hand, t.header.world_from_tracker).unwrap();
        let index = FingerModel::Hand(Fingers::one(Part::Digit(nendo::hand::Digit::Index)));
        let options = HandOptions {
            finger: index,
            ..HandOptions::default()
        };
        let mut s = HandSession::new(start.clone(), Regulation::default(), hand, options).unwrap();
        for f in &t.frames {
            s.feed(f);
        }
        s.finish();
        for (b, a) in before.iter().zip(&deviation::samples(s.grid(), 10)) {
            let toward = (*a - *b).dot(sided(primitive, from, *b).1);
            worst = worst.max(toward / depth);
        }
    }
    worst
}

#[derive(Debug, Default)]
struct Tally {
    cases: usize,
    skipped: usize,
    pressed: usize,
    /// Cases that left the surface as it was although a fingertip went past it.
    untouched_with_a_tip_in: usize,
    /// Their fingertips' entries, each after a part of the finger's own body.
    tips_in_after_their_body: usize,
    held: usize,
    /// Cases held off the clay by the clutch (a fist), which left it as it was.
    clutched: usize,
    samples: usize,
    /// The largest move of a sample over the deepest penetration of the parts near it.
    worst_move: f64,
    /// The largest move of a sample no penetrating part came near, over the deepest
    /// penetration.
    worst_far: f64,
    /// The largest move toward the hand, over the paper's own overshoot for the deepest
    /// penetration of the parts near.
    worst_toward: f64,
}

#[test]
fn random_hand_poses_never_pull_the_clay_nor_press_deeper_than_they_went() {
    let mut rng = ChaCha8Rng::seed_from_u64(25);
    let r_f = HandOptions::default().finger_radius;
    let mut tally = Tally::default();
    let mut by_primitive = Vec::new();
    for primitive in Primitive::ALL {
        let start = surface(primitive);
        let patch = patch_size(&start);
        let kappa = overshoot(primitive, &start, &mut rng);
        let before = deviation::samples(&start, 10);
        let mut pressed_here = 0;
        for round in 0..8 {
            for shape in SHAPES {
                let Some(case) = case(&mut rng, primitive, shape) else {
                    tally.skipped += 1;
                    continue;
                };
                tally.cases += 1;
                let hand = Hand::new(case.trace.header.hand, case.trace.header.world_from_tracker)
                    .unwrap();
                let options = HandOptions {
                    finger: FingerModel::Hand(case.finger),
                    ..HandOptions::default()
                };
                let mut s =
                    HandSession::new(start.clone(), Regulation::default(), hand, options).unwrap();
                for f in &case.trace.frames {
                    s.feed(f);
                }
                s.finish();
                let held = s.hand_loop().stats().holds > 0;
                if s.hand_loop().stats().clutched > 0 {
                    // A fist (rule 10, the clutch: every finger but the thumb bent past
                    // 1.3 rad) moves the hand without touching: the clay stays as it was.
                    tally.clutched += 1;
                    assert_eq!(
                        deviation::samples(s.grid(), 10),
                        before,
                        "a fist moved the clay"
                    );
                    continue;
                }
                let parts = penetrations(&case);
                let deepest = parts.iter().map(|p| p.1).fold(0.0, f64::max);
                let after = deviation::samples(s.grid(), 10);
                let label = format!(
                    "{primitive} round {round} {:?} from {:?} at {} side/m, {}",
                    case.shape, case.from, case.scale, case.finger
                );
                if after == before {
                    if deepest > 0.0 {
                        tally.untouched_with_a_tip_in += 1;
                        // Every fingertip that went past the surface went in after a part of
                        // its own body (the back of the hand, a knuckle, a curled joint): it
                        // did not enter from the hand's side.
                        let entries = entries(&case);
                        assert!(
                            entries.iter().all(|(_, body_first)| *body_first),
                            "{label}: a fingertip entered the clay ahead of its body and pressed nothing: {entries:?}"
                        );
                        tally.tips_in_after_their_body += entries.len();
                    }
                    continue;
                }
                tally.pressed += 1;
                pressed_here += 1;
                if held {
                    // A pinch draws the clay toward the hand by where the hand takes it.
                    tally.held += 1;
                    continue;
                }
                // The deepest penetration of the parts whose tip came within `reach` of `b`
                // while past the surface.
                let near = |b: DVec3, reach: f64| {
                    parts
                        .iter()
                        .filter(|(_, _, at)| at.iter().any(|t| (*t - b).length() <= reach))
                        .map(|p| p.1)
                        .fold(0.0, f64::max)
                };
                for (b, a) in before.iter().zip(&after) {
                    tally.samples += 1;
                    let moved = *a - *b;
                    let m = moved.length();
                    // Near: the shape function's reach and a patch (the regulation's).
                    let close = near(*b, r_f + patch);
                    assert!(
                        m <= 1.5 * close + 0.05 * deepest + 1e-9,
                        "{label}: a sample at {b} moved {m}, the parts near it went {close} deep, the deepest {deepest}"
                    );
                    if close > 0.0 {
                        tally.worst_move = tally.worst_move.max(m / close);
                    } else if deepest > 0.0 {
                        tally.worst_far = tally.worst_far.max(m / deepest);
                    }
                    // Toward the hand: no more than the paper's own press of that depth
                    // bulges beside its dent (a third more for the envelope of several),
                    // the bulge reaching a patch farther.
                    let toward = moved.dot(sided(case.primitive, case.from, *b).1);
                    let around = near(*b, r_f + 2.0 * patch);
                    let allowed = 1.35 * kappa * around;
                    assert!(
                        toward <= allowed + 1e-9,
                        "{label}: a sample at {b} moved {toward} toward the hand; the parts near it went {around} deep (a straight press bulges by {kappa} of its depth)"
                    );
                    if toward > 0.0 && allowed > 0.0 {
                        tally.worst_toward = tally.worst_toward.max(toward / (kappa * around));
                    }
                }
            }
        }
        by_primitive.push((primitive.to_string(), kappa, pressed_here));
    }
    println!(
        "random hand poses: {tally:?}; by primitive (the straight press's bulge, cases that changed the surface): {by_primitive:?}"
    );
    assert!(tally.skipped * 10 <= tally.cases, "{tally:?}");
    assert!(
        tally.pressed * 2 >= tally.cases - tally.clutched,
        "most cases press: {tally:?}"
    );
    assert!(
        by_primitive.iter().all(|(_, _, n)| *n >= 15),
        "every primitive is pressed: {by_primitive:?}"
    );
}
