//! The egui panels: file and edit commands, the new-primitive form, tools, regulation,
//! display options, the continuity and timing readouts, recording and replay; the keyboard
//! shortcuts. The modal prompts and the file dialog are in [`super::dialogs`].
//!
//! Each `*_ui` function draws from the state it is handed and returns the [`Command`]s the user
//! gave; it edits only plain settings in place (sliders, check boxes, the form) and never does
//! file I/O or touches the document — [`Modeller::apply`](crate::editor::Modeller::apply)
//! does.

use egui::{Color32, RichText, Ui};

use super::file_dialog::DialogPurpose;
use super::keymap::{self, KeyAction};
use crate::curve::edit::GrabMethod;
use crate::editor::autosave::Autosave;
use crate::editor::camera::ViewPreset;
use crate::editor::command::Command;
use crate::editor::document::OpTiming;
use crate::editor::export_job::{ExportJob, TOLERANCE_RANGE};
use crate::editor::history::History;
use crate::editor::input::OrbitButton;
use crate::editor::lifecycle::PrimitiveForm;
use crate::editor::live::LatencySummary;
use crate::editor::modeller::Status;
use crate::editor::scene::{Overlays, SurfaceDisplay};
use crate::editor::symmetry::MirrorToggle;
use crate::editor::tools::{DEPTH_RANGE, RADIUS_RANGE, STRENGTH_RANGE, Tool, ToolSettings};
use crate::surface::Falloff;
use crate::surface::continuity::ContinuityReport;
use crate::surface::{Primitive, Regulation, Topology};

const ERROR: Color32 = Color32::from_rgb(235, 95, 75);

/// The status line's hand feedback (the touched region's orange).
const HAND: Color32 = Color32::from_rgb(255, 140, 40);

/// Width of the tool panel, points (`.ci/checks/window.sh` clicks right of it).
pub(super) const PANEL_WIDTH: f32 = 290.0;

/// Frame timing for the Timing panel.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct FrameRate {
    /// Wall time of a frame from its start to the present, ms (exponentially smoothed).
    pub(super) frame_ms: f64,
    /// Frames in the last full second.
    pub(super) fps: u32,
}

/// The keys pressed this frame, as [`keymap`](super::keymap) actions (none while egui takes
/// the keyboard, a text field say).
pub(super) fn shortcuts_ui(ui: &mut Ui) -> Vec<KeyAction> {
    if ui.ctx().egui_wants_keyboard_input() {
        return Vec::new();
    }
    ui.input_mut(keymap::take_clutch_events);
    ui.input_mut(keymap::pressed)
}

/// The help overlay: every key and mouse binding, from the keymap. Returns false when the
/// user closed it.
pub(super) fn help_ui(ctx: &egui::Context, orbit: OrbitButton) -> bool {
    let mut open = true;
    egui::Window::new("Keys and mouse")
        .id(egui::Id::unique("nendo help"))
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::CENTER_CENTER, egui::Vec2::ZERO)
        .default_width(620.0)
        .max_width(620.0)
        .open(&mut open)
        .show(ctx, |ui| {
            egui::Grid::new("nendo help grid")
                .num_columns(2)
                .striped(true)
                .show(ui, |ui| {
                    for (input, does) in keymap::mouse(orbit) {
                        ui.strong(input);
                        ui.add(egui::Label::new(does).wrap());
                        ui.end_row();
                    }
                    let keys = keymap::keys();
                    let mut seen = Vec::new();
                    for binding in &keys {
                        if seen.contains(&binding.action) {
                            continue;
                        }
                        seen.push(binding.action);
                        let all: Vec<String> = keys
                            .iter()
                            .filter(|k| k.action == binding.action)
                            .map(keymap::KeyBinding::keys)
                            .collect();
                        ui.strong(all.join(", "));
                        ui.add(egui::Label::new(binding.action.describe()).wrap());
                        ui.end_row();
                    }
                    for binding in keymap::physical_keys() {
                        ui.strong(binding.label);
                        ui.add(egui::Label::new(binding.action.describe()).wrap());
                        ui.end_row();
                    }
                    for (keys, does) in keymap::held() {
                        ui.strong(keys);
                        ui.add(egui::Label::new(does).wrap());
                        ui.end_row();
                    }
                });
            ui.small("F1, ? or Esc closes this.");
        });
    open
}

