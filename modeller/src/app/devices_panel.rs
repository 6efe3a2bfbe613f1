//! The Devices panel: the window's own side panel (the toolbar's Devices button shows and
//! hides it) for a glove user — profile, ports, recording, Connect, each device's status,
//! replay, alignment, hand size and the glove calibration. It draws [`LiveInput`]'s state and
//! calls its actions; the file dialogs it asks for come back through
//! [`LiveInput::dialog_chosen`].

use egui::{Color32, RichText, Ui};
use nendo_devices::discover::inventory;
use nendo_devices::glove_calibration::CalibrationPose;
use nendo_devices::profile::{FingerLengths, GloveProfile, Input};
use nendo_devices::{DeviceStatus, HandSize, SourceState};

use crate::editor::command::{Command, DialogPurpose};
use crate::editor::document::Document;
use crate::editor::live::{LiveInput, ViewAnchor, fresh_name, state_name};

const ERROR: Color32 = Color32::from_rgb(230, 90, 70);
const GOOD: Color32 = Color32::from_rgb(110, 200, 120);
const WAIT: Color32 = Color32::from_rgb(230, 180, 70);

/// The panel's width, points.
pub const DEVICES_PANEL_WIDTH: f32 = 330.0;

fn state_colour(state: SourceState) -> Color32 {
    match state {
        SourceState::Ok => GOOD,
        SourceState::Silent => WAIT,
        SourceState::Disconnected => ERROR,
        SourceState::Absent => Color32::GRAY,
    }
}

/// A port field with a menu of the ports found.
fn port_picker(ui: &mut Ui, label: &str, port: &mut String, found: &[String]) {
    ui.horizontal(|ui| {
        ui.label(label);
        egui::ComboBox::from_id_salt(label)
            .selected_text("found…")
            .width(70.0)
            .show_ui(ui, |ui| {
                if found.is_empty() {
                    ui.label("no ports found: Scan ports, or type a path");
                }
                for p in found {
                    if ui.selectable_label(port == p, p).clicked() {
                        port.clone_from(p);
                    }
                }
            });
    });
    ui.add(egui::TextEdit::singleline(port).desired_width(ui.available_width()));
}

fn device_status_ui(ui: &mut Ui, d: &DeviceStatus, replay: bool) {
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new(d.role.name()).strong());
        let state = if replay {
            format!("{} (recorded)", state_name(d.state))
        } else {
            state_name(d.state).to_string()
        };
        ui.colored_label(state_colour(d.state), state);
        ui.label(format!("{:.0} Hz, {} samples", d.rate_hz, d.samples));
    });
    ui.small(&d.description);
    if !replay {
        ui.small(format!(
            "faults {}, rejected {}, watchdog restarts {}, disconnects {}",
            d.faults, d.rejected, d.watchdog_trips, d.disconnects
        ));
    }
    // A skeleton source (VMC): its packets, the malformed ones and the bones it has seen.
    if !replay && !d.seen.is_empty() {
        ui.small(format!(
            "packets {}, malformed {}, invalid {}, incomplete hands {}",
            d.stats.decode.records + d.stats.decode.rejected,
            d.stats.decode.rejected,
            d.stats.invalid,
            d.stats.faults
        ));
        ui.small(format!("bones seen: {}", d.seen.join(" ")));
    }
    if let Some(e) = &d.last_error {
        ui.colored_label(ERROR, e);
    }
}

fn lengths_ui(ui: &mut Ui, name: &str, f: &mut FingerLengths) {
    ui.label(name);
    for v in [&mut f.proximal, &mut f.middle, &mut f.distal] {
        let mut cm = *v * 100.0;
        if ui
            .add(
                egui::DragValue::new(&mut cm)
                    .speed(0.05)
                    .range(0.5..=15.0)
                    .fixed_decimals(1),
            )
            .changed()
        {
            *v = cm / 100.0;
        }
    }
    ui.end_row();
}

