//! The mouse tools' gestures on the default plane: clicks, drawn lines, the wheel, moves and
//! smoothing strokes.

use super::gesture::*;
use super::*;
use crate::editor::camera::OrbitCamera;
use crate::editor::camera::ViewPreset;
use crate::mesh::{PatchPoints, TriMesh};
use crate::mesh::{Tessellation, tessellate};
use crate::render::LineBatch;
use crate::surface::Dirs;
use crate::surface::{Primitive, PrimitiveParams};
use glam::Vec2;

/// The default plane seen from the iso view in an 800 × 600 viewport.
struct PlaneScene {
    patches: Vec<PatchPoints>,
    mesh: TriMesh,
    camera: OrbitCamera,
    viewport: Vec2,
}

impl PlaneScene {
    fn new() -> Self {
        let patches = Primitive::Plane
            .build(&PrimitiveParams::default())
            .expect("plane")
            .patches();
        let mesh = tessellate(&patches, &Tessellation::DISPLAY);
        let viewport = Vec2::new(800.0, 600.0);
        let camera =
            OrbitCamera::framing(ViewPreset::Iso, &mesh.positions, viewport.x / viewport.y);
        Self {
            patches,
            mesh,
            camera,
            viewport,
        }
    }

    fn context(&self) -> ToolContext<'_> {
        ToolContext {
            camera: &self.camera,
            viewport: self.viewport,
            patches: &self.patches,
            mesh: &self.mesh,
            curves: &[],
        }
    }
}

#[test]
fn a_click_on_the_plane_pushes_it_away_from_the_viewer() {
    let scene = PlaneScene::new();
    let ctx = scene.context();
    let viewport = scene.viewport;
    let settings = ToolSettings::default();
    let mut state = ToolState::default();
    let centre = viewport / 2.0;
    assert!(state.press(Tool::Push, &ctx, &settings, centre).is_empty());
    let edits = state.release(Tool::Push, &ctx, &settings, centre);
    let [
        Edit::Sculpt(Op::Push {
            at,
            dir,
            depth,
            radius,
        }),
    ] = edits.as_slice()
    else {
        panic!("one push expected, got {edits:?}");
    };
    assert!(at.z.abs() < 1e-9 && *depth == settings.depth && *radius == settings.radius);
    assert!(
        dir.dot(DVec3::Z) < -0.999,
        "into the plane, away from a viewer above: {dir}"
    );
    // A drag sets the depth from its length; pull reverses it.
    state.press(Tool::Pull, &ctx, &settings, centre);
    let edits = state.release(Tool::Pull, &ctx, &settings, centre + Vec2::new(0.0, 80.0));
    let [Edit::Sculpt(Op::Push { depth, .. })] = edits.as_slice() else {
        panic!("{edits:?}")
    };
    assert!(*depth < -0.1, "{depth}");
    // Outside the surface nothing happens.
    assert!(
        state
            .press(Tool::Push, &ctx, &settings, Vec2::new(2.0, 2.0))
            .is_empty()
    );
    assert!(
        state
            .release(Tool::Push, &ctx, &settings, Vec2::new(2.0, 2.0))
            .is_empty()
    );
}

