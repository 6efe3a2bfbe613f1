//! A small file dialog drawn with egui: a folder listing, a path field, and a filter on the
//! extension.
//!
//! Chosen over a native dialog (`rfd`) because it needs no system library at build time and no
//! desktop portal (D-Bus) at run time, so it works the same under Xvfb, in CI and on a bare X
//! server.

use std::path::{Path, PathBuf};

pub use crate::editor::command::DialogPurpose;

/// How an entry is listed: folders end in `/` (a marker every font has; the default egui
/// fonts have no folder emoji).
fn entry_label(name: &str, is_dir: bool) -> String {
    if is_dir {
        format!("{name}/")
    } else {
        name.to_string()
    }
}

/// An open file dialog.
#[derive(Debug, Clone)]
pub struct FileDialog {
    /// What it is for.
    pub purpose: DialogPurpose,
    dir: PathBuf,
    name: String,
    entries: Vec<(String, bool)>,
    error: Option<String>,
}

/// What the dialog did this frame.
#[derive(Debug, Clone, PartialEq)]
pub enum DialogResult {
    /// Still open.
    Open,
    /// Closed without a choice.
    Cancelled,
    /// A path was chosen.
    Chosen(PathBuf),
}

impl FileDialog {
    /// A dialog starting in `dir` with `name` in the file field.
    #[must_use]
    pub fn new(purpose: DialogPurpose, dir: PathBuf, name: String) -> Self {
        let mut dialog = Self {
            purpose,
            dir,
            name,
            entries: Vec::new(),
            error: None,
        };
        dialog.refresh();
        dialog
    }

    /// A dialog starting beside `current` (or in the working directory).
    #[must_use]
    pub fn beside(purpose: DialogPurpose, current: Option<&Path>, default_name: &str) -> Self {
        let dir = current
            .and_then(Path::parent)
            .filter(|d| !d.as_os_str().is_empty())
            .map(Path::to_path_buf)
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_else(|| PathBuf::from("."));
        let name = current
            .and_then(Path::file_name)
            .map(|n| n.to_string_lossy().into_owned())
            .filter(|_| purpose.saves() && purpose != DialogPurpose::ExportMesh)
            .unwrap_or_else(|| default_name.to_string());
        Self::new(purpose, dir, name)
    }

    fn refresh(&mut self) {
        self.entries.clear();
        match std::fs::read_dir(&self.dir) {
            Ok(read) => {
                for entry in read.filter_map(Result::ok) {
                    let name = entry.file_name().to_string_lossy().into_owned();
                    if name.starts_with('.') {
                        continue;
                    }
                    let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
                    let lower = name.to_ascii_lowercase();
                    if is_dir || self.purpose.endings().iter().any(|e| lower.ends_with(e)) {
                        self.entries.push((name, is_dir));
                    }
                }
                self.entries
                    .sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
                self.error = None;
            }
            Err(e) => self.error = Some(format!("{}: {e}", self.dir.display())),
        }
    }

    /// Draws the dialog as a window; reports the outcome.
    pub fn ui(&mut self, ctx: &egui::Context) -> DialogResult {
        self.ui_with(ctx, |_, _| {})
    }

    /// [`FileDialog::ui`] with `extra` drawn under the file field, given the name typed there
    /// (the export dialog's tolerance and estimate).
    pub fn ui_with(
        &mut self,
        ctx: &egui::Context,
        extra: impl FnOnce(&mut egui::Ui, &str),
    ) -> DialogResult {
        let mut result = DialogResult::Open;
        let mut open = true;
        egui::Window::new(self.purpose.title())
            .collapsible(false)
            .resizable(true)
            .default_size([480.0, 360.0])
            .open(&mut open)
            .show(ctx, |ui| {
                ui.horizontal(|ui| {
                    if ui.button("Up").clicked()
                        && let Some(parent) = self.dir.parent()
                    {
                        self.dir = parent.to_path_buf();
                        self.refresh();
                    }
                    ui.label(self.dir.display().to_string());
                });
                ui.separator();
                let mut enter: Option<PathBuf> = None;
                egui::ScrollArea::vertical()
                    .max_height(220.0)
                    .auto_shrink([false, true])
                    .show(ui, |ui| {
                        for (name, is_dir) in &self.entries {
                            let label = entry_label(name, *is_dir);
                            let selected = !*is_dir && *name == self.name;
                            let response = ui.selectable_label(selected, label);
                            if response.clicked() {
                                if *is_dir {
                                    enter = Some(self.dir.join(name));
                                } else {
                                    self.name = name.clone();
                                }
                            }
                            if response.double_clicked() && !*is_dir {
                                result = DialogResult::Chosen(self.dir.join(name));
                            }
                        }
                    });
                if let Some(dir) = enter {
                    self.dir = dir;
                    self.refresh();
                }
                ui.separator();
                ui.horizontal(|ui| {
                    ui.label("File:");
                    let field = ui.text_edit_singleline(&mut self.name);
                    let confirm_label = if self.purpose.saves() { "Save" } else { "Open" };
                    let pressed_enter =
                        field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                    if (ui.button(confirm_label).clicked() || pressed_enter)
                        && !self.name.trim().is_empty()
                    {
                        let typed = PathBuf::from(self.name.trim());
                        let path = if typed.is_absolute() {
                            typed
                        } else {
                            self.dir.join(typed)
                        };
                        if !self.purpose.saves() && !path.is_file() {
                            self.error = Some(format!("{} is not a file", path.display()));
                        } else {
                            result = DialogResult::Chosen(path);
                        }
                    }
                    if ui.button("Cancel").clicked() {
                        result = DialogResult::Cancelled;
                    }
                });
                extra(ui, self.name.trim());
                if let Some(e) = &self.error {
                    ui.colored_label(egui::Color32::from_rgb(230, 90, 70), e);
                }
            });
        if !open {
            result = DialogResult::Cancelled;
        }
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every character of an entry's label is in egui's default fonts (a missing one is drawn
    /// as a box).
    #[test]
    fn entry_labels_use_glyphs_the_default_fonts_have() {
        let ctx = egui::Context::default();
        // Fonts are loaded by the first frame.
        let _ = ctx.run_ui(egui::RawInput::default(), |_| {});
        let font = egui::FontId::proportional(14.0);
        for (name, is_dir) in [("models", true), ("plane.nendo.json", false)] {
            let label = entry_label(name, is_dir);
            assert!(
                ctx.fonts_mut(|f| f.has_glyphs(&font, &label)),
                "{label:?} has a glyph the default fonts lack"
            );
        }
        assert!(entry_label("models", true).contains("models"));
        assert_ne!(entry_label("models", true), entry_label("models", false));
    }
}
