//! `nendo replay` end to end: byte-identical output for the same trace, progress on long
//! traces, the same result as the library loop, clear errors that write nothing.

use crate::support::{run as nendo, temp_dir};
use nendo::hand::{Hand, HandOptions, Session};
use nendo::model::Model;
use nendo::surface::{Primitive, PrimitiveParams, Regulation};
use nendo_devices::Trace;
use std::path::Path;

fn shipped(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("devices/traces")
        .join(format!("{name}.trace"))
        .display()
        .to_string()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn replaying_twice_writes_identical_bytes_equal_to_the_library_loop() {
    let dir = temp_dir("twice");
    let (a, b) = (dir.join("a.json"), dir.join("b.json"));
    let trace = shipped("sphere-push-pull");
    for out in [&a, &b] {
        let o = nendo(&["replay", &trace, "--primitive", "sphere", "--out", s(out)]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("2 contacts") && err.contains("1 pushes") && err.contains("1 pulls"),
            "{err}"
        );
    }
    let bytes = std::fs::read(&a).unwrap();
    assert_eq!(bytes, std::fs::read(&b).unwrap());

    // The same as the loop run in this process.
    let t = Trace::read(Path::new(&trace)).unwrap();
    let grid = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .unwrap();
    let hand = Hand::new(t.header.hand, t.header.world_from_tracker).unwrap();
    let mut session =
        Session::new(grid, Regulation::default(), hand, HandOptions::default()).unwrap();
    for f in &t.frames {
        session.feed(f);
    }
    session.finish();
    let model = Model::new(session.into_grid());
    assert_eq!(String::from_utf8(bytes).unwrap(), model.to_json_string());
    assert_eq!(Model::read(&a).unwrap().model, model);
}

#[test]
fn a_long_trace_shows_progress_and_a_model_can_be_the_start() {
    let dir = temp_dir("progress");
    let tube = dir.join("tube.json");
    Model::new(Primitive::Tube.build(&PrimitiveParams::default()).unwrap())
        .write(&tube)
        .unwrap();
    let (from_model, from_primitive) = (dir.join("m.json"), dir.join("p.json"));
    let trace = shipped("tube-pot");
    let o = nendo(&[
        "replay",
        &trace,
        "--model",
        s(&tube),
        "--out",
        s(&from_model),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    for pct in [10, 50, 100] {
        assert!(
            err.contains(&format!("{pct:3}% (")),
            "no {pct}% line in:\n{err}"
        );
    }
    assert_eq!(
        err.lines().filter(|l| l.contains("% (")).count(),
        10,
        "{err}"
    );
    let o = nendo(&[
        "replay",
        &trace,
        "--primitive",
        "tube",
        "--out",
        s(&from_primitive),
    ]);
    assert!(o.status.success());
    assert_eq!(
        std::fs::read(&from_model).unwrap(),
        std::fs::read(&from_primitive).unwrap()
    );
    // A short trace says nothing until the end.
    let o = nendo(&[
        "replay",
        &shipped("mouse-sphere"),
        "--primitive",
        "sphere",
        "--out",
        s(&dir.join("x.json")),
    ]);
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("4 contacts"), "{err}");
}

#[test]
fn options_change_the_result_as_they_say() {
    let dir = temp_dir("options");
    let trace = shipped("plane-groove");
    let run = |extra: &[&str], name: &str| {
        let out = dir.join(name);
        let mut args = vec![
            "replay",
            trace.as_str(),
            "--primitive",
            "plane",
            "--out",
            s(&out),
        ];
        args.extend_from_slice(extra);
        let o = nendo(&args);
        assert!(
            o.status.success(),
            "{extra:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        Model::read(&out).unwrap().model
    };
    let base = run(&[], "base.json");
    let wide = run(&["--finger-radius", "1.5"], "wide.json");
    assert_ne!(base.surface, wide.surface);
    let g1 = run(&["--regulation", "g1"], "g1.json");
    assert_eq!(g1.regulation, Regulation::G1);
    assert_ne!(base.surface, g1.surface);
    // The middle finger of the same hand is elsewhere: a different groove.
    let middle = run(&["--finger", "middle"], "middle.json");
    assert_ne!(base.surface, middle.surface);
    // A profile's hand and transform instead of the trace's (the builtin profile maps the
    // tracker 1:1 into the world, not 20:1): the hand is elsewhere.
    let profile = run(&["--profile", "cyberglove2-18-fastrak"], "profile.json");
    assert_ne!(profile.surface, base.surface);
    // The mouse's view-ray finger on a glove trace: the finger acts only with a button held,
    // and the glove trace's switch is never pressed.
    let ray = run(&["--finger", "ray"], "ray.json");
    assert_eq!(
        ray.surface,
        Primitive::Plane.build(&PrimitiveParams::default()).unwrap()
    );
}

#[test]
fn bad_input_is_reported_and_nothing_is_written() {
    let dir = temp_dir("errors");
    let out = dir.join("out.json");
    let text = std::fs::read_to_string(shipped("sphere-push-pull")).unwrap();
    let cut: String = text.lines().take(40).map(|l| format!("{l}\n")).collect();
    let truncated = dir.join("cut.trace");
    std::fs::write(&truncated, cut).unwrap();
    let broken = dir.join("broken.trace");
    std::fs::write(
        &broken,
        text.replacen(" ok* ok* 0 P ", " ok* ok* 0 P nan ", 3),
    )
    .unwrap();
    for (args, says) in [
        (
            vec![
                "replay",
                s(&truncated),
                "--primitive",
                "sphere",
                "--out",
                s(&out),
            ],
            "truncated",
        ),
        (
            vec![
                "replay",
                s(&broken),
                "--primitive",
                "sphere",
                "--out",
                s(&out),
            ],
            "line 7",
        ),
        (
            vec![
                "replay",
                s(&dir.join("none.trace")),
                "--primitive",
                "sphere",
                "--out",
                s(&out),
            ],
            "none.trace",
        ),
        (
            vec!["replay", &shipped("sphere-push-pull"), "--out", s(&out)],
            "give --primitive or --model",
        ),
        (
            vec![
                "replay",
                &shipped("sphere-push-pull"),
                "--primitive",
                "sphere",
                "--finger-radius",
                "0",
                "--out",
                s(&out),
            ],
            "finger radius",
        ),
        (
            vec![
                "replay",
                &shipped("sphere-push-pull"),
                "--primitive",
                "sphere",
                "--profile",
                "no-such",
                "--out",
                s(&out),
            ],
            "no-such",
        ),
    ] {
        let o = nendo(&args);
        assert!(!o.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(!out.exists(), "{args:?} wrote a file");
    }
}

#[test]
fn a_missing_model_or_trace_is_named_once() {
    let dir = temp_dir("named-once");
    let out = dir.join("out.json");
    let model = dir.join("nonexist.json");
    let o = nendo(&[
        "replay",
        &shipped("sphere-push-pull"),
        "--model",
        s(&model),
        "--out",
        s(&out),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.matches("nonexist.json").count(), 1, "{err}");
    let trace = dir.join("nonexist.trace");
    let o = nendo(&[
        "replay",
        s(&trace),
        "--primitive",
        "sphere",
        "--out",
        s(&out),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.matches("nonexist.trace").count(), 1, "{err}");
    assert!(!out.exists());
    // A syntax error, which does not name the file, is given the path once.
    let broken = dir.join("broken.trace");
    std::fs::write(
        &broken,
        "nendo-hand-trace 1\nframes\n0 ok ok 0 P x\nend 1\n",
    )
    .unwrap();
    let o = nendo(&[
        "replay",
        s(&broken),
        "--primitive",
        "sphere",
        "--out",
        s(&out),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.matches("broken.trace").count(), 1, "{err}");
    assert!(err.contains("line 3"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Issue 16: the window's hand loop (`HandDriver::feed`, what its Devices panel calls per
/// frame, with the window's finger radius) and `nendo replay` with its defaults give the same
/// surface for a shipped trace.
#[cfg(feature = "gui")]
#[test]
fn the_windows_hand_loop_and_nendo_replay_give_the_same_surface() {
    use nendo::app::document::Document;
    use nendo::app::hand_input::HandDriver;
    use nendo::hand::{DEFAULT_FINGER_RADIUS, FingerModel};

    let dir = temp_dir("window-vs-replay");
    let out = dir.join("replayed.json");
    let path = shipped("plane-groove");
    let o = nendo(&["replay", &path, "--primitive", "plane", "--out", s(&out)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let replayed = Model::read(&out).unwrap().model;

    let trace = Trace::read(Path::new(&path)).unwrap();
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let mut doc = Document::new(Model::new(plane.clone()));
    let mut driver = HandDriver::new(
        trace.header.hand,
        trace.header.world_from_tracker,
        FingerModel::for_profile_name(trace.header.profile.as_deref()),
        DEFAULT_FINGER_RADIUS,
    )
    .unwrap();
    for f in &trace.frames {
        driver.feed(&mut doc, f);
    }
    driver.end_contact(&mut doc);
    let window = &doc.model().surface;
    assert_ne!(window, &plane, "the trace deforms the plane");
    assert_eq!(doc.model().regulation, replayed.regulation);
    // The model file keeps every bit of the control points.
    assert_eq!(window.nodes(), replayed.surface.nodes());
    std::fs::remove_dir_all(&dir).unwrap();
}