/// The top bar: file, undo / redo, the named views.
pub(super) fn top_bar_ui(ui: &mut Ui, history: &History) -> Vec<Command> {
    let mut commands = Vec::new();
    ui.horizontal_wrapped(|ui| {
        if ui.button("Open…").on_hover_text("Ctrl+O").clicked() {
            commands.push(Command::ShowDialog(DialogPurpose::OpenModel));
        }
        if ui.button("Save").on_hover_text("Ctrl+S").clicked() {
            commands.push(Command::Save);
        }
        if ui
            .button("Save as…")
            .on_hover_text("Save the model to a new file")
            .clicked()
        {
            commands.push(Command::ShowDialog(DialogPurpose::SaveModel));
        }
        if ui
            .button("Export…")
            .on_hover_text(
                "OBJ, STL or GLB (meshes), STEP or IGES (exact), by the file's extension",
            )
            .clicked()
        {
            commands.push(Command::ShowDialog(DialogPurpose::ExportMesh));
        }
        ui.separator();
        let undo_text = match history.undo_name() {
            Some(w) => format!("Undo {w}"),
            None => "Undo".into(),
        };
        if ui
            .add_enabled(history.undo_name().is_some(), egui::Button::new(undo_text))
            .on_hover_text("Ctrl+Z")
            .clicked()
        {
            commands.push(Command::Undo);
        }
        if ui
            .add_enabled(history.redo_name().is_some(), egui::Button::new("Redo"))
            .on_hover_text("Ctrl+Shift+Z")
            .clicked()
        {
            commands.push(Command::Redo);
        }
        ui.label(format!(
            "{} steps, {:.1} MB",
            history.undo_len() + history.redo_len(),
            history.bytes() as f64 / 1e6
        ))
        .on_hover_text(format!(
            "Memory the undo history holds: what each edit changed, plus one copy of the model \
             ({:.1} MB). Past {:.0} MB the oldest steps are dropped.",
            history.base_bytes() as f64 / 1e6,
            history.limit_bytes() as f64 / 1e6
        ));
        ui.separator();
        for preset in [
            ViewPreset::Front,
            ViewPreset::Top,
            ViewPreset::Right,
            ViewPreset::Iso,
        ] {
            if ui
                .button(preset.name())
                .on_hover_text("Look from this side at the whole model")
                .clicked()
            {
                commands.push(Command::View(preset));
            }
        }
        if ui
            .button("frame")
            .on_hover_text("Frame the whole model (Home)")
            .clicked()
        {
            commands.push(Command::FrameAll);
        }
        ui.separator();
        if ui
            .button("Keys (F1)")
            .on_hover_text("Every key and mouse binding (F1 or ?)")
            .clicked()
        {
            commands.push(Command::ToggleHelp);
        }
    });
    commands
}

