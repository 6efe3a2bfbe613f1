//! The clutch (rule 10 of [`super`]): the hand moves without touching the clay while a key is
//! held ([`nendo_devices::buttons::CLUTCH`] in the frame's buttons, stamped by the window as
//! the samples arrive, so a recording carries it) or while the glove makes a fist.
//!
//! **The fist**, read from the filtered joint angles: a finger's flexion `φ` is the mean of
//! its metacarpophalangeal and proximal interphalangeal angles (those the glove measures; a
//! finger with neither gives no fist). The fist closes when the index, middle, ring and little
//! fingers all have `φ ≥ φ_close` = [`FIST_CLOSE`] (1.3 rad, 74°) and opens when any of them
//! has `φ < φ_open` = [`FIST_OPEN`] (1.1 rad, 63°): the gap between the two is the
//! hysteresis, so a fist held at the threshold does not flicker. The thumb is free (tucked or
//! out). The poses that press are far from it: pointing has the index straight (`φ ≈ 0.18`,
//! the others curled at 1.3); a pinch curls the index toward the thumb no further than
//! `φ = 1.2` ([`crate::hand::script::pinching`]) — a fist curls it into the palm, past 1.4.

use nendo_devices::{Joint, JointAngles, buttons};

/// The flexion (mean of MCP and PIP, radians) every one of the four fingers reaches for the
/// fist to close.
pub const FIST_CLOSE: f64 = 1.3;

/// The flexion below which any one of the four fingers opens the fist.
pub const FIST_OPEN: f64 = 1.1;

/// The four fingers' MCP and PIP joints, index to little finger.
const FINGERS: [(Joint, Joint); 4] = [
    (Joint::IndexMcp, Joint::IndexPip),
    (Joint::MiddleMcp, Joint::MiddlePip),
    (Joint::RingMcp, Joint::RingPip),
    (Joint::PinkyMcp, Joint::PinkyPip),
];

/// A finger's flexion `φ` (see the module docs), if the glove measures either joint.
fn flexion(joints: &JointAngles, (mcp, pip): (Joint, Joint)) -> Option<f64> {
    match (joints.get(mcp), joints.get(pip)) {
        (Some(a), Some(b)) => Some(0.5 * (a + b)),
        (Some(a), None) | (None, Some(a)) => Some(a),
        (None, None) => None,
    }
}

/// Whether the fist is closed after `joints`, given whether it was (`was`): the hysteresis of
/// the module docs. No glove, or a finger not measured: open.
#[must_use]
pub fn fist(was: bool, joints: Option<&JointAngles>) -> bool {
    let Some(joints) = joints else {
        return false;
    };
    let mut least = f64::INFINITY;
    for f in FINGERS {
        match flexion(joints, f) {
            Some(phi) if phi.is_finite() => least = least.min(phi),
            _ => return false,
        }
    }
    if was {
        least >= FIST_OPEN
    } else {
        least >= FIST_CLOSE
    }
}

/// Whether the frame's buttons hold the clutch key.
#[must_use]
pub fn key(buttons: u32) -> bool {
    buttons & buttons::CLUTCH != 0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hand(phi: [f64; 4]) -> JointAngles {
        let mut j = JointAngles::new();
        for ((mcp, pip), a) in FINGERS.into_iter().zip(phi) {
            j.set(mcp, a).expect("angle");
            j.set(pip, a).expect("angle");
        }
        j
    }

    #[test]
    fn the_fist_closes_at_1_3_radians_and_opens_below_1_1() {
        assert!(!fist(false, None));
        assert!(
            !fist(false, Some(&hand([0.18, 1.3, 1.35, 1.3]))),
            "pointing"
        );
        assert!(!fist(false, Some(&hand([1.2, 1.3, 1.35, 1.3]))), "a pinch");
        assert!(!fist(false, Some(&hand([1.29, 1.4, 1.45, 1.4]))));
        assert!(fist(false, Some(&hand([1.3, 1.4, 1.45, 1.4]))));
        // Held: stays closed down to 1.1, opens below.
        assert!(fist(true, Some(&hand([1.15, 1.4, 1.45, 1.4]))));
        assert!(fist(true, Some(&hand([1.4, 1.1, 1.45, 1.4]))));
        assert!(!fist(true, Some(&hand([1.4, 1.4, 1.09, 1.4]))));
        // A glove that measures no little finger gives no fist.
        let mut j = hand([1.3; 4]);
        j = {
            let mut k = JointAngles::new();
            for (joint, a) in j.iter() {
                if !matches!(joint, Joint::PinkyMcp | Joint::PinkyPip) {
                    k.set(joint, a).expect("angle");
                }
            }
            k
        };
        assert!(!fist(false, Some(&j)));
        assert!(key(buttons::CLUTCH | buttons::PRIMARY));
        assert!(!key(buttons::PRIMARY));
    }
}
