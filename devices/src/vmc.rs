//! The VMC protocol (Virtual Motion Capture): a humanoid's bones as OSC messages over UDP,
//! sent by webcam hand trackers (XR Animator, VSeeFace, Webcam Motion Capture) and
//! VirtualMotionCapture (SteamVR trackers, Index knuckles); default port 39539.
//!
//! ## Messages read
//!
//! Packets are OSC messages or bundles (nested bundles too), decoded with `rosc`:
//!
//! | address | arguments | what it is |
//! |---|---|---|
//! | `/VMC/Ext/Root/Pos` | name, `px py pz`, `qx qy qz qw` (more after are ignored) | the avatar's root in Unity's world |
//! | `/VMC/Ext/Bone/Pos` | bone name, `px py pz`, `qx qy qz qw` | a humanoid bone's **local** pose, relative to its parent |
//! | `/VMC/Ext/OK`, `/VMC/Ext/T` | availability, sender time | counted as messages, nothing else |
//! | anything else (`/VMC/Ext/Blend/…`, `/VMC/Ext/Cam`, …) | | ignored and counted |
//!
//! A bone keeps its last pose until a new one comes (a sender may spread its bones over
//! several datagrams), for at most the profile's `bone_timeout_s` (see "Stale bones"). Numbers may be OSC floats, doubles or ints. A message of a known address with the wrong
//! arguments, a non-finite number or a quaternion far from unit norm is **invalid**: counted,
//! and the bone is forgotten until a good message for it comes again (a hand through it then
//! cannot be composed). A datagram that does not decode as OSC (truncated, garbage) is
//! **malformed**: counted and skipped. Nothing a sender does stops the receiver.
//!
//! ## Composing the hand
//!
//! Each bone's world pose is its parent's composed with its local pose, in Unity's frame:
//! `p = p_parent + R_parent · p_local`, `R = R_parent · R_local`, down the humanoid hierarchy
//! Root → `Hips` → `Spine` → `Chest` → `UpperChest` → `RightShoulder` → `RightUpperArm` →
//! `RightLowerArm` → `RightHand` → `RightIndexProximal` → `RightIndexIntermediate` →
//! `RightIndexDistal` (and the same for the other fingers and the left side). `Chest`,
//! `UpperChest` and the shoulders are optional in a Unity humanoid: a bone's parent is the
//! nearest of its ancestors the sender has sent. The bones of the profile's side map to the
//! skeleton's joints as [`BONE_MAP`] says; the tips, the finger metacarpals and the palm are
//! made ([`Skeleton::make_missing`]).
//!
//! ## Unity's frame → nendo's
//!
//! Unity is left-handed, +Y up, metres; nendo's tracker frames are right-handed, +Z up. The
//! change is the reflection `M` swapping Y and Z: a position `(x, y, z)` becomes `(x, z, y)`;
//! a rotation `R` becomes `M·R·M`, which for a quaternion `(x, y, z, w)` is
//! `(−x, −z, −y, w)` (a reflection maps a rotation's axis `a` to `M·a` and reverses its angle).
//! `M` is linear, so composing in Unity's frame and converting the result equals converting
//! each bone and composing in nendo's. Worked example: a hand bone at Unity `(0.55, 1.30,
//! 0.10)` with rotation 90° about Unity's +Z (`q = (0, 0, 0.7071, 0.7071)`, turning +X toward
//! +Y, up) is at `(0.55, 0.10, 1.30)` in nendo's frame with `q = (0, −0.7071, 0, 0.7071)`:
//! 90° about nendo's −Y, which turns +X toward +Z — up again. The profile's
//! `world_from_tracker` then places it in the world.
//!
//! ## Stale bones
//!
//! A bone not refreshed for longer than the profile's `bone_timeout_s`
//! ([`DEFAULT_BONE_TIMEOUT_S`], 0.5 s) is **stale**: it counts as never sent, so the joints
//! composed through it are missing (their validity false) instead of keeping a pose the hand
//! left long ago — a tracker that loses one finger (occluded, out of the camera) while it
//! keeps sending the others. Time is the receiver's clock at each datagram
//! ([`VmcState::packet_at`]): staleness is decided when a datagram comes, so a sender that
//! stops altogether is the stream watchdog's business (silent, then lost). A stale finger's
//! joints are missing, so that finger does not press (the hand loop takes only the fingers
//! whose chains are whole); a stale wrist, or a stale index, middle or little knuckle (the
//! palm is made from them), takes the whole hand with it.
//!
//! ## Frames
//!
//! Every datagram that brought a bone or the root and leaves the profile's palm composable
//! (the wrist and the index, middle and little knuckles) gives one [`Skeleton`] (senders send
//! one bundle per frame), with the joints that can be composed and the rest missing; one that
//! leaves the hand incomplete (a bone of the chain never sent, forgotten or stale) is counted
//! as a fault, and gives no skeleton when not even the palm can be made. Frames that stop
//! arriving make the source silent, then lost, through the stream's watchdog, as for a serial
//! device.
//!
//! Counters, in [`DeviceStats`]: `decode.records` datagrams that decoded, `decode.rejected`
//! malformed datagrams, `decode.bytes_in` bytes received, `invalid` invalid messages,
//! `ignored` messages of other addresses, `faults` datagrams that left the hand incomplete.

