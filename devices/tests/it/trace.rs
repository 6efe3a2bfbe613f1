//! The trace format: bit-exact round trips, line-numbered errors, atomic writing.

use glam::{DQuat, DVec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use nendo_devices::profile::Side;
use nendo_devices::skeleton::{HandJoint, JointPose, JointSource, Skeleton};
use nendo_devices::trace::{HeldMarks, TraceWriter, quantize_frame};
use nendo_devices::{
    DeviceError, FrameStatus, HandFrame, Joint, JointAngles, SceneText, SourceState, Timestamp,
    Trace, TraceHeader, TrackerPose,
};

fn random_frames(seed: u64, n: usize, joints: &[Joint]) -> Vec<HandFrame> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let states = [
        SourceState::Absent,
        SourceState::Ok,
        SourceState::Silent,
        SourceState::Disconnected,
    ];
    let mut t = 0;
    (0..n)
        .map(|_| {
            t += rng.gen_range(0..20_000);
            let pose = rng.gen_bool(0.8).then(|| {
                let q = DQuat::from_axis_angle(
                    DVec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), 1.0).normalize(),
                    rng.gen_range(-3.0..3.0),
                );
                let p = DVec3::new(
                    rng.gen_range(-2.0..2.0),
                    rng.gen_range(-2.0..2.0),
                    rng.gen_range(-1e-7..1e-7),
                );
                TrackerPose::new(p, q).unwrap()
            });
            let angles = rng.gen_bool(0.8).then(|| {
                let mut a = JointAngles::new();
                for &j in joints {
                    if rng.gen_bool(0.95) {
                        a.set(j, rng.gen_range(-3.1..3.1)).unwrap();
                    }
                }
                a
            });
            HandFrame {
                time: Timestamp(t),
                pose,
                joints: angles,
                buttons: rng.gen_range(0..8),
                skeleton: None,
                status: FrameStatus {
                    tracker: states[rng.gen_range(0..4)],
                    glove: states[rng.gen_range(0..4)],
                    tracker_fresh: rng.r#gen(),
                    glove_fresh: rng.r#gen(),
                },
            }
        })
        .collect()
}

fn header() -> TraceHeader {
    TraceHeader {
        profile: Some("cyberglove2-18-fastrak".into()),
        joints: vec![
            Joint::IndexMcp,
            Joint::IndexPip,
            Joint::ThumbRoll,
            Joint::WristYaw,
        ],
        ..TraceHeader::default()
    }
}

#[test]
fn traces_round_trip_bit_exactly() {
    let header = header();
    let frames = random_frames(42, 2000, &header.joints);
    let trace = Trace {
        header: header.clone(),
        frames: frames.clone(),
        held: Vec::new(),
    };
    let text = trace.to_text();
    let back = Trace::parse(&text).unwrap();
    // Reading reproduces the frames rounded to the trace's six decimals, bit for bit…
    assert_eq!(back.header, header);
    assert_eq!(back.frames.len(), frames.len());
    for (b, f) in back.frames.iter().zip(&frames) {
        let q = quantize_frame(f, &header.joints);
        assert_eq!(format!("{b:?}"), format!("{q:?}"));
        if let (Some(x), Some(y)) = (b.pose, q.pose) {
            assert_eq!(
                x.position.to_array().map(f64::to_bits),
                y.position.to_array().map(f64::to_bits)
            );
            assert_eq!(
                x.orientation.to_array().map(f64::to_bits),
                y.orientation.to_array().map(f64::to_bits)
            );
        }
    }
    // …and writing a parsed trace reproduces its text exactly.
    assert_eq!(back.to_text(), text);
    assert_eq!(Trace::parse(&back.to_text()).unwrap(), back);
}

