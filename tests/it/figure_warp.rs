//! Warping figures by moving the curves laid over them (P0 §4.1, Fig. 9 and 10).

use std::path::Path;

use glam::DVec2;
use nendo::curve::{Bezier, Curve};
use nendo::figure::document::FilledPolygon;
use nendo::figure::warp::{WarpOptions, warp_document};
use nendo::figure::{Contour, FigureDocument, Rgb};

fn load(name: &str) -> FigureDocument {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/figures")
        .join(name);
    FigureDocument::from_json(&std::fs::read_to_string(p).unwrap()).unwrap()
}

fn cubic(p: [[f64; 2]; 4]) -> Curve<DVec2> {
    Bezier::new(p.iter().map(|&[x, y]| DVec2::new(x, y)).collect()).into()
}

#[test]
fn warp_by_unchanged_curves_is_the_identity() {
    for name in ["horse.json", "tiger.json"] {
        let doc = load(name);
        let out = warp_document(&doc, &doc.curves, &WarpOptions::default()).unwrap();
        assert_eq!(out.figure, doc.figure, "{name}");
        // No edge is divided: the contour keeps its vertices exactly.
        assert_eq!(out.contour, doc.contour, "{name}");
        assert_eq!(out, doc, "{name}");
    }
}

/// `nendo figure warp` with the figure's own curves writes the figure back unchanged (the
/// contour keeps its vertex count), and `--max-edge` sets how finely a real warp divides edges.
#[test]
fn warp_cli_keeps_the_contour_when_no_curve_moves_and_honours_max_edge() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/figures");
    let dir = std::env::temp_dir().join(format!("nendo-figure-warp-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |curves: &Path, out: &Path, extra: &[&str]| {
        let status = std::process::Command::new(env!("CARGO_BIN_EXE_nendo"))
            .args(["figure", "warp"])
            .arg(data.join("horse.json"))
            .arg("--curves")
            .arg(curves)
            .arg("--out")
            .arg(out)
            .args(extra)
            .status()
            .unwrap();
        assert!(status.success());
        let text = std::fs::read_to_string(out).unwrap();
        FigureDocument::from_json(&text).unwrap()
    };
    let doc = load("horse.json");
    let same = run(&data.join("horse.json"), &dir.join("same.json"), &[]);
    assert_eq!(
        same.contour.as_ref().unwrap().len(),
        doc.contour.as_ref().unwrap().len()
    );
    assert_eq!(same.figure, doc.figure);
    // Move the spine: with --max-edge 5 every edge of the warped contour comes from edges
    // divided into pieces of at most 5 units.
    let mut deformed = doc.curves.clone();
    let spine = doc.curves[0].points().to_vec();
    deformed[0] = Bezier::new(vec![
        spine[0],
        spine[1],
        spine[2],
        spine[3] + DVec2::new(0.0, -20.0),
    ])
    .into();
    let curves = dir.join("deformed.json");
    std::fs::write(
        &curves,
        nendo::figure::document::curves_to_json(&deformed).to_string(),
    )
    .unwrap();
    let c = doc.contour.as_ref().unwrap();
    let expected: usize = c
        .edges()
        .map(|(a, b)| (a.distance(b) / 5.0).ceil().max(1.0) as usize)
        .sum();
    let fine = run(&curves, &dir.join("fine.json"), &["--max-edge", "5"]);
    assert_eq!(fine.contour.as_ref().unwrap().len(), expected);
    let coarse = run(&curves, &dir.join("coarse.json"), &["--max-edge", "inf"]);
    assert_eq!(coarse.contour.as_ref().unwrap().len(), c.len());
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_nendo"))
        .args(["figure", "warp"])
        .arg(data.join("horse.json"))
        .arg("--curves")
        .arg(&curves)
        .arg("--out")
        .arg(dir.join("bad.json"))
        .arg("--max-edge=-1")
        .output()
        .unwrap();
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("positive"));
    std::fs::remove_dir_all(&dir).ok();
}

