//! Replays of the shipped traces through the whole hand loop, checked where the surface moved,
//! by how much, and how continuous it stayed.

use glam::DVec3;
use nendo::hand::{
    Digit, FingerModel, Fingers, Hand, HandOptions, HandSession, LoopStats, Part, Probe,
};
use nendo::surface::{Grid, Primitive, PrimitiveParams, Regulation, continuity};
use nendo_devices::Trace;
use std::path::Path;

fn trace(name: &str) -> Trace {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("devices/traces")
        .join(format!("{name}.trace"));
    Trace::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn replay(trace: &Trace, start: &Grid, regulation: Regulation) -> (Grid, LoopStats) {
    // The shipped glove traces before the whole hand were scripted for the index finger alone
    // (their scene says so); the mouse's is a ray.
    let finger = match FingerModel::for_profile_name(trace.header.profile.as_deref()) {
        FingerModel::Ray => FingerModel::Ray,
        FingerModel::Hand(_) => FingerModel::digit(Digit::Index),
    };
    replay_with(trace, start, regulation, finger)
}

fn replay_with(
    trace: &Trace,
    start: &Grid,
    regulation: Regulation,
    finger: FingerModel,
) -> (Grid, LoopStats) {
    let hand = Hand::new(trace.header.hand, trace.header.world_from_tracker).unwrap();
    let options = HandOptions {
        finger,
        ..HandOptions::default()
    };
    let mut session = HandSession::new(start.clone(), regulation, hand, options).unwrap();
    for f in &trace.frames {
        session.feed(f);
    }
    session.finish();
    let stats = *session.hand_loop().stats();
    (session.into_grid(), stats)
}

fn build(p: Primitive) -> Grid {
    p.build(&PrimitiveParams::default()).unwrap()
}

/// Distance from `origin` along `dir` to the surface.
fn along(grid: &Grid, origin: DVec3, dir: DVec3) -> f64 {
    Probe::new()
        .first_crossing(grid, origin, dir, 50.0)
        .unwrap_or_else(|| panic!("no surface from {origin} along {dir}"))
        .t
}

fn finite(grid: &Grid) -> bool {
    grid.nodes().iter().all(|p| p.is_finite())
}

/// Continuity after regulation: C0 exact, G1 to rounding, a tangent plane at every pole.
fn assert_g1(name: &str, grid: &Grid) {
    let c = continuity::report(grid, 33);
    assert!(c.g0_gap < 1e-12, "{name}: G0 {}", c.g0_gap);
    assert!(c.g1_max_deg < 1e-6, "{name}: G1 max {}°", c.g1_max_deg);
    assert_eq!(c.undefined_normals, 0, "{name}");
    for p in &c.poles {
        assert!(
            p.spread_deg < 1e-6,
            "{name}: pole {:?} spread {}°",
            p.end,
            p.spread_deg
        );
    }
}

#[test]
fn sphere_push_at_the_pole_and_pull_at_the_equator() {
    let sphere = build(Primitive::Sphere);
    let t = trace("sphere-push-pull");
    let (g, st) = replay(&t, &sphere, Regulation::default());
    assert!(finite(&g));
    assert_eq!(
        (st.contacts, st.pushes, st.pulls, st.strokes),
        (2, 1, 1, 0),
        "{st:?}"
    );
    // The pole went down 0.6 (the fingertip's depth), the equator at longitude 0 out by 0.6.
    let top = 10.0 - along(&g, DVec3::new(0.0, 0.0, 10.0), -DVec3::Z);
    assert!((top - 2.4).abs() < 0.01, "pole at z = {top}");
    let out = 10.0 - along(&g, DVec3::new(10.0, 0.0, 0.0), -DVec3::X);
    assert!((out - 3.6).abs() < 0.01, "equator at x = {out}");
    // The far side did not move (to the probe's rounding: from −10 z the line meets the south
    // pole, where eight patches meet, each solving for the same point).
    for d in [DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z] {
        let (a, b) = (along(&g, -10.0 * d, d), along(&sphere, -10.0 * d, d));
        assert!((a - b).abs() < 1e-12, "{d}: {a} {b}");
    }
    assert_g1("sphere", &g);
    let south = g.pole(nendo::surface::PoleEnd::Start).unwrap();
    assert_eq!(g.nodes()[south.node], sphere.nodes()[south.node]);
    // Every regulation method moves the same places, without NaN (g2 included: its contact
    // projects the contact's exact net each frame, so a held contact does not drift).
    for r in Regulation::ALL {
        let (g, _) = replay(&t, &sphere, r);
        assert!(finite(&g), "{r}");
        let top = 10.0 - along(&g, DVec3::new(0.0, 0.0, 10.0), -DVec3::Z);
        assert!((top - 2.4).abs() < 0.05, "{r}: pole at z = {top}");
        let out = 10.0 - along(&g, DVec3::new(10.0, 0.0, 0.0), -DVec3::X);
        // g2 projects the pulled net onto curvature-continuous ones over a window two patches
        // past the pull (on this 8 × 4 sphere, the whole grid): the bump comes out wider and
        // lower, its top at 3.42 — the same figure the contact applied at once gives.
        let reach = if r == Regulation::G2 { 0.25 } else { 0.05 };
        assert!((out - 3.6).abs() < reach, "{r}: equator at x = {out}");
    }
}

#[test]
fn plane_groove_is_as_deep_as_the_fingertip_went() {
    let plane = build(Primitive::Plane);
    let (g, st) = replay(&trace("plane-groove"), &plane, Regulation::default());
    assert!(finite(&g));
    assert_eq!((st.contacts, st.strokes), (1, 1), "{st:?}");
    let z = |x: f64, y: f64| 10.0 - along(&g, DVec3::new(x, y, 10.0), -DVec3::Z);
    // Along the stroke the fingertip was 0.3 below the plane.
    for k in 0..=12 {
        let x = -3.0 + 0.5 * k as f64;
        let d = z(x, 0.0);
        assert!((-0.33..=-0.29).contains(&d), "groove at x = {x}: z = {d}");
    }
    // Across it the groove rises to the plane within the finger radius, monotonically.
    for x in [-2.0, 0.0, 2.0] {
        let profile: Vec<f64> = (0..=10).map(|k| z(x, 0.1 * k as f64)).collect();
        for w in profile.windows(2) {
            assert!(w[1] >= w[0] - 1e-9, "x = {x}: {profile:?}");
        }
        assert!(z(x, 1.0) > -0.06, "x = {x}: {profile:?}");
    }
    // Far from it nothing moved, and before the start and after the end the plane is flat.
    for (x, y) in [(0.0, 3.0), (0.0, -3.0), (-4.8, 3.5), (4.8, -4.8)] {
        assert_eq!(z(x, y), 0.0, "({x}, {y})");
    }
    assert_g1("plane", &g);
}

#[test]
fn tube_becomes_a_pot() {
    let tube = build(Primitive::Tube);
    assert_eq!(tube.patch_count(), 128);
    let (g, st) = replay(&trace("tube-pot"), &tube, Regulation::default());
    assert!(finite(&g));
    assert!(st.contacts >= 100 && st.strokes >= 1, "{st:?}");
    // Mean radius around the axis at height z, and its spread, from 32 rays out of the axis.
    let radius = |g: &Grid, z: f64| {
        let r: Vec<f64> = (0..32)
            .map(|k| {
                let phi = std::f64::consts::TAU * k as f64 / 32.0;
                along(
                    g,
                    DVec3::new(0.0, 0.0, z),
                    DVec3::new(phi.cos(), phi.sin(), 0.0),
                )
            })
            .collect();
        let mean = r.iter().sum::<f64>() / r.len() as f64;
        let spread = r.iter().fold(0.0f64, |s, x| s.max((x - mean).abs()));
        (mean, spread)
    };
    let (belly, _) = radius(&g, 3.2);
    let (shoulder, _) = radius(&g, 4.0);
    let (neck, neck_spread) = radius(&g, 5.0);
    let (lip, _) = radius(&g, 5.95);
    // The tube was 2 across everywhere above its round bottom.
    assert!(belly > 2.6, "belly {belly}");
    assert!(shoulder > 2.1 && shoulder < belly, "shoulder {shoulder}");
    assert!(neck < 1.45, "neck {neck}");
    // Round to 0.17 (0.11 when a push went along the normal where the finger's axis crossed
    // the surface; since issue 25 along the normal through the fingertip, the tip's true
    // depth: on the sloping shoulder the two differ by 15°, and the 16 pushes of the neck
    // ring leave slightly deeper scallops; the belly came out rounder, 0.04 from 0.06).
    assert!(neck_spread < 0.17, "neck roundness {neck_spread}");
    assert!(lip > neck + 0.5, "lip {lip}");
    // The round bottom below the belly's reach (and one row of regulated groups) did not move.
    for z in [0.2, 0.4] {
        assert_eq!(radius(&g, z), radius(&tube, z), "z = {z}");
    }
    assert_eq!(g.nodes()[0], tube.nodes()[0], "the pole");
    assert_g1("pot", &g);
}

#[test]
fn mouse_click_drag_pull_and_wheel_on_the_sphere() {
    let sphere = build(Primitive::Sphere);
    let t = trace("mouse-sphere");
    let hand = Hand::new(t.header.hand, t.header.world_from_tracker).unwrap();
    let options = HandOptions {
        finger: FingerModel::Ray,
        ..HandOptions::default()
    };
    let mut session =
        HandSession::new(sphere.clone(), Regulation::default(), hand, options).unwrap();
    let eye = nendo::hand::shipped::MOUSE_CAMERA;
    let on = |lat: f64, lon: f64| {
        let (lat, lon): (f64, f64) = (lat.to_radians(), lon.to_radians());
        3.0 * DVec3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin())
    };
    // How far the surface under a point of the sphere moved along the view ray (+: toward
    // the eye).
    let moved = |g: &Grid, p: DVec3| along(&sphere, eye, p - eye) - along(g, eye, p - eye);
    let mut released = 0;
    let mut held = 0;
    for f in &t.frames {
        session.feed(f);
        if held != 0 && f.buttons == 0 {
            released += 1;
            let g = session.grid();
            match released {
                // Left click: pushed by the click depth along the view ray.
                1 => assert!(
                    (moved(g, on(25.0, -120.0)) + 0.3).abs() < 0.01,
                    "{}",
                    moved(g, on(25.0, -120.0))
                ),
                // Left drag: a groove along the parallel −20°, the click depth deep (the big
                // patches of the 8 × 4 sphere fit the swept groove to within a tenth).
                2 => {
                    for lon in [-110.0, -90.0, -70.0] {
                        let d = moved(g, on(-20.0, lon));
                        assert!((-0.32..=-0.26).contains(&d), "groove at {lon}°: {d}");
                    }
                }
                // Right click: pulled back by the click depth.
                3 => assert!(
                    (moved(g, on(30.0, -60.0)) - 0.3).abs() < 0.01,
                    "{}",
                    moved(g, on(30.0, -60.0))
                ),
                // The wheel took the last press 5 steps of 0.02 deeper.
                4 => assert!(
                    (moved(g, on(5.0, -90.0)) + 0.4).abs() < 0.01,
                    "{}",
                    moved(g, on(5.0, -90.0))
                ),
                _ => unreachable!(),
            }
        }
        held = f.buttons;
    }
    assert_eq!(released, 4);
    let st = *session.hand_loop().stats();
    assert_eq!(
        (st.contacts, st.pushes, st.pulls, st.strokes),
        (4, 2, 1, 1),
        "{st:?}"
    );
    assert!(finite(session.grid()));
    assert_g1("mouse", session.grid());
}

