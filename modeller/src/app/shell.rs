//! The modeller's panels drawn with egui: the toolbar, the side panel, the Devices panel, the
//! status line, the prompts, the file dialog, the help, the cursor's label. Everything drawn
//! returns [`Command`]s (the keys too, through [`keymap`](super::keymap)), which the
//! [`Modeller`] carries out after the frame's drawing; the panels edit only plain settings in
//! place. The shell's own state is the file dialog on screen: the modeller says which file it
//! asks for ([`Modeller::file_request`]), the dialog lists folders for it.

use crate::app::dialogs;
use crate::app::file_dialog::FileDialog;
use crate::app::panels::{self, FrameRate, PANEL_WIDTH};
use crate::editor::Projection;
use crate::editor::command::Command;
use crate::editor::modeller::{FileRequest, Modeller};

/// What the window draws around the modeller, and the state that drawing keeps.
#[derive(Debug, Default)]
pub struct Shell {
    /// The file dialog on screen, with the id of the modeller's request it answers.
    dialog: Option<(u64, FileDialog)>,
}

impl Shell {
    /// Draws the panels and dialogs and has `modeller` carry out what the user asked for;
    /// returns the rectangle left for the 3D view, in points.
    pub fn ui(&mut self, ui: &mut egui::Ui, modeller: &mut Modeller) -> egui::Rect {
        let keys = panels::shortcuts_ui(ui);
        if !ui.ctx().egui_wants_keyboard_input() {
            let m = ui.input(|i| i.modifiers);
            modeller.set_modifiers(m.shift, m.command || m.ctrl);
        }
        // The clutch is the key held (never while a text field takes the keyboard).
        let clutch = !ui.ctx().egui_wants_keyboard_input()
            && ui.input(|i| i.key_down(crate::app::keymap::CLUTCH_KEY));
        modeller.set_clutch(clutch);
        let mut commands: Vec<Command> = keys.into_iter().map(|k| k.command()).collect();
        egui::Panel::top("nendo top").show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.toggle_value(&mut modeller.panel_mut().devices_open, "Devices")
                    .on_hover_text(
                        "glove and tracker: profile, ports, status, alignment, calibration",
                    );
                ui.separator();
                commands.extend(panels::top_bar_ui(ui, modeller.document().history()));
            });
        });
        egui::Panel::left("nendo tools")
            .exact_size(PANEL_WIDTH)
            .show(ui, |ui| {
                egui::ScrollArea::vertical()
                    .show(ui, |ui| side_panel_ui(ui, modeller, &mut commands));
            });
        if modeller.panel().devices_open {
            let anchor = modeller.view_anchor();
            egui::Panel::right("nendo devices")
                .exact_size(crate::app::devices_panel::DEVICES_PANEL_WIDTH)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| {
                        ui.heading("Devices");
                        let (live, doc) = modeller.devices_mut();
                        commands.extend(live.ui(ui, doc, &anchor));
                    });
                });
        }
        egui::Panel::bottom("nendo status").show(ui, |ui| {
            let hand = modeller.hand_status();
            let latency = modeller.hand_latency();
            panels::status_ui(
                ui,
                hand.as_deref(),
                modeller.status(),
                modeller.session().autosave(),
                latency.as_ref(),
            );
        });
        let ctx = ui.ctx().clone();
        if let Some(prompt) = modeller.session().prompt() {
            commands.extend(dialogs::prompt_ui(&ctx, &prompt));
        }
        if let Some((_, dialog)) = self.dialog_for(modeller.file_request()) {
            commands.extend(dialogs::dialog_ui(&ctx, dialog, modeller));
        }
        if modeller.help_open() && !panels::help_ui(&ctx, modeller.panel().orbit) {
            commands.push(Command::ToggleHelp);
        }
        let view = ui.available_rect_before_wrap();
        if let Some((cursor, text)) = modeller.cursor_label() {
            cursor_label(&ctx, view, cursor, text);
        }
        for command in commands {
            modeller.apply(command);
        }
        modeller.remember_settings();
        view
    }

    /// The dialog for `request`: the one on screen if it answers that request, a new one
    /// otherwise; none without a request.
    fn dialog_for(&mut self, request: Option<&FileRequest>) -> Option<&mut (u64, FileDialog)> {
        let Some(request) = request else {
            self.dialog = None;
            return None;
        };
        if self.dialog.as_ref().map(|(id, _)| *id) != Some(request.id) {
            let dialog = FileDialog::beside(
                request.purpose,
                request.current.as_deref(),
                &request.default_name,
            );
            self.dialog = Some((request.id, dialog));
        }
        self.dialog.as_mut()
    }
}

