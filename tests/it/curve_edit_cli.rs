//! `nendo curve --batch` end to end: every op through the binary, answers checked against the
//! library's geometry, per-line errors and the exit status. The requests of
//! `tests/data/curves/batch.jsonl` are the documented examples.

use glam::{DVec2, DVec3};
use nendo::curve::json::{DynCurve, curve_from_json};
use nendo::curve::{Curve, Point};
use serde_json::{Value, json};
use std::io::Write;
use std::process::{Command, Stdio};

fn run(input: &str) -> (Vec<Value>, i32) {
    let out = crate::support::run_with_input(&["curve", "--batch"], input);
    let text = String::from_utf8(out.stdout).expect("utf-8");
    let lines = text
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON answer"))
        .collect();
    (lines, out.status.code().unwrap_or(-1))
}

fn curve2(v: &Value) -> Curve<DVec2> {
    match curve_from_json(v).expect("curve") {
        DynCurve::D2(c) => c,
        DynCurve::D3(_) => panic!("expected 2D"),
    }
}

fn curve3(v: &Value) -> Curve<DVec3> {
    match curve_from_json(v).expect("curve") {
        DynCurve::D3(c) => c,
        DynCurve::D2(_) => panic!("expected 3D"),
    }
}

fn pt<P: Point>(v: &Value) -> P {
    let c: Vec<f64> = v
        .as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect();
    P::from_coords(&c).expect("point")
}

#[test]
fn edits_through_the_binary() {
    let cubic = json!({"bezier": [[0, 0, 0], [1, 2, 0], [3, 2, 1], [4, 0, 0]]});
    let spline = json!({"bspline": {"degree": 2, "knots": [0, 0, 0, 0.5, 1, 1, 1], "points": [[0, 0], [1, 1], [2, -1], [3, 0]]}});
    let requests = [
        json!({"op": "grab", "curve": cubic, "from": [2, 1.6, 0.5], "to": [2.2, 2.4, 0.1]}),
        json!({"op": "grab", "curve": spline, "from": [1.5, 0.2], "to": [1.5, 1.0], "method": "least_change", "keep_ends": true}),
        json!({"op": "grab", "curve": spline, "from": [9, 9], "to": [0, 0], "rmax": 1}),
        json!({"op": "split", "curve": spline, "u": 0.3}),
        json!({"op": "insert", "curve": cubic, "u": 0.4}),
        json!({"op": "tangent", "left": {"bezier": [[0, 0], [1, 1], [2, 1]]}, "right": {"bezier": [[2, 1], [3, 1], [4, 0]]},
               "side": "left", "to": [1, 0], "follow": "ratio"}),
    ];
    let input: String = requests.iter().map(|r| format!("{r}\n")).collect();
    let (out, code) = run(&input);
    assert_eq!(code, 0, "{out:?}");
    assert_eq!(out.len(), requests.len());

    // Grab: C'(u) = C(u) + (T − P).
    let c = curve3(&cubic);
    let moved = curve3(&out[0]["curve"]);
    let u = out[0]["u"].as_f64().expect("u");
    let want = c.eval(u) + (DVec3::new(2.2, 2.4, 0.1) - DVec3::new(2.0, 1.6, 0.5));
    assert!((moved.eval(u) - want).length() < 1e-12);
    let s = curve2(&spline);
    let moved = curve2(&out[1]["curve"]);
    let u = out[1]["u"].as_f64().expect("u");
    assert!((moved.eval(u) - s.eval(u) - DVec2::new(0.0, 0.8)).length() < 1e-12);
    assert_eq!(moved.points()[0], s.points()[0]);
    assert_eq!(moved.points()[3], s.points()[3]);
    assert!(out[2]["curve"].is_null() && out[2]["u"].is_null());
    // Split.
    let halves = out[3]["curves"].as_array().expect("two");
    let (l, r) = (curve2(&halves[0]), curve2(&halves[1]));
    assert!(
        (l.eval(0.3) - s.eval(0.3)).length() < 1e-12
            && (r.eval(0.3) - s.eval(0.3)).length() < 1e-12
    );
    // Insert.
    let grown = curve3(&out[4]["curve"]);
    assert_eq!(grown.points().len(), 5);
    assert!((grown.eval(0.7) - c.eval(0.7)).length() < 1e-12);
    assert!(out[4]["index"].as_u64().is_some());
    // Tangent: Q_L, Q, Q_R collinear.
    let pair = out[5]["curves"].as_array().expect("two");
    let (l, r) = (curve2(&pair[0]), curve2(&pair[1]));
    let (ql, q, qr) = (l.points()[1], l.points()[2], r.points()[1]);
    assert_eq!(ql, DVec2::new(1.0, 0.0));
    assert!((q - ql).perp_dot(qr - q).abs() < 1e-12);
}