use std::collections::BTreeSet;
use std::net::{SocketAddr, UdpSocket};
use std::time::Duration;

use glam::{DQuat, DVec3};
use rosc::{OscMessage, OscPacket, OscType};

use crate::DeviceError;
use crate::device::DeviceStats;
use crate::frame::QUATERNION_NORM_TOLERANCE;
use crate::profile::{HandSize, Side};
use crate::skeleton::{HandJoint, JointPose, JointSource, Skeleton, SkeletonSource};

/// The VMC protocol's default port.
pub const DEFAULT_PORT: u16 = 39539;
/// How long a bone's pose stays good without a new one by default, seconds (a profile's
/// `bone_timeout_s`): fifteen frames of a 30 Hz webcam tracker.
pub const DEFAULT_BONE_TIMEOUT_S: f64 = 0.5;
/// The largest datagram read (a UDP datagram's limit).
const MAX_DATAGRAM: usize = 65_536;
/// Distinct bone names kept for the status panel (a sender cannot grow it without end).
const MAX_SEEN: usize = 128;
/// Datagrams read in one [`SkeletonSource::read`] at most (the rest wait for the next).
const MAX_PER_READ: usize = 4096;

/// Unity humanoid bones (without the side) → skeleton joints.
pub const BONE_MAP: [(&str, HandJoint); 16] = [
    ("Hand", HandJoint::Wrist),
    ("ThumbProximal", HandJoint::ThumbMetacarpal),
    ("ThumbIntermediate", HandJoint::ThumbProximal),
    ("ThumbDistal", HandJoint::ThumbDistal),
    ("IndexProximal", HandJoint::IndexProximal),
    ("IndexIntermediate", HandJoint::IndexIntermediate),
    ("IndexDistal", HandJoint::IndexDistal),
    ("MiddleProximal", HandJoint::MiddleProximal),
    ("MiddleIntermediate", HandJoint::MiddleIntermediate),
    ("MiddleDistal", HandJoint::MiddleDistal),
    ("RingProximal", HandJoint::RingProximal),
    ("RingIntermediate", HandJoint::RingIntermediate),
    ("RingDistal", HandJoint::RingDistal),
    ("LittleProximal", HandJoint::LittleProximal),
    ("LittleIntermediate", HandJoint::LittleIntermediate),
    ("LittleDistal", HandJoint::LittleDistal),
];

/// A position in Unity's frame → nendo's: `(x, y, z) → (x, z, y)`.
pub fn position_from_unity(p: DVec3) -> DVec3 {
    DVec3::new(p.x, p.z, p.y)
}

/// A rotation in Unity's frame → nendo's: `M·R·M`, quaternion `(x, y, z, w) → (−x, −z, −y, w)`.
pub fn rotation_from_unity(q: DQuat) -> DQuat {
    DQuat::from_xyzw(-q.x, -q.z, -q.y, q.w)
}

/// A pose: position and rotation (of a bone, in its parent's or in the world's frame).
type Pose = (DVec3, DQuat);

/// The bones the hands hang from, by Unity humanoid name: the side-independent ones, then
/// per side (prefix `Right` / `Left`) the arm, the hand and the fingers.
fn parents(bone: &str) -> Vec<String> {
    let side = ["Right", "Left"].into_iter().find(|s| bone.starts_with(s));
    let body = |names: &[&str]| names.iter().map(|s| (*s).to_owned()).collect();
    let Some(side) = side else {
        return match bone {
            "Hips" => Vec::new(),
            "Spine" => body(&["Hips"]),
            "Chest" => body(&["Spine"]),
            "UpperChest" => body(&["Chest", "Spine"]),
            _ => Vec::new(),
        };
    };
    let rest = &bone[side.len()..];
    let sided = |names: &[&str]| names.iter().map(|s| format!("{side}{s}")).collect();
    match rest {
        "Shoulder" => body(&["UpperChest", "Chest", "Spine"]),
        "UpperArm" => {
            let mut v: Vec<String> = sided(&["Shoulder"]);
            v.extend(body(&["UpperChest", "Chest", "Spine"]));
            v
        }
        "LowerArm" => sided(&["UpperArm"]),
        "Hand" => sided(&["LowerArm"]),
        _ => {
            for finger in ["Thumb", "Index", "Middle", "Ring", "Little"] {
                match rest.strip_prefix(finger) {
                    Some("Proximal") => return sided(&["Hand"]),
                    Some("Intermediate") => return vec![format!("{side}{finger}Proximal")],
                    Some("Distal") => return vec![format!("{side}{finger}Intermediate")],
                    _ => {}
                }
            }
            Vec::new()
        }
    }
}

