//! Recordings that survive: the recorder's file is a trace from its first moment, holds every
//! frame pushed, and an interrupted recording — cut at any byte, with a torn or damaged end —
//! reads back to its last complete frame, saying so. A live stream's frames are exactly what a
//! recording of them stores.

use std::path::Path;
use std::time::Duration;

use glam::{DQuat, DVec3};
use nendo_devices::cyberglove::SensorCount;
use nendo_devices::emulator::{CyberGloveModel, FastrakModel, PtyEmulator};
use nendo_devices::trace::{DroppedTail, Existing, quantize_frame};
use nendo_devices::{
    DeviceError, FrameStatus, HandFrame, HandStream, Joint, JointAngles, SourceState,
    StreamOptions, Timestamp, Trace, TraceHeader, TraceRecorder, TrackerPose, profile,
};

fn header() -> TraceHeader {
    TraceHeader {
        profile: Some("cyberglove2-18-fastrak".into()),
        joints: vec![Joint::IndexMcp, Joint::IndexPip],
        ..TraceHeader::default()
    }
}

/// Frames with values that are not six-decimal numbers (as devices deliver them).
fn frames(n: u64) -> Vec<HandFrame> {
    (0..n)
        .map(|i| {
            let x = i as f64;
            let mut a = JointAngles::new();
            a.set(Joint::IndexMcp, 0.1 + x / 7.0e3).unwrap();
            a.set(Joint::IndexPip, (x / 3.0).sin()).unwrap();
            HandFrame {
                time: Timestamp(i * 8_333),
                pose: Some(
                    TrackerPose::new(
                        DVec3::new(0.1 / 3.0, x * 1e-3 / 7.0, -0.05),
                        DQuat::from_rotation_z(x / 11.0),
                    )
                    .unwrap(),
                ),
                joints: Some(a),
                buttons: (i % 2) as u32,
                skeleton: None,
                status: FrameStatus {
                    tracker: SourceState::Ok,
                    glove: SourceState::Ok,
                    tracker_fresh: true,
                    glove_fresh: i % 3 == 0,
                },
            }
        })
        .collect()
}

fn quantized(frames: &[HandFrame]) -> Vec<HandFrame> {
    let joints = header().joints;
    frames.iter().map(|f| quantize_frame(f, &joints)).collect()
}

#[test]
fn a_recording_is_a_trace_from_its_first_moment_and_holds_every_frame_pushed() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("live.trace");
    let all = frames(50);
    let mut rec = TraceRecorder::create(&path, header(), Existing::Refuse).unwrap();
    // The header alone: an interrupted recording of no frame.
    let r = Trace::read_recovering(&path).unwrap();
    assert_eq!(r.trace.header, header());
    assert!(r.trace.frames.is_empty());
    assert_eq!(r.interrupted.as_ref().map(|i| i.frames), Some(0));
    for (k, f) in all.iter().enumerate() {
        rec.push(f).unwrap();
        if k % 10 == 9 {
            // Read by another reader while recording: every frame pushed is in the file.
            let r = Trace::read_recovering(&path).unwrap();
            assert_eq!(r.trace.frames, quantized(&all[..=k]));
            let i = r.interrupted.expect("no end line yet");
            assert_eq!((i.frames, &i.dropped), (k + 1, &None));
            assert_eq!(
                i.to_string(),
                format!(
                    "an interrupted recording (no `end` line): recovered its {} complete frames",
                    k + 1
                )
            );
        }
    }
    assert_eq!(rec.frames(), 50);
    assert_eq!(rec.finish().unwrap(), 50);
    let t = Trace::read(&path).unwrap();
    assert_eq!(t.frames, quantized(&all));
    let r = Trace::read_recovering(&path).unwrap();
    assert_eq!((r.trace, r.interrupted), (t, None));
}

