//! The modeller without a window: opening, strokes, the lifecycle's questions, autosave and
//! recovery, the Hand tool, framing, symmetry, refinement and regulation as undo steps — the
//! same commands and pointer events the window's shell gives it.

use super::*;
use crate::editor::autosave::Autosave;
use crate::editor::input::Button;
use crate::editor::lifecycle::{Prompt, UnsavedAnswer};
use crate::editor::scene::SurfaceDisplay;
use crate::model::Model;
use crate::surface::{Primitive, PrimitiveParams};

mod symmetry;

fn plane_doc() -> Document {
    Document::new(Model::new(
        Primitive::Plane
            .build(&PrimitiveParams::default())
            .expect("plane"),
    ))
}

#[test]
fn a_model_that_cannot_be_opened_is_named_once() {
    let dir = std::env::temp_dir().join(format!("nendo-open-once-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary folder");
    let missing = dir.join("missing.nendo.json");
    let bad = dir.join("bad.nendo.json");
    std::fs::write(&bad, "{ not json").expect("write");
    for path in [&missing, &bad] {
        let mut m = Modeller::new(plane_doc(), None, false);
        m.open(path);
        let status = m.status.as_ref().expect("a status");
        assert!(status.error);
        let name = path.display().to_string();
        assert!(
            status.text.starts_with(&format!("cannot open {name}: ")),
            "{}",
            status.text
        );
        assert_eq!(status.text.matches(&name).count(), 1, "{}", status.text);
    }
    std::fs::remove_dir_all(&dir).expect("clean up");
}

#[test]
fn a_new_document_at_revision_zero_still_rebuilds_the_display() {
    let mut m = Modeller::new(plane_doc(), None, false);
    m.refresh();
    let first = m.surface_generation();
    let flat = m.surface().mesh.clone();
    // An opened or recovered document restarts at revision 0, like the one it replaces.
    let mut pushed = plane_doc();
    let op = Op::Push {
        at: DVec3::new(0.5, 0.5, 0.0),
        dir: -DVec3::Z,
        depth: 0.5,
        radius: 1.25,
    };
    pushed.apply(&op).expect("push");
    let mut opened = Document::new(pushed.model().clone());
    opened.path = None;
    assert_eq!(opened.revision(), 0);
    m.replace_document(opened);
    m.refresh();
    assert_ne!(m.surface_generation(), first);
    assert_ne!(m.surface().mesh.positions, flat.positions);
}

#[test]
fn pointer_gestures_sculpt_and_camera_buttons_do_not() {
    let mut m = Modeller::new(plane_doc(), None, false);
    m.set_viewport(Vec2::new(800.0, 600.0));
    m.refresh();
    let centre = Vec2::new(400.0, 300.0);
    // Right drag orbits: the model is untouched.
    m.pointer(PointerInput::Pressed(Button::Right, centre));
    m.pointer(PointerInput::Moved(centre + Vec2::new(40.0, 10.0)));
    m.pointer(PointerInput::Released(
        Button::Right,
        centre + Vec2::new(40.0, 10.0),
    ));
    assert_eq!(m.document().revision(), 0);
    m.refresh();
    // A left click in the middle pushes.
    m.pointer(PointerInput::Moved(centre));
    m.pointer(PointerInput::Pressed(Button::Left, centre));
    m.pointer(PointerInput::Released(Button::Left, centre));
    // One edit: the push, on the grid auto-refined under the finger (on by default).
    assert_eq!(m.document().revision(), 1);
    assert_eq!(m.document().history().undo_name(), Some("push"));
    let surface = &m.document().model().surface;
    assert!(
        surface.patches_u() > 10 && surface.patches_v() > 10,
        "refined under the finger: {} x {}",
        surface.patches_u(),
        surface.patches_v()
    );
    assert!(m.session.doc.undo());
    assert_eq!(
        m.document().model().surface.patches_u(),
        10,
        "one undo step"
    );
}

/// Push deforms live while the button is held; Esc (or a right click) during the stroke
/// restores the surface bit for bit; a released stroke is one undo step.
#[test]
fn strokes_are_live_and_cancel_exactly() {
    let mut m = Modeller::new(plane_doc(), None, false);
    m.set_viewport(Vec2::new(800.0, 600.0));
    m.refresh();
    let start = m.document().model().clone();
    let centre = Vec2::new(400.0, 300.0);
    m.pointer(PointerInput::Moved(centre));
    m.refresh();
    assert!(
        !m.reach.patches().is_empty(),
        "the reach is outlined on hover"
    );
    for cancel in [true, false] {
        m.pointer(PointerInput::Pressed(Button::Left, centre));
        m.pointer(PointerInput::Moved(centre + Vec2::new(0.0, 30.0)));
        m.refresh();
        assert!(
            lowest(&m) < -0.05,
            "pushed before the release: {}",
            lowest(&m)
        );
        let shallow = lowest(&m);
        m.pointer(PointerInput::Wheel(4.0));
        m.refresh();
        assert!(lowest(&m) < shallow, "the wheel goes deeper live");
        if cancel {
            m.apply(Command::Cancel);
            assert_eq!(m.document().model(), &start, "Esc restores exactly");
            m.pointer(PointerInput::Released(Button::Left, centre));
            assert_eq!(m.document().model(), &start);
            assert!(m.document().history().undo_name().is_none());
        } else {
            m.pointer(PointerInput::Pressed(Button::Right, centre));
            m.pointer(PointerInput::Released(Button::Right, centre));
            assert_eq!(
                m.document().model(),
                &start,
                "a right click restores exactly"
            );
            m.pointer(PointerInput::Released(Button::Left, centre));
        }
        m.refresh();
    }
    // Ctrl inverts: a Push drag pulls; release keeps it as one undo step.
    m.set_modifiers(false, true);
    m.pointer(PointerInput::Pressed(Button::Left, centre));
    m.pointer(PointerInput::Moved(centre + Vec2::new(0.0, 30.0)));
    m.pointer(PointerInput::Released(
        Button::Left,
        centre + Vec2::new(0.0, 30.0),
    ));
    m.set_modifiers(false, false);
    let highest = m
        .document()
        .model()
        .surface
        .patches()
        .iter()
        .flatten()
        .map(|p| p.z)
        .fold(0.0, f64::max);
    assert!(highest > 0.05, "Ctrl+Push pulls: {highest}");
    assert_eq!(m.document().history().undo_name(), Some("pull"));
    m.apply(Command::Undo);
    assert_eq!(m.document().model(), &start);
    // F then a move to the right grows the radius; Esc restores it.
    let radius = m.tools.settings.radius;
    m.apply(Command::AdjustRadius);
    m.pointer(PointerInput::Moved(centre + Vec2::new(150.0, 0.0)));
    assert!((m.tools.settings.radius - 2.0 * radius).abs() < 1e-9);
    m.apply(Command::Cancel);
    assert_eq!(m.tools.settings.radius, radius);
}

fn pushed_model() -> Model {
    let mut doc = plane_doc();
    doc.apply(&Op::Push {
        at: DVec3::new(0.5, 0.5, 0.0),
        dir: -DVec3::Z,
        depth: 0.5,
        radius: 1.25,
    })
    .expect("push");
    doc.model().clone()
}

/// An earlier session's autosave of `model` at `path` (with the autosave header).
pub(super) fn write_autosave(model: &Model, path: &Path) {
    let mut a = Autosave::new(path.to_path_buf());
    a.write_now(model, 1);
    assert_eq!(a.last_error, None, "autosave written");
}

fn temp_autosave(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("nendo-modeller-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join("autosave.nendo.json")
}

/// A recovered autosave is unsaved work: closing asks, the autosave stays until the user
/// saves or chooses to drop it.
#[test]
fn recovered_work_is_kept_until_saved_or_dropped() {
    let autosave = temp_autosave("recover");
    let work = pushed_model();
    write_autosave(&work, &autosave);
    let mut m = Modeller::new(plane_doc(), Some(autosave.clone()), true);
    assert_eq!(
        m.session().prompt(),
        Some(Prompt::Recover(autosave.clone()))
    );
    m.apply(Command::Recover(autosave.clone()));
    assert_eq!(m.document().model(), &work);
    assert!(m.document().is_dirty(), "recovered work is unsaved");
    assert!(m.title().ends_with('*'));
    m.request_close();
    assert!(!m.wants_to_quit(), "closing asks first");
    assert_eq!(m.session().prompt(), Some(Prompt::Unsaved(Pending::Close)));
    m.apply(Command::AnswerUnsaved(UnsavedAnswer::Cancel));
    assert!(!m.wants_to_quit() && m.session().prompt().is_none());
    // An exit that nobody confirmed (the window going away) keeps the autosave.
    m.on_exit();
    assert!(autosave.is_file(), "unsaved work keeps its autosave");
    // Saving makes the document clean; then closing quits and drops the autosave.
    let saved = autosave.with_file_name("kept.nendo.json");
    m.apply(Command::DialogChosen(
        DialogPurpose::SaveModel,
        saved.clone(),
    ));
    assert!(!m.document().is_dirty());
    m.request_close();
    assert!(m.wants_to_quit());
    m.on_exit();
    assert!(!autosave.exists(), "a clean exit removes the autosave");
    assert_eq!(
        Model::read(&saved).expect("saved").model,
        work,
        "the work is in the file"
    );
    // Quitting without saving is the user's choice, and only then does a dirty
    // document's autosave go.
    write_autosave(&work, &autosave);
    let mut m = Modeller::new(plane_doc(), Some(autosave.clone()), true);
    m.apply(Command::Recover(autosave.clone()));
    m.request_close();
    m.apply(Command::AnswerUnsaved(UnsavedAnswer::Discard));
    assert!(m.wants_to_quit());
    m.on_exit();
    assert!(!autosave.exists());
    let _ = std::fs::remove_dir_all(autosave.parent().expect("dir"));
}

/// An autosave nobody answered for (the recovery question still open, or not offered)
/// survives a clean exit.
#[test]
fn an_unanswered_autosave_survives_the_exit() {
    let autosave = temp_autosave("unanswered");
    write_autosave(&pushed_model(), &autosave);
    let mut m = Modeller::new(plane_doc(), Some(autosave.clone()), true);
    m.request_close();
    assert!(m.wants_to_quit(), "closing with the question open quits");
    m.on_exit();
    assert!(
        autosave.is_file(),
        "and leaves the autosave for the next start"
    );
    let mut m = Modeller::new(plane_doc(), Some(autosave.clone()), false);
    m.request_close();
    m.on_exit();
    assert!(autosave.is_file(), "--no-recover leaves it in place too");
    let _ = std::fs::remove_dir_all(autosave.parent().expect("dir"));
}

/// Create and Open replace a document with unsaved changes only once the user said so,
/// and the autosave of that work is not overwritten while the question is open.
#[test]
fn create_and_open_ask_before_dropping_unsaved_work() {
    let autosave = temp_autosave("create");
    let mut m = Modeller::new(plane_doc(), Some(autosave.clone()), false);
    m.set_viewport(Vec2::new(800.0, 600.0));
    m.refresh();
    let centre = Vec2::new(400.0, 300.0);
    m.pointer(PointerInput::Moved(centre));
    m.pointer(PointerInput::Pressed(Button::Left, centre));
    m.pointer(PointerInput::Released(Button::Left, centre));
    assert!(m.document().is_dirty());
    let work = m.document().model().clone();
    let t0 = Instant::now();
    m.tick(t0);
    m.tick(t0 + Autosave::SETTLE * 2);
    assert_eq!(Model::read(&autosave).expect("autosaved").model, work);

    let sphere = PrimitiveForm::defaults_for(Primitive::Sphere);
    m.apply(Command::Create(sphere));
    assert_eq!(m.document().model(), &work, "nothing replaced yet");
    assert_eq!(
        m.session().prompt(),
        Some(Prompt::Unsaved(Pending::Create(sphere))),
        "Create asks"
    );
    m.tick(t0 + Autosave::INTERVAL * 3);
    assert_eq!(
        Model::read(&autosave).expect("autosave").model,
        work,
        "the earlier work's autosave stays while the question is open"
    );
    m.apply(Command::AnswerUnsaved(UnsavedAnswer::Cancel));
    assert_eq!(m.document().model(), &work, "cancel keeps the work");
    assert!(m.document().is_dirty());

    // Open asks too; saving first keeps the work in a file, then the file opens.
    let other = autosave.with_file_name("other.nendo.json");
    Model::new(
        Primitive::Torus
            .build(&PrimitiveParams::default())
            .expect("torus"),
    )
    .write(&other)
    .expect("write");
    m.open(&other);
    assert_eq!(m.document().model(), &work, "Open asks first");
    assert!(matches!(m.session().prompt(), Some(Prompt::Unsaved(_))));
    let kept = autosave.with_file_name("work.nendo.json");
    m.session.doc.path = Some(kept.clone());
    m.apply(Command::AnswerUnsaved(UnsavedAnswer::Save));
    assert_eq!(Model::read(&kept).expect("saved").model, work);
    assert_eq!(m.document().path.as_deref(), Some(other.as_path()));
    assert!(!m.document().is_dirty());

    // Opening the autosave file itself by name keeps it (it is the opened document).
    work.write(&autosave).expect("an autosave");
    m.open(&autosave);
    assert_eq!(m.document().path.as_deref(), Some(autosave.as_path()));
    assert!(autosave.is_file(), "the opened file is not removed");

    // With nothing unsaved, Create goes ahead without asking.
    m.apply(Command::Create(sphere));
    assert!(m.session().prompt().is_none());
    assert_eq!(
        m.document().model().surface.topology(),
        Primitive::Sphere.topology()
    );
    let _ = std::fs::remove_dir_all(autosave.parent().expect("dir"));
}

/// A modeller on the default plane, an 800 × 600 view, the Hand tool picked.
fn hand_tool_on_the_plane() -> Modeller {
    let mut m = Modeller::new(plane_doc(), None, false);
    m.set_viewport(Vec2::new(800.0, 600.0));
    m.refresh();
    m.apply(Command::UseMouseHand(
        nendo_devices::profile::MouseProfile::default(),
    ));
    assert_eq!(m.tools.active, Tool::Hand);
    m
}

/// The Hand tool drives the mouse hand from the pointer: a press in the view pushes the
/// plane through the document (one undoable "hand" edit), the hand is drawn, and the wheel
/// while pressed goes deeper.
#[test]
fn the_hand_tool_sculpts_through_the_document() {
    let mut m = hand_tool_on_the_plane();
    let centre = Vec2::new(400.0, 300.0);
    m.pointer(PointerInput::Moved(centre));
    assert_eq!(m.document().revision(), 0, "hovering does not sculpt");
    let mut lines = LineBatch::new();
    let mut spheres = Vec::new();
    m.scene(&mut lines, &mut spheres);
    assert!(
        lines.len() >= 15 && spheres.len() >= 20,
        "the hand is drawn with its fingers"
    );
    m.pointer(PointerInput::Pressed(Button::Left, centre));
    m.pointer(PointerInput::Moved(centre));
    let shallow = lowest(&m);
    m.pointer(PointerInput::Wheel(10.0));
    let deeper = lowest(&m);
    m.pointer(PointerInput::Released(Button::Left, centre));
    assert!(shallow < -0.1, "the press pushed: {shallow}");
    assert!(
        deeper < shallow - 0.05,
        "the wheel pushed deeper: {deeper} vs {shallow}"
    );
    assert!(m.document().is_dirty());
    assert_eq!(m.document().history().undo_name(), Some("hand"));
    m.apply(Command::Undo);
    assert_eq!(
        m.document().model(),
        plane_doc().model(),
        "one undo for the contact"
    );
}

fn lowest(m: &Modeller) -> f64 {
    m.document()
        .model()
        .surface
        .patches()
        .iter()
        .flatten()
        .map(|p| p.z)
        .fold(0.0, f64::min)
}

/// With the control net shown, framing takes in the control points, which stand off the
/// surface: framed on the surface alone, a coarse torus's net runs out of the view.
#[test]
fn framing_includes_the_control_net_when_it_is_drawn() {
    let grid = Primitive::Torus
        .build(&PrimitiveParams {
            patches: Some((4, 2)),
            ..PrimitiveParams::default()
        })
        .expect("torus");
    let model = Model::new(grid);
    let patches = model.surface.patches();
    let display = SurfaceDisplay::new(&patches, &Tessellation::DISPLAY);
    let aspect = 16.0 / 9.0;
    // The largest |NDC| of a control point, framed on what `overlays` draws.
    let worst = |overlays: &Overlays| {
        let points = framing_points(&model, &patches, &display, overlays);
        let view = OrbitCamera::framing(ViewPreset::Iso, &points, aspect).view(aspect);
        patches
            .iter()
            .flatten()
            .map(|q| {
                let c = view.clip_from_world * q.as_vec3().extend(1.0);
                (c.x / c.w).abs().max((c.y / c.w).abs())
            })
            .fold(0.0f32, f32::max)
    };
    let net = Overlays {
        control_net: true,
        ..Overlays::default()
    };
    assert!(worst(&net) <= 1.0, "the net is in view: {}", worst(&net));
    assert!(
        worst(&Overlays::default()) > 1.1,
        "framed on the surface alone the net runs out: {}",
        worst(&Overlays::default())
    );
}

/// A modeller whose plane has one push and no file yet.
fn unsaved_work(name: &str) -> (Modeller, PathBuf) {
    let dir = temp_autosave(name).parent().expect("dir").to_path_buf();
    let mut m = Modeller::new(plane_doc(), None, false);
    m.set_viewport(Vec2::new(800.0, 600.0));
    m.refresh();
    m.sculpt(&Op::Push {
        at: DVec3::new(0.5, 0.5, 0.0),
        dir: -DVec3::Z,
        depth: 0.5,
        radius: 1.25,
    });
    assert!(m.document().is_dirty() && m.document().path.is_none());
    (m, dir)
}

/// "Save…" in the unsaved-changes question of a document with no file opens the save
/// dialog; once it picked a file and the save worked, the action that asked (Close,
/// Create, Open) goes on. It used to be lost: opening the dialog forgot it.
#[test]
fn save_in_the_unsaved_question_then_runs_the_waiting_action() {
    // Close.
    let (mut m, dir) = unsaved_work("save-close");
    let work = m.document().model().clone();
    m.request_close();
    m.apply(Command::AnswerUnsaved(UnsavedAnswer::Save));
    assert_eq!(
        m.dialog.as_ref().map(|d| d.purpose),
        Some(DialogPurpose::SaveModel),
        "Save… asks for a file"
    );
    assert!(!m.wants_to_quit(), "not before the save");
    let file = dir.join("closing.nendo.json");
    m.apply(Command::DialogChosen(
        DialogPurpose::SaveModel,
        file.clone(),
    ));
    assert_eq!(Model::read(&file).expect("saved").model, work);
    assert!(m.wants_to_quit(), "the Close went on after the save");
    assert!(m.dialog.is_none());

    // Create.
    let (mut m, dir) = unsaved_work("save-create");
    let torus = PrimitiveForm::defaults_for(Primitive::Torus);
    m.apply(Command::Create(torus));
    m.apply(Command::AnswerUnsaved(UnsavedAnswer::Save));
    let file = dir.join("before-torus.nendo.json");
    m.apply(Command::DialogChosen(
        DialogPurpose::SaveModel,
        file.clone(),
    ));
    assert!(file.is_file(), "saved");
    assert_eq!(
        m.document().model().surface.topology(),
        Primitive::Torus.topology(),
        "the Create went on after the save"
    );

    // Open.
    let (mut m, dir) = unsaved_work("save-open");
    let other = dir.join("other.nendo.json");
    let sphere = Model::new(
        Primitive::Sphere
            .build(&PrimitiveParams::default())
            .expect("sphere"),
    );
    sphere.write(&other).expect("write");
    m.open(&other);
    m.apply(Command::AnswerUnsaved(UnsavedAnswer::Save));
    let file = dir.join("before-open.nendo.json");
    m.apply(Command::DialogChosen(
        DialogPurpose::SaveModel,
        file.clone(),
    ));
    assert!(file.is_file(), "saved");
    assert_eq!(
        m.document().model(),
        &sphere,
        "the Open went on after the save"
    );
    assert_eq!(m.document().path.as_deref(), Some(other.as_path()));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Cancelling the save dialog that "Save…" opened keeps the work and drops the action;
/// a failed save asks again; "Discard" goes on without writing anything.
#[test]
fn cancel_keeps_the_work_and_discard_drops_it() {
    let (mut m, dir) = unsaved_work("cancel");
    let work = m.document().model().clone();
    m.request_close();
    m.apply(Command::AnswerUnsaved(UnsavedAnswer::Save));
    m.apply(Command::DialogCancelled);
    assert!(!m.wants_to_quit());
    assert!(m.session().prompt().is_none() && m.dialog.is_none());
    assert_eq!(m.document().model(), &work);
    assert!(m.document().is_dirty());
    // A later plain "Save as…" does not close the window.
    let file = dir.join("plain.nendo.json");
    m.apply(Command::ShowDialog(DialogPurpose::SaveModel));
    m.apply(Command::DialogChosen(
        DialogPurpose::SaveModel,
        file.clone(),
    ));
    assert!(file.is_file() && !m.wants_to_quit());

    // A save that fails asks the question again.
    let (mut m, dir) = unsaved_work("fail");
    m.request_close();
    m.apply(Command::AnswerUnsaved(UnsavedAnswer::Save));
    let nowhere = dir.join("missing-folder").join("x.nendo.json");
    m.apply(Command::DialogChosen(DialogPurpose::SaveModel, nowhere));
    assert!(!m.wants_to_quit());
    assert_eq!(m.session().prompt(), Some(Prompt::Unsaved(Pending::Close)));
    assert!(m.status.as_ref().is_some_and(|s| s.error));

    // Discard creates without writing a file.
    let (mut m, dir) = unsaved_work("discard");
    m.apply(Command::Create(PrimitiveForm::defaults_for(
        Primitive::Torus,
    )));
    m.apply(Command::AnswerUnsaved(UnsavedAnswer::Discard));
    assert_eq!(
        m.document().model().surface.topology(),
        Primitive::Torus.topology()
    );
    assert!(!m.document().is_dirty());
    assert!(m.dialog.is_none());
    let _ = std::fs::remove_dir_all(&dir);
}

/// "Refine" splits every patch into 2 × 2 as one undoable edit; with auto-refine (on by
/// default) a push refines where its finger reaches first, and the stroke follows.
#[test]
fn refine_and_auto_refine_are_undoable_edits() {
    let mut m = Modeller::new(plane_doc(), None, false);
    assert!(m.auto_refine);
    // Unmirrored: a mirrored operation refines within its own undo step.
    m.apply(Command::SetSymmetry(false));
    m.apply(Command::Refine);
    assert_eq!(m.document().model().surface.patch_count(), 400);
    assert_eq!(m.document().history().undo_name(), Some("refine"));
    m.apply(Command::Undo);
    assert_eq!(m.document().model(), plane_doc().model());
    m.sculpt(&Op::Push {
        at: DVec3::new(0.5, 0.5, 0.0),
        dir: -DVec3::Z,
        depth: 0.2,
        radius: 0.5,
    });
    let g = &m.document().model().surface;
    // Only the columns and rows around the finger: far fewer than uniform ×4 (40 × 40).
    assert!(
        g.patch_count() > 100 && g.patches_u() < 30 && g.patches_v() < 30,
        "{} x {}",
        g.patches_u(),
        g.patches_v()
    );
    assert_eq!(m.document().history().undo_name(), Some("push"));
    m.apply(Command::Undo);
    assert_eq!(
        m.document().history().undo_name(),
        Some("refine for the finger")
    );
    m.apply(Command::SetAutoRefine(false));
    m.apply(Command::Undo);
    m.sculpt(&Op::Push {
        at: DVec3::new(0.5, 0.5, 0.0),
        dir: -DVec3::Z,
        depth: 0.2,
        radius: 0.5,
    });
    assert_eq!(m.document().model().surface.patch_count(), 100);
}

/// A left-button stroke from `from` to `to` in eight moves, a frame after each.
fn drag_stroke(m: &mut Modeller, from: Vec2, to: Vec2) {
    m.pointer(PointerInput::Moved(from));
    m.refresh();
    m.pointer(PointerInput::Pressed(Button::Left, from));
    for k in 1..=8 {
        m.pointer(PointerInput::Moved(from.lerp(to, k as f32 / 8.0)));
        m.refresh();
    }
    m.pointer(PointerInput::Released(Button::Left, to));
    m.refresh();
}

fn bits(model: &Model) -> Vec<[u64; 3]> {
    model
        .surface
        .nodes()
        .iter()
        .map(|p| p.to_array().map(f64::to_bits))
        .collect()
}

/// A move stroke puts the grabbed surface point on the target (the surface passes through
/// it to 1e-9 of the model's size), with symmetry on or off.
#[test]
fn a_move_stroke_lands_the_grabbed_point_on_the_target() {
    for symmetric in [true, false] {
        let mut m = Modeller::new(plane_doc(), None, false);
        m.set_viewport(Vec2::new(800.0, 600.0));
        m.refresh();
        m.apply(Command::SetSymmetry(symmetric));
        m.apply(Command::SelectTool(Tool::Move));
        m.apply(Command::StartRecording);
        drag_stroke(&mut m, Vec2::new(260.0, 320.0), Vec2::new(280.0, 250.0));
        let recorded = m.document().recording.clone().unwrap_or_default();
        let [Op::Move { at, to, .. }] = recorded.as_slice() else {
            panic!("one move recorded: {recorded:?}")
        };
        assert!((*to - *at).length() > 0.3, "moved: {at} -> {to}");
        let surface = &m.document().model().surface;
        let near = crate::surface::nearest(surface, *to).expect("near");
        assert!(
            (near.point - *to).length() < 1e-9 * 5.0,
            "symmetric {symmetric}: the surface passes through the target: {}",
            (near.point - *to).length()
        );
        assert_eq!(m.document().history().undo_name(), Some("move"));
    }
}

/// "Regulate now" applies the chosen regulation to the whole surface as one undoable
/// command; undo restores the model bit for bit, redo the regulated one.
#[test]
fn regulate_now_is_one_exact_undo_step() {
    let mut model = plane_doc().model().clone();
    model.regulation = crate::surface::Regulation::None;
    let mut m = Modeller::new(Document::new(model), None, false);
    m.set_viewport(Vec2::new(800.0, 600.0));
    m.refresh();
    m.apply(Command::SetSymmetry(false));
    m.apply(Command::SetAutoRefine(false));
    m.sculpt(&Op::Push {
        at: DVec3::new(0.7, 0.3, 0.0),
        dir: DVec3::new(0.3, 0.2, -1.0),
        depth: 0.6,
        radius: 1.3,
    });
    m.apply(Command::SetRegulation(crate::surface::Regulation::Exact));
    let creased = m.document().model().clone();
    let seam = |model: &Model| crate::surface::continuity::report(&model.surface, 8).g1_max_deg;
    m.apply(Command::RegulateNow);
    let regulated = m.document().model().clone();
    assert_ne!(regulated.surface, creased.surface, "regulated");
    assert!(
        seam(&regulated) < 0.01 && seam(&creased) > 0.1,
        "G1 after: {} (before {})",
        seam(&regulated),
        seam(&creased)
    );
    assert_eq!(m.document().history().undo_name(), Some("regulate now"));
    m.apply(Command::Undo);
    assert!(
        bits(m.document().model()) == bits(&creased),
        "undo: bit-identical"
    );
    m.apply(Command::Redo);
    assert!(bits(m.document().model()) == bits(&regulated), "redo");
}

/// A file asked of the user stays asked until a choice or a cancel answers it; asking again
/// makes a new request (the shell's dialog starts afresh), and Esc closes it when nothing
/// else is in progress. Save… of a document with a file offers that file.
#[test]
fn a_file_request_lasts_until_answered() {
    let mut m = Modeller::new(plane_doc(), None, false);
    assert!(m.file_request().is_none());
    m.apply(Command::ShowDialog(DialogPurpose::ExportMesh));
    let first = m.file_request().cloned().expect("a request");
    assert_eq!(first.purpose, DialogPurpose::ExportMesh);
    assert_eq!(first.default_name, "model.obj");
    m.refresh();
    assert_eq!(m.file_request(), Some(&first), "a frame does not answer it");
    m.apply(Command::ShowDialog(DialogPurpose::ExportMesh));
    let second = m.file_request().cloned().expect("asked again");
    assert_ne!(second.id, first.id, "a new request");
    m.apply(Command::Cancel);
    assert!(m.file_request().is_none(), "Esc closes it");

    let file = temp_autosave("request").with_file_name("mine.nendo.json");
    m.session.doc.path = Some(file.clone());
    m.apply(Command::ShowDialog(DialogPurpose::SaveModel));
    let request = m.file_request().cloned().expect("a save request");
    assert_eq!(request.current.as_deref(), Some(file.as_path()));
    m.apply(Command::DialogChosen(
        DialogPurpose::SaveModel,
        file.clone(),
    ));
    assert!(m.file_request().is_none(), "a choice answers it");
    assert!(file.is_file(), "and the model is saved there");
    let _ = std::fs::remove_dir_all(file.parent().expect("dir"));
}

/// The label by the cursor: the radius while F sets it, then the depth and the reached
/// patches during a push stroke; nothing when neither is in progress.
#[test]
fn the_cursor_label_follows_the_gesture() {
    let mut m = Modeller::new(plane_doc(), None, false);
    m.set_viewport(Vec2::new(800.0, 600.0));
    m.apply(Command::SetAutoRefine(false));
    m.refresh();
    let centre = Vec2::new(400.0, 300.0);
    m.pointer(PointerInput::Moved(centre));
    assert_eq!(m.cursor_label(), None);
    m.apply(Command::AdjustRadius);
    let (at, text) = m.cursor_label().expect("a label");
    assert_eq!(at, centre);
    assert!(text.starts_with("radius "), "{text}");
    m.pointer(PointerInput::Pressed(Button::Left, centre));
    assert_eq!(m.cursor_label(), None, "the click kept the radius");
    assert_eq!(m.document().revision(), 0, "and pushed nothing");
    m.pointer(PointerInput::Pressed(Button::Left, centre));
    m.pointer(PointerInput::Moved(centre + Vec2::new(0.0, 30.0)));
    m.refresh();
    let (_, text) = m.cursor_label().expect("a stroke's label");
    let patches = m.stroke.as_ref().map_or(0, |s| s.touched().len());
    assert!(patches > 0);
    assert!(
        text.starts_with("depth ")
            && text.contains(" in · ")
            && text.ends_with(&format!("{patches} patches")),
        "{text}"
    );
    m.apply(Command::Cancel);
    assert_eq!(m.cursor_label(), None);
}

/// The clutch through the modeller, as the shell gives it (the key held, read each frame): no
/// hand status without a device session; with the shipped groove replayed and the key held,
/// the status line says the hand is clutched and the clay stays as it was.
#[test]
fn the_clutch_key_holds_the_device_hand_off_the_clay() {
    let dir = std::env::temp_dir().join(format!("nendo-modeller-clutch-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary folder");
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("../devices/traces/plane-groove.trace");
    let profile = dir.join("replay.json");
    let json = serde_json::json!({
        "format": "nendo-device-profile",
        "version": 1,
        "name": "groove-replay",
        "input": {"replay": {"trace": source, "speed": 40.0}},
    });
    std::fs::write(&profile, json.to_string()).expect("profile written");
    let mut m = Modeller::new(plane_doc(), None, false);
    let start = m.document().model().clone();
    m.set_clutch(true);
    assert_eq!(m.hand_status(), None, "no device hand: no clutch to show");
    m.connect_profile(&profile.display().to_string())
        .expect("the replay profile");
    let deadline = Instant::now() + std::time::Duration::from_secs(60);
    let mut shown = Vec::new();
    while m.live.is_connected() && Instant::now() < deadline {
        std::thread::sleep(std::time::Duration::from_millis(5));
        m.set_clutch(true);
        m.tick(Instant::now());
        shown.extend(m.hand_status());
    }
    assert!(!m.live.is_connected(), "the replay ended");
    assert!(
        shown.iter().any(|s| s.starts_with("clutch (Space held)")),
        "{shown:?}"
    );
    assert_eq!(m.document().model(), &start, "the clay untouched");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The export dialog proposes the model's own name and a tolerance for its size (a thousandth
/// of its box's diagonal), and keeps a tolerance the user set.
#[test]
fn the_export_dialog_proposes_the_models_name_and_a_tolerance_for_its_size() {
    use super::commands::export_name;
    assert_eq!(export_name(None), "model.obj");
    assert_eq!(
        export_name(Some(Path::new("/x/face.nendo.json"))),
        "face.obj"
    );
    assert_eq!(export_name(Some(Path::new("vase.JSON"))), "vase.obj");
    assert_eq!(export_name(Some(Path::new("/x/.nendo.json"))), "model.obj");

    let mut m = Modeller::new(plane_doc(), None, false);
    m.refresh();
    m.apply(Command::ShowDialog(DialogPurpose::ExportMesh));
    let want = 1e-3 * 200f64.sqrt();
    assert!(
        (m.panel().export_tolerance - want).abs() < 1e-9,
        "{}",
        m.panel().export_tolerance
    );
    let (_, estimate) = m.export_dialog("plane.stl");
    let estimate = estimate.expect("a mesh format");
    // The flat plane: every patch one cell of two triangles.
    assert_eq!(estimate.triangles, 200);
    assert_eq!(estimate.bytes, 84 + 50 * 200);
    assert_eq!(m.export_dialog("plane.step").1, None);
    m.apply(Command::Cancel);
    m.panel_mut().export_tolerance = 0.002;
    m.apply(Command::ShowDialog(DialogPurpose::ExportMesh));
    assert_eq!(
        m.panel().export_tolerance,
        0.002,
        "the user's tolerance is kept"
    );
}
