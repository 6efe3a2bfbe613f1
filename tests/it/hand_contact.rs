//! Contact of the virtual finger with the surface: the probe against exact algebra on random
//! rays, and the loop's contact rules on scripted motions, with fixed seeds.

use glam::DVec3;
use nendo::hand::script::{self, Choreography};
use nendo::hand::shipped;
use nendo::hand::{
    DEFAULT_PINCH_CLOSED, Digit, FingerModel, Fingers, Hand, HandLoop, HandOptions, HandSession,
    Part, Probe, Touch,
};
use nendo::surface::{Grid, Op, Primitive, PrimitiveParams, Regulation, continuity};
use nendo_devices::{HandSize, Joint, Trace, buttons};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn unit(rng: &mut ChaCha8Rng) -> DVec3 {
    loop {
        let v = DVec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        );
        if v.length_squared() > 0.05 && v.length_squared() <= 1.0 {
            return v.normalize();
        }
    }
}

#[test]
fn the_probe_meets_the_sphere_where_the_quadratic_says() {
    // The primitive's arcs of 45° are within 4.2e-6 of the radius each way, so the surface of
    // revolution is within 8.4e-6 · 3 = 2.5e-5 side of the sphere.
    let sphere = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut probe = Probe::new();
    let (mut hits, mut misses) = (0, 0);
    for case in 0..400 {
        let origin = unit(&mut rng) * rng.gen_range(3.5..9.0);
        // Aim near the sphere: some rays hit, some pass by.
        let target = unit(&mut rng) * rng.gen_range(0.0..5.5);
        let d = (target - origin).normalize();
        // |o + t d|² = R²: t² + 2 (o·d) t + |o|² − R² = 0, the smaller root.
        let b = origin.dot(d);
        let c = origin.length_squared() - 9.0;
        let disc = b * b - c;
        let got = probe.first_crossing(&sphere, origin, d, 20.0);
        if disc > 0.05 {
            let t = -b - disc.sqrt();
            let hit = got.unwrap_or_else(|| panic!("case {case}: missed"));
            assert!(
                (hit.t - t).abs() < 2.6e-5 / (disc.sqrt() / 3.0).min(1.0),
                "case {case}: {} vs {t}",
                hit.t
            );
            assert!(
                (hit.point.length() - 3.0).abs() < 2.6e-5,
                "case {case}: {}",
                hit.point.length()
            );
            assert!(
                hit.normal.dot(hit.point.normalize()) > 0.999,
                "case {case}: outward normal"
            );
            hits += 1;
        } else if disc < -0.05 {
            assert!(got.is_none(), "case {case}: {got:?}");
            misses += 1;
        }
    }
    assert!(hits > 100 && misses > 50, "{hits} hits, {misses} misses");
}

#[test]
fn the_probe_meets_plane_and_torus_exactly_or_on_their_equations() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let mut probe = Probe::new();
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    for case in 0..300 {
        let target = DVec3::new(rng.gen_range(-4.9..4.9), rng.gen_range(-4.9..4.9), 0.0);
        let origin = target + unit(&mut rng) * rng.gen_range(0.5..8.0);
        if origin.z.abs() < 0.05 {
            continue;
        }
        let d = (target - origin).normalize();
        let hit = probe
            .first_crossing(&plane, origin, d, 20.0)
            .unwrap_or_else(|| panic!("case {case}"));
        assert!(
            (hit.point - target).length() < 1e-9,
            "case {case}: {} vs {target}",
            hit.point
        );
        // A segment that stops short does not reach it.
        assert!(
            probe
                .first_crossing(&plane, origin, d, hit.t * 0.99)
                .is_none()
        );
    }
    // The torus (R 3, r 1) of 8 × 4 patches: arcs of 90° around the tube are within 2.7e-4 of r.
    let torus = Primitive::Torus.build(&PrimitiveParams::default()).unwrap();
    let on_torus = |p: DVec3| ((p.x.hypot(p.y) - 3.0).powi(2) + p.z * p.z).sqrt() - 1.0;
    for case in 0..300 {
        let origin = unit(&mut rng) * rng.gen_range(5.0..9.0);
        let target = DVec3::new(
            rng.gen_range(-3.5..3.5),
            rng.gen_range(-3.5..3.5),
            rng.gen_range(-0.8..0.8),
        );
        if let Some(hit) = probe.first_crossing(&torus, origin, target - origin, 20.0) {
            assert!(
                on_torus(hit.point).abs() < 5e-4,
                "case {case}: {}",
                on_torus(hit.point)
            );
            // Nothing of the torus lies on the ray before the hit: march and check.
            let d = (target - origin).normalize();
            for k in 1..200 {
                let p = origin + d * (hit.t * k as f64 / 200.0);
                assert!(on_torus(p) > -1e-3, "case {case}: inside before the hit");
            }
        }
    }
}