/// The new-primitive form and its Create button.
pub(super) fn primitive_ui(ui: &mut Ui, form: &mut PrimitiveForm) -> Vec<Command> {
    egui::ComboBox::from_id_salt("primitive")
        .selected_text(form.primitive.name())
        .show_ui(ui, |ui| {
            for p in Primitive::ALL {
                if ui.selectable_label(form.primitive == p, p.name()).clicked() {
                    *form = PrimitiveForm::defaults_for(p);
                }
            }
        });
    let topology = form.primitive.topology();
    ui.label(format!("topology: {}", topology.name()));
    let closed_u = !matches!(topology, Topology::Plane);
    ui.horizontal(|ui| {
        ui.label("patches");
        let step_u = if closed_u { 2.0 } else { 1.0 };
        ui.add(
            egui::DragValue::new(&mut form.patches.0)
                .range(1..=256)
                .speed(step_u)
                .prefix("M "),
        );
        ui.add(
            egui::DragValue::new(&mut form.patches.1)
                .range(1..=256)
                .prefix("N "),
        );
    });
    match form.primitive {
        Primitive::Plane => {}
        Primitive::Cylinder | Primitive::Tube => {
            ui.add(egui::Slider::new(&mut form.radius, 0.1..=20.0).text("radius"));
            ui.add(egui::Slider::new(&mut form.height, 0.1..=40.0).text("height"));
        }
        Primitive::Hemisphere | Primitive::Sphere => {
            ui.add(egui::Slider::new(&mut form.radius, 0.1..=20.0).text("radius"));
        }
        Primitive::Torus => {
            ui.add(egui::Slider::new(&mut form.radius, 0.1..=20.0).text("major radius"));
            ui.add(egui::Slider::new(&mut form.minor_radius, 0.05..=10.0).text("minor radius"));
        }
    }
    ui.label(format!("{} patches", form.patches.0 * form.patches.1));
    if ui
        .button("Create")
        .on_hover_text("Start a new model of this shape (asks first about unsaved changes)")
        .clicked()
    {
        vec![Command::Create(*form)]
    } else {
        Vec::new()
    }
}

/// The tool choice and its settings.
pub(super) fn tool_ui(
    ui: &mut Ui,
    tool: Tool,
    settings: &mut ToolSettings,
    mirror: &MirrorToggle,
    session_note: Option<&str>,
) -> Vec<Command> {
    let mut commands = Vec::new();
    let mut chosen = tool;
    let keys = super::keymap::keys();
    for t in Tool::ALL {
        let key: Vec<String> = keys
            .iter()
            .filter(|k| k.action == super::keymap::KeyAction::Tool(t))
            .map(super::keymap::KeyBinding::keys)
            .collect();
        ui.radio_value(&mut chosen, t, t.label())
            .on_hover_text(format!("{} (key {})", tool_help(t), key.join(", ")));
    }
    if chosen != tool {
        commands.push(Command::SelectTool(chosen));
    }
    commands.extend(symmetry_ui(ui, mirror, session_note));
    let s = settings;
    ui.add(
        egui::Slider::new(&mut s.radius, RADIUS_RANGE)
            .logarithmic(true)
            .text("finger radius"),
    )
    .on_hover_text("How far the finger reaches around the point pressed, in model units (F, then move the mouse)");
    ui.add(
        egui::Slider::new(&mut s.depth, DEPTH_RANGE)
            .logarithmic(true)
            .text("depth (click)"),
    )
    .on_hover_text("How deep a plain click pushes or pulls, and how deep a drawn line presses (Shift+F, then move the mouse)");
    ui.add(
        egui::Slider::new(&mut s.strength, STRENGTH_RANGE)
            .text("smooth strength"),
    )
    .on_hover_text("How much each smoothing dab relaxes the clay under the brush (an implicit fairing step of the surface: the dab diffuses it over about r·√(0.2·strength)): 1 is the longest step");
    egui::ComboBox::from_label("brush")
        .selected_text(s.falloff.name())
        .show_ui(ui, |ui| {
            for f in Falloff::ALL {
                ui.selectable_value(&mut s.falloff, f, f.name());
            }
        })
        .response
        .on_hover_text("The profile push, pull and draw a line press: finger (the paper's paraboloid 1 − r²/R²), soft ((1 − r²/R²)³, no rim) or flat (full depth to half the radius, a smooth rim)");
    ui.add(egui::Slider::new(&mut s.press_strength, STRENGTH_RANGE).text("brush strength"))
        .on_hover_text("The fraction of the depth push, pull and draw a line press");
    ui.checkbox(&mut s.ridge, "draw ridges (not grooves)")
        .on_hover_text(
            "Draw a line raises a ridge instead of cutting a groove (Ctrl while drawing swaps it)",
        );
    ui.add(
        egui::Slider::new(&mut s.probe_radius, 0.02..=3.0)
            .logarithmic(true)
            .text("probe sphere"),
    )
    .on_hover_text("The sphere drawn around the point under the cursor on a curve: the part of the curve inside it is highlighted, to see where a grab takes hold");
    let method_name = |m: GrabMethod| match m {
        GrabMethod::LargestWeight => "largest weight (P4)",
        GrabMethod::NearestParameter => "nearest parameter (P0)",
        GrabMethod::LeastChange => "least change",
    };
    let method_help = |m: GrabMethod| match m {
        GrabMethod::LargestWeight => {
            "moves the control point whose basis function weighs most at the grabbed point (Satoh–Miwa, P4): simple and local"
        }
        GrabMethod::NearestParameter => {
            "moves the control point nearest in parameter to the grabbed point (P0)"
        }
        GrabMethod::LeastChange => {
            "moves every control point, by the least total change (the sum of their squared moves) that puts the grabbed point under the cursor"
        }
    };
    egui::ComboBox::from_label("curve grab")
        .selected_text(method_name(s.grab.method))
        .show_ui(ui, |ui| {
            for m in [
                GrabMethod::LargestWeight,
                GrabMethod::NearestParameter,
                GrabMethod::LeastChange,
            ] {
                ui.selectable_value(&mut s.grab.method, m, method_name(m))
                    .on_hover_text(method_help(m));
            }
        });
    ui.checkbox(&mut s.grab.keep_ends, "keep curve end points")
        .on_hover_text("A curve grab never moves the curve's two end points");
    ui.small("Left: tool · Esc or right click: cancel a stroke · F1: every key");
    if tool == Tool::Hand {
        ui.small("Hand: the view ray is the finger. Press pushes, drag draws a groove; with Shift (or \"draw ridges\") the finger grips and pulls; the wheel while pressing goes deeper.");
    }
    if ui
        .button("Add a curve")
        .on_hover_text("a straight cubic above the surface, to grab and bend")
        .clicked()
    {
        commands.push(Command::AddCurve);
    }
    commands
}