/// Whether a bone is one the hands hang from (the others are only listed as seen).
fn is_hand_chain(bone: &str) -> bool {
    bone == "Hips" || !parents(bone).is_empty()
}

/// The receiver's state: the root and the latest local pose of every bone of the hands'
/// chains, in Unity's frame. Pure (no socket): [`VmcState::packet`] takes a datagram.
#[derive(Debug, Clone)]
pub struct VmcState {
    side: Side,
    hand: HandSize,
    root: Pose,
    /// Every bone's local pose and the time it came, seconds on the receiver's clock.
    bones: std::collections::HashMap<String, (Pose, f64)>,
    seen: BTreeSet<String>,
    stats: DeviceStats,
    /// The time of the latest datagram, seconds.
    now: f64,
    /// Bones older than this are stale, seconds.
    timeout: f64,
}

impl VmcState {
    /// A receiver's state for the hand of `hand.side`, with `hand`'s distal lengths for the
    /// made tips.
    pub fn new(hand: HandSize) -> VmcState {
        VmcState {
            side: hand.side,
            hand,
            root: (DVec3::ZERO, DQuat::IDENTITY),
            bones: Default::default(),
            seen: BTreeSet::new(),
            stats: DeviceStats::default(),
            now: 0.0,
            timeout: DEFAULT_BONE_TIMEOUT_S,
        }
    }

    /// Sets how long a bone stays good without a new pose, seconds (see "Stale bones"; a
    /// value that is not positive and finite keeps the current one).
    pub fn set_bone_timeout(&mut self, seconds: f64) {
        if seconds.is_finite() && seconds > 0.0 {
            self.timeout = seconds;
        }
    }

    /// The hand-chain bones that are stale now (for a status panel).
    pub fn stale(&self) -> Vec<String> {
        let mut v: Vec<String> = self
            .bones
            .iter()
            .filter(|(_, (_, at))| !self.is_fresh(*at))
            .map(|(name, _)| name.clone())
            .collect();
        v.sort();
        v
    }

    fn is_fresh(&self, at: f64) -> bool {
        self.now - at <= self.timeout
    }

    /// A bone's local pose, if it was sent and is not stale.
    fn bone(&self, name: &str) -> Option<Pose> {
        self.bones
            .get(name)
            .filter(|(_, at)| self.is_fresh(*at))
            .map(|(p, _)| *p)
    }

    /// The counters (see the module docs).
    pub fn stats(&self) -> DeviceStats {
        self.stats
    }

    /// The bone names received so far (at most 128).
    pub fn seen(&self) -> Vec<String> {
        self.seen.iter().cloned().collect()
    }

    /// Reads one datagram at the time of the last one (no bone goes stale): see
    /// [`VmcState::packet_at`].
    pub fn packet(&mut self, bytes: &[u8]) -> Option<Skeleton> {
        self.packet_at(bytes, self.now)
    }

    /// Reads one datagram that came at `now` seconds on the receiver's clock (never before
    /// the last one's: an earlier time is taken as the last one's); returns the hand it
    /// gives, if any (see the module docs).
    pub fn packet_at(&mut self, bytes: &[u8], now: f64) -> Option<Skeleton> {
        if now.is_finite() && now > self.now {
            self.now = now;
        }
        self.stats.decode.bytes_in += bytes.len() as u64;
        // rosc reads a bundle's elements while they decode and leaves the rest: a datagram
        // with bytes left over is truncated or has garbage after it, and is refused whole.
        let packet = match rosc::decoder::decode_udp(bytes) {
            Ok(([], p)) => p,
            _ => {
                self.stats.decode.rejected += 1;
                self.stats.decode.skipped_bytes += bytes.len() as u64;
                return None;
            }
        };
        self.stats.decode.records += 1;
        self.stats.decode.record_bytes += bytes.len() as u64;
        let mut posed = false;
        self.visit(&packet, &mut posed);
        if !posed {
            return None;
        }
        let skeleton = self.skeleton();
        if !skeleton.as_ref().is_some_and(Skeleton::is_complete) {
            self.stats.faults += 1;
        }
        skeleton
    }

