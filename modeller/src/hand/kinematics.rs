//! The kinematic hand: glove bend angles → joint positions of every finger; the tracker pose
//! and the profile's `world_from_tracker` place it in the world (P2 §2.1: "from these
//! values the coordinates of the hand and of the finger joints in virtual space are computed").
//!
//! ## The hand in its sensor frame
//!
//! Coordinates are those of the hand sensor (`nendo_devices::frame`): origin on the back of the
//! hand, **+X along the middle finger, +Y toward the thumb of a right hand (toward the little
//! finger of a left one), +Z out of the back of the hand**; metres. With `L` the palm length,
//! `W` the palm width (both from the profile's [`HandSize`]) and `s = +1` for a right hand,
//! `−1` for a left one:
//!
//! - the sensor sits over the centre of the palm; the palm is `T = 0.3·W` thick, so the
//!   knuckles (metacarpophalangeal joints) of the four fingers lie on the line `x = L/2`,
//!   `z = −T/2`, at `y = s·(3/8, 1/8, −1/8, −3/8)·W` for index, middle, ring and little finger;
//! - the thumb's base (its carpometacarpal joint) is at `(−0.2·L, s·0.3·W, −T/2)`;
//! - a straight finger points along `f(α) = cos α·X + s·sin α·Y`, `α` its spread toward the
//!   thumb: 0 for the middle finger (the frame's reference), `+a_im` for the index, `−a_mr` for
//!   the ring finger and `−a_mr − a_rp` for the little finger (`a_im`, `a_mr`, `a_rp` the
//!   glove's abduction angles between neighbouring fingers); the thumb spreads
//!   `α = 25° + a_im + a_ti` (`a_ti`: the thumb–index abduction, measured from the index);
//! - flexion curls a finger toward the palm: segment `k` of a finger points along
//!   `d_k = cos Θ_k·f + sin Θ_k·n`, `Θ_k = θ_1 + … + θ_k` the sum of the flexion angles of the
//!   joints before it, `n = −Z` for the four fingers; for the thumb `n = cos ρ·g − sin ρ·Z`,
//!   `g = sin α·X − s·cos α·Y` the in-palm direction across toward the fingers and `ρ` the
//!   thumb roll, so a thumb without roll folds across the palm and a rolled one toward it;
//! - joint positions follow from the segment lengths `l_1, l_2, l_3` of the profile:
//!   `p_0` = knuckle (thumb base), `p_k = p_{k−1} + l_k·d_k`; `p_3` is the fingertip.
//!
//! The flexions: `θ_1, θ_2, θ_3` = MCP, PIP, DIP of a finger; for the thumb `θ_1 = 0` (its
//! carpometacarpal flexion is not measured), `θ_2` = thumb MCP, `θ_3` = thumb IP. A joint the
//! glove does not measure takes the angle of the joint before it (a 5-sensor glove measures one
//! bend per finger), except the DIP, which takes two thirds of the PIP angle (the usual coupling
//! of the two distal joints). Unmeasured abductions and roll are 0. The palm arch and the wrist
//! angles are not used: the sensor rides on the back of the hand, past the wrist.
//!
//! ## In the world
//!
//! A point `x` of the hand is at `t + c·R·(P + Q·x)` in the world, `(P, Q)` the tracker pose
//! (metres, sensor → tracker rotation) and `(t, R, c)` the profile's `world_from_tracker`:
//! the hand's lengths scale with the tracker's motion, so the virtual hand is as big, in world
//! units, as the real one is in the tracker's metres times `c`.

use glam::{DQuat, DVec3};
use nendo_devices::profile::{FingerLengths, Side};
use nendo_devices::{HandSize, Joint, JointAngles, TrackerPose, WorldFromTracker};
use std::fmt;
use std::str::FromStr;

use super::HandError;

/// A finger of the hand.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Digit {
    /// The thumb.
    Thumb,
    /// The index finger (the active finger by default).
    #[default]
    Index,
    /// The middle finger.
    Middle,
    /// The ring finger.
    Ring,
    /// The little finger.
    Pinky,
}

impl Digit {
    /// Every digit, thumb first.
    pub const ALL: [Digit; 5] = [
        Digit::Thumb,
        Digit::Index,
        Digit::Middle,
        Digit::Ring,
        Digit::Pinky,
    ];