#[test]
fn the_documented_example_parses() {
    let text = "nendo-hand-trace 1
# comments may appear anywhere before `frames`
profile cyberglove2-18-fastrak
joints index_mcp index_pip
frames
0 ok* ok 0 P 0.100000 0.200000 -0.050000 1.000000 0.000000 0.000000 0.000000 J 0.250000 0.500000
8333 ok ok* 1 P 0.100000 0.200000 -0.050000 1.000000 0.000000 0.000000 0.000000 J 0.260000 ?
16666 lost ok* 1 P - J 0.270000 0.510000
end 3
";
    let t = Trace::parse(text).unwrap();
    assert_eq!(t.frames.len(), 3);
    assert_eq!(t.frames[1].joints.unwrap().get(Joint::IndexPip), None);
    assert_eq!(t.frames[2].status.tracker, SourceState::Disconnected);
    assert!(t.frames[2].pose.is_none());
    assert!(t.frames[0].status.tracker_fresh && !t.frames[0].status.glove_fresh);
}

fn error_line(text: &str) -> (usize, String) {
    match Trace::parse(text) {
        Err(DeviceError::TraceSyntax { line, message }) => (line, message),
        other => panic!("expected a syntax error, got {other:?}"),
    }
}

#[test]
fn malformed_traces_report_the_line() {
    let good = Trace {
        header: header(),
        frames: random_frames(1, 12, &header().joints),
        held: Vec::new(),
    }
    .to_text();
    let lines: Vec<&str> = good.lines().collect();
    let frames_at = lines.iter().position(|l| *l == "frames").unwrap();
    let with = |i: usize, new: &str| {
        let mut v = lines.clone();
        v[i] = new;
        v.join("\n")
    };
    assert_eq!(error_line("nendo-hand-trace 5\nframes\nend 0\n").0, 1);
    assert!(
        error_line("nendo-hand-trace 0\nframes\nend 0\n")
            .1
            .contains("reads versions 1 to 4")
    );
    assert_eq!(error_line("hello\n").0, 1);
    // The first frame line with a number (values only come with an `ok` source).
    let numbered = (frames_at + 1..lines.len())
        .find(|&i| lines[i].contains('.'))
        .unwrap();
    let bad_number = lines[numbered].replacen(".", ",", 1);
    assert_eq!(error_line(&with(numbered, &bad_number)).0, numbered + 1);
    let nan = "5 ok ok 0 P nan 0.000000 0.000000 1.000000 0.000000 0.000000 0.000000 J -";
    assert_eq!(error_line(&with(frames_at + 1, nan)).0, frames_at + 2);
    let far = "5 ok ok 0 P 500.000000 0.000000 0.000000 1.000000 0.000000 0.000000 0.000000 J -";
    let (line, message) = error_line(&with(frames_at + 1, far));
    assert_eq!(line, frames_at + 2);
    assert!(message.contains("position"), "{message}");
    let short = lines[..lines.len() - 1].join("\n");
    assert!(error_line(&short).1.contains("truncated"));
    assert!(
        error_line(&with(lines.len() - 1, "end 9"))
            .1
            .contains("end says 9")
    );
    assert!(
        error_line(&with(1, "profiles x"))
            .1
            .contains("unknown header keyword")
    );
    assert!(
        error_line(&with(frames_at - 1, "joints index_mcp elbow"))
            .1
            .contains("elbow")
    );
    let backwards = format!(
        "{}\n0 none none 0 P - J -\nend {}",
        lines[..lines.len() - 1].join("\n"),
        13
    );
    assert!(error_line(&backwards).1.contains("backwards"));
}