/// The regulation method.
pub(super) fn regulation_ui(ui: &mut Ui, current: Regulation) -> Vec<Command> {
    let mut regulation = current;
    egui::ComboBox::from_id_salt("regulation")
        .selected_text(regulation.name())
        .show_ui(ui, |ui| {
            for r in Regulation::ALL {
                ui.selectable_value(&mut regulation, r, r.name())
                    .on_hover_text(regulation_help(r));
            }
        })
        .response
        .on_hover_text("How the control points around a stroke are adjusted afterwards so the patches still meet smoothly (tangent-continuous, G1)");
    ui.small(format!(
        "{}. A change applies to the next strokes; the surface as it is stays (or use \"Regulate now\").",
        regulation_help(current)
    ));
    let mut commands = Vec::new();
    if regulation != current {
        commands.push(Command::SetRegulation(regulation));
    }
    if ui
        .add_enabled(
            current != Regulation::None,
            egui::Button::new("Regulate now"),
        )
        .on_hover_text(format!(
            "apply {} to the whole surface now, every seam and pole (undoable)",
            current.name()
        ))
        .on_disabled_hover_text("regulation none adjusts nothing")
        .clicked()
    {
        commands.push(Command::RegulateNow);
    }
    commands
}

/// Refinement: the "Refine" command (every patch into 2 × 2) and the auto-refine setting.
pub(super) fn refine_ui(ui: &mut Ui, auto_refine: bool) -> Vec<Command> {
    let mut commands = Vec::new();
    if ui
        .button("Refine ×2")
        .on_hover_text("split every patch into 2 × 2; the surface does not change (undoable)")
        .clicked()
    {
        commands.push(Command::Refine);
    }
    let mut on = auto_refine;
    ui.checkbox(&mut on, "auto-refine under the finger")
        .on_hover_text(
            "before each push, pull or draw-a-line, split the patches the finger reaches until \
             they are at most half the finger radius across",
        );
    if on != auto_refine {
        commands.push(Command::SetAutoRefine(on));
    }
    commands
}

