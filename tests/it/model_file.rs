//! The `nendo-model` document: exact round trips, validation with clear errors, atomic writes.

use crate::support::temp_dir;
use glam::DVec3;
use nendo::curve::json::curve_from_json;
use nendo::model::{Model, ModelError};
use nendo::surface::{Op, Primitive, PrimitiveParams, Regulation, Sculptor};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

/// Every node bit for bit, reporting only the first difference.
fn assert_same_nodes(a: &Model, b: &Model) {
    assert_eq!(a.surface.nodes().len(), b.surface.nodes().len());
    let diff = a
        .surface
        .nodes()
        .iter()
        .zip(b.surface.nodes())
        .position(|(x, y)| x.to_array().map(f64::to_bits) != y.to_array().map(f64::to_bits));
    if let Some(k) = diff {
        panic!(
            "node {k}: {} vs {}",
            a.surface.nodes()[k],
            b.surface.nodes()[k]
        );
    }
}

fn sculpted_sphere() -> Model {
    let mut g = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .unwrap();
    let mut s = Sculptor::new();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..40 {
        let at = DVec3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        )
        .normalize()
            * 3.0;
        let op = Op::Push {
            at,
            dir: -at,
            depth: rng.gen_range(-0.4..0.4),
            radius: rng.gen_range(0.5..1.5),
        };
        s.apply(&mut g, &op, Regulation::None).unwrap();
    }
    let mut m = Model::new(g);
    m.curves.push(
        curve_from_json(
            &json!({"bezier": [[0.1, 0.2, 0.3], [1.0 / 3.0, 2.0, 0.0], [2.0, 0.0, 1e-7]]}),
        )
        .unwrap(),
    );
    m.curves.push(
        curve_from_json(&json!({"bspline": {"degree": 2, "knots": [0, 0, 0, 0.5, 1, 1, 1], "points": [[0,0],[1,1],[2,0],[3,1]]}}))
            .unwrap(),
    );
    m
}

#[test]
fn a_written_model_reads_back_bit_identical() {
    let m = sculpted_sphere();
    let dir = temp_dir("roundtrip");
    let path = dir.join("m.json");
    m.write(&path).unwrap();
    let back = Model::read(&path).unwrap();
    assert_eq!(back.seam_gap, 0.0);
    assert_same_nodes(&back.model, &m);
    assert!(
        back.model == m,
        "grid, regulation and curves must read back equal"
    );
    // No temporary file is left behind.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("m.json")]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn every_topology_round_trips_with_its_layout() {
    for p in Primitive::ALL {
        let g = p.build(&PrimitiveParams::default()).unwrap();
        let m = Model::new(g);
        let v = m.to_json();
        assert_eq!(v["format"], "nendo-model");
        assert_eq!(v["version"], 1);
        assert_eq!(v["surface"]["topology"], p.topology().name());
        let patches = v["surface"]["patches"].as_array().unwrap();
        assert_eq!(patches.len(), m.surface.patch_count());
        // patches[iv * M + iu][4 i + j] is P[4 i + j] of patch (iu, iv).
        let mm = m.surface.patches_u();
        let (iu, iv) = (mm - 1, m.surface.patches_v() - 1);
        let want = m.surface.patch(iu, iv)[4 * 2 + 1];
        assert_eq!(patches[iv * mm + iu][9], json!([want.x, want.y, want.z]));
        assert!(Model::from_json(&v).unwrap().model == m, "{p}");
    }
}