    /// The name used on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Digit::Thumb => "thumb",
            Digit::Index => "index",
            Digit::Middle => "middle",
            Digit::Ring => "ring",
            Digit::Pinky => "pinky",
        }
    }

    /// Position in [`Digit::ALL`].
    #[must_use]
    pub fn index(self) -> usize {
        self as usize
    }
}

impl fmt::Display for Digit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Digit {
    type Err = crate::surface::UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Digit::ALL
            .into_iter()
            .find(|d| d.name() == s)
            .ok_or_else(|| crate::surface::UnknownName {
                kind: "finger",
                given: s.to_owned(),
                expected: "thumb, index, middle, ring or pinky",
            })
    }
}

/// The four points of one finger: `points[0]` the knuckle (the thumb's base), then the two
/// inner joints, `points[3]` the fingertip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FingerChain {
    /// Knuckle, two joints, fingertip.
    pub points: [DVec3; 4],
}

impl FingerChain {
    /// The fingertip `p_3`.
    #[must_use]
    pub fn tip(&self) -> DVec3 {
        self.points[3]
    }

    /// The unit direction of the distal segment (`p_2 → p_3`): the finger's pointing direction
    /// at its tip.
    #[must_use]
    pub fn direction(&self) -> DVec3 {
        (self.points[3] - self.points[2]).normalize_or(DVec3::X)
    }

    /// Total length of the three segments.
    #[must_use]
    pub fn length(&self) -> f64 {
        self.points.windows(2).map(|w| (w[1] - w[0]).length()).sum()
    }
}

/// The whole hand at one instant, in world coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HandPose {
    /// Where the hand sensor is (the back of the hand).
    pub sensor: DVec3,
    /// Rotation from the hand's sensor frame to the world.
    pub orientation: DQuat,
    /// World units per metre of the hand (`c` of `world_from_tracker`).
    pub scale: f64,
    /// The fingers, indexed by [`Digit::index`].
    pub fingers: [FingerChain; 5],
}

impl HandPose {
    /// One finger.
    #[must_use]
    pub fn finger(&self, digit: Digit) -> &FingerChain {
        &self.fingers[digit.index()]
    }
}

/// The palm of a placed hand, in world units ([`Hand::palm`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Palm {
    /// The centre of the palm's face.
    pub centre: DVec3,
    /// The unit normal out of the palm (away from the back of the hand).
    pub normal: DVec3,
    /// Half the palm's width.
    pub half_width: f64,
}

/// The kinematic hand of a profile: its sizes and the tracker-to-world transform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hand {
    size: HandSize,
    world_from_tracker: WorldFromTracker,
}

/// Palm thickness as a fraction of the palm width.
const PALM_THICKNESS: f64 = 0.3;
/// Rest spread of the thumb from the middle finger, radians (25°).
const THUMB_REST_SPREAD: f64 = 25.0 * std::f64::consts::PI / 180.0;

impl Hand {
    /// A hand of these sizes placed by this transform.
    ///
    /// # Errors
    /// [`HandError::Model`] when a length is not a positive finite number or the transform is
    /// not a similarity (see [`WorldFromTracker::validate`]).
    pub fn new(size: HandSize, world_from_tracker: WorldFromTracker) -> Result<Self, HandError> {
        let fingers = [size.thumb, size.index, size.middle, size.ring, size.pinky];
        let ok = fingers
            .iter()
            .flat_map(|f| [f.proximal, f.middle, f.distal])
            .chain([size.palm_length, size.palm_width])
            .all(|l| l.is_finite() && l > 0.0);
        if !ok {
            return Err(HandError::Model(format!(
                "hand lengths must be positive: {size:?}"
            )));
        }
        world_from_tracker
            .validate()
            .map_err(|e| HandError::Model(e.to_string()))?;
        Ok(Self {
            size,
            world_from_tracker,
        })
    }

    /// The hand's sizes.
    #[must_use]
    pub fn size(&self) -> &HandSize {
        &self.size
    }

    /// The tracker-to-world transform.
    #[must_use]
    pub fn world_from_tracker(&self) -> &WorldFromTracker {
        &self.world_from_tracker
    }

    /// World units per metre.
    #[must_use]
    pub fn scale(&self) -> f64 {
        self.world_from_tracker.scale
    }

    fn lengths(&self, digit: Digit) -> FingerLengths {
        match digit {
            Digit::Thumb => self.size.thumb,
            Digit::Index => self.size.index,
            Digit::Middle => self.size.middle,
            Digit::Ring => self.size.ring,
            Digit::Pinky => self.size.pinky,
        }
    }

