//! The kinematic hand against an independent chain of rotations, and its inverse, on random
//! cases with fixed seeds.

use glam::{DQuat, DVec3};
use nendo::hand::{Digit, Hand};
use nendo_devices::profile::Side;
use nendo_devices::{HandSize, Joint, JointAngles, TrackerPose, WorldFromTracker};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn random_joints(rng: &mut ChaCha8Rng) -> JointAngles {
    let mut a = JointAngles::new();
    for j in Joint::ALL {
        // Skip some joints: a glove that does not measure them.
        if rng.gen_bool(0.2) {
            continue;
        }
        let abduction = j.name().contains("abduction");
        let range = if abduction { -0.4..0.4 } else { -0.3..1.5 };
        a.set(j, rng.gen_range(range)).unwrap();
    }
    a
}

fn random_unit(rng: &mut ChaCha8Rng) -> DVec3 {
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

fn random_rotation(rng: &mut ChaCha8Rng) -> DQuat {
    DQuat::from_axis_angle(random_unit(rng), rng.gen_range(0.0..std::f64::consts::PI))
}

fn random_world(rng: &mut ChaCha8Rng) -> WorldFromTracker {
    let q = random_rotation(rng);
    WorldFromTracker {
        translation: [
            rng.gen_range(-5.0..5.0),
            rng.gen_range(-5.0..5.0),
            rng.gen_range(-5.0..5.0),
        ],
        rotation_wxyz: [q.w, q.x, q.y, q.z],
        scale: rng.gen_range(0.5..50.0),
    }
}

fn random_size(rng: &mut ChaCha8Rng) -> HandSize {
    let d = HandSize::default();
    let f = rng.gen_range(0.8..1.25);
    let g = rng.gen_range(0.9..1.1);
    let scale = |l: nendo_devices::profile::FingerLengths| nendo_devices::profile::FingerLengths {
        proximal: l.proximal * f,
        middle: l.middle * f * g,
        distal: l.distal * f,
    };
    HandSize {
        side: if rng.gen_bool(0.5) {
            Side::Right
        } else {
            Side::Left
        },
        palm_length: d.palm_length * f,
        palm_width: d.palm_width * f,
        thumb: scale(d.thumb),
        index: scale(d.index),
        middle: scale(d.middle),
        ring: scale(d.ring),
        pinky: scale(d.pinky),
    }
}

/// The finger's joints by an independent construction: yaw the rest direction about the
/// palm normal, then turn each segment about the finger's own lateral axis by the summed
/// flexion, with quaternions.
fn reference_finger(size: &HandSize, digit: Digit, a: &JointAngles) -> [DVec3; 4] {
    let s = if size.side == Side::Right { 1.0 } else { -1.0 };
    let get = |j: Joint| a.get(j);
    let (l, w) = (size.palm_length, size.palm_width);
    let t = 0.3 * w;
    let (im, mr, rp) = (
        get(Joint::IndexMiddleAbduction).unwrap_or(0.0),
        get(Joint::MiddleRingAbduction).unwrap_or(0.0),
        get(Joint::RingPinkyAbduction).unwrap_or(0.0),
    );
    let (base, spread, flex, lengths) = match digit {
        Digit::Thumb => {
            let mcp = get(Joint::ThumbMcp).unwrap_or(0.0);
            let ip = get(Joint::ThumbIp).unwrap_or(mcp);
            (
                DVec3::new(-0.2 * l, s * 0.3 * w, -0.5 * t),
                25f64.to_radians() + im + get(Joint::ThumbIndexAbduction).unwrap_or(0.0),
                [0.0, mcp, ip],
                size.thumb,
            )
        }
        _ => {
            let (y, spread, joints, lengths) = match digit {
                Digit::Index => (
                    0.375,
                    im,
                    [Joint::IndexMcp, Joint::IndexPip, Joint::IndexDip],
                    size.index,
                ),
                Digit::Middle => (
                    0.125,
                    0.0,
                    [Joint::MiddleMcp, Joint::MiddlePip, Joint::MiddleDip],
                    size.middle,
                ),
                Digit::Ring => (
                    -0.125,
                    -mr,
                    [Joint::RingMcp, Joint::RingPip, Joint::RingDip],
                    size.ring,
                ),
                _ => (
                    -0.375,
                    -mr - rp,
                    [Joint::PinkyMcp, Joint::PinkyPip, Joint::PinkyDip],
                    size.pinky,
                ),
            };
            let mcp = get(joints[0]).unwrap_or(0.0);
            let pip = get(joints[1]).unwrap_or(mcp);
            let dip = get(joints[2]).unwrap_or(2.0 / 3.0 * pip);
            (
                DVec3::new(0.5 * l, s * y * w, -0.5 * t),
                spread,
                [mcp, pip, dip],
                lengths,
            )
        }
    };
    let f = DQuat::from_axis_angle(DVec3::Z, s * spread) * DVec3::X;
    // The direction a segment curls toward, at right angles to `f`.
    let toward = if digit == Digit::Thumb {
        let g = DQuat::from_axis_angle(DVec3::Z, -s * std::f64::consts::FRAC_PI_2) * f;
        let roll = get(Joint::ThumbRoll).unwrap_or(0.0);
        DQuat::from_axis_angle(s * f, roll) * g
    } else {
        -DVec3::Z
    };
    let axis = f.cross(toward).normalize();
    let mut points = [base; 4];
    let mut theta = 0.0;
    for (k, len) in [lengths.proximal, lengths.middle, lengths.distal]
        .into_iter()
        .enumerate()
    {
        theta += flex[k];
        points[k + 1] = points[k] + len * (DQuat::from_axis_angle(axis, theta) * f);
    }
    points
}

#[test]
fn the_chain_matches_rotations_about_each_fingers_own_axes() {
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    for case in 0..400 {
        let size = random_size(&mut rng);
        let hand = Hand::new(size, WorldFromTracker::default()).unwrap();
        let joints = random_joints(&mut rng);
        for digit in Digit::ALL {
            let got = hand.local_finger(digit, Some(&joints)).points;
            let want = reference_finger(&size, digit, &joints);
            for k in 0..4 {
                assert!(
                    (got[k] - want[k]).length() < 1e-14,
                    "case {case} {digit} point {k}: {} vs {}",
                    got[k],
                    want[k]
                );
            }
        }
    }
}

#[test]
fn placed_hands_keep_their_shape_scaled_by_the_transform() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for case in 0..300 {
        let size = random_size(&mut rng);
        let world = random_world(&mut rng);
        let hand = Hand::new(size, world).unwrap();
        let joints = random_joints(&mut rng);
        let pose = TrackerPose::new(
            DVec3::new(
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
            ),
            random_rotation(&mut rng),
        )
        .unwrap();
        let placed = hand.pose(&pose, Some(&joints));
        for digit in Digit::ALL {
            let local = hand.local_finger(digit, Some(&joints));
            let chain = placed.finger(digit);
            for k in 0..3 {
                let a = (local.points[k + 1] - local.points[k]).length() * world.scale;
                let b = (chain.points[k + 1] - chain.points[k]).length();
                assert!((a - b).abs() < 1e-12 * world.scale, "case {case} {digit}");
            }
            // Angles between segments survive the placement.
            let bend = |p: &[DVec3; 4]| {
                let (a, b) = (p[2] - p[1], p[3] - p[2]);
                a.cross(b).length().atan2(a.dot(b))
            };
            assert!(
                (bend(&local.points) - bend(&chain.points)).abs() < 1e-9,
                "case {case}"
            );
            // The sensor sits where the transform puts the tracked point.
            let (at, _) = world.apply(&pose);
            assert!((placed.sensor - at).length() < 1e-9, "case {case}");
        }
    }
}

