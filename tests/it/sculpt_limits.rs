//! `nendo sculpt` refuses operations whose result would not be finite, would exceed the
//! surface coordinate limit, or would leave a seam the exact regulation could not keep G1 —
//! with the operation's line number, a non-zero exit and nothing written.

use std::path::Path;
use std::process::Output;

use crate::support::{run, temp_dir};

/// Runs `nendo sculpt ARGS` with `ops` on standard input.
fn sculpt_stdin(args: &[&str], ops: &str) -> Output {
    let mut all = vec!["sculpt"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--ops", "-"]);
    crate::support::run_with_input(&all, ops)
}

fn pole_push(depth: &str, radius: f64) -> String {
    format!(
        "{{\"op\":\"push\",\"at\":[0,0,3],\"dir\":[0,0,-1],\"depth\":{depth},\"radius\":{radius}}}\n"
    )
}

fn path_str(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

#[test]
fn a_1e308_push_is_refused_with_its_line_and_the_model_kept() {
    let dir = temp_dir("limits-1e308");
    let model = dir.join("my.json");
    let out = run(&["sculpt", "--primitive", "sphere", "--out", path_str(&model)]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let before = std::fs::read(&model).expect("model written");
    let ops = dir.join("ops.jsonl");
    // A blank line first: the refusal names the file's line, not the operation's index.
    std::fs::write(&ops, format!("\n{}", pole_push("1e308", 0.5))).expect("ops written");
    let out = run(&[
        "sculpt",
        "--model",
        path_str(&model),
        "--ops",
        path_str(&ops),
        "--out",
        path_str(&model),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(err.contains("line 2"), "{err}");
    assert!(err.contains("coordinate limit"), "{err}");
    assert!(err.contains("nothing written"), "{err}");
    assert_eq!(std::fs::read(&model).expect("model still there"), before);
}

#[test]
fn twenty_huge_pulls_are_refused_and_nothing_written() {
    let dir = temp_dir("limits-pulls");
    let out_path = dir.join("x.json");
    let ops = pole_push("-1e307", 0.5).repeat(20);
    let out = sculpt_stdin(
        &["--primitive", "sphere", "--out", path_str(&out_path)],
        &ops,
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(err.contains("line 1"), "{err}");
    assert!(!out_path.exists());
}

#[test]
fn depths_near_1e302_never_give_inf_in_an_obj() {
    let dir = temp_dir("limits-1e302");
    for depth in ["1e302", "-1e302", "1e49", "-1e45"] {
        let model = dir.join("m.json");
        let _ = std::fs::remove_file(&model);
        let out = sculpt_stdin(
            &["--primitive", "sphere", "--out", path_str(&model)],
            &pole_push(depth, 0.5),
        );
        if !out.status.success() {
            assert!(!model.exists(), "{depth}: refused but written");
            continue;
        }
        let obj = dir.join("m.obj");
        let out = run(&["export", path_str(&model), path_str(&obj)]);
        assert!(
            out.status.success(),
            "{depth}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = std::fs::read_to_string(&obj).expect("obj written");
        let lower = text.to_lowercase();
        assert!(!lower.contains("inf") && !lower.contains("nan"), "{depth}");
    }
    // The largest of them is refused outright.
    let out = sculpt_stdin(
        &[
            "--primitive",
            "sphere",
            "--out",
            path_str(&dir.join("big.json")),
        ],
        &pole_push("1e302", 0.5),
    );
    assert!(!out.status.success());
}

#[test]
fn a_30_side_pull_at_the_pole_is_refused_with_the_crease() {
    let dir = temp_dir("limits-g1");
    let out_path = dir.join("x.json");
    let out = sculpt_stdin(
        &["--primitive", "sphere", "--out", path_str(&out_path)],
        &pole_push("-30", 0.5),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(err.contains("line 1") && err.contains("G1"), "{err}");
    assert!(err.contains("degrees"), "{err}");
    assert!(!out_path.exists());
    // At 10 sides the regulation keeps G1 and the pull goes through.
    let out = sculpt_stdin(
        &["--primitive", "sphere", "--out", path_str(&out_path)],
        &pole_push("-10", 0.5),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The baselines promise no G1: the same pull is not refused under g1.
    let out = sculpt_stdin(
        &[
            "--primitive",
            "sphere",
            "--regulation",
            "g1",
            "--out",
            path_str(&out_path),
        ],
        &pole_push("-30", 0.5),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_model_beyond_the_limit_is_refused_on_reading() {
    let dir = temp_dir("limits-read");
    let model = dir.join("m.json");
    let out = run(&["sculpt", "--primitive", "plane", "--out", path_str(&model)]);
    assert!(out.status.success());
    let text = std::fs::read_to_string(&model).expect("model");
    let mut v: serde_json::Value = serde_json::from_str(&text).expect("json");
    // Scale the first coordinate found beyond the limit.
    fn first_number(v: &mut serde_json::Value) -> bool {
        match v {
            serde_json::Value::Number(_) => {
                *v = serde_json::json!(1e60);
                true
            }
            serde_json::Value::Array(a) => a.iter_mut().any(first_number),
            _ => false,
        }
    }
    let patches = v
        .get_mut("surface")
        .and_then(|s| s.get_mut("patches"))
        .expect("control points in the model");
    assert!(first_number(patches));
    std::fs::write(&model, v.to_string()).expect("written");
    let out = run(&["check", path_str(&model)]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(err.contains("limit"), "{err}");
}