#[test]
fn a_replay_is_a_pure_function_of_trace_surface_and_options() {
    let t = trace("tube-pot");
    let tube = build(Primitive::Tube);
    let (a, sa) = replay(&t, &tube, Regulation::default());
    let (b, sb) = replay(&t, &tube, Regulation::default());
    assert_eq!(sa, sb);
    assert_eq!(a.nodes(), b.nodes());
    assert_eq!(a, b);
}

#[test]
fn sphere_pinch_pull_draws_a_nose_out_with_one_move() {
    let sphere = build(Primitive::Sphere);
    let (g, st) = replay_with(
        &trace("sphere-pinch-pull"),
        &sphere,
        Regulation::default(),
        FingerModel::Hand(PINCH_FINGERS),
    );
    assert!(finite(&g));
    // One contact, the hold: the fingertips never press.
    assert_eq!(
        (st.contacts, st.holds, st.operations()),
        (1, 1, 1),
        "{st:?}"
    );
    // The clay at the equator, longitude 0, came out with the pinch, 1 side.
    let out = 10.0 - along(&g, DVec3::new(10.0, 0.0, 0.0), -DVec3::X);
    assert!((out - 4.0).abs() < 0.02, "the nose reaches x = {out}");
    eprintln!("sphere pinch pull: the nose reaches x = {out}");
    // Only the patches next to longitude 0 moved (columns 0, 1, 6, 7 of the 8 × 4 sphere);
    // the far side, the top and the bottom did not.
    let m = sphere.patches_u();
    for p in 0..m * sphere.patches_v() {
        let moved = sphere
            .patch_node_ids(p % m, p / m)
            .iter()
            .any(|&id| sphere.nodes()[id] != g.nodes()[id]);
        assert_eq!(moved, [0, 1, 6, 7].contains(&(p % m)), "patch {p}");
    }
    for d in [DVec3::X, DVec3::Z, -DVec3::Z] {
        let (now, before) = (along(&g, -10.0 * d, d), along(&sphere, -10.0 * d, d));
        assert!((now - before).abs() < 1e-12, "{d}: {now} vs {before}");
    }
    assert_g1("pinch", &g);
}