    /// Length of a finger (sum of its three segments) in world units.
    #[must_use]
    pub fn finger_length(&self, digit: Digit) -> f64 {
        let l = self.lengths(digit);
        (l.proximal + l.middle + l.distal) * self.scale()
    }

    /// One finger in the sensor frame, metres (see the module docs). `joints: None` is the flat
    /// hand (every angle 0).
    #[must_use]
    pub fn local_finger(&self, digit: Digit, joints: Option<&JointAngles>) -> FingerChain {
        let angle = |j: Joint| joints.and_then(|a| a.get(j));
        let s = match self.size.side {
            Side::Right => 1.0,
            Side::Left => -1.0,
        };
        let (l, w) = (self.size.palm_length, self.size.palm_width);
        let t = PALM_THICKNESS * w;
        let a_im = angle(Joint::IndexMiddleAbduction).unwrap_or(0.0);
        let a_mr = angle(Joint::MiddleRingAbduction).unwrap_or(0.0);
        let a_rp = angle(Joint::RingPinkyAbduction).unwrap_or(0.0);
        // (base, spread, flexion joints, bend direction)
        let (base, spread, flex) = match digit {
            Digit::Thumb => {
                let a = THUMB_REST_SPREAD + a_im + angle(Joint::ThumbIndexAbduction).unwrap_or(0.0);
                let mcp = angle(Joint::ThumbMcp).unwrap_or(0.0);
                let ip = angle(Joint::ThumbIp).unwrap_or(mcp);
                (
                    DVec3::new(-0.2 * l, s * 0.3 * w, -0.5 * t),
                    a,
                    [0.0, mcp, ip],
                )
            }
            _ => {
                let (y, a, [mcp, pip, dip]) = match digit {
                    Digit::Index => (
                        0.375,
                        a_im,
                        [Joint::IndexMcp, Joint::IndexPip, Joint::IndexDip],
                    ),
                    Digit::Middle => (
                        0.125,
                        0.0,
                        [Joint::MiddleMcp, Joint::MiddlePip, Joint::MiddleDip],
                    ),
                    Digit::Ring => (
                        -0.125,
                        -a_mr,
                        [Joint::RingMcp, Joint::RingPip, Joint::RingDip],
                    ),
                    _ => (
                        -0.375,
                        -a_mr - a_rp,
                        [Joint::PinkyMcp, Joint::PinkyPip, Joint::PinkyDip],
                    ),
                };
                let t1 = angle(mcp).unwrap_or(0.0);
                let t2 = angle(pip).unwrap_or(t1);
                let t3 = angle(dip).unwrap_or(2.0 / 3.0 * t2);
                (DVec3::new(0.5 * l, s * y * w, -0.5 * t), a, [t1, t2, t3])
            }
        };
        let f = DVec3::new(spread.cos(), s * spread.sin(), 0.0);
        let n = if digit == Digit::Thumb {
            let rho = angle(Joint::ThumbRoll).unwrap_or(0.0);
            let g = DVec3::new(spread.sin(), -s * spread.cos(), 0.0);
            rho.cos() * g - rho.sin() * DVec3::Z
        } else {
            -DVec3::Z
        };
        let lengths = self.lengths(digit);
        let mut points = [base; 4];
        let mut theta = 0.0;
        for (k, len) in [lengths.proximal, lengths.middle, lengths.distal]
            .into_iter()
            .enumerate()
        {
            theta += flex[k];
            points[k + 1] = points[k] + len * (theta.cos() * f + theta.sin() * n);
        }
        FingerChain { points }
    }

    /// The hand placed in the world by a tracker pose.
    #[must_use]
    pub fn pose(&self, pose: &TrackerPose, joints: Option<&JointAngles>) -> HandPose {
        self.pose_shifted(pose, joints, DVec3::ZERO)
    }

    /// The hand placed so that the fingertip of `digit` sits at the tracker position: the
    /// mouse hand, whose pose is the point on the view ray where the finger ends.
    #[must_use]
    pub fn pose_at_fingertip(
        &self,
        pose: &TrackerPose,
        joints: Option<&JointAngles>,
        digit: Digit,
    ) -> HandPose {
        let tip = self.local_finger(digit, joints).tip();
        self.pose_shifted(pose, joints, tip)
    }