/// A drawn line's path is evenly spaced along the surface (a fifth of the radius), however
/// the cursor moved (a few long jumps, many short steps), and the live operation is a drag
/// along it; Ctrl turns the groove into a ridge.
#[test]
fn a_drawn_line_is_evenly_spaced() {
    let scene = PlaneScene::new();
    let ctx = scene.context();
    let settings = ToolSettings::default();
    let spacing = 0.2 * settings.radius;
    let mut state = ToolState::default();
    let start = Vec2::new(300.0, 300.0);
    state.press(Tool::DrawLine, &ctx, &settings, start);
    assert_eq!(
        state.stroke_op(Tool::DrawLine, &ctx, &settings),
        None,
        "one point: no op yet"
    );
    for (k, step) in [(3, 60.0f32), (40, 2.5)] {
        for _ in 0..k {
            let Gesture::Stroke { last, .. } = &state.gesture else {
                panic!("a stroke")
            };
            let to = last.0 + Vec2::new(step, 0.3 * step);
            state.drag(&ctx, &settings, to);
        }
    }
    let Some(Op::Groove {
        path, depth, dirs, ..
    }) = state.stroke_op(Tool::DrawLine, &ctx, &settings)
    else {
        panic!("a groove")
    };
    assert_eq!(dirs, Dirs::Normal, "the line follows the clay");
    assert!(path.len() > 10, "{}", path.len());
    assert!(depth > 0.0, "a groove");
    for w in path.windows(2) {
        let d = (w[1] - w[0]).length();
        assert!(
            (d - spacing).abs() < 1e-9 * spacing.max(1.0),
            "spacing {d} vs {spacing}"
        );
    }
    state.set_invert(true);
    let Some(Op::Groove { depth, .. }) = state.stroke_op(Tool::DrawLine, &ctx, &settings) else {
        panic!("a groove")
    };
    assert!(depth < 0.0, "Ctrl: a ridge");
}

#[test]
fn the_wheel_never_turns_a_dragged_push_into_a_pull() {
    let scene = PlaneScene::new();
    let ctx = scene.context();
    let viewport = scene.viewport;
    // A deep click depth, a short drag: the drag's depth is far below the panel's.
    let settings = ToolSettings {
        depth: 3.0,
        ..ToolSettings::default()
    };
    let centre = viewport / 2.0;
    let end = centre + Vec2::new(0.0, 10.0);
    let mut state = ToolState::default();
    state.press(Tool::Push, &ctx, &settings, centre);
    state.drag(&ctx, &settings, end);
    for _ in 0..40 {
        assert!(state.wheel(&ctx, &settings, -1.0));
    }
    let mut lines = LineBatch::new();
    let mut spheres = Vec::new();
    state.preview(Tool::Push, &ctx, &settings, &mut lines, &mut spheres);
    assert_eq!(lines.on_top_len(), 1, "the push's travel is drawn on top");
    let edits = state.release(Tool::Push, &ctx, &settings, end);
    assert!(
        edits.iter().all(|e| match e {
            Edit::Sculpt(Op::Push { depth, .. }) => *depth > 0.0,
            _ => false,
        }),
        "wheeled back to nothing, a push is no pull: {edits:?}"
    );
    // One notch forward from the floor pushes again, by one notch.
    state.press(Tool::Push, &ctx, &settings, centre);
    state.drag(&ctx, &settings, end);
    for _ in 0..40 {
        state.wheel(&ctx, &settings, -1.0);
    }
    state.wheel(&ctx, &settings, 1.0);
    let edits = state.release(Tool::Push, &ctx, &settings, end);
    let [Edit::Sculpt(Op::Push { depth, .. })] = edits.as_slice() else {
        panic!("{edits:?}")
    };
    assert!(
        (*depth - 0.05 * settings.radius).abs() < 1e-9,
        "one notch: {depth}"
    );
}