#[test]
fn a_recording_never_replaces_a_file_unless_asked() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("earlier.trace");
    let mut rec = TraceRecorder::create(&path, header(), Existing::Refuse).unwrap();
    for f in &frames(5) {
        rec.push(f).unwrap();
    }
    // Killed: never finished.
    drop(rec);
    let before = std::fs::read(&path).unwrap();
    let e = TraceRecorder::create(&path, header(), Existing::Refuse).unwrap_err();
    match &e {
        DeviceError::File { path: p, error } => {
            assert_eq!(p, &path);
            assert_eq!(error.kind(), std::io::ErrorKind::AlreadyExists);
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        std::fs::read(&path).unwrap(),
        before,
        "the earlier frames kept"
    );
    let rec = TraceRecorder::create(&path, header(), Existing::Replace).unwrap();
    assert_eq!(rec.finish().unwrap(), 0);
    assert!(Trace::read(&path).unwrap().frames.is_empty());
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(names.len(), 1, "no temporary left");
    let e = TraceRecorder::create(Path::new("/dev/full"), header(), Existing::Replace)
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("/dev/full: is not a regular file"), "{e}");
}

/// Every cut of a finished recording after its header — at every byte — reads as an
/// interrupted recording holding exactly the frames whose lines are complete.
#[test]
fn a_recording_cut_at_any_byte_recovers_its_complete_frames() {
    let all = quantized(&frames(40));
    let text = Trace {
        header: header(),
        frames: all.clone(),
        held: Vec::new(),
    }
    .to_text();
    let body = text.find("frames\n").unwrap() + "frames\n".len();
    let end = text.rfind("end ").unwrap();
    for cut in body..end {
        let part = &text[..cut];
        let r = Trace::parse_recovering(part).unwrap_or_else(|e| panic!("cut at {cut}: {e}"));
        let complete = part[body..].matches('\n').count();
        assert_eq!(r.trace.frames, all[..complete], "cut at {cut}");
        let i = r.interrupted.expect("interrupted");
        assert_eq!(i.frames, complete);
        let torn = !part.ends_with('\n');
        match &i.dropped {
            None => assert!(!torn, "cut at {cut}"),
            // A torn line that still reads as a frame with fewer decimals is not taken.
            Some(DroppedTail {
                cut_short: true,
                lines: 1,
                ..
            }) => assert!(torn, "cut at {cut}"),
            Some(other) => panic!("cut at {cut}: {other:?}"),
        }
        if torn {
            assert!(
                i.to_string().ends_with(&format!(
                    "; its last line (line {}) was cut short and is dropped",
                    part.lines().count()
                )),
                "{i}"
            );
        }
        // The strict reader refuses every cut, naming the truncation.
        let e = Trace::parse(part).unwrap_err().to_string();
        assert!(e.contains("truncated"), "cut at {cut}: {e}");
    }
}

