//! `nendo record` survives whatever ends it: killed with SIGKILL at random moments (the real
//! binary, recording two `nendo emulate` processes doing the press gesture over the plane), its
//! file under `--out` replays up to the last complete frame, saying how many it recovered; a
//! write the file system refuses (a file size limit here, a full tmpfs in
//! `.ci/checks/record-survives.sh`) stops it with a clear error and keeps every frame before;
//! the next recording never replaces an earlier one unless told to.
#![cfg(unix)]

use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::support::{nendo, temp_dir};
use nendo_devices::Trace;

/// A child process of ours, killed when dropped (a failing test leaves none running).
struct Owned(Child);

impl Drop for Owned {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// The shipped glove + tracker profile placed so the emulators' press gesture reaches the
/// default plane (as `.ci/checks/window-devices.sh` places it).
fn profile(dir: &Path) -> PathBuf {
    let shipped =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("devices/profiles/cyberglove2-18-fastrak.json");
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(shipped).expect("shipped profile"))
            .expect("profile JSON");
    json["name"] = "record-survives".into();
    json["world_from_tracker"]["translation"] = serde_json::json!([0.0, 0.0, 0.0]);
    json["world_from_tracker"]["scale"] = 21.5.into();
    let path = dir.join("profile.json");
    std::fs::write(&path, json.to_string()).expect("profile written");
    path
}

/// `nendo emulate DEVICE --motion press --profile P`, and the port it prints first.
fn emulate(device: &str, profile: &Path) -> (Owned, String) {
    let mut child = nendo()
        .args(["emulate", device, "--motion", "press", "--seconds", "600"])
        .arg("--profile")
        .arg(profile)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("nendo emulate runs");
    let mut line = String::new();
    let stdout = child.stdout.take().expect("stdout");
    std::io::BufReader::new(stdout)
        .read_line(&mut line)
        .expect("the port line");
    (Owned(child), line.trim().to_owned())
}