fn hand_size_ui(ui: &mut Ui, hand: &mut HandSize) {
    egui::Grid::new("hand size").num_columns(4).show(ui, |ui| {
        ui.label("palm (cm)");
        for v in [&mut hand.palm_length, &mut hand.palm_width] {
            let mut cm = *v * 100.0;
            if ui
                .add(
                    egui::DragValue::new(&mut cm)
                        .speed(0.05)
                        .range(3.0..=20.0)
                        .fixed_decimals(1),
                )
                .changed()
            {
                *v = cm / 100.0;
            }
        }
        ui.label("len, width");
        ui.end_row();
        ui.label("finger (cm)");
        ui.label("base");
        ui.label("middle");
        ui.label("tip");
        ui.end_row();
        lengths_ui(ui, "thumb", &mut hand.thumb);
        lengths_ui(ui, "index", &mut hand.index);
        lengths_ui(ui, "middle", &mut hand.middle);
        lengths_ui(ui, "ring", &mut hand.ring);
        lengths_ui(ui, "little", &mut hand.pinky);
    });
}

impl LiveInput {
    /// Draws the panel and carries out what it can itself; returns what the modeller must do
    /// (a file dialog, the mouse hand).
    pub fn ui(&mut self, ui: &mut Ui, doc: &mut Document, anchor: &ViewAnchor) -> Vec<Command> {
        let mut commands = Vec::new();
        if self.entries.is_empty() {
            self.rescan();
        }
        // What the automatic fit of a first connect aims at.
        self.set_view_anchor(*anchor);
        self.profile_ui(ui, &mut commands);
        ui.separator();
        self.connect_ui(ui, doc, &mut commands);
        ui.separator();
        self.status_ui(ui);
        ui.separator();
        self.replay_ui(ui, doc, &mut commands);
        if self.running_devices().is_some()
            || self.entries.get(self.selected).is_some_and(|e| {
                matches!(e.profile.input, Input::Devices { .. } | Input::Skeleton(_))
            })
        {
            ui.separator();
            self.alignment_ui(ui, doc, anchor);
            ui.separator();
            self.calibration_ui(ui, doc);
        }
        if let Some(m) = &self.message {
            ui.separator();
            ui.label(RichText::new(m).small());
        }
        commands
    }

    fn profile_ui(&mut self, ui: &mut Ui, commands: &mut Vec<Command>) {
        ui.label(RichText::new("Profile").strong());
        let mut pick = None;
        let current = self
            .entries
            .get(self.selected)
            .map(|e| e.label())
            .unwrap_or_default();
        egui::ComboBox::from_id_salt("devices profile")
            .selected_text(current)
            .width(ui.available_width() - 8.0)
            .show_ui(ui, |ui| {
                for (i, e) in self.entries.iter().enumerate() {
                    if ui.selectable_label(i == self.selected, e.label()).clicked() {
                        pick = Some(i);
                    }
                }
            });
        if let Some(i) = pick {
            self.select(i);
        }
        if let Some(e) = self.entries.get(self.selected) {
            ui.small(&e.profile.description);
        }
        ui.horizontal_wrapped(|ui| {
            if ui
                .button("Open profile…")
                .on_hover_text("a device profile file (JSON, devices/README.md)")
                .clicked()
            {
                commands.push(Command::ShowDialog(DialogPurpose::OpenProfile));
            }
            if ui
                .button("Rescan")
                .on_hover_text("list your profile folder again")
                .clicked()
            {
                self.rescan();
            }
            if ui
                .button("Scan ports")
                .on_hover_text("serial ports and USB HID devices present")
                .clicked()
            {
                let profiles: Vec<_> = self.entries.iter().map(|e| e.profile.clone()).collect();
                self.inventory = Some(inventory(&profiles));
            }
        });
        let Some(entry) = self.entries.get(self.selected) else {
            return;
        };
        let profile = entry.profile.clone();
        let serial: Vec<String> = self
            .inventory
            .as_ref()
            .map(|inv| inv.serial.iter().map(|s| s.path.clone()).collect())
            .unwrap_or_default();
        if profile.glove().and_then(GloveProfile::port).is_some() {
            port_picker(ui, "glove port", &mut self.glove_port, &serial);
        }
        if let Some(GloveProfile::FiveDtUltraUsb { usb, .. }) = profile.glove() {
            let found = self
                .inventory
                .as_ref()
                .map(|inv| inv.hid.iter().any(|h| usb.matches(h.vid, h.pid)));
            let text = match found {
                Some(true) => "found",
                Some(false) => "not found",
                None => "Scan ports to look",
            };
            ui.small(format!("USB HID glove {:04x}: {text}", usb.vid));
        }
        if profile.tracker().is_some() {
            port_picker(ui, "tracker port", &mut self.tracker_port, &serial);
        }
        if let Input::Skeleton(s) = &profile.input {
            // A VMC receiver: where it listens, applied on (re)connect and remembered.
            ui.horizontal(|ui| {
                ui.label("VMC listen (ADDR:PORT)");
                ui.add(
                    egui::TextEdit::singleline(&mut self.tracker_port)
                        .desired_width(ui.available_width())
                        .hint_text(s.listen()),
                );
            });
            if let Some(e) = self.listen_error() {
                ui.colored_label(ERROR, e);
            } else {
                ui.small("applied on Connect (Connect again to move a running receiver)");
            }
        }
        if let Some(inv) = &self.inventory {
            if let Some(e) = &inv.serial_error {
                ui.small(format!("serial ports: {e}"));
            }
            if let Some(e) = &inv.hid_error {
                ui.small(format!("HID: {e}"));
            }
        }
    }

