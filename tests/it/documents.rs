//! Every file and batch format is read strictly: unknown, repeated and misspelled members are
//! refused with the member's path (and line and column where the text has them), a UTF-8
//! byte-order mark is named as such, and what used to be silently accepted is refused.

use crate::support::{nendo, temp_dir};
use nendo::figure::document::FigureDocument;
use nendo::figure::shape_document::ShapeDocument;
use nendo::model::Model;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::process::Output;

/// A sculpted-free 4 x 4 plane model written by `nendo sculpt`, as JSON.
fn plane_model(dir: &Path) -> Value {
    let path = dir.join("plane.json");
    let out = nendo()
        .args([
            "sculpt",
            "--primitive",
            "plane",
            "--patches",
            "4x4",
            "--out",
        ])
        .arg(&path)
        .output()
        .expect("nendo runs");
    assert!(out.status.success(), "{}", stderr(&out));
    serde_json::from_str(&std::fs::read_to_string(&path).expect("written")).expect("JSON")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write");
    path
}

/// `nendo check FILE`, which must fail; its standard error.
fn check_fails(path: &Path) -> String {
    let out = nendo().arg("check").arg(path).output().expect("nendo runs");
    assert!(!out.status.success(), "accepted {}", path.display());
    stderr(&out)
}

/// Answers of a batch command (`closest` or `curve`) to `input`.
fn batch(command: &str, input: &str) -> Vec<Value> {
    let out = crate::support::run_with_input(&[command, "--batch"], input);
    String::from_utf8(out.stdout)
        .expect("UTF-8")
        .lines()
        .map(|l| serde_json::from_str(l).expect("every answer is JSON"))
        .collect()
}

fn error_of(answer: &Value) -> &str {
    answer["error"]
        .as_str()
        .unwrap_or_else(|| panic!("expected an error: {answer}"))
}

#[test]
fn a_model_with_two_surfaces_is_refused_not_read_as_the_last() {
    let dir = temp_dir("documents-dup");
    let m = plane_model(&dir);
    let first = m["surface"].to_string();
    let mut other = m["surface"].clone();
    other["regulation"] = json!("none");
    let text = format!(
        "{{\"format\":\"nendo-model\",\"version\":1,\"surface\":{first},\"surface\":{other}}}"
    );
    let err = check_fails(&write(&dir, "dup.json", &text));
    assert!(err.contains("duplicate field \"surface\""), "{err}");
    assert!(err.contains("line 1 column"), "{err}");
}

#[test]
fn a_misspelled_member_is_refused_not_dropped_on_rewrite() {
    let dir = temp_dir("documents-curvs");
    let mut m = plane_model(&dir);
    m["curvs"] = json!([{"bezier": [[0, 0, 0], [1, 1, 1]]}]);
    let model = write(&dir, "curvs.json", &m.to_string());
    let out_path = dir.join("rewritten.json");
    let out = nendo()
        .args(["sculpt", "--model"])
        .arg(&model)
        .arg("--out")
        .arg(&out_path)
        .output()
        .expect("nendo runs");
    assert!(!out.status.success(), "a misspelled member was accepted");
    assert!(
        stderr(&out).contains("unknown field \"curvs\""),
        "{}",
        stderr(&out)
    );
    assert!(!out_path.exists(), "nothing is written");
    // Deeper: an unknown member of the surface, and of a curve, are named with their path.
    let mut m = plane_model(&dir);
    m["surface"]["ratio"] = json!({"u": [], "v": []});
    let err = Model::from_json_str(&m.to_string())
        .unwrap_err()
        .to_string();
    assert!(
        err.starts_with("surface.ratio: unknown field \"ratio\""),
        "{err}"
    );
    let mut m = plane_model(&dir);
    m["curves"] =
        json!([{"bezier": [[0, 0], [1, 1]]}, {"bezier": [[0, 0], [1, 1]], "closed": true}]);
    let err = Model::from_json_str(&m.to_string())
        .unwrap_err()
        .to_string();
    assert!(
        err.starts_with("curves[1].closed: unknown field \"closed\""),
        "{err}"
    );
}