#[test]
fn the_inverse_puts_any_fingertip_anywhere_pointing_any_way() {
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    let mut checked = 0;
    for case in 0..500 {
        let size = random_size(&mut rng);
        let world = random_world(&mut rng);
        let hand = Hand::new(size, world).unwrap();
        let joints = random_joints(&mut rng);
        let digit = Digit::ALL[rng.gen_range(0..5)];
        let tip = DVec3::new(
            rng.gen_range(-6.0..6.0),
            rng.gen_range(-6.0..6.0),
            rng.gen_range(-6.0..6.0),
        );
        let dir = random_unit(&mut rng);
        let up = random_unit(&mut rng);
        if dir.cross(up).length() < 1e-3 {
            continue;
        }
        let Some(pose) = hand.pose_for_fingertip(digit, Some(&joints), tip, dir, up) else {
            panic!("case {case}: no pose");
        };
        let placed = hand.pose(&pose, Some(&joints));
        let f = placed.finger(digit);
        let tol = 1e-12 * (1.0 + world.scale) * 50.0;
        assert!(
            (f.tip() - tip).length() < tol,
            "case {case}: {} vs {tip}",
            f.tip()
        );
        assert!((f.direction() - dir).length() < 1e-10, "case {case}");
        // The back of the hand turns toward `up` as far as the finger allows: the component
        // of the back across the finger's direction points along that of `up`.
        let back = placed.orientation * DVec3::Z;
        let up_across = up - up.dot(dir) * dir;
        assert!(back.dot(up_across) > 0.0, "case {case}");
        checked += 1;
    }
    assert!(checked > 450);
}

#[test]
fn the_mouse_hand_puts_its_fingertip_on_the_tracked_point() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let hand = Hand::new(HandSize::default(), WorldFromTracker::default()).unwrap();
    let profile = nendo_devices::profile::MouseProfile::default();
    let mouse = nendo_devices::MouseDevice::new(profile);
    for case in 0..200 {
        let ray = nendo_devices::ViewRay {
            origin: DVec3::new(
                rng.gen_range(-10.0..10.0),
                rng.gen_range(-10.0..10.0),
                rng.gen_range(-10.0..10.0),
            ),
            direction: random_unit(&mut rng) * rng.gen_range(0.1..10.0),
        };
        let frame = mouse.frame(nendo_devices::Timestamp(case), ray, 0).unwrap();
        let placed =
            hand.pose_at_fingertip(&frame.pose.unwrap(), frame.joints.as_ref(), Digit::Index);
        let f = placed.finger(Digit::Index);
        let want = ray.origin + mouse.depth() * ray.direction.normalize();
        assert!((f.tip() - want).length() < 1e-12 * 20.0, "case {case}");
        assert!(
            (f.direction() - ray.direction.normalize()).length() < 1e-12,
            "case {case}"
        );
    }
}
