//! The traces shipped in `devices/traces/` are exactly what their generators write
//! (`nendo::hand::shipped`, run by `examples/hand_traces.rs`), and stay small.

use nendo::hand::{script, shipped};
use nendo_devices::{HandFrame, Trace};
use std::path::Path;

fn shipped_file(name: &str) -> (Trace, usize) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("devices/traces")
        .join(format!("{name}.trace"));
    let bytes = std::fs::metadata(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .len();
    (
        Trace::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display())),
        bytes as usize,
    )
}

/// Frames equal up to the last written decimal (the generators run the same arithmetic, but a
/// different libm could round a sine differently in the sixth decimal).
fn assert_frames_match(name: &str, k: usize, a: &HandFrame, b: &HandFrame) {
    assert_eq!(
        (a.time, a.buttons, a.status),
        (b.time, b.buttons, b.status),
        "{name} frame {k}"
    );
    match (a.pose, b.pose) {
        (Some(p), Some(q)) => {
            assert!(
                (p.position - q.position).abs().max_element() <= 2e-6,
                "{name} frame {k}"
            );
            let d = (p.orientation - q.orientation).to_array();
            assert!(d.iter().all(|x| x.abs() <= 2e-6), "{name} frame {k}");
        }
        (None, None) => {}
        _ => panic!("{name} frame {k}: pose present in one only"),
    }
    match (a.joints, b.joints) {
        (Some(p), Some(q)) => {
            assert_eq!(p.len(), q.len(), "{name} frame {k}");
            for ((j, x), (i, y)) in p.iter().zip(q.iter()) {
                assert_eq!(j, i);
                assert!((x - y).abs() <= 2e-6, "{name} frame {k} {j}");
            }
        }
        (None, None) => {}
        _ => panic!("{name} frame {k}: joints present in one only"),
    }
}

#[test]
fn the_shipped_traces_are_what_the_generators_write() {
    let shipped = shipped::shipped().unwrap();
    let names: Vec<&str> = shipped.iter().map(|s| s.name).collect();
    assert_eq!(
        names,
        [
            "sphere-push-pull",
            "plane-groove",
            "tube-pot",
            "mouse-sphere",
            "sphere-pinch-pull",
            "tube-rim-pinch",
            "plane-palm"
        ]
    );
    for s in shipped {
        let (file, bytes) = shipped_file(s.name);
        assert!(bytes < 1_000_000, "{}: {bytes} bytes", s.name);
        assert_eq!(file.header, s.trace.header, "{}", s.name);
        assert_eq!(file.frames.len(), s.trace.frames.len(), "{}", s.name);
        for (k, (a, b)) in file.frames.iter().zip(&s.trace.frames).enumerate() {
            assert_frames_match(s.name, k, a, b);
        }
    }
}

#[test]
fn glove_traces_carry_the_profiles_glove_columns_and_a_steady_rate() {
    let profile = nendo_devices::profile::resolve(script::GLOVE_PROFILE).unwrap();
    let columns = profile.glove().unwrap().joints();
    for (name, hz) in [
        ("sphere-push-pull", 120.0),
        ("plane-groove", 120.0),
        ("tube-pot", 60.0),
        ("sphere-pinch-pull", 120.0),
        ("tube-rim-pinch", 60.0),
        ("plane-palm", 120.0),
    ] {
        let (t, _) = shipped_file(name);
        assert_eq!(t.header.profile.as_deref(), Some(script::GLOVE_PROFILE));
        assert_eq!(t.header.joints, columns, "{name}");
        let period = 1e6 / hz;
        for (k, f) in t.frames.iter().enumerate() {
            assert_eq!(
                f.time.as_micros(),
                (k as f64 * period).round() as u64,
                "{name} frame {k}"
            );
            assert!(f.pose.is_some() && f.joints.is_some());
            assert_eq!(f.joints.unwrap().len(), 18);
        }
    }
    let (mouse, _) = shipped_file("mouse-sphere");
    assert_eq!(mouse.header.profile.as_deref(), Some("mouse"));
    assert!(
        mouse
            .frames
            .iter()
            .any(|f| f.buttons == nendo_devices::buttons::SECONDARY)
    );
}

#[test]
fn the_generators_are_deterministic() {
    let a = shipped::tube_pot().unwrap();
    let b = shipped::tube_pot().unwrap();
    assert_eq!(a.0, b.0);
    assert_eq!(a.1, b.1);
    assert!(a.1 >= 140, "gestures planned: {}", a.1);
    assert_eq!(
        shipped::mouse_sphere().unwrap(),
        shipped::mouse_sphere().unwrap()
    );
}
