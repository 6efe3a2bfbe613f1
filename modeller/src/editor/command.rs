//! What the panels, prompts, dialogs and shortcuts ask the modeller to do.
//!
//! The window's UI functions (`*_ui` in the shell's `panels` module) draw and return
//! [`Command`]s, and its key table maps each key to one; only
//! [`Modeller::apply`](super::modeller::Modeller::apply) acts on them — file I/O, undo,
//! replacing the document — so the same actions run from a test without a window.

use std::path::PathBuf;

use super::camera::ViewPreset;
use super::lifecycle::{ConflictAnswer, PrimitiveForm, UnsavedAnswer};
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
    /// Turn symmetry on if it is off, off if it is on.
    ToggleSymmetry,
    /// Ask for another symmetry: mirrors across x, y, z, radial `N` about z, the lathe.
    SetSymmetrySpec(crate::surface::SymmetrySpec),
    /// Radial symmetry about the z axis (`N` from the tool panel): off → `N`-fold → lathe →
    /// off.
    ToggleRadial,
    /// Show the surface in the next display mode: clay → zebra → curvature → isophotes.
    CycleSurfaceMode,
    /// Switch the view between perspective and orthographic (numpad 5).
    ToggleProjection,
    /// Project the view in perspective or orthographically (the Display panel).
    SetProjection(crate::editor::camera::Projection),
    /// Set the finger radius by moving the mouse (a left click keeps it, Esc or another
    /// click restores it).
    AdjustRadius,
    /// Set the depth by moving the mouse (as [`Command::AdjustRadius`]).
    AdjustDepth,
    /// Esc: cancel the stroke in progress, else the radius or depth being set; else close
    /// the help, else the file dialog.
    Cancel,
    /// Start recording operations.
    StartRecording,
    /// Drop the recording.
    DiscardRecording,
    /// Stop the replay in progress.
    StopReplay,
    /// The answer to the unsaved-changes question.
    AnswerUnsaved(UnsavedAnswer),
    /// The answer to the question about a file changed on disk since it was opened.
    AnswerConflict(ConflictAnswer),
    /// Recover the earlier session's autosave at this path.
    Recover(PathBuf),
    /// Drop the earlier session's autosave.
    DiscardRecovery,
    /// The mouse drives the hand, with this profile (the Hand tool is selected).
    UseMouseHand(nendo_devices::profile::MouseProfile),
}

/// What a file dialog is for: the file the command asks for, its title, whether it names a
/// new file, the endings listed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DialogPurpose {
    /// Open a model.
    OpenModel,
    /// Save the model.
    SaveModel,
    /// Export a mesh or, exactly, STEP / IGES (the extension picks the format).
    ExportMesh,
    /// Save the recorded operations.
    SaveOps,
    /// Replay an operations file.
    ReplayOps,
    /// Open a device profile (JSON).
    OpenProfile,
    /// Name the trace file a device session records to.
    RecordTrace,
    /// Pick a recorded trace to replay.
    ReplayTrace,
}

impl DialogPurpose {
    /// The dialog's title.
    #[must_use]
    pub fn title(self) -> &'static str {
        match self {
            DialogPurpose::OpenModel => "Open model",
            DialogPurpose::SaveModel => "Save model as",
            DialogPurpose::ExportMesh => "Export (.obj, .stl, .glb; exact: .step, .igs)",
            DialogPurpose::SaveOps => "Save recorded operations",
            DialogPurpose::ReplayOps => "Replay operations",
            DialogPurpose::OpenProfile => "Open a device profile",
            DialogPurpose::RecordTrace => "Record the device session to (.trace)",
            DialogPurpose::ReplayTrace => "Replay a hand trace (.trace)",
        }
    }

    /// True when the dialog names a new file rather than picking an existing one.
    #[must_use]
    pub fn saves(self) -> bool {
        matches!(
            self,
            DialogPurpose::SaveModel
                | DialogPurpose::ExportMesh
                | DialogPurpose::SaveOps
                | DialogPurpose::RecordTrace
        )
    }

    /// File name endings listed (lower case).
    #[must_use]
    pub fn endings(self) -> &'static [&'static str] {
        match self {
            DialogPurpose::OpenModel | DialogPurpose::SaveModel => &[".json"],
            DialogPurpose::ExportMesh => {
                &[".obj", ".stl", ".glb", ".step", ".stp", ".igs", ".iges"]
            }
            DialogPurpose::SaveOps | DialogPurpose::ReplayOps => &[".jsonl", ".ops", ".txt"],
            DialogPurpose::OpenProfile => &[".json"],
            DialogPurpose::RecordTrace | DialogPurpose::ReplayTrace => &[".trace"],
        }
    }
}
