//! The egui panels: file and edit commands, the new-primitive form, tools, regulation,
//! display options, the continuity and timing readouts, recording and replay; the modal
//! prompts and the file dialog; the keyboard shortcuts.
//!
//! Each `*_ui` function draws from the state it is handed and returns the [`Command`]s the user
//! gave; it edits only plain settings in place (sliders, check boxes, the form) and never does
//! file I/O or touches the document — [`Modeller::apply`](super::Modeller::apply) does.

use egui::{Color32, Key, KeyboardShortcut, Modifiers, RichText, Ui};

use super::autosave::Autosave;
use super::camera::ViewPreset;
use super::command::Command;
use super::document::OpTiming;
use super::export_job::{ExportJob, TOLERANCE_RANGE};
use super::file_dialog::{DialogPurpose, DialogResult, FileDialog};
use super::history::History;
use super::lifecycle::{Pending, PrimitiveForm, Prompt, UnsavedAnswer};
use super::scene::{Overlays, SurfaceDisplay};
use super::tools::{Tool, ToolSettings};
use crate::curve::edit::GrabMethod;
use crate::surface::continuity::ContinuityReport;
use crate::surface::{Primitive, Regulation, Topology};

const ERROR: Color32 = Color32::from_rgb(235, 95, 75);

/// Width of the tool panel, points (`.ci/checks/window.sh` clicks right of it).
pub(super) const PANEL_WIDTH: f32 = 290.0;

/// A message for the status line.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Status {
    /// The message.
    pub(super) text: String,
    /// Shown as an error.
    pub(super) error: bool,
}

/// Frame timing for the Timing panel.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct FrameRate {
    /// Wall time of a frame from its start to the present, ms (exponentially smoothed).
    pub(super) frame_ms: f64,
    /// Frames in the last full second.
    pub(super) fps: u32,
}

/// The keyboard shortcuts (none while egui takes the keyboard, a text field say).
pub(super) fn shortcuts_ui(ui: &mut Ui) -> Vec<Command> {
    if ui.ctx().egui_wants_keyboard_input() {
        return Vec::new();
    }
    let redo = KeyboardShortcut::new(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    let redo_y = KeyboardShortcut::new(Modifiers::COMMAND, Key::Y);
    let undo = KeyboardShortcut::new(Modifiers::COMMAND, Key::Z);
    let save = KeyboardShortcut::new(Modifiers::COMMAND, Key::S);
    let open = KeyboardShortcut::new(Modifiers::COMMAND, Key::O);
    // Consume the longer shortcut first: Ctrl+Shift+Z also matches Ctrl+Z.
    let (r1, r2, u, s, o, f) = ui.input_mut(|i| {
        (
            i.consume_shortcut(&redo),
            i.consume_shortcut(&redo_y),
            i.consume_shortcut(&undo),
            i.consume_shortcut(&save),
            i.consume_shortcut(&open),
            i.consume_key(Modifiers::NONE, Key::F),
        )
    });
    let mut commands = Vec::new();
    if r1 || r2 {
        commands.push(Command::Redo);
    }
    if u {
        commands.push(Command::Undo);
    }
    if s {
        commands.push(Command::Save);
    }
    if o {
        commands.push(Command::ShowDialog(DialogPurpose::OpenModel));
    }
    if f {
        commands.push(Command::FrameAll);
    }
    commands
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
        if ui.button("Save as…").clicked() {
            commands.push(Command::ShowDialog(DialogPurpose::SaveModel));
        }
        if ui
            .button("Export…")
            .on_hover_text("OBJ, STL or GLB, by the file's extension")
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
            if ui.button(preset.name()).clicked() {
                commands.push(Command::View(preset));
            }
        }
        if ui.button("frame").on_hover_text("F").clicked() {
            commands.push(Command::FrameAll);
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
    if ui.button("Create").clicked() {
        vec![Command::Create(*form)]
    } else {
        Vec::new()
    }
}

/// The tool choice and its settings.
pub(super) fn tool_ui(ui: &mut Ui, tool: Tool, settings: &mut ToolSettings) -> Vec<Command> {
    let mut commands = Vec::new();
    let mut chosen = tool;
    for t in Tool::ALL {
        ui.radio_value(&mut chosen, t, t.label());
    }
    if chosen != tool {
        commands.push(Command::SelectTool(chosen));
    }
    let s = settings;
    ui.add(
        egui::Slider::new(&mut s.radius, 0.05..=6.0)
            .logarithmic(true)
            .text("finger radius"),
    );
    ui.add(
        egui::Slider::new(&mut s.depth, 0.01..=3.0)
            .logarithmic(true)
            .text("depth (click)"),
    );
    ui.checkbox(&mut s.ridge, "draw ridges (not grooves)");
    ui.add(
        egui::Slider::new(&mut s.probe_radius, 0.02..=3.0)
            .logarithmic(true)
            .text("probe sphere"),
    );
    let method_name = |m: GrabMethod| match m {
        GrabMethod::LargestWeight => "largest weight (seed 004)",
        GrabMethod::NearestParameter => "nearest parameter (seed 000)",
        GrabMethod::LeastChange => "least change",
    };
    egui::ComboBox::from_label("curve grab")
        .selected_text(method_name(s.grab.method))
        .show_ui(ui, |ui| {
            for m in [
                GrabMethod::LargestWeight,
                GrabMethod::NearestParameter,
                GrabMethod::LeastChange,
            ] {
                ui.selectable_value(&mut s.grab.method, m, method_name(m));
            }
        });
    ui.checkbox(&mut s.grab.keep_ends, "keep curve end points");
    ui.small("Left: tool · Right drag: orbit · Middle or Shift+Right: pan · Wheel: zoom (while pressing: depth)");
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
                ui.selectable_value(&mut regulation, r, r.name());
            }
        });
    if regulation == current {
        Vec::new()
    } else {
        vec![Command::SetRegulation(regulation)]
    }
}

