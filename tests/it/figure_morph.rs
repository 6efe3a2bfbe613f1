//! Morphing the shipped horse into the shipped tiger (P0 §4.2, Fig. 11): the first and
//! last frames are the source and the destination, and `nendo morph` writes the frames.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::support::temp_dir as scratch;
use nendo::figure::iso::polyline_distance;
use nendo::figure::morph::{Morph, MorphOptions};
use nendo::figure::picture::{Backdrop, PictureOptions, draw};
use nendo::figure::{FigureDocument, RasterView, Rgb};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/figures")
        .join(name)
}

fn load(name: &str) -> FigureDocument {
    FigureDocument::from_json(&std::fs::read_to_string(data(name)).unwrap()).unwrap()
}

#[test]
fn end_frames_are_the_source_and_the_destination() {
    let (src, dst) = (load("horse.json"), load("tiger.json"));
    let view = RasterView {
        origin: glam::DVec2::ZERO,
        scale: 1.0,
    };
    let options = PictureOptions::default();
    let backdrop = Backdrop {
        background: Some(Rgb::WHITE),
        ..Backdrop::default()
    };
    for skeleton in [false, true] {
        let morph = Morph::new(
            (&src.figure, &src.curves),
            (&dst.figure, &dst.curves),
            MorphOptions {
                skeleton,
                ..MorphOptions::default()
            },
        )
        .unwrap();
        for (t, doc) in [(0.0, &src), (1.0, &dst)] {
            let frame = draw(&morph.at(t).unwrap(), &backdrop, &view, &options).unwrap();
            let truth = draw(&doc.figure, &backdrop, &view, &options).unwrap();
            let iso = polyline_distance(&frame.boundary, &truth.boundary)
                .max(polyline_distance(&truth.boundary, &frame.boundary));
            let differing = frame
                .image
                .pixels
                .chunks_exact(4)
                .zip(truth.image.pixels.chunks_exact(4))
                .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 1))
                .count();
            eprintln!(
                "skeleton {skeleton} t {t}: iso-curve distance {iso:.3e} px, {differing} pixels differ"
            );
            assert!(iso < 1e-6, "t {t}: {iso}");
            assert_eq!(differing, 0, "t {t}");
        }
        // In between, the figure is one piece or nearly: every frame keeps most of the area.
        let area = |f: &nendo::figure::Figure| {
            let c = nendo::figure::raster::coverage(f, &view, options.size, 1).unwrap();
            c.alpha.iter().map(|&a| a as f64).sum::<f64>()
        };
        let (a0, a1) = (area(&src.figure), area(&dst.figure));
        for k in 1..8 {
            let a = area(&morph.at(k as f64 / 8.0).unwrap());
            assert!(
                a > 0.6 * a0.min(a1) && a < 1.4 * a0.max(a1),
                "t {}: area {a} ({a0}, {a1})",
                k as f64 / 8.0
            );
        }
    }
}

#[test]
fn matching_pairs_everything_with_few_dummies() {
    let (src, dst) = (load("horse.json"), load("tiger.json"));
    let morph = Morph::new(
        (&src.figure, &src.curves),
        (&dst.figure, &dst.curves),
        MorphOptions::default(),
    )
    .unwrap();
    let s = morph.stats();
    eprintln!("{s:?}, {} pairs", morph.pairs().len());
    assert_eq!(
        s.forward + s.dummies_destination,
        src.figure.metacircles.len()
    );
    assert!(
        morph.pairs().len()
            >= src
                .figure
                .metacircles
                .len()
                .max(dst.figure.metacircles.len())
    );
    // Every destination metacircle is in some pair.
    let mut seen = vec![false; dst.figure.metacircles.len()];
    for (_, b) in morph.pairs() {
        if let Some(j) = b.index {
            seen[j] = true;
        }
    }
    assert!(seen.iter().all(|&s| s));
}

#[test]
fn morph_cli_writes_frames_whose_ends_match_the_figures() {
    let out = scratch("cli");
    let status = Command::new(env!("CARGO_BIN_EXE_nendo"))
        .args(["morph"])
        .arg(data("horse.json"))
        .arg(data("tiger.json"))
        .args(["--frames", "4", "--size", "256x256", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let summary: serde_json::Value = serde_json::from_slice(&status.stdout).unwrap();
    assert_eq!(summary["frames"], 4);
    for i in 0..4 {
        assert!(out.join(format!("frame_{i:04}.png")).is_file());
        assert!(out.join(format!("frame_{i:04}.svg")).is_file());
    }
    // Frame 0 decodes to the source drawn in the same view (both documents view 0..512).
    let decoder = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(out.join("frame_0000.png")).unwrap(),
    ));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (256, 256));
    let src = load("horse.json");
    let options = PictureOptions {
        size: nendo::figure::ImageSize::new(256, 256).unwrap(),
        ..PictureOptions::default()
    };
    let view = RasterView::fit(
        glam::DVec2::ZERO,
        glam::DVec2::splat(512.0),
        options.size,
        0.0,
    );
    let truth = draw(
        &src.figure,
        &Backdrop {
            background: Some(Rgb::WHITE),
            ..Backdrop::default()
        },
        &view,
        &options,
    )
    .unwrap();
    assert_eq!(&buf[..info.buffer_size()], &truth.image.pixels[..]);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn morph_cli_leaves_out_the_svg_with_no_svg() {
    let out = scratch("no-svg");
    let status = Command::new(env!("CARGO_BIN_EXE_nendo"))
        .args(["morph"])
        .arg(data("horse.json"))
        .arg(data("tiger.json"))
        .args(["--frames", "2", "--no-svg", "--size", "64x64", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(status.status.success());
    for i in 0..2 {
        assert!(out.join(format!("frame_{i:04}.png")).is_file());
        assert!(!out.join(format!("frame_{i:04}.svg")).exists());
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn morph_cli_refuses_bad_input() {
    let out = scratch("bad");
    let bad = out.join("bad.json");
    std::fs::write(&bad, r#"{"format": "nendo-figure", "version": 1, "metacircles": [{"centre": [0, 0], "radius": "big", "density": 1}]}"#).unwrap();
    let run = |args: &[&std::ffi::OsStr]| {
        Command::new(env!("CARGO_BIN_EXE_nendo"))
            .arg("morph")
            .args(args)
            .output()
            .unwrap()
    };
    let horse = data("horse.json");
    let o = run(&[
        horse.as_os_str(),
        bad.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(!o.status.success());
    // Named once: before, the JSON error was printed twice (as the message and its source).
    assert_eq!(
        String::from_utf8_lossy(&o.stderr)
            .matches("metacircles[0].radius")
            .count(),
        1,
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let o = run(&[
        horse.as_os_str(),
        horse.as_os_str(),
        "--frames".as_ref(),
        "1".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--frames"));
    // Curves that do not correspond (the destination has none).
    let bare = out.join("bare.json");
    std::fs::write(&bare, r#"{"format": "nendo-figure", "version": 1, "metacircles": [{"centre": [0, 0], "radius": 5, "density": 1}]}"#).unwrap();
    let o = run(&[
        horse.as_os_str(),
        bare.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(!o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("curves"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // `--out` naming a file: before, "cannot create …: File exists".
    let o = run(&[
        horse.as_os_str(),
        horse.as_os_str(),
        "--out".as_ref(),
        bare.as_os_str(),
    ]);
    assert!(!o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("is not a directory"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let _ = std::fs::remove_dir_all(&out);
}
