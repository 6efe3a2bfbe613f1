//! Tests of [`super`].

use super::*;

#[test]
fn replay_speeds_beyond_a_thousandfold_are_refused() {
    for speed in ["1e-300", "5e-324", "1.5e-21", "1e9"] {
        let text = format!(
            r#"{{"format":"nendo-device-profile","version":1,"name":"rp","description":"r",
               "input":{{"replay":{{"trace":"t.trace","speed":{speed}}}}}}}"#
        );
        let e = Profile::from_json(&text, "rp").unwrap_err().to_string();
        assert!(e.contains("replay speed"), "{speed}: {e}");
    }
    let ok = r#"{"format":"nendo-device-profile","version":1,"name":"rp","description":"r",
                "input":{"replay":{"trace":"t.trace","speed":10}}}"#;
    assert!(Profile::from_json(ok, "rp").is_ok());
}

#[test]
fn every_shipped_profile_parses_and_validates() {
    for (name, text) in BUILTIN {
        let p = Profile::from_json(text, name).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(p.name, name);
    }
    assert_eq!(builtin().len(), BUILTIN.len());
}

#[test]
fn the_filter_has_defaults_and_old_profiles_load_without_it() {
    // Every shipped profile but one leaves `filter` out: the defaults.
    let fastrak = resolve("fastrak").unwrap();
    assert!(!BUILTIN[4].1.contains("\"filter\""));
    assert_eq!(fastrak.filter, FilterSettings::default());
    // The paper's set-up writes it out, with the defaults' values.
    let paper = resolve("cyberglove2-18-fastrak").unwrap();
    assert!(BUILTIN[6].1.contains("\"filter\""));
    assert_eq!(paper.filter, FilterSettings::default());
    // A member of it alone; a bad value names itself; an unknown member is refused.
    let (_, text) = BUILTIN[4];
    let with = |filter: &str| text.replacen('{', &format!("{{\"filter\": {filter},"), 1);
    let p = Profile::from_json(
        &with(r#"{"position":{"min_cutoff_hz":0.5,"beta":80,"d_cutoff_hz":1}}"#),
        "f",
    )
    .unwrap();
    assert_eq!(p.filter.position.min_cutoff_hz, 0.5);
    assert_eq!(p.filter.joints, FilterSettings::default().joints);
    let e = Profile::from_json(&with(r#"{"gate":{"max_speed_m_s":-5}}"#), "f")
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "profile f: filter.gate.max_speed_m_s is -5; it must be a positive number"
    );
    let e = Profile::from_json(&with(r#"{"gate":{"max_speed":5}}"#), "f")
        .unwrap_err()
        .to_string();
    assert!(e.contains("filter.gate") && e.contains("max_speed"), "{e}");
    let p = Profile::from_json(&with(r#"{"enabled":false}"#), "f").unwrap();
    assert!(!p.filter.enabled);
}

#[test]
fn profile_errors_name_the_problem() {
    let (_, text) = BUILTIN[0];
    let broken = text.replace("\"sensors\": 18", "\"sensors\": 19");
    let e = Profile::from_json(&broken, "x").unwrap_err().to_string();
    assert!(e.contains("18 or 22"), "{e}");
    let unknown = text.replace("\"baud\"", "\"bauds\"");
    assert!(Profile::from_json(&unknown, "x").is_err());
    assert!(
        resolve("no-such-profile")
            .unwrap_err()
            .to_string()
            .contains("cyberglove2-18")
    );
}

#[test]
fn calibration_is_offset_then_gain_and_rejects_wild_values() {
    let table = [
        SensorCalibration {
            joint: Some(Joint::IndexMcp),
            offset: 50.0,
            gain: 0.01,
        },
        SensorCalibration {
            joint: None,
            offset: 0.0,
            gain: 1.0,
        },
    ];
    let a = calibrate(&table, &[150.0, 9.0]).unwrap();
    assert!((a.get(Joint::IndexMcp).unwrap() - 1.0).abs() < 1e-12);
    assert_eq!(a.len(), 1);
    assert!(calibrate(&table, &[1e6, 0.0]).is_err());
}

#[test]
fn a_saved_profile_reads_back_the_same() {
    let mut p = resolve("cyberglove2-18-fastrak").unwrap();
    p.name = "mine".into();
    if let Some(g) = p.glove_mut() {
        g.set_port("/tmp/glove");
        g.calibration_mut()[0].offset = 12.5;
    }
    let dir = std::env::temp_dir().join(format!("nendo-profile-save-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("mine.json");
    p.save(&path).unwrap();
    assert_eq!(Profile::load(&path).unwrap(), p);
    // An invalid profile is refused and the file is left as it was.
    let mut bad = p.clone();
    bad.world_from_tracker.scale = -1.0;
    assert!(bad.save(&path).is_err());
    assert_eq!(Profile::load(&path).unwrap(), p);
    assert!(is_builtin("fastrak") && !is_builtin("mine"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn world_from_tracker_is_a_similarity() {
    let w = WorldFromTracker {
        translation: [1.0, 2.0, 3.0],
        rotation_wxyz: [0.5f64.sqrt(), 0.0, 0.0, 0.5f64.sqrt()],
        scale: 10.0,
    };
    let pose = TrackerPose::new(DVec3::X, DQuat::IDENTITY).unwrap();
    let (p, q) = w.apply(&pose);
    assert!((p - DVec3::new(1.0, 12.0, 3.0)).length() < 1e-12);
    assert!((q * DVec3::X - DVec3::Y).length() < 1e-12);
}