/// What to draw besides the clay.
pub(super) fn display_ui(ui: &mut Ui, overlays: &mut Overlays) {
    let o = overlays;
    ui.checkbox(&mut o.patch_edges, "patch boundaries");
    ui.checkbox(&mut o.control_net, "control net");
    ui.checkbox(&mut o.control_polygons, "curve control polygons");
    ui.checkbox(&mut o.heat_map, "G1 heat map along seams");
    ui.add_enabled(
        o.heat_map,
        egui::Slider::new(&mut o.heat_max_deg, 0.01..=30.0)
            .logarithmic(true)
            .text("° = red"),
    );
}

/// The export tolerance, and the export in progress or its button.
pub(super) fn export_ui(ui: &mut Ui, tolerance: &mut f64, job: Option<&ExportJob>) -> Vec<Command> {
    ui.add(
        egui::Slider::new(tolerance, TOLERANCE_RANGE)
            .logarithmic(true)
            .text("tolerance (side)"),
    );
    ui.small("Largest distance from the mesh to the surface. OBJ (with normals), binary STL or GLB, by the file's extension. Written in the background.");
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
        ui.label("G1 max");
        ui.label(format!("{:.4}°", r.g1_max_deg));
        ui.end_row();
        ui.label("G1 mean");
        ui.label(format!("{:.4}°", r.g1_mean_deg));
        ui.end_row();
        ui.label("G0 gap");
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
            if ui.button("Record operations").clicked() {
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
            if ui.button("Replay operations…").clicked() {
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

/// The status line: the last message and the autosave's file or error.
pub(super) fn status_ui(ui: &mut Ui, status: Option<&Status>, autosave: Option<&Autosave>) {
    ui.horizontal(|ui| {
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

/// The modal question.
pub(super) fn prompt_ui(ctx: &egui::Context, prompt: &Prompt) -> Vec<Command> {
    let mut commands = Vec::new();
    egui::Modal::new(egui::Id::unique("nendo prompt")).show(ctx, |ui| match prompt {
        Prompt::Recover(path) => {
            ui.heading("Recover unsaved work?");
            ui.label(format!(
                "An autosave from a session that did not close cleanly exists:\n{}",
                path.display()
            ));
            ui.horizontal(|ui| {
                if ui.button("Recover").clicked() {
                    commands.push(Command::Recover(path.clone()));
                }
                if ui.button("Discard it").clicked() {
                    commands.push(Command::DiscardRecovery);
                }
            });
        }
        Prompt::Unsaved(action) => {
            ui.heading("Unsaved changes");
            let (what, discard) = match action {
                Pending::Close => ("before closing".to_string(), "Quit without saving"),
                Pending::Create(form) => (
                    format!("before starting a new {}", form.primitive.name()),
                    "Discard changes",
                ),
                Pending::Open(path) => (
                    format!("before opening {}", path.display()),
                    "Discard changes",
                ),
            };
            ui.label(format!(
                "The model has changes that are not saved. Save them {what}?"
            ));
            ui.horizontal(|ui| {
                if ui.button("Save…").clicked() {
                    commands.push(Command::AnswerUnsaved(UnsavedAnswer::Save));
                }
                if ui.button(discard).clicked() {
                    commands.push(Command::AnswerUnsaved(UnsavedAnswer::Discard));
                }
                if ui.button("Cancel").clicked() {
                    commands.push(Command::AnswerUnsaved(UnsavedAnswer::Cancel));
                }
            });
        }
    });
    commands
}

/// The file dialog.
pub(super) fn dialog_ui(ctx: &egui::Context, dialog: &mut FileDialog) -> Vec<Command> {
    let purpose = dialog.purpose;
    match dialog.ui(ctx) {
        DialogResult::Open => Vec::new(),
        DialogResult::Cancelled => vec![Command::DialogCancelled],
        DialogResult::Chosen(path) => vec![Command::DialogChosen(purpose, path)],
    }
}
