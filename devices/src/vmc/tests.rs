use super::send::{bundle, straight_arms};
use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn hand(side: Side) -> HandSize {
    HandSize {
        side,
        ..HandSize::default()
    }
}

fn root() -> (DVec3, DQuat) {
    (DVec3::new(0.0, 0.2, 0.0), DQuat::IDENTITY)
}

/// The sum of a chain's offsets: with identity rotations the world position of a bone.
fn offsets(bones: &[send::Bone], chain: &[&str]) -> DVec3 {
    chain
        .iter()
        .map(|n| bones.iter().find(|b| b.0 == *n).map(|b| b.1).unwrap())
        .sum()
}

#[test]
fn a_straight_arm_composes_to_the_sum_of_its_offsets_converted() {
    for side in [Side::Right, Side::Left] {
        let bones = straight_arms(side, DQuat::IDENTITY);
        let mut state = VmcState::new(hand(side));
        let s = state
            .packet(&bundle(root(), &bones, 0.0).unwrap())
            .expect("a whole skeleton");
        let n = if side == Side::Right { "Right" } else { "Left" };
        let chain: Vec<String> = [
            "Hips",
            "Spine",
            "Chest",
            "UpperChest",
            "Shoulder",
            "UpperArm",
            "LowerArm",
            "Hand",
            "IndexProximal",
            "IndexIntermediate",
            "IndexDistal",
        ]
        .iter()
        .enumerate()
        .map(|(i, b)| {
            if i < 4 {
                (*b).into()
            } else {
                format!("{n}{b}")
            }
        })
        .collect();
        let names: Vec<&str> = chain.iter().map(String::as_str).collect();
        let unity = root().0 + offsets(&bones, &names);
        let got = s.get(HandJoint::IndexDistal).unwrap().position;
        // f32 on the wire.
        assert!(
            (got - position_from_unity(unity)).length() < 1e-6,
            "{side:?} {got}"
        );
        let wrist = root().0 + offsets(&bones, &names[..8]);
        assert!(
            (s.get(HandJoint::Wrist).unwrap().position - position_from_unity(wrist)).length()
                < 1e-6
        );
        assert_eq!(s.source(HandJoint::IndexDistal), JointSource::Measured);
        assert_eq!(s.source(HandJoint::IndexTip), JointSource::Made);
        assert_eq!(s.source(HandJoint::Palm), JointSource::Made);
        // Straight finger: the tip one distal length further along it (±X).
        let tip = s.get(HandJoint::IndexTip).unwrap().position;
        let sign = if side == Side::Right { 1.0 } else { -1.0 };
        assert!(
            (tip - got - DVec3::new(sign * HandSize::default().index.distal, 0.0, 0.0)).length()
                < 1e-6
        );
        // Palms down: the back of the hand up (+Z in nendo's frame), for either hand.
        let q = s.get(HandJoint::Palm).unwrap().orientation;
        assert!((q * DVec3::Z - DVec3::Z).length() < 1e-6, "{side:?}");
        assert!(s.is_complete());
        assert_eq!(state.stats().faults, 0);
    }
}

#[test]
fn the_worked_example_of_the_module_docs() {
    let p = position_from_unity(DVec3::new(0.55, 1.30, 0.10));
    assert_eq!(p, DVec3::new(0.55, 0.10, 1.30));
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let q = DQuat::from_xyzw(0.0, 0.0, h, h);
    // Unity: +X turned toward +Y (up).
    assert!((q * DVec3::X - DVec3::Y).length() < 1e-12);
    let n = rotation_from_unity(q);
    assert_eq!(n, DQuat::from_xyzw(0.0, -h, 0.0, h));
    // nendo: +X turned toward +Z (up).
    assert!((n * DVec3::X - DVec3::Z).length() < 1e-12);
}

