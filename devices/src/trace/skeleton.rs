//! Skeleton frames in a trace (version 3): the `skeleton` header line and each frame's `S`
//! section (see the module docs of [`crate::trace`]).
//!
//! After the `J` columns a frame of a skeleton trace has `S` and then either `-` (no hand: the
//! source is not `ok`, or sent no complete hand) or 26 joint groups in OpenXR's order
//! ([`HandJoint::ALL`]), each `-` (missing) or a flag — `m` measured, `d` made (derived, see
//! [`crate::skeleton`]) — followed by `x y z qw qx qy qz` (metres, unit quaternion, six
//! decimals) and the radius (six decimals) or `?` when unknown.

use std::fmt::Write as _;

use glam::{DQuat, DVec3};

use super::{DECIMALS, FrameError, number, parse_number, quantize};
use crate::profile::Side;
use crate::skeleton::{HandJoint, JointPose, JointSource, Skeleton};

/// The skeleton rounded to the trace's six decimals, exactly as writing and reading it would.
pub(super) fn quantize_skeleton(s: &Skeleton) -> Skeleton {
    let mut q = Skeleton::new(s.side);
    for (joint, pose, source) in s.iter() {
        let pose = JointPose {
            position: DVec3::from_array(pose.position.to_array().map(quantize)),
            orientation: DQuat::from_array(pose.orientation.to_array().map(quantize)),
            radius: pose.radius.map(quantize),
        };
        q.set(joint, pose, source);
    }
    q
}

/// Appends ` S …` for a frame of a skeleton trace.
pub(super) fn format_skeleton(s: Option<&Skeleton>, out: &mut String) {
    out.push_str(" S");
    let Some(s) = s else {
        out.push_str(" -");
        return;
    };
    for joint in HandJoint::ALL {
        let Some(pose) = s.get(joint) else {
            out.push_str(" -");
            continue;
        };
        out.push_str(match s.source(joint) {
            JointSource::Made => " d",
            _ => " m",
        });
        for x in pose.position.to_array() {
            number(x, out);
        }
        let q = pose.orientation;
        for x in [q.w, q.x, q.y, q.z] {
            number(x, out);
        }
        match pose.radius {
            Some(r) => number(r, out),
            None => {
                let _ = write!(out, " ?");
            }
        }
    }
}

/// Reads the words after `S` of a frame of a skeleton trace of hand `side`.
pub(super) fn parse_skeleton(words: &[&str], side: Side) -> Result<Option<Skeleton>, FrameError> {
    if words == ["-"] {
        return Ok(None);
    }
    let mut s = Skeleton::new(side);
    let mut w = words.iter().copied();
    for joint in HandJoint::ALL {
        let source = match w.next() {
            Some("-") => continue,
            Some("m") => JointSource::Measured,
            Some("d") => JointSource::Made,
            Some(other) => {
                return Err(FrameError::BadSkeleton(format!(
                    "joint {joint}: `{other}` is not `m`, `d` or `-`"
                )));
            }
            None => return Err(FrameError::EndsEarly),
        };
        let mut v = [0.0; 7];
        for x in &mut v {
            *x = parse_number(w.next())?;
        }
        let radius = match w.next() {
            Some("?") => None,
            word => Some(parse_number(word)?),
        };
        let position = DVec3::new(v[0], v[1], v[2]);
        let orientation = DQuat::from_xyzw(v[4], v[5], v[6], v[3]);
        // Validate, but keep the numbers exactly as written so the trace round-trips.
        JointPose::new(position, orientation, radius)
            .map_err(|e| FrameError::BadSkeleton(format!("joint {joint}: {e}")))?;
        s.set(
            joint,
            JointPose {
                position,
                orientation,
                radius,
            },
            source,
        );
    }
    if let Some(extra) = w.next() {
        return Err(FrameError::BadSkeleton(format!(
            "`{extra}` after the {} joints",
            HandJoint::COUNT
        )));
    }
    Ok(Some(s))
}

/// The `skeleton` header line's value.
pub(super) fn side_token(side: Side) -> &'static str {
    match side {
        Side::Left => "left",
        Side::Right => "right",
    }
}

/// The hand of a `skeleton` header line.
pub(super) fn parse_side(token: &str) -> Option<Side> {
    match token {
        "left" => Some(Side::Left),
        "right" => Some(Side::Right),
        _ => None,
    }
}

const _: () = assert!(DECIMALS == 6);
