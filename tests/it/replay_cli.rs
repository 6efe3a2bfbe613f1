//! `nendo replay` end to end: byte-identical output for the same trace, progress on long
//! traces, the same result as the library loop, clear errors that write nothing.

use crate::support::{run as nendo, temp_dir};
use nendo::hand::{Hand, HandOptions, HandSession};
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
        HandSession::new(grid, Regulation::default(), hand, HandOptions::default()).unwrap();
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
    let no_scene = dir.join("no-scene.trace");
    std::fs::write(&no_scene, with_scene(&text, "none")).unwrap();
    // A trace cut short (no `end` line) is an interrupted recording: it replays its complete
    // frames, saying how many.
    let frames = text.lines().take(40).skip_while(|l| *l != "frames").count() - 1;
    let o = nendo(&[
        "replay",
        s(&truncated),
        "--primitive",
        "sphere",
        "--out",
        s(&out),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains(&format!(
            "an interrupted recording (no `end` line): recovered its {frames} complete frames"
        )) && err.contains(&format!(
            "{frames} frames recovered from an interrupted recording"
        )),
        "{err}"
    );
    std::fs::remove_file(&out).unwrap();
    for (args, says) in [
        (
            vec![
                "replay",
                s(&broken),
                "--primitive",
                "sphere",
                "--out",
                s(&out),
            ],
            "line 8",
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
            vec!["replay", s(&no_scene), "--out", s(&out)],
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
/// surface for a shipped trace. The headless editor serves it, with or without `gui`.
#[test]
fn the_windows_hand_loop_and_nendo_replay_give_the_same_surface() {
    use nendo::editor::document::Document;
    use nendo::editor::hand_input::HandDriver;
    use nendo::hand::DEFAULT_FINGER_RADIUS;

    let dir = temp_dir("window-vs-replay");
    let out = dir.join("replayed.json");
    let path = shipped("plane-groove");
    let o = nendo(&["replay", &path, "--primitive", "plane", "--out", s(&out)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let replayed = Model::read(&out).unwrap().model;

    let trace = Trace::read(Path::new(&path)).unwrap();
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let mut doc = Document::new(Model::new(plane.clone()));
    // The finger the trace's scene names, as the window's replay takes it.
    let mut driver = HandDriver::new(
        trace.header.hand,
        trace.header.world_from_tracker,
        nendo::editor::live::trace_finger(&trace.header),
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

// ---------------------------------------------------------------------------------------------
// Self-contained traces (issue 17): the header's scene.

/// Runs `nendo replay` and returns the bytes written, asserting success.
fn replay_bytes(args: &[&str], out: &Path) -> Vec<u8> {
    let mut all = vec!["replay"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--out", s(out)]);
    let o = nendo(&all);
    assert!(
        o.status.success(),
        "{all:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    std::fs::read(out).unwrap()
}

/// Runs `nendo replay` expecting a failure that says `says` and writes nothing.
fn replay_fails(args: &[&str], out: &Path, says: &str) {
    let mut all = vec!["replay"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--out", s(out)]);
    let o = nendo(&all);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{all:?}: {err}");
    assert!(err.contains(says), "{all:?}: {err}");
    assert!(!out.exists(), "{all:?} wrote a file");
}

/// The trace's text with its scene line replaced.
fn with_scene(text: &str, scene: &str) -> String {
    text.lines()
        .map(|l| {
            if l.starts_with("scene ") {
                format!("scene {scene}\n")
            } else {
                format!("{l}\n")
            }
        })
        .collect()
}

fn scene_line(text: &str) -> &str {
    text.lines()
        .find_map(|l| l.strip_prefix("scene "))
        .expect("a scene line")
}

#[test]
fn every_shipped_trace_replays_by_itself_as_with_the_arguments_it_names() {
    use nendo::hand::scene::Scene;
    let dir = temp_dir("self-contained");
    // What each shipped trace was replayed with before it carried its scene (README, "start
    // from"): the same bytes without them.
    let before: &[(&str, &[&str])] = &[
        ("sphere-push-pull", &["--primitive", "sphere"]),
        ("plane-groove", &["--primitive", "plane"]),
        ("tube-pot", &["--primitive", "tube"]),
        ("mouse-sphere", &["--primitive", "sphere"]),
    ];
    let traces = Path::new(env!("CARGO_MANIFEST_DIR")).join("devices/traces");
    let mut names: Vec<String> = std::fs::read_dir(&traces)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "trace"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    for (name, _) in before {
        assert!(names.iter().any(|n| n == name), "{name} is shipped");
    }
    for name in &names {
        let path = shipped(name);
        let t = Trace::read(Path::new(&path)).unwrap();
        let scene = Scene::of_trace(&t.header)
            .unwrap()
            .unwrap_or_else(|| panic!("{name} names its scene"));
        let named = scene
            .arguments()
            .unwrap_or_else(|| panic!("{name}: a scene the command line can name"));
        let alone = replay_bytes(&[&path], &dir.join(format!("{name}-alone.json")));
        let mut explicit: Vec<&str> = vec![&path];
        explicit.extend(named.iter().map(String::as_str));
        let given = replay_bytes(&explicit, &dir.join(format!("{name}-given.json")));
        assert!(alone == given, "{name}: {named:?}");
        if let Some((_, old)) = before.iter().find(|(n, _)| n == name) {
            let mut args: Vec<&str> = vec![&path];
            args.extend_from_slice(old);
            let old = replay_bytes(&args, &dir.join(format!("{name}-old.json")));
            assert!(alone == old, "{name}: {named:?}");
        }
    }
    // The names the header gives, written out.
    let t = Trace::read(Path::new(&shipped("tube-pot"))).unwrap();
    assert_eq!(
        Scene::of_trace(&t.header)
            .unwrap()
            .unwrap()
            .arguments()
            .unwrap()
            .join(" "),
        "--primitive tube --patches 16x8 --radius 2 --height 4 --regulation exact --finger index --finger-radius 1"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A profile replaying `trace` 40 times faster than recorded.
fn replay_profile(dir: &Path, trace: &str) -> std::path::PathBuf {
    let profile = dir.join("replay-profile.json");
    let json = serde_json::json!({
        "format": "nendo-device-profile",
        "version": 1,
        "name": "replay-for-test",
        "input": {"replay": {"trace": trace, "speed": 40.0}},
    });
    std::fs::write(&profile, json.to_string()).unwrap();
    profile
}

fn record(args: &[&str]) {
    let mut all = vec!["record", "--seconds", "30"];
    all.extend_from_slice(args);
    let o = nendo(&all);
    assert!(
        o.status.success(),
        "{all:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn a_trace_recorded_against_a_model_replays_to_the_same_surface() {
    use nendo::hand::scene::{Scene, Start};
    let dir = temp_dir("recorded-on-a-model");
    // The start model: the sphere after the mouse trace — no primitive.
    let start = dir.join("start.json");
    replay_bytes(&[&shipped("mouse-sphere")], &start);
    let start_model = Model::read(&start).unwrap().model;
    let profile = replay_profile(&dir, &shipped("sphere-push-pull"));
    // Embedded (the default) and by reference.
    let embedded = dir.join("embedded.trace");
    record(&[
        "--profile",
        s(&profile),
        "--model",
        s(&start),
        "--finger",
        "index",
        "--finger-radius",
        "0.8",
        "--out",
        s(&embedded),
    ]);
    let referenced = dir.join("referenced.trace");
    record(&[
        "--profile",
        s(&profile),
        "--model",
        s(&start),
        "--reference",
        "--finger",
        "index",
        "--finger-radius",
        "0.8",
        "--out",
        s(&referenced),
    ]);
    let t = Trace::read(&embedded).unwrap();
    let scene = Scene::of_trace(&t.header).unwrap().unwrap();
    assert_eq!(scene.start, Start::Model(Box::new(start_model.clone())));
    assert_eq!(scene.finger_radius, Some(0.8));
    let r = Trace::read(&referenced).unwrap();
    let Some(Start::ModelFile { path, sha256 }) =
        Scene::of_trace(&r.header).unwrap().map(|s| s.start)
    else {
        panic!("a model named by reference")
    };
    assert_eq!(path, Path::new("start.json"), "relative to the trace");
    assert_eq!(sha256.len(), 64);
    // The frames are the source trace's.
    let source = Trace::read(Path::new(&shipped("sphere-push-pull"))).unwrap();
    assert_eq!(t.frames, source.frames);

    let want = replay_bytes(
        &[
            &shipped("sphere-push-pull"),
            "--model",
            s(&start),
            "--finger-radius",
            "0.8",
        ],
        &dir.join("want.json"),
    );
    assert_ne!(
        Model::from_json_str(std::str::from_utf8(&want).unwrap())
            .unwrap()
            .model,
        start_model,
        "the trace moves the surface"
    );
    assert!(replay_bytes(&[s(&embedded)], &dir.join("embedded.json")) == want);
    // Replayed from elsewhere: the reference is found beside the trace.
    let o = crate::support::nendo()
        .current_dir(std::env::temp_dir())
        .args([
            "replay",
            s(&referenced),
            "--out",
            s(&dir.join("referenced.json")),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(std::fs::read(dir.join("referenced.json")).unwrap() == want);

    // A changed model file is refused, naming both hashes; nothing is written.
    let changed = Model::new(
        Primitive::Sphere
            .build(&PrimitiveParams::default())
            .unwrap(),
    );
    changed.write(&start).unwrap();
    let now = nendo::hand::scene::sha256_hex(&std::fs::read(&start).unwrap());
    let out = dir.join("stale.json");
    replay_fails(&[s(&referenced)], &out, &sha256);
    replay_fails(&[s(&referenced)], &out, &now);
    // The embedded model does not depend on the file.
    assert!(replay_bytes(&[s(&embedded)], &dir.join("embedded-again.json")) == want);
    // Without --primitive or --model the recording says it has no scene, and replay asks.
    let bare = dir.join("bare.trace");
    let plain = dir.join("plain-profile");
    std::fs::create_dir_all(&plain).unwrap();
    let v1 = dir.join("v1.trace");
    std::fs::write(
        &v1,
        std::fs::read_to_string(shipped("plane-groove"))
            .unwrap()
            .replacen("nendo-hand-trace 2", "nendo-hand-trace 1", 1)
            .lines()
            .filter(|l| !l.starts_with("scene "))
            .map(|l| format!("{l}\n"))
            .collect::<String>(),
    )
    .unwrap();
    record(&[
        "--profile",
        s(&replay_profile(&plain, s(&v1))),
        "--out",
        s(&bare),
    ]);
    assert!(
        std::fs::read_to_string(&bare)
            .unwrap()
            .contains("\nscene none\n")
    );
    replay_fails(
        &[s(&bare)],
        &dir.join("bare.json"),
        "give --primitive or --model",
    );
    // Settings without a start surface are refused.
    let o = nendo(&[
        "record",
        "--profile",
        s(&profile),
        "--finger-radius",
        "2",
        "--out",
        s(&bare),
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("give --primitive or --model"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_old_version_trace_still_reads() {
    let dir = temp_dir("version-1");
    let text = std::fs::read_to_string(shipped("sphere-push-pull")).unwrap();
    assert!(text.starts_with("nendo-hand-trace 2\n"));
    let old: String = text
        .replacen("nendo-hand-trace 2", "nendo-hand-trace 1", 1)
        .lines()
        .filter(|l| !l.starts_with("scene "))
        .map(|l| format!("{l}\n"))
        .collect();
    let v1 = dir.join("v1.trace");
    std::fs::write(&v1, &old).unwrap();
    let t = Trace::read(&v1).unwrap();
    assert_eq!(t.header.scene, None);
    assert_eq!(
        t.frames,
        Trace::read(Path::new(&shipped("sphere-push-pull")))
            .unwrap()
            .frames
    );
    let from_old = replay_bytes(
        &[s(&v1), "--primitive", "sphere", "--finger", "index"],
        &dir.join("old.json"),
    );
    let from_new = replay_bytes(&[&shipped("sphere-push-pull")], &dir.join("new.json"));
    assert!(from_old == from_new);
    replay_fails(
        &[s(&v1)],
        &dir.join("none.json"),
        "give --primitive or --model",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_bad_scene_is_a_clear_error() {
    let dir = temp_dir("bad-scene");
    let text = std::fs::read_to_string(shipped("plane-groove")).unwrap();
    let scene = scene_line(&text).to_string();
    let line = text.lines().position(|l| l.starts_with("scene ")).unwrap() + 1;
    let out = dir.join("out.json");
    for (k, (bad, says)) in [
        (
            scene.replace("\"finger_radius\":1.0", "\"finger_radius\":NaN"),
            format!(
                "trace line {line}: scene: not well-formed JSON: expected value at line 1 column"
            ),
        ),
        (
            scene.replace("\"finger_radius\":1.0", "\"finger_radius\":-1.0"),
            "the trace's scene: finger_radius: -1 is not a positive number".to_string(),
        ),
        (
            scene.replace(
                "\"patches\":[10,10]",
                "\"patches\":[10,10],\"radius\":1e999",
            ),
            "primitive.radius: a number is out of range".to_string(),
        ),
        (
            scene.replace("\"name\":\"plane\"", "\"name\":\"cube\""),
            "unknown primitive \"cube\"".to_string(),
        ),
        (
            scene.replace("\"patches\":[10,10]", "\"patches\":[0,10]"),
            "primitive plane".to_string(),
        ),
        (
            scene.replace("\"finger\":\"index\"", "\"finger\":\"toe\""),
            "finger: unknown finger \"toe\"".to_string(),
        ),
        (
            scene.replace("\"regulation\":\"exact\"", "\"regulation\":\"c7\""),
            "c7".to_string(),
        ),
        (
            scene.replace(
                "\"auto_refine\":false",
                "\"auto_refine\":false,\"mirror\":\"q\"",
            ),
            "\"q\"".to_string(),
        ),
        (
            format!(
                "{{\"model_file\":{{\"path\":\"m.json\",\"sha256\":\"{}\"}}}}",
                "0".repeat(63)
            ),
            "not a SHA-256".to_string(),
        ),
        (
            "{\"finger\":\"index\"}".to_string(),
            "exactly one start surface".to_string(),
        ),
    ]
    .into_iter()
    .enumerate()
    {
        assert_ne!(bad, scene, "case {k} changes the scene");
        let path = dir.join(format!("bad-{k}.trace"));
        std::fs::write(&path, with_scene(&text, &bad)).unwrap();
        replay_fails(&[s(&path)], &out, &says);
        // The error names the trace.
        let o = nendo(&["replay", s(&path), "--out", s(&out)]);
        assert!(String::from_utf8_lossy(&o.stderr).contains(&format!("bad-{k}.trace")));
    }
    // A named model file that is not there is named.
    let path = dir.join("missing.trace");
    std::fs::write(
        &path,
        with_scene(
            &text,
            &format!(
                "{{\"model_file\":{{\"path\":\"m.json\",\"sha256\":\"{}\"}}}}",
                "0".repeat(64)
            ),
        ),
    )
    .unwrap();
    replay_fails(&[s(&path)], &out, &dir.join("m.json").display().to_string());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn command_line_options_override_the_header() {
    let dir = temp_dir("override");
    let groove = shipped("plane-groove");
    let run = |args: &[&str], name: &str| replay_bytes(args, &dir.join(name));
    let model = |b: &[u8]| {
        Model::from_json_str(std::str::from_utf8(b).unwrap())
            .unwrap()
            .model
    };
    let base = run(&[&groove], "base.json");
    // Settings: the command line's instead of the header's, the rest from the header.
    let wide = run(&[&groove, "--finger-radius", "1.5"], "wide.json");
    assert!(wide != base);
    assert!(
        wide == run(
            &[&groove, "--primitive", "plane", "--finger-radius", "1.5"],
            "wide-old.json"
        )
    );
    let g1 = run(&[&groove, "--regulation", "g1"], "g1.json");
    assert_eq!(model(&g1).regulation, Regulation::G1);
    let middle = run(&[&groove, "--finger", "middle"], "middle.json");
    assert!(middle != base);
    // The primitive's shape alone changes the header's primitive's parameters.
    let fine = run(&[&groove, "--patches", "20x20"], "fine.json");
    assert_eq!(model(&fine).surface.patch_count(), 400);
    assert!(
        fine == run(
            &[&groove, "--primitive", "plane", "--patches", "20x20"],
            "fine-old.json"
        )
    );
    // Another start surface.
    let other = run(&[&groove, "--primitive", "cylinder"], "cylinder.json");
    assert_eq!(
        model(&other).surface.topology(),
        nendo::surface::Topology::Cylinder
    );

    // Mirror and auto-refine from the header, and switched off from the command line.
    let sphere_trace = shipped("sphere-push-pull");
    let text = std::fs::read_to_string(&sphere_trace).unwrap();
    let scene = scene_line(&text).to_string();
    let mirrored = dir.join("mirrored.trace");
    std::fs::write(
        &mirrored,
        with_scene(
            &text,
            &scene.replace(
                "\"auto_refine\":false",
                "\"mirror\":\"y\",\"auto_refine\":false",
            ),
        ),
    )
    .unwrap();
    let refined = dir.join("refined.trace");
    std::fs::write(
        &refined,
        with_scene(
            &text,
            &scene.replace("\"auto_refine\":false", "\"auto_refine\":true"),
        ),
    )
    .unwrap();
    let plain = run(&[&sphere_trace], "plain.json");
    let m = run(&[s(&mirrored)], "m.json");
    assert!(m != plain);
    assert!(m == run(&[&sphere_trace, "--mirror", "y"], "m-old.json"));
    assert!(plain == run(&[s(&mirrored), "--mirror", "none"], "m-none.json"));
    let r = run(&[s(&refined)], "r.json");
    assert!(r != plain);
    assert!(r == run(&[&sphere_trace, "--auto-refine"], "r-old.json"));
    assert!(plain == run(&[s(&refined), "--no-auto-refine"], "r-off.json"));
    let out = dir.join("clash.json");
    replay_fails(&[s(&mirrored), "--auto-refine"], &out, "--mirror none");
    replay_fails(&[s(&refined), "--mirror", "y"], &out, "--no-auto-refine");
    // A model start refuses a primitive's shape.
    std::fs::remove_dir_all(&dir).unwrap();
}