/// What to draw besides the clay.
pub(super) fn display_ui(
    ui: &mut Ui,
    overlays: &mut Overlays,
    orbit: &mut OrbitButton,
    max_seam_deg: f32,
) {
    let o = overlays;
    ui.checkbox(&mut o.patch_edges, "patch boundaries")
        .on_hover_text("Draw the edges between the Bezier patches the surface is made of (off by default: refined grids draw them as dense bands); the lines refinement added are drawn fainter than the primitive's own");
    ui.checkbox(&mut o.control_net, "control net")
        .on_hover_text("Draw the patches' control points, joined row by row: the numbers the surface is made from");
    ui.checkbox(&mut o.control_polygons, "curve control polygons")
        .on_hover_text("Draw each curve's control points, joined");
    ui.checkbox(&mut o.heat_map, "G1 heat map along seams")
        .on_hover_text("Colour the surface along each seam between patches by the angle between the two sides' normals there: 0° is perfectly smooth");
    if o.heat_map {
        ui.add(
            egui::Slider::new(&mut o.heat_max_deg, 0.0001..=30.0)
                .logarithmic(true)
                .text("° = red"),
        )
        .on_hover_text("The seam angle drawn red; smaller angles go yellow, cyan, blue; seams below 1 % of it are not coloured");
        heat_legend_ui(ui, o.heat_max_deg);
        if max_seam_deg < o.heat_max_deg {
            ui.label(format!("all seams ≤ {max_seam_deg:.2e}°: nothing is red"));
            if max_seam_deg > 0.0
                && ui
                    .button("scale to the worst seam")
                    .on_hover_text("Make the worst seam red, to see where the small angles are (under exact regulation they are rounding)")
                    .clicked()
            {
                o.heat_max_deg = max_seam_deg.max(0.0001);
            }
        } else {
            ui.label(format!("worst seam {max_seam_deg:.3}°"));
        }
    }
    ui.horizontal(|ui| {
        ui.label("orbit with");
        egui::ComboBox::from_id_salt("orbit button")
            .selected_text(orbit.label())
            .show_ui(ui, |ui| {
                for b in [OrbitButton::Right, OrbitButton::Middle] {
                    ui.selectable_value(orbit, b, b.label());
                }
            });
    })
    .response
    .on_hover_text("Which mouse button orbits the view; the other one pans");
}

/// The heat map's colours from 0° to `max_deg` (the shader's ramp, `modeller/shaders/clay.wgsl`).
fn heat_legend_ui(ui: &mut Ui, max_deg: f32) {
    let ramp = |t: f32| {
        let c = [
            [0.05, 0.15, 0.85],
            [0.0, 0.75, 0.8],
            [0.95, 0.85, 0.1],
            [0.9, 0.05, 0.02],
        ];
        let (a, b, u) = if t < 1.0 / 3.0 {
            (c[0], c[1], t * 3.0)
        } else if t < 2.0 / 3.0 {
            (c[1], c[2], (t - 1.0 / 3.0) * 3.0)
        } else {
            (c[2], c[3], (t - 2.0 / 3.0) * 3.0)
        };
        let mix = |k: usize| ((a[k] + (b[k] - a[k]) * u) * 255.0) as u8;
        Color32::from_rgb(mix(0), mix(1), mix(2))
    };
    let (rect, _) =
        ui.allocate_exact_size(egui::vec2(ui.available_width(), 12.0), egui::Sense::hover());
    let steps = 32;
    for k in 0..steps {
        let t = k as f32 / steps as f32;
        let x0 = rect.left() + rect.width() * t;
        let x1 = rect.left() + rect.width() * (k + 1) as f32 / steps as f32;
        ui.painter().rect_filled(
            egui::Rect::from_x_y_ranges(x0..=x1, rect.y_range()),
            0.0,
            ramp(t + 0.5 / steps as f32),
        );
    }
    ui.horizontal(|ui| {
        ui.small("0°");
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            ui.small(format!("{max_deg:.3}°"));
            ui.small(format!("{:.3}° ·", max_deg / 2.0));
        });
    });
}