fn session(start: &Grid, regulation: Regulation) -> HandSession {
    let hand = Hand::new(HandSize::default(), Choreography::WORLD).unwrap();
    HandSession::new(start.clone(), regulation, hand, HandOptions::default()).unwrap()
}

fn feed(s: &mut HandSession, t: &Trace) {
    for f in &t.frames {
        s.feed(f);
    }
}

#[test]
fn a_held_press_meets_the_fingertip_for_every_regulation_and_any_lean() {
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    for case in 0..8 {
        let at = DVec3::new(rng.gen_range(-2.0..2.0), rng.gen_range(-2.0..2.0), 0.0);
        let lean: f64 = rng.gen_range(0.0..35f64.to_radians());
        let turn: f64 = rng.gen_range(0.0..std::f64::consts::TAU);
        let axis = DVec3::new(
            lean.sin() * turn.cos(),
            lean.sin() * turn.sin(),
            -lean.cos(),
        );
        let depth = rng.gen_range(0.1..0.5);
        let tip = at + depth / lean.cos() * axis;
        let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
        c.place(
            at - 1.0 * axis,
            axis,
            DVec3::new(turn.cos(), turn.sin(), 0.0),
        );
        c.move_to(tip, axis, 30).hold(40);
        let t = c.finish("test").unwrap();
        for r in Regulation::ALL {
            let mut s = session(&plane, r);
            feed(&mut s, &t);
            let miss = (tip
                - Probe::new()
                    .first_crossing(s.grid(), tip - 2.0 * axis, axis, 4.0)
                    .unwrap()
                    .point)
                .dot(axis);
            assert!(
                miss.abs() < 2e-3,
                "case {case} {r}: the clay misses the fingertip by {miss}"
            );
            assert_eq!(s.hand_loop().touch(), Touch::Pressing);
        }
    }
}

#[test]
fn a_finger_that_never_reaches_changes_nothing_and_a_grip_pulls() {
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let down = -DVec3::Z;
    // Hovering 1 mm of clay above the plane, and withdrawing: nothing moves.
    let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
    c.place(DVec3::new(1.0, 1.0, 1.0), down, DVec3::Y);
    c.move_to(DVec3::new(1.0, 1.0, 0.05), down, 20)
        .move_to(DVec3::new(1.0, 1.0, 1.0), down, 20);
    let mut s = session(&plane, Regulation::default());
    feed(&mut s, &c.finish("test").unwrap());
    assert_eq!(s.grid(), &plane);
    assert_eq!(s.hand_loop().stats().contacts, 0);
    // The same, with the switch held from the start: the grip catches within 0.05 and pulls
    // the clay up behind the withdrawing finger.
    let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
    c.place(DVec3::new(1.0, 1.0, 1.0), down, DVec3::Y);
    c.press(buttons::PRIMARY);
    c.move_to(DVec3::new(1.0, 1.0, 0.03), down, 20)
        .hold(5)
        .move_to(DVec3::new(1.0, 1.0, 0.5), down, 30);
    c.hold(10)
        .press(0)
        .hold(5)
        .move_to(DVec3::new(1.0, 1.0, 1.5), down, 10);
    let mut s = session(&plane, Regulation::default());
    feed(&mut s, &c.finish("test").unwrap());
    let z = 10.0
        - Probe::new()
            .first_crossing(s.grid(), DVec3::new(1.0, 1.0, 10.0), down, 20.0)
            .unwrap()
            .t;
    assert!((z - 0.5).abs() < 2e-3, "pulled to z = {z}");
    let st = s.hand_loop().stats();
    assert_eq!((st.contacts, st.pulls, st.pushes), (1, 1, 0), "{st:?}");
}

