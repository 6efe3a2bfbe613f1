//! Metaball shapes fitted to horizontal sections and deformed through them (P0 §4.3,
//! Fig. 12): fits against known solids (the distance of the mesh to the true sphere and
//! ellipsoid), the identity when no curve moves, the locality of a drag, the closed mesh, and
//! `nendo figure shape` end to end on the shipped torso.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use crate::support::temp_dir as scratch;
use glam::{DVec2, DVec3};
use nendo::curve::Curve;
use nendo::curve::warp::WarpParams;
use nendo::figure::marching::{MeshOptions, iso_surface};
use nendo::figure::shape::{ShapeFitReport, deform, measure_sections};
use nendo::figure::{Contour, Section, Shape, ShapeDocument, ShapeFitOptions, fit_sections};

fn ellipse(a: f64, b: f64, n: usize) -> Contour {
    Contour::new(
        (0..n)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / n as f64;
                DVec2::new(a * t.cos(), b * t.sin())
            })
            .collect(),
        "ellipse",
    )
    .unwrap()
}

/// Sections of the ellipsoid `x²/a² + y²/b² + z²/c² = 1` at `zs`.
fn ellipsoid_sections(a: f64, b: f64, c: f64, zs: &[f64]) -> Vec<Section> {
    zs.iter()
        .map(|&z| {
            let k = (1.0 - (z / c).powi(2)).sqrt();
            Section::new(z, ellipse(a * k, b * k, 48), Vec::new()).unwrap()
        })
        .collect()
}

/// The first-order distance `|g| / |∇g|` of `p` to the ellipsoid `g = Σ x²/a² − 1 = 0` (exact
/// for a sphere; within the square of the distance otherwise).
fn ellipsoid_distance(p: DVec3, a: f64, b: f64, c: f64) -> f64 {
    let g = (p.x / a).powi(2) + (p.y / b).powi(2) + (p.z / c).powi(2) - 1.0;
    let grad = 2.0 * DVec3::new(p.x / (a * a), p.y / (b * b), p.z / (c * c));
    g.abs() / grad.length()
}

#[test]
fn sections_of_a_sphere_and_an_ellipsoid_fit_the_true_surface() {
    for (a, b, c, within, overall) in [(1.0, 1.0, 1.0, 0.005, 0.005), (1.0, 0.6, 0.8, 0.025, 0.06)]
    {
        let zs: Vec<f64> = [-0.8, -0.4, 0.0, 0.4, 0.8].iter().map(|z| z * c).collect();
        let sections = ellipsoid_sections(a, b, c, &zs);
        let (shape, report) = fit_sections(&sections, &ShapeFitOptions::default()).unwrap();
        assert!(report.final_cost < 1e-3 * report.initial_cost, "{report:?}");
        assert!(report.max_distance < 0.005, "{report:?}");
        assert_eq!(report.guards_violated, 0);
        let mesh = iso_surface(&shape, &MeshOptions::default()).unwrap();
        let (mut inner, mut all) = (0.0f64, 0.0f64);
        for p in &mesh.positions {
            let p = p.as_dvec3();
            let d = ellipsoid_distance(p, a, b, c);
            all = all.max(d);
            if p.z.abs() <= 0.8 * c {
                inner = inner.max(d);
            }
        }
        eprintln!(
            "ellipsoid ({a}, {b}, {c}): samples within {:.2e}, mesh within {inner:.4} between the outer sections, {all:.4} overall",
            report.max_distance
        );
        assert!(inner < within, "{inner}");
        assert!(all < overall, "{all}");
    }
}

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/shapes")
        .join(name)
}

fn torso() -> ShapeDocument {
    ShapeDocument::from_json(&std::fs::read_to_string(data("torso.json")).unwrap()).unwrap()
}

/// The shipped torso fitted once for every test.
fn fitted_torso() -> &'static (ShapeDocument, Shape, ShapeFitReport) {
    static FIT: OnceLock<(ShapeDocument, Shape, ShapeFitReport)> = OnceLock::new();
    FIT.get_or_init(|| {
        let doc = torso();
        let (shape, report) = fit_sections(&doc.sections, &ShapeFitOptions::default()).unwrap();
        (doc, shape, report)
    })
}

#[test]
fn the_shipped_torso_fits_its_sections() {
    let (doc, _, report) = fitted_torso();
    assert_eq!(doc.sections.len(), 5);
    assert!(doc.has_moves());
    // Distances in cm on a torso about 36 cm wide: within a millimetre at every sample.
    assert!(report.max_distance < 0.1, "{report:?}");
    assert!(report.rms_distance < 0.03, "{report:?}");
    assert_eq!(report.guards_violated, 0);
}

