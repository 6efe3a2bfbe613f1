//! The modeller window: winit + egui over the wgpu renderer, modelling with the mouse alone
//! (and, through `nendo-devices`, a glove and tracker).
//!
//! ## Controls
//!
//! Every key and mouse binding is in one table, [`keymap`] (the help overlay, F1 or `?`, and
//! the README list it from there). Push, Pull, Draw a line, Move and Smooth deform live while
//! the button is held ([`stroke`]); Esc or a right click cancels the stroke exactly. With
//! symmetry on (X, [`symmetry`]) every stroke is mirrored across `x = 0`.
//!
//! Input egui takes (a panel, a text field, a dialog) never reaches the tools.
//!
//! ## Parts
//!
//! | module | what it is |
//! |---|---|
//! | [`camera`] | the orbit camera and the named views |
//! | [`scene`] | the document turned into what the renderer draws |
//! | [`document`], [`history`] | the model being edited, undo / redo |
//! | [`lifecycle`] | the document's lifecycle: unsaved changes, the questions, the action waiting on them (a state machine without I/O), autosave and recovery |
//! | [`autosave`] | the autosave file |
//! | [`tools`], [`curve_edit`] | the mouse tools and the curve edits they make |
//! | [`stroke`] | a live stroke: re-applied from its start each frame, one undo step, cancelled exactly |
//! | [`symmetry`] | the symmetry toggle, the mirror image of an operation, refinement for a mirrored stroke |
//! | [`reach`] | the patches an operation changes, outlined around the cursor |
//! | [`keymap`] | every key and mouse binding, the one table the shortcuts, the help and the README use |
//! | [`display_cache`] | what the window derives from the document (tessellation, continuity) |
//! | [`modeller`] | the modeller's state, split by concern, its input handling, and [`Modeller::apply`] |
//! | [`command`], `panels` | the egui panels (`*_ui` functions) and the [`Command`]s they return |
//! | [`file_dialog`] | the egui file dialog |
//! | [`export_job`] | mesh export off the UI thread |
//! | [`hand_input`] | device frames and the mouse as a hand: the hand loop on the document, the hand drawn |
//! | [`live`] | the device loop on its own thread; profiles, ports, alignment, calibration, the status file |
//! | [`devices_panel`] | the Devices panel (the toolbar's Devices button) |
//! | [`settings`] | the settings remembered between runs, the user's profile folder |
//! | [`window`] | winit, the surface, egui and the renderer together |

pub mod autosave;
pub mod camera;
pub mod command;
pub mod curve_edit;
pub mod devices_panel;
pub mod display_cache;
pub mod document;
pub mod export_job;
pub mod file_dialog;
pub mod hand_input;
pub mod history;
pub mod keymap;
pub mod lifecycle;
pub mod live;
pub mod modeller;
mod panels;
pub mod reach;
pub mod scene;
pub mod settings;
pub mod stroke;
pub mod symmetry;
pub mod tools;
pub mod window;

pub use camera::{OrbitCamera, ViewPreset};
pub use command::Command;
pub use document::Document;
pub use modeller::Modeller;
pub use window::WindowApp;

use std::path::PathBuf;

use crate::model::Model;
use crate::surface::{Primitive, PrimitiveParams};

/// How the window starts.
#[derive(Debug, Clone, Default)]
pub struct WindowOptions {
    /// A model file to open; without one, the paper's 10 × 10 plane.
    pub model: Option<PathBuf>,
    /// The autosave file; `None` for the default (see [`autosave`]).
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
        options.autosave.clone().or_else(autosave::default_path)
    };
    let mut modeller =
        Modeller::new(doc, autosave, !options.no_recover).with_settings(settings::default_path());
    if let Some(profile) = &options.profile {
        modeller
            .connect_profile(profile)
            .map_err(|e| anyhow::anyhow!("--profile {profile}: {e}"))?;
    }
    WindowApp::new(modeller).run()
}