fn error_of(v: Value) -> String {
    match Model::from_json(&v) {
        Ok(_) => panic!("accepted {v}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_documents_are_rejected_with_clear_errors() {
    let good = Model::new(
        Primitive::Sphere
            .build(&PrimitiveParams::default())
            .unwrap(),
    )
    .to_json();
    let with = |f: &dyn Fn(&mut Value)| {
        let mut v = good.clone();
        f(&mut v);
        v
    };
    let cases: Vec<(Value, &str)> = vec![
        (json!([1, 2]), "object"),
        (with(&|v| v["format"] = json!("obj")), "format"),
        (with(&|v| v["version"] = json!(2)), "version 2"),
        (
            with(&|v| {
                v.as_object_mut()
                    .unwrap()
                    .remove("surface")
                    .map(|_| ())
                    .unwrap_or(())
            }),
            "\"surface\"",
        ),
        (
            with(&|v| v["surface"]["topology"] = json!("cube")),
            "unknown topology",
        ),
        (with(&|v| v["surface"]["patches_u"] = json!(7)), "even"),
        (
            with(&|v| v["surface"]["patches_v"] = json!(-1)),
            "patches_v",
        ),
        (
            with(&|v| v["surface"]["regulation"] = json!("magic")),
            "regulation",
        ),
        (
            with(&|v| v["surface"]["patches"].as_array_mut().unwrap().truncate(31)),
            "needs 32",
        ),
        (
            with(&|v| {
                v["surface"]["patches"][3]
                    .as_array_mut()
                    .unwrap()
                    .truncate(15)
            }),
            "patches[3]",
        ),
        (
            with(&|v| v["surface"]["patches"][3][2] = json!([1, 2])),
            "patches[3][2]",
        ),
        (
            with(&|v| v["surface"]["patches"][3][2][1] = json!("x")),
            "patches[3][2][1]",
        ),
        (
            with(&|v| v["surface"]["patches"][7][13] = json!([9, 9, 9])),
            "closed seam",
        ),
        (
            with(&|v| v["surface"]["patches"][2][4] = json!([0, 0.5, -3])),
            "pole",
        ),
        (
            with(&|v| v["surface"]["patches"][9][14] = json!([1, 1, 1])),
            "shared edge",
        ),
        (
            with(&|v| v["curves"] = json!([{"bezier": [[0, 0], [1, 1, 1]]}])),
            "curves[0]",
        ),
        (
            with(&|v| v["surface"]["ratios"]["u"] = json!([1, 1])),
            "spacing ratios",
        ),
        (
            with(&|v| v["surface"]["ratios"]["v"][1] = json!(-2)),
            "spacing ratio",
        ),
        (
            with(&|v| v["surface"]["ratios"] = json!({"u": "x"})),
            "ratios.u",
        ),
        (
            with(&|v| v["curves"] = json!({"bezier": []})),
            "curves: invalid type",
        ),
    ];
    for (v, want) in cases {
        let e = error_of(v);
        assert!(e.contains(want), "expected {want:?} in {e:?}");
    }
    assert!(matches!(
        Model::from_json_str("{\"format\": "),
        Err(ModelError::Json(_))
    ));
    // A number out of range is rejected by the JSON layer rather than read as infinity.
    let text = good
        .to_string()
        .replacen("[0.0,0.0,-3.0]", "[0.0,0.0,-3e999]", 1);
    let e = Model::from_json_str(&text).unwrap_err().to_string();
    assert!(e.contains("out of range") && e.contains("finite"), "{e}");
    // What Python's json module writes for NaN and infinity: named, not "expected value".
    for token in ["NaN", "Infinity", "-Infinity"] {
        let text = good
            .to_string()
            .replacen("[0.0,0.0,-3.0]", &format!("[0.0,0.0,{token}]"), 1);
        let e = Model::from_json_str(&text).unwrap_err().to_string();
        assert!(
            e.contains(token.trim_start_matches('-')) && e.contains("finite"),
            "{token}: {e}"
        );
    }
}

#[test]
fn io_errors_name_the_file_once() {
    let path = temp_dir("io").join("missing.json");
    let e = Model::read(&path).unwrap_err();
    let shown = format!("{:#}", anyhow::Error::from(e));
    let name = path.display().to_string();
    assert_eq!(shown.matches(&name).count(), 1, "{shown}");
    assert_eq!(shown.matches("os error").count(), 1, "{shown}");
}

#[test]
fn float_coordinates_survive_the_text_form_exactly() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut g = Primitive::Plane
        .build(&PrimitiveParams {
            patches: Some((20, 20)),
            ..PrimitiveParams::default()
        })
        .unwrap();
    let mut s = Sculptor::new();
    for _ in 0..300 {
        let at = DVec3::new(rng.gen_range(-10.0..10.0), rng.gen_range(-10.0..10.0), 0.0);
        let dir = DVec3::new(rng.gen_range(-0.3..0.3), rng.gen_range(-0.3..0.3), -1.0);
        s.apply(
            &mut g,
            &Op::Push {
                at,
                dir,
                depth: rng.gen_range(-1.0..1.0),
                radius: rng.gen_range(0.3..3.0),
            },
            Regulation::None,
        )
        .unwrap();
    }
    let m = Model::new(g);
    let back = Model::from_json_str(&m.to_json_string()).unwrap().model;
    assert_same_nodes(&back, &m);
}

#[test]
fn a_failed_write_leaves_nothing() {
    let dir = temp_dir("failed");
    let path = dir.join("no-such-dir").join("m.json");
    let m = Model::new(Primitive::Plane.build(&PrimitiveParams::default()).unwrap());
    assert!(matches!(m.write(&path), Err(ModelError::Io { .. })));
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    std::fs::remove_dir_all(&dir).unwrap();
}