#[test]
fn unmoved_curves_leave_the_shape_exactly_as_it_was() {
    let (doc, shape, _) = fitted_torso();
    let same: Vec<Vec<Curve<DVec2>>> = doc.sections.iter().map(|s| s.curves.clone()).collect();
    let out = deform(
        shape,
        &doc.sections,
        &same,
        WarpParams::default(),
        None,
        &ShapeFitOptions::default(),
    )
    .unwrap();
    assert_eq!(&out.shape, shape);
    assert_eq!(out.sections, doc.sections);
    assert!(out.moved.iter().all(|m| !m));
    assert!(out.report.is_none());
    // A drag that brings a curve back where it was is no move either.
    let s = &doc.sections[3];
    let there_and_back = s
        .moved_curves(&[nendo::figure::CurveMove::Replace {
            curve: 0,
            deformed: s.curves[0].clone(),
        }])
        .unwrap();
    assert_eq!(there_and_back, s.curves);
}

/// Where the iso-surface crosses the ray from `origin` along `dir` in the plane `z`
/// (bisection on the density, from inside to outside within `reach`).
fn crossing(shape: &Shape, origin: DVec2, dir: DVec2, z: f64, reach: f64) -> f64 {
    let at = |t: f64| {
        let p = origin + dir * t;
        shape.field(DVec3::new(p.x, p.y, z)) - shape.threshold
    };
    let (mut lo, mut hi) = (0.0, reach);
    assert!(at(lo) > 0.0 && at(hi) < 0.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if at(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

#[test]
fn a_dragged_section_moves_the_surface_there_and_not_far_away() {
    let (doc, shape, _) = fitted_torso();
    let deformed: Vec<Vec<Curve<DVec2>>> = doc
        .sections
        .iter()
        .zip(&doc.moves)
        .map(|(s, m)| s.moved_curves(m).unwrap())
        .collect();
    let options = ShapeFitOptions::default();
    let out = deform(
        shape,
        &doc.sections,
        &deformed,
        WarpParams::default(),
        None,
        &options,
    )
    .unwrap();
    assert_eq!(out.moved, vec![false, false, false, true, false]);
    let report = out.report.as_ref().unwrap();
    // The re-fitted surface passes through the warped chest samples…
    let chest = &report.sections[3];
    assert!(chest.rms_distance < 0.1, "{chest:?}");
    assert!(chest.max_distance < 0.5, "{chest:?}");
    // …and the unmoved sections' samples, 10 to 34 cm away, stay on it.
    for s in [0, 1, 2, 4] {
        assert!(
            report.sections[s].max_distance < 0.15,
            "{:?}",
            report.sections[s]
        );
    }
    // On the chest plane, along each drag (front left and right) the surface moved out by the
    // 3 cm the grabbed curve points moved; at the back, under a still curve, and at the sides
    // (the curves' end points, which stay) it did not move.
    let z = doc.sections[3].z;
    let moved_along = |from: DVec2, dir: DVec2| {
        let origin = from - dir * 5.0;
        crossing(&out.shape, origin, dir, z, 20.0) - crossing(shape, origin, dir, z, 20.0)
    };
    for m in &doc.moves[3] {
        let nendo::figure::CurveMove::Grab { from, to, .. } = m else {
            panic!("the torso's moves are grabs");
        };
        let d = moved_along(*from, (*to - *from).normalize());
        eprintln!("chest plane, along the drag from {from}: the surface moved {d:.3} cm");
        assert!((2.7..3.3).contains(&d), "{from}: {d}");
    }
    for deg in [90.0f64, 0.0, 180.0] {
        let t = deg.to_radians();
        let dir = DVec2::new(t.cos(), t.sin());
        let d = moved_along(dir * 8.0, dir);
        eprintln!("chest plane, {deg}°: the surface moved {d:.3} cm");
        assert!(d.abs() < 0.3, "{deg}°: {d}");
    }
    // Far below, at the hips (34 cm down), the surface did not move.
    let hips = doc.sections[0].z;
    for deg in [225.0, 270.0, 315.0] {
        let t = f64::to_radians(deg);
        let dir = DVec2::new(t.cos(), t.sin());
        let d = crossing(&out.shape, DVec2::ZERO, dir, hips, 40.0)
            - crossing(shape, DVec2::ZERO, dir, hips, 40.0);
        eprintln!("hips plane, {deg}°: the surface moved {d:.4} cm");
        assert!(d.abs() < 0.1, "hips {deg}°: {d}");
    }
    // Measured against the sections it was fitted to, the old shape misses the new chest.
    let before = measure_sections(shape, &out.sections, &options);
    assert!(
        before.sections[3].max_distance > 2.0,
        "{:?}",
        before.sections[3]
    );
}

#[test]
fn the_mesh_is_closed_oriented_and_on_the_surface() {
    let (_, shape, _) = fitted_torso();
    let mesh = iso_surface(shape, &MeshOptions::default()).unwrap();
    let mut edges: HashMap<(u32, u32), (u32, i32)> = HashMap::new();
    let mut volume = 0.0;
    let mut agree = 0usize;
    for t in mesh.triangles() {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let e = edges.entry((a.min(b), a.max(b))).or_default();
            e.0 += 1;
            e.1 += if a < b { 1 } else { -1 };
        }
        let [a, b, c] = t.map(|v| mesh.positions[v as usize].as_dvec3());
        volume += a.dot(b.cross(c)) / 6.0;
        let face = (b - a).cross(c - a);
        let n: DVec3 = t.iter().map(|&v| mesh.normals[v as usize].as_dvec3()).sum();
        if face.dot(n) > 0.0 {
            agree += 1;
        }
    }
    // Closed and consistently oriented: every edge has two triangles, one each way.
    assert!(edges.values().all(|&(n, balance)| n == 2 && balance == 0));
    // One piece without handles: Euler characteristic V − E + F = 2.
    let euler = mesh.positions.len() as i64 - edges.len() as i64 + mesh.triangle_count() as i64;
    assert_eq!(euler, 2);
    // Outward: a positive volume, near the torso's (an elliptic cylinder of ~16 × 11 cm over
    // 44 cm is about 24 000 cm³).
    assert!((15_000.0..40_000.0).contains(&volume), "{volume}");
    // The gradient normals face the way the triangles do (degenerate slivers aside).
    assert!(agree * 1000 >= mesh.triangle_count() * 999, "{agree}");
    // Every vertex lies on the iso-surface.
    for p in &mesh.positions {
        let (f, g) = shape.field_and_gradient(p.as_dvec3());
        assert!((f - shape.threshold).abs() / g.length() < 1e-3, "{p}");
    }
    assert!(nendo::figure::marching::is_closed(&mesh));
}

fn nendo(args: &[&std::ffi::OsStr]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_nendo"))
        .arg("figure")
        .arg("shape")
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn shape_cli_writes_the_mesh_the_picture_and_the_deformed_shape() {
    let dir = scratch("cli");
    let (obj, png, out) = (
        dir.join("torso.obj"),
        dir.join("torso.png"),
        dir.join("out.json"),
    );
    let o = nendo(&[
        data("torso.json").as_os_str(),
        "--mesh".as_ref(),
        obj.as_os_str(),
        "--png".as_ref(),
        png.as_os_str(),
        "--size".as_ref(),
        "320x240".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(summary["moved_sections"], serde_json::json!([3]));
    assert_eq!(summary["mesh"]["closed"], true);
    assert!(summary["fit"]["max_distance"].as_f64().unwrap() < 0.1);
    assert!(summary["refit"]["max_distance"].as_f64().unwrap() < 0.5);
    // The OBJ reads back with its normals and as many vertices and triangles as reported.
    let (models, _) = tobj::load_obj(&obj, &tobj::LoadOptions::default()).unwrap();
    let m = &models[0].mesh;
    assert_eq!(
        m.positions.len() / 3,
        summary["mesh"]["vertices"].as_u64().unwrap() as usize
    );
    assert_eq!(
        m.indices.len() / 3,
        summary["mesh"]["triangles"].as_u64().unwrap() as usize
    );
    assert_eq!(m.normals.len(), m.positions.len());
    // The picture: the asked size, clay in the middle, background in the corner.
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (320, 240));
    let px = |x: u32, y: u32| {
        let k = ((y * info.width + x) * 4) as usize;
        [buf[k], buf[k + 1], buf[k + 2]]
    };
    assert_ne!(px(160, 120), px(2, 2));
    // The written shape has the deformed chest, fitted balls and no moves: running it again
    // fits nothing, moves nothing, and meshes the same surface.
    let written = ShapeDocument::from_json(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert!(!written.has_moves() && written.shape.is_some());
    let obj2 = dir.join("again.obj");
    let o = nendo(&[out.as_os_str(), "--mesh".as_ref(), obj2.as_os_str()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let again: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(again["fit"].is_null() && again["refit"].is_null());
    assert_eq!(again["moved_sections"], serde_json::json!([]));
    assert_eq!(
        std::fs::read(&obj).unwrap(),
        std::fs::read(&obj2).unwrap(),
        "the same shape meshes to the same file"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn shape_cli_refuses_bad_input_without_writing() {
    let dir = scratch("bad");
    let bad = dir.join("bad.json");
    std::fs::write(
        &bad,
        r#"{"format": "nendo-shape", "version": 1, "sections": [{"z": 0, "contour": [[0, 0], [1, 0], [0, 1]], "moves": [{"curve": 0, "from": [0, 0], "to": [1, 1]}]}]}"#,
    )
    .unwrap();
    let obj = dir.join("bad.obj");
    let torso = data("torso.json");
    let ply = dir.join("x.ply");
    let cases: [(Vec<&std::ffi::OsStr>, &str); 3] = [
        (
            vec![bad.as_os_str(), "--mesh".as_ref(), obj.as_os_str()],
            "names curve 0",
        ),
        (
            vec![torso.as_os_str(), "--mesh".as_ref(), ply.as_os_str()],
            "unknown mesh format",
        ),
        (
            vec![
                torso.as_os_str(),
                "--mesh".as_ref(),
                obj.as_os_str(),
                "--resolution".as_ref(),
                "1000".as_ref(),
            ],
            "--resolution",
        ),
    ];
    for (args, needle) in cases {
        let o = nendo(&args);
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(needle), "{err}");
        assert!(!obj.exists() && !ply.exists());
    }
    std::fs::remove_dir_all(&dir).ok();
}