#[test]
fn a_fast_stroke_leaves_no_gaps_and_the_finger_bend_alone_can_press() {
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let down = -DVec3::Z;
    // 6 side in 8 frames (90 side/s): 0.75 side between frames, most of a finger radius.
    let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
    c.place(DVec3::new(-3.0, -2.0, 0.5), down, DVec3::X);
    c.move_to(DVec3::new(-3.0, -2.0, -0.2), down, 10);
    c.path(8, |s| (DVec3::new(-3.0 + 6.0 * s, -2.0, -0.2), down));
    c.move_to(DVec3::new(3.0, -2.0, 0.5), down, 10);
    let mut s = session(&plane, Regulation::default());
    // No hand starts at 4.5 m/s from one sample to the next: the plausibility gate would hold
    // these frames (nendo::hand::filter). The stroke's gap filling is what is tested here.
    s.set_filter(nendo_devices::FilterSettings::off());
    feed(&mut s, &c.finish("test").unwrap());
    for k in 0..=40 {
        let x = -2.5 + 5.0 * k as f64 / 40.0;
        let z = 10.0
            - Probe::new()
                .first_crossing(s.grid(), DVec3::new(x, -2.0, 10.0), down, 20.0)
                .unwrap()
                .t;
        assert!((z + 0.2).abs() < 0.02, "x = {x}: z = {z}");
    }
    assert_eq!(s.hand_loop().stats().strokes, 1);

    // The hand stays still above the plane; only the index finger curls into it.
    let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
    c.set_angles(&[(Joint::IndexMcp, 0.9)]);
    c.place(DVec3::new(2.0, 2.0, -0.25), down, DVec3::X);
    let pressing = c.pose();
    c.set_angles(&[(Joint::IndexMcp, 0.1)]);
    let (above, _) = c.fingertip();
    assert!(
        above.z > 0.1,
        "straight, the fingertip is above the plane: {above}"
    );
    c.set_pose(pressing)
        .hold(5)
        .bend_to(&[(Joint::IndexMcp, 0.9)], 30)
        .hold(30);
    let t = c.finish("test").unwrap();
    assert!(
        t.frames.windows(2).all(|w| w[0].pose == w[1].pose),
        "the tracker never moves"
    );
    let mut s = session(&plane, Regulation::default());
    feed(&mut s, &t);
    let fingertip = s.hand_loop().fingertip().unwrap();
    assert!((fingertip.tip - DVec3::new(2.0, 2.0, -0.25)).length() < 1e-4);
    let miss = (fingertip.tip
        - Probe::new()
            .first_crossing(
                s.grid(),
                fingertip.tip - 2.0 * fingertip.axis,
                fingertip.axis,
                4.0,
            )
            .unwrap()
            .point)
        .dot(fingertip.axis);
    // The finger went 0.25 in. The exact regulation keeps the surface change over the
    // patches least (an L2 fit, not an interpolation), so the bottom of the dent may lie a
    // little off the fingertip: within a tenth of the depth.
    assert!(miss.abs() < 0.025, "{miss}");
}