/// Fig. 10 (c): the head raised by dragging the end of the spine curve while the leg curves
/// stay put — the legs do not move, the head follows the curve's end.
#[test]
fn raising_the_spine_moves_the_head_and_keeps_the_legs() {
    let doc = load("horse.json");
    let mut deformed = doc.curves.clone();
    let spine: Vec<DVec2> = doc.curves[0].points().to_vec();
    let lift = DVec2::new(10.0, -50.0);
    deformed[0] = Bezier::new(vec![
        spine[0],
        spine[1],
        spine[2] + 0.5 * lift,
        spine[3] + lift,
    ])
    .into();
    let out = warp_document(&doc, &deformed, &WarpOptions::default()).unwrap();
    let pairs = doc.figure.metacircles.iter().zip(&out.figure.metacircles);
    let mut head_moves = Vec::new();
    for (a, b) in pairs {
        let moved = b.centre - a.centre;
        if a.centre.y > 330.0 {
            // Hooves, next to the fixed leg curves: barely moved.
            assert!(
                moved.length() < 0.1 * lift.length(),
                "{} moved {}",
                a.centre,
                moved
            );
        }
        if a.centre.x > 400.0 && a.centre.y < 160.0 {
            head_moves.push(moved);
        }
        assert_eq!((a.radius, a.density), (b.radius, b.density));
    }
    assert!(!head_moves.is_empty());
    let mean = head_moves.iter().copied().sum::<DVec2>() / head_moves.len() as f64;
    assert!(
        mean.dot(lift) > 0.5 * lift.length_squared(),
        "head moved {mean}"
    );
    // The curves of the result are the deformed ones.
    assert_eq!(out.curves, deformed);
}

/// Fig. 9: a chequered flag of polygons with curves along its top, bottom and left edges;
/// the top and bottom curves are bent, the left one is not: the left border stays straight
/// and the points on the bent curves follow them exactly.
#[test]
fn chequered_flag_follows_its_top_and_bottom_curves() {
    let (w, h, n) = (200.0, 120.0, 8);
    let mut polygons = Vec::new();
    for j in 0..n / 2 {
        for i in 0..n {
            let (x0, y0) = (i as f64 * w / n as f64, j as f64 * h / (n / 2) as f64);
            let (x1, y1) = (x0 + w / n as f64, y0 + h / (n / 2) as f64);
            let colour = if (i + j) % 2 == 0 {
                Rgb::BLACK
            } else {
                Rgb([200, 30, 30])
            };
            let contour = Contour::new(
                vec![
                    DVec2::new(x0, y0),
                    DVec2::new(x1, y0),
                    DVec2::new(x1, y1),
                    DVec2::new(x0, y1),
                ],
                "square",
            )
            .unwrap();
            polygons.push(FilledPolygon { contour, colour });
        }
    }
    let top = cubic([[0.0, 0.0], [w / 3.0, 0.0], [2.0 * w / 3.0, 0.0], [w, 0.0]]);
    let bottom = cubic([[0.0, h], [w / 3.0, h], [2.0 * w / 3.0, h], [w, h]]);
    let left = cubic([[0.0, 0.0], [0.0, h / 3.0], [0.0, 2.0 * h / 3.0], [0.0, h]]);
    let doc = FigureDocument {
        polygons,
        curves: vec![top, bottom, left.clone()],
        ..Default::default()
    };
    let wave_top = cubic([
        [0.0, 0.0],
        [w / 3.0, -30.0],
        [2.0 * w / 3.0, 30.0],
        [w, 10.0],
    ]);
    let wave_bottom = cubic([
        [0.0, h],
        [w / 3.0, h - 30.0],
        [2.0 * w / 3.0, h + 30.0],
        [w, h + 10.0],
    ]);
    // Corners only (no edge division), so that vertices correspond one to one.
    let corners = WarpOptions {
        max_edge: Some(f64::INFINITY),
        ..WarpOptions::default()
    };
    let out = warp_document(&doc, &[wave_top.clone(), wave_bottom, left], &corners).unwrap();
    let mut on_top = 0;
    for (a, b) in doc.polygons.iter().zip(&out.polygons) {
        assert_eq!(a.colour, b.colour);
        assert_eq!(a.contour.len(), b.contour.len());
        // Vertices of the left border stay on it.
        for (pa, pb) in a.contour.points().iter().zip(b.contour.points()) {
            if pa.x == 0.0 {
                assert!(
                    pb.x.abs() < 1e-6 && (pb.y - pa.y).abs() < 1e-6,
                    "{pa} -> {pb}"
                );
            }
            if pa.y == 0.0 {
                // On the top curve: the warped point is on the bent curve.
                let near = wave_top.closest(*pb, f64::INFINITY).unwrap();
                assert!(near.distance < 1e-6, "{pa} -> {pb}: {}", near.distance);
                on_top += 1;
            }
        }
    }
    assert!(on_top >= 8);
}