#[test]
fn refinement_warp_and_svg_through_the_binary() {
    let arch = json!({"bezier": [[0, 0], [0.5, 1], [2, 1.2], [3, 0]]});
    let requests = [
        // A quarter turn of the end about the start: the similar copy.
        json!({"op": "refine", "curve": arch, "mode": "curvature",
               "constraints": [{"u": 0, "point": [0, 0]}, {"u": 1, "point": [0, 3]}]}),
        // A piecewise curve with a C1 join asked for, and a tangent.
        json!({"op": "refine", "mode": "variation",
               "curves": [{"bezier": [[0, 0], [0.3, 0.5], [0.7, 0.6], [1, 0]]}, {"bezier": [[1, 0], [1.4, 0.5], [1.7, -0.4], [2, 0.1]]}],
               "constraints": [{"u": 0, "point": [0, 0]}, {"u": 2, "point": [2, 0.1]}, {"join": 0, "order": 1},
                               {"u": 0, "tangent": [1, 1]}, {"u": 1.5, "derivative": [1, 0]}]}),
        json!({"op": "warp", "pairs": [[{"bezier": [[0, 0], [2, 0]]}, {"bezier": [[0, 1], [2, 1]]}]], "points": [[1, -1], [0.5, 3]]}),
        json!({"op": "svg_write", "curves": [arch]}),
    ];
    let input: String = requests.iter().map(|r| format!("{r}\n")).collect();
    let (out, code) = run(&input);
    assert_eq!(code, 0, "{out:?}");
    let copy = curve2(&out[0]["curve"]);
    let turned = [
        DVec2::ZERO,
        DVec2::new(-1.0, 0.5),
        DVec2::new(-1.2, 2.0),
        DVec2::new(0.0, 3.0),
    ];
    for (a, b) in copy.points().iter().zip(turned) {
        assert!((*a - b).length() < 1e-9);
    }
    assert!(out[0]["similarity"].as_f64().expect("number") < 1e-9);
    let segs = out[1]["curves"].as_array().expect("segments");
    let (a, b) = (curve2(&segs[0]), curve2(&segs[1]));
    let (Curve::Bezier(a), Curve::Bezier(b)) = (a, b) else {
        panic!("Bezier segments")
    };
    assert!((a.eval_derivative(1.0, 1) - b.eval_derivative(0.0, 1)).length() < 1e-9);
    assert!((b.eval_derivative(0.5, 1) - DVec2::X).length() < 1e-9);
    assert!(a.eval_derivative(0.0, 1).perp_dot(DVec2::ONE).abs() < 1e-9);
    assert!(out[1]["residual"].as_f64().expect("number") < 1e-9);
    let warped: Vec<DVec2> = out[2]["points"]
        .as_array()
        .expect("points")
        .iter()
        .map(pt)
        .collect();
    assert!((warped[0] - DVec2::new(1.0, 0.0)).length() < 1e-12);
    assert!((warped[1] - DVec2::new(0.5, 4.0)).length() < 1e-12);
    // The written SVG reads back through svg_read.
    let svg = out[3]["svg"].as_str().expect("text");
    let (back, code) = run(&format!("{}\n", json!({"op": "svg_read", "svg": svg})));
    assert_eq!(code, 0);
    let read = curve2(&back[0]["paths"][0]["curves"][0]);
    assert_eq!(read, curve2(&arch));
}

#[test]
fn the_documented_batch_file_answers_every_line() {
    let input = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/curves/batch.jsonl"
    ))
    .expect("data file");
    let (out, code) = run(&input);
    assert_eq!(code, 0, "{out:?}");
    assert_eq!(
        out.len(),
        input.lines().filter(|l| !l.trim().is_empty()).count()
    );
    assert!(out.iter().all(|v| v.get("error").is_none()));
}