/// The tool panel's sections, in order.
fn side_panel_ui(ui: &mut egui::Ui, m: &mut Modeller, commands: &mut Vec<Command>) {
    egui::CollapsingHeader::new("New primitive")
        .default_open(false)
        .show(ui, |ui| {
            commands.extend(panels::primitive_ui(ui, &mut m.panel_mut().form));
        });
    egui::CollapsingHeader::new("Tool")
        .default_open(true)
        .show(ui, |ui| {
            let (tool, settings, mirror, note) = m.tool_panel();
            commands.extend(panels::tool_ui(ui, tool, settings, mirror, note.as_deref()));
        });
    egui::CollapsingHeader::new("Regulation")
        .default_open(true)
        .show(ui, |ui| {
            let current = m.document().model().regulation;
            commands.extend(panels::regulation_ui(ui, current));
            commands.extend(panels::refine_ui(ui, m.auto_refine()));
        });
    egui::CollapsingHeader::new("Display")
        .default_open(true)
        .show(ui, |ui| {
            let max_seam_deg = m.surface().max_seam_deg;
            let panel = m.panel_mut();
            panels::display_ui(ui, &mut panel.overlays, &mut panel.orbit, max_seam_deg);
            let mut ortho = m.camera().projection == Projection::Orthographic;
            if ui
                .checkbox(&mut ortho, "orthographic view (numpad 5)")
                .on_hover_text("Parallel rays, as in Blender: sizes read the same at every depth; the framing at the orbit target is kept")
                .changed()
            {
                commands.push(Command::SetProjection(if ortho {
                    Projection::Orthographic
                } else {
                    Projection::Perspective
                }));
            }
            ui.separator();
            let mut analysis = m.panel().analysis;
            super::analysis_panel::analysis_ui(ui, &mut analysis, m.surface_patches());
            if analysis.mode == crate::render::SurfaceMode::Clay {
                super::analysis_panel::matcap_ui(ui, &mut m.panel_mut().matcap);
            }
            m.panel_mut().analysis = analysis;
        });
    egui::CollapsingHeader::new("Export")
        .default_open(false)
        .show(ui, |ui| {
            let (tolerance, job) = m.export_panel();
            commands.extend(panels::export_ui(ui, tolerance, job));
        });
    egui::CollapsingHeader::new("Continuity")
        .default_open(true)
        .show(ui, |ui| {
            let cache = m.display_cache();
            let (report, ms) = cache.continuity();
            panels::continuity_ui(ui, report, ms, cache.display().max_seam_deg);
        });
    egui::CollapsingHeader::new("Timing")
        .default_open(true)
        .show(ui, |ui| {
            let (frame_ms, fps) = m.frame_rate();
            let rate = FrameRate { frame_ms, fps };
            panels::timing_ui(ui, m.document().last_op.as_ref(), m.surface(), rate);
        });
    egui::CollapsingHeader::new("Record / replay")
        .default_open(false)
        .show(ui, |ui| {
            let recorded = m.document().recording.as_ref().map(Vec::len);
            commands.extend(panels::record_ui(ui, recorded, m.replay_progress()));
        });
}

/// Draws `text` in a dark box by the cursor (viewport pixels) in the 3D view `view`.
fn cursor_label(ctx: &egui::Context, view: egui::Rect, cursor: glam::Vec2, text: String) {
    let ppp = ctx.pixels_per_point();
    let at = view.min + egui::vec2(cursor.x, cursor.y) / ppp + egui::vec2(18.0, 14.0);
    let painter = ctx.layer_painter(egui::LayerId::new(
        egui::Order::Foreground,
        egui::Id::unique("nendo cursor label"),
    ));
    let font = egui::FontId::proportional(15.0);
    let galley = painter.layout_no_wrap(text, font, egui::Color32::WHITE);
    let rect = egui::Rect::from_min_size(at, galley.size()).expand(4.0);
    painter.rect_filled(rect, 3.0, egui::Color32::from_black_alpha(170));
    painter.galley(at, galley, egui::Color32::WHITE);
}
