//! `nendo emulate vmc --to ADDR:PORT`: a VMC performer for trying the window (or `nendo
//! record --profile vmc`) without a hand tracker.
//!
//! The hand moves through the same [`Gesture`] as the glove emulators', scripted for the
//! profile's tracker-to-world transform (`vmc` by default) so the fingertip does the gesture
//! over the default plane; each frame, the kinematic hand's skeleton ([`Hand::skeleton`]) is
//! sent as one OSC bundle of VMC bones ([`nendo_devices::vmc::send::bones_of`]: identity
//! rotations, each bone offset from its parent) at 60 bundles a second over UDP to `--to`. The
//! receiver composes them back to the hand's joints and makes the tips by its own rule (the
//! distal joint extended along the middle phalanx), so a bent fingertip lands a little off the
//! glove model's. It prints where it sends on its first line, and ends after `--seconds` or on
//! SIGINT / SIGTERM / SIGHUP.

use std::io::Write as _;
use std::net::UdpSocket;
use std::time::{Duration, Instant};

use glam::{DQuat, DVec3};
use nendo_devices::profile::{self, Input};
use nendo_devices::vmc::{self, send};

use super::emulate::EmulateArgs;
use crate::hand::Hand;

/// Bundles a second, the rate of a webcam tracker.
pub const VMC_RATE_HZ: f64 = 60.0;

/// Sends the gesture until the time is up or a signal comes; the summary line.
pub(crate) fn emulate_vmc(args: &EmulateArgs) -> anyhow::Result<String> {
    let to = args
        .to
        .clone()
        .unwrap_or_else(|| format!("127.0.0.1:{}", vmc::DEFAULT_PORT));
    let addr = vmc::parse_listen(&to)?;
    let name = args.profile.clone().unwrap_or_else(|| "vmc".into());
    let profile = profile::resolve(&name)?;
    if !matches!(profile.input, Input::Skeleton(_)) {
        anyhow::bail!(
            "profile {} has no VMC source: give a VMC profile (the default is vmc)",
            profile.name
        );
    }
    let hand = Hand::new(profile.hand, profile.world_from_tracker)?;
    let trace = args.motion.trace(profile.world_from_tracker, VMC_RATE_HZ)?;
    let mut packets = Vec::with_capacity(trace.frames.len());
    for (k, f) in trace.frames.iter().enumerate() {
        let Some(pose) = f.pose else { continue };
        let skeleton = hand.skeleton(&pose, f.joints.as_ref());
        let bones = send::bones_of(&skeleton)
            .ok_or_else(|| anyhow::anyhow!("frame {k} of the gesture has no whole hand"))?;
        packets.push(send::bundle(
            (DVec3::ZERO, DQuat::IDENTITY),
            &bones,
            k as f32,
        )?);
    }
    if packets.is_empty() {
        anyhow::bail!("motion {} has no frames", args.motion.name());
    }
    let socket = UdpSocket::bind(if addr.is_ipv4() {
        "0.0.0.0:0"
    } else {
        "[::]:0"
    })?;
    println!("{addr}");
    let _ = std::io::stdout().flush();
    let stop = super::signal::DeferredStop::new();
    let period = Duration::from_secs_f64(1.0 / VMC_RATE_HZ);
    let start = Instant::now();
    let end = args.seconds.map(|s| start + Duration::from_secs_f64(s));
    let (mut sent, mut refused) = (0u64, 0u64);
    while !stop.requested() && end.is_none_or(|e| Instant::now() < e) {
        let packet = &packets[(sent % packets.len() as u64) as usize];
        // Nobody listening yet is not an error for a sender: it goes on.
        match socket.send_to(packet, addr) {
            Ok(_) => {}
            Err(_) => refused += 1,
        }
        sent += 1;
        let due = start + period.mul_f64(sent as f64);
        if let Some(wait) = due.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
    }
    Ok(format!(
        "sent {sent} VMC bundles of the {} gesture to {addr} in {:.1} s ({refused} not delivered)",
        args.motion.name(),
        start.elapsed().as_secs_f64()
    ))
}