    fn visit(&mut self, packet: &OscPacket, posed: &mut bool) {
        match packet {
            OscPacket::Message(m) => *posed |= self.message(m),
            OscPacket::Bundle(b) => {
                for p in &b.content {
                    self.visit(p, posed);
                }
            }
        }
    }

    /// Reads one message; whether it was a pose (of the root or a bone).
    fn message(&mut self, m: &OscMessage) -> bool {
        match m.addr.as_str() {
            "/VMC/Ext/Root/Pos" | "/VMC/Ext/Bone/Pos" => {
                let root = m.addr == "/VMC/Ext/Root/Pos";
                let name = match m.args.first() {
                    Some(OscType::String(s)) => s.clone(),
                    _ => {
                        self.stats.invalid += 1;
                        return false;
                    }
                };
                let pose = pose_of(&m.args[1..]);
                if !root && self.seen.len() < MAX_SEEN {
                    self.seen.insert(name.clone());
                }
                match (root, pose) {
                    (true, Some(p)) => self.root = p,
                    (true, None) => {
                        self.stats.invalid += 1;
                        self.root = (DVec3::ZERO, DQuat::IDENTITY);
                    }
                    (false, Some(p)) if is_hand_chain(&name) => {
                        self.bones.insert(name, (p, self.now));
                    }
                    (false, Some(_)) => {}
                    (false, None) => {
                        self.stats.invalid += 1;
                        self.bones.remove(&name);
                    }
                }
                true
            }
            "/VMC/Ext/OK" | "/VMC/Ext/T" => false,
            _ => {
                self.stats.ignored += 1;
                false
            }
        }
    }

    /// A bone's pose in Unity's world, through the nearest ancestors the sender has sent
    /// (stale bones count as not sent).
    fn world(&self, bone: &str, depth: usize) -> Option<Pose> {
        let (p, q) = self.bone(bone)?;
        if bone == "Hips" {
            let (rp, rq) = self.root;
            return Some((rp + rq * p, rq * q));
        }
        if depth > 16 {
            return None;
        }
        let parent = parents(bone).into_iter().find(|b| self.bone(b).is_some())?;
        let (pp, pq) = self.world(&parent, depth + 1)?;
        Some((pp + pq * p, pq * q))
    }

    /// The profile's hand, composed and converted (the tips, metacarpals and palm made):
    /// every joint whose bones are sent and fresh, the others missing; `None` when not even
    /// the palm can be made (see the module docs).
    pub fn skeleton(&self) -> Option<Skeleton> {
        let side = match self.side {
            Side::Right => "Right",
            Side::Left => "Left",
        };
        let mut s = Skeleton::new(self.side);
        for (bone, joint) in BONE_MAP {
            let Some((p, q)) = self.world(&format!("{side}{bone}"), 0) else {
                continue;
            };
            if let Ok(pose) = JointPose::new(position_from_unity(p), rotation_from_unity(q), None) {
                s.set(joint, pose, JointSource::Measured);
            }
        }
        s.make_missing(&self.hand);
        s.get(HandJoint::Palm).is_some().then_some(s)
    }
}

/// Seven numbers `px py pz qx qy qz qw` (more may follow): finite, the quaternion of unit
/// norm within [`QUATERNION_NORM_TOLERANCE`] (normalised), the position within 100 m.
fn pose_of(args: &[OscType]) -> Option<Pose> {
    if args.len() < 7 {
        return None;
    }
    let mut v = [0.0; 7];
    for (x, a) in v.iter_mut().zip(args) {
        *x = match a {
            OscType::Float(f) => f64::from(*f),
            OscType::Double(d) => *d,
            OscType::Int(i) => f64::from(*i),
            _ => return None,
        };
    }
    let p = DVec3::new(v[0], v[1], v[2]);
    let q = DQuat::from_xyzw(v[3], v[4], v[5], v[6]);
    let n = q.length();
    let ok = p.is_finite()
        && p.abs().max_element() <= crate::frame::POSITION_LIMIT_M
        && q.is_finite()
        && (n - 1.0).abs() <= QUATERNION_NORM_TOLERANCE;
    ok.then(|| (p, q / n))
}