    fn connect_ui(&mut self, ui: &mut Ui, doc: &mut Document, commands: &mut Vec<Command>) {
        let mouse = self.selected_mouse().is_some();
        if !mouse {
            ui.checkbox(&mut self.record, "record a trace of the session to:");
            ui.add_enabled_ui(self.record, |ui| {
                ui.add(
                    egui::TextEdit::singleline(&mut self.record_to)
                        .desired_width(ui.available_width())
                        .hint_text("session.trace"),
                );
                if ui.button("Choose…").clicked() {
                    commands.push(Command::ShowDialog(DialogPurpose::RecordTrace));
                }
            });
        }
        if let Some(path) = self.confirm_overwrite.clone() {
            ui.colored_label(WAIT, format!("{} exists.", path.display()));
            let fresh = fresh_name(&path);
            ui.horizontal_wrapped(|ui| {
                if ui.button("Replace it").clicked() {
                    self.connect_recording(doc, Some(path.clone()));
                }
                let name = fresh
                    .file_name()
                    .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
                if ui.button(format!("Record to {name}")).clicked() {
                    self.connect_recording(doc, Some(fresh.clone()));
                }
                if ui.button("Cancel").clicked() {
                    self.confirm_overwrite = None;
                }
            });
            return;
        }
        ui.horizontal_wrapped(|ui| {
            if self.is_connected() {
                if ui.button("Disconnect").clicked() {
                    self.disconnect_from(doc);
                }
            } else {
                let (label, hint) = if mouse {
                    (
                        "Use the mouse hand",
                        "selects the Hand tool: the view ray is the finger",
                    )
                } else {
                    (
                        "Connect",
                        "opens the profile's devices; one that is off is retried until it answers",
                    )
                };
                if ui.button(label).on_hover_text(hint).clicked()
                    && let Some(m) = self.connect_or_mouse(doc)
                {
                    commands.push(Command::UseMouseHand(m));
                }
            }
        });
    }

    fn status_ui(&mut self, ui: &mut Ui) {
        let Some(line) = self.session_line() else {
            ui.label("not connected");
            return;
        };
        ui.small(line);
        if let Some((devices, recording_error, replay)) = self.device_status() {
            for d in &devices {
                device_status_ui(ui, d, replay);
            }
            if let Some(e) = recording_error {
                ui.colored_label(ERROR, e);
            }
        }
    }