/// Issue 17: "pinching a thin wall between thumb and index from both sides presses both
/// sides". The tube's wall is one sheet; the thumb presses it in from outside, the index out
/// from inside, 0.15 side each, at spots 1 side apart along it: the wall near the thumb moves
/// in (toward the index), the wall near the index moves out (toward the thumb), each as far
/// as its finger went within 0.02 side; one contact, nothing held, the far side and the
/// bottom untouched.
#[test]
fn tube_rim_pinch_presses_both_sides_of_the_wall_toward_each_other() {
    use nendo::hand::shipped::{RIM_INDEX, RIM_THUMB};
    let tube = build(Primitive::Tube);
    let (g, st) = replay_with(
        &trace("tube-rim-pinch"),
        &tube,
        Regulation::default(),
        FingerModel::Hand(PINCH_FINGERS),
    );
    assert!(finite(&g));
    assert_eq!(
        (st.contacts, st.holds, st.operations()),
        (1, 0, 1),
        "{st:?}"
    );
    // The wall's distance from the axis at azimuth φ, height z.
    let radius = |g: &Grid, phi: f64, z: f64| {
        along(
            g,
            DVec3::new(0.0, 0.0, z),
            DVec3::new(phi.cos(), phi.sin(), 0.0),
        )
    };
    let thumb_phi = RIM_THUMB.y.atan2(RIM_THUMB.x);
    let mut figures = Vec::new();
    for dz in [-0.1, 0.0, 0.1] {
        for dphi in [-0.05, 0.0, 0.05] {
            assert!((radius(&tube, thumb_phi + dphi, RIM_THUMB.z + dz) - 2.0).abs() < 1e-6);
            let outer = radius(&g, thumb_phi + dphi, RIM_THUMB.z + dz);
            let inner = radius(&g, dphi, RIM_INDEX.z + dz);
            figures.push((outer, inner));
            assert!(
                (1.85 - 0.02..2.0 - 0.08).contains(&outer),
                "near the thumb the wall moves in: r = {outer}"
            );
            assert!(
                (2.0 + 0.08..2.15 + 0.02).contains(&inner),
                "near the index the wall moves out: r = {inner}"
            );
        }
    }
    // The far side and the bottom did not move.
    let pi = std::f64::consts::PI;
    assert_eq!(radius(&g, pi, 4.5), radius(&tube, pi, 4.5));
    let bottom = |g: &Grid| along(g, DVec3::new(0.0, 0.0, -5.0), DVec3::Z);
    assert_eq!(bottom(&g), bottom(&tube));
    assert_g1("rim pinch", &g);
    eprintln!("tube rim pinch, wall radius (near the thumb, near the index): {figures:?}");
}

