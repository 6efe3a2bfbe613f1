//! The modeller's symmetry without a window: offered only for a symmetric model, and every
//! live stroke and Hand-tool contact keeping the model symmetric, each one undo step.

use super::*;

/// Symmetry is on for a symmetric model (every primitive), X toggles it; a model that is
/// not symmetric about x = 0 does not get it, and the status line says why.
#[test]
fn symmetry_is_offered_only_for_a_symmetric_model() {
    let mut m = Modeller::new(plane_doc(), None, false);
    m.set_viewport(Vec2::new(800.0, 600.0));
    m.refresh();
    let grid = m.document().model().surface.clone();
    assert!(m.mirror.available() && m.mirror.active(&grid).is_some());
    m.apply(Command::ToggleSymmetry);
    assert!(
        !m.mirror.wanted() && m.mirror.active(&grid).is_none(),
        "X: off"
    );
    m.apply(Command::ToggleSymmetry);
    assert!(m.mirror.active(&grid).is_some(), "X: on again");

    let mut lopsided = plane_doc();
    lopsided
        .apply(&Op::Push {
            at: DVec3::new(2.5, 0.5, 0.0),
            dir: -DVec3::Z,
            depth: 0.4,
            radius: 1.0,
        })
        .expect("push");
    m.replace_document(Document::new(lopsided.model().clone()));
    m.refresh();
    assert!(!m.mirror.available());
    assert!(m.mirror.active(&m.document().model().surface).is_none());
    m.mirror.set_wanted(false);
    m.apply(Command::SetSymmetry(true));
    let status = m.status.as_ref().expect("a status");
    assert!(
        status.error && status.text.contains("not symmetric"),
        "{}",
        status.text
    );
    assert!(!m.mirror.wanted(), "refused");
}

/// With symmetry on (and auto-refine, the window's default), every live stroke — Push,
/// Pull, Draw a line, Move, Smooth, Shift+Push smoothing, and the surface brushes (Inflate,
/// Flatten, Pinch, Crease, on the clay the strokes before them left) — changes both sides of the
/// plane and leaves the model symmetric to 1e-12; each is one undo step back to the
/// bit-identical model before it.
#[test]
fn mirrored_live_strokes_keep_the_model_symmetric() {
    use crate::surface::symmetry_error;
    let mut m = Modeller::new(plane_doc(), None, false);
    m.set_viewport(Vec2::new(800.0, 600.0));
    m.refresh();
    let (from, to) = (Vec2::new(250.0, 330.0), Vec2::new(310.0, 290.0));
    let cases = [
        (Tool::Push, false),
        (Tool::Pull, false),
        (Tool::DrawLine, false),
        (Tool::Move, false),
        (Tool::Smooth, false),
        (Tool::Push, true),
        (Tool::Inflate, false),
        (Tool::Flatten, false),
        (Tool::Pinch, false),
        (Tool::Crease, false),
    ];
    for (tool, shift) in cases {
        m.apply(Command::SelectTool(tool));
        m.set_modifiers(shift, false);
        let before = m.document().model().clone();
        drag_stroke(&mut m, from, to);
        m.set_modifiers(false, false);
        let after = &m.document().model().surface;
        let asym = symmetry_error(after, Plane::X).relative;
        assert!(asym < 1e-12, "{tool:?} shift {shift}: asymmetry {asym:e}");
        // Changed on both sides of the plane (compared on the same surface points).
        let moved_on = |side: f64| {
            [0.5, 1.0, 1.5, 2.0, 2.5, 3.0].iter().any(|&x| {
                [-1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5].iter().any(|&y| {
                    let q = DVec3::new(side * x, y, 0.0);
                    let a = crate::surface::nearest(&before.surface, q).expect("near");
                    let b = crate::surface::nearest(after, a.point).expect("near");
                    (a.point - b.point).length() > 1e-4
                })
            })
        };
        assert!(
            moved_on(1.0) && moved_on(-1.0),
            "{tool:?} shift {shift}: both sides move"
        );
        assert!(m.document().history().undo_name().is_some());
        let after = m.document().model().clone();
        m.apply(Command::Undo);
        assert_eq!(
            bits(m.document().model()),
            bits(&before),
            "{tool:?}: one undo step"
        );
        m.apply(Command::Redo);
        assert!(bits(m.document().model()) == bits(&after), "{tool:?}: redo");
    }
}

/// With symmetry on, the Hand tool's contacts — a click (a push), a drag (a groove) and a
/// pulled drag — change both sides of the plane as one contact, leave the model symmetric
/// to 1e-12 relative, and undo to the bit-identical model before them. With symmetry off
/// the same drag leaves it asymmetric.
#[test]
fn mirrored_hand_contacts_keep_the_model_symmetric() {
    use crate::surface::symmetry_error;
    let mut m = hand_tool_on_the_plane();
    let (from, to) = (Vec2::new(250.0, 330.0), Vec2::new(310.0, 290.0));
    for (what, end, pull) in [
        ("click", from, false),
        ("drag", to, false),
        ("pulled drag", to, true),
    ] {
        m.set_modifiers(pull, false);
        let before = m.document().model().clone();
        drag_stroke(&mut m, from, end);
        m.set_modifiers(false, false);
        // Off the button, the hand hovers again.
        m.pointer(PointerInput::Moved(Vec2::new(600.0, 100.0)));
        let after = m.document().model().clone();
        assert_eq!(m.document().history().undo_name(), Some("hand"), "{what}");
        let asym = symmetry_error(&after.surface, Plane::X);
        eprintln!("hand {what}: asymmetry {:e} relative", asym.relative);
        assert!(asym.relative < 1e-12, "{what}: asymmetry {asym:?}");
        let moved_on = |side: f64| {
            [0.5, 1.0, 1.5, 2.0, 2.5, 3.0].iter().any(|&x| {
                [-1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5].iter().any(|&y| {
                    let q = DVec3::new(side * x, y, 0.0);
                    let a = crate::surface::nearest(&before.surface, q).expect("near");
                    let b = crate::surface::nearest(&after.surface, a.point).expect("near");
                    (a.point - b.point).length() > 1e-4
                })
            })
        };
        assert!(moved_on(1.0) && moved_on(-1.0), "{what}: both sides move");
        m.apply(Command::Undo);
        assert_eq!(bits(m.document().model()), bits(&before), "{what}: undo");
        assert_eq!(m.document().model(), &before, "{what}: undo");
        m.apply(Command::Redo);
        assert_eq!(bits(m.document().model()), bits(&after), "{what}: redo");
    }
    m.apply(Command::SetSymmetry(false));
    drag_stroke(&mut m, from, to);
    let asym = symmetry_error(&m.document().model().surface, Plane::X).relative;
    assert!(asym > 1e-3, "symmetry off: one-sided ({asym:e})");
}
