//! Meshes written by the library's own mesher read back with independent readers (`tobj`,
//! `stl_io`, `gltf`) and checked: same vertices and triangles, unit normals, a closed sphere
//! with the right volume, the up axes (GLB and OBJ +Y by default: model `(x, y, z)` as
//! `(x, z, −y)`; OBJ `--up z` and STL as they are), OBJ's `s 1`, and `nendo export` on the
//! command line.

use std::collections::HashMap;
use std::process::Command;

use crate::support::temp_dir;
use glam::{DVec3, Vec3};
use nendo::mesh::{MeshFormat, Tessellation, TriMesh, UpAxis, save_mesh, save_mesh_up, tessellate};
use nendo::model::Model;
use nendo::surface::{Op, Primitive, PrimitiveParams, deform};

const TOLERANCE: f64 = 1e-3;

/// The paper's sphere (8 × 4 patches, radius 3, two poles), welded.
fn sphere_mesh() -> TriMesh {
    let grid = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .expect("sphere");
    tessellate(&grid.patches(), &Tessellation::with_tolerance(TOLERANCE)).welded()
}

/// Every undirected edge is shared by exactly two triangles, traversed once each way.
fn assert_closed_and_oriented(positions: &[Vec3], indices: &[u32]) {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for t in indices.chunks_exact(3) {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            *directed.entry((a, b)).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &directed {
        assert_eq!(n, 1, "edge {a}->{b} used {n} times in one direction");
        assert_eq!(
            directed.get(&(b, a)),
            Some(&1),
            "edge {a}-{b} at {:?} is on a hole",
            positions[a as usize]
        );
    }
}

/// Volume enclosed by a closed triangle mesh (divergence theorem).
fn volume(positions: &[Vec3], indices: &[u32]) -> f64 {
    indices
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| positions[i as usize].as_dvec3());
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

#[test]
fn sphere_is_closed_round_and_outward() {
    let mesh = sphere_mesh();
    assert_closed_and_oriented(&mesh.positions, &mesh.indices);
    let r = 3.0f64;
    let exact = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    let v = volume(&mesh.positions, &mesh.indices);
    // Chords cut inside by at most the tolerance over the area; the cubic arcs of the
    // primitive deviate from the circle by ~1e-5 of the radius.
    let area = 4.0 * std::f64::consts::PI * r * r;
    assert!(
        (v - exact).abs() <= area * TOLERANCE + 1e-3,
        "volume {v} vs {exact}"
    );
    assert!(
        v > 0.0,
        "triangles wind counter-clockwise seen from outside"
    );
    for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
        let radial = p.as_dvec3().length();
        assert!((radial - r).abs() < 1e-3, "vertex off the sphere: {radial}");
        assert!((n.length() - 1.0).abs() < 1e-5);
        assert!(
            n.as_dvec3().dot(p.as_dvec3() / radial) > 0.999,
            "normal not radial at {p}"
        );
    }
}

