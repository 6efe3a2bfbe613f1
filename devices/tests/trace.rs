//! The trace format: bit-exact round trips, line-numbered errors, atomic writing.

use glam::{DQuat, DVec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use nendo_devices::trace::{TraceWriter, quantize_frame};
use nendo_devices::{
    DeviceError, FrameStatus, HandFrame, Joint, JointAngles, SourceState, Timestamp, Trace,
    TraceHeader, TrackerPose,
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
        frames: random_frames(1, 5, &header().joints),
    }
    .to_text();
    let lines: Vec<&str> = good.lines().collect();
    let frames_at = lines.iter().position(|l| *l == "frames").unwrap();
    let with = |i: usize, new: &str| {
        let mut v = lines.clone();
        v[i] = new;
        v.join("\n")
    };
    assert_eq!(error_line("nendo-hand-trace 2\nframes\nend 0\n").0, 1);
    assert_eq!(error_line("hello\n").0, 1);
    let bad_number = lines[frames_at + 2].replacen(".", ",", 1);
    assert_eq!(
        error_line(&with(frames_at + 2, &bad_number)).0,
        frames_at + 3
    );
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
        6
    );
    assert!(error_line(&backwards).1.contains("backwards"));
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
