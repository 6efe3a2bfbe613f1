//! The gate's marks in a trace (version 4): which samples of a frame the plausibility gate
//! ([`crate::filter`]) rejected, so the trace says what the recording's gate held while
//! keeping the raw samples.
//!
//! A trace whose header has the line `marks held` carries them: each frame where the gate held
//! something ends with the per-frame field `held=CHANNELS`, and a frame without it had nothing
//! held. `CHANNELS` is a comma-separated list, without blanks or repeats, in this order:
//!
//! 1. `position`, `orientation`: the tracker's position, its orientation;
//! 2. glove joints by their header names (`index_mcp`, …), in the order of the header's
//!    `joints` line;
//! 3. skeleton joints ([`HandJoint`], in OpenXR's order) as `NAME.position` and
//!    `NAME.orientation` (`index_tip.position`), the position first. Only these contain a `.`,
//!    so no token can be read two ways.
//!
//! For example `held=position,orientation` (a tracker spike), `held=index_pip` (a glove
//! glitch), `held=wrist.position,palm.orientation` is refused (out of order:
//! `palm.orientation,wrist.position`). A mark names a channel the frame carries a value of: a
//! pose for `position` / `orientation`, a value in the joint's column, the skeleton joint in
//! the `S` section; anything else is refused, as is an empty list, an unknown name, a repeat
//! or a list out of order — so each set of marks has one spelling, and a trace read and
//! written again is the same text. Parsing holds the marks as bit sets (no allocation per
//! token), so a hostile line costs at most its own length.

use crate::filter::Held;
use crate::profile::Side;
use crate::skeleton::HandJoint;
use crate::{HandFrame, Joint};

use super::FrameError;

/// The per-frame field that carries the marks.
pub const HELD_FIELD: &str = "held";

/// The channels of one frame the gate held (rejected, keeping the last good value), as a trace
/// marks them (see the module docs). Built from what a [`crate::FrameFilter`] reports
/// ([`HeldMarks::from`] a [`Held`]), without the reasons (the trace does not keep them).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct HeldMarks {
    /// The tracker's position.
    pub position: bool,
    /// The tracker's orientation.
    pub orientation: bool,
    /// Glove joints ([`Joint::index`] bits).
    pub joints: u32,
    /// Skeleton joints whose position was held ([`HandJoint::index`] bits).
    pub skeleton_positions: u32,
    /// Skeleton joints whose orientation was held ([`HandJoint::index`] bits).
    pub skeleton_orientations: u32,
}

impl From<Held> for HeldMarks {
    fn from(h: Held) -> Self {
        Self {
            position: h.position.is_some(),
            orientation: h.orientation.is_some(),
            joints: h.joints,
            skeleton_positions: h.skeleton_positions,
            skeleton_orientations: h.skeleton_orientations,
        }
    }
}

impl HeldMarks {
    /// Nothing held.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// The marks as a trace writes them after `held=` (the header's glove columns give the
    /// joints' order; a joint outside them is not written, as its column is not either).
    /// Empty when nothing is marked.
    #[must_use]
    pub fn to_value(&self, joints: &[Joint]) -> String {
        let mut out = String::new();
        let mut put = |token: &str, suffix: &str| {
            if !out.is_empty() {
                out.push(',');
            }
            out.push_str(token);
            out.push_str(suffix);
        };
        if self.position {
            put("position", "");
        }
        if self.orientation {
            put("orientation", "");
        }
        for j in joints {
            if self.joints & (1 << j.index()) != 0 {
                put(j.name(), "");
            }
        }
        for j in HandJoint::ALL {
            if self.skeleton_positions & (1 << j.index()) != 0 {
                put(j.name(), ".position");
            }
            if self.skeleton_orientations & (1 << j.index()) != 0 {
                put(j.name(), ".orientation");
            }
        }
        out
    }

