//! The modeller drawn with egui: the toolbar, the side panel, the prompts, the dialogs, the
//! help, the cursor's label; everything drawn returns [`Command`]s.

use glam::Vec2;

use crate::app::panels::{self, FrameRate, PANEL_WIDTH};
use crate::editor::command::Command;
use crate::editor::tools::ToolContext;
use crate::surface::Op;

use super::*;

impl Modeller {
    /// Draws the panels and dialogs and carries out what the user asked for; returns the
    /// rectangle left for the 3D view, in points.
    pub fn ui(&mut self, ui: &mut egui::Ui) -> egui::Rect {
        let actions = panels::shortcuts_ui(ui);
        if !ui.ctx().egui_wants_keyboard_input() {
            let m = ui.input(|i| i.modifiers);
            self.set_modifiers(m.shift, m.command || m.ctrl);
        }
        let mut commands = Vec::new();
        for action in actions {
            commands.extend(self.key_action(action));
        }
        egui::Panel::top("nendo top").show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.toggle_value(&mut self.devices_open, "Devices")
                    .on_hover_text(
                        "glove and tracker: profile, ports, status, alignment, calibration",
                    );
                ui.separator();
                commands.extend(panels::top_bar_ui(ui, self.session.doc.history()));
            });
        });
        egui::Panel::left("nendo tools")
            .exact_size(PANEL_WIDTH)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.side_panel_ui(ui, &mut commands));
            });
        if self.devices_open {
            let anchor = self.view_anchor();
            egui::Panel::right("nendo devices")
                .exact_size(crate::app::devices_panel::DEVICES_PANEL_WIDTH)
                .show(ui, |ui| {
                    egui::ScrollArea::vertical().show(ui, |ui| {
                        ui.heading("Devices");
                        commands.extend(self.live.ui(ui, &mut self.session.doc, &anchor));
                    });
                });
        }
        egui::Panel::bottom("nendo status").show(ui, |ui| {
            panels::status_ui(ui, self.status.as_ref(), self.session.autosave());
        });
        let ctx = ui.ctx().clone();
        if let Some(prompt) = self.session.prompt() {
            commands.extend(panels::prompt_ui(&ctx, &prompt));
        }
        if let Some(dialog) = &mut self.dialog {
            commands.extend(panels::dialog_ui(&ctx, dialog));
        }
        if self.help && !panels::help_ui(&ctx, self.panel.orbit) {
            self.help = false;
        }
        let view = ui.available_rect_before_wrap();
        self.cursor_label_ui(&ctx, view);
        for command in commands {
            self.apply(command);
        }
        self.remember_settings();
        view
    }

    /// The tool panel's sections, in order.
    pub(super) fn side_panel_ui(&mut self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
        egui::CollapsingHeader::new("New primitive")
            .default_open(false)
            .show(ui, |ui| {
                commands.extend(panels::primitive_ui(ui, &mut self.panel.form));
            });
        egui::CollapsingHeader::new("Tool")
            .default_open(true)
            .show(ui, |ui| {
                commands.extend(panels::tool_ui(
                    ui,
                    self.tools.active,
                    &mut self.tools.settings,
                    &self.mirror,
                ));
            });
        egui::CollapsingHeader::new("Regulation")
            .default_open(true)
            .show(ui, |ui| {
                let current = self.session.doc.model().regulation;
                commands.extend(panels::regulation_ui(ui, current));
                commands.extend(panels::refine_ui(ui, self.panel.auto_refine));
            });
        egui::CollapsingHeader::new("Display")
            .default_open(true)
            .show(ui, |ui| {
                panels::display_ui(
                    ui,
                    &mut self.panel.overlays,
                    &mut self.panel.orbit,
                    self.cache.display().max_seam_deg,
                );
            });
        egui::CollapsingHeader::new("Export")
            .default_open(false)
            .show(ui, |ui| {
                commands.extend(panels::export_ui(
                    ui,
                    &mut self.panel.export_tolerance,
                    self.export_job.as_ref(),
                ));
            });
        egui::CollapsingHeader::new("Continuity")
            .default_open(true)
            .show(ui, |ui| {
                let (report, ms) = self.cache.continuity();
                panels::continuity_ui(ui, report, ms, self.cache.display().max_seam_deg);
            });
        egui::CollapsingHeader::new("Timing")
            .default_open(true)
            .show(ui, |ui| {
                let rate = FrameRate {
                    frame_ms: self.timing.frame_ms,
                    fps: self.timing.fps,
                };
                panels::timing_ui(
                    ui,
                    self.session.doc.last_op.as_ref(),
                    self.cache.display(),
                    rate,
                );
            });
        egui::CollapsingHeader::new("Record / replay")
            .default_open(false)
            .show(ui, |ui| {
                let recorded = self.session.doc.recording.as_ref().map(Vec::len);
                let replaying = self.replay.as_ref().map(|r| (r.next, r.ops.len()));
                commands.extend(panels::record_ui(ui, recorded, replaying));
            });
    }

    /// The number by the cursor: a stroke's depth (and the patches it reaches), or the radius
    /// or depth F / Shift+F is setting.
    pub(super) fn cursor_label_ui(&self, ctx_egui: &egui::Context, view: egui::Rect) {
        let Some(cursor) = self.pointer.cursor else {
            return;
        };
        let text = if let Some(adjust) = &self.adjust {
            match adjust.what {
                Adjusted::Radius => format!("radius {:.3}", self.tools.settings.radius),
                Adjusted::Depth => format!("depth {:.3}", self.tools.settings.depth),
            }
        } else if let Some(stroke) = &self.stroke {
            let ctx = ToolContext {
                camera: &self.camera,
                viewport: self.pointer.viewport,
                patches: stroke.base_patches(),
                mesh: stroke.base_mesh(),
                curves: &[],
            };
            let Some(depth) = self.tools.state.stroke_depth(&ctx, &self.tools.settings) else {
                // Move and Smooth press no depth: how far the grab went, or the dabs so far.
                let text = match stroke.shown() {
                    Some(Op::Move { at, to, .. }) => format!(
                        "move {:.3} · {} patches",
                        (*to - *at).length(),
                        stroke.touched().len()
                    ),
                    _ if self.tools.state.smoothing() => "smooth".to_string(),
                    _ => return,
                };
                return Self::cursor_label(ctx_egui, view, cursor, text);
            };
            let signed = stroke.shown().map_or(0.0, |op| match op {
                Op::Push { depth, .. }
                | Op::PushNormal { depth, .. }
                | Op::Drag { depth, .. }
                | Op::Groove { depth, .. } => *depth,
                Op::Move { .. } | Op::Smooth { .. } => 0.0,
            });
            let way = if signed < 0.0 { "out" } else { "in" };
            format!(
                "depth {depth:.3} {way} · {} patches",
                stroke.touched().len()
            )
        } else {
            return;
        };
        Self::cursor_label(ctx_egui, view, cursor, text);
    }

    /// Draws `text` in a dark box by the cursor.
    pub(super) fn cursor_label(ctx: &egui::Context, view: egui::Rect, cursor: Vec2, text: String) {
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
}