#[test]
fn a_damaged_end_is_dropped_only_from_an_unfinished_recording() {
    let all = quantized(&frames(6));
    let text = Trace {
        header: header(),
        frames: all.clone(),
        held: Vec::new(),
    }
    .to_text();
    let unfinished = &text[..text.rfind("end ").unwrap()];
    // What a power cut can leave: a block of zeros after the last frame written back.
    let zeros = format!("{unfinished}{}", "\0".repeat(700));
    let r = Trace::parse_recovering(&zeros).unwrap();
    assert_eq!(r.trace.frames, all);
    let i = r.interrupted.unwrap();
    let tail = i.dropped.as_ref().unwrap();
    assert_eq!(tail.line, unfinished.lines().count() + 1);
    assert!(tail.cut_short, "{i}");
    // Zeros with a line break among them: a line that does not read, and one after it.
    let zeros = format!("{unfinished}{}\n{}", "\0".repeat(300), "\0".repeat(300));
    let r = Trace::parse_recovering(&zeros).unwrap();
    assert_eq!(r.trace.frames, all);
    let i = r.interrupted.unwrap();
    assert_eq!(
        i.dropped.as_ref().map(|t| (t.line, t.lines, t.cut_short)),
        Some((unfinished.lines().count() + 1, 2, false))
    );
    assert!(i.to_string().contains("does not read"), "{i}");
    // A bad frame line and lines after it.
    let lines: Vec<&str> = unfinished.lines().collect();
    let frames_at = lines.iter().position(|l| *l == "frames").unwrap() + 1;
    let mut damaged = lines.clone();
    damaged[frames_at + 3] = "garbage";
    let damaged = damaged.join("\n") + "\n";
    let r = Trace::parse_recovering(&damaged).unwrap();
    assert_eq!(r.trace.frames, all[..3]);
    let i = r.interrupted.unwrap();
    assert_eq!(
        i.dropped.as_ref().map(|t| (t.line, t.lines)),
        Some((frames_at + 4, 3))
    );
    assert!(
        i.to_string()
            .contains(&format!("line {} does not read", frames_at + 4))
            && i.to_string()
                .ends_with("and is dropped with the 2 lines after it"),
        "{i}"
    );
    // The same bad line in a finished trace is an error, not a recovery.
    let finished = format!("{damaged}end 6\n");
    let e = Trace::parse_recovering(&finished).unwrap_err();
    assert!(
        matches!(&e, DeviceError::TraceSyntax { line, .. } if *line == frames_at + 4),
        "{e}"
    );
    // Bytes that are not UTF-8 at the end of a file.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cut.trace");
    let mut bytes = unfinished.as_bytes().to_vec();
    bytes.extend_from_slice(b"123 ok* ok 0 P 0.1\xff\xfe\n\xff");
    std::fs::write(&path, &bytes).unwrap();
    let r = Trace::read_recovering(&path).unwrap();
    assert_eq!(r.trace.frames, all);
    let tail = r.interrupted.unwrap().dropped.unwrap();
    assert_eq!((tail.line, tail.lines), (unfinished.lines().count() + 1, 2));
    assert_eq!(tail.reason, "not UTF-8 text");
    assert!(Trace::read(&path).is_err(), "the strict reader refuses it");
    // A finished trace followed by such bytes is refused.
    let mut bytes = text.as_bytes().to_vec();
    bytes.extend_from_slice(b"\xff\n");
    std::fs::write(&path, &bytes).unwrap();
    assert!(Trace::read_recovering(&path).is_err());
}

#[test]
fn per_frame_fields_are_an_extension_point_refused_until_defined() {
    let joints = [Joint::IndexMcp];
    let line = "0 ok ok 0 P - J 0.100000";
    assert!(nendo_devices::trace::parse_frame(&joints, line).is_ok());
    let e = nendo_devices::trace::parse_frame(&joints, &format!("{line} rejected=tracker"))
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "unknown per-frame field `rejected` (a trace from a newer nendo?)"
    );
    for bad in [
        format!("{line} =x"),
        format!("{line} Rejected=x"),
        format!("{line} rejected="),
    ] {
        let e = nendo_devices::trace::parse_frame(&joints, &bad).unwrap_err();
        assert!(
            e.to_string().contains("is not a per-frame field"),
            "{bad}: {e}"
        );
    }
    // A joint column after a field is not read as one.
    let e = nendo_devices::trace::parse_frame(&joints, "0 ok ok 0 P - J a=b 0.100000").unwrap_err();
    assert!(e.to_string().contains("per-frame field"), "{e}");
}

/// A live stream (emulated glove and tracker, whose values are not six-decimal numbers)
/// delivers exactly the frames its recording reads back: bit for bit, the window's hand loop
/// and a replay of its recording get the same numbers.
#[test]
fn a_live_streams_frames_are_what_its_recording_reads_back() {
    let glove = PtyEmulator::spawn(CyberGloveModel::new(SensorCount::Eighteen)).unwrap();
    let tracker = PtyEmulator::spawn(FastrakModel::new()).unwrap();
    let profile = profile::resolve("cyberglove2-18-fastrak").unwrap();
    let options = StreamOptions {
        glove_port: Some(glove.port()),
        tracker_port: Some(tracker.port()),
        ..StreamOptions::default()
    };
    let stream = HandStream::open(&profile, &options).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("live.trace");
    let header = stream.recording_header(&profile);
    let mut rec = TraceRecorder::create(&path, header.clone(), Existing::Refuse).unwrap();
    let mut got = Vec::new();
    while got.len() < 60 {
        if let Some(f) = stream.next_timeout(Duration::from_secs(5)) {
            rec.push(&f).unwrap();
            got.push(f);
        } else {
            panic!("the devices stopped after {} frames", got.len());
        }
    }
    drop(stream);
    rec.finish().unwrap();
    let back = Trace::read(&path).unwrap();
    assert!(got.iter().any(|f| f.pose.is_some()) && got.iter().any(|f| f.joints.is_some()));
    let bits = |f: &HandFrame| {
        let mut v: Vec<u64> = Vec::new();
        if let Some(p) = f.pose {
            v.extend(p.position.to_array().map(f64::to_bits));
            v.extend(p.orientation.to_array().map(f64::to_bits));
        }
        if let Some(a) = f.joints {
            v.extend(a.iter().map(|(_, x)| x.to_bits()));
        }
        v
    };
    assert_eq!(back.frames.len(), got.len());
    for (k, (a, b)) in got.iter().zip(&back.frames).enumerate() {
        assert_eq!(a, b, "frame {k}");
        assert_eq!(bits(a), bits(b), "frame {k}");
    }
}