/// `nendo record` of both emulators into `out` on the plane, with `extra` options.
fn record(profile: &Path, glove: &str, tracker: &str, out: &Path, extra: &[&str]) -> Command {
    let mut c = nendo();
    c.args(["record", "--primitive", "plane"])
        .args(extra)
        .arg("--profile")
        .arg(profile)
        .args(["--glove-port", glove, "--tracker-port", tracker])
        .arg("--out")
        .arg(out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    c
}

fn names(dir: &Path) -> Vec<String> {
    let mut n: Vec<String> = std::fs::read_dir(dir)
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    n.sort();
    n
}

/// `nendo replay TRACE --out M` (the trace's own scene): its exit status and standard error.
fn replay(trace: &Path, model: &Path) -> (bool, String) {
    let out = nendo()
        .arg("replay")
        .arg(trace)
        .arg("--out")
        .arg(model)
        .output()
        .expect("nendo replay runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// 24 recordings killed with SIGKILL at random moments up to 1.5 s after the file appeared:
/// each leaves its trace under `--out` and nothing else; `nendo replay` reads it, saying how
/// many frames it recovered — every frame up to at most half a second before the kill. Then
/// 8 killed at random moments from the start (perhaps before any file): whatever is left
/// reads. The figures are printed (`--nocapture`).
#[test]
fn record_killed_at_random_moments_leaves_a_trace_replay_recovers() {
    let dir = temp_dir("record-kill");
    let profile = profile(&dir);
    let (_glove, glove_port) = emulate("cyberglove", &profile);
    let (_tracker, tracker_port) = emulate("fastrak", &profile);
    let mut rng = ChaCha8Rng::seed_from_u64(0x6b11_1939);
    let mut table = Vec::new();
    let mut contacts_seen = 0;
    for k in 0..32 {
        let during = k < 24;
        let work = dir.join(format!("try-{k:02}"));
        std::fs::create_dir_all(&work).expect("dir");
        let out = work.join("session.trace");
        let delay = Duration::from_millis(if during {
            rng.gen_range(0..1500)
        } else {
            rng.gen_range(0..400)
        });
        let mut child = Owned(
            record(
                &profile,
                &glove_port,
                &tracker_port,
                &out,
                &["--seconds", "60"],
            )
            .spawn()
            .expect("nendo record runs"),
        );
        if during {
            // The moment the trace appears (its header placed); the deadline only guards
            // against a recording that never starts.
            let deadline = Instant::now() + Duration::from_secs(30);
            while !out.exists() {
                assert!(
                    child.0.try_wait().expect("wait").is_none(),
                    "try {k}: nendo record ended before recording"
                );
                assert!(Instant::now() < deadline, "try {k}: no trace after 30 s");
                std::thread::sleep(Duration::from_millis(2));
            }
        }
        std::thread::sleep(delay);
        child.0.kill().expect("SIGKILL");
        let status = child.0.wait().expect("reaped");
        assert_eq!(
            std::os::unix::process::ExitStatusExt::signal(&status),
            Some(9),
            "try {k}: killed, not ended ({status:?})"
        );
        let files = names(&work);
        if !during && !out.exists() {
            // Killed before its header was placed: nothing, or at most a header-only
            // temporary (never a file at --out with half a header).
            for f in &files {
                let r = Trace::read_recovering(&work.join(f)).expect("a header");
                assert!(r.trace.frames.is_empty(), "try {k}: {f}");
            }
            table.push(format!(
                "try {k:2}: killed {:4} ms after start: before the trace appeared",
                delay.as_millis()
            ));
            continue;
        }
        assert_eq!(
            files,
            ["session.trace"],
            "try {k}: only the trace, no temporary"
        );
        let r = Trace::read_recovering(&out)
            .unwrap_or_else(|e| panic!("try {k}: the killed recording does not read: {e}"));
        let interrupted = r.interrupted.expect("no end line: it was killed");
        let frames = r.trace.frames.len();
        assert_eq!(interrupted.frames, frames);
        let last_ms = r
            .trace
            .frames
            .last()
            .map_or(0, |f| f.time.as_micros() / 1000);
        if during {
            // Frame times count from the stream's start, before the file appeared: every
            // frame up to half a second before the kill is in the file.
            let killed_ms = delay.as_millis() as u64;
            assert!(
                last_ms + 500 >= killed_ms,
                "try {k}: killed {killed_ms} ms after the trace appeared, its last frame at {last_ms} ms"
            );
        }
        let model = work.join("replayed.json");
        let (ok, stderr) = replay(&out, &model);
        assert!(ok, "try {k}: {stderr}");
        let notice = format!("recovered its {frames} complete frame");
        assert!(stderr.contains(&notice), "try {k}: {stderr}");
        let contacts: u64 = stderr
            .split(" contacts")
            .next()
            .and_then(|s| s.rsplit(' ').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or(0);
        contacts_seen += contacts;
        table.push(format!(
            "try {k:2}: killed {:4} ms after {}: {frames:4} frames recovered (last at {last_ms:5} ms of the stream){}, {contacts} contacts replayed",
            delay.as_millis(),
            if during { "the trace appeared" } else { "start" },
            if interrupted.dropped.is_some() {
                ", a torn last line dropped"
            } else {
                ""
            }
        ));
    }
    eprintln!("{}", table.join("\n"));
    assert!(
        contacts_seen > 0,
        "the press gesture reached the clay in some replay"
    );
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// A killed recording is never replaced by the next one: `nendo record` to the same `--out`
/// is refused (before any device opens) and leaves the file byte for byte; `--replace`
/// replaces it with a finished trace.
#[test]
fn the_next_recording_never_replaces_a_killed_one_unless_told() {
    let dir = temp_dir("record-again");
    let profile = profile(&dir);
    let (_glove, glove_port) = emulate("cyberglove", &profile);
    let (_tracker, tracker_port) = emulate("fastrak", &profile);
    let out = dir.join("session.trace");
    let mut child = Owned(
        record(
            &profile,
            &glove_port,
            &tracker_port,
            &out,
            &["--seconds", "60"],
        )
        .spawn()
        .expect("nendo record runs"),
    );
    let deadline = Instant::now() + Duration::from_secs(30);
    while Trace::read_recovering(&out).map_or(0, |r| r.trace.frames.len()) < 20 {
        assert!(Instant::now() < deadline, "no frames recorded in 30 s");
        std::thread::sleep(Duration::from_millis(10));
    }
    child.0.kill().expect("SIGKILL");
    child.0.wait().expect("reaped");
    let killed = std::fs::read(&out).expect("the killed recording");
    let again = record(
        &profile,
        &glove_port,
        &tracker_port,
        &out,
        &["--seconds", "0.3"],
    )
    .output()
    .expect("runs");
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert!(!again.status.success());
    assert_eq!(
        stderr.trim_end(),
        format!(
            "nendo record: {}: a file is already there (an earlier recording?): nendo record does not replace it; give another --out, or --replace to replace it",
            out.display()
        )
    );
    assert_eq!(std::fs::read(&out).expect("kept"), killed, "byte for byte");
    let replaced = record(
        &profile,
        &glove_port,
        &tracker_port,
        &out,
        &["--seconds", "0.3", "--replace"],
    )
    .output()
    .expect("runs");
    assert!(
        replaced.status.success(),
        "{}",
        String::from_utf8_lossy(&replaced.stderr)
    );
    let t = Trace::read(&out).expect("a finished trace");
    assert!(!t.frames.is_empty());
    assert_eq!(names(&dir), ["profile.json", "session.trace"]);
    std::fs::remove_dir_all(&dir).expect("clean up");
}

/// A write the file system refuses part-way (here a file size limit, `ulimit -f`, with
/// SIGXFSZ ignored so the write fails with EFBIG; a full disk fails the same way with ENOSPC,
/// see `.ci/checks/record-survives.sh`): the recording stops at once with an error naming the
/// file and the frames it keeps, exit status 1, and the file replays those frames exactly.
#[test]
fn a_refused_write_stops_the_recording_and_keeps_every_frame_before() {
    let dir = temp_dir("record-limit");
    let profile = profile(&dir);
    let (_glove, glove_port) = emulate("cyberglove", &profile);
    let (_tracker, tracker_port) = emulate("fastrak", &profile);
    let out = dir.join("limited.trace");
    let cmd = record(
        &profile,
        &glove_port,
        &tracker_port,
        &out,
        &["--seconds", "30"],
    );
    let program = cmd.get_program().to_owned();
    let args: Vec<_> = cmd.get_args().map(|a| a.to_owned()).collect();
    // 128 blocks of 512 bytes (dash) or 1024 (bash): far below 30 s of frames.
    let started = Instant::now();
    let done = Command::new("sh")
        .arg("-c")
        .arg("trap '' XFSZ; ulimit -f 128 || exit 97; exec \"$0\" \"$@\"")
        .arg(program)
        .args(args)
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&done.stderr);
    assert_eq!(done.status.code(), Some(1), "{stderr}");
    assert!(
        started.elapsed() < Duration::from_secs(25),
        "it stopped at the failure, not at its --seconds"
    );
    let kept: usize = stderr
        .split("the file keeps the ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no count of the frames kept: {stderr}"));
    assert!(
        stderr.starts_with(&format!("nendo record: {}: File too large", out.display()))
            && stderr.contains("the recording stopped"),
        "{stderr}"
    );
    let size = std::fs::metadata(&out).expect("the trace").len();
    let r = Trace::read_recovering(&out).expect("reads");
    assert_eq!(r.trace.frames.len(), kept, "{stderr}");
    assert!(kept > 50, "{kept} frames");
    let i = r.interrupted.expect("no end line");
    assert_eq!(
        i.dropped, None,
        "the torn line was taken back ({size} bytes)"
    );
    let (ok, replayed) = replay(&out, &dir.join("m.json"));
    assert!(ok, "{replayed}");
    assert!(
        replayed.contains(&format!("recovered its {kept} complete frames")),
        "{replayed}"
    );
    eprintln!("size limit: {stderr}{size} bytes kept; replay: {replayed}");
    std::fs::remove_dir_all(&dir).expect("clean up");
}