/// What a regulation method does, in plain words.
fn regulation_help(r: Regulation) -> &'static str {
    match r {
        Regulation::None => {
            "none: the finger's deformation alone; the patches may meet at a crease"
        }
        Regulation::C1 => {
            "c1: the older method — neighbouring control points kept in equal steps; smooth only where the grid is even"
        }
        Regulation::G1 => {
            "g1: the paper's method — smooth at the grid's corners, along an edge only where it can be"
        }
        Regulation::Exact => {
            "exact: the nearest surface that meets smoothly everywhere (to rounding), poles included"
        }
        Regulation::G2 => {
            "g2: as exact, and the curvature continuous across every seam (no reflection-line kinks); a stroke moves a few patches more"
        }
    }
}

/// What a tool does, in plain words.
fn tool_help(t: Tool) -> &'static str {
    match t {
        Tool::Push => "Press a dent: drag to set the depth, live; Ctrl pulls instead",
        Tool::Pull => "Pull a bump: drag to set the height, live; Ctrl pushes instead",
        Tool::DrawLine => "Drag along the surface to cut a groove (Ctrl: a ridge)",
        Tool::GrabCurve => "Grab a curve anywhere and move it",
        Tool::SplitCurve => "Click a curve to split it in two there",
        Tool::Tangent => "Drag a handle at a joint of two curves; the other side stays in line",
        Tool::Move => {
            "Grab the clay and move it (G): the point pressed follows the cursor, the clay within the finger radius follows it; the wheel moves it nearer or farther"
        }
        Tool::Smooth => {
            "Drag over the clay to smooth it (Shift with Push, Pull or Draw a line does the same)"
        }
        Tool::Hand => "The mouse drives the virtual hand: the view ray is the finger",
        Tool::Inflate => {
            "Press or drag over the clay to swell it along its own normals by the depth, brush and strength (Ctrl: deflate)"
        }
        Tool::Flatten => {
            "Press or drag over the clay to move it toward the average plane under the brush, by the brush strength"
        }
        Tool::Pinch => {
            "Drag over the clay to draw it together toward the stroke along the surface, by the brush strength"
        }
        Tool::Crease => {
            "Drag over the clay to pinch it toward the stroke and press it in by the depth: a sharp valley (Ctrl: a ridge)"
        }
    }
}