    fn pose_shifted(
        &self,
        pose: &TrackerPose,
        joints: Option<&JointAngles>,
        origin: DVec3,
    ) -> HandPose {
        let w = &self.world_from_tracker;
        let (r, c, t) = (w.rotation(), w.scale, w.translation());
        let world = |x: DVec3| t + c * (r * (pose.position + pose.orientation * (x - origin)));
        let fingers = Digit::ALL.map(|d| {
            let chain = self.local_finger(d, joints);
            FingerChain {
                points: chain.points.map(world),
            }
        });
        HandPose {
            sensor: world(DVec3::ZERO),
            orientation: r * pose.orientation,
            scale: c,
            fingers,
        }
    }

    /// The palm as a contact shape, in the world: the centre of the palm's face, under the
    /// sensor (`(0, 0, −T)` in the sensor frame, `T = 0.3·W` the palm's thickness), its
    /// outward normal (`−Z`, away from the back of the hand), and its half-width `W/2`.
    #[must_use]
    pub fn palm(&self, pose: &HandPose) -> Palm {
        let t = PALM_THICKNESS * self.size.palm_width;
        Palm {
            centre: pose.sensor + pose.orientation * DVec3::new(0.0, 0.0, -t) * pose.scale,
            normal: pose.orientation * DVec3::NEG_Z,
            half_width: 0.5 * self.size.palm_width * pose.scale,
        }
    }

    /// The tracker pose that puts the fingertip of `digit`, bent by `joints`, at `tip` (world)
    /// with its distal segment pointing along `direction` and the back of the hand turned as
    /// far toward `up` as that allows: the inverse of [`Hand::pose`] for one finger, used to
    /// script hand motions. `None` when `direction` is zero or parallel to `up` or a value is
    /// not finite.
    #[must_use]
    pub fn pose_for_fingertip(
        &self,
        digit: Digit,
        joints: Option<&JointAngles>,
        tip: DVec3,
        direction: DVec3,
        up: DVec3,
    ) -> Option<TrackerPose> {
        let chain = self.local_finger(digit, joints);
        let local = frame_of(chain.direction(), DVec3::Z)?;
        let world = frame_of(direction, up)?;
        // hand → world rotation W with W·local = world, then tracker orientation Q = R⁻¹·W.
        let w = world * local.inverse();
        let r = self.world_from_tracker.rotation();
        let q = (r.inverse() * w).normalize();
        let c = self.world_from_tracker.scale;
        let p = r.inverse() * (tip - self.world_from_tracker.translation()) / c - q * chain.tip();
        TrackerPose::new(p, q).ok()
    }
}