/// The VMC receiver: a UDP socket on the profile's address and a [`VmcState`].
#[derive(Debug)]
pub struct VmcReceiver {
    listen: String,
    socket: Option<UdpSocket>,
    state: VmcState,
    starts: u64,
    buffer: Vec<u8>,
    /// The receiver's clock for stale bones.
    clock: std::time::Instant,
}

impl VmcReceiver {
    /// A receiver for `listen` (`ADDR:PORT`), not yet bound.
    ///
    /// # Errors
    /// [`DeviceError::InvalidValue`] when `listen` is not an address and port.
    pub fn new(listen: &str, hand: HandSize) -> Result<VmcReceiver, DeviceError> {
        parse_listen(listen)?;
        Ok(VmcReceiver {
            listen: listen.to_owned(),
            socket: None,
            state: VmcState::new(hand),
            starts: 0,
            buffer: vec![0; MAX_DATAGRAM],
            clock: std::time::Instant::now(),
        })
    }

    /// Sets how long a bone stays good without a new pose ([`VmcState::set_bone_timeout`]).
    pub fn set_bone_timeout(&mut self, seconds: f64) {
        self.state.set_bone_timeout(seconds);
    }

    /// The bound address (the port chosen, for `:0`), once started.
    pub fn local_addr(&self) -> Option<SocketAddr> {
        self.socket.as_ref().and_then(|s| s.local_addr().ok())
    }

    fn io(&self, error: std::io::Error) -> DeviceError {
        DeviceError::Io {
            device: self.describe(),
            error,
        }
    }
}

/// Checks a listening address `ADDR:PORT` (an IP address, not a host name).
///
/// # Errors
/// [`DeviceError::InvalidValue`] saying what is expected.
pub fn parse_listen(listen: &str) -> Result<SocketAddr, DeviceError> {
    listen.parse().map_err(|_| {
        DeviceError::InvalidValue(format!(
            "VMC listen address `{listen}`: expected ADDR:PORT, such as 127.0.0.1:{DEFAULT_PORT}"
        ))
    })
}

impl SkeletonSource for VmcReceiver {
    fn describe(&self) -> String {
        format!("VMC receiver on {}", self.listen)
    }

    fn start(&mut self) -> Result<(), DeviceError> {
        if self.socket.is_some() {
            return Ok(());
        }
        let addr = parse_listen(&self.listen)?;
        let socket = UdpSocket::bind(addr).map_err(|e| self.io(e))?;
        self.socket = Some(socket);
        self.starts += 1;
        Ok(())
    }

    fn read(&mut self, timeout: Duration, out: &mut Vec<Skeleton>) -> Result<(), DeviceError> {
        let Some(socket) = self.socket.take() else {
            return Err(self.io(std::io::Error::new(
                std::io::ErrorKind::NotConnected,
                "not started",
            )));
        };
        let result = self.receive(&socket, timeout, out);
        self.socket = Some(socket);
        result
    }

    fn stop(&mut self) {
        self.socket = None;
    }

    fn stats(&self) -> DeviceStats {
        DeviceStats {
            starts: self.starts,
            ..self.state.stats()
        }
    }

    fn seen(&self) -> Vec<String> {
        self.state.seen()
    }
}

impl VmcReceiver {
    /// Waits at most `timeout` for a datagram, then reads every one waiting.
    fn receive(
        &mut self,
        socket: &UdpSocket,
        timeout: Duration,
        out: &mut Vec<Skeleton>,
    ) -> Result<(), DeviceError> {
        let timeout = timeout.max(Duration::from_millis(1));
        socket
            .set_read_timeout(Some(timeout))
            .map_err(|e| self.io(e))?;
        for i in 0..MAX_PER_READ {
            if i == 1 {
                socket.set_nonblocking(true).map_err(|e| self.io(e))?;
            }
            match socket.recv(&mut self.buffer) {
                Ok(n) => {
                    let bytes = &self.buffer[..n.min(MAX_DATAGRAM)];
                    let now = self.clock.elapsed().as_secs_f64();
                    if let Some(s) = self.state.packet_at(bytes, now) {
                        out.push(s);
                    }
                }
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::WouldBlock
                            | std::io::ErrorKind::TimedOut
                            | std::io::ErrorKind::Interrupted
                    ) =>
                {
                    break;
                }
                // An ICMP "port unreachable" from an earlier send is not ours to mind.
                Err(e) if e.kind() == std::io::ErrorKind::ConnectionRefused => break,
                Err(e) => {
                    let _ = socket.set_nonblocking(false);
                    return Err(self.io(e));
                }
            }
        }
        socket.set_nonblocking(false).map_err(|e| self.io(e))?;
        Ok(())
    }
}

pub mod send;

#[cfg(test)]
mod tests;