/// The symmetry checkbox: on when wanted and the model allows it; disabled, with the reason,
/// when it does not. Below it, what the symmetry is made of: the mirrors across x, y and z,
/// radial symmetry about the z axis with its `N`, the lathe; a change the model does not
/// allow is refused with the reason on the status line. Under them, `session_note`: the group
/// a device session presses with when the toggle does not govern it (a recording's, a replayed
/// trace's).
fn symmetry_ui(ui: &mut Ui, mirror: &MirrorToggle, session_note: Option<&str>) -> Vec<Command> {
    let available = mirror.available();
    let mut on = mirror.wanted() && available;
    let label = format!("symmetry ({})", mirror.spec());
    let response = ui.add_enabled(available, egui::Checkbox::new(&mut on, label));
    match mirror.why_not() {
        Some(why) => {
            response.on_disabled_hover_text(why);
        }
        None => {
            response.on_hover_text(
                "Every stroke is applied together with its images (mirrored, turned about the z axis), as one operation (X; Shift+X: radial). The planes and the axis are drawn in the view. The Hand tool's contacts and a glove session's too, taken up between contacts; a recording glove session keeps the symmetry it started with until it stops, and a replayed trace presses with its scene's, as nendo replay does.",
            );
        }
    }
    let mut commands = Vec::new();
    if available && on != mirror.wanted() {
        commands.push(Command::SetSymmetry(on));
    }
    let spec = mirror.spec();
    let mut wanted = spec.clone();
    ui.horizontal(|ui| {
        ui.label("mirror");
        for plane in crate::surface::Plane::ALL {
            let mut has = spec.planes.contains(&plane);
            if ui.checkbox(&mut has, plane.name()).changed() {
                wanted.planes.retain(|p| *p != plane);
                if has {
                    wanted.add_plane(plane);
                }
            }
        }
    });
    ui.horizontal(|ui| {
        let mut radial = spec.radial > 1 && !spec.lathe;
        let mut n = mirror.radial_n();
        if ui
            .checkbox(&mut radial, "radial")
            .on_hover_text("N-fold about the z axis (Shift+X); N must divide the patch columns")
            .changed()
        {
            wanted = mirror.with_radial(radial);
            wanted.planes.clone_from(&spec.planes);
        }
        if ui
            .add(egui::DragValue::new(&mut n).range(2..=64).prefix("N "))
            .changed()
        {
            wanted.radial = n;
            wanted.lathe = false;
        }
        let mut lathe = spec.lathe;
        if ui
            .checkbox(&mut lathe, "lathe")
            .on_hover_text("every stroke applied all the way round the z axis")
            .changed()
        {
            wanted.lathe = lathe;
            wanted.radial = 0;
        }
    });
    if let Some(note) = session_note {
        ui.small(note);
    }
    if &wanted != spec {
        commands.push(Command::SetSymmetrySpec(wanted));
    }
    commands
}

/// The export tolerance, and the export in progress or its button.
pub(super) fn export_ui(ui: &mut Ui, tolerance: &mut f64, job: Option<&ExportJob>) -> Vec<Command> {
    ui.add(
        egui::Slider::new(tolerance, TOLERANCE_RANGE)
            .logarithmic(true)
            .text("tolerance (side)"),
    );
    ui.small("Largest distance from the mesh to the surface. OBJ (with normals), binary STL or GLB, by the file's extension; STEP (.step) or IGES (.igs) write the exact patches and curves instead (millimetres). Written in the background.");
    match job {
        Some(job) => {
            ui.label(format!(
                "exporting {}… {:.0} s",
                job.path().display(),
                job.elapsed_s()
            ));
            Vec::new()
        }
        None if ui.button("Export…").clicked() => {
            vec![Command::ShowDialog(DialogPurpose::ExportMesh)]
        }
        None => Vec::new(),
    }
}

/// The continuity readout: `report` took `measure_ms`; `max_seam_deg` is the mesh's.
pub(super) fn continuity_ui(
    ui: &mut Ui,
    report: Option<&ContinuityReport>,
    measure_ms: f64,
    max_seam_deg: f32,
) {
    let Some(r) = report else {
        ui.label("measuring…");
        return;
    };
    egui::Grid::new("continuity").num_columns(2).show(ui, |ui| {
        ui.label("G1 max").on_hover_text(
            "The largest angle between the two sides' normals along any seam between patches: 0° is perfectly smooth",
        );
        ui.label(format!("{:.4}°", r.g1_max_deg));
        ui.end_row();
        ui.label("G1 mean");
        ui.label(format!("{:.4}°", r.g1_mean_deg));
        ui.end_row();
        ui.label("G0 gap")
            .on_hover_text("The largest distance between two patches along a seam they share: 0 when they meet");
        ui.label(format!("{:.2e}", r.g0_gap));
        ui.end_row();
        for pole in &r.poles {
            ui.label(format!("pole {:?} spread", pole.end));
            ui.label(format!("{:.4}°", pole.spread_deg));
            ui.end_row();
        }
        ui.label("seam (mesh) max");
        ui.label(format!("{max_seam_deg:.4}°"));
        ui.end_row();
    });
    ui.small(format!(
        "{} shared edges × {} points, {} undefined normals; measured in {measure_ms:.1} ms",
        r.shared_edges, r.samples_per_edge, r.undefined_normals
    ));
}

