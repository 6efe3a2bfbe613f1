//! The window's symmetry groups driven headless (issue 27): radial symmetry and the lathe turned
//! on with Shift+X on the tube — with the window's defaults, auto-refine on and the x mirror on —
//! then strokes pressed with the pointer, as `.ci/checks/window-live.sh` section 3c does in the
//! real window; and the Hand tool pressing with the same group.

use glam::Vec2;
use nendo::editor::command::Command;
use nendo::editor::input::{Button, PointerInput};
use nendo::editor::{Document, Modeller};
use nendo::mesh::{Tessellation, tessellate};
use nendo::model::Model;
use nendo::surface::{
    Grid, Plane, Primitive, PrimitiveParams, Symmetry, SymmetrySpec, group_error,
};

/// Sectors round the z axis the wall is measured in.
const SECTORS: usize = 64;

fn tube() -> Grid {
    Primitive::Tube
        .build(&PrimitiveParams::default())
        .expect("tube")
}

/// The window on the tube: the view framed on it, the finger radius 0.6 (with the default
/// 1.25 the eight images of a dihedral push overlap all the way round).
fn tube_modeller() -> Modeller {
    let mut m = Modeller::new(Document::new(Model::new(tube())), None, false);
    m.set_viewport(Vec2::new(990.0, 660.0));
    m.refresh();
    m.tool_panel().1.radius = 0.6;
    m.refresh();
    m
}

/// A left-button stroke at the view's centre dragged 40 pixels down, a frame after each move.
fn push_centre(m: &mut Modeller) {
    let c = m.viewport() * 0.5;
    m.pointer(PointerInput::Moved(c));
    m.refresh();
    m.pointer(PointerInput::Pressed(Button::Left, c));
    for dy in [10.0, 20.0, 30.0, 40.0] {
        m.pointer(PointerInput::Moved(c + Vec2::new(0.0, dy)));
        m.refresh();
    }
    m.pointer(PointerInput::Released(
        Button::Left,
        c + Vec2::new(0.0, 40.0),
    ));
    m.refresh();
}

/// Of [`SECTORS`] sectors round the z axis, those where the tessellated wall (2.1 < z < 5.9,
/// radius 2 before) comes inside radius 1.95 — the measure of the window check.
fn dented_sectors(grid: &Grid) -> Vec<usize> {
    let mesh = tessellate(&grid.patches(), &Tessellation::DISPLAY);
    let mut dented = [false; SECTORS];
    for p in &mesh.positions {
        let p = p.as_dvec3();
        if p.z > 2.1 && p.z < 5.9 && p.truncate().length() < 1.95 {
            let a = p.y.atan2(p.x).rem_euclid(std::f64::consts::TAU);
            dented[(a / std::f64::consts::TAU * SECTORS as f64) as usize % SECTORS] = true;
        }
    }
    (0..SECTORS).filter(|&s| dented[s]).collect()
}

fn status(m: &Modeller) -> (String, bool) {
    m.status()
        .map_or((String::new(), false), |s| (s.text.clone(), s.error))
}

/// How far the model is from invariant under `spec`'s group (relative to its size); infinite
/// when the group is refused.
fn invariance(grid: &Grid, spec: &SymmetrySpec) -> f64 {
    Symmetry::group(grid, spec).map_or(f64::INFINITY, |s| group_error(grid, &s))
}

fn dihedral(n: u32) -> SymmetrySpec {
    let mut spec = SymmetrySpec {
        radial: n,
        ..SymmetrySpec::default()
    };
    spec.add_plane(Plane::X);
    spec
}

