//! `nendo emulate vmc` and `nendo record --profile vmc --vmc-listen`, run as the binary: the
//! emulator's bundles over UDP recorded as a skeleton trace that replays.
#![cfg(unix)]

use std::process::{Child, Stdio};
use std::time::{Duration, Instant};

use crate::support::{nendo, temp_dir as temp};
use nendo_devices::Trace;
use nendo_devices::skeleton::{HandJoint, JointSource};

/// A child process killed when dropped (a failed assertion leaves none running).
struct Running(Child);

impl Drop for Running {
    fn drop(&mut self) {
        if matches!(self.0.try_wait(), Ok(None)) {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
}

fn free_port() -> u16 {
    let s = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    s.local_addr().unwrap().port()
}

#[test]
fn the_vmc_emulator_is_recorded_as_a_skeleton_trace_that_replays() {
    let dir = temp("vmc-record");
    let trace = dir.join("vmc.trace");
    let listen = format!("127.0.0.1:{}", free_port());
    let mut record = Running(
        nendo()
            .args([
                "record",
                "--profile",
                "vmc",
                "--vmc-listen",
                &listen,
                "--out",
            ])
            .arg(&trace)
            .args([
                "--seconds",
                "60",
                "--primitive",
                "plane",
                "--finger",
                "index",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    // The trace appears once the receiver is bound (a hang guard, not a timing assertion).
    let deadline = Instant::now() + Duration::from_secs(60);
    while !trace.exists() {
        assert!(Instant::now() < deadline, "nendo record did not start");
        assert!(
            matches!(record.0.try_wait(), Ok(None)),
            "nendo record exited early"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let emulate = nendo()
        .args([
            "emulate",
            "vmc",
            "--to",
            &listen,
            "--seconds",
            "3.5",
            "--motion",
            "press",
        ])
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&emulate.stdout);
    assert!(
        emulate.status.success(),
        "{said}{}",
        String::from_utf8_lossy(&emulate.stderr)
    );
    assert_eq!(said.lines().next(), Some(listen.as_str()));
    // Ends the recording with a finished trace.
    let pid = record.0.id().to_string();
    assert!(
        std::process::Command::new("kill")
            .args(["-INT", &pid])
            .status()
            .unwrap()
            .success()
    );
    let deadline = Instant::now() + Duration::from_secs(60);
    while matches!(record.0.try_wait(), Ok(None)) {
        assert!(
            Instant::now() < deadline,
            "nendo record did not stop on SIGINT"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let t = Trace::read(&trace).unwrap();
    assert_eq!(t.header.skeleton, Some(nendo_devices::profile::Side::Right));
    let hands: Vec<_> = t.frames.iter().filter_map(|f| f.skeleton).collect();
    assert!(!hands.is_empty(), "no hand recorded");
    for h in &hands {
        assert_eq!(h.source(HandJoint::IndexDistal), JointSource::Measured);
        assert_eq!(h.source(HandJoint::IndexTip), JointSource::Made);
        assert!(h.is_complete());
    }
    // The press reaches 0.3 into the plane: the replay presses it.
    let out = nendo()
        .arg("replay")
        .arg(&trace)
        .arg("--out")
        .arg(dir.join("out.json"))
        .output()
        .unwrap();
    let summary = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{summary}");
    assert!(!summary.contains(" 0 contacts"), "{summary}");
}

#[test]
fn vmc_options_are_refused_where_they_do_not_apply() {
    let dir = temp("vmc-refused");
    let out = nendo()
        .args([
            "record",
            "--profile",
            "fastrak",
            "--vmc-listen",
            "127.0.0.1:39539",
            "--out",
        ])
        .arg(dir.join("t.trace"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no VMC receiver"));
    let out = nendo()
        .args([
            "emulate",
            "vmc",
            "--to",
            "not-an-address",
            "--seconds",
            "0.1",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("ADDR:PORT"));
    let out = nendo()
        .args([
            "emulate",
            "fastrak",
            "--to",
            "127.0.0.1:39539",
            "--seconds",
            "0.1",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(!dir.join("t.trace").exists());
}