#[test]
fn composing_then_converting_equals_converting_then_composing() {
    let mut rng = ChaCha8Rng::seed_from_u64(26);
    for _ in 0..200 {
        let mut r = || rng.gen_range(-1.0..1.0);
        let q1 = DQuat::from_xyzw(r(), r(), r(), r()).normalize();
        let q2 = DQuat::from_xyzw(r(), r(), r(), r()).normalize();
        let (p1, p2) = (DVec3::new(r(), r(), r()), DVec3::new(r(), r(), r()));
        let (p, q) = (p1 + q1 * p2, q1 * q2);
        let (c1, c2) = (rotation_from_unity(q1), rotation_from_unity(q2));
        let pc = position_from_unity(p1) + c1 * position_from_unity(p2);
        assert!((pc - position_from_unity(p)).length() < 1e-12);
        let v = DVec3::new(r(), r(), r());
        // Rotating a converted vector by the converted rotation = converting the rotated one.
        assert!(((c1 * c2) * position_from_unity(v) - position_from_unity(q * v)).length() < 1e-12);
        assert!(rotation_from_unity(q).dot(c1 * c2).abs() > 1.0 - 1e-12);
    }
}

#[test]
fn a_missing_bone_a_nan_garbage_and_other_addresses_are_counted_not_fatal() {
    let side = Side::Right;
    let all = straight_arms(side, DQuat::IDENTITY);
    let mut state = VmcState::new(hand(side));
    // Missing: no RightIndexIntermediate. The hand comes without the index's intermediate,
    // distal and tip, and the datagram is counted as a fault.
    let missing: Vec<_> = all
        .iter()
        .filter(|b| b.0 != "RightIndexIntermediate")
        .cloned()
        .collect();
    let partial = state
        .packet(&bundle(root(), &missing, 0.0).unwrap())
        .expect("the palm can be made");
    assert!(!partial.is_complete());
    for j in [
        HandJoint::IndexIntermediate,
        HandJoint::IndexDistal,
        HandJoint::IndexTip,
    ] {
        assert_eq!(partial.source(j), JointSource::Missing, "{j}");
    }
    assert_eq!(
        partial.source(HandJoint::IndexProximal),
        JointSource::Measured
    );
    assert_eq!(state.stats().faults, 1);
    // Whole: a hand.
    assert!(state.packet(&bundle(root(), &all, 0.0).unwrap()).is_some());
    // A NaN: the bone is forgotten, the hand incomplete, the message counted invalid.
    let mut nan = all.clone();
    if let Some(b) = nan.iter_mut().find(|b| b.0 == "RightHand") {
        b.1.x = f64::NAN;
    }
    assert!(state.packet(&bundle(root(), &nan, 0.0).unwrap()).is_none());
    assert_eq!(state.stats().invalid, 1);
    assert_eq!(state.stats().faults, 2);
    // Truncated and garbage datagrams.
    let whole = bundle(root(), &all, 0.0).unwrap();
    assert!(state.packet(&whole[..whole.len() / 2]).is_none());
    assert!(state.packet(b"\xff\x00garbage").is_none());
    assert!(state.packet(&[]).is_none());
    assert_eq!(state.stats().decode.rejected, 3);
    // Back to a hand; an unknown address is ignored.
    let other = rosc::encoder::encode(&OscPacket::Message(OscMessage {
        addr: "/VMC/Ext/Blend/Val".into(),
        args: vec![OscType::String("A".into()), OscType::Float(0.5)],
    }))
    .unwrap();
    assert!(state.packet(&other).is_none());
    assert_eq!(state.stats().ignored, 1);
    assert!(state.packet(&whole).is_some());
    assert!(state.seen().contains(&"RightIndexDistal".to_owned()));
}

#[test]
fn optional_bones_may_be_absent() {
    // No Chest, UpperChest or shoulders: the arm hangs from the spine.
    let side = Side::Left;
    let all = straight_arms(side, DQuat::IDENTITY);
    let few: Vec<_> = all
        .iter()
        .filter(|b| {
            !["Chest", "UpperChest", "LeftShoulder", "RightShoulder"].contains(&b.0.as_str())
        })
        .cloned()
        .collect();
    let mut state = VmcState::new(hand(side));
    let s = state
        .packet(&bundle(root(), &few, 0.0).unwrap())
        .expect("a hand");
    let spine = root().0 + DVec3::new(0.0, 1.1, 0.0);
    // The wrist is the hand bone's origin: upper arm, lower arm and hand offsets.
    let arm = DVec3::new(-(0.10 + 0.28 + 0.25), 0.0, 0.0);
    let want = position_from_unity(spine + arm);
    assert!((s.get(HandJoint::Wrist).unwrap().position - want).length() < 1e-6);
}