/// The timing readout.
pub(super) fn timing_ui(
    ui: &mut Ui,
    last_op: Option<&OpTiming>,
    display: &SurfaceDisplay,
    rate: FrameRate,
) {
    egui::Grid::new("timing").num_columns(2).show(ui, |ui| {
        ui.label("last operation");
        match last_op {
            Some(t) => ui.label(format!("{:.2} ms, {} patches", t.ms, t.patches)),
            None => ui.label("—"),
        };
        ui.end_row();
        ui.label("tessellation");
        ui.label(format!(
            "{:.2} ms, {} triangles",
            display.tessellate_ms,
            display.mesh.triangle_count()
        ));
        ui.end_row();
        ui.label("frame (to present)");
        ui.label(format!("{:.1} ms", rate.frame_ms));
        ui.end_row();
        ui.label("frame rate");
        ui.label(format!("{} /s", rate.fps));
        ui.end_row();
    });
}

/// Recording and replay: `recorded` operations so far when recording, `(next, of)` when
/// replaying.
pub(super) fn record_ui(
    ui: &mut Ui,
    recorded: Option<usize>,
    replaying: Option<(usize, usize)>,
) -> Vec<Command> {
    let mut commands = Vec::new();
    match recorded {
        None => {
            if ui
                .button("Record operations")
                .on_hover_text("Keep every operation from now on, to save as a file `nendo sculpt --ops` or Replay can run again")
                .clicked()
            {
                commands.push(Command::StartRecording);
            }
        }
        Some(n) => {
            ui.label(format!("recording: {n} operations"));
            if ui.button("Stop and save…").clicked() {
                commands.push(Command::ShowDialog(DialogPurpose::SaveOps));
            }
            if ui.button("Discard recording").clicked() {
                commands.push(Command::DiscardRecording);
            }
        }
    }
    match replaying {
        None => {
            if ui
                .button("Replay operations…")
                .on_hover_text(
                    "Apply the operations of a recorded file to this model, one per frame",
                )
                .clicked()
            {
                commands.push(Command::ShowDialog(DialogPurpose::ReplayOps));
            }
        }
        Some((next, of)) => {
            ui.label(format!("replaying {next} / {of}"));
            if ui.button("Stop replay").clicked() {
                commands.push(Command::StopReplay);
            }
        }
    }
    ui.small("Operations are JSON lines, as `nendo sculpt --ops` reads them.");
    commands
}

/// The status line: the hand's contact or clutch, the last message, the autosave's file or
/// error, and while a device session runs, the device samples' latency to the frame that shows
/// them.
pub(super) fn status_ui(
    ui: &mut Ui,
    hand: Option<&str>,
    status: Option<&Status>,
    autosave: Option<&Autosave>,
    latency: Option<&LatencySummary>,
) {
    ui.horizontal(|ui| {
        if let Some(h) = hand {
            ui.label(RichText::new(h).strong().color(HAND));
            ui.separator();
        }
        if let Some(l) = latency {
            ui.small(l.line());
            ui.separator();
        }
        if let Some(s) = status {
            let text = RichText::new(&s.text);
            ui.label(if s.error { text.color(ERROR) } else { text });
        }
        if let Some(a) = autosave {
            ui.separator();
            match &a.last_error {
                Some(e) => ui.colored_label(ERROR, format!("autosave: {e}")),
                None => ui.small(format!("autosave: {}", a.path().display())),
            };
        }
    });
}