    fn replay_ui(&mut self, ui: &mut Ui, doc: &mut Document, commands: &mut Vec<Command>) {
        ui.label("trace to replay:");
        ui.add(
            egui::TextEdit::singleline(&mut self.trace_path)
                .desired_width(ui.available_width())
                .hint_text("session.trace"),
        );
        ui.horizontal_wrapped(|ui| {
            if ui.button("Choose…").clicked() {
                commands.push(Command::ShowDialog(DialogPurpose::ReplayTrace));
            }
            let path = std::path::PathBuf::from(self.trace_path.trim());
            if ui
                .add_enabled(path.is_file(), egui::Button::new("Replay trace"))
                .clicked()
            {
                self.replay(&path, doc);
            }
        });
    }

    /// The parts of the hand that press, by name (every finger by default; remembered).
    fn pressing_ui(&mut self, ui: &mut Ui, doc: &mut Document) {
        ui.horizontal_wrapped(|ui| {
            ui.label("presses with")
                .on_hover_text("the parts of the glove's hand that press the clay");
            let set = self.pressing();
            for part in crate::hand::Part::ALL {
                let mut on = set.contains(part);
                if ui.checkbox(&mut on, part.name()).changed() {
                    self.toggle_pressing(doc, part);
                }
            }
        });
    }

    fn alignment_ui(&mut self, ui: &mut Ui, doc: &mut Document, anchor: &ViewAnchor) {
        egui::CollapsingHeader::new("Alignment and hand")
            .default_open(true)
            .show(ui, |ui| {
                let Some(entry) = self.entries.get(self.selected) else {
                    return;
                };
                let profile = entry.profile.clone();
                let has_pose = self.last_pose().is_some();
                ui.horizontal_wrapped(|ui| {
                    if ui
                        .add_enabled(has_pose, egui::Button::new("Recenter"))
                        .on_hover_text(
                            "the hand, where it is now, comes to the model under the view centre",
                        )
                        .on_disabled_hover_text("needs a tracker pose: connect the tracker")
                        .clicked()
                    {
                        self.recenter(doc, anchor);
                    }
                    if ui
                        .button("Fit the hand to the model")
                        .on_hover_text("sides per metre so the hand is 0.4 of the model's size")
                        .clicked()
                    {
                        self.fit_hand(doc, anchor);
                    }
                });
                ui.horizontal(|ui| {
                    let mut scale = self.scale_edit.unwrap_or(profile.world_from_tracker.scale);
                    ui.label("sides per metre");
                    let r = ui.add(
                        egui::DragValue::new(&mut scale)
                            .speed(0.1)
                            .range(0.01..=100_000.0),
                    );
                    if r.changed() {
                        self.scale_edit = Some(scale);
                    }
                    // Applied (and saved) when typed, or when the drag ends.
                    if ((r.changed() && !r.dragged()) || r.drag_stopped())
                        && let Some(s) = self.scale_edit.take()
                    {
                        self.set_scale(doc, s);
                    }
                });
                self.pressing_ui(ui, doc);
                let radius = self.radius(&profile, false);
                ui.horizontal(|ui| {
                    let mut follow = self.radius_set.is_none();
                    if ui
                        .checkbox(&mut follow, "finger radius follows the hand")
                        .changed()
                    {
                        self.radius_set = (!follow).then_some(radius);
                        self.rebuild_hand(doc);
                    }
                });
                match self.radius_set {
                    Some(mut r) => {
                        let resp = ui.add(
                            egui::DragValue::new(&mut r)
                                .speed(0.01)
                                .range(0.001..=1000.0)
                                .prefix("radius "),
                        );
                        if resp.changed() {
                            self.radius_set = Some(r);
                        }
                        if resp.drag_stopped() || (resp.changed() && !resp.dragged()) {
                            self.rebuild_hand(doc);
                        }
                    }
                    None => {
                        ui.small(format!("radius {radius:.3} sides"));
                    }
                }
                egui::CollapsingHeader::new("hand size")
                    .default_open(false)
                    .show(ui, |ui| {
                        let mut hand = self.hand_edit.unwrap_or(profile.hand);
                        hand_size_ui(ui, &mut hand);
                        if hand != profile.hand {
                            self.hand_edit = Some(hand);
                        }
                        ui.horizontal(|ui| {
                            if ui
                                .add_enabled(
                                    self.hand_edit.is_some(),
                                    egui::Button::new("Apply hand size"),
                                )
                                .clicked()
                            {
                                self.apply_hand(doc, hand);
                            }
                            if ui
                                .add_enabled(self.hand_edit.is_some(), egui::Button::new("Reset"))
                                .clicked()
                            {
                                self.hand_edit = None;
                            }
                        });
                    });
            });
    }