#[test]
fn the_receiver_reads_datagrams_from_a_socket() {
    let mut rx = VmcReceiver::new("127.0.0.1:0", hand(Side::Right)).unwrap();
    assert!(VmcReceiver::new("localhost", hand(Side::Right)).is_err());
    rx.start().unwrap();
    let addr = rx.local_addr().unwrap();
    let tx = UdpSocket::bind("127.0.0.1:0").unwrap();
    let packet = bundle(root(), &straight_arms(Side::Right, DQuat::IDENTITY), 0.0).unwrap();
    for _ in 0..5 {
        tx.send_to(&packet, addr).unwrap();
    }
    tx.send_to(b"junk", addr).unwrap();
    let mut out = Vec::new();
    // A hang guard, not a timing assertion.
    let deadline = std::time::Instant::now() + Duration::from_secs(10);
    while out.len() < 5 && std::time::Instant::now() < deadline {
        rx.read(Duration::from_millis(50), &mut out).unwrap();
    }
    assert_eq!(out.len(), 5);
    while rx.stats().decode.rejected < 1 && std::time::Instant::now() < deadline {
        rx.read(Duration::from_millis(50), &mut out).unwrap();
    }
    assert_eq!(rx.stats().decode.rejected, 1);
    assert_eq!(rx.stats().starts, 1);
    rx.stop();
    assert!(rx.read(Duration::from_millis(1), &mut out).is_err());
}

#[test]
fn a_bone_not_refreshed_within_the_timeout_goes_missing() {
    let side = Side::Right;
    let all = straight_arms(side, DQuat::IDENTITY);
    let no_ring: Vec<_> = all
        .iter()
        .filter(|b| !b.0.starts_with("RightRing"))
        .cloned()
        .collect();
    let ring = [
        HandJoint::RingProximal,
        HandJoint::RingIntermediate,
        HandJoint::RingDistal,
        HandJoint::RingTip,
    ];
    let mut state = VmcState::new(hand(side));
    state.set_bone_timeout(0.5);
    let first = state
        .packet_at(&bundle(root(), &all, 0.0).unwrap(), 0.0)
        .unwrap();
    assert!(first.is_complete());
    // The sender stops the ring finger's bones: 30 Hz of the others for a second.
    let mut faults_from = None;
    for k in 1..=30 {
        let t = f64::from(k) / 30.0;
        let s = state
            .packet_at(&bundle(root(), &no_ring, t as f32).unwrap(), t)
            .expect("the palm can still be made");
        let stale = t > 0.5;
        for j in ring {
            assert_eq!(s.get(j).is_some(), !stale, "{j} at {t:.3} s");
        }
        assert_eq!(s.is_complete(), !stale);
        for j in [HandJoint::IndexTip, HandJoint::LittleTip, HandJoint::Palm] {
            assert!(s.get(j).is_some(), "{j} at {t:.3} s");
        }
        if stale && faults_from.is_none() {
            faults_from = Some(state.stats().faults);
        }
    }
    // Every datagram after the timeout left the hand incomplete.
    assert_eq!(state.stats().faults, 15, "{:?}", state.stats());
    assert!(faults_from.is_some());
    assert!(state.stale().contains(&"RightRingProximal".to_owned()));
    // The ring's bones come back: the hand is whole again at once.
    let back = state
        .packet_at(&bundle(root(), &all, 1.1).unwrap(), 1.1)
        .unwrap();
    assert!(back.is_complete());
    assert!(state.stale().is_empty());
    // Without a time (packet), nothing goes stale.
    let mut state = VmcState::new(hand(side));
    assert!(state.packet(&bundle(root(), &all, 0.0).unwrap()).is_some());
    for _ in 0..100 {
        assert!(
            state
                .packet(&bundle(root(), &no_ring, 0.0).unwrap())
                .unwrap()
                .is_complete()
        );
    }
}
