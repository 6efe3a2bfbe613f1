//! Nothing lost, nothing silently accepted (issue 28, items 5–11): outputs never replace the
//! start model a trace names; inputs are bounded (batch lines, traces, profiles, figures,
//! shapes, picture sizes, warp work) and refused up front with a clear error; saved spacing
//! ratios are checked against their points; degenerate meshes and CAD scales out of range are
//! refused; `morph` does not mix runs; `emulate --link` replaces only an emulator's own link.
//!
//! The probes that would exhaust memory on a binary without the bounds run under `ulimit -v`
//! (a guard: an unbounded read then ends in an allocation failure, not in a swapped machine).

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::support::{nendo, run, run_with_input, temp_dir};
use nendo::hand::scene::sha256_hex;
use nendo::model::Model;
use nendo::surface::{Primitive, PrimitiveParams};

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

fn shipped_trace(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("devices/traces")
        .join(format!("{name}.trace"))
}

fn figure(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/figures")
        .join(name)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs `nendo ARGS` with its address space limited to 3 GB (a guard against unbounded
/// reads) and a 120 s hang guard; the output once it ends.
fn guarded(args: &[&str]) -> Output {
    let mut child = Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 3000000; exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_nendo"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sh runs");
    let deadline = Instant::now() + Duration::from_secs(120);
    while child.try_wait().expect("wait").is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("nendo {args:?} did not end within 120 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

/// Refused with a clear error (exit status 1 or 2, not a signal or an abort), the message
/// holding `needle`.
fn refused(o: &Output, needle: &str) {
    let err = stderr(o);
    assert!(
        matches!(o.status.code(), Some(1 | 2)),
        "expected a refusal (status 1 or 2), got {:?}: {err}",
        o.status
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains(needle), "expected {needle:?} in: {err}");
}

fn plane_model(patches: (usize, usize)) -> Model {
    Model::new(
        Primitive::Plane
            .build(&PrimitiveParams {
                patches: Some(patches),
                ..PrimitiveParams::default()
            })
            .expect("plane"),
    )
}

/// The model file at `path` with every control-point coordinate multiplied by `k`.
fn scaled_plane(path: &Path, k: f64) {
    let mut doc: serde_json::Value =
        serde_json::from_str(&plane_model((2, 2)).to_json_string()).expect("json");
    for patch in doc["surface"]["patches"].as_array_mut().expect("patches") {
        for point in patch.as_array_mut().expect("points") {
            for x in point.as_array_mut().expect("xyz") {
                *x = serde_json::json!(x.as_f64().expect("number") * k);
            }
        }
    }
    std::fs::write(path, doc.to_string()).expect("written");
}

// --- 5: replay --out never replaces the start model its trace names.

#[test]
fn replay_out_may_not_replace_the_start_model_its_trace_names() {
    let dir = temp_dir("replay-start");
    let start = dir.join("start.json");
    let model = Model::new(
        Primitive::Sphere
            .build(&PrimitiveParams {
                patches: Some((8, 4)),
                radius: Some(3.0),
                ..PrimitiveParams::default()
            })
            .expect("sphere"),
    );
    model.write(&start).expect("written");
    let bytes = std::fs::read(&start).expect("read");
    let scene = format!(
        r#"scene {{"model_file":{{"path":"start.json","sha256":"{}"}}}}"#,
        sha256_hex(&bytes)
    );
    let text = std::fs::read_to_string(shipped_trace("mouse-sphere")).expect("shipped trace");
    let trace_text: String = text
        .lines()
        .map(|l| {
            if l.starts_with("scene ") {
                scene.as_str()
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n";
    let trace = dir.join("t.trace");
    std::fs::write(&trace, trace_text).expect("trace written");
    let dotted = dir.join("sub");
    std::fs::create_dir_all(&dotted).expect("dir");
    for (extra, out) in [
        (vec![], start.clone()),
        (
            vec!["--primitive", "sphere"],
            dotted.join("..").join("start.json"),
        ),
        (vec!["--model", s(&start)], start.clone()),
    ] {
        let mut args = vec!["replay", s(&trace), "--out", s(&out)];
        args.extend(extra);
        let o = run(&args);
        refused(&o, "start model the trace's scene names");
        assert_eq!(std::fs::read(&start).expect("read"), bytes, "{args:?}");
    }
    let other = dir.join("out.json");
    let o = run(&["replay", s(&trace), "--out", s(&other)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(other.is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

// --- 6: bounded inputs.

#[test]
fn an_over_long_batch_line_is_answered_with_an_error_and_the_next_line_is_read() {
    let ok = r#"{"op":"closest","curve":{"bezier":[[0,0],[1,0]]},"point":[0.5,1]}"#;
    let long = format!(r#"{{"op":"closest","pad":"{}"}}"#, "x".repeat(17 << 20));
    let input = format!("{ok}\n{long}\n{ok}\n");
    let o = run_with_input(&["closest", "--batch"], &input);
    let out = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 3, "{out:.400}");
    assert!(lines[0].contains("\"distance\""), "{}", lines[0]);
    assert!(
        lines[1].contains("line 2 is longer than the limit of 16 MB"),
        "{}",
        lines[1]
    );
    assert!(lines[2].contains("\"distance\""), "{}", lines[2]);
    assert_eq!(o.status.code(), Some(1), "one line failed");
}

#[test]
fn devices_and_endless_files_are_refused_quickly_as_any_input() {
    let dir = temp_dir("dev-zero");
    let zero = "/dev/zero";
    let png = dir.join("x.png");
    let fig = figure("horse.json");
    let out = dir.join("o.json");
    let (obj, frames, mouse) = (
        dir.join("x.obj"),
        dir.join("m"),
        shipped_trace("mouse-sphere"),
    );
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["figure", "render", zero, "--png", s(&png)],
            "figure file",
        ),
        (vec!["figure", "measure", zero], "figure file"),
        (
            vec![
                "figure",
                "warp",
                s(&fig),
                "--curves",
                zero,
                "--out",
                s(&out),
            ],
            "curves file",
        ),
        (
            vec!["figure", "shape", zero, "--mesh", s(&obj)],
            "shape file",
        ),
        (
            vec!["morph", zero, zero, "--out", s(&frames)],
            "figure file",
        ),
        (
            vec!["replay", zero, "--out", s(&out)],
            "not a nendo hand trace",
        ),
        (
            vec!["replay", s(&mouse), "--profile", zero, "--out", s(&out)],
            "device profile",
        ),
    ];
    for (args, needle) in cases {
        let o = guarded(&args);
        refused(&o, needle);
    }
    assert!(!out.exists() && !png.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_trace_frame_line_over_its_limit_ends_an_interrupted_recording_without_being_held() {
    let dir = temp_dir("long-frame");
    let text = std::fs::read_to_string(shipped_trace("mouse-sphere")).expect("shipped trace");
    let frames = text
        .lines()
        .filter(|l| l.starts_with(char::is_numeric))
        .count();
    // An interrupted recording (no `end` line) whose last line is 2 MB of garbage.
    let mut cut: String = text
        .lines()
        .filter(|l| !l.starts_with("end "))
        .collect::<Vec<_>>()
        .join("\n");
    cut.push('\n');
    cut.push_str(&"9".repeat(2 << 20));
    cut.push('\n');
    let trace = dir.join("t.trace");
    std::fs::write(&trace, &cut).expect("written");
    let out = dir.join("o.json");
    let o = guarded(&["replay", s(&trace), "--out", s(&out)]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains(&format!("recovered its {frames} complete frames")),
        "{err}"
    );
    assert!(err.contains("the line is longer than 1 MB"), "{err}");
    // The same line inside a finished trace is an error, and nothing is written.
    cut.push_str(&format!("end {frames}\n"));
    std::fs::write(&trace, &cut).expect("written");
    let out2 = dir.join("o2.json");
    let o = guarded(&["replay", s(&trace), "--out", s(&out2)]);
    refused(&o, "the line is longer than 1 MB");
    assert!(!out2.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_picture_too_large_is_refused_up_front_with_its_estimate() {
    let dir = temp_dir("big-picture");
    let png = dir.join("x.png");
    let fig = figure("horse.json");
    for args in [
        vec![
            "figure",
            "render",
            s(&fig),
            "--png",
            s(&png),
            "--size",
            "16384x16384",
        ],
        vec![
            "figure",
            "render",
            s(&fig),
            "--png",
            s(&png),
            "--size",
            "9000x8000",
        ],
        vec![
            "morph",
            s(&fig),
            s(&fig),
            "--out",
            s(&dir.join("m")),
            "--size",
            "16384x8193",
        ],
    ] {
        let o = guarded(&args);
        refused(&o, "GB while drawing");
    }
    assert!(!png.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

// --- 7: warp work.

#[test]
fn warp_work_beyond_the_cap_is_refused_up_front_with_the_estimate() {
    let pair = r#"[{"bezier":[[0,0],[1,0]]},{"bezier":[[0,0],[1,0.1]]}]"#;
    let pairs = vec![pair; 1001].join(",");
    let points = vec!["[0.5,0.5]"; 10_000].join(",");
    let big = format!(r#"{{"op":"warp","pairs":[{pairs}],"points":[{points}]}}"#);
    let small = format!(r#"{{"op":"warp","pairs":[{pair}],"points":[[0.5,0.5]]}}"#);
    let o = run_with_input(&["curve", "--batch"], &format!("{big}\n{small}\n"));
    let out = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 2, "{out:.400}");
    assert!(
        lines[0].contains("1001 pairs x 10000 points = 10010000 weight evaluations"),
        "{}",
        lines[0]
    );
    assert!(lines[0].contains("s of work"), "{}", lines[0]);
    assert!(lines[1].contains("\"points\""), "{}", lines[1]);
}

// --- 8: saved ratios.

#[test]
fn a_saved_ratio_that_is_not_its_points_ratio_is_refused_naming_the_line_and_both_values() {
    let dir = temp_dir("ratios");
    let good = dir.join("good.json");
    plane_model((4, 3)).write(&good).expect("written");
    let o = run(&["check", s(&good)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&good).expect("read")).expect("json");
    let measured = doc["surface"]["ratios"]["u"][2].as_f64().expect("a ratio");
    doc["surface"]["ratios"]["u"][2] = serde_json::json!(measured * 1.00001);
    let bad = dir.join("bad.json");
    std::fs::write(&bad, doc.to_string()).expect("written");
    let o = run(&["check", s(&bad)]);
    refused(&o, "surface.ratios.u[2]");
    let err = stderr(&o);
    assert!(err.contains("1.00001"), "the saved value: {err}");
    assert!(
        err.contains("control points, 1."),
        "the measured value: {err}"
    );
    // Sculpting on it is refused as well: the model never loads.
    let o = run(&["export", s(&bad), s(&dir.join("x.stl"))]);
    refused(&o, "surface.ratios.u[2]");
    let _ = std::fs::remove_dir_all(&dir);
}

// --- 9: degenerate meshes, CAD scales.

#[test]
fn an_empty_or_degenerate_mesh_is_refused_and_cad_scales_out_of_range_too() {
    let dir = temp_dir("degenerate");
    for k in [1e-50, 1e-13] {
        let model = dir.join("tiny.json");
        scaled_plane(&model, k);
        for ext in ["stl", "obj", "glb"] {
            let out = dir.join(format!("tiny.{ext}"));
            let o = run(&["export", s(&model), s(&out)]);
            let err = stderr(&o);
            assert_eq!(o.status.code(), Some(1), "scale {k} .{ext}: {err}");
            assert!(
                err.contains("degenerate") || err.contains("no triangles"),
                "scale {k} .{ext}: {err}"
            );
            assert!(!out.exists(), "scale {k}: nothing written");
        }
    }
    // A sane plane exports, and its scale range is stated.
    let model = dir.join("plane.json");
    scaled_plane(&model, 1.0);
    let o = run(&["export", s(&model), s(&dir.join("p.stl"))]);
    assert!(o.status.success(), "{}", stderr(&o));
    for scale in ["1e-9", "1e40", "9.9e-5", "1.1e4"] {
        let out = dir.join("p.step");
        let o = run(&["export", s(&model), s(&out), "--scale", scale]);
        assert_eq!(o.status.code(), Some(2), "--scale {scale}: {}", stderr(&o));
        assert!(stderr(&o).contains("outside 1e-4 to 1e4"), "{}", stderr(&o));
        assert!(!out.exists());
    }
    for scale in ["1e-4", "25.4", "1e4"] {
        let o = run(&[
            "export",
            s(&model),
            s(&dir.join("p.step")),
            "--scale",
            scale,
        ]);
        assert!(o.status.success(), "--scale {scale}: {}", stderr(&o));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

// --- 10: morph does not mix runs.

#[test]
fn morph_refuses_a_directory_with_an_earlier_run_unless_told_to_replace_it() {
    let dir = temp_dir("morph-replace");
    let frames = dir.join("frames");
    let (horse, tiger) = (figure("horse.json"), figure("tiger.json"));
    let morph = |n: &str, extra: &[&str]| {
        let mut args = vec![
            "morph",
            s(&horse),
            s(&tiger),
            "--frames",
            n,
            "--size",
            "32x32",
            "--out",
            s(&frames),
        ];
        args.extend_from_slice(extra);
        run(&args)
    };
    let o = morph("4", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let notes = frames.join("notes.txt");
    std::fs::write(&notes, "mine").expect("written");
    let o = morph("2", &[]);
    refused(&o, "is not empty");
    assert!(frames.join("frame_0003.png").is_file(), "left as it was");
    let o = morph("2", &["--replace", "--no-svg"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut names: Vec<String> = std::fs::read_dir(&frames)
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["frame_0000.png", "frame_0001.png", "notes.txt"]);
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).expect("summary");
    assert_eq!(summary["frames"], 2);
    assert_eq!(summary["old_frames_removed"], 6);
    let _ = std::fs::remove_dir_all(&dir);
}

// --- 11: emulate --link.

/// Runs `nendo emulate fastrak --seconds 0.3 --link LINK`, to the end (30 s hang guard).
fn emulate_link(link: &Path) -> Output {
    let mut child = nendo()
        .args(["emulate", "fastrak", "--seconds", "0.3", "--link", s(link)])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("runs");
    let deadline = Instant::now() + Duration::from_secs(30);
    while child.try_wait().expect("wait").is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("the emulator did not end within 30 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("output")
}

#[test]
fn emulate_link_replaces_only_a_killed_emulators_own_link() {
    let dir = temp_dir("emulate-link");
    let mine = dir.join("mine.txt");
    std::fs::write(&mine, "keep").expect("written");
    let link = dir.join("tty");
    std::os::unix::fs::symlink(&mine, &link).expect("link");
    let o = emulate_link(&link);
    refused(&o, "not one an emulator made");
    assert_eq!(std::fs::read_link(&link).expect("still a link"), mine);
    // A link to a pty link of an emulator that is gone (no such process) is its own: replaced,
    // and removed at its end.
    std::fs::remove_file(&link).expect("removed");
    let stale = std::env::temp_dir().join("nendo-emulator-4199999-0/tty");
    std::os::unix::fs::symlink(&stale, &link).expect("link");
    let o = emulate_link(&link);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        String::from_utf8_lossy(&o.stdout).lines().next(),
        Some(s(&link))
    );
    assert!(std::fs::symlink_metadata(&link).is_err(), "removed at exit");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_trace_from_a_fifo_is_replayed_and_not_opened_twice() {
    // The progress count reads the file a second time: never a fifo, whose second open would
    // wait for a writer that never comes (the crash hunt's hang).
    let dir = temp_dir("fifo-trace");
    let fifo = dir.join("t.trace");
    let made = Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    let text = std::fs::read(shipped_trace("mouse-sphere")).expect("shipped trace");
    let writer = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::write(fifo, text))
    };
    let out = dir.join("o.json");
    let o = guarded(&["replay", s(&fifo), "--out", s(&out)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.is_file());
    writer
        .join()
        .expect("the writer ends")
        .expect("the trace written");
    let _ = std::fs::remove_dir_all(&dir);
}

// --- The operations file of `sculpt --ops`, and the warp cap on every figure warp.

#[test]
fn sculpt_ops_are_read_line_by_line_and_an_endless_or_over_long_line_is_refused() {
    let dir = temp_dir("ops-lines");
    let out = dir.join("o.json");
    // `/dev/zero`: one line that never ends, refused once it passes 1 MB.
    let started = Instant::now();
    let o = guarded(&[
        "sculpt",
        "--primitive",
        "plane",
        "--ops",
        "/dev/zero",
        "--out",
        s(&out),
    ]);
    refused(&o, "line 1 is longer than 1 MB");
    assert!(
        started.elapsed() < Duration::from_secs(30),
        "refused at once"
    );
    // A line of 1 MB + 1 byte after a good one (a drag path padded with blanks).
    let push = r#"{"op":"push","at":[0,0,0],"dir":[0,0,-1],"depth":0.1,"radius":0.5}"#;
    let pad = " ".repeat((1 << 20) + 1 - push.len());
    let ops = dir.join("ops.jsonl");
    std::fs::write(&ops, format!("{push}\n{push}{pad}\n")).expect("written");
    let o = run(&[
        "sculpt",
        "--primitive",
        "plane",
        "--ops",
        s(&ops),
        "--out",
        s(&out),
    ]);
    refused(&o, "line 2 is longer than 1 MB");
    assert!(stderr(&o).contains("nothing written"), "{}", stderr(&o));
    assert!(!out.exists());
    // One byte less is a line at the limit: read, and the operations applied.
    std::fs::write(&ops, format!("{push}\n{push}{}\n", &pad[1..])).expect("written");
    let o = run(&[
        "sculpt",
        "--primitive",
        "plane",
        "--ops",
        s(&ops),
        "--out",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("2 operations"), "{}", stderr(&o));
    // Standard input is read the same way.
    let o = run_with_input(
        &[
            "sculpt",
            "--primitive",
            "plane",
            "--ops",
            "-",
            "--out",
            s(&out),
        ],
        &format!("{push}\n{push}{pad}\n"),
    );
    refused(&o, "line 2 is longer than 1 MB");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A figure document with `curves` short horizontal lines laid over it, `metacircles`
/// metacircles and a square contour.
fn crowded_figure(curves: usize, metacircles: usize, dy: f64) -> String {
    let curves: Vec<serde_json::Value> = (0..curves)
        .map(|k| {
            let y = k as f64 * 0.01 + dy;
            serde_json::json!({"bezier": [[10.0, y], [90.0, y]]})
        })
        .collect();
    let metacircles: Vec<serde_json::Value> = (0..metacircles)
        .map(|i| {
            let x = 20.0 + (i % 100) as f64 * 0.6;
            let y = 20.0 + (i / 100) as f64 * 0.6;
            serde_json::json!({"centre": [x, y], "radius": 5.0, "density": 1.0})
        })
        .collect();
    serde_json::json!({
        "format": "nendo-figure", "version": 1, "name": "crowded", "threshold": 0.5,
        "view": {"min": [0, 0], "max": [100, 100]}, "background": "#ffffff",
        "metacircles": metacircles,
        "contour": [[10, 10], [90, 10], [90, 90], [10, 90]],
        "curves": curves,
    })
    .to_string()
}

#[test]
fn every_figure_warp_is_held_to_the_warp_work_cap() {
    let dir = temp_dir("figure-warp-cap");
    // figure warp: 1 000 curves x (10 centres + the contour divided to 0.01: 32 000 vertices).
    let fig = dir.join("f.json");
    std::fs::write(&fig, crowded_figure(1000, 10, 0.0)).expect("written");
    let moved: Vec<serde_json::Value> = (0..1000)
        .map(|k| {
            let y = k as f64 * 0.01;
            serde_json::json!({"bezier": [[10.0, y], [90.0, y + 1.0]]})
        })
        .collect();
    let curves = dir.join("c.json");
    std::fs::write(&curves, serde_json::Value::from(moved).to_string()).expect("written");
    let out = dir.join("o.json");
    let args = |edge: &'static str| {
        vec![
            "figure".to_owned(),
            "warp".into(),
            s(&fig).into(),
            "--curves".into(),
            s(&curves).into(),
            "--out".into(),
            s(&out).into(),
            "--max-edge".into(),
            edge.into(),
        ]
    };
    let started = Instant::now();
    let a = args("0.01");
    let o = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    refused(&o, "weight evaluations");
    assert!(
        stderr(&o).contains("warp of 1000 pairs x 320"),
        "{}",
        stderr(&o)
    );
    assert!(
        started.elapsed() < Duration::from_secs(20),
        "refused up front"
    );
    assert!(!out.exists());
    // Coarse edges: 1 000 x (10 + 4) points, under the cap, warps.
    let a = args("1000");
    let o = run(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", stderr(&o));
    // morph: the matching warps carry every metacircle (at most 2 000) by every curve.
    let (src, dst) = (dir.join("src.json"), dir.join("dst.json"));
    std::fs::write(&src, crowded_figure(5001, 2000, 0.0)).expect("written");
    std::fs::write(&dst, crowded_figure(5001, 2000, 1.0)).expect("written");
    let frames = dir.join("frames");
    let started = Instant::now();
    let o = run(&[
        "morph",
        s(&src),
        s(&dst),
        "--frames",
        "2",
        "--size",
        "16x16",
        "--out",
        s(&frames),
    ]);
    refused(&o, "5001 pairs x 2000 points = 10002000 weight evaluations");
    assert!(
        started.elapsed() < Duration::from_secs(20),
        "refused up front"
    );
    assert!(!frames.exists());
    let _ = std::fs::remove_dir_all(&dir);
}
