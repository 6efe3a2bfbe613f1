//! What the panels, prompts, dialogs and shortcuts ask the modeller to do.
//!
//! The UI functions (`*_ui` in the `panels` module) draw and return [`Command`]s; only
//! [`Modeller::apply`](super::Modeller::apply) acts on them — file I/O, undo, replacing the
//! document — so the same actions run from a test without a window.

use std::path::PathBuf;

use super::camera::ViewPreset;
use super::file_dialog::DialogPurpose;
use super::lifecycle::{PrimitiveForm, UnsavedAnswer};
use super::tools::Tool;
use crate::surface::Regulation;

/// An action asked for by the UI.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// Undo the last edit.
    Undo,
    /// Redo the last undone edit.
    Redo,
    /// Save to the document's file, or ask for one.
    Save,
    /// Show a file dialog (Open…, Save as…, Export…, the recording's).
    ShowDialog(DialogPurpose),
    /// A file dialog picked a file.
    DialogChosen(DialogPurpose, PathBuf),
    /// The file dialog was closed without a file.
    DialogCancelled,
    /// Start a new document from the form (asking first about unsaved changes).
    Create(PrimitiveForm),
    /// Add a straight cubic above the surface, to grab and bend.
    AddCurve,
    /// Make this the active tool.
    SelectTool(Tool),
    /// Change the model's regulation method (undoable).
    SetRegulation(Regulation),
    /// Apply the model's regulation method to the whole surface now (undoable).
    RegulateNow,
    /// Turn symmetry (every stroke mirrored across x = 0) on or off.
    SetSymmetry(bool),
    /// Split every patch into 2 × 2 without changing the surface (undoable).
    Refine,
    /// Turn the refinement before each push, pull or draw-a-line on or off.
    SetAutoRefine(bool),
    /// Look from a named direction.
    View(ViewPreset),
    /// Frame the whole model.
    FrameAll,
    /// Open or close the help overlay (every key and mouse binding).
    ToggleHelp,
    /// Start recording operations.
    StartRecording,
    /// Drop the recording.
    DiscardRecording,
    /// Stop the replay in progress.
    StopReplay,
    /// The answer to the unsaved-changes question.
    AnswerUnsaved(UnsavedAnswer),
    /// Recover the earlier session's autosave at this path.
    Recover(PathBuf),
    /// Drop the earlier session's autosave.
    DiscardRecovery,
    /// The mouse drives the hand, with this profile (the Hand tool is selected).
    UseMouseHand(nendo_devices::profile::MouseProfile),
}
