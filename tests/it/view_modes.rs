//! The view's modes without a GPU (issue 27): orthographic picking against a brute-force ray
//! intersection and a stroke made in the orthographic view, the lines refinement made drawn
//! fainter (and kept in the model file), the matcap remembered in the settings.

use glam::{DMat3, DVec3, Vec2, Vec3};
use nendo::editor::input::{Button, PointerInput};
use nendo::editor::scene::{Overlays, SurfaceDisplay, model_lines};
use nendo::editor::{Command, Document, Modeller, OrbitCamera, Projection};
use nendo::mesh::{Ray, Tessellation};
use nendo::model::Model;
use nendo::render::{LineBatch, Matcap, Rgba};
use nendo::surface::{Op, Patch, PatchPoints, Primitive, PrimitiveParams};

use crate::support::temp_dir;

/// The nearest intersection of `ray` with the patches by brute force: Newton's method on
/// `S(u, v) − (o + t d) = 0` from 6 × 6 seeds in every patch, kept where it converges inside
/// the patch; `(t, point)` of the smallest `t`.
fn brute_force_hit(patches: &[PatchPoints], ray: &Ray) -> Option<(f64, DVec3)> {
    let mut best: Option<(f64, DVec3)> = None;
    for p in patches {
        let patch = Patch::new(*p);
        for i in 0..6 {
            for j in 0..6 {
                let (mut u, mut v) = ((i as f64 + 0.5) / 6.0, (j as f64 + 0.5) / 6.0);
                let mut t = (patch.eval(u, v) - ray.origin).dot(ray.direction);
                let mut converged = false;
                for _ in 0..40 {
                    let f = patch.frame(u.clamp(-0.2, 1.2), v.clamp(-0.2, 1.2));
                    let residual = f.point - (ray.origin + t * ray.direction);
                    if residual.length() < 1e-12 {
                        converged = true;
                        break;
                    }
                    let jac = DMat3::from_cols(f.du, f.dv, -ray.direction);
                    if jac.determinant().abs() < 1e-14 {
                        break;
                    }
                    let step = jac.inverse() * residual;
                    u -= step.x;
                    v -= step.y;
                    t -= step.z;
                }
                let inside = (-1e-9..=1.0 + 1e-9).contains(&u) && (-1e-9..=1.0 + 1e-9).contains(&v);
                if converged && inside && t > 0.0 && best.is_none_or(|(b, _)| t < b) {
                    best = Some((t, patch.eval(u, v)));
                }
            }
        }
    }
    best
}

/// Picking under the cursor in the orthographic view hits the surface point a brute-force
/// intersection of the same ray finds, and that ray is the one the view draws: parallel to
/// the view direction, through the pixel's unprojected points.
#[test]
fn orthographic_picking_hits_the_brute_force_point() {
    let mut doc = Document::new(Model::new(
        Primitive::Sphere
            .build(&PrimitiveParams::default())
            .expect("sphere"),
    ));
    let bump = Op::Push {
        at: DVec3::new(0.0, -3.0, 0.4),
        dir: DVec3::Y,
        depth: -0.6,
        radius: 1.2,
    };
    doc.apply(&bump).expect("a pulled bump");
    let patches = doc.model().surface.patches();
    let display = SurfaceDisplay::new(&patches, &Tessellation::DISPLAY);
    let size = Vec2::new(640.0, 480.0);
    let (mut hits, mut misses, mut worst) = (0, 0, 0.0f64);
    for (yaw, pitch) in [(-1.2f32, 0.3f32), (0.4, -0.7), (2.5, 1.2)] {
        let mut camera = OrbitCamera {
            yaw,
            pitch,
            projection: Projection::Orthographic,
            ..OrbitCamera::default()
        };
        camera.frame(&display.mesh.positions, size.x / size.y);
        let inverse = camera.view(size.x / size.y).clip_from_world.inverse();
        for i in 0..9 {
            for j in 0..7 {
                let pixel = Vec2::new(40.0 + 70.0 * i as f32, 30.0 + 70.0 * j as f32);
                let ray = camera.ray(pixel, size);
                // The drawn ray: the pixel's NDC unprojected at the near and far depths.
                let ndc = Vec2::new(2.0 * pixel.x / size.x - 1.0, 1.0 - 2.0 * pixel.y / size.y);
                let near = inverse
                    .project_point3(Vec3::new(ndc.x, ndc.y, 0.0))
                    .as_dvec3();
                let far = inverse
                    .project_point3(Vec3::new(ndc.x, ndc.y, 1.0))
                    .as_dvec3();
                let drawn = (far - near).normalize();
                assert!((drawn - ray.direction).length() < 1e-5, "parallel rays");
                let off =
                    (near - ray.origin) - ray.direction * (near - ray.origin).dot(ray.direction);
                assert!(off.length() < 1e-3, "the ray is the drawn one: {off}");
                let picked = nendo::mesh::pick(&patches, &display.mesh, &ray);
                let brute = brute_force_hit(&patches, &ray);
                match (picked, brute) {
                    (Some(hit), Some((t, point))) => {
                        hits += 1;
                        let d = (hit.point - point).length();
                        worst = worst.max(d);
                        assert!(
                            d < 1e-7,
                            "pixel {pixel}: picked {:?}, brute force {point:?} ({d})",
                            hit.point
                        );
                        assert!((hit.t - t).abs() < 1e-7);
                    }
                    (None, None) => misses += 1,
                    (a, b) => panic!("pixel {pixel}: picked {a:?}, brute force {b:?}"),
                }
            }
        }
    }
    eprintln!(
        "orthographic picks: {hits} hits (largest distance to the brute-force point {worst:.1e}), {misses} misses"
    );
    assert!(hits > 60 && misses > 10, "{hits} hits, {misses} misses");
}