#[test]
fn plane_palm_presses_as_deep_as_the_palm_went() {
    let plane = build(Primitive::Plane);
    let (g, st) = replay_with(
        &trace("plane-palm"),
        &plane,
        Regulation::default(),
        FingerModel::Hand(Fingers::ALL.with(Part::Palm)),
    );
    assert!(finite(&g));
    assert_eq!((st.contacts, st.pushes), (1, 1), "{st:?}");
    let z = |x: f64, y: f64| 10.0 - along(&g, DVec3::new(x, y, 10.0), -DVec3::Z);
    assert!(
        (z(0.0, 0.0) + 0.1).abs() < 5e-3,
        "under the palm: {}",
        z(0.0, 0.0)
    );
    let largest = plane
        .nodes()
        .iter()
        .zip(g.nodes())
        .map(|(a, b)| (*b - *a).length())
        .fold(0.0f64, f64::max);
    assert!(largest <= 0.15, "a control point moved {largest}");
    assert_eq!(z(4.0, 4.0), 0.0);
    assert_g1("palm", &g);
}

/// G1 ≤ 0.01° after every shipped trace, replayed with the fingers it was made for.
#[test]
fn every_shipped_trace_leaves_the_surface_g1() {
    for s in nendo::hand::shipped::shipped().unwrap() {
        let (g, _) = replay_with(
            &trace(s.name),
            &s.grid().unwrap(),
            Regulation::default(),
            s.finger,
        );
        let c = continuity::report(&g, 17);
        assert!(c.g1_max_deg <= 0.01, "{}: G1 {}°", s.name, c.g1_max_deg);
        assert!(c.g0_gap < 1e-9, "{}: G0 {}", s.name, c.g0_gap);
    }
}

/// The fingers the shipped pinch is made with (its scene names them): thumb and index; the
/// other three, curled out of the way, would brush the sphere on the way in.
const PINCH_FINGERS: Fingers = Fingers::THUMB_AND_INDEX;