/// Version 2 carries the scene as opaque one-line JSON, exactly as written; version 1 (no
/// scene line) still reads, with no scene, and writes back as version 2.
#[test]
fn the_scene_is_carried_as_its_text_and_version_1_still_reads() {
    let json = r#"{"primitive":{"name":"sphere","radius":3.0},"x":[1e-7, 0.1, "é\n"]}"#;
    let with_scene = TraceHeader {
        scene: Some(SceneText::new(json).unwrap()),
        ..header()
    };
    let trace = Trace {
        header: with_scene.clone(),
        frames: random_frames(9, 5, &with_scene.joints),
        held: Vec::new(),
    };
    let text = trace.to_text();
    assert!(text.starts_with("nendo-hand-trace 2\n"), "{text}");
    assert!(
        text.contains(&format!("\nscene {json}\nframes\n")),
        "{text}"
    );
    let back = Trace::parse(&text).unwrap();
    assert_eq!(
        back.header.scene.as_ref().map(SceneText::as_str),
        Some(json)
    );
    assert_eq!(back.to_text(), text);
    // No scene: the trace says so.
    let none = Trace {
        header: header(),
        frames: Vec::new(),
        held: Vec::new(),
    }
    .to_text();
    assert!(none.contains("\nscene none\nframes\n"), "{none}");
    assert_eq!(Trace::parse(&none).unwrap().header.scene, None);
    // A version-1 trace reads, without a scene, and writes back as version 2.
    let v1 = "nendo-hand-trace 1\nprofile p\njoints index_mcp\nframes\n0 none ok* 0 P - J 0.250000\nend 1\n";
    let t = Trace::parse(v1).unwrap();
    assert_eq!(t.header.scene, None);
    assert_eq!(t.frames.len(), 1);
    let written = t.to_text();
    assert!(written.starts_with("nendo-hand-trace 2\n"), "{written}");
    assert!(written.contains("\nscene none\nframes\n0 none ok* 0 P - J 0.250000\n"));
    assert_eq!(Trace::parse(&written).unwrap(), t);
    // A version-1 trace cannot carry a scene; a scene that is not a JSON object is refused
    // with its line.
    let (line, message) = error_line("nendo-hand-trace 1\nscene {}\nframes\nend 0\n");
    assert_eq!(line, 2);
    assert!(message.contains("needs trace version 2"), "{message}");
    for (scene, says) in [
        ("{\"radius\": NaN}", "not well-formed JSON"),
        ("{\"radius\": 1", "not well-formed JSON"),
        ("[1, 2]", "a JSON object"),
        ("3", "a JSON object"),
        ("{} {}", "not well-formed JSON"),
    ] {
        let (line, message) = error_line(&format!(
            "nendo-hand-trace 2\njoints\nscene {scene}\nframes\nend 0\n"
        ));
        assert_eq!(line, 3, "{scene}");
        assert!(message.contains(says), "{scene}: {message}");
    }
    assert!(SceneText::new("{\"a\":\n1}").is_err());
    assert_eq!(
        SceneText::new(" {\"a\": 1} ").unwrap().as_str(),
        "{\"a\": 1}"
    );
}