#[test]
fn bad_lines_get_errors_and_the_rest_is_answered() {
    let lines = [
        "not json".to_string(),
        json!({"op": "split", "curve": {"bezier": [[0, 0], [1, 1]]}, "u": 1.0}).to_string(),
        json!({"op": "refine", "curve": {"bezier": [[0, 0, 0], [1, 1, 0], [2, 0, 0]]}, "mode": "curvature"}).to_string(),
        json!({"op": "refine", "curve": {"bezier": [[0, 0], [1, 1], [2, 0]]}, "mode": "variation"}).to_string(),
        json!({"op": "refine", "curve": {"bezier": [[0, 0], [1, 1], [2, 0]]}, "mode": "curvature", "constraints": [{"u": 0.5}]}).to_string(),
        json!({"op": "grab", "curve": {"bezier": [[0, 0], [1, 1]]}, "from": [0, 0, 0], "to": [1, 1]}).to_string(),
        json!({"op": "svg_read", "svg": "<path d='M 0 0 A 1 1 0 0 1 2 2'/>"}).to_string(),
        json!({"op": "warp", "pairs": [[{"bezier": [[0, 0], [1, 0]]}, {"bezier": [[0, 0, 0], [1, 0, 0]]}]], "points": [[0, 1]]}).to_string(),
        json!({"op": "split", "curve": {"bezier": [[0, 0], [1, 1], [2, 0]]}, "u": 0.5}).to_string(),
    ];
    let (out, code) = run(&(lines.join("\n") + "\n"));
    assert_eq!(code, 1);
    assert_eq!(out.len(), lines.len());
    for (i, v) in out.iter().enumerate().take(lines.len() - 1) {
        let msg = v["error"]
            .as_str()
            .unwrap_or_else(|| panic!("line {i} should fail: {v}"));
        assert!(!msg.is_empty());
    }
    assert!(out[2]["error"].as_str().expect("msg").contains("2D"));
    assert!(out[lines.len() - 1].get("curves").is_some());
    // Extreme numbers in the messages are compact (before: 309 digits, or `0.000…01`).
    let extreme = [
        json!({"op": "refine", "curve": {"bezier": [[0, 0], [1, 1], [2, 0]]}, "mode": "curvature", "constraints": [{"u": 1e308, "point": [0, 0]}]}),
        json!({"op": "tangent", "left": {"bezier": [[0, 0], [1, 1], [2, 1]]}, "right": {"bezier": [[1e30, 1], [3, 1], [4, 0]]}, "side": "right", "to": [3, 1.5]}),
        json!({"op": "grab", "curve": {"bezier": [[0, 0, 0], [1e30, 2, 0], [3, 2, 1], [4, 0, 0]]}, "from": [2, 1.6, 0.5], "to": [2, 2, 1], "method": "nearest", "keep_ends": true}),
    ];
    let text: Vec<String> = extreme.iter().map(Value::to_string).collect();
    let (out, code) = run(&(text.join("\n") + "\n"));
    assert_eq!(code, 1);
    for (v, want) in out.iter().zip([
        "parameter 1e308 is outside",
        "1.000000e30 from the right curve's first",
        "e-31 while the end points are kept",
    ]) {
        let msg = v["error"].as_str().expect("an error");
        assert!(msg.contains(want) && msg.len() < 200, "{msg}");
    }
}