/// The dent's centre: the centroid of the surface below z = 0 weighted by depth and area
/// (`Σ x (−z) |S_u × S_v|` over 9 × 9 samples per patch), with its depth there the lowest z.
fn deepest(m: &Modeller) -> DVec3 {
    let (mut sum, mut weight, mut lowest) = (DVec3::ZERO, 0.0, 0.0f64);
    for p in m.document().model().surface.patches() {
        let patch = Patch::new(p);
        for i in 0..=8 {
            for j in 0..=8 {
                let f = patch.frame(i as f64 / 8.0, j as f64 / 8.0);
                if f.point.z < 0.0 {
                    let w = -f.point.z * f.du.cross(f.dv).length();
                    sum += w * f.point;
                    weight += w;
                    lowest = lowest.min(f.point.z);
                }
            }
        }
    }
    if weight > 0.0 {
        (sum / weight).truncate().extend(lowest)
    } else {
        DVec3::ZERO
    }
}

/// Where the view's ray through `pixel` meets the plane z = 0, from the view matrix alone.
fn on_the_plane(camera: &OrbitCamera, pixel: Vec2, size: Vec2) -> DVec3 {
    let inverse = camera.view(size.x / size.y).clip_from_world.inverse();
    let ndc = Vec2::new(2.0 * pixel.x / size.x - 1.0, 1.0 - 2.0 * pixel.y / size.y);
    let a = inverse
        .project_point3(Vec3::new(ndc.x, ndc.y, 0.0))
        .as_dvec3();
    let b = inverse
        .project_point3(Vec3::new(ndc.x, ndc.y, 1.0))
        .as_dvec3();
    a + (b - a) * (-a.z / (b.z - a.z))
}

/// A click of the Push tool in the orthographic view (numpad 5's command) dents the plane
/// under the cursor — where the orthographic ray meets it, well away from where the
/// perspective ray through the same pixel would.
#[test]
fn a_stroke_in_the_orthographic_view_lands_under_the_cursor() {
    let plane = Primitive::Plane
        .build(&PrimitiveParams::default())
        .expect("plane");
    let mut m = Modeller::new(Document::new(Model::new(plane)), None, false);
    let size = Vec2::new(800.0, 600.0);
    m.set_viewport(size);
    m.refresh();
    let perspective = *m.camera();
    m.apply(Command::SetSymmetry(false));
    m.apply(Command::ToggleProjection);
    assert_eq!(m.camera().projection, Projection::Orthographic);
    // The pixel of a plane point near a corner, through the orthographic view.
    let target = Vec3::new(3.5, -3.5, 0.0);
    let clip = m.camera().view(size.x / size.y).clip_from_world * target.extend(1.0);
    let pixel = Vec2::new(
        (clip.x / clip.w + 1.0) * 0.5 * size.x,
        (1.0 - clip.y / clip.w) * 0.5 * size.y,
    );
    let expected = on_the_plane(m.camera(), pixel, size);
    assert!(
        (expected - target.as_dvec3()).length() < 1e-3,
        "{expected:?}"
    );
    let elsewhere = on_the_plane(&perspective, pixel, size);
    m.pointer(PointerInput::Moved(pixel));
    m.refresh();
    m.pointer(PointerInput::Pressed(Button::Left, pixel));
    m.pointer(PointerInput::Moved(pixel));
    m.refresh();
    m.pointer(PointerInput::Released(Button::Left, pixel));
    m.refresh();
    let dent = deepest(&m);
    let off = (dent.truncate() - expected.truncate()).length();
    let apart = (expected.truncate() - elsewhere.truncate()).length();
    eprintln!(
        "ortho click: dent at {dent:?}, {off:.3} from the ortho ray's point; the perspective ray's point is {apart:.3} away"
    );
    assert!(dent.z < -0.05, "dented: {dent:?}");
    assert!(off < 0.1, "under the cursor: {off}");
    assert!(apart > 0.5, "the projections differ there: {apart}");
    m.apply(Command::ToggleProjection);
    assert_eq!(m.camera().projection, Projection::Perspective);
    assert_eq!(*m.camera(), perspective, "toggled back: the same camera");
}

/// `(constant coordinate, along x)` of a segment parallel to the x or the y axis.
fn axis_line(a: Vec3, b: Vec3) -> Option<(f32, bool)> {
    if (a.y - b.y).abs() < 1e-5 {
        Some((a.y, true))
    } else if (a.x - b.x).abs() < 1e-5 {
        Some((a.x, false))
    } else {
        None
    }
}