#[test]
fn obj_stl_glb_read_back_the_same_mesh() {
    let dir = temp_dir("formats");
    // A sphere, and a pushed plane (an open surface with a dent).
    let mut plane = Primitive::Plane
        .build(&PrimitiveParams::default())
        .expect("plane");
    let op = Op::Push {
        at: DVec3::new(0.5, 0.5, 0.0),
        dir: -DVec3::Z,
        depth: 0.6,
        radius: 1.25,
    };
    deform(&mut plane, &op, Default::default()).expect("push");
    let pushed = tessellate(&plane.patches(), &Tessellation::with_tolerance(TOLERANCE)).welded();
    for (name, mesh) in [("sphere", sphere_mesh()), ("pushed", pushed)] {
        // OBJ
        let obj = dir.join(format!("{name}.obj"));
        save_mesh(&obj, MeshFormat::Obj, &mesh).expect("write OBJ");
        let options = tobj::LoadOptions {
            single_index: true,
            triangulate: true,
            ..Default::default()
        };
        let text = std::fs::read_to_string(&obj).expect("read OBJ");
        assert!(
            text.contains("\ns 1\n"),
            "{name}: OBJ asks for smooth shading"
        );
        assert!(
            !text.contains("0.00000"),
            "{name}: OBJ numbers are short (exponents, not runs of zeros)"
        );
        let (models, _) = tobj::load_obj(&obj, &options).expect("tobj reads it");
        assert_eq!(models.len(), 1);
        let m = &models[0].mesh;
        assert_eq!(m.indices.len(), mesh.indices.len(), "{name}: OBJ triangles");
        assert_eq!(
            m.positions.len(),
            3 * mesh.positions.len(),
            "{name}: OBJ vertices"
        );
        assert_eq!(
            m.normals.len(),
            m.positions.len(),
            "{name}: OBJ has a normal per vertex"
        );
        for (k, &i) in m.indices.iter().enumerate() {
            let i = i as usize;
            let p = Vec3::new(
                m.positions[3 * i],
                m.positions[3 * i + 1],
                m.positions[3 * i + 2],
            );
            let n = Vec3::new(m.normals[3 * i], m.normals[3 * i + 1], m.normals[3 * i + 2]);
            let j = mesh.indices[k] as usize;
            // Y-up: model (x, y, z) is (x, z, -y) in the file.
            let want = mesh.positions[j];
            assert_eq!(
                p,
                Vec3::new(want.x, want.z, -want.y),
                "{name}: OBJ position, Y-up (shortest round-trip text is exact)"
            );
            let want = mesh.normals[j];
            assert_eq!(n, Vec3::new(want.x, want.z, -want.y), "{name}: OBJ normal");
        }
        // `--up z`: the model's coordinates as they are.
        let obj_z = dir.join(format!("{name}-z.obj"));
        save_mesh_up(&obj_z, MeshFormat::Obj, &mesh, UpAxis::Z).expect("write OBJ");
        let (models, _) = tobj::load_obj(&obj_z, &options).expect("tobj reads it");
        let m = &models[0].mesh;
        for (k, &i) in m.indices.iter().enumerate() {
            let i = i as usize;
            let p = Vec3::new(
                m.positions[3 * i],
                m.positions[3 * i + 1],
                m.positions[3 * i + 2],
            );
            assert_eq!(
                p, mesh.positions[mesh.indices[k] as usize],
                "{name}: Z-up OBJ"
            );
        }

        // Binary STL
        let stl = dir.join(format!("{name}.stl"));
        save_mesh(&stl, MeshFormat::Stl, &mesh).expect("write STL");
        let bytes = std::fs::read(&stl).expect("read STL");
        assert_eq!(
            bytes.len(),
            84 + 50 * mesh.triangle_count(),
            "{name}: binary STL size"
        );
        let read = stl_io::read_stl(&mut std::fs::File::open(&stl).expect("open"))
            .expect("stl_io reads it");
        assert_eq!(
            read.faces.len(),
            mesh.triangle_count(),
            "{name}: STL triangles"
        );
        assert_eq!(
            read.vertices.len(),
            mesh.positions.len(),
            "{name}: STL distinct vertices"
        );
        for (face, t) in read.faces.iter().zip(mesh.triangles()) {
            let got: [Vec3; 3] = face.vertices.map(|i| Vec3::from_array(read.vertices[i].0));
            let want = t.map(|i| mesh.positions[i as usize]);
            assert_eq!(got, want, "{name}: STL triangle");
            let n = Vec3::from_array(face.normal.0);
            let geometric = (want[1] - want[0]).cross(want[2] - want[0]).normalize();
            assert!((n - geometric).length() < 1e-5, "{name}: STL facet normal");
        }

        // GLB
        let glb = dir.join(format!("{name}.glb"));
        save_mesh(&glb, MeshFormat::Glb, &mesh).expect("write GLB");
        let bytes = std::fs::read(&glb).expect("read GLB");
        let gltf = gltf::Gltf::from_slice(&bytes).expect("gltf validates it");
        let blob = gltf.blob.as_deref().expect("a BIN chunk");
        let gmesh = gltf.meshes().next().expect("one mesh");
        let primitive = gmesh.primitives().next().expect("one primitive");
        assert_eq!(primitive.mode(), gltf::mesh::Mode::Triangles);
        let reader = primitive.reader(|_| Some(blob));
        let positions: Vec<Vec3> = reader
            .read_positions()
            .expect("positions")
            .map(Vec3::from_array)
            .collect();
        let normals: Vec<Vec3> = reader
            .read_normals()
            .expect("normals")
            .map(Vec3::from_array)
            .collect();
        let indices: Vec<u32> = reader.read_indices().expect("indices").into_u32().collect();
        let y_up = |v: &Vec3| Vec3::new(v.x, v.z, -v.y);
        let want: Vec<Vec3> = mesh.positions.iter().map(y_up).collect();
        assert_eq!(positions, want, "{name}: GLB positions, Y-up");
        let want: Vec<Vec3> = mesh.normals.iter().map(y_up).collect();
        assert_eq!(normals, want, "{name}: GLB normals, Y-up");
        assert_eq!(indices, mesh.indices, "{name}: GLB indices");
        let bounds = primitive.bounding_box();
        let (lo, hi) = mesh.bounds().expect("bounds");
        // +Y up: the model's highest point (largest z) is glTF's largest y, and the model's
        // +y side is glTF's -z side.
        assert_eq!(
            (Vec3::from_array(bounds.min), Vec3::from_array(bounds.max)),
            (Vec3::new(lo.x, lo.z, -hi.y), Vec3::new(hi.x, hi.z, -lo.y))
        );
        let top = mesh
            .positions
            .iter()
            .copied()
            .max_by(|a, b| a.z.total_cmp(&b.z))
            .expect("vertices");
        let highest = positions
            .iter()
            .copied()
            .max_by(|a, b| a.y.total_cmp(&b.y))
            .expect("vertices");
        assert_eq!(highest.y, top.z, "{name}: GLB's up (+Y) is the model's +Z");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn export_command_writes_the_mesh_and_rejects_bad_input() {
    let dir = temp_dir("cli");
    let model_path = dir.join("torus.nendo.json");
    let torus = Primitive::Torus
        .build(&PrimitiveParams::default())
        .expect("torus");
    Model::new(torus).write(&model_path).expect("write model");
    let out = dir.join("torus.glb");
    let status = Command::new(env!("CARGO_BIN_EXE_nendo"))
        .args([
            "export",
            model_path.to_str().expect("utf-8"),
            out.to_str().expect("utf-8"),
            "--tolerance",
            "0.002",
        ])
        .output()
        .expect("nendo runs");
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let bytes = std::fs::read(&out).expect("the GLB exists");
    let gltf = gltf::Gltf::from_slice(&bytes).expect("valid GLB");
    let primitive = gltf
        .meshes()
        .next()
        .and_then(|m| m.primitives().next())
        .expect("a primitive");
    let reader = primitive.reader(|_| gltf.blob.as_deref());
    let positions: Vec<Vec3> = reader
        .read_positions()
        .expect("positions")
        .map(Vec3::from_array)
        .collect();
    let indices: Vec<u32> = reader.read_indices().expect("indices").into_u32().collect();
    // A torus is closed: watertight across its two closed seams.
    assert_closed_and_oriented(&positions, &indices);

    // OBJ: Y-up by default, `--up z` as the model; the same vertices otherwise.
    let first_vertex = |up: Option<&str>| -> Vec3 {
        let out = dir.join(format!("torus-{}.obj", up.unwrap_or("default")));
        let mut args = vec![
            "export",
            model_path.to_str().expect("utf-8"),
            out.to_str().expect("utf-8"),
        ];
        if let Some(up) = up {
            args.extend(["--up", up]);
        }
        let o = Command::new(env!("CARGO_BIN_EXE_nendo"))
            .args(&args)
            .output()
            .expect("nendo runs");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = std::fs::read_to_string(&out).expect("the OBJ exists");
        let line = text
            .lines()
            .find(|l| l.starts_with("v "))
            .expect("a vertex");
        let xyz: Vec<f32> = line[2..]
            .split(' ')
            .map(|x| x.parse().expect("a number"))
            .collect();
        Vec3::new(xyz[0], xyz[1], xyz[2])
    };
    let (default, y, z) = (
        first_vertex(None),
        first_vertex(Some("y")),
        first_vertex(Some("z")),
    );
    assert_eq!(default, y);
    assert_eq!(y, Vec3::new(z.x, z.z, -z.y));

    for (args, code) in [
        (
            vec![
                "export",
                model_path.to_str().unwrap_or(""),
                "x.obj",
                "--tolerance",
                "0",
            ],
            2,
        ),
        (
            vec!["export", model_path.to_str().unwrap_or(""), "x.ply"],
            2,
        ),
        (vec!["export", "/nonexistent/model.json", "x.obj"], 1),
        // glTF is always Y-up, STL always Z-up.
        (
            vec![
                "export",
                model_path.to_str().unwrap_or(""),
                "x.glb",
                "--up",
                "z",
            ],
            2,
        ),
        (
            vec![
                "export",
                model_path.to_str().unwrap_or(""),
                "x.stl",
                "--up",
                "y",
            ],
            2,
        ),
        (
            vec![
                "export",
                model_path.to_str().unwrap_or(""),
                "x.obj",
                "--up",
                "x",
            ],
            2,
        ),
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_nendo"))
            .args(&args)
            .current_dir(&dir)
            .output()
            .expect("nendo runs");
        assert_eq!(
            o.status.code(),
            Some(code),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(!o.stderr.is_empty(), "{args:?} explains itself");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
