//! The export size rule (issue 27): without `--tolerance`, a mesh is exported within a
//! thousandth of the diagonal of the model's box, so that a face mask sculpted on the 10 × 10
//! plane comes out under 200 000 triangles; the estimate the window's export dialog shows
//! (triangles exactly, the file's size within 15 %) matches what is written.

use std::path::Path;

use nendo::editor::export_job::estimate_export;
use nendo::mesh::{MeshFormat, Tessellation};
use nendo::model::Model;
use serde_json::{Value, json};

use crate::support::{run, run_with_input, temp_dir};

/// A path on the plane z = 0 through `corners`, a point every fifth of `radius`.
fn path(corners: &[(f64, f64)], radius: f64) -> Value {
    let mut out = Vec::new();
    for w in corners.windows(2) {
        let ((ax, ay), (bx, by)) = (w[0], w[1]);
        let n = (((bx - ax).hypot(by - ay)) / (radius / 5.0))
            .ceil()
            .max(1.0) as usize;
        for k in 0..n {
            let t = k as f64 / n as f64;
            out.push(json!([ax + t * (bx - ax), ay + t * (by - ay), 0.0]));
        }
    }
    let (x, y) = corners[corners.len() - 1];
    out.push(json!([x, y, 0.0]));
    Value::Array(out)
}

/// A face-mask session on the 10 × 10 plane as a sculptor makes it: cheeks, eye sockets,
/// brows, a nose moved up with its ridge, nostrils, a mouth and lips, a chin, a few smoothing
/// dabs — 20 operations of radii 0.25 to 1.5, each side drawn (no `--mirror`, which
/// `--auto-refine` refuses).
pub fn face_mask_ops() -> String {
    let push = |x: f64, y: f64, depth: f64, radius: f64| json!({"op": "push", "at": [x, y, 0.0], "dir": "normal", "depth": depth, "radius": radius});
    let drag = |corners: &[(f64, f64)], depth: f64, radius: f64| json!({"op": "drag", "path": path(corners, radius), "dir": "normal", "depth": depth, "radius": radius});
    let smooth = |x: f64, y: f64, radius: f64| json!({"op": "smooth", "at": [x, y, 0.0], "radius": radius, "strength": 0.5});
    let mut ops = Vec::new();
    for s in [1.0, -1.0] {
        ops.push(push(s * 2.5, -0.8, -0.35, 1.5));
    }
    for s in [1.0, -1.0] {
        ops.push(push(s * 1.6, 1.2, 0.45, 0.9));
        ops.push(push(s * 1.6, 1.2, 0.2, 0.55));
    }
    for s in [1.0, -1.0] {
        ops.push(drag(
            &[(s * 2.4, 2.0), (s * 1.6, 2.35), (s * 0.8, 2.2)],
            -0.3,
            0.5,
        ));
    }
    ops.push(json!({"op": "move", "at": [0.0, 0.0, 0.0], "to": [0.0, 0.0, 1.0], "radius": 1.2}));
    ops.push(drag(&[(0.0, 1.6), (0.0, 0.3), (0.0, -0.6)], -0.25, 0.5));
    for s in [1.0, -1.0] {
        ops.push(push(s * 0.35, -0.85, 0.15, 0.25));
    }
    ops.push(drag(
        &[
            (-1.2, -2.1),
            (-0.6, -2.3),
            (0.0, -2.35),
            (0.6, -2.3),
            (1.2, -2.1),
        ],
        0.25,
        0.4,
    ));
    ops.push(drag(
        &[(-0.9, -1.75), (0.0, -1.85), (0.9, -1.75)],
        -0.12,
        0.3,
    ));
    ops.push(drag(&[(-0.8, -2.8), (0.0, -2.9), (0.8, -2.8)], -0.15, 0.35));
    ops.push(push(0.0, -3.6, -0.4, 1.0));
    for s in [1.0, -1.0] {
        ops.push(smooth(s * 2.5, -0.8, 1.0));
        ops.push(smooth(s * 1.6, 1.2, 0.8));
    }
    ops.iter().map(|op| format!("{op}\n")).collect()
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8")
}

#[test]
fn a_face_mask_exports_under_200k_triangles_and_the_estimate_holds() {
    let dir = temp_dir("export-size");
    let model = dir.join("face.nendo.json");
    let o = run_with_input(
        &[
            "sculpt",
            "--primitive",
            "plane",
            "--ops",
            "-",
            "--auto-refine",
            "--out",
            s(&model),
        ],
        &face_mask_ops(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let patches = Model::read(&model).expect("reads").model.surface.patches();
    let tolerance = Tessellation::export_tolerance_for(&patches);
    // The face's box: the plane's 10 × 10 and the relief, so a little over 10·√2 / 1000.
    assert!(
        (0.0141..0.016).contains(&tolerance),
        "tolerance {tolerance}"
    );
    eprintln!(
        "face mask: {} patches, tolerance {tolerance:.4}",
        patches.len()
    );
    for (name, format) in [
        ("face.obj", MeshFormat::Obj),
        ("face.stl", MeshFormat::Stl),
        ("face.glb", MeshFormat::Glb),
    ] {
        let out = dir.join(name);
        let o = run(&["export", s(&model), s(&out)]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let line = String::from_utf8_lossy(&o.stdout).into_owned();
        let written: u64 = line
            .split(", ")
            .find_map(|part| part.strip_suffix(" triangles"))
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("a triangle count in {line:?}"));
        assert!(written < 200_000, "{name}: {written} triangles");
        let estimate = estimate_export(&patches, tolerance, format);
        let bytes = std::fs::metadata(&out).expect("written").len();
        eprintln!(
            "{name}: {written} triangles ({} estimated), {bytes} bytes ({} estimated)",
            estimate.triangles, estimate.bytes
        );
        // Welding drops only triangles collapsed at a pole; the plane has none.
        assert_eq!(estimate.triangles, written, "{name}");
        let ratio = estimate.bytes as f64 / bytes as f64;
        assert!(
            (0.85..1.15).contains(&ratio),
            "{name}: size estimate off by {ratio}"
        );
    }
}
