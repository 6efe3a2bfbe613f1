//! Bounded memory: `nendo export` sizes the mesh before allocating it and refuses one over
//! `--max-triangles` with the size; `nendo check` streams `--against` and refuses `--samples`
//! that would hold too many pole directions; the size estimate matches the mesher.

use std::path::Path;

use crate::support::{run, temp_dir};
use nendo::mesh::{Tessellation, estimate, tessellate};
use nendo::surface::{Primitive, PrimitiveParams};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Writes a primitive with `patches` (`"MxN"`) to `dir/name.json` through `nendo sculpt`.
fn sculpt(dir: &Path, name: &str, primitive: &str, patches: &str) -> String {
    let out = dir.join(format!("{name}.json"));
    let path = out.display().to_string();
    let made = run(&[
        "sculpt",
        "--primitive",
        primitive,
        "--patches",
        patches,
        "--out",
        &path,
    ]);
    assert!(made.status.success(), "{made:?}");
    path
}

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn export_refuses_the_issues_meshes_with_their_size() {
    let dir = temp_dir("memory-export");
    // The issue: 128 × 64 sphere at 1e-9 tried to allocate 52 GB; every patch takes the cap of
    // 256 × 256 cells, 8192 × 131 072 triangles.
    let sphere = sculpt(&dir, "sphere", "sphere", "128x64");
    let stl = dir.join("sphere.stl").display().to_string();
    let out = run(&["export", &sphere, &stl, "--tolerance", "1e-9"]);
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    let err = stderr(&out);
    assert!(err.contains("1073741824 triangles"), "{err}");
    assert!(err.contains("--max-triangles"), "{err}");
    assert!(!Path::new(&stl).exists());
    // A limit of one triangle refuses even the default export; raising it lets it through.
    let small = sculpt(&dir, "small", "sphere", "8x4");
    let obj = dir.join("small.obj").display().to_string();
    let out = run(&["export", &small, &obj, "--max-triangles", "1"]);
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    assert!(
        stderr(&out).contains("limit of 1 triangles"),
        "{}",
        stderr(&out)
    );
    let out = run(&["export", &small, &obj]);
    assert!(out.status.success(), "{out:?}");
    assert!(Path::new(&obj).is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn export_refuses_a_256_by_256_grid_at_1e_7() {
    let dir = temp_dir("memory-export-256");
    let torus = sculpt(&dir, "torus", "torus", "256x256");
    let glb = dir.join("torus.glb").display().to_string();
    let out = run(&["export", &torus, &glb, "--tolerance", "1e-7"]);
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    let err = stderr(&out);
    assert!(
        err.contains("triangles") && err.contains("--max-triangles"),
        "{err}"
    );
    assert!(!Path::new(&glb).exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_estimate_is_the_raw_mesh_and_bounds_the_welded_one() {
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let primitives = [
        Primitive::Plane,
        Primitive::Cylinder,
        Primitive::Sphere,
        Primitive::Torus,
    ];
    for _ in 0..12 {
        let primitive = primitives[rng.gen_range(0..primitives.len())];
        // Even counts: closed directions of a sphere or torus need them.
        let counts = (2 * rng.gen_range(3..6), 2 * rng.gen_range(2..4));
        let grid = primitive
            .build(&PrimitiveParams {
                patches: Some(counts),
                ..PrimitiveParams::default()
            })
            .expect("primitive");
        let tolerance = 10f64.powf(rng.gen_range(-5.0..-1.0));
        let settings = Tessellation::with_tolerance(tolerance);
        let patches = grid.patches();
        let size = estimate(&patches, &settings);
        let raw = tessellate(&patches, &settings);
        assert_eq!(size.triangles, raw.triangle_count() as u64);
        assert_eq!(size.vertices, raw.positions.len() as u64);
        let welded = raw.welded();
        assert!(welded.triangle_count() as u64 <= size.triangles);
        assert!(welded.positions.len() as u64 <= size.vertices);
    }
}

#[test]
fn check_streams_against_and_refuses_too_many_pole_samples() {
    let dir = temp_dir("memory-check");
    let sphere = sculpt(&dir, "sphere", "sphere", "128x64");
    // 128 patches around each pole × 100 000 samples = 12.8 million directions: refused.
    let out = run(&["check", &sphere, "--samples", "100000"]);
    assert_eq!(out.status.code(), Some(2), "{out:?}");
    let err = stderr(&out);
    assert!(
        err.contains("12800000 pole directions") && err.contains("--samples"),
        "{err}"
    );
    // Without a pole the same --samples is within the bound.
    let plane = sculpt(&dir, "plane", "plane", "2x2");
    let out = run(&["check", &plane, "--samples", "100000"]);
    assert!(out.status.success(), "{out:?}");
    // --against on 8192 patches: 13 million samples, streamed.
    let out = run(&["check", &sphere, "--against", &sphere]);
    assert!(out.status.success(), "{out:?}");
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(report["deviation"]["samples"], 8192 * 1600);
    assert_eq!(report["deviation"]["max"], 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}
