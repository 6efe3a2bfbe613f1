//! Absurd sizes and odd targets get a clear error from every subcommand that takes them —
//! never an allocation failure, a panic, hours of work, or a device replaced by a file.

use crate::support::{run as nendo, temp_dir};
use std::process::{Command, Output};

fn refused(out: &Output, want: &str) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && out.status.code() != Some(101),
        "expected a clean failure, got {:?}: {err}",
        out.status
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains(want), "expected {want:?} in {err}");
}

#[test]
fn grids_beyond_the_patch_limit_are_refused() {
    let dir = temp_dir("grid");
    let out = dir.join("o.json");
    let o = out.to_str().expect("utf-8 path");
    for patches in ["1000x1000", "6x100000"] {
        let r = nendo(&[
            "sculpt",
            "--primitive",
            "plane",
            "--patches",
            patches,
            "--out",
            o,
        ]);
        refused(&r, "too large");
        assert!(!out.exists());
    }
}

#[test]
fn a_fifo_is_not_replaced_by_an_atomic_write() {
    let dir = temp_dir("fifo");
    let fifo = dir.join("pipe");
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        panic!("mkfifo (coreutils) is needed for this test");
    }
    let p = fifo.to_str().expect("utf-8 path");
    let r = nendo(&["sculpt", "--primitive", "plane", "--out", p]);
    refused(&r, "not a regular file");
    let kind = std::fs::symlink_metadata(&fifo)
        .expect("still there")
        .file_type();
    assert!(!kind.is_file(), "the pipe was replaced by a file");
}

#[test]
fn counts_and_durations_beyond_use_are_refused() {
    let dir = temp_dir("counts");
    let model = dir.join("m.json");
    let m = model.to_str().expect("utf-8 path");
    assert!(
        nendo(&["sculpt", "--primitive", "sphere", "--out", m])
            .status
            .success()
    );
    refused(&nendo(&["check", m, "--samples", "4294967296"]), "at most");
    let o = dir.join("t.trace");
    let t = o.to_str().expect("utf-8 path");
    for s in ["1e300", "1e19", "100000"] {
        let r = nendo(&["record", "--profile", "mouse", "--seconds", s, "--out", t]);
        refused(&r, "--seconds");
    }
    let horse = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/figures/horse.json");
    let f = dir.join("f.json");
    let r = nendo(&[
        "figure",
        "fit",
        horse,
        "--out",
        f.to_str().expect("utf-8 path"),
        "--contour-samples",
        "18446744073709551615",
    ]);
    refused(&r, "--contour-samples");
    let torso = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/shapes/torso.json");
    let mesh = dir.join("s.obj");
    let r = nendo(&[
        "figure",
        "shape",
        torso,
        "--mesh",
        mesh.to_str().expect("utf-8 path"),
        "--samples",
        "18446744073709551615",
    ]);
    refused(&r, "--samples");
    assert!(!f.exists() && !mesh.exists());
}

