//! Contact of the virtual finger with the surface: the probe against exact algebra on random
//! rays, and the loop's contact rules on scripted motions, with fixed seeds.

use glam::DVec3;
use nendo::hand::script::Choreography;
use nendo::hand::{Hand, HandOptions, Probe, Session, Touch};
use nendo::surface::{Grid, Primitive, PrimitiveParams, Regulation};
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

fn session(start: &Grid, regulation: Regulation) -> Session {
    let hand = Hand::new(HandSize::default(), Choreography::WORLD).unwrap();
    Session::new(start.clone(), regulation, hand, HandOptions::default()).unwrap()
}

fn feed(s: &mut Session, t: &Trace) {
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
    assert!(miss.abs() < 2e-3, "{miss}");
}
