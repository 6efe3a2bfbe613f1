//! `nendo devices` and `nendo record`, run as the binary, against device emulators on
//! pseudo-terminals.
#![cfg(unix)]

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::support::{nendo, temp_dir as temp};
use nendo_devices::Trace;
use nendo_devices::cyberglove::SensorCount;
use nendo_devices::emulator::{CyberGloveModel, FastrakModel, PtyEmulator};

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
    // Both sources' counters, faults among them.
    assert!(
        stdout.contains("glove: ") && stdout.contains("tracker: ") && stdout.contains(" faults"),
        "{stdout}"
    );
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

fn shipped_trace(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("devices/traces")
        .join(format!("{name}.trace"))
}

#[test]
fn recording_a_replay_keeps_the_source_traces_header() {
    let dir = temp("replay-record");
    let source = Trace::read(&shipped_trace("plane-groove")).unwrap();
    assert_eq!(source.header.world_from_tracker.scale, 20.0);
    let profile = dir.join("groove-replay.json");
    let json = serde_json::json!({
        "format": "nendo-device-profile",
        "version": 1,
        "name": "groove-replay",
        "input": {"replay": {"trace": shipped_trace("plane-groove"), "speed": 40.0}},
    });
    std::fs::write(&profile, json.to_string()).unwrap();
    let path = dir.join("again.trace");
    let out = nendo()
        .args(["record", "--seconds", "20", "--profile"])
        .arg(&profile)
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
    assert!(stdout.contains("the replayed trace ended"), "{stdout}");
    let again = Trace::read(&path).unwrap();
    // The recording's header is the source trace's, not the replay profile's — and says
    // that its frames carry the marks of the gate it was recorded with (version 4).
    assert_eq!(
        again.header,
        nendo_devices::TraceHeader {
            marks_held: true,
            ..source.header.clone()
        }
    );
    assert_eq!(again.frames.len(), source.frames.len());
    let first = source.frames[0].time.as_micros();
    for (a, s) in again.frames.iter().zip(&source.frames) {
        assert_eq!(a.time.as_micros(), s.time.as_micros() - first);
        assert_eq!((a.pose, a.joints, a.buttons), (s.pose, s.joints, s.buttons));
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Records the 22-sensor emulated glove with a long `--seconds`, sends `signal` once the glove
/// has streamed a few dozen records, and checks that the recording ended then with a finished
/// trace and nothing else.
fn stop_recording_with(signal: &str) {
    let glove = PtyEmulator::spawn(CyberGloveModel::new(SensorCount::TwentyTwo)).unwrap();
    let dir = temp(&format!("signal-{signal}"));
    let path = dir.join("stopped.trace");
    let mut child = nendo()
        .args([
            "record",
            "--profile",
            "cyberglove2-22",
            "--seconds",
            "60",
            "--port",
        ])
        .arg(glove.path())
        .arg("--out")
        .arg(&path)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until recording has begun (its trace exists) and the glove has streamed
    // records to it; the deadline only guards against a hang.
    let begun = Instant::now() + Duration::from_secs(60);
    while (std::fs::read_dir(&dir).unwrap().count() == 0 || glove.records_sent() < 40)
        && Instant::now() < begun
    {
        std::thread::sleep(Duration::from_millis(10));
    }
    assert!(glove.records_sent() >= 40, "the glove never streamed");
    let kill = Command::new("kill")
        .args([format!("-{signal}"), child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    // It stops on the signal, not at its 60 s: a generous guard, far below them.
    let deadline = Instant::now() + Duration::from_secs(30);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            // Our own child: end it so the test does not hang.
            let _ = child.kill();
            panic!("nendo record did not stop on SIG{signal}");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let out = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "SIG{signal}: {:?}\n{stdout}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("stopped by a signal"), "{stdout}");
    let trace = Trace::read(&path).unwrap();
    assert!(trace.frames.len() > 10, "{} frames", trace.frames.len());
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["stopped.trace"], "no temporary file left behind");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sigterm_ends_a_recording_with_a_finished_trace() {
    stop_recording_with("TERM");
}

#[test]
fn sigint_ends_a_recording_with_a_finished_trace() {
    stop_recording_with("INT");
}

#[test]
fn recording_into_a_missing_directory_names_out_once() {
    let glove = PtyEmulator::spawn(CyberGloveModel::new(SensorCount::TwentyTwo)).unwrap();
    let dir = temp("missing-dir");
    let path = dir.join("no-such-dir").join("t.trace");
    let out = nendo()
        .args([
            "record",
            "--profile",
            "cyberglove2-22",
            "--seconds",
            "0.2",
            "--port",
        ])
        .arg(glove.path())
        .arg("--out")
        .arg(&path)
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains(&path.display().to_string()), "{stderr}");
    assert!(!stderr.contains(".tmp-"), "{stderr}");
    assert_eq!(
        stderr.matches("No such file or directory").count(),
        1,
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn devices_skips_a_bad_profile_with_a_warning_and_lists_the_rest() {
    let dir = temp("profiles");
    let good = nendo_devices::profile::resolve("flock").unwrap();
    let mut mine = good.clone();
    mine.name = "my-flock".into();
    std::fs::write(dir.join("a-broken.json"), "{ not json").unwrap();
    std::fs::write(dir.join("b-mine.json"), mine.to_json()).unwrap();
    let out = nendo()
        .args(["devices", "--profiles"])
        .arg(&dir)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(
        stderr.contains("warning") && stderr.contains("a-broken.json"),
        "{stderr}"
    );
    assert!(
        stdout.contains("my-flock") && stdout.contains("cyberglove2-18"),
        "{stdout}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Starts `nendo emulate ARGS`, returning the child and the port its first line names.
fn emulate(args: &[&str]) -> (std::process::Child, String) {
    use std::io::BufRead;
    let mut child = nendo()
        .arg("emulate")
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    let stdout = child.stdout.take().unwrap();
    std::io::BufReader::new(stdout)
        .read_line(&mut line)
        .unwrap();
    (child, line.trim().to_string())
}

/// Waits for a child at most `seconds`, killing it (our own) if it overruns.
fn wait_for(mut child: std::process::Child, seconds: u64) -> std::process::Output {
    let deadline = Instant::now() + Duration::from_secs(seconds);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("the child did not end within {seconds} s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

#[test]
fn record_records_from_nendo_emulate_and_the_emulator_ends_after_its_seconds() {
    let (emulator, port) = emulate(&["fastrak", "--seconds", "3", "--motion", "press"]);
    assert!(
        port.starts_with('/'),
        "the first line is the port: {port:?}"
    );
    assert!(Path::new(&port).exists(), "{port}");
    let dir = temp("emulate-record");
    let out_path = dir.join("emulated.trace");
    let out = nendo()
        .args([
            "record",
            "--profile",
            "fastrak",
            "--seconds",
            "1",
            "--port",
            &port,
        ])
        .arg("--out")
        .arg(&out_path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let trace = Trace::read(&out_path).unwrap();
    // 120 Hz for a second: a hundred samples or so, every one with a pose.
    assert!(trace.frames.len() > 60, "{} frames", trace.frames.len());
    assert!(trace.frames.iter().all(|f| f.pose.is_some()));
    // The press: the hand comes down, so the tracker's z changes.
    let z: Vec<f64> = trace
        .frames
        .iter()
        .filter_map(|f| f.pose)
        .map(|p| p.position.z)
        .collect();
    let span =
        z.iter().cloned().fold(f64::MIN, f64::max) - z.iter().cloned().fold(f64::MAX, f64::min);
    assert!(span > 0.01, "the hand moves: z spans {span} m");
    // The emulator ends on its own clock after its 3 s (the guard only catches a hang).
    let done = wait_for(emulator, 60);
    let stderr = String::from_utf8_lossy(&done.stderr);
    assert!(done.status.success(), "{stderr}");
    let ran: f64 = stderr
        .split("records streamed in ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|x| x.parse().ok())
        .unwrap_or_else(|| panic!("no summary: {stderr}"));
    assert!(
        ran >= 2.95 && !stderr.contains("stopped by a signal"),
        "{stderr}"
    );
    assert!(!Path::new(&port).exists(), "the emulator removed its port");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn emulate_ends_cleanly_on_sigterm_and_refuses_bad_options() {
    let (emulator, port) = emulate(&["cyberglove", "--motion", "pinch"]);
    assert!(Path::new(&port).exists(), "{port}");
    // No wait: the emulator takes stop signals before it prints its port (read above).
    let kill = Command::new("kill")
        .args(["-TERM", &emulator.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let done = wait_for(emulator, 10);
    let stderr = String::from_utf8_lossy(&done.stderr);
    assert!(done.status.success(), "{stderr}");
    assert!(stderr.contains("stopped by a signal"), "{stderr}");
    assert!(!Path::new(&port).exists(), "the emulator removed its port");
    for (args, says) in [
        (&["fastrak", "--motion", "juggle"][..], "unknown motion"),
        (&["fastrak", "--format", "hex"][..], "ascii or binary"),
        (&["flock", "--format", "50"][..], "36, 72 or 144"),
        (&["cyberglove", "--corrupt", "2"][..], "probability"),
        (&["5dt-glove5", "--seconds=-1"][..], "--seconds"),
        // A profile without the emulated device: before, the emulator ran and told the host to
        // connect with a profile that has no such tracker or glove.
        (
            &["fastrak", "--seconds", "0.2", "--profile", "cyberglove2-18"][..],
            "does not have a Fastrak tracker",
        ),
        (
            &["flock", "--seconds", "0.2", "--profile", "fastrak"][..],
            "does not have a Flock of Birds tracker",
        ),
        (
            &[
                "5dt-glove5",
                "--seconds",
                "0.2",
                "--profile",
                "cyberglove2-18-fastrak",
            ][..],
            "does not have a 5DT Data Glove 5",
        ),
    ] {
        let out = nendo().arg("emulate").args(args).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    }
}

#[test]
fn record_starts_with_the_device_present_and_takes_in_the_other_when_it_answers() {
    let glove = PtyEmulator::spawn(CyberGloveModel::new(SensorCount::Eighteen)).unwrap();
    let tracker = PtyEmulator::spawn(FastrakModel::new()).unwrap();
    // The tracker is switched off when recording starts, and switched on a second later.
    tracker.unplug();
    let dir = temp("record-partial");
    let path = dir.join("partial.trace");
    let child = nendo()
        .args([
            "record",
            "--profile",
            "cyberglove2-18-fastrak",
            "--seconds",
            "3",
            "--glove-port",
        ])
        .arg(glove.path())
        .arg("--tracker-port")
        .arg(tracker.path())
        .arg("--out")
        .arg(&path)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_secs(1));
    tracker.replug();
    let out = wait_for(child, 20);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("tracker is not there yet") && stderr.contains("cannot open serial port"),
        "{stderr}"
    );
    let trace = Trace::read(&path).unwrap();
    let first_pose = trace.frames.iter().position(|f| f.pose.is_some());
    assert!(
        trace.frames[0].joints.is_some() && trace.frames[0].pose.is_none(),
        "the glove records from the start, without the tracker"
    );
    let first_pose = first_pose.expect("the tracker joined the recording");
    assert!(
        trace.frames[first_pose..]
            .iter()
            .filter(|f| f.pose.is_some())
            .count()
            > 50
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