#[test]
fn a_bad_point_deep_in_a_model_is_named_with_its_path_line_and_column() {
    let dir = temp_dir("documents-deep");
    let mut m = plane_model(&dir);
    m["surface"]["patches"][3][7] = json!([1.0, 2.0]);
    let text = serde_json::to_string_pretty(&m).expect("text");
    // The line of the bad point in the pretty text: the second coordinate's line + 1.
    let err = check_fails(&write(&dir, "deep.json", &text));
    assert!(
        err.contains("surface.patches[3][7]: invalid length 2, expected an array of length 3"),
        "{err}"
    );
    let line: usize = err
        .split("(line ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no line in {err}"));
    let lines: Vec<&str> = text.lines().collect();
    assert!(line > 10 && line <= lines.len(), "{err}");
    assert!(
        lines[line - 1].trim_start().starts_with(']'),
        "the line of the point's end: {:?}",
        lines[line - 1]
    );
    // A wrong type deeper still.
    let mut m = plane_model(&dir);
    m["surface"]["patches"][3][7][2] = json!("z");
    let err = Model::from_json_str(&m.to_string())
        .unwrap_err()
        .to_string();
    assert!(
        err.starts_with("surface.patches[3][7][2]: invalid type: string"),
        "{err}"
    );
}

#[test]
fn a_byte_order_mark_is_named_as_such() {
    let dir = temp_dir("documents-bom");
    let m = plane_model(&dir);
    let err = check_fails(&write(&dir, "bom.json", &format!("\u{feff}{m}")));
    assert!(err.contains("byte-order mark (BOM)"), "{err}");
    assert!(!err.contains("expected value"), "{err}");
    let answers = batch(
        "closest",
        "\u{feff}{\"op\":\"closest\",\"curve\":{\"bezier\":[[0,0],[1,0]]},\"point\":[0,1]}\n",
    );
    assert!(
        error_of(&answers[0]).contains("byte-order mark"),
        "{}",
        answers[0]
    );
    let ops = write(
        &dir,
        "bom.jsonl",
        "\u{feff}{\"op\":\"push\",\"at\":[0,0,0],\"dir\":[0,0,-1],\"depth\":0.1,\"radius\":1}\n",
    );
    let out = nendo()
        .args(["sculpt", "--primitive", "plane", "--ops"])
        .arg(&ops)
        .arg("--out")
        .arg(dir.join("out.json"))
        .output()
        .expect("nendo runs");
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("line 1: the file starts with a UTF-8 byte-order mark"),
        "{}",
        stderr(&out)
    );
    let err = FigureDocument::from_json("\u{feff}{\"format\": \"nendo-figure\", \"version\": 1}")
        .unwrap_err()
        .to_string();
    assert!(err.contains("byte-order mark"), "{err}");
    let err = nendo_devices::Profile::from_json("\u{feff}{}", "p")
        .unwrap_err()
        .to_string();
    assert!(err.contains("byte-order mark"), "{err}");
}

#[test]
fn a_misspelled_rmax_is_refused_not_ignored() {
    // Without "rMax" being read, the far point would be answered at distance 10.
    let answers = batch(
        "closest",
        "{\"op\":\"closest\",\"curve\":{\"bezier\":[[0,0],[1,0]]},\"point\":[0,10],\"rMax\":1}\n\
         {\"op\":\"pick\",\"curves\":[{\"bezier\":[[0,0],[1,0]]}],\"point\":[0,10],\"rMax\":1}\n\
         {\"op\":\"closest\",\"curve\":{\"bezier\":[[0,0],[1,0]]},\"point\":[0,10],\"rmax\":1}\n",
    );
    assert_eq!(answers.len(), 3);
    for a in &answers[..2] {
        let e = error_of(a);
        assert!(e.contains("unknown field \"rMax\""), "{e}");
        assert!(e.contains("column"), "{e}");
    }
    assert_eq!(answers[2], json!({"u": null}));
    // Repeated members and members deep in a curve, in both batch protocols.
    let answers = batch(
        "closest",
        "{\"op\":\"closest\",\"curve\":{\"bezier\":[[0,0],[1,0]]},\"point\":[0,1],\"point\":[0,2]}\n\
         {\"op\":\"closest\",\"curve\":{\"bezier\":[[0,0],[1,0],[2,\"x\"]]},\"point\":[0,1]}\n",
    );
    assert!(
        error_of(&answers[0]).contains("duplicate field \"point\""),
        "{}",
        answers[0]
    );
    assert!(
        error_of(&answers[1]).starts_with("curve.bezier[2][1]: invalid type: string"),
        "{}",
        answers[1]
    );
    let answers = batch(
        "curve",
        "{\"op\":\"split\",\"curve\":{\"bezier\":[[0,0],[1,1],[2,0]]},\"u\":0.5,\"U\":0.2}\n\
         {\"op\":\"warp\",\"pairs\":[[{\"bezier\":[[0,0],[1,0]]},{\"bezier\":[[0,0],[1,0]],\"bspline\":null,\"x\":1}]],\"points\":[[0,1]]}\n\
         {\"op\":\"refine\",\"mode\":\"curvature\",\"curve\":{\"bezier\":[[0,0],[1,1],[2,0]]},\"constraints\":[{\"u\":0,\"point\":[0,0],\"tangent\":[1,0]}]}\n",
    );
    assert!(
        error_of(&answers[0]).contains("unknown field \"U\""),
        "{}",
        answers[0]
    );
    assert!(
        error_of(&answers[1]).starts_with("pairs[0][1].x: unknown field \"x\""),
        "{}",
        answers[1]
    );
    assert!(
        error_of(&answers[2]).starts_with("constraints[0]: one of"),
        "{}",
        answers[2]
    );
}

