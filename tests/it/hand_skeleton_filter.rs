//! Skeleton hands through the hand loop's gate and filter, with stale bones, and drawn: a
//! one-frame spike of the index leaves the plane flat; a finger whose bones stop coming does
//! not press (the others do); the window draws wrist, metacarpals and palm, made joints apart
//! from measured ones.

use glam::{DQuat, DVec3};
use nendo::editor::document::Document;
use nendo::editor::hand_input::{HandDriver, MADE_JOINT, MEASURED_JOINT};
use nendo::hand::{Digit, FingerModel, Fingers, Hand, HandOptions, HandSession, Part};
use nendo::model::Model;
use nendo::render::{LineBatch, SphereInstance};
use nendo::surface::{Grid, Primitive, PrimitiveParams, Regulation};
use nendo_devices::profile::{self, Side};
use nendo_devices::skeleton::{HandJoint, JointSource, Skeleton};
use nendo_devices::vmc::VmcState;
use nendo_devices::vmc::send::{Bone, bundle, straight_arms};
use nendo_devices::{
    FilterSettings, FrameStatus, HandFrame, HandSize, SourceState, Timestamp, WorldFromTracker,
};

fn plane() -> Grid {
    Primitive::Plane.build(&PrimitiveParams::default()).unwrap()
}

/// The largest `|z|` of the surface on a 17 × 17 grid of parameters per patch.
fn max_height(g: &Grid) -> f64 {
    let mut h: f64 = 0.0;
    for iu in 0..g.patches_u() {
        for iv in 0..g.patches_v() {
            for a in 0..17 {
                for b in 0..17 {
                    let p = g.eval(iu, iv, a as f64 / 16.0, b as f64 / 16.0);
                    h = h.max(p.z.abs());
                }
            }
        }
    }
    h
}

/// A VMC performer's right hand, index down, at 60 Hz: `root_for(tip)` gives the Unity root
/// that puts the index tip at a world point.
struct Performer {
    size: HandSize,
    world: WorldFromTracker,
    bones: Vec<Bone>,
    tip0: DVec3,
}

impl Performer {
    fn new() -> Self {
        let vmc = profile::resolve("vmc").unwrap();
        let size = HandSize {
            side: Side::Right,
            ..vmc.hand
        };
        let bones = straight_arms(
            Side::Right,
            DQuat::from_rotation_z(-std::f64::consts::FRAC_PI_2),
        );
        let hand = Hand::new(size, vmc.world_from_tracker).unwrap();
        let s = VmcState::new(size)
            .packet(&bundle((DVec3::ZERO, DQuat::IDENTITY), &bones, 0.0).unwrap())
            .unwrap();
        let tip0 = hand.skeleton_pose(&s).unwrap().finger(Digit::Index).tip();
        Self {
            size,
            world: vmc.world_from_tracker,
            bones,
            tip0,
        }
    }

    fn hand(&self) -> Hand {
        Hand::new(self.size, self.world).unwrap()
    }

    fn root_for(&self, tip: DVec3) -> (DVec3, DQuat) {
        let d = (tip - self.tip0) / self.world.scale;
        (DVec3::new(d.x, d.z, d.y), DQuat::IDENTITY)
    }
}

fn frame(k: usize, s: Skeleton) -> HandFrame {
    HandFrame {
        time: Timestamp::from_micros(k as u64 * 16_667),
        status: FrameStatus {
            tracker: SourceState::Ok,
            glove: SourceState::Absent,
            tracker_fresh: true,
            glove_fresh: false,
        },
        skeleton: Some(s),
        ..HandFrame::default()
    }
}

fn session(hand: Hand, finger: FingerModel, filter: FilterSettings) -> HandSession {
    let options = HandOptions {
        finger,
        ..HandOptions::default()
    };
    let mut s = HandSession::new(plane(), Regulation::default(), hand, options).unwrap();
    s.set_filter(filter);
    s
}