/// A flat hand (every joint straight) lowered onto the default plane at `degrees` to it, its
/// index fingertip `depth` into the clay at (0.3, 0.2), and held: the trace. It comes from
/// 0.4 side above the plane and 0.4 back along the finger's up direction: every fingertip
/// enters the clay from above (rule 3: a hand put down inside the clay presses nothing).
fn flat_hand_at(degrees: f64, depth: f64) -> Trace {
    let a = degrees.to_radians();
    let axis = DVec3::new(a.cos(), 0.0, -a.sin());
    // The back of the hand up, square to the finger.
    let up = DVec3::new(a.sin(), 0.0, a.cos());
    let tip = DVec3::new(0.3, 0.2, -depth);
    let mut c = Choreography::new(Choreography::WORLD, 120.0).unwrap();
    let flat: Vec<(Joint, f64)> = Joint::ALL.iter().map(|&j| (j, 0.0)).collect();
    c.set_angles(&flat);
    c.place(tip + 0.4 * up + 0.4 * DVec3::Z, axis, up);
    c.move_to(tip, axis, 30).hold(20);
    c.finish("test").unwrap()
}

/// Issue 16: the clay never moves farther than the finger penetrated it, whatever the finger's
/// angle. A flat hand 0.05 side into the plane at 3° to 90°: no control point moves more than
/// 1.5 × 0.05 (before the rule, the push depth was measured along the finger: 1.35 side at
/// 3°, 0.42 at 10°, 0.105 at 30°), the clay is pressed (down, not sideways) and meets the
/// fingertip.
#[test]
fn a_flat_hand_at_any_angle_moves_the_clay_no_farther_than_it_went_in() {
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let depth = 0.05;
    let mut figures = Vec::new();
    for degrees in [3.0, 10.0, 30.0, 60.0, 90.0] {
        let t = flat_hand_at(degrees, depth);
        let mut s = session(&plane, Regulation::default());
        feed(&mut s, &t);
        let tip = s.hand_loop().fingertip().unwrap().tip;
        assert!(
            (tip - DVec3::new(0.3, 0.2, -depth)).length() < 1e-4,
            "{degrees}°: the fingertip is where it was put: {tip}"
        );
        let (mut largest, mut sideways) = (0.0f64, 0.0f64);
        for (a, b) in plane.nodes().iter().zip(s.grid().nodes()) {
            let d = *b - *a;
            largest = largest.max(d.length());
            sideways = sideways.max(d.truncate().length());
        }
        figures.push((degrees, largest, sideways));
        assert!(
            largest <= 1.5 * depth,
            "{degrees}°: a control point moved {largest} for a penetration of {depth}"
        );
        assert!(
            largest >= 0.5 * depth,
            "{degrees}°: the clay was pressed ({largest})"
        );
        // Under the fingertip the clay went down to it.
        let z = 10.0
            - Probe::new()
                .first_crossing(s.grid(), DVec3::new(0.3, 0.2, 10.0), -DVec3::Z, 20.0)
                .unwrap()
                .t;
        assert!(
            (z + depth).abs() < 2e-3,
            "{degrees}°: the clay under the fingertip is at {z}"
        );
        assert_eq!(s.hand_loop().stats().contacts, 1, "{degrees}°");
    }
    eprintln!(
        "flat hand 0.05 into the plane: (angle°, largest move, largest sideways move) {figures:?}"
    );
}

fn session_with(start: &Grid, finger: FingerModel) -> HandSession {
    let hand = Hand::new(HandSize::default(), Choreography::WORLD).unwrap();
    let options = HandOptions {
        finger,
        ..HandOptions::default()
    };
    HandSession::new(start.clone(), Regulation::default(), hand, options).unwrap()
}

/// The largest control-point move and the largest G1 angle of a result.
fn largest_move_and_g1(before: &Grid, after: &Grid) -> (f64, f64) {
    let largest = before
        .nodes()
        .iter()
        .zip(after.nodes())
        .map(|(a, b)| (*b - *a).length())
        .fold(0.0f64, f64::max);
    (largest, continuity::report(after, 17).g1_max_deg)
}

