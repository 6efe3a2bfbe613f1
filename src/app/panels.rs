//! The egui panels: file and edit commands, the new-primitive form, tools, regulation,
//! display options, the continuity and timing readouts, recording and replay, devices; and the
//! modal prompts and file dialogs.

use egui::{Color32, Key, KeyboardShortcut, Modifiers, RichText, Ui};
use std::path::{Path, PathBuf};

use super::camera::ViewPreset;
use super::curve_edit::straight_cubic;
use super::export_job::{ExportJob, TOLERANCE_RANGE};
use super::file_dialog::{DialogPurpose, DialogResult, FileDialog};
use super::modeller::{Modeller, Pending, PrimitiveForm, Prompt, Replay, UnsavedAnswer};
use super::tools::Tool;
use crate::curve::edit::GrabMethod;
use crate::curve::json::DynCurve;
use crate::mesh::Tessellation;
use crate::model::ops::{op_to_json, parse_ops};
use crate::surface::{Primitive, Regulation, Topology};

const ERROR: Color32 = Color32::from_rgb(235, 95, 75);

/// Width of the tool panel, points (`.ci/checks/window.sh` clicks right of it).
pub(super) const PANEL_WIDTH: f32 = 290.0;

impl Modeller {
    /// Draws the panels and dialogs; returns the rectangle left for the 3D view, in points.
    pub fn ui(&mut self, ui: &mut Ui) -> egui::Rect {
        self.shortcuts(ui);
        egui::Panel::top("nendo top").show(ui, |ui| self.top_bar_ui(ui));
        egui::Panel::left("nendo tools")
            .exact_size(PANEL_WIDTH)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.side_panel_ui(ui));
            });
        egui::Panel::bottom("nendo status").show(ui, |ui| self.status_ui(ui));
        let ctx = ui.ctx().clone();
        self.prompt_ui(&ctx);
        self.dialog_ui(&ctx);
        ui.available_rect_before_wrap()
    }

    fn shortcuts(&mut self, ui: &mut Ui) {
        if ui.ctx().egui_wants_keyboard_input() {
            return;
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
        self.shift = ui.input(|i| i.modifiers.shift);
        if r1 || r2 {
            self.redo();
        }
        if u {
            self.undo();
        }
        if s {
            self.save();
        }
        if o {
            self.open_dialog(DialogPurpose::OpenModel);
        }
        if f {
            self.frame_all();
        }
    }

    pub(super) fn undo(&mut self) {
        self.tools.cancel();
        self.end_hand_contacts();
        if !self.doc.undo() {
            self.set_status("nothing to undo", false);
        }
    }

    pub(super) fn redo(&mut self) {
        self.tools.cancel();
        self.end_hand_contacts();
        if !self.doc.redo() {
            self.set_status("nothing to redo", false);
        }
    }

    fn save(&mut self) {
        match self.doc.path.clone() {
            Some(path) => {
                self.save_to(&path);
            }
            None => self.open_dialog(DialogPurpose::SaveModel),
        }
    }

    /// Opens a file dialog (forgetting any action that waited for an earlier save dialog).
    pub(super) fn open_dialog(&mut self, purpose: DialogPurpose) {
        self.after_save = None;
        let default = match purpose {
            DialogPurpose::SaveModel | DialogPurpose::OpenModel => "model.nendo.json",
            DialogPurpose::ExportMesh => "model.obj",
            DialogPurpose::SaveOps | DialogPurpose::ReplayOps => "ops.jsonl",
        };
        self.dialog = Some(FileDialog::beside(
            purpose,
            self.doc.path.as_deref(),
            default,
        ));
    }

    /// Starts exporting the surface to `path` on its own thread (see [`ExportJob`]).
    fn export(&mut self, path: &Path) {
        if let Some(job) = &self.export_job {
            let busy = format!("still exporting {}", job.path().display());
            return self.set_status(busy, true);
        }
        let tolerance = self
            .export_tolerance
            .clamp(*TOLERANCE_RANGE.start(), *TOLERANCE_RANGE.end());
        match ExportJob::start(
            self.patches.clone(),
            path.to_path_buf(),
            Tessellation::with_tolerance(tolerance),
        ) {
            Ok(job) => {
                self.set_status(format!("exporting {}…", path.display()), false);
                self.export_job = Some(job);
            }
            Err(e) => self.set_status(e, true),
        }
    }

    fn top_bar_ui(&mut self, ui: &mut Ui) {
        ui.horizontal_wrapped(|ui| {
            if ui.button("Open…").on_hover_text("Ctrl+O").clicked() {
                self.open_dialog(DialogPurpose::OpenModel);
            }
            if ui.button("Save").on_hover_text("Ctrl+S").clicked() {
                self.save();
            }
            if ui.button("Save as…").clicked() {
                self.open_dialog(DialogPurpose::SaveModel);
            }
            if ui
                .button("Export…")
                .on_hover_text("OBJ, STL or GLB, by the file's extension")
                .clicked()
            {
                self.open_dialog(DialogPurpose::ExportMesh);
            }
            ui.separator();
            let undo_text = match self.doc.history().undo_name() {
                Some(w) => format!("Undo {w}"),
                None => "Undo".into(),
            };
            if ui
                .add_enabled(
                    self.doc.history().undo_name().is_some(),
                    egui::Button::new(undo_text),
                )
                .on_hover_text("Ctrl+Z")
                .clicked()
            {
                self.undo();
            }
            if ui
                .add_enabled(
                    self.doc.history().redo_name().is_some(),
                    egui::Button::new("Redo"),
                )
                .on_hover_text("Ctrl+Shift+Z")
                .clicked()
            {
                self.redo();
            }
            ui.separator();
            for preset in [
                ViewPreset::Front,
                ViewPreset::Top,
                ViewPreset::Right,
                ViewPreset::Iso,
            ] {
                if ui.button(preset.name()).clicked() {
                    self.view_from(preset);
                }
            }
            if ui.button("frame").on_hover_text("F").clicked() {
                self.frame_all();
            }
        });
    }

    fn side_panel_ui(&mut self, ui: &mut Ui) {
        egui::CollapsingHeader::new("New primitive")
            .default_open(false)
            .show(ui, |ui| self.primitive_ui(ui));
        egui::CollapsingHeader::new("Tool")
            .default_open(true)
            .show(ui, |ui| self.tool_ui(ui));
        egui::CollapsingHeader::new("Regulation")
            .default_open(true)
            .show(ui, |ui| {
                let mut regulation = self.doc.model().regulation;
                egui::ComboBox::from_id_salt("regulation")
                    .selected_text(regulation.name())
                    .show_ui(ui, |ui| {
                        for r in Regulation::ALL {
                            ui.selectable_value(&mut regulation, r, r.name());
                        }
                    });
                self.doc.set_regulation(regulation);
            });
        egui::CollapsingHeader::new("Display")
            .default_open(true)
            .show(ui, |ui| {
                let o = &mut self.overlays;
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
            });
        egui::CollapsingHeader::new("Export").default_open(false).show(ui, |ui| {
            ui.add(
                egui::Slider::new(&mut self.export_tolerance, TOLERANCE_RANGE)
                    .logarithmic(true)
                    .text("tolerance (side)"),
            );
            ui.small("Largest distance from the mesh to the surface. OBJ (with normals), binary STL or GLB, by the file's extension. Written in the background.");
            match &self.export_job {
                Some(job) => {
                    ui.label(format!(
                        "exporting {}… {:.0} s",
                        job.path().display(),
                        job.elapsed_s()
                    ));
                }
                None => {
                    if ui.button("Export…").clicked() {
                        self.open_dialog(DialogPurpose::ExportMesh);
                    }
                }
            }
        });
        egui::CollapsingHeader::new("Continuity")
            .default_open(true)
            .show(ui, |ui| self.continuity_ui(ui));
        egui::CollapsingHeader::new("Timing")
            .default_open(true)
            .show(ui, |ui| self.timing_ui(ui));
        egui::CollapsingHeader::new("Record / replay")
            .default_open(false)
            .show(ui, |ui| self.record_ui(ui));
        egui::CollapsingHeader::new("Devices")
            .default_open(false)
            .show(ui, |ui| {
                if let Some(profile) = self.live.ui(ui, self.settings.radius, &mut self.doc) {
                    self.use_mouse_hand(profile);
                }
            });
    }

    fn primitive_ui(&mut self, ui: &mut Ui) {
        let mut form = self.form;
        egui::ComboBox::from_id_salt("primitive")
            .selected_text(form.primitive.name())
            .show_ui(ui, |ui| {
                for p in Primitive::ALL {
                    if ui.selectable_label(form.primitive == p, p.name()).clicked() {
                        form = PrimitiveForm::defaults_for(p);
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
        self.form = form;
        if ui.button("Create").clicked() {
            self.new_from_form();
        }
    }

    fn tool_ui(&mut self, ui: &mut Ui) {
        let mut chosen = self.tool;
        for tool in Tool::ALL {
            ui.radio_value(&mut chosen, tool, tool.label());
        }
        self.select_tool(chosen);
        let s = &mut self.settings;
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
        if self.tool == Tool::Hand {
            ui.small("Hand: the view ray is the finger. Press pushes, drag draws a groove; with Shift (or \"draw ridges\") the finger grips and pulls; the wheel while pressing goes deeper.");
        }
        if ui
            .button("Add a curve")
            .on_hover_text("a straight cubic above the surface, to grab and bend")
            .clicked()
        {
            let (lo, hi) = self
                .surface()
                .mesh
                .bounds()
                .unwrap_or((glam::Vec3::splat(-1.0), glam::Vec3::splat(1.0)));
            let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
            let z = hi.z + 0.25 * (hi - lo).length();
            let mid_y = 0.5 * (lo.y + hi.y);
            let curve = straight_cubic(
                glam::DVec3::new(lo.x, mid_y, z),
                glam::DVec3::new(hi.x, mid_y, z),
            );
            self.end_hand_contacts();
            self.doc.begin_edit("add curve");
            self.doc.curves_mut().push(DynCurve::D3(curve));
            self.select_tool(Tool::GrabCurve);
        }
    }

    fn continuity_ui(&mut self, ui: &mut Ui) {
        let Some(r) = &self.continuity else {
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
            ui.label(format!("{:.4}°", self.display.max_seam_deg));
            ui.end_row();
        });
        ui.small(format!(
            "{} shared edges × {} points, {} undefined normals; measured in {:.1} ms",
            r.shared_edges, r.samples_per_edge, r.undefined_normals, self.continuity_ms
        ));
    }

    fn timing_ui(&mut self, ui: &mut Ui) {
        egui::Grid::new("timing").num_columns(2).show(ui, |ui| {
            ui.label("last operation");
            match &self.doc.last_op {
                Some(t) => ui.label(format!("{:.2} ms, {} patches", t.ms, t.patches)),
                None => ui.label("—"),
            };
            ui.end_row();
            ui.label("tessellation");
            ui.label(format!(
                "{:.2} ms, {} triangles",
                self.display.tessellate_ms,
                self.display.mesh.triangle_count()
            ));
            ui.end_row();
            ui.label("frame (to present)");
            ui.label(format!("{:.1} ms", self.timing.frame_ms));
            ui.end_row();
            ui.label("frame rate");
            ui.label(format!("{} /s", self.timing.fps));
            ui.end_row();
        });
    }

    fn record_ui(&mut self, ui: &mut Ui) {
        match &self.doc.recording {
            None => {
                if ui.button("Record operations").clicked() {
                    self.doc.recording = Some(Vec::new());
                }
            }
            Some(ops) => {
                ui.label(format!("recording: {} operations", ops.len()));
                if ui.button("Stop and save…").clicked() {
                    self.open_dialog(DialogPurpose::SaveOps);
                }
                if ui.button("Discard recording").clicked() {
                    self.doc.recording = None;
                }
            }
        }
        match &self.replay {
            None => {
                if ui.button("Replay operations…").clicked() {
                    self.open_dialog(DialogPurpose::ReplayOps);
                }
            }
            Some(r) => {
                ui.label(format!("replaying {} / {}", r.next, r.ops.len()));
                if ui.button("Stop replay").clicked() {
                    self.replay = None;
                }
            }
        }
        ui.small("Operations are JSON lines, as `nendo sculpt --ops` reads them.");
    }

    fn status_ui(&mut self, ui: &mut Ui) {
        ui.horizontal(|ui| {
            if let Some(s) = &self.status {
                let text = RichText::new(&s.text);
                ui.label(if s.error { text.color(ERROR) } else { text });
            }
            if let Some(a) = &self.autosave {
                ui.separator();
                match &a.last_error {
                    Some(e) => ui.colored_label(ERROR, format!("autosave: {e}")),
                    None => ui.small(format!("autosave: {}", a.path().display())),
                };
            }
        });
    }

    fn prompt_ui(&mut self, ctx: &egui::Context) {
        let Some(prompt) = self.prompt.clone() else {
            return;
        };
        egui::Modal::new(egui::Id::unique("nendo prompt")).show(ctx, |ui| match prompt {
            Prompt::Recover(path) => {
                ui.heading("Recover unsaved work?");
                ui.label(format!(
                    "An autosave from a session that did not close cleanly exists:\n{}",
                    path.display()
                ));
                ui.horizontal(|ui| {
                    if ui.button("Recover").clicked() {
                        self.recover(&path);
                    }
                    if ui.button("Discard it").clicked() {
                        self.discard_recovery();
                    }
                });
            }
            Prompt::Unsaved(action) => {
                ui.heading("Unsaved changes");
                let (what, discard) = match &action {
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
                    let mut answer = None;
                    if ui.button("Save…").clicked() {
                        answer = Some(UnsavedAnswer::Save);
                    }
                    if ui.button(discard).clicked() {
                        answer = Some(UnsavedAnswer::Discard);
                    }
                    if ui.button("Cancel").clicked() {
                        answer = Some(UnsavedAnswer::Cancel);
                    }
                    if let Some(answer) = answer {
                        self.answer_unsaved(action.clone(), answer);
                    }
                });
            }
        });
    }

    fn dialog_ui(&mut self, ctx: &egui::Context) {
        let Some(dialog) = &mut self.dialog else {
            return;
        };
        let purpose = dialog.purpose;
        match dialog.ui(ctx) {
            DialogResult::Open => {}
            DialogResult::Cancelled => {
                self.dialog = None;
                self.after_save = None;
            }
            DialogResult::Chosen(path) => {
                self.dialog = None;
                self.dialog_chosen(purpose, path);
            }
        }
    }

    fn dialog_chosen(&mut self, purpose: DialogPurpose, path: PathBuf) {
        match purpose {
            DialogPurpose::OpenModel => self.open(&path),
            DialogPurpose::SaveModel => {
                let then = self.after_save.take();
                if self.save_to(&path)
                    && let Some(action) = then
                {
                    self.carry_out(action);
                }
            }
            DialogPurpose::ExportMesh => self.export(&path),
            DialogPurpose::SaveOps => {
                let ops = self.doc.recording.take().unwrap_or_default();
                let text: String = ops
                    .iter()
                    .map(|op| format!("{}\n", op_to_json(op)))
                    .collect();
                match crate::model::write_atomically(&path, text.as_bytes()) {
                    Ok(()) => self.set_status(
                        format!("saved {} operations to {}", ops.len(), path.display()),
                        false,
                    ),
                    Err(e) => {
                        self.doc.recording = Some(ops);
                        self.set_status(format!("cannot save the recording: {e}"), true);
                    }
                }
            }
            DialogPurpose::ReplayOps => match std::fs::read_to_string(&path) {
                Ok(text) => match parse_ops(&text) {
                    Ok(ops) => self.replay = Some(Replay { ops, next: 0 }),
                    Err(e) => self.set_status(format!("{}: {e}", path.display()), true),
                },
                Err(e) => self.set_status(format!("{}: {e}", path.display()), true),
            },
        }
    }
}
