//! The sending side of the VMC protocol, for the emulator (`nendo emulate vmc`) and tests: a
//! humanoid's bones as one OSC bundle per frame, as a VMC performer sends them.

use glam::{DQuat, DVec3};
use rosc::{OscBundle, OscMessage, OscPacket, OscTime, OscType};

use crate::DeviceError;
use crate::profile::Side;

/// A bone's local pose in Unity's frame: name, position, rotation.
pub type Bone = (String, DVec3, DQuat);

fn pose_args(name: &str, p: DVec3, q: DQuat) -> Vec<OscType> {
    let mut args = vec![OscType::String(name.to_owned())];
    // VMC sends single-precision floats.
    args.extend(
        [p.x, p.y, p.z, q.x, q.y, q.z, q.w]
            .into_iter()
            .map(|v| OscType::Float(v as f32)),
    );
    args
}

/// One frame as a bundle: `/VMC/Ext/Root/Pos` ("root"), a `/VMC/Ext/Bone/Pos` per bone,
/// `/VMC/Ext/OK 1` and `/VMC/Ext/T time`.
///
/// # Errors
/// [`DeviceError::InvalidValue`] if OSC cannot encode it (it always can for finite values).
pub fn bundle(root: (DVec3, DQuat), bones: &[Bone], time: f32) -> Result<Vec<u8>, DeviceError> {
    let mut content = vec![OscPacket::Message(OscMessage {
        addr: "/VMC/Ext/Root/Pos".into(),
        args: pose_args("root", root.0, root.1),
    })];
    for (name, p, q) in bones {
        content.push(OscPacket::Message(OscMessage {
            addr: "/VMC/Ext/Bone/Pos".into(),
            args: pose_args(name, *p, *q),
        }));
    }
    content.push(OscPacket::Message(OscMessage {
        addr: "/VMC/Ext/OK".into(),
        args: vec![OscType::Int(1)],
    }));
    content.push(OscPacket::Message(OscMessage {
        addr: "/VMC/Ext/T".into(),
        args: vec![OscType::Float(time)],
    }));
    let packet = OscPacket::Bundle(OscBundle {
        timetag: OscTime::from((0, 1)),
        content,
    });
    rosc::encoder::encode(&packet)
        .map_err(|e| DeviceError::InvalidValue(format!("cannot encode a VMC bundle: {e}")))
}

/// A humanoid standing at the origin, facing Unity's +Z, its arms straight out to the sides
/// (right along +X, left along −X), palms down, fingers straight, every rotation the identity
/// except the hand of `side`, which is `hand` (local to the lower arm). Metres.
pub fn straight_arms(side: Side, hand: DQuat) -> Vec<Bone> {
    let v = DVec3::new;
    let mut bones: Vec<Bone> = vec![
        ("Hips".into(), v(0.0, 1.0, 0.0), DQuat::IDENTITY),
        ("Spine".into(), v(0.0, 0.1, 0.0), DQuat::IDENTITY),
        ("Chest".into(), v(0.0, 0.1, 0.0), DQuat::IDENTITY),
        ("UpperChest".into(), v(0.0, 0.1, 0.0), DQuat::IDENTITY),
    ];
    for (s, name) in [(1.0, "Right"), (-1.0, "Left")] {
        let rotation = |r: bool| {
            if r && ((name == "Right") == (side == Side::Right)) {
                hand
            } else {
                DQuat::IDENTITY
            }
        };
        let mut add = |bone: &str, x: f64, y: f64, z: f64, r: bool| {
            bones.push((format!("{name}{bone}"), v(s * x, y, z), rotation(r)));
        };
        add("Shoulder", 0.05, 0.12, 0.0, false);
        add("UpperArm", 0.10, 0.0, 0.0, false);
        add("LowerArm", 0.28, 0.0, 0.0, false);
        add("Hand", 0.25, 0.0, 0.0, true);
        // The thumb toward +Z (forward: palms down, the thumbs point ahead).
        add("ThumbProximal", 0.02, -0.01, 0.025, false);
        add("ThumbIntermediate", 0.03, 0.0, 0.02, false);
        add("ThumbDistal", 0.03, 0.0, 0.0, false);
        for (finger, z, lengths) in [
            ("Index", 0.025, [0.095, 0.040, 0.023]),
            ("Middle", 0.0, [0.095, 0.045, 0.027]),
            ("Ring", -0.02, [0.09, 0.042, 0.026]),
            ("Little", -0.04, [0.085, 0.033, 0.019]),
        ] {
            add(&format!("{finger}Proximal"), lengths[0], 0.0, z, false);
            add(
                &format!("{finger}Intermediate"),
                lengths[1],
                0.0,
                0.0,
                false,
            );
            add(&format!("{finger}Distal"), lengths[2], 0.0, 0.0, false);
        }
    }
    bones
}

/// The bones a VMC performer would send for a skeleton (in the tracker's frame, as the
/// receiver reads it): the root at the origin, every rotation the identity, `Hips`, `Spine`,
/// the arm and the lower arm at the origin, the hand at the wrist and each finger bone offset
/// from its parent by the difference of their joints, all in Unity's frame (the inverse of
/// [`super::position_from_unity`], the same swap of Y and Z). The receiver composes them back
/// to the skeleton's measured joints; its tips it makes by its own rule.
///
/// `None` when the wrist or a joint of the finger chains below the tips is missing.
pub fn bones_of(skeleton: &crate::skeleton::Skeleton) -> Option<Vec<Bone>> {
    let unity = |p: DVec3| DVec3::new(p.x, p.z, p.y);
    let side = match skeleton.side {
        Side::Right => "Right",
        Side::Left => "Left",
    };
    let mut bones: Vec<Bone> = ["Hips", "Spine"]
        .into_iter()
        .map(|b| (b.to_owned(), DVec3::ZERO, DQuat::IDENTITY))
        .collect();
    for b in ["UpperArm", "LowerArm"] {
        bones.push((format!("{side}{b}"), DVec3::ZERO, DQuat::IDENTITY));
    }
    let at = |j| skeleton.get(j).map(|p| unity(p.position));
    let wrist = at(crate::skeleton::HandJoint::Wrist)?;
    bones.push((format!("{side}Hand"), wrist, DQuat::IDENTITY));
    let names = [
        ["ThumbProximal", "ThumbIntermediate", "ThumbDistal"],
        ["IndexProximal", "IndexIntermediate", "IndexDistal"],
        ["MiddleProximal", "MiddleIntermediate", "MiddleDistal"],
        ["RingProximal", "RingIntermediate", "RingDistal"],
        ["LittleProximal", "LittleIntermediate", "LittleDistal"],
    ];
    for (chain, names) in crate::skeleton::HandJoint::FINGERS.iter().zip(names) {
        let mut parent = wrist;
        for (joint, name) in chain[..3].iter().zip(names) {
            let p = at(*joint)?;
            bones.push((format!("{side}{name}"), p - parent, DQuat::IDENTITY));
            parent = p;
        }
    }
    Some(bones)
}