#[test]
fn figures_and_shapes_beyond_their_counts_are_refused() {
    // The crash hunt's slow inputs: 10 000 metacircles took minutes to measure, 1 000 sections
    // minutes to fit.
    let dir = temp_dir("limits-figure-counts");
    let circle = r#"{"centre": [0, 0], "radius": 1, "density": 1}"#;
    let circles = vec![circle; 2_001].join(",");
    let figure = dir.join("many.json");
    std::fs::write(
        &figure,
        format!(
            r#"{{"format": "nendo-figure", "version": 1, "metacircles": [{circles}], "contour": [[0, 0], [1, 0], [0, 1]]}}"#
        ),
    )
    .expect("figure written");
    let path = figure.to_str().expect("utf-8");
    refused(&nendo(&["figure", "measure", path]), "at most 2000");

    let section = r#"{"z": 0, "contour": [[0, 0], [1, 0], [0, 1]]}"#;
    let sections = vec![section; 257].join(",");
    let shape = dir.join("many-sections.json");
    std::fs::write(
        &shape,
        format!(r#"{{"format": "nendo-shape", "version": 1, "sections": [{sections}]}}"#),
    )
    .expect("shape written");
    let mesh = dir.join("m.obj");
    refused(
        &nendo(&[
            "figure",
            "shape",
            shape.to_str().expect("utf-8"),
            "--mesh",
            mesh.to_str().expect("utf-8"),
        ]),
        "at most 256",
    );
    assert!(!mesh.exists());
}

#[test]
fn a_bench_scale_beyond_use_is_refused_compactly() {
    // `--scale 1e308` asked for a case vector of ~1e311 entries: a capacity-overflow panic;
    // 1e6 an allocation of 96 GB.
    for s in ["1e308", "1e6", "101"] {
        let r = nendo(&["bench", "closest", "--scale", s]);
        refused(&r, "--scale must be a positive number of at most 100");
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(err.len() < 200, "{err}");
    }
}

/// `nendo render --heat-max` is an angle: zero, negative or not a number is refused before any
/// work, not drawn as a meaningless colour scale.
#[test]
fn a_heat_scale_that_is_no_positive_angle_is_refused() {
    let dir = temp_dir("heat-max");
    let model = dir.join("m.json");
    let m = model.to_str().expect("utf-8 path");
    let made = nendo(&["sculpt", "--primitive", "plane", "--out", m]);
    assert!(made.status.success(), "{made:?}");
    let png = dir.join("m.png");
    let png = png.to_str().expect("utf-8 path");
    for v in ["0", "-1", "NaN", "inf", "1e308"] {
        let r = nendo(&["render", m, "--png", png, "--heat", "--heat-max", v]);
        refused(&r, "--heat-max must be a positive angle in degrees");
    }
    assert!(!dir.join("m.png").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A negative number written as a separate word (`--scale -1`, `--radius -.5`) reaches the
/// option's own range check, exactly as `--scale=-1` does, instead of clap's "unexpected
/// argument '-1'".
#[test]
fn negative_numbers_reach_the_range_checks_whether_written_apart_or_with_equals() {
    let dir = temp_dir("negative-values");
    let model = dir.join("m.json");
    let m = model.to_str().expect("utf-8 path");
    let made = nendo(&["sculpt", "--primitive", "plane", "--out", m]);
    assert!(made.status.success(), "{made:?}");
    let stl = dir.join("m.stl");
    let stl = stl.to_str().expect("utf-8 path");
    let out = dir.join("o.json");
    let o = out.to_str().expect("utf-8 path");
    let missing = dir.join("missing.json");
    let missing = missing.to_str().expect("utf-8 path");
    // (arguments before the option, the option, its value, arguments after)
    let cases: &[(&[&str], &str, &str, &[&str])] = &[
        (&["bench", "closest"], "--scale", "-1", &[]),
        (&["emulate", "fastrak"], "--corrupt", "-0.5", &[]),
        (&["emulate", "fastrak"], "--seconds", "-1", &[]),
        (&["export", m, stl], "--tolerance", "-1", &[]),
        (&["export", m, stl], "--scale", "-2", &[]),
        (
            &["sculpt", "--primitive", "sphere"],
            "--radius",
            "-1",
            &["--out", o],
        ),
        (
            &["sculpt", "--primitive", "sphere"],
            "--radius",
            "-.5",
            &["--out", o],
        ),
        (
            &["sculpt", "--primitive", "sphere"],
            "--radius",
            "-inf",
            &["--out", o],
        ),
        (
            &["sculpt", "--primitive", "cylinder"],
            "--height",
            "-1",
            &["--out", o],
        ),
        (
            &["sculpt", "--primitive", "torus"],
            "--minor-radius",
            "-0.1",
            &["--out", o],
        ),
        (
            &["record", "--profile", "fastrak", "--out", o],
            "--seconds",
            "-1",
            &[],
        ),
        (&["refine", m], "--insert-u", "-1", &["--out", o]),
        (
            &["figure", "warp", missing, "--curves", missing],
            "--a",
            "-1",
            &["--out", o],
        ),
        (
            &["figure", "shape", missing, "--mesh", o],
            "--reach",
            "-1",
            &[],
        ),
        (
            &["morph", missing, missing, "--out", o],
            "--match-distance",
            "-1",
            &[],
        ),
    ];
    for &(before, option, value, after) in cases {
        let apart: Vec<&str> = [before, &[option, value], after].concat();
        let joined = format!("{option}={value}");
        let with_equals: Vec<&str> = [before, &[joined.as_str()], after].concat();
        let (a, e) = (nendo(&apart), nendo(&with_equals));
        let a_err = String::from_utf8_lossy(&a.stderr);
        let e_err = String::from_utf8_lossy(&e.stderr);
        assert!(!a.status.success(), "{apart:?}: {a_err}");
        assert!(!a_err.contains("unexpected argument"), "{apart:?}: {a_err}");
        assert_eq!(a.status.code(), e.status.code(), "{apart:?}: {a_err}");
        assert_eq!(a_err, e_err, "{apart:?}");
        assert!(!out.exists(), "{apart:?} wrote {o}");
    }
}