/// Issue 17: the contact rule holds for every finger at once. A flat hand with all five
/// fingers pressing, lowered onto the plane at 3° to 90° (the index 0.05 in, the others as
/// deep as the hand's shape puts them): no control point moves more than 1.5 × the deepest
/// fingertip's penetration (read off the fingertips' heights: the plane is z = 0), all of it
/// one contact, regulated (G1).
#[test]
fn a_flat_hand_with_every_finger_moves_the_clay_no_farther_than_its_deepest_finger() {
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    for degrees in [3.0, 10.0, 30.0, 60.0, 90.0] {
        let t = flat_hand_at(degrees, 0.05);
        let mut s = session_with(&plane, FingerModel::Hand(Fingers::ALL));
        let mut touching = Fingers::one(Part::Palm);
        for f in &t.frames {
            s.feed(f);
            touching = s.hand_loop().touching();
        }
        let tips = s.hand_loop().fingertips().to_vec();
        assert_eq!(tips.len(), 5, "{degrees}°");
        let deepest = tips.iter().map(|(_, f)| -f.tip.z).fold(0.0f64, f64::max);
        let (largest, g1) = largest_move_and_g1(&plane, s.grid());
        assert!(
            largest <= 1.5 * deepest,
            "{degrees}°: a control point moved {largest}, the deepest fingertip is {deepest} in"
        );
        assert!(g1 < 0.01, "{degrees}°: G1 {g1}°");
        assert_eq!(s.hand_loop().stats().contacts, 1, "{degrees}°");
        // Every fingertip below the plane is in the contact.
        for (part, f) in &tips {
            assert_eq!(
                touching.contains(*part),
                f.tip.z < -1e-3,
                "{degrees}°: {} at z = {}",
                part.name(),
                f.tip.z
            );
        }
    }
}

/// The palm presses as a flat contact shape: laid 0.1 into the plane, the clay under its
/// centre goes down to it, no control point moves more than 1.5 × 0.1, the fingers (level,
/// above the clay) do not press, and the surface stays G1.
#[test]
fn the_palm_laid_on_the_plane_presses_as_deep_as_it_went() {
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let depth = 0.1;
    let t = shipped::plane_palm(depth).unwrap();
    let mut s = session_with(&plane, FingerModel::Hand(Fingers::ALL.with(Part::Palm)));
    let mut deepest_touch = Fingers::one(Part::Palm);
    let mut palm_at = DVec3::ZERO;
    for (k, f) in t.frames.iter().enumerate() {
        s.feed(f);
        if k == 6 + 60 + 10 {
            deepest_touch = s.hand_loop().touching();
            palm_at = s
                .hand_loop()
                .fingertips()
                .iter()
                .find(|(p, _)| *p == Part::Palm)
                .unwrap()
                .1
                .tip;
        }
    }
    assert!(
        (palm_at - DVec3::new(0.0, 0.0, -depth)).length() < 1e-3,
        "{palm_at}"
    );
    assert_eq!(deepest_touch, Fingers::one(Part::Palm));
    let z = 10.0
        - Probe::new()
            .first_crossing(s.grid(), DVec3::new(0.0, 0.0, 10.0), -DVec3::Z, 20.0)
            .unwrap()
            .t;
    assert!((z + depth).abs() < 5e-3, "under the palm: {z}");
    let (largest, g1) = largest_move_and_g1(&plane, s.grid());
    assert!(
        largest <= 1.5 * depth && largest >= 0.5 * depth,
        "{largest}"
    );
    assert!(g1 < 0.01, "G1 {g1}°");
    let st = *s.hand_loop().stats();
    assert_eq!((st.contacts, st.pushes), (1, 1), "{st:?}");
}