#[test]
fn overflowing_curves_and_mistyped_members_are_refused() {
    let huge = json!({"bezier": [[1e308, 0], [-1e308, 1]]});
    let cubic = json!({"bezier": [[0, 0], [1, 1], [2, 1], [3, 0]]});
    let lines = [
        json!({"op": "split", "curve": huge, "u": 0.5}),
        json!({"op": "grab", "curve": huge, "from": [0, 0], "to": [1, 1]}),
        json!({"op": "grab", "curve": cubic, "from": [1.5, 0], "to": [1.5, 1], "method": 3}),
        json!({"op": "grab", "curve": cubic, "from": [1.5, 0], "to": [1.5, 1], "method": ["largest"]}),
        json!({"op": "tangent", "left": {"bezier": [[0, 0], [1, 1], [2, 0]]},
               "right": {"bezier": [[2, 0], [3, -1], [4, 0]]}, "side": "left", "to": [1, 2], "follow": 7}),
        json!({"op": "tangent", "left": {"bezier": [[0, 0], [1, 1], [2, 0]]},
               "right": {"bezier": [[2, 0], [3, -1], [4, 0]]}, "side": "left", "to": [1, 2], "follow": true}),
        json!({"op": "insert", "curve": {"bspline": {"degree": 2.5, "knots": [0, 0, 0, 1, 1, 1],
               "points": [[0, 0], [1, 1], [2, 0]]}}, "u": 0.5}),
    ];
    let input: String = lines.iter().map(|l| l.to_string() + "\n").collect();
    let (out, code) = run(&input);
    assert_eq!(code, 1);
    assert_eq!(out.len(), lines.len());
    for (i, v) in out.iter().enumerate() {
        let msg = v["error"]
            .as_str()
            .unwrap_or_else(|| panic!("line {i} should fail: {v}"));
        assert!(!msg.is_empty());
    }
    // Refused when read: coordinates this large overflow the curve's arithmetic.
    assert!(out[0]["error"].as_str().expect("msg").contains("too large"));
    assert!(out[1]["error"].as_str().expect("msg").contains("too large"));
    assert!(
        out[2]["error"]
            .as_str()
            .expect("msg")
            .contains("\"method\" must be a string")
    );
    assert!(
        out[4]["error"]
            .as_str()
            .expect("msg")
            .contains("\"follow\" must be a string")
    );
}

#[test]
fn whole_float_degrees_are_read_and_an_unconstrained_refine_reports_a_zero_residual() {
    let lines = [
        json!({"op": "insert", "curve": {"bspline": {"degree": 3.0, "knots": [0, 0, 0, 0, 1, 1, 1, 1],
               "points": [[0, 0], [1, 1], [2, 1], [3, 0]]}}, "u": 0.5}),
        json!({"op": "refine", "curve": {"bezier": [[0, 0], [1, 1], [2, 1], [3, 0]]},
               "mode": "curvature", "constraints": []}),
        json!({"op": "refine", "curve": {"bezier": [[0, 0], [0.5, 1], [2, 1.2], [3, 0]]}, "mode": "variation"}),
        json!({"op": "grab", "curve": {"bezier": [[0, 0], [1, 1], [2, 1], [3, 0]]},
               "from": [1.5, 0], "to": [1.5, 1], "method": null, "keep_ends": null}),
    ];
    let input: String = lines.iter().map(|l| l.to_string() + "\n").collect();
    let mut child = Command::new(env!("CARGO_BIN_EXE_nendo"))
        .args(["curve", "--batch"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("nendo runs");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(input.as_bytes())
        .expect("write");
    let raw = child.wait_with_output().expect("finishes");
    let text = String::from_utf8(raw.stdout).expect("utf-8");
    assert!(!text.contains("-0.0"), "{text}");
    let out: Vec<Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON"))
        .collect();
    assert_eq!(raw.status.code(), Some(0), "{text}");
    assert!(out[0]["index"].as_u64().is_some(), "{}", out[0]);
    for v in &out[1..3] {
        assert_eq!(v["residual"].as_f64(), Some(0.0), "{v}");
        assert!(v["residual"].as_f64().is_some_and(|r| r.is_sign_positive()));
    }
    assert!(out[3].get("curve").is_some_and(|c| !c.is_null()));
}

#[test]
fn a_refinement_too_large_to_solve_densely_is_refused() {
    let n = 400;
    let points: Vec<[f64; 2]> = (0..n).map(|i| [i as f64, ((i * 7) % 5) as f64]).collect();
    let mut knots = vec![0.0; 4];
    knots.extend((1..n - 3).map(|i| i as f64));
    knots.extend([(n - 3) as f64; 4]);
    let line = json!({"op": "refine", "mode": "curvature",
        "curve": {"bspline": {"degree": 3, "knots": knots, "points": points}},
        "constraints": [{"u": 0.0, "point": [0, 0]}, {"u": (n - 3) as f64, "point": [1, 1]}]});
    let (out, code) = run(&(line.to_string() + "\n"));
    assert_eq!(code, 1);
    assert!(
        out[0]["error"]
            .as_str()
            .is_some_and(|e| e.contains("too many")),
        "{}",
        out[0]
    );
}
