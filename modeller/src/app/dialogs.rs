//! The modal prompts (recover, unsaved changes, a file changed on disk, …) and the file dialog
//! with the mesh export's own part (tolerance, triangles and size before writing).
//!
//! Like the panels, each function draws from the state it is handed and returns the
//! [`Command`]s the user gave.

use egui::Ui;

use super::file_dialog::{DialogPurpose, DialogResult, FileDialog};
use crate::editor::command::Command;
use crate::editor::export_job::TOLERANCE_RANGE;
use crate::editor::lifecycle::{ConflictAnswer, Pending, Prompt, UnsavedAnswer};

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
        Prompt::ChangedOnDisk(path) => {
            ui.heading("The file changed on disk");
            ui.label(format!(
                "{} was changed by another program since it was opened or saved here.\n\
                 Saving now would overwrite those changes.",
                path.display()
            ));
            ui.horizontal(|ui| {
                for (label, answer) in [
                    ("Overwrite", ConflictAnswer::Overwrite),
                    ("Save as…", ConflictAnswer::SaveAs),
                    ("Reload (drop my edits)", ConflictAnswer::Reload),
                    ("Cancel", ConflictAnswer::Cancel),
                ] {
                    if ui.button(label).clicked() {
                        commands.push(Command::AnswerConflict(answer));
                    }
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

/// The file dialog; for a mesh export, with the tolerance and what the file will hold.
pub(super) fn dialog_ui(
    ctx: &egui::Context,
    dialog: &mut FileDialog,
    m: &mut crate::editor::Modeller,
) -> Vec<Command> {
    let purpose = dialog.purpose;
    let result = if purpose == DialogPurpose::ExportMesh {
        dialog.ui_with(ctx, |ui, name| export_dialog_ui(ui, m, name))
    } else {
        dialog.ui(ctx)
    };
    match result {
        DialogResult::Open => Vec::new(),
        DialogResult::Cancelled => vec![Command::DialogCancelled],
        DialogResult::Chosen(path) => vec![Command::DialogChosen(purpose, path)],
    }
}

/// The export dialog's own part: the tolerance, and the triangles and file size the name's
/// format will get, before anything is written.
fn export_dialog_ui(ui: &mut Ui, m: &mut crate::editor::Modeller, name: &str) {
    ui.separator();
    let (tolerance, estimate) = m.export_dialog(name);
    ui.add(
        egui::Slider::new(tolerance, TOLERANCE_RANGE)
            .logarithmic(true)
            .text("tolerance (side)"),
    )
    .on_hover_text("Largest distance from the mesh to the surface; proposed from the model's size (a thousandth of its box's diagonal)");
    let lower = name.to_ascii_lowercase();
    match estimate {
        Some(e) => {
            ui.label(format!(
                "{} triangles, about {}",
                thousands(e.triangles),
                file_size(e.bytes)
            ));
        }
        None if [".step", ".stp", ".igs", ".iges"]
            .iter()
            .any(|x| lower.ends_with(x)) =>
        {
            ui.label("the exact patches and curves: no tolerance applies");
        }
        None => {
            ui.label("name the file .obj, .stl or .glb (a mesh), or .step or .igs (CAD)");
        }
    }
}

/// `1234567` as `1 234 567`.
fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// Bytes as kB, MB or GB (powers of 1000), three significant digits or so.
fn file_size(bytes: u64) -> String {
    let b = bytes as f64;
    if b < 1e3 {
        format!("{bytes} bytes")
    } else if b < 1e6 {
        format!("{:.0} kB", b / 1e3)
    } else if b < 1e9 {
        format!("{:.1} MB", b / 1e6)
    } else {
        format!("{:.2} GB", b / 1e9)
    }
}