/// Pinch to grab: thumb and index, open, come in beside the sphere and close on it; together
/// they take hold of the clay (one `move`, no press: the fingertips never reach into the clay)
/// and pull it out with the hand, 1 side along +x; opening the fingers lets go. While held,
/// the clay point taken hold of follows the pinch point; after letting go the surface passes
/// through the last target exactly (the `move` operation lands to rounding), and the one
/// operation the loop commits gives the same surface when applied to the sphere (one undo
/// step).
#[test]
fn a_pinch_takes_hold_of_the_clay_and_pulls_it_with_the_hand() {
    let sphere = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .unwrap();
    let hand = Hand::new(HandSize::default(), Choreography::WORLD).unwrap();
    let pinch = script::pinching(&hand);
    let mut angles = nendo_devices::JointAngles::new();
    for (j, a) in script::POINTING.iter().chain(&pinch) {
        angles.set(*j, *a).unwrap();
    }
    let gap = (hand.local_finger(Digit::Thumb, Some(&angles)).tip()
        - hand.local_finger(Digit::Index, Some(&angles)).tip())
    .length()
        * hand.scale();
    let pinch_distance = DEFAULT_PINCH_CLOSED * hand.finger_length(Digit::Index);
    assert!((pinch_distance - 0.405).abs() < 1e-9, "{pinch_distance}");
    assert!(gap < 0.5 * pinch_distance, "the tips meet: {gap}");

    let t = shipped::sphere_pinch_pull().unwrap();
    let mut s = session_with(&sphere, FingerModel::Hand(PINCH_FINGERS)).logging_contacts();
    let (held, released) = feed_pinch(&mut s, &t, true);
    assert!(held > 90, "held for {held} frames");
    let st = *s.hand_loop().stats();
    assert_eq!(
        (st.contacts, st.holds, st.operations()),
        (1, 1, 1),
        "one contact, the hold: {st:?}"
    );
    let contacts = s.contacts().unwrap();
    let [ops] = contacts else {
        panic!("one operation: {contacts:?}");
    };
    let [Op::Move { at, to, radius }] = ops.as_slice() else {
        panic!("the pinch is a move: {contacts:?}");
    };
    // Taken hold of on the untouched sphere (within its arc error), pulled 1 side along +x: the
    // pinch point drifts by hundredths while the fingers close and open (a little more with
    // the One-Euro filter's lag on the closing and opening joints).
    assert!((at.length() - 3.0).abs() < 1e-4, "held on the sphere: {at}");
    let pull = *to - *at;
    assert!((pull - DVec3::X).length() < 0.025, "{at} → {to}");
    // The surface passes through the target exactly, when letting go and at the end.
    let released = released.expect("the pinch let go");
    for (when, g) in [("released", &released), ("end", s.grid())] {
        let miss = (nendo::surface::nearest(g, *to).unwrap().point - *to).length();
        assert!(
            miss < 1e-9 * 3.0,
            "{when}: the surface misses the target by {miss}"
        );
    }
    // The one operation committed is the whole pinch.
    let mut replayed = sphere.clone();
    nendo::surface::Sculptor::new()
        .apply(
            &mut replayed,
            &Op::Move {
                at: *at,
                to: *to,
                radius: *radius,
            },
            Regulation::default(),
        )
        .unwrap();
    assert_eq!(&replayed, s.grid());
    let (_, g1) = largest_move_and_g1(&sphere, s.grid());
    assert!(g1 < 0.01, "G1 {g1}°");
}

/// Feeds a pinch trace to `s` and finishes it: the frames the pinch held, and the surface
/// when it let go. With `never_presses`, every frame must be free or holding.
fn feed_pinch(s: &mut HandSession, t: &Trace, never_presses: bool) -> (usize, Option<Grid>) {
    let mut held = 0;
    let mut released = None;
    for f in &t.frames {
        let out = s.feed(f);
        if never_presses {
            assert!(
                matches!(out.touch, Touch::Free | Touch::Holding),
                "nothing presses: {:?}",
                out.touch
            );
        }
        if out.touch == Touch::Holding {
            held += 1;
        } else if held > 0 && released.is_none() {
            released = Some(s.grid().clone());
        }
    }
    s.finish();
    (held, released)
}