#[test]
fn a_direction_too_long_to_normalise_is_named_as_such() {
    let dir = temp_dir("documents-dir");
    let ops = write(
        &dir,
        "huge.jsonl",
        "{\"op\":\"push\",\"at\":[0.5,0.5,0],\"dir\":[0,0,-1],\"depth\":0.1,\"radius\":1}\n\
         {\"op\":\"push\",\"at\":[0.5,0.5,0],\"dir\":[1e308,1e308,-1e308],\"depth\":0.1,\"radius\":1}\n",
    );
    let out = nendo()
        .args(["sculpt", "--primitive", "plane", "--ops"])
        .arg(&ops)
        .arg("--out")
        .arg(dir.join("out.json"))
        .output()
        .expect("nendo runs");
    assert!(!out.status.success());
    let err = stderr(&out);
    assert!(
        err.contains("line 2: dir is not finite after normalising"),
        "{err}"
    );
    assert!(!err.contains("must not be zero"), "{err}");
}

#[test]
fn figure_shape_and_profile_documents_refuse_unknown_members() {
    let err = FigureDocument::from_json(
        r##"{"format": "nendo-figure", "version": 1,
            "metacircles": [{"centre": [0, 0], "radius": 1, "density": 1, "color": "#ffffff"}]}"##,
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.starts_with("metacircles[0].color: unknown field \"color\""),
        "{err}"
    );
    assert!(err.contains("line 2 column"), "{err}");
    let err = ShapeDocument::from_json(
        r#"{"format": "nendo-shape", "version": 1,
            "sections": [{"z": 0, "contour": [[0, 0], [2, 0], [2, 2]], "curve": []}]}"#,
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.starts_with("sections[0].curve: unknown field \"curve\""),
        "{err}"
    );
    // A move that is both a grab and a replacement used to drop the grab silently.
    let err = ShapeDocument::from_json(
        r#"{"format": "nendo-shape", "version": 1,
            "sections": [{"z": 0, "contour": [[0, 0], [2, 0], [2, 2]],
                          "curves": [{"bezier": [[0, 0], [1, 0]]}],
                          "moves": [{"curve": 0, "from": [0, 0], "to": [1, 1],
                                     "deformed": {"bezier": [[0, 0], [1, 1]]}}]}]}"#,
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("section 0 move 0 is either a grab"), "{err}");
    let shipped = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("devices/profiles/mouse.json"),
    )
    .expect("a shipped profile");
    nendo_devices::Profile::from_json(&shipped, "mouse").expect("shipped profiles still read");
    let mut v: Value = serde_json::from_str(&shipped).expect("JSON");
    v["watchdog"] = json!(10);
    let err = nendo_devices::Profile::from_json(&v.to_string(), "mouse")
        .unwrap_err()
        .to_string();
    assert!(err.contains("unknown field \"watchdog\""), "{err}");
    let text = shipped.replacen('{', "{\"name\": \"twice\",", 1);
    let err = nendo_devices::Profile::from_json(&text, "mouse")
        .unwrap_err()
        .to_string();
    assert!(err.contains("duplicate field \"name\""), "{err}");
}