#[test]
fn a_one_frame_spike_of_the_index_leaves_the_plane_flat() {
    let p = Performer::new();
    let mut state = VmcState::new(p.size);
    // The index tip hovering one side above the plane for one second; at frame 30 the
    // index's intermediate, distal and (made) tip joints jump 6 cm down (1.2 side): the tip
    // 0.2 side into the plane for one frame.
    let root = p.root_for(DVec3::new(0.5, 0.5, 1.0));
    let mut frames = Vec::new();
    for k in 0..60 {
        let mut s = state
            .packet(&bundle(root, &p.bones, k as f32).unwrap())
            .unwrap();
        if k == 30 {
            for j in [
                HandJoint::IndexIntermediate,
                HandJoint::IndexDistal,
                HandJoint::IndexTip,
            ] {
                let mut pose = *s.get(j).unwrap();
                pose.position.z -= 0.06;
                let source = s.source(j);
                s.set(j, pose, source);
            }
        }
        frames.push(frame(k, s));
    }
    let index = FingerModel::digit(Digit::Index);
    let run = |filter| {
        let mut s = session(p.hand(), index, filter);
        for f in &frames {
            s.feed(f);
        }
        s.finish();
        let held = s.hand_loop().filter().stats().skeleton_positions;
        (max_height(s.grid()), held)
    };
    let (raw, _) = run(FilterSettings::off());
    let (filtered, held) = run(profile::resolve("vmc").unwrap().filter);
    eprintln!("index spike of 6 cm: {raw:.3} side unfiltered, {filtered:.2e} filtered");
    assert!(raw > 0.1, "the spike reaches the clay unfiltered: {raw}");
    assert!(filtered < 0.01, "{filtered}");
    assert_eq!(held.total(), 3, "{held:?}");
}

/// Bundles with every bone but the ring finger's after `stop` (frame index), at 60 Hz, the
/// hand's fingertips lowered from 1 side above the plane to 0.3 into it and held.
fn ring_stops(p: &Performer, stop: usize) -> Vec<HandFrame> {
    let mut state = VmcState::new(p.size);
    state.set_bone_timeout(0.5);
    let no_ring: Vec<Bone> = p
        .bones
        .iter()
        .filter(|b| !b.0.starts_with("RightRing"))
        .cloned()
        .collect();
    let mut frames = Vec::new();
    for k in 0..120 {
        let depth = if k < 60 {
            1.0
        } else {
            1.0 - 0.05 * (k - 60).min(26) as f64
        };
        let root = p.root_for(DVec3::new(0.0, 0.0, depth));
        let bones = if k < stop { &p.bones } else { &no_ring };
        let t = k as f64 / 60.0;
        let s = state
            .packet_at(&bundle(root, bones, t as f32).unwrap(), t)
            .unwrap();
        frames.push(frame(k, s));
    }
    frames
}

#[test]
fn a_finger_whose_bones_stop_coming_does_not_press() {
    let p = Performer::new();
    // The ring's bones stop after frame 19 (0.32 s); 0.5 s later (frame 50, before the hand
    // comes down at frame 60) they are stale.
    let stale = ring_stops(&p, 20);
    assert!(
        stale[51]
            .skeleton
            .unwrap()
            .get(HandJoint::RingTip)
            .is_none()
    );
    assert!(
        stale[30]
            .skeleton
            .unwrap()
            .get(HandJoint::RingTip)
            .is_some()
    );
    let ring = FingerModel::Hand(Fingers::one(Part::Digit(Digit::Ring)));
    let every = FingerModel::Hand(Fingers::ALL);
    let vmc = profile::resolve("vmc").unwrap().filter;
    // The ring alone: no contact with its bones stale; one with them fresh.
    let contacts = |frames: &[HandFrame], finger| {
        let mut s = session(p.hand(), finger, vmc);
        let mut ring_tips = 0;
        for f in frames {
            s.feed(f);
            ring_tips += s
                .hand_loop()
                .fingertips()
                .iter()
                .filter(|(part, _)| *part == Part::Digit(Digit::Ring))
                .count();
        }
        s.finish();
        (s.hand_loop().stats().contacts, ring_tips)
    };
    let fresh = ring_stops(&p, usize::MAX);
    assert!(contacts(&fresh, ring).0 >= 1, "the fresh ring presses");
    assert_eq!(contacts(&stale, ring).0, 0, "the stale ring does not");
    // Every finger: the others still press, and the ring is never a pressing part once stale.
    let (n, ring_tips) = contacts(&stale, every);
    assert!(n >= 1);
    let (_, fresh_ring_tips) = contacts(&fresh, every);
    assert_eq!(fresh_ring_tips, 120);
    assert!(ring_tips <= 51, "{ring_tips}");
}

