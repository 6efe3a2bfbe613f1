//! The one safe writer end to end: permissions kept, symbolic links written through, stale
//! temporaries swept, temporaries removed on SIGTERM, non-finite meshes refused, and standard
//! output failures reported as errors (not panics); an output path that is an input of another
//! kind, or another output, is refused before anything is read or written.

use std::fs;
use std::io::Write;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use glam::Vec3;
use nendo::mesh::{ExportError, MeshFormat, TriMesh, save_mesh};

use crate::support::{nendo, temp_dir};

/// The temporaries (`.NAME.nendo-tmp-XXXXXX`) in `dir`.
fn temporaries(dir: &Path) -> Vec<String> {
    fs::read_dir(dir)
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".nendo-tmp-"))
        .collect()
}

fn succeeded(out: &Output) {
    assert!(
        out.status.success(),
        "{:?}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
}

/// `nendo sculpt --primitive PRIMITIVE --out OUT`.
fn sculpt_primitive(primitive: &str, out: &Path) -> Output {
    nendo()
        .args(["sculpt", "--primitive", primitive, "--out"])
        .arg(out)
        .output()
        .expect("run nendo")
}

/// A push in the middle of a plane, as an ops file in `dir`.
fn push_ops(dir: &Path) -> PathBuf {
    let ops = dir.join("ops.jsonl");
    fs::write(
        &ops,
        "{\"op\":\"push\",\"at\":[0,0,0],\"dir\":[0,0,-1],\"depth\":0.5,\"radius\":1.5}\n",
    )
    .expect("ops");
    ops
}

fn mode(path: &Path) -> u32 {
    fs::metadata(path).expect("stat").permissions().mode() & 0o7777
}

#[test]
fn sculpting_a_model_in_place_keeps_its_permissions() {
    let dir = temp_dir("perm");
    let model = dir.join("m.json");
    succeeded(&sculpt_primitive("plane", &model));
    fs::set_permissions(&model, fs::Permissions::from_mode(0o600)).expect("chmod");
    let before = fs::read(&model).expect("read");
    let out = nendo()
        .args(["sculpt", "--model"])
        .arg(&model)
        .arg("--ops")
        .arg(push_ops(&dir))
        .arg("--out")
        .arg(&model)
        .output()
        .expect("run");
    succeeded(&out);
    assert_ne!(
        fs::read(&model).expect("read"),
        before,
        "the model was rewritten"
    );
    assert_eq!(mode(&model), 0o600, "a private model stays private");
    assert!(temporaries(&dir).is_empty());
    fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn an_out_symlink_is_written_through_and_stays_a_link() {
    let dir = temp_dir("symlink");
    let real_dir = dir.join("models");
    fs::create_dir(&real_dir).expect("mkdir");
    let real = real_dir.join("m.json");
    succeeded(&sculpt_primitive("plane", &real));
    let link = dir.join("current.json");
    std::os::unix::fs::symlink("models/m.json", &link).expect("symlink");
    succeeded(&sculpt_primitive("sphere", &link));
    assert!(
        fs::symlink_metadata(&link)
            .expect("lstat")
            .file_type()
            .is_symlink(),
        "the link was replaced by a file"
    );
    let check = nendo().arg("check").arg(&real).output().expect("run");
    succeeded(&check);
    let report: serde_json::Value = serde_json::from_slice(&check.stdout).expect("JSON");
    assert_eq!(
        report["topology"], "sphere",
        "the link's target was updated"
    );
    assert!(temporaries(&dir).is_empty() && temporaries(&real_dir).is_empty());
    fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_stale_temporary_is_removed_by_the_next_write() {
    let dir = temp_dir("stale");
    let stale = dir.join(".m.json.nendo-tmp-Ab12Cd");
    fs::write(&stale, "half a model from a killed run").expect("seed");
    let other = dir.join(".n.json.nendo-tmp-Ab12Cd");
    fs::write(&other, "another target's").expect("seed");
    succeeded(&sculpt_primitive("plane", &dir.join("m.json")));
    assert!(!stale.exists(), "the stale temporary is still there");
    assert!(other.exists(), "another target's temporary was removed");
    fs::remove_dir_all(&dir).expect("clean up");
}

/// A model whose OBJ export takes a while (a fine tessellation of a sculpted sphere).
fn big_model(dir: &Path) -> PathBuf {
    let model = dir.join("big.json");
    let out = nendo()
        .args([
            "sculpt",
            "--primitive",
            "sphere",
            "--patches",
            "64x32",
            "--out",
        ])
        .arg(&model)
        .output()
        .expect("run");
    succeeded(&out);
    model
}

/// Starts `nendo export MODEL OUT` and waits until its temporary exists (a 40 MB OBJ, written in
/// about half a second); after a few attempts that ended before one was seen, a ten times
/// larger one.
fn export_until_writing(model: &Path, out: &Path) -> std::process::Child {
    for tolerance in ["1e-4", "1e-4", "1e-4", "1e-5"] {
        if let Some(child) = try_export_until_writing(model, out, tolerance) {
            return child;
        }
    }
    panic!("the export was never seen writing");
}

fn try_export_until_writing(
    model: &Path,
    out: &Path,
    tolerance: &str,
) -> Option<std::process::Child> {
    let dir = out.parent().expect("a directory");
    let _ = fs::remove_file(out);
    let mut child = nendo()
        .arg("export")
        .arg(model)
        .arg(out)
        .args(["--tolerance", tolerance])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let deadline = Instant::now() + Duration::from_secs(120);
    while temporaries(dir).is_empty() {
        if child.try_wait().expect("poll").is_some() || Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    Some(child)
}

#[test]
fn sigterm_during_an_export_leaves_no_temporary_and_sigkill_leaves_a_stale_one() {
    let dir = temp_dir("sigterm");
    let model = big_model(&dir);
    let out_dir = dir.join("out");
    fs::create_dir(&out_dir).expect("mkdir");
    let mesh = out_dir.join("big.obj");

    let child = export_until_writing(&model, &mesh);
    let kill = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(kill.success());
    let out = child.wait_with_output().expect("wait");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(temporaries(&out_dir).is_empty(), "SIGTERM left a temporary");
    assert!(!mesh.exists(), "a partial mesh was written");

    // SIGKILL runs no handler: its temporary stays until the next write of that mesh.
    let mut child = export_until_writing(&model, &mesh);
    child.kill().expect("SIGKILL");
    child.wait().expect("wait");
    assert_eq!(temporaries(&out_dir).len(), 1, "SIGKILL left its temporary");
    let out = nendo()
        .arg("export")
        .arg(&model)
        .arg(&mesh)
        .args(["--tolerance", "0.1"])
        .output()
        .expect("run");
    succeeded(&out);
    assert!(
        temporaries(&out_dir).is_empty(),
        "the stale temporary is still there"
    );
    assert!(mesh.exists());
    fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_model_with_a_non_finite_coordinate_is_refused_and_nothing_is_written() {
    let dir = temp_dir("nan-model");
    // Two pushes by nearly f64::MAX would overflow the pushed control points to infinity: the
    // first is refused where it is applied (the writer's own guard is the last line behind it).
    let ops = dir.join("ops.jsonl");
    let push =
        "{\"op\":\"push\",\"at\":[0,0,0],\"dir\":[0,0,-1],\"depth\":1.7e308,\"radius\":1.5}\n";
    fs::write(&ops, push.repeat(2)).expect("ops");
    let model = dir.join("m.json");
    let out = nendo()
        .args([
            "sculpt",
            "--primitive",
            "plane",
            "--regulation",
            "none",
            "--ops",
        ])
        .arg(&ops)
        .arg("--out")
        .arg(&model)
        .output()
        .expect("run");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("line 1")
            && stderr.contains("patch")
            && stderr.contains("control point")
            && stderr.contains("not finite"),
        "names the line, the first bad patch and point: {stderr}"
    );
    assert!(stderr.contains("nothing written"), "{stderr}");
    assert!(!model.exists());
    assert!(temporaries(&dir).is_empty());
    fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_mesh_with_a_non_finite_vertex_is_refused_and_nothing_is_written() {
    let dir = temp_dir("nan-mesh");
    let path = dir.join("m.stl");
    let mesh = TriMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(0.0, f32::NAN, 0.0)],
        normals: vec![Vec3::Z; 3],
        indices: vec![0, 1, 2],
        blocks: Vec::new(),
        error_bound: 0.0,
    };
    for format in MeshFormat::ALL {
        let e = save_mesh(&path, format, &mesh).expect_err("refused");
        assert!(matches!(e, ExportError::NonFinite { vertex: 2 }), "{e}");
    }
    assert_eq!(fs::read_dir(&dir).expect("list").count(), 0);
    fs::remove_dir_all(&dir).expect("clean up");
}

/// Runs `nendo ARGS` with stdout on `/dev/full` and `stdin` as input.
fn to_dev_full(args: &[&str], stdin: &str) -> Output {
    let full = fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full");
    let mut child = nendo()
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::from(full))
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let mut input = child.stdin.take().expect("stdin");
    input.write_all(stdin.as_bytes()).expect("write stdin");
    drop(input);
    child.wait_with_output().expect("wait")
}

fn failed_cleanly(out: &Output, what: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{what}: {:?}", out.status);
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    assert!(
        stderr.contains("No space left on device"),
        "{what}: the error is named: {stderr}"
    );
}

#[test]
fn a_full_stdout_is_an_error_not_a_panic() {
    let dir = temp_dir("dev-full");
    let model = dir.join("m.json");
    succeeded(&sculpt_primitive("plane", &model));
    let m = model.to_str().expect("utf-8");
    let out = to_dev_full(&["check", m], "");
    failed_cleanly(&out, "check");
    assert_eq!(out.status.code(), Some(1));

    let mesh = dir.join("m.obj");
    let out = to_dev_full(&["export", m, mesh.to_str().expect("utf-8")], "");
    failed_cleanly(&out, "export");

    let request =
        "{\"op\":\"closest\",\"curve\":{\"bezier\":[[0,0],[1,2],[2,0]]},\"point\":[1,3]}\n";
    failed_cleanly(
        &to_dev_full(&["closest", "--batch"], request),
        "closest --batch",
    );
    failed_cleanly(&to_dev_full(&["devices"], ""), "devices");
    fs::remove_dir_all(&dir).expect("clean up");
}

/// `nendo emulate` prints its port on standard output; a failure there names standard output,
/// as every subcommand's does.
#[test]
fn emulate_names_standard_output_when_it_cannot_print_its_port() {
    let out = to_dev_full(&["emulate", "fastrak", "--seconds", "5"], "");
    failed_cleanly(&out, "emulate");
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr
            .starts_with("nendo emulate: cannot write to standard output: No space left on device"),
        "{stderr}"
    );
}

/// The batch commands (`closest`, `curve`) name standard output when their answers cannot be
/// written, and keep their documented status 2 for an output error.
#[test]
fn batch_commands_name_standard_output_when_it_is_full() {
    for (command, request) in [
        (
            "closest",
            "{\"op\":\"closest\",\"curve\":{\"bezier\":[[0,0],[1,2],[2,0]]},\"point\":[1,3]}\n",
        ),
        (
            "curve",
            "{\"op\":\"split\",\"curve\":{\"bezier\":[[0,0],[1,2],[2,0]]},\"u\":0.5}\n",
        ),
    ] {
        let out = to_dev_full(&[command, "--batch"], request);
        failed_cleanly(&out, command);
        assert_eq!(out.status.code(), Some(2), "{command}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(
            stderr.starts_with(&format!(
                "nendo {command}: cannot write to standard output: No space left on device"
            )),
            "{stderr}"
        );
    }
}

#[test]
fn a_closed_pipe_ends_quietly() {
    let dir = temp_dir("closed-pipe");
    let model = dir.join("m.json");
    let out = nendo()
        .args([
            "sculpt",
            "--primitive",
            "sphere",
            "--patches",
            "32x16",
            "--out",
        ])
        .arg(&model)
        .output()
        .expect("run");
    succeeded(&out);
    // As `nendo check m.json | head -c0`: the reader is gone before the report is printed.
    let mut child = nendo()
        .arg("check")
        .arg(&model)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("wait");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.is_empty(), "{stderr}");
    assert_eq!(out.status.code(), Some(141), "{:?}", out.status);
    fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn an_output_over_an_input_of_another_kind_or_another_output_is_refused() {
    let dir = temp_dir("clobber");
    let data = concat!(env!("CARGO_MANIFEST_DIR"), "/");
    let copy = |from: &str, to: &str| {
        let p = dir.join(to);
        fs::copy(format!("{data}{from}"), &p).expect("copy");
        p
    };
    let trace = copy("devices/traces/mouse-sphere.trace", "t.trace");
    let ops = push_ops(&dir);
    let figure = copy("tests/data/figures/horse.json", "horse.json");
    let shape = copy("tests/data/shapes/torso.json", "torso.json");
    let model = dir.join("m.json");
    succeeded(&sculpt_primitive("plane", &model));
    let model_obj = dir.join("m.obj");
    fs::copy(&model, &model_obj).expect("copy");
    let (png, mesh) = (dir.join("p.png"), dir.join("s.obj"));
    let s = |p: &Path| p.to_str().expect("utf-8").to_string();
    let cases: [(Vec<String>, &str, Option<&Path>); 6] = [
        // Before: the trace was replaced by the replayed model.
        (
            vec!["replay".into(), s(&trace), "--out".into(), s(&trace)],
            "is the trace the command reads",
            Some(&trace),
        ),
        // Before: the operations file was replaced by the sculpted model.
        (
            vec![
                "sculpt".into(),
                "--primitive".into(),
                "plane".into(),
                "--ops".into(),
                s(&ops),
                "--out".into(),
                s(&ops),
            ],
            "is the operations file the command reads",
            Some(&ops),
        ),
        // Before: the model was replaced by its own mesh.
        (
            vec!["export".into(), s(&model_obj), s(&model_obj)],
            "is the model the command reads",
            Some(&model_obj),
        ),
        // Before: the PNG was written, then silently replaced by the SVG.
        (
            vec![
                "figure".into(),
                "render".into(),
                s(&figure),
                "--png".into(),
                s(&png),
                "--svg".into(),
                s(&png),
            ],
            "--png and --svg are the same file",
            None,
        ),
        // Before: the shape file was replaced by the mesh.
        (
            vec![
                "figure".into(),
                "shape".into(),
                s(&shape),
                "--mesh".into(),
                s(&shape),
            ],
            "is the shape file the command reads",
            Some(&shape),
        ),
        (
            vec![
                "figure".into(),
                "shape".into(),
                s(&shape),
                "--mesh".into(),
                s(&mesh),
                "--out".into(),
                s(&mesh),
            ],
            "--mesh and --out are the same file",
            Some(&shape),
        ),
    ];
    for (args, says, kept) in cases {
        let before = kept.map(|p| fs::read(p).expect("input"));
        let out = nendo().args(&args).output().expect("run nendo");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && out.status.code() != Some(101),
            "{args:?}: {err}"
        );
        assert!(err.contains(says), "{args:?}: {err}");
        if let (Some(p), Some(b)) = (kept, before) {
            assert_eq!(fs::read(p).expect("still there"), b, "{args:?} changed it");
        }
        assert!(!png.exists() && !mesh.exists(), "{args:?} wrote an output");
    }
    // A mesh into a missing folder: the path and the reason once each (before, both twice).
    let lost = dir.join("nope").join("s.obj");
    let out = nendo()
        .args(["figure", "shape", &s(&shape), "--mesh", &s(&lost)])
        .args(["--resolution", "8", "--iterations", "3"])
        .output()
        .expect("run nendo");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.matches(&s(&lost)).count(), 1, "{err}");
    assert_eq!(err.matches("No such file").count(), 1, "{err}");
    // Writing a model over the model it read stays allowed.
    let out = nendo()
        .args(["sculpt", "--model", &s(&model), "--ops", &s(&ops), "--out"])
        .arg(&model)
        .output()
        .expect("run nendo");
    succeeded(&out);
}
