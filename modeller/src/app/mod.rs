//! The modeller window: winit + egui over the wgpu renderer, modelling with the mouse alone
//! (and, through `nendo-devices`, a glove and tracker).
//!
//! ## Controls
//!
//! Every key and mouse binding is in one table, [`keymap`] (the help overlay, F1 or `?`, and
//! the README list it from there). Push, Pull, Draw a line, Move and Smooth deform live while
//! the button is held ([`stroke`](crate::editor::stroke)); Esc or a right click cancels the stroke exactly. With
//! symmetry on (X, [`symmetry`](crate::editor::symmetry)) every stroke is mirrored across `x = 0`.
//!
//! Input egui takes (a panel, a text field, a dialog) never reaches the tools.
//!
//! ## Parts
//!
//! Everything of the window that is not drawing or input — the modeller carrying out commands
//! and following the pointer, the document, undo, the lifecycle, live strokes, the tools,
//! symmetry, the camera, the scene, the device loop — is the headless editor,
//! [`crate::editor`]; this module is the thin egui / winit shell around it: winit's events
//! become [`crate::editor::input`] events, the panels' clicks and the keys become
//! [`Command`](crate::editor::Command)s, and the [`Modeller`]'s scene and state are drawn.
//!
//! | module | what it is |
//! |---|---|
//! | [`shell`] | the modeller's panels, dialogs, help and cursor label drawn with egui; the commands they return carried out |
//! | `panels` | the egui panels (`*_ui` functions) and the [`Command`](crate::editor::Command)s they return |
//! | [`keymap`] | every key and mouse binding, the one table the shortcuts, the help and the README use |
//! | [`file_dialog`] | the egui file dialog |
//! | [`devices_panel`] | the Devices panel (the toolbar's Devices button) |
//! | [`window`] | winit, the surface, egui and the renderer together |

mod analysis_panel;
pub mod devices_panel;
mod dialogs;
pub mod file_dialog;
pub mod keymap;
mod panels;
pub mod shell;
mod surface_upload;
pub mod window;

pub use shell::Shell;
pub use window::WindowApp;

use std::path::PathBuf;

use crate::editor::{Document, Modeller};
use crate::model::Model;
use crate::surface::{Primitive, PrimitiveParams};

/// How the window starts.
#[derive(Debug, Clone, Default)]
pub struct WindowOptions {
    /// A model file to open; without one, the paper's 10 × 10 plane.
    pub model: Option<PathBuf>,
    /// The autosave file; `None` for the default (see [`autosave`](crate::editor::autosave)).
    pub autosave: Option<PathBuf>,
    /// Do not autosave at all.
    pub no_autosave: bool,
    /// Do not offer to recover an earlier autosave (it is left in place until overwritten).
    pub no_recover: bool,
    /// A device profile (shipped name or file) to connect to at start.
    pub profile: Option<String>,
}

/// Opens the modeller window and runs it until it closes.
///
/// # Errors
/// When the model cannot be read, or no window or GPU can be had.
pub fn run(options: WindowOptions) -> anyhow::Result<()> {
    let doc = match &options.model {
        Some(path) => Document::open(path).map_err(|e| anyhow::anyhow!(e.in_file(path)))?,
        None => Document::new(Model::new(
            Primitive::Plane.build(&PrimitiveParams::default())?,
        )),
    };
    let autosave = if options.no_autosave {
        None
    } else {
        options
            .autosave
            .clone()
            .or_else(crate::editor::autosave::default_path)
    };
    // An autosave path holds an autosave or nothing, and is never the model being edited.
    // (The default path's slots that hold something else are passed over instead.)
    if let Some(path) = options.autosave.as_ref().filter(|_| !options.no_autosave) {
        crate::editor::autosave::check_path(path, options.model.as_deref())?;
    }
    let mut modeller = Modeller::new(doc, autosave, !options.no_recover)
        .with_settings(crate::editor::settings::default_path());
    if let Some(profile) = &options.profile {
        modeller
            .connect_profile(profile)
            .map_err(|e| anyhow::anyhow!("--profile {profile}: {e}"))?;
    }
    WindowApp::new(modeller).run()
}

/// Applies egui's texture changes (and frees) when a frame is skipped, so none is lost.
pub(crate) fn apply_textures(
    renderer: &mut egui_wgpu::Renderer,
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    delta: &egui::TexturesDelta,
) {
    for (id, deltas) in &delta.set {
        for d in deltas {
            renderer.update_texture(device, queue, *id, d);
        }
    }
    for id in &delta.free {
        renderer.free_texture(id);
    }
}