/// The pinch with a mirror (x = 0): the hold moves the clay together with its mirror image as
/// one operation, so the sphere stays symmetric to 1e-12 relative and is drawn out on both
/// sides, to the pinch's target and to its mirror image.
#[test]
fn a_mirrored_pinch_pulls_both_sides() {
    use nendo::surface::{Plane, Symmetry, symmetry_error};
    let sphere = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .unwrap();
    let t = shipped::sphere_pinch_pull().unwrap();
    let mut s = session_with(&sphere, FingerModel::Hand(PINCH_FINGERS)).logging_contacts();
    s.set_mirror(Some(Symmetry::of(&sphere, Plane::X).unwrap()));
    let (held, released) = feed_pinch(&mut s, &t, false);
    assert!(held > 90, "held for {held} frames");
    let asym = symmetry_error(s.grid(), Plane::X).relative;
    assert!(asym < 1e-12, "asymmetry {asym:e}");
    let contacts = s.contacts().unwrap();
    let Some(Op::Move { to, .. }) = contacts
        .iter()
        .find_map(|ops| matches!(ops.as_slice(), [Op::Move { .. }]).then(|| ops[0].clone()))
    else {
        panic!("the pinch is a move: {contacts:?}");
    };
    let released = released.expect("the pinch let go");
    let asym = symmetry_error(&released, Plane::X).relative;
    assert!(asym < 1e-12, "asymmetry when the pinch lets go {asym:e}");
    for target in [to, Plane::X.reflect(to)] {
        let outward = DVec3::new(target.x.signum(), 0.0, 0.0);
        let hit = Probe::new()
            .first_crossing(&released, target + 2.0 * outward, -outward, 4.0)
            .unwrap();
        assert!(
            (hit.point - target).length() < 0.1,
            "{} vs {target}",
            hit.point
        );
    }
}

/// The fingers the shipped pinch is made with (its scene names them): thumb and index; the
/// other three, curled out of the way, would brush the sphere on the way in.
const PINCH_FINGERS: Fingers = Fingers::THUMB_AND_INDEX;

/// The press gesture of `nendo emulate` (the index straight down 0.3 side into the plane, the
/// other fingers curled in the pointing pose) with every finger pressing: only the index goes
/// in, so the clay moves no farther than the index went (0.3), and at every frame a finger is
/// in the contact only while its tip is below the plane. A curled finger's tip points back up
/// out of the fist, 1.5 side above the plane; its capsule used to run its whole length
/// (1.9 side) straight back from that tip, through the plane, and pressed the clay by the
/// tip's height above it (a dent 2.4 deep).
#[test]
fn in_the_press_gesture_only_the_index_presses_and_no_deeper_than_it_went() {
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    for scale in [20.0, 21.5] {
        let world = nendo_devices::WorldFromTracker {
            translation: [0.0, 0.0, 0.0],
            rotation_wxyz: [1.0, 0.0, 0.0, 0.0],
            scale,
        };
        let t = script::Gesture::Press.trace(world, 100.0).unwrap();
        let hand = Hand::new(HandSize::default(), world).unwrap();
        let options = HandOptions {
            finger: FingerModel::Hand(Fingers::ALL),
            ..HandOptions::default()
        };
        let mut s = HandSession::new(plane.clone(), Regulation::default(), hand, options).unwrap();
        let mut deepest = (0.0f64, Vec::new());
        for f in &t.frames {
            s.feed(f);
            let tips = s.hand_loop().fingertips().to_vec();
            let touching = s.hand_loop().touching();
            for (part, tip) in &tips {
                assert!(
                    !touching.contains(*part) || tip.tip.z < 1e-3,
                    "scale {scale}: {} presses with its tip {} above the plane",
                    part.name(),
                    tip.tip.z
                );
            }
            let d = tips.iter().map(|(_, f)| -f.tip.z).fold(0.0f64, f64::max);
            if d > deepest.0 {
                deepest = (d, tips);
            }
        }
        let heights: Vec<(&str, f64)> =
            deepest.1.iter().map(|(p, f)| (p.name(), f.tip.z)).collect();
        println!("scale {scale}: fingertip heights at the deepest frame {heights:?}");
        let index = heights.iter().find(|(n, _)| *n == "index").unwrap().1;
        assert!((index + 0.3).abs() < 1e-3, "scale {scale}: {heights:?}");
        for (name, z) in &heights {
            assert!(
                *name == "index" || *z > index + 0.5,
                "scale {scale}: {heights:?}"
            );
        }
        let (largest, g1) = largest_move_and_g1(&plane, s.grid());
        assert!(
            (0.5 * 0.3..=1.5 * 0.3).contains(&largest),
            "scale {scale}: a control point moved {largest}; fingertips at the deepest frame {heights:?}"
        );
        assert!(g1 < 0.01, "scale {scale}: G1 {g1}°");
    }
}

