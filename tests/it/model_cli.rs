//! `nendo sculpt` and `nendo check` end to end.

use crate::support::{nendo, temp_dir};
use serde_json::Value;
use std::path::PathBuf;

fn check(path: &PathBuf) -> Value {
    let out = nendo().arg("check").arg(path).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn sculpt_replays_operations_and_check_reports_on_the_result() {
    let dir = temp_dir("sculpt");
    let ops = dir.join("ops.jsonl");
    std::fs::write(
        &ops,
        "{\"op\":\"push\",\"at\":[0.5,0.5,0],\"dir\":[0,0,-1],\"depth\":0.5,\"radius\":1.25}\n\n\
         {\"op\":\"drag\",\"path\":[[-3,-3,0],[-1,-3,0]],\"dir\":[0,0,-1],\"depth\":-0.2,\"radius\":0.8}\n",
    )
    .unwrap();
    let out_path = dir.join("out.json");
    let out = nendo()
        .args([
            "sculpt",
            "--primitive",
            "plane",
            "--patches",
            "10x10",
            "--regulation",
            "none",
            "--ops",
        ])
        .arg(&ops)
        .arg("--out")
        .arg(&out_path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("2 operations"));
    let model: Value = serde_json::from_str(&std::fs::read_to_string(&out_path).unwrap()).unwrap();
    assert_eq!(model["surface"]["topology"], "plane");
    assert_eq!(model["surface"]["patches"].as_array().unwrap().len(), 100);
    let r = check(&out_path);
    assert_eq!(r["patches"], 100);
    assert_eq!(r["shared_edges"], 180);
    assert_eq!(r["g0_gap"], 0.0);
    assert!(
        r["g1_max_deg"].as_f64().unwrap() > 1.0,
        "the inverse alone creases the dent: {r}"
    );
    assert_eq!(r["poles"].as_array().unwrap().len(), 0);

    // Continue from the model, regulated this time, and compare the two.
    let again = dir.join("again.json");
    let out = nendo()
        .args(["sculpt", "--regulation", "exact", "--model"])
        .arg(&out_path)
        .arg("--ops")
        .arg(&ops)
        .arg("--out")
        .arg(&again)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = nendo()
        .arg("check")
        .arg(&again)
        .arg("--against")
        .arg(&out_path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["regulation"], "exact");
    assert!(r["g1_max_deg"].as_f64().unwrap() < 1e-9, "{r}");
    assert_eq!(r["deviation"]["samples"], 160_000);
    assert!(
        r["deviation"]["max"].as_f64().unwrap() > 0.4,
        "pushed twice as deep: {r}"
    );
    // Models of different shapes cannot be compared.
    let sphere = dir.join("sphere.json");
    let out = nendo()
        .args(["sculpt", "--primitive", "sphere", "--out"])
        .arg(&sphere)
        .output()
        .unwrap();
    assert!(out.status.success());
    let out = nendo()
        .arg("check")
        .arg(&again)
        .arg("--against")
        .arg(&sphere)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_bad_operation_line_is_reported_by_number_and_nothing_is_written() {
    let dir = temp_dir("badop");
    let ops = dir.join("ops.jsonl");
    std::fs::write(
        &ops,
        "{\"op\":\"push\",\"at\":[0,0,3],\"dir\":[0,0,-1],\"depth\":0.5,\"radius\":1.25}\n\
         {\"op\":\"push\",\"at\":[0,0,3],\"dir\":[0,0,-1],\"depth\":0.5,\"radius\":1.25}\n\
         {\"op\":\"push\",\"at\":[0,0,3],\"dir\":[0,0,-1],\"depth\":0.5}\n",
    )
    .unwrap();
    let out_path = dir.join("out.json");
    let out = nendo()
        .args(["sculpt", "--primitive", "sphere", "--ops"])
        .arg(&ops)
        .arg("--out")
        .arg(&out_path)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("line 3") && err.contains("radius") && err.contains("nothing written"),
        "{err}"
    );
    assert!(!out_path.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn primitives_from_the_command_line_are_checked() {
    let dir = temp_dir("prims");
    for (args, topology, poles) in [
        (vec!["--primitive", "sphere"], "sphere", 2),
        (vec!["--primitive", "tube"], "hemisphere", 1),
        (
            vec![
                "--primitive",
                "torus",
                "--radius",
                "4",
                "--minor-radius",
                "1.5",
                "--patches",
                "12x6",
            ],
            "torus",
            0,
        ),
        (
            vec!["--primitive", "cylinder", "--radius", "2", "--height", "5"],
            "cylinder",
            0,
        ),
    ] {
        let out_path = dir.join(format!("{topology}.json"));
        let out = nendo()
            .arg("sculpt")
            .args(&args)
            .arg("--out")
            .arg(&out_path)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let r = check(&out_path);
        assert_eq!(r["topology"], topology);
        assert_eq!(r["poles"].as_array().unwrap().len(), poles);
        assert!(r["g1_max_deg"].as_f64().unwrap() < 1e-9, "{r}");
        for p in r["poles"].as_array().unwrap() {
            assert!(p["spread_deg"].as_f64().unwrap() < 1e-9, "{r}");
        }
    }
    // Odd counts around a closed direction are refused with a clear message.
    let out = nendo()
        .args([
            "sculpt",
            "--primitive",
            "sphere",
            "--patches",
            "7x4",
            "--out",
        ])
        .arg(dir.join("x.json"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("even"));
    // A broken model file is refused by check.
    let bad = dir.join("bad.json");
    std::fs::write(
        &bad,
        "{\"format\":\"nendo-model\",\"version\":1,\"surface\":{\"topology\":\"plane\"}}",
    )
    .unwrap();
    let out = nendo().arg("check").arg(&bad).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("patches_u"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn regulation_default_names_our_own_method() {
    let dir = temp_dir("default-regulation");
    let ops = dir.join("ops.jsonl");
    std::fs::write(
        &ops,
        "{\"op\":\"push\",\"at\":[0.5,0.5,0],\"dir\":[0,0,-1],\"depth\":0.5,\"radius\":1.25}\n",
    )
    .unwrap();
    let mut written = Vec::new();
    for method in ["default", "exact"] {
        let out_path = dir.join(format!("{method}.json"));
        let out = nendo()
            .args([
                "sculpt",
                "--primitive",
                "plane",
                "--regulation",
                method,
                "--ops",
            ])
            .arg(&ops)
            .arg("--out")
            .arg(&out_path)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{method}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        written.push(std::fs::read(&out_path).unwrap());
    }
    assert_eq!(written[0], written[1], "default is exact");
    let out = nendo()
        .args([
            "sculpt",
            "--primitive",
            "plane",
            "--regulation",
            "bogus",
            "--out",
        ])
        .arg(dir.join("bogus.json"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(!dir.join("bogus.json").exists());
}

/// The window (`nendo MODEL`, no subcommand) reads its model before any window opens, so a model
/// it cannot read fails headless, naming the file once.
#[test]
fn the_window_names_a_model_it_cannot_read_once() {
    let dir = temp_dir("window-model");
    let missing = dir.join("missing.nendo.json");
    let bad = dir.join("bad.nendo.json");
    std::fs::write(&bad, "{ not json").unwrap();
    for path in [&missing, &bad] {
        let out = nendo()
            .arg(path)
            .arg("--no-autosave")
            .arg("--no-recover")
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1));
        let err = String::from_utf8_lossy(&out.stderr);
        let name = path.display().to_string();
        assert!(err.starts_with(&format!("nendo: {name}: ")), "{err}");
        assert_eq!(err.matches(&name).count(), 1, "{err}");
    }
}

/// A size option the chosen primitive does not use is refused, naming the option, the
/// primitives it shapes and the one chosen; nothing is written.
#[test]
fn a_size_option_the_primitive_does_not_use_is_refused() {
    let dir = temp_dir("prims-unused");
    let out_path = dir.join("o.json");
    for (primitive, option, want) in [
        (
            "sphere",
            "--height",
            "--height applies to cylinder and tube, not sphere",
        ),
        (
            "plane",
            "--minor-radius",
            "--minor-radius applies to torus, not plane",
        ),
        (
            "plane",
            "--radius",
            "--radius applies to cylinder, hemisphere, sphere, torus and tube, not plane",
        ),
        (
            "torus",
            "--height",
            "--height applies to cylinder and tube, not torus",
        ),
        (
            "tube",
            "--minor-radius",
            "--minor-radius applies to torus, not tube",
        ),
    ] {
        let out = nendo()
            .args(["sculpt", "--primitive", primitive, option, "0.5", "--out"])
            .arg(&out_path)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{primitive} {option}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim_end(), format!("nendo sculpt: {want}"));
        assert!(!out_path.exists());
    }
    // `nendo record` refuses it before opening any device.
    let out = nendo()
        .args([
            "record",
            "--profile",
            "fastrak",
            "--primitive",
            "sphere",
            "--height",
            "2",
            "--out",
        ])
        .arg(&out_path)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--height applies to cylinder and tube, not sphere"),
        "{err}"
    );
    assert!(!out_path.exists());
    // `nendo replay` too, whether the primitive comes from the command line or from the
    // trace's scene (a sphere).
    let trace = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("devices/traces/sphere-push-pull.trace");
    for extra in [
        &["--primitive", "plane", "--radius", "2"][..],
        &["--height", "2"][..],
    ] {
        let out = nendo()
            .arg("replay")
            .arg(&trace)
            .args(extra)
            .arg("--out")
            .arg(&out_path)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{extra:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(" applies to "), "{extra:?}: {err}");
        assert!(!out_path.exists());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `nendo render` and `nendo export` name a model they cannot read once, as `nendo check`.
#[test]
fn render_and_export_name_a_model_they_cannot_read_once() {
    let dir = temp_dir("read-once");
    let missing = dir.join("missing.json");
    let bad = dir.join("bad.json");
    std::fs::write(&bad, "{ not json").unwrap();
    for path in [&missing, &bad] {
        let name = path.display().to_string();
        let mut runs = vec![
            (
                "export",
                nendo()
                    .arg("export")
                    .arg(path)
                    .arg(dir.join("o.stl"))
                    .output()
                    .unwrap(),
            ),
            (
                "export",
                nendo()
                    .arg("export")
                    .arg(path)
                    .arg(dir.join("o.step"))
                    .output()
                    .unwrap(),
            ),
        ];
        if cfg!(feature = "gui") {
            runs.push((
                "render",
                nendo()
                    .arg("render")
                    .arg(path)
                    .arg("--png")
                    .arg(dir.join("o.png"))
                    .output()
                    .unwrap(),
            ));
        }
        for (command, out) in runs {
            assert_eq!(out.status.code(), Some(1), "{command}");
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(
                err.starts_with(&format!("nendo {command}: {name}: ")),
                "{err}"
            );
            assert_eq!(err.matches(&name).count(), 1, "{err}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn check_reports_g2_on_the_sphere_primitive_and_a_sculpted_plane() {
    let dir = temp_dir("check-g2");
    let sculpt = |primitive: &str, ops: &str, name: &str| {
        let ops_path = dir.join(format!("{name}.jsonl"));
        std::fs::write(&ops_path, ops).unwrap();
        let out_path = dir.join(format!("{name}.json"));
        let out = nendo()
            .args(["sculpt", "--primitive", primitive, "--ops"])
            .arg(&ops_path)
            .arg("--out")
            .arg(&out_path)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        check(&out_path)
    };
    // The sphere primitive: its seams match in curvature to rounding, both poles nearly.
    let r = sculpt("sphere", "", "sphere");
    let g2 = &r["g2"];
    assert_eq!(g2["seams"], r["shared_edges"]);
    assert!(g2["relative_max"].as_f64().unwrap() < 1e-9, "{g2}");
    assert_eq!(g2["poles"].as_array().unwrap().len(), 2);
    for pole in g2["poles"].as_array().unwrap() {
        assert!(pole["relative"].as_f64().unwrap() < 1e-3, "{pole}");
        // Outward normals, radius 3: both principal curvatures near −1/3.
        for k in pole["principal_curvatures"].as_array().unwrap() {
            assert!((k.as_f64().unwrap() + 1.0 / 3.0).abs() < 0.01, "{pole}");
        }
    }
    // A dent in the plane (exact, G1): curvature jumps across the seams around it, and the
    // worst seams are listed worst first.
    let r = sculpt(
        "plane",
        "{\"op\":\"push\",\"at\":[0.5,0.5,0],\"dir\":[0,0,-1],\"depth\":0.5,\"radius\":1.25}\n",
        "plane",
    );
    let g2 = &r["g2"];
    assert!(r["g1_max_deg"].as_f64().unwrap() < 1e-6);
    assert!(g2["relative_max"].as_f64().unwrap() > 0.1, "{g2}");
    let worst = g2["worst"].as_array().unwrap();
    assert_eq!(worst.len(), 5);
    assert_eq!(worst[0]["relative"], g2["relative_max"]);
    for pair in worst.windows(2) {
        assert!(pair[0]["relative"].as_f64() >= pair[1]["relative"].as_f64());
    }
    let _ = std::fs::remove_dir_all(&dir);
}