#[test]
fn the_writer_is_atomic() {
    let dir = std::env::temp_dir().join(format!("nendo-trace-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("t.trace");
    let frames = random_frames(3, 10, &header().joints);
    let mut w = TraceWriter::create(&path, header()).unwrap();
    for f in &frames {
        w.push(f).unwrap();
    }
    assert!(!path.exists(), "nothing appears before finish");
    assert_eq!(w.finish().unwrap(), 10);
    let t = Trace::read(&path).unwrap();
    assert_eq!(t.frames.len(), 10);
    // An abandoned writer leaves neither the trace nor its temporary file.
    let other = dir.join("abandoned.trace");
    drop(TraceWriter::create(&other, header()).unwrap());
    assert!(!other.exists());
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_source_that_is_not_ok_carries_no_values() {
    let header = "nendo-hand-trace 1\njoints index_mcp\nframes\n";
    let pose = "P 0.100000 0.200000 -0.050000 1.000000 0.000000 0.000000 0.000000";
    for (tracker, glove, values, says) in [
        ("lost", "ok", format!("{pose} J -"), "tracker is `lost`"),
        ("silent", "ok", format!("{pose} J -"), "tracker is `silent`"),
        ("none", "ok", format!("{pose} J -"), "tracker is `none`"),
        (
            "ok",
            "silent",
            "P - J 0.250000".to_string(),
            "glove is `silent`",
        ),
        (
            "ok",
            "lost*",
            "P - J 0.250000".to_string(),
            "glove is `lost`",
        ),
        ("ok", "none", "P - J ?".to_string(), "glove is `none`"),
    ] {
        let text = format!("{header}0 ok ok 0 P - J -\n5 {tracker} {glove} 0 {values}\nend 2\n");
        let (line, message) = error_line(&text);
        assert_eq!(line, 5, "{text}");
        assert!(message.contains(says), "{message}");
    }
    // The same states without values read.
    let text = format!("{header}5 lost silent 0 P - J -\n8 ok* ok* 0 {pose} J 0.250000\nend 2\n");
    let t = Trace::parse(&text).unwrap();
    assert!(t.frames[1].pose.is_some() && t.frames[1].joints.is_some());
}

#[test]
fn the_writer_withdraws_values_of_a_source_that_is_not_ok() {
    let mut frame = random_frames(7, 1, &header().joints)[0];
    frame.pose = Some(TrackerPose::new(DVec3::new(0.1, 0.2, 0.3), DQuat::IDENTITY).unwrap());
    let mut angles = JointAngles::new();
    angles.set(Joint::IndexMcp, 0.5).unwrap();
    frame.joints = Some(angles);
    frame.status.tracker = SourceState::Disconnected;
    frame.status.glove = SourceState::Silent;
    let trace = Trace {
        header: header(),
        frames: vec![frame],
        held: Vec::new(),
    };
    let back = Trace::parse(&trace.to_text()).unwrap();
    assert!(back.frames[0].pose.is_none() && back.frames[0].joints.is_none());
    assert_eq!(back.frames[0], quantize_frame(&frame, &header().joints));
}

#[test]
fn the_hand_header_is_validated_with_its_line_number() {
    let good = Trace {
        header: header(),
        frames: Vec::new(),
        held: Vec::new(),
    }
    .to_text();
    let lines: Vec<&str> = good.lines().collect();
    let at = lines.iter().position(|l| l.starts_with("hand ")).unwrap();
    for (from, to) in [
        ("\"palm_length\":0.095", "\"palm_length\":50.0"),
        ("\"palm_length\":0.095", "\"palm_length\":1e200"),
        ("\"palm_width\":0.085", "\"palm_width\":0.0"),
        ("\"distal\":0.018", "\"distal\":-0.018"),
    ] {
        assert!(lines[at].contains(from), "{}", lines[at]);
        let mut v = lines.clone();
        let bad = lines[at].replacen(from, to, 1);
        v[at] = &bad;
        let (line, message) = error_line(&v.join("\n"));
        assert_eq!(line, at + 1, "{to}");
        assert!(message.contains("hand length"), "{to}: {message}");
    }
}

#[test]
fn a_trace_cut_mid_line_is_reported_as_truncated() {
    let good = Trace {
        header: header(),
        frames: random_frames(5, 6, &header().joints),
        held: Vec::new(),
    }
    .to_text();
    let lines = good.lines().count();
    // Cut inside the 4th frame line, inside the hand header, and inside the `end` line.
    let frame_line = good.lines().nth(lines - 3).unwrap();
    let cut_at = good.find(frame_line).unwrap() + frame_line.len() / 2;
    let hand_at = good.find("hand ").unwrap() + 30;
    let end_at = good.rfind("end ").unwrap() + 2;
    for cut in [cut_at, hand_at, end_at] {
        let (line, message) = error_line(&good[..cut]);
        assert_eq!(line, good[..cut].lines().count());
        assert!(message.contains("truncated"), "cut at {cut}: {message}");
    }
    // A trace cut right after a frame line still says so.
    let (_, message) = error_line(&good[..good.rfind("end ").unwrap()]);
    assert!(message.contains("truncated"), "{message}");
}

#[test]
fn a_writer_error_names_the_trace_not_its_temporary_file() {
    let path = std::env::temp_dir()
        .join(format!("nendo-no-such-dir-{}", std::process::id()))
        .join("t.trace");
    let e = TraceWriter::create(&path, header())
        .unwrap_err()
        .to_string();
    assert!(e.starts_with(&path.display().to_string()), "{e}");
    assert!(!e.contains("nendo-tmp"), "{e}");
}

/// Version 3: skeleton frames round-trip bit for bit; a glove trace is still written as
/// version 2; a `skeleton` line needs version 3; a bad `S` section is an error on its line.
#[test]
fn skeleton_traces_round_trip_and_glove_traces_stay_version_2() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut frames = Vec::new();
    for k in 0..20u64 {
        let mut s = Skeleton::new(Side::Left);
        for j in HandJoint::ALL {
            if rng.gen_bool(0.1) {
                continue;
            }
            let q = glam::DQuat::from_xyzw(
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
                rng.gen_range(-1.0..1.0),
            )
            .normalize();
            let p = glam::DVec3::new(rng.gen_range(-2.0..2.0), rng.gen_range(-2.0..2.0), 1.0);
            let radius = rng.gen_bool(0.5).then(|| rng.gen_range(0.005..0.02));
            let source = if rng.gen_bool(0.5) {
                JointSource::Measured
            } else {
                JointSource::Made
            };
            s.set(j, JointPose::new(p, q, radius).unwrap(), source);
        }
        let ok = k % 7 != 3;
        frames.push(HandFrame {
            time: Timestamp::from_micros(k * 16_667),
            skeleton: ok.then_some(s),
            status: FrameStatus {
                tracker: if ok {
                    SourceState::Ok
                } else {
                    SourceState::Silent
                },
                glove: SourceState::Absent,
                tracker_fresh: ok,
                glove_fresh: false,
            },
            ..HandFrame::default()
        });
    }
    let trace = Trace {
        header: TraceHeader {
            skeleton: Some(Side::Left),
            ..TraceHeader::default()
        },
        frames: frames
            .iter()
            .map(|f| nendo_devices::trace::quantize_frame(f, &[]))
            .collect(),
        held: Vec::new(),
    };
    let text = trace.to_text();
    assert!(text.starts_with("nendo-hand-trace 3\n"), "{text}");
    assert!(text.contains("\nskeleton left\n"));
    let back = Trace::parse(&text).unwrap();
    assert_eq!(back, trace);
    assert_eq!(back.to_text(), text);
    // Without skeletons: version 2, as before.
    let glove = Trace {
        header: header(),
        frames: Vec::new(),
        held: Vec::new(),
    };
    assert!(glove.to_text().starts_with("nendo-hand-trace 2\n"));
    // A skeleton line in a version-2 trace, a bad flag, a short section.
    let v2 = text.replacen("nendo-hand-trace 3", "nendo-hand-trace 2", 1);
    assert!(
        Trace::parse(&v2)
            .unwrap_err()
            .to_string()
            .contains("needs trace version 3")
    );
    let first = text
        .lines()
        .position(|l| l.contains(" S m") || l.contains(" S d"))
        .unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let bad_flag = lines[first]
        .replacen(" S m", " S x", 1)
        .replacen(" S d", " S x", 1);
    let short = lines[first].rsplit_once(' ').unwrap().0.to_owned();
    for bad in [bad_flag, short] {
        let mut v = lines.clone();
        v[first] = &bad;
        let e = Trace::parse(&(v.join("\n") + "\n"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with(&format!("trace line {}:", first + 1)), "{e}");
    }
}

/// Random marks on the channels a frame carries (the tracker, its joint columns, its skeleton
/// joints), about one frame in two.
fn random_marks(rng: &mut ChaCha8Rng, f: &HandFrame, joints: &[Joint]) -> HeldMarks {
    if !rng.gen_bool(0.5) {
        return HeldMarks::default();
    }
    let mut m = HeldMarks {
        position: rng.gen_bool(0.5),
        orientation: rng.gen_bool(0.3),
        ..HeldMarks::default()
    };
    for j in joints {
        if rng.gen_bool(0.3) {
            m.joints |= 1 << j.index();
        }
    }
    for k in 0..HandJoint::COUNT {
        if rng.gen_bool(0.2) {
            m.skeleton_positions |= 1 << k;
        }
        if rng.gen_bool(0.2) {
            m.skeleton_orientations |= 1 << k;
        }
    }
    // Only what the frame carries: the rest could not be written.
    m.carried_by(&quantize_frame(f, joints), joints, f.skeleton.is_some())
}

/// Version 4: the gate's marks round-trip text to text and value to value, on glove frames
/// and on skeleton frames, and only where a frame carries the channel; `marks held` makes the
/// version 4 whatever else the header has; a trace without marks is written as before.
#[test]
fn held_marks_round_trip_in_version_4() {
    let joints = header().joints;
    for seed in 0..20u64 {
        let mut rng = ChaCha8Rng::seed_from_u64(100 + seed);
        let frames: Vec<HandFrame> = random_frames(seed, 60, &joints)
            .iter()
            .map(|f| quantize_frame(f, &joints))
            .collect();
        let held: Vec<(usize, HeldMarks)> = frames
            .iter()
            .enumerate()
            .map(|(k, f)| (k, random_marks(&mut rng, f, &joints)))
            .filter(|(_, m)| !m.is_empty())
            .collect();
        assert!(!held.is_empty(), "seed {seed}");
        let trace = Trace {
            header: TraceHeader {
                marks_held: true,
                ..header()
            },
            frames,
            held,
        };
        let text = trace.to_text();
        assert!(text.starts_with("nendo-hand-trace 4\n"), "{text}");
        assert!(text.contains("\nmarks held\n"));
        let marked_lines = text.lines().filter(|l| l.contains(" held=")).count();
        assert_eq!(marked_lines, trace.held.len());
        let back = Trace::parse(&text).unwrap();
        assert_eq!(back, trace, "seed {seed}");
        assert_eq!(back.to_text(), text);
        // The stream reads the same marks.
        let mut stream = nendo_devices::TraceStream::new(text.as_bytes()).unwrap();
        let mut streamed = Vec::new();
        let mut k = 0;
        while stream.next_frame().unwrap().is_some() {
            if !stream.held().is_empty() {
                streamed.push((k, stream.held()));
            }
            k += 1;
        }
        assert_eq!(streamed, trace.held);
    }
    // Skeleton frames: `NAME.position` / `NAME.orientation`, in OpenXR's order.
    let mut s = Skeleton::new(Side::Right);
    for j in [HandJoint::Wrist, HandJoint::IndexTip] {
        s.set(j, JointPose::IDENTITY, JointSource::Measured);
    }
    let frame = HandFrame {
        time: Timestamp(5),
        skeleton: Some(s),
        status: FrameStatus {
            tracker: SourceState::Ok,
            tracker_fresh: true,
            ..FrameStatus::default()
        },
        ..HandFrame::default()
    };
    let marks = HeldMarks {
        skeleton_positions: (1 << HandJoint::IndexTip.index()) | (1 << HandJoint::Palm.index()),
        skeleton_orientations: 1 << HandJoint::Wrist.index(),
        ..HeldMarks::default()
    };
    let trace = Trace {
        header: TraceHeader {
            skeleton: Some(Side::Right),
            ..TraceHeader::default()
        },
        frames: vec![frame],
        held: vec![(0, marks)],
    };
    let text = trace.to_text();
    assert!(text.starts_with("nendo-hand-trace 4\n"), "{text}");
    // The palm is not in the frame: its mark is not written.
    assert!(
        text.contains(" held=wrist.orientation,index_tip.position\n"),
        "{text}"
    );
    let back = Trace::parse(&text).unwrap();
    assert_eq!(
        back.held,
        vec![(0, marks.carried_by(&trace.frames[0], &[], true))]
    );
    // No marks: written as before (version 2, no `marks` line).
    let plain = Trace {
        header: header(),
        frames: random_frames(1, 5, &joints),
        held: Vec::new(),
    }
    .to_text();
    assert!(plain.starts_with("nendo-hand-trace 2\n") && !plain.contains("marks"));
    // A version-4 trace with `marks held` and no mark says nothing was held.
    let none = Trace {
        header: TraceHeader {
            marks_held: true,
            ..header()
        },
        frames: random_frames(1, 5, &joints)
            .iter()
            .map(|f| quantize_frame(f, &joints))
            .collect(),
        held: Vec::new(),
    };
    let text = none.to_text();
    assert!(text.contains("\nmarks held\n") && !text.contains("held="));
    assert_eq!(Trace::parse(&text).unwrap(), none);
}

/// Every way a mark can be wrong is an error naming the line, and none panics or holds more
/// than the line: a mark in a trace that does not declare marks, a `marks` line before
/// version 4 or naming another field, a channel the frame does not carry, a name that is no
/// channel, a repeat, a list out of order, two `held=` fields, an empty item, a hostile list.
#[test]
fn malformed_marks_are_errors_on_their_line() {
    let joints = vec![Joint::IndexMcp, Joint::IndexPip];
    let h = TraceHeader {
        joints: joints.clone(),
        marks_held: true,
        ..TraceHeader::default()
    };
    let head = nendo_devices::trace::format_header(&h);
    let pose = "P 0.100000 0.200000 -0.050000 1.000000 0.000000 0.000000 0.000000";
    let line = |rest: &str| format!("{head}0 ok* ok* 0 {rest}\nend 1\n");
    let good = line(&format!(
        "{pose} J 0.100000 0.200000 held=position,index_pip"
    ));
    let t = Trace::parse(&good).unwrap();
    assert_eq!(
        t.held,
        vec![(
            0,
            HeldMarks {
                position: true,
                joints: 1 << Joint::IndexPip.index(),
                ..HeldMarks::default()
            }
        )]
    );
    let frames_line = head.lines().count() + 1;
    let cases: Vec<(String, &str)> = vec![
        (
            line(&format!("{pose} J 0.100000 ? held=index_pip")),
            "no value in this column",
        ),
        (
            line("P - J 0.100000 0.200000 held=orientation"),
            "no tracker pose",
        ),
        (
            line(&format!("{pose} J 0.100000 0.200000 held=thumb_roll")),
            "not a joint column",
        ),
        (
            line(&format!("{pose} J 0.100000 0.200000 held=elbow")),
            "not a channel",
        ),
        (
            line(&format!(
                "{pose} J 0.100000 0.200000 held=position,position"
            )),
            "in order",
        ),
        (
            line(&format!(
                "{pose} J 0.100000 0.200000 held=index_pip,index_mcp"
            )),
            "in order",
        ),
        (
            line(&format!(
                "{pose} J 0.100000 0.200000 held=orientation,position"
            )),
            "in order",
        ),
        (
            line(&format!("{pose} J 0.100000 0.200000 held=position,")),
            "not a channel",
        ),
        (
            line(&format!("{pose} J 0.100000 0.200000 held=wrist.position")),
            "no skeleton",
        ),
        (
            line(&format!("{pose} J 0.100000 0.200000 held=wrist.angle")),
            ".position or .orientation",
        ),
        (
            line(&format!(
                "{pose} J 0.100000 0.200000 held=position held=index_mcp"
            )),
            "twice",
        ),
        (
            line(&format!("{pose} J 0.100000 0.200000 held=position other=1")),
            "unknown per-frame field `other`",
        ),
        (
            line(&format!("{pose} J 0.100000 0.200000 held=")),
            "is not a per-frame field",
        ),
    ];
    for (text, says) in &cases {
        let (at, message) = error_line(text);
        assert_eq!(at, frames_line, "{message}");
        assert!(message.contains(says), "{says}: {message}");
    }
    // Marks need the header's `marks held`, which needs version 4.
    let undeclared = good.replacen("marks held\n", "", 1);
    assert!(
        error_line(&undeclared)
            .1
            .contains("does not say `marks held`")
    );
    let v3 = good.replacen("nendo-hand-trace 4", "nendo-hand-trace 3", 1);
    assert!(error_line(&v3).1.contains("needs trace version 4"));
    let other = good.replacen("marks held", "marks rejected", 1);
    assert!(error_line(&other).1.contains("knows only `marks held`"));
    // A hostile list: a 1 MB value of valid-looking tokens is refused at its first repeat,
    // quoting at most 40 characters of it; the stream refuses a longer line unread.
    let long = "index_mcp,".repeat(100_000);
    let (_, message) = error_line(&line(&format!("{pose} J 0.100000 0.200000 held={long}x")));
    assert!(message.len() < 300, "{}", message.len());
    let huge = "position".repeat(200_000);
    let (_, message) = error_line(&line(&format!("{pose} J 0.100000 0.200000 held={huge}")));
    assert!(
        message.len() < 300 && message.contains('…'),
        "{}",
        message.len()
    );
    let text = line(&format!("{pose} J 0.100000 0.200000 held={huge}"));
    let mut stream = nendo_devices::TraceStream::new(text.as_bytes()).unwrap();
    assert!(
        stream
            .next_frame()
            .unwrap_err()
            .to_string()
            .contains("longer than 1 MB")
    );
}
