//! `nendo closest --batch`: the JSON Lines contract, answered by the real binary.

use serde_json::Value;
use std::io::Write;
use std::process::{Command, Stdio};

fn run(input: &str) -> (Vec<Value>, i32) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_nendo"))
        .args(["closest", "--batch"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the nendo binary runs");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(input.as_bytes())
        .expect("write requests");
    let out = child.wait_with_output().expect("nendo exits");
    let lines = String::from_utf8(out.stdout)
        .expect("UTF-8 output")
        .lines()
        .map(|l| serde_json::from_str(l).expect("every output line is JSON"))
        .collect();
    (lines, out.status.code().unwrap_or(-1))
}

#[test]
fn answers_every_op_in_order() {
    let input = r#"{"op":"closest","curve":{"bezier":[[0,0],[1,2],[2,0]]},"point":[1,3]}
{"op":"closest","curve":{"bezier":[[0,0],[1,2],[2,0]]},"point":[1,3],"rmax":1.5}
{"op":"pick","curves":[{"bezier":[[0,0],[1,0]]},{"bezier":[[0,1],[1,1]]},{"bezier":[[0,2],[1,2]]}],"point":[0.5,1.2]}
{"op":"pick","curves":[{"bezier":[[0,0],[1,0]]}],"point":[0.5,9],"rmax":1}
{"op":"sphere","curve":{"bezier":[[-2,0,0],[2,0,0]]},"center":[0,0,0],"radius":1}
{"op":"ray","curve":{"bezier":[[-1,1,0],[0,1,2],[1,1,0]]},"origin":[0,0,5],"dir":[0,0,-1]}
{"op":"closest","curve":{"bspline":{"degree":2,"knots":[0,0,0,1,2,2,2],"points":[[0,0],[1,1],[2,0],[3,1]]}},"point":[1.5,2]}
"#;
    let (out, code) = run(input);
    assert_eq!(code, 0, "{out:?}");
    assert_eq!(out.len(), 7);
    assert!((out[0]["u"].as_f64().expect("u") - 0.5).abs() < 1e-12);
    assert!((out[0]["distance"].as_f64().expect("d") - 2.0).abs() < 1e-12);
    assert_eq!(out[0]["point"].as_array().expect("point").len(), 2);
    assert!(out[1]["u"].is_null());
    assert_eq!(out[2]["index"], 1);
    assert!(out[3]["index"].is_null());
    let iv = out[4]["intervals"].as_array().expect("intervals");
    assert_eq!(iv.len(), 1);
    assert!((iv[0][0].as_f64().expect("a") - 0.25).abs() < 1e-12);
    assert!((out[5]["ray_t"].as_f64().expect("s") - 4.0).abs() < 1e-9);
    assert!((out[5]["distance"].as_f64().expect("d") - 1.0).abs() < 1e-9);
    let u = out[6]["u"].as_f64().expect("B-spline u");
    assert!(
        (0.0..=2.0).contains(&u),
        "u in the B-spline's own domain: {u}"
    );
}

#[test]
fn bad_lines_get_errors_and_later_lines_are_answered() {
    let input = r#"this is not json
{"op":"closest","curve":{"bezier":[]},"point":[0,0]}
{"op":"closest","curve":{"bezier":[[0,0],[1,1,1]]},"point":[0,0]}
{"op":"closest","curve":{"bezier":[[0,0],[1,1]]},"point":[0,0,0]}
{"op":"closest","curve":{"bspline":{"degree":2,"knots":[0,1,0,1,2,2],"points":[[0,0],[1,1],[2,0]]}},"point":[0,0]}
{"op":"closest","curve":{"bezier":[[0,0],[1,1]]},"point":[1e400,0]}
{"op":"closest","curve":{"bezier":[[0,0],[1,1]]},"point":[0,0],"rmax":-1}
{"op":"ray","curve":{"bezier":[[0,0,0],[1,1,1]]},"origin":[0,0,0],"dir":[0,0,0]}
{"op":"fly","curve":{"bezier":[[0,0],[1,1]]}}
{"op":"closest","curve":{"bezier":[[0,0],[2,0]]},"point":[1,1]}
"#;
    let (out, code) = run(input);
    assert_eq!(code, 1, "a failed line makes the exit status non-zero");
    assert_eq!(out.len(), 10);
    for (i, line) in out.iter().enumerate().take(9) {
        let msg = line["error"]
            .as_str()
            .unwrap_or_else(|| panic!("line {i} should be an error: {line}"));
        assert!(!msg.is_empty());
    }
    assert!((out[9]["distance"].as_f64().expect("answered after errors") - 1.0).abs() < 1e-12);
}

#[test]
fn extreme_but_valid_inputs_are_answered_or_refused_never_null() {
    let input = r#"{"op":"closest","curve":{"bezier":[[0,0],[1,2],[2,0]]},"point":[1e300,1e300]}
{"op":"ray","curve":{"bezier":[[-1,0,0],[1,0,0]]},"origin":[0,-3,0],"dir":[0,1e-300,0]}
{"op":"closest","curve":{"bezier":[[1e308,0],[1e308,1]]},"point":[-1e308,0]}
{"op":"closest","curve":{"bezier":[[0,0],[2,0]]},"point":[1,1],"rmax":1}
"#;
    let (out, code) = run(input);
    assert_eq!(out.len(), 4);
    let d = out[0]["distance"].as_f64().expect("a finite distance");
    assert!((d / 1.414_213_562_373_095e300 - 1.0).abs() < 1e-3, "{d}");
    assert!(
        out[1]["distance"].as_f64().expect("finite") < 1e-12,
        "{}",
        out[1]
    );
    assert!((out[1]["ray_t"].as_f64().expect("finite") - 3e300).abs() < 1e291);
    assert!(out[2]["error"].is_string(), "2e308 overflows: {}", out[2]);
    assert_eq!(
        out[3]["u"].as_f64(),
        Some(0.5),
        "R is inclusive: {}",
        out[3]
    );
    assert_eq!(code, 1, "one line failed");
}

#[test]
fn a_curve_is_one_kind() {
    let input = r#"{"op":"closest","curve":{"bezier":[[0,0],[1,0]],"bspline":{"degree":1,"knots":[0,0,1,1],"points":[[0,0],[1,0]]}},"point":[0,1]}
"#;
    let (out, code) = run(input);
    assert!(
        out[0]["error"]
            .as_str()
            .is_some_and(|e| e.contains("not both")),
        "{}",
        out[0]
    );
    assert_eq!(code, 1);
}

#[test]
fn coordinates_too_large_for_the_arithmetic_are_refused_not_a_panic() {
    let input = r#"{"op":"closest","curve":{"bspline":{"degree":2,"knots":[0,0,0,0.5,1,1,1],"points":[[1e308,0],[-1e308,0],[1e308,1],[0,0]]}},"point":[0,1]}
{"op":"closest","curve":{"bezier":[[1e308,0],[-1e308,0]]},"point":[0,1]}
{"op":"closest","curve":{"bezier":[[8e307,0],[-8e307,0],[8e307,1]]},"point":[0,1]}
"#;
    let (out, code) = run(input);
    assert_eq!(out.len(), 3, "every line answered");
    for o in &out[..2] {
        assert!(
            o["error"].as_str().is_some_and(|e| e.contains("too large")),
            "{o}"
        );
    }
    assert_eq!(out[2]["u"].as_f64(), Some(0.5), "{}", out[2]);
    assert_eq!(code, 1);
}