/// [`HandLoop::starting`] — what `nendo replay --auto-refine` refines for — says a frame
/// starts a contact exactly when feeding it to the loop starts one, with the loop's own first
/// placements (a push each, from `E − h·m̂` along `m̂`) or, for a pinch, the point held: over
/// the shipped traces but the long pot (one finger, every finger and the palm, a pinch, the
/// mouse's ray) and the gestures of `nendo emulate` with every finger pressing the plane.
#[test]
fn what_a_frame_starts_is_what_the_loop_starts() {
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let mut cases: Vec<(String, Grid, FingerModel, Trace)> = shipped::shipped()
        .unwrap()
        .into_iter()
        .filter(|s| s.name != "tube-pot")
        .map(|s| (s.name.to_owned(), s.grid().unwrap(), s.finger, s.trace))
        .collect();
    for g in script::Gesture::ALL {
        cases.push((
            g.name().to_owned(),
            plane.clone(),
            FingerModel::Hand(Fingers::ALL),
            g.trace(Choreography::WORLD, 120.0).unwrap(),
        ));
    }
    let (mut presses, mut holds) = (0, 0);
    for (name, mut grid, finger, trace) in cases {
        let hand = Hand::new(trace.header.hand, trace.header.world_from_tracker).unwrap();
        let options = HandOptions {
            finger,
            ..HandOptions::default()
        };
        let mut hl = HandLoop::new(hand, options).unwrap();
        for (k, f) in trace.frames.iter().enumerate() {
            let free = hl.touch() == Touch::Free;
            let contacts = hl.stats().contacts;
            let predicted = hl.starting(f, &grid);
            hl.frame(f, &mut grid, Regulation::default());
            if !free {
                assert!(predicted.is_none(), "{name} frame {k}");
                continue;
            }
            let started = hl.stats().contacts > contacts;
            assert_eq!(predicted.is_some(), started, "{name} frame {k}");
            let Some(ops) = predicted else {
                continue;
            };
            if hl.touch() == Touch::Holding {
                holds += 1;
                assert!(
                    matches!(ops[..], [Op::Move { at, to, .. }] if at == to),
                    "{name} frame {k}: {ops:?}"
                );
                continue;
            }
            presses += 1;
            let placements = hl.placements();
            assert_eq!(ops.len(), placements.len(), "{name} frame {k}");
            for (op, p) in ops.iter().zip(&placements) {
                let Op::Push { at, dir, .. } = op else {
                    panic!("{name} frame {k}: {op:?}");
                };
                // The first frame's correction (rule 7) changes the depth, not the anchor.
                assert_eq!(*dir, p.dir, "{name} frame {k}");
                let anchor = p.tip - p.depth * p.dir;
                assert!(
                    (*at - anchor).length() < 1e-9,
                    "{name} frame {k}: {at} {anchor}"
                );
            }
        }
    }
    // Both kinds of start were met (12 presses and 1 pinch taking hold when written).
    assert!(
        presses >= 8 && holds >= 1,
        "{presses} presses, {holds} holds"
    );
}