    fn calibration_ui(&mut self, ui: &mut Ui, doc: &mut Document) {
        let glove = self.running_devices().and_then(|p| p.glove()).is_some();
        egui::CollapsingHeader::new("Glove calibration")
            .default_open(glove)
            .show(ui, |ui| {
                if !glove {
                    ui.small("connect a glove to calibrate it");
                    return;
                }
                ui.small("Hold each pose, press its button, keep still for a second.");
                let capturing = self.calibration.capturing.map(|(p, _)| p);
                for (k, pose) in CalibrationPose::ALL.into_iter().enumerate() {
                    ui.horizontal(|ui| {
                        let n = self.calibration.samples.of(pose).len();
                        if ui
                            .add_enabled(
                                capturing.is_none(),
                                egui::Button::new(format!("{}. {}", k + 1, pose.name())),
                            )
                            .on_hover_text(pose.instruction())
                            .clicked()
                        {
                            self.capture_pose(pose);
                        }
                        if capturing == Some(pose) {
                            ui.colored_label(WAIT, format!("capturing… {n}"));
                        } else if n > 0 {
                            ui.colored_label(GOOD, format!("{n} samples"));
                        }
                    });
                    ui.small(pose.instruction());
                }
                let ready = capturing.is_none()
                    && CalibrationPose::ALL
                        .iter()
                        .all(|p| !self.calibration.samples.of(*p).is_empty());
                if ui
                    .add_enabled(ready, egui::Button::new("Compute and save"))
                    .on_hover_text("offsets and gains of every sensor, into your profile")
                    .clicked()
                {
                    self.finish_calibration(doc);
                }
                if let Some(r) = &self.calibration.result {
                    ui.small(r);
                }
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use nendo_devices::profile;

    fn plane_doc() -> Document {
        use crate::model::Model;
        use crate::surface::{Primitive, PrimitiveParams};
        Document::new(Model::new(
            Primitive::Plane
                .build(&PrimitiveParams::default())
                .expect("plane"),
        ))
    }

    /// The Devices panel fits its width: nothing (the Replay button, the record field, the
    /// port fields) reaches past its right edge, whichever profile is selected.
    #[test]
    fn the_device_panel_fits_its_width() {
        let mut live = LiveInput::default();
        let mut doc = plane_doc();
        live.trace_path = "/some/rather/long/path/to/a/recorded/session.trace".into();
        live.record = true;
        live.record_to = "/another/rather/long/path/to/a/recording/session.trace".into();
        let anchor = ViewAnchor {
            point: DVec3::ZERO,
            normal: DVec3::Z,
            extent: 10.0,
        };
        let ctx = egui::Context::default();
        let count = profile::builtin().len();
        for selected in 0..count {
            let mut overflow = None;
            for _ in 0..2 {
                let raw = egui::RawInput {
                    screen_rect: Some(egui::Rect::from_min_size(
                        egui::Pos2::ZERO,
                        egui::vec2(1280.0, 800.0),
                    )),
                    ..Default::default()
                };
                let _ = ctx.run_ui(raw, |ui| {
                    egui::Panel::right("devices test")
                        .exact_size(DEVICES_PANEL_WIDTH)
                        .show(ui, |ui| {
                            let right = ui.max_rect().max.x;
                            let _ = live.ui(ui, &mut doc, &anchor);
                            if live.selected != selected {
                                live.select(selected);
                            }
                            overflow = Some(ui.min_rect().max.x - right);
                        });
                });
            }
            let overflow = overflow.expect("the panel ran");
            assert!(
                overflow <= 0.5,
                "profile {selected}: the panel's content runs {overflow} points past its edge"
            );
        }
    }
}