/// With patch lines shown, the lines refinement made are drawn fainter than the plane's own:
/// every segment's colour against where the 2 × 2 plane's own lines are, after
/// a refinement ×2 and one more column; the marks survive the model file, and a file without
/// them (an older file) draws every line as the primitive's.
#[test]
fn refined_lines_are_fainter_and_kept_in_the_file() {
    let plane = Primitive::Plane
        .build(&PrimitiveParams {
            patches: Some((2, 2)),
            ..PrimitiveParams::default()
        })
        .expect("plane");
    let twice = nendo::surface::refine::uniform(&plane, 2).expect("refined");
    let refined = nendo::surface::Refinement::new(&twice, &[2.5], &[])
        .and_then(|r| r.apply(&twice))
        .expect("one more column");
    // Where the plane's own lines are: its lattice columns and rows 0, 3, 6.
    let node = |a: isize, b: isize| plane.nodes()[plane.node_id(a, b).expect("node")].as_vec3();
    let own: Vec<f32> = [0, 3, 6]
        .iter()
        .flat_map(|&k| [node(k, 0).x, node(0, k).y])
        .collect();
    let model = Model::new(refined);
    let overlays = Overlays {
        patch_edges: true,
        ..Overlays::default()
    };
    let lines_of = |model: &Model| {
        let patches = model.surface.patches();
        let display = SurfaceDisplay::new(&patches, &Tessellation::DISPLAY);
        let mut lines = LineBatch::new();
        model_lines(model, &patches, &display, &overlays, &mut lines);
        lines
    };
    let (strong, faint) = (Rgba::PATCH_EDGE.to_unorm8(), Rgba::REFINED_EDGE.to_unorm8());
    assert!(
        faint[3] < strong[3] / 2,
        "fainter: {faint:?} against {strong:?}"
    );
    let lines = lines_of(&model);
    let (mut counted, mut faint_count) = (0, 0);
    for pair in lines.vertices().chunks_exact(2) {
        let (a, b) = (Vec3::from(pair[0].position), Vec3::from(pair[1].position));
        let Some((c, _)) = axis_line(a, b) else {
            panic!("a patch line of the plane is parallel to an axis: {a} {b}");
        };
        let original = own.iter().any(|o| (o - c).abs() < 1e-5);
        let expected = if original { strong } else { faint };
        assert_eq!(pair[0].colour, expected, "segment {a} – {b}");
        counted += 1;
        faint_count += usize::from(!original);
    }
    eprintln!("{counted} segments, {faint_count} of them on refined lines");
    assert!(faint_count > 0 && faint_count < counted);

    let text = model.to_json_string();
    assert!(text.contains("\"refined\""), "saved");
    let back = Model::from_json_str(&text).expect("reads").model;
    assert_eq!(back, model, "the marks round-trip");
    let mut old: serde_json::Value = serde_json::from_str(&text).expect("json");
    old["surface"]
        .as_object_mut()
        .expect("surface")
        .remove("refined");
    let old = Model::from_json(&old).expect("an older file reads").model;
    assert!(old.surface.refined_u().iter().all(|r| !r));
    let all_strong = lines_of(&old);
    assert!(all_strong.vertices().iter().all(|v| v.colour == strong));
    let mut bad: serde_json::Value = serde_json::from_str(&text).expect("json");
    bad["surface"]["refined"]["u"] = serde_json::json!([1, 99]);
    let e = Model::from_json(&bad).expect_err("a line past the grid");
    assert!(
        e.to_string().contains("surface.refined.u[1]: grid line 99"),
        "{e}"
    );
    // An unrefined model is written as before, without the member.
    assert!(
        !Model::new(plane.clone())
            .to_json_string()
            .contains("refined")
    );
}

/// The matcap chosen in the panel is drawn (the scene's style carries it) and remembered in
/// the settings file for the next window.
#[test]
fn the_matcap_is_remembered_in_the_settings() {
    let dir = temp_dir("matcap-settings");
    let path = dir.join("settings.json");
    let plane = || {
        Document::new(Model::new(
            Primitive::Plane
                .build(&PrimitiveParams::default())
                .expect("plane"),
        ))
    };
    let mut m = Modeller::new(plane(), None, false).with_settings(Some(path.clone()));
    assert_eq!(m.panel().matcap, None, "lit by default");
    m.panel_mut().matcap = Some(Matcap::RedWax);
    m.remember_settings();
    let text = std::fs::read_to_string(&path).expect("settings written");
    assert!(text.contains("\"red-wax\""), "{text}");
    let mut next = Modeller::new(plane(), None, false).with_settings(Some(path.clone()));
    assert_eq!(next.panel().matcap, Some(Matcap::RedWax));
    next.refresh();
    let style = next.scene(&mut LineBatch::new(), &mut Vec::new());
    assert_eq!(style.matcap, Some(Matcap::RedWax));
    let _ = std::fs::remove_dir_all(&dir);
}
