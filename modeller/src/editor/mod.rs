//! The headless editor: everything of the modeller window that is not drawing or input — the
//! modeller that carries out the panels' commands and follows the pointer, the document and
//! its undo history, the lifecycle (unsaved changes, autosave, recovery), live strokes, the
//! mouse tools, symmetry, the camera, the scene handed to the renderer, what is derived from
//! the document, the device loop, the settings remembered between runs.
//!
//! It builds without the `gui` feature: nothing here uses winit, egui or wgpu. The window
//! (`app`, with the `gui` feature) translates its events into [`input`] and its panels' clicks
//! into [`Command`]s, and draws what the [`Modeller`] builds; `nendo bench live`,
//! `nendo render` and the tests drive it without a window.
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
//! | [`move_fold`] | whether a mirrored Move would fold the clay at the mirror plane (the cursor's warning) |
//! | [`reach`] | the patches an operation changes, outlined around the cursor |
//! | [`display_cache`] | what the window derives from the document (tessellation, continuity) |
//! | [`modeller`] | the modeller: the state the window shows and edits, [`Modeller::apply`] carrying out commands, the editing policy, the pointer state machine |
//! | [`command`] | what the panels, prompts, dialogs and shortcuts ask the modeller to do |
//! | [`input`] | the pointer events the window's shell feeds the modeller, the orbit button |
//! | [`export_job`] | mesh export off the UI thread |
//! | [`hand_input`] | device frames and the mouse as a hand: the hand loop on the document, the hand drawn |
//! | [`live`] | the device loop on its own thread; profiles, ports, alignment, calibration, the status file |
//! | [`settings`] | the settings remembered between runs, the user's profile folder |

pub mod autosave;
pub mod camera;
pub mod command;
pub mod curve_edit;
pub mod display_cache;
pub mod document;
pub mod export_job;
pub mod hand_input;
pub mod history;
pub mod input;
pub mod lifecycle;
// Half of the device loop's surface is the Devices panel's (in `app`), unused without `gui`.
#[cfg_attr(not(feature = "gui"), allow(dead_code))]
pub mod live;
pub mod modeller;
pub mod move_fold;
pub mod reach;
pub mod scene;
pub mod settings;
pub mod stroke;
pub mod symmetry;
pub mod tools;

pub use camera::{OrbitCamera, Projection, ViewPreset};
pub use command::Command;
pub use document::Document;
pub use modeller::Modeller;
