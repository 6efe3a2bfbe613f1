//! `nendo devices` and `nendo record`, run as the binary, against device emulators on
//! pseudo-terminals.
#![cfg(unix)]

use std::process::Command;

use nendo_devices::Trace;
use nendo_devices::cyberglove::SensorCount;
use nendo_devices::emulator::{CyberGloveModel, FastrakModel, PtyEmulator};

fn nendo() -> Command {
    Command::new(env!("CARGO_BIN_EXE_nendo"))
}

fn temp(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("nendo-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn devices_lists_ports_hid_and_profiles() {
    let out = nendo().arg("devices").output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    for section in ["Serial ports:", "HID devices:", "Profiles:"] {
        assert!(text.contains(section), "{text}");
    }
    assert!(
        text.contains("cyberglove2-18") && text.contains("5dt-ultra-usb on USB 5d70:*"),
        "{text}"
    );
}

#[test]
fn record_writes_a_trace_from_an_emulated_glove_and_tracker() {
    let glove = PtyEmulator::spawn(CyberGloveModel::new(SensorCount::Eighteen)).unwrap();
    let tracker = PtyEmulator::spawn(FastrakModel::new()).unwrap();
    let dir = temp("record");
    let path = dir.join("hand.trace");
    let out = nendo()
        .args([
            "record",
            "--profile",
            "cyberglove2-18-fastrak",
            "--seconds",
            "0.5",
            "--glove-port",
        ])
        .arg(glove.path())
        .arg("--tracker-port")
        .arg(tracker.path())
        .arg("--out")
        .arg(&path)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("recorded"), "{stdout}");
    let trace = Trace::read(&path).unwrap();
    assert_eq!(
        trace.header.profile.as_deref(),
        Some("cyberglove2-18-fastrak")
    );
    assert_eq!(trace.header.joints.len(), 18);
    assert!(
        trace.frames.len() > 50,
        "{} frames in 0.5 s",
        trace.frames.len()
    );
    assert!(
        trace
            .frames
            .iter()
            .any(|f| f.pose.is_some() && f.joints.is_some())
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn record_with_a_single_device_takes_port() {
    let glove = PtyEmulator::spawn(CyberGloveModel::new(SensorCount::TwentyTwo)).unwrap();
    let dir = temp("single");
    let path = dir.join("glove.trace");
    let out = nendo()
        .args([
            "record",
            "--profile",
            "cyberglove2-22",
            "--seconds",
            "0.3",
            "--port",
        ])
        .arg(glove.path())
        .arg("--out")
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let trace = Trace::read(&path).unwrap();
    assert!(trace.frames.iter().all(|f| f.pose.is_none()));
    assert!(trace.frames.iter().filter(|f| f.joints.is_some()).count() > 15);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn record_fails_clearly_when_the_port_is_absent() {
    let dir = temp("absent");
    let path = dir.join("never.trace");
    let out = nendo()
        .args([
            "record",
            "--profile",
            "fastrak",
            "--seconds",
            "0.2",
            "--port",
            "/dev/nendo-absent-port",
            "--out",
        ])
        .arg(&path)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("cannot open serial port /dev/nendo-absent-port"),
        "{stderr}"
    );
    assert!(!path.exists());
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "no temporary file left behind"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn record_refuses_ambiguous_and_mouse_profiles() {
    let out = nendo()
        .args([
            "record",
            "--profile",
            "cyberglove2-18-fastrak",
            "--port",
            "/dev/null",
            "--out",
            "/tmp/x.trace",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--glove-port"));
    let out = nendo()
        .args(["record", "--profile", "mouse", "--out", "/tmp/x.trace"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("window"));
}