/// A gated recorder marks the frames its gate holds: every injected tracker spike, and
/// exactly the frames a gate run afterwards over the frames read back holds (the same
/// settings, the same rounded frames); its header says `marks held` (version 4). With the gate
/// off, or made without one, it writes no marks and the version of before.
#[test]
fn a_gated_recorder_marks_what_its_gate_holds() {
    use nendo_devices::trace::HeldMarks;
    use nendo_devices::{FilterSettings, FrameFilter};
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();
    let spikes = [40usize, 90, 151, 152, 230];
    let mut all = frames(300);
    for &k in &spikes {
        if let Some(p) = &mut all[k].pose {
            p.position.z -= 0.06;
        }
    }
    let path = dir.join("gated.trace");
    let settings = FilterSettings::default();
    let mut rec = TraceRecorder::create_gated(&path, header(), Existing::Refuse, settings).unwrap();
    for f in &all {
        rec.push(f).unwrap();
    }
    let marked = rec.marked();
    assert_eq!(rec.finish().unwrap(), 300);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("nendo-hand-trace 4\n") && text.contains("\nmarks held\n"));
    let trace = Trace::read(&path).unwrap();
    assert_eq!(trace.held.len() as u64, marked);
    // The reference: a gate run over the frames as read back.
    let mut gate = FrameFilter::new(settings);
    let mut expected = Vec::new();
    for (k, f) in trace.frames.iter().enumerate() {
        gate.apply(f);
        let m = HeldMarks::from(gate.held());
        if !m.is_empty() {
            expected.push((k, m));
        }
    }
    assert_eq!(trace.held, expected);
    // Every spike held (a two-sample spike too), and nothing far from them.
    for &k in &spikes {
        assert!(
            trace.held.iter().any(|(i, m)| *i == k && m.position),
            "spike at {k}: {:?}",
            trace.held
        );
    }
    let position_marks: Vec<usize> = trace
        .held
        .iter()
        .filter(|(_, m)| m.position)
        .map(|(i, _)| *i)
        .collect();
    assert!(
        position_marks
            .iter()
            .all(|i| spikes.iter().any(|s| s.abs_diff(*i) <= 2)),
        "{position_marks:?}"
    );
    eprintln!(
        "gated recorder: {marked} of 300 frames marked, position marks at {position_marks:?}"
    );
    // Gate off, or no gate: no marks, the version of before.
    for (name, off) in [("off", true), ("plain", false)] {
        let path = dir.join(format!("{name}.trace"));
        let mut rec = if off {
            TraceRecorder::create_gated(&path, header(), Existing::Refuse, FilterSettings::off())
        } else {
            TraceRecorder::create(
                &path,
                TraceHeader {
                    marks_held: true,
                    ..header()
                },
                Existing::Refuse,
            )
        }
        .unwrap();
        for f in &all {
            rec.push(f).unwrap();
        }
        assert_eq!(rec.marked(), 0);
        rec.finish().unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with("nendo-hand-trace 2\n"), "{name}");
        assert!(!text.contains("marks") && !text.contains("held="), "{name}");
        assert_eq!(Trace::read(&path).unwrap().frames, trace.frames);
    }
}