    /// The marks on channels `frame` carries in a trace with these glove columns (and
    /// skeleton section): `position` / `orientation` with a pose, a joint with a value in its
    /// column, a skeleton joint the frame's skeleton has — what a `held=` field of that frame
    /// can say ([`HeldMarks::parse`] refuses the others).
    #[must_use]
    pub fn carried_by(&self, frame: &HandFrame, joints: &[Joint], skeleton: bool) -> HeldMarks {
        let pose = frame.pose.is_some();
        let columns = joints
            .iter()
            .filter(|&&j| frame.joints.is_some_and(|a| a.get(j).is_some()))
            .fold(0u32, |m, j| m | (1 << j.index()));
        let bones = match (&frame.skeleton, skeleton) {
            (Some(s), true) => s.iter().fold(0u32, |m, (j, _, _)| m | (1 << j.index())),
            _ => 0,
        };
        HeldMarks {
            position: self.position && pose,
            orientation: self.orientation && pose,
            joints: self.joints & columns,
            skeleton_positions: self.skeleton_positions & bones,
            skeleton_orientations: self.skeleton_orientations & bones,
        }
    }

    /// Reads the value of a `held=` field for `frame` (already read) of a trace with these
    /// glove columns and skeleton hand (see the module docs for what is refused).
    ///
    /// # Errors
    /// [`FrameError::BadHeld`] naming the token and what is wrong with it.
    pub fn parse(
        value: &str,
        joints: &[Joint],
        skeleton: Option<Side>,
        frame: &HandFrame,
    ) -> Result<HeldMarks, FrameError> {
        let mut marks = HeldMarks::default();
        // The rank of the last token read: each must come after it.
        let mut last: Option<usize> = None;
        let skeleton_rank = 2 + joints.len();
        for token in value.split(',') {
            let bad = |why: &str| FrameError::BadHeld(format!("`{}`: {why}", clip(token)));
            let rank = if token == "position" || token == "orientation" {
                if frame.pose.is_none() {
                    return Err(bad("the frame has no tracker pose"));
                }
                if token == "position" {
                    marks.position = true;
                    0
                } else {
                    marks.orientation = true;
                    1
                }
            } else if let Some((name, what)) = token.split_once('.') {
                let joint = HandJoint::from_name(name)
                    .ok_or_else(|| bad("not a skeleton joint (NAME.position, NAME.orientation)"))?;
                let k = joint.index();
                let (bits, offset) = match what {
                    "position" => (&mut marks.skeleton_positions, 0),
                    "orientation" => (&mut marks.skeleton_orientations, 1),
                    _ => return Err(bad("a skeleton mark ends in .position or .orientation")),
                };
                if skeleton.is_none() {
                    return Err(bad("the trace has no skeleton (no `skeleton` header line)"));
                }
                if frame.skeleton.as_ref().and_then(|s| s.get(joint)).is_none() {
                    return Err(bad("the frame's skeleton has no such joint"));
                }
                *bits |= 1 << k;
                skeleton_rank + 2 * k + offset
            } else {
                let joint = Joint::from_name(token).ok_or_else(|| {
                    bad("not a channel (position, orientation, a joint column, NAME.position)")
                })?;
                let column = joints
                    .iter()
                    .position(|&j| j == joint)
                    .ok_or_else(|| bad("not a joint column of this trace"))?;
                if frame.joints.and_then(|a| a.get(joint)).is_none() {
                    return Err(bad("the frame has no value in this column"));
                }
                marks.joints |= 1 << joint.index();
                2 + column
            };
            if last.is_some_and(|l| rank <= l) {
                return Err(bad(
                    "marks are listed once each, in order: position, orientation, joint columns, skeleton joints",
                ));
            }
            last = Some(rank);
        }
        Ok(marks)
    }
}

/// A token as an error message quotes it: at most 40 characters.
pub(super) fn clip(token: &str) -> String {
    match token.char_indices().nth(40) {
        Some((at, _)) => format!("{}…", &token[..at]),
        None => token.to_owned(),
    }
}
