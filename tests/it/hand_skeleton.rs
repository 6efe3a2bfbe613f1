//! Skeleton hands through the hand model and the hand loop: a glove frame and its skeleton
//! place the same hand; a VMC performer's skeleton, recorded in a trace, dents the plane as
//! deep as its index tip went (for either hand).

use glam::{DQuat, DVec3};
use nendo::hand::{Digit, FingerModel, Hand, HandOptions, HandSession, Probe};
use nendo::surface::{Primitive, PrimitiveParams, Regulation};
use nendo_devices::profile::{self, Side};
use nendo_devices::skeleton::HandJoint;
use nendo_devices::trace::quantize_frame;
use nendo_devices::vmc::VmcState;
use nendo_devices::vmc::send::{bundle, straight_arms};
use nendo_devices::{
    FrameStatus, HandFrame, HandSize, Joint, JointAngles, SourceState, Timestamp, Trace,
    TraceHeader, TrackerPose, WorldFromTracker,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[test]
fn a_glove_frame_and_its_skeleton_place_the_same_hand() {
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    for side in [Side::Right, Side::Left] {
        let size = HandSize {
            side,
            ..HandSize::default()
        };
        let w = WorldFromTracker {
            translation: [0.5, -6.0, 1.0],
            rotation_wxyz: [0.9238795325112867, 0.0, 0.0, 0.3826834323650898],
            scale: 20.0,
        };
        let hand = Hand::new(size, w).unwrap();
        for _ in 0..50 {
            let mut angles = JointAngles::new();
            for j in Joint::ALL {
                angles.set(j, rng.gen_range(-0.3..1.5)).unwrap();
            }
            let q = DQuat::from_xyzw(
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
            )
            .normalize();
            let p = DVec3::new(rng.gen_range(-0.5..0.5), rng.gen_range(-0.5..0.5), 0.3);
            let pose = TrackerPose::new(p, q).unwrap();
            let direct = hand.pose(&pose, Some(&angles));
            let skeleton = hand.skeleton(&pose, Some(&angles));
            let via = hand.skeleton_pose(&skeleton).expect("a complete skeleton");
            assert!((direct.sensor - via.sensor).length() < 1e-12);
            assert!(direct.orientation.dot(via.orientation).abs() > 1.0 - 1e-12);
            for d in Digit::ALL {
                for (a, b) in direct.finger(d).points.iter().zip(via.finger(d).points) {
                    assert!((*a - b).length() < 1e-12, "{side:?} {d}: {a} vs {b}");
                }
            }
            let (pa, pb) = (hand.palm(&direct), hand.palm(&via));
            assert!((pa.centre - pb.centre).length() < 1e-12);
        }
    }
}

/// The hand rotated so the index points down (Unity −Y): about Unity's Z, by −90° for the
/// right hand (its fingers along +X), +90° for the left (along −X).
fn index_down(side: Side) -> DQuat {
    let half_turn = std::f64::consts::FRAC_PI_2;
    match side {
        Side::Right => DQuat::from_rotation_z(-half_turn),
        Side::Left => DQuat::from_rotation_z(half_turn),
    }
}

#[test]
fn a_vmc_skeleton_dents_the_plane_as_deep_as_its_index_tip_went() {
    let vmc = profile::resolve("vmc").unwrap();
    for side in [Side::Right, Side::Left] {
        let size = HandSize { side, ..vmc.hand };
        let hand = Hand::new(size, vmc.world_from_tracker).unwrap();
        let bones = straight_arms(side, index_down(side));
        let mut state = VmcState::new(size);
        // Where the index tip is with the root at Unity's origin.
        let at_origin = state
            .packet(&bundle((DVec3::ZERO, DQuat::IDENTITY), &bones, 0.0).unwrap())
            .unwrap();
        let tip0 = hand
            .skeleton_pose(&at_origin)
            .unwrap()
            .finger(Digit::Index)
            .tip();
        let want = DVec3::new(1.0, 0.5, 0.0);
        // Down from 1 side above the plane to 0.3 into it and back up, 1/60 s apart.
        let depths: Vec<f64> = (0..=26)
            .map(|k| 1.0 - 0.05 * k as f64)
            .chain((0..=26).rev().map(|k| 1.0 - 0.05 * k as f64))
            .collect();
        let mut frames = Vec::new();
        for (k, depth) in depths.iter().enumerate() {
            let target = DVec3::new(want.x, want.y, *depth);
            // World offset → Unity root: world = t + c·(x, z, y).
            let d = (target - tip0) / vmc.world_from_tracker.scale;
            let root = DVec3::new(d.x, d.z, d.y);
            let s = state
                .packet(&bundle((root, DQuat::IDENTITY), &bones, k as f32).unwrap())
                .unwrap();
            let frame = HandFrame {
                time: Timestamp::from_micros(k as u64 * 16_667),
                pose: None,
                joints: None,
                buttons: 0,
                status: FrameStatus {
                    tracker: SourceState::Ok,
                    glove: SourceState::Absent,
                    tracker_fresh: true,
                    glove_fresh: false,
                },
                skeleton: Some(s),
            };
            frames.push(quantize_frame(&frame, &[]));
        }
        // The deepest frame's tip is where it was asked to be (to f32 on the wire).
        let deepest = hand
            .skeleton_pose(frames[26].skeleton.as_ref().unwrap())
            .unwrap()
            .finger(Digit::Index)
            .tip();
        assert!(
            (deepest - DVec3::new(1.0, 0.5, -0.3)).length() < 1e-3,
            "{deepest}"
        );
        assert_eq!(
            frames[26].skeleton.unwrap().source(HandJoint::IndexTip),
            nendo_devices::JointSource::Made
        );
        // Written and read back: the same frames, bit for bit.
        let trace = Trace {
            header: TraceHeader {
                profile: Some("vmc".into()),
                world_from_tracker: vmc.world_from_tracker,
                hand: size,
                skeleton: Some(side),
                ..TraceHeader::default()
            },
            frames,
            held: Vec::new(),
        };
        let text = trace.to_text();
        assert!(text.starts_with("nendo-hand-trace 3\n"));
        let back = Trace::parse(&text).unwrap();
        assert_eq!(back, trace);
        assert_eq!(back.to_text(), text);
        // Through the hand loop, the index alone pressing.
        let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
        let options = HandOptions {
            finger: FingerModel::digit(Digit::Index),
            ..HandOptions::default()
        };
        let mut session = HandSession::new(plane, Regulation::default(), hand, options).unwrap();
        for f in &back.frames {
            session.feed(f);
        }
        session.finish();
        assert_eq!(session.hand_loop().stats().pushes, 1, "{side:?}");
        let grid = session.into_grid();
        let probe = |x: f64, y: f64| {
            Probe::new()
                .first_crossing(&grid, DVec3::new(x, y, 5.0), DVec3::NEG_Z, 50.0)
                .map(|h| h.t - 5.0)
                .unwrap()
        };
        let dent = probe(want.x, want.y);
        assert!((dent - 0.30).abs() <= 0.03, "{side:?}: dent {dent}");
        // The deepest point within 0.1 of the tip; far away the plane is untouched.
        let far = probe(-4.0, -4.0);
        assert!(far.abs() < 1e-9, "{side:?}: far {far}");
    }
}