/// The window's flow on the tube (the window check's section 3c, headless): Shift+X turns on
/// radial symmetry (N = 4, with the x mirror on by default) and a push at the view's centre —
/// auto-refined — dents the wall in some sectors, not all, and leaves the model invariant
/// under the dihedral group to 1e-12. Shift+X again asks for the lathe: the auto-refined,
/// radially dented model is no longer invariant under every column's turn, so the lathe turns
/// by the radial `N` (before the fix it was refused — the stroke after it was a radial one,
/// and the window check's lathe push dented nothing new); a push then dents every sector and
/// the model is still invariant to 1e-12.
#[test]
fn radial_then_lathe_strokes_on_the_tube() {
    let mut m = tube_modeller();
    m.apply(Command::ToggleRadial);
    let (text, error) = status(&m);
    assert!(!error && text.contains("4-fold"), "{text}");

    push_centre(&mut m);
    assert_eq!(m.document().history().undo_name(), Some("push"));
    let grid = m.document().model().surface.clone();
    assert!(
        grid.patch_count() > tube().patch_count(),
        "auto-refined: {} x {}",
        grid.patches_u(),
        grid.patches_v()
    );
    let radial_error = invariance(&grid, &dihedral(4));
    let radial = dented_sectors(&grid);
    eprintln!(
        "radial push: {} x {} patches, {} of {SECTORS} sectors dented, dihedral invariance {radial_error:e}",
        grid.patches_u(),
        grid.patches_v(),
        radial.len()
    );
    assert!(radial_error < 1e-12, "{radial_error:e}");
    assert!(
        radial.len() >= 8 && radial.len() < SECTORS,
        "some sectors, not all: {radial:?}"
    );
    let lathe_proper = SymmetrySpec {
        lathe: true,
        ..dihedral(0)
    };
    assert!(
        Symmetry::group(&grid, &lathe_proper).is_err(),
        "the radially dented model has no lathe symmetry of its own"
    );

    m.apply(Command::ToggleRadial);
    let (text, error) = status(&m);
    assert!(!error && text.contains("lathe"), "{text}");
    let revision = m.document().revision();
    push_centre(&mut m);
    assert!(
        m.document().revision() > revision,
        "the lathe push sculpted"
    );
    let grid = m.document().model().surface.clone();
    let lathe_error = invariance(&grid, &dihedral(4));
    let lathe = dented_sectors(&grid);
    eprintln!(
        "lathe push: {} x {} patches, {} of {SECTORS} sectors dented, dihedral invariance {lathe_error:e}",
        grid.patches_u(),
        grid.patches_v(),
        lathe.len()
    );
    assert!(lathe_error < 1e-12, "{lathe_error:e}");
    assert_eq!(lathe.len(), SECTORS, "dented all the way round");

    // Shift+X a third time: off.
    m.apply(Command::ToggleRadial);
    let (text, _) = status(&m);
    assert!(!text.contains("lathe") && !text.contains("fold"), "{text}");
}

/// On the undented tube the lathe is the lathe proper: every column's turn (Shift+X from a
/// radial symmetry with no stroke yet goes to it, not to the radial `N`).
#[test]
fn the_lathe_on_a_turned_model_turns_by_every_column() {
    let mut m = tube_modeller();
    m.apply(Command::ToggleRadial);
    m.apply(Command::ToggleRadial);
    let (text, error) = status(&m);
    assert!(
        !error && text.contains("lathe") && !text.contains("fold"),
        "{text}"
    );
}

/// The Hand tool presses with the window's group too: with radial symmetry on (N = 4, the x
/// mirror on) a hand press on the tube leaves the model invariant under the dihedral group to
/// 1e-12 relative, dents several sectors, and is one undo step back to the model before it.
#[test]
fn a_hand_press_with_radial_symmetry_keeps_the_tube_invariant() {
    let mut m = tube_modeller();
    m.apply(Command::UseMouseHand(
        nendo_devices::profile::MouseProfile::default(),
    ));
    m.apply(Command::ToggleRadial);
    let before = m.document().model().clone();
    let c = m.viewport() * 0.5;
    m.pointer(PointerInput::Moved(c));
    m.refresh();
    m.pointer(PointerInput::Pressed(Button::Left, c));
    m.refresh();
    m.pointer(PointerInput::Wheel(6.0));
    m.refresh();
    m.pointer(PointerInput::Released(Button::Left, c));
    m.refresh();
    m.pointer(PointerInput::Moved(Vec2::new(20.0, 20.0)));
    m.refresh();
    assert_eq!(m.document().history().undo_name(), Some("hand"));
    let grid = m.document().model().surface.clone();
    let error = invariance(&grid, &dihedral(4));
    let dented = dented_sectors(&grid);
    eprintln!(
        "hand press, radial 4 with the x mirror: {} of {SECTORS} sectors dented, dihedral invariance {error:e}",
        dented.len()
    );
    assert!(error < 1e-12, "{error:e}");
    assert!(dented.len() >= 8, "the images pressed too: {dented:?}");
    m.apply(Command::Undo);
    assert_eq!(m.document().model(), &before, "one undo step");
}