/// Move: a press grabs the surface point under the cursor, a drag takes it to the cursor
/// on the plane through it facing the camera, the wheel moves that plane nearer; a click
/// without a move is no edit.
#[test]
fn move_takes_the_grabbed_point_to_the_cursor_on_the_facing_plane() {
    let scene = PlaneScene::new();
    let ctx = scene.context();
    let settings = ToolSettings::default();
    let mut state = ToolState::default();
    let centre = scene.viewport / 2.0;
    assert!(state.press(Tool::Move, &ctx, &settings, centre).is_empty());
    assert!(state.stroking() && !state.smoothing());
    assert_eq!(
        state.stroke_op(Tool::Move, &ctx, &settings),
        None,
        "not moved yet"
    );
    let hit = ctx
        .pick_surface(centre)
        .expect("the plane is under the centre");
    let end = centre + Vec2::new(60.0, -40.0);
    state.drag(&ctx, &settings, end);
    let Some(Op::Move { at, to, radius }) = state.stroke_op(Tool::Move, &ctx, &settings) else {
        panic!("a move")
    };
    assert_eq!(at, hit.point);
    assert_eq!(radius, settings.radius);
    let eye = scene.camera.eye().as_dvec3();
    let forward = -scene.camera.to_eye().as_dvec3();
    assert!(
        (to - at).dot(forward).abs() < 1e-9 * (at - eye).length(),
        "on the plane facing the camera"
    );
    let ray = ctx.ray(end);
    assert!(
        (to - ray.origin).cross(ray.direction).length() < 1e-9 * (to - eye).length(),
        "under the cursor"
    );
    // The wheel away from the user brings the plane nearer the eye.
    assert!(state.wheel(&ctx, &settings, 3.0));
    let Some(Op::Move { to: nearer, .. }) = state.stroke_op(Tool::Move, &ctx, &settings) else {
        panic!("a move")
    };
    assert!((nearer - eye).dot(forward) < (to - eye).dot(forward) - 1e-3);
    let edits = state.release(Tool::Move, &ctx, &settings, end);
    assert!(matches!(edits.as_slice(), [Edit::Sculpt(Op::Move { .. })]));
    // A click is nothing.
    state.press(Tool::Move, &ctx, &settings, centre);
    assert!(
        state
            .release(Tool::Move, &ctx, &settings, centre)
            .is_empty()
    );
}

/// Smooth, and Push / Pull / Draw a line with Shift held: dabs of the panel's radius and
/// strength at even spacing along the path, all of them released as edits in order.
#[test]
fn smoothing_strokes_are_evenly_spaced_dabs() {
    let scene = PlaneScene::new();
    let ctx = scene.context();
    let settings = ToolSettings::default();
    let spacing = 0.2 * settings.radius;
    for (tool, shift) in [
        (Tool::Smooth, false),
        (Tool::Push, true),
        (Tool::Pull, true),
        (Tool::DrawLine, true),
    ] {
        let mut state = ToolState::default();
        state.set_smooth(shift);
        assert_eq!(state.acting_tool(tool), Tool::Smooth);
        let start = Vec2::new(300.0, 300.0);
        state.press(tool, &ctx, &settings, start);
        assert!(state.smoothing(), "{tool:?}");
        assert_eq!(state.stroke_op(tool, &ctx, &settings), None);
        for k in 1..=20 {
            state.drag(
                &ctx,
                &settings,
                start + Vec2::new(6.0 * k as f32, 2.0 * k as f32),
            );
        }
        let dabs = state.stroke_dabs(&settings).expect("dabs");
        assert!(dabs.len() > 5, "{}", dabs.len());
        let points: Vec<DVec3> = dabs
            .iter()
            .map(|d| match d {
                Op::Smooth {
                    at,
                    radius,
                    strength,
                } => {
                    assert_eq!((*radius, *strength), (settings.radius, settings.strength));
                    *at
                }
                other => panic!("a smoothing dab: {other:?}"),
            })
            .collect();
        for w in points.windows(2) {
            let d = (w[1] - w[0]).length();
            assert!((d - spacing).abs() < 1e-9, "spacing {d} vs {spacing}");
        }
        let edits = state.release(tool, &ctx, &settings, start + Vec2::new(120.0, 40.0));
        assert!(edits.len() >= dabs.len());
        assert!(
            edits
                .iter()
                .all(|e| matches!(e, Edit::Sculpt(Op::Smooth { .. })))
        );
    }
    // Without Shift, Push pushes.
    let mut state = ToolState::default();
    assert_eq!(state.acting_tool(Tool::Push), Tool::Push);
    state.press(Tool::Push, &ctx, &settings, Vec2::new(300.0, 300.0));
    assert!(!state.smoothing());
    assert!(state.stroke_dabs(&settings).is_none());
}