/// The spheres of a given colour.
fn coloured(spheres: &[SphereInstance], colour: [f32; 4]) -> Vec<&SphereInstance> {
    spheres.iter().filter(|s| s.colour == colour).collect()
}

#[test]
fn the_window_draws_wrist_metacarpals_and_made_joints_apart() {
    let p = Performer::new();
    let mut state = VmcState::new(p.size);
    let root = p.root_for(DVec3::new(0.5, 0.5, 2.0));
    let s = state.packet(&bundle(root, &p.bones, 0.0).unwrap()).unwrap();
    let mut doc = Document::new(Model::new(plane()));
    let mut driver = HandDriver::new(p.size, p.world, FingerModel::Hand(Fingers::ALL), 0.5)
        .unwrap()
        .with_filter(FilterSettings::default());
    driver.feed(&mut doc, &frame(0, s));
    let (mut lines, mut spheres) = (LineBatch::new(), Vec::new());
    driver.draw(&mut lines, &mut spheres);
    // Every joint a sphere: 16 measured (wrist and the 15 finger joints sent as bones), 10
    // made (5 tips, 4 metacarpals, the palm), the made ones larger.
    let measured = coloured(&spheres, MEASURED_JOINT);
    let made = coloured(&spheres, MADE_JOINT);
    assert_eq!((measured.len(), made.len()), (16, 10));
    assert!(made[0].radius > measured[0].radius);
    let hand = p.hand();
    let placed = hand.skeleton_joints(&s);
    let at = |j: HandJoint| placed.iter().find(|(k, ..)| *k == j).unwrap().1.as_vec3();
    let near = |a: [f32; 3], b: glam::Vec3| (glam::Vec3::from_array(a) - b).length() < 1e-5;
    assert!(
        measured
            .iter()
            .any(|s| near(s.center, at(HandJoint::Wrist)))
    );
    for j in [
        HandJoint::IndexTip,
        HandJoint::Palm,
        HandJoint::RingMetacarpal,
    ] {
        assert_eq!(s.source(j), JointSource::Made);
        assert!(made.iter().any(|s| near(s.center, at(j))), "{j}");
    }
    // Bones from the wrist: to the palm and the five metacarpals, and the four finger
    // metacarpals' (made at the wrist) to their knuckles.
    let ends = lines.vertices();
    let from_wrist = ends
        .chunks(2)
        .filter(|seg| seg.iter().any(|v| near(v.position, at(HandJoint::Wrist))))
        .count();
    assert_eq!(from_wrist, 10);
    // A stale ring: its joints are not drawn.
    let stale = ring_stops(&p, 0);
    let mut driver =
        HandDriver::new(p.size, p.world, FingerModel::Hand(Fingers::ALL), 0.5).unwrap();
    for f in &stale[..40] {
        driver.feed(&mut doc, f);
    }
    let (mut lines, mut spheres) = (LineBatch::new(), Vec::new());
    driver.draw(&mut lines, &mut spheres);
    let joints = coloured(&spheres, MEASURED_JOINT).len() + coloured(&spheres, MADE_JOINT).len();
    assert_eq!(joints, 22);
}