/// The rotation taking (X, Z) to (`x`, the part of `z` across `x`), as a quaternion.
fn frame_of(x: DVec3, z: DVec3) -> Option<DQuat> {
    let x = x.try_normalize()?;
    let z = (z - z.dot(x) * x).try_normalize()?;
    let y = z.cross(x);
    Some(DQuat::from_mat3(&glam::DMat3::from_cols(x, y, z)).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hand() -> Hand {
        Hand::new(HandSize::default(), WorldFromTracker::default()).unwrap()
    }

    #[test]
    fn a_flat_hand_points_along_x_with_the_profile_lengths() {
        let h = hand();
        let size = HandSize::default();
        for d in [Digit::Index, Digit::Middle, Digit::Ring, Digit::Pinky] {
            let c = h.local_finger(d, None);
            assert!((c.direction() - DVec3::X).length() < 1e-15, "{d}");
            assert!((c.points[0].x - 0.5 * size.palm_length).abs() < 1e-15);
            assert!((c.length() - h.finger_length(d)).abs() < 1e-15);
        }
        let index = h.local_finger(Digit::Index, None);
        let little = h.local_finger(Digit::Pinky, None);
        assert!(
            index.tip().y > 0.0 && little.tip().y < 0.0,
            "right hand: thumb side is +Y"
        );
        let thumb = h.local_finger(Digit::Thumb, None);
        assert!(thumb.tip().y > index.tip().y);
    }

    #[test]
    fn flexion_curls_toward_the_palm_and_keeps_lengths() {
        let h = hand();
        let mut a = JointAngles::new();
        a.set(Joint::IndexMcp, 0.5).unwrap();
        a.set(Joint::IndexPip, 0.8).unwrap();
        let c = h.local_finger(Digit::Index, Some(&a));
        let size = HandSize::default();
        let seg = |k: usize| (c.points[k + 1] - c.points[k]).length();
        assert!((seg(0) - size.index.proximal).abs() < 1e-15);
        assert!((seg(2) - size.index.distal).abs() < 1e-15);
        // DIP unmeasured: two thirds of the PIP; the distal direction is at 0.5 + 0.8 + 0.8·2/3.
        let theta: f64 = 0.5 + 0.8 + 0.8 * 2.0 / 3.0;
        let want = DVec3::new(theta.cos(), 0.0, -theta.sin());
        assert!((c.direction() - want).length() < 1e-12);
        assert!(c.tip().z < c.points[0].z, "curled toward the palm (−Z)");
        // One sensor per finger: the PIP follows the MCP.
        let mut one = JointAngles::new();
        one.set(Joint::MiddleMcp, 0.4).unwrap();
        let m = h.local_finger(Digit::Middle, Some(&one));
        let d1 = (m.points[1] - m.points[0]).normalize();
        let d2 = (m.points[2] - m.points[1]).normalize();
        assert!((d1.angle_between(d2) - 0.4).abs() < 1e-12);
    }

    #[test]
    fn a_left_hand_mirrors_a_right_hand() {
        let right = hand();
        let size = HandSize {
            side: Side::Left,
            ..HandSize::default()
        };
        let left = Hand::new(size, WorldFromTracker::default()).unwrap();
        let mut a = JointAngles::new();
        a.set(Joint::IndexMiddleAbduction, 0.2).unwrap();
        a.set(Joint::ThumbRoll, 0.4).unwrap();
        a.set(Joint::ThumbMcp, 0.3).unwrap();
        for d in Digit::ALL {
            let r = right.local_finger(d, Some(&a));
            let l = left.local_finger(d, Some(&a));
            for k in 0..4 {
                let m = r.points[k] * DVec3::new(1.0, -1.0, 1.0);
                assert!((l.points[k] - m).length() < 1e-15, "{d} {k}");
            }
        }
    }

    #[test]
    fn the_inverse_places_the_fingertip_where_asked() {
        let w = WorldFromTracker {
            translation: [0.5, -6.0, 1.0],
            rotation_wxyz: [0.9f64.sqrt(), 0.0, 0.1f64.sqrt(), 0.0],
            scale: 20.0,
        };
        let h = Hand::new(HandSize::default(), w).unwrap();
        let mut a = JointAngles::new();
        a.set(Joint::IndexMcp, 0.3).unwrap();
        a.set(Joint::IndexPip, 0.4).unwrap();
        let tip = DVec3::new(1.0, 2.0, 3.0);
        let dir = DVec3::new(0.2, -0.3, -1.0).normalize();
        let pose = h
            .pose_for_fingertip(Digit::Index, Some(&a), tip, dir, DVec3::Z)
            .unwrap();
        let placed = h.pose(&pose, Some(&a));
        let f = placed.finger(Digit::Index);
        assert!((f.tip() - tip).length() < 1e-12);
        assert!((f.direction() - dir).length() < 1e-12);
        assert!((f.length() - h.finger_length(Digit::Index)).abs() < 1e-12);
        // The back of the hand turns toward `up` as far as the finger's direction allows.
        let back = placed.orientation * DVec3::Z;
        assert!(back.dot(DVec3::Z) > 0.0);
        assert!(
            h.pose_for_fingertip(Digit::Index, Some(&a), tip, DVec3::ZERO, DVec3::Z)
                .is_none()
        );
    }

    #[test]
    fn the_mouse_hand_ends_at_the_tracked_point() {
        let h = hand();
        let pose =
            TrackerPose::new(DVec3::new(1.0, 2.0, 3.0), DQuat::from_rotation_z(0.7)).unwrap();
        let placed = h.pose_at_fingertip(&pose, None, Digit::Index);
        assert!((placed.finger(Digit::Index).tip() - pose.position).length() < 1e-15);
        assert!(
            (placed.finger(Digit::Index).direction() - pose.orientation * DVec3::X).length()
                < 1e-12
        );
    }

    #[test]
    fn digits_parse_by_name() {
        for d in Digit::ALL {
            assert_eq!(d.name().parse::<Digit>(), Ok(d));
        }
        assert!("toe".parse::<Digit>().is_err());
    }
}
