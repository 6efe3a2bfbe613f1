//! The modeller's state and its frame, independent of winit and of the GPU (the window feeds
//! it input and draws what it builds).
//!
//! The state is split by concern: the document and its lifecycle ([`Session`]: unsaved
//! changes, the questions, the action waiting on them, autosave), the camera and the pointer,
//! each tool's state ([`ToolState`] for the mouse tools, [`MouseHand`] for the Hand tool,
//! [`LiveInput`] for devices), what is derived from the document ([`DisplayCache`]), and the
//! panels' settings. The panels return [`Command`]s; [`Modeller::apply`] carries them out.

use glam::{DVec3, Vec2};
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::camera::{OrbitCamera, ViewPreset};
use super::command::Command;
use super::curve_edit::straight_cubic;
use super::display_cache::DisplayCache;
use super::document::Document;
use super::export_job::{ExportJob, TOLERANCE_RANGE};
use super::file_dialog::{DialogPurpose, FileDialog};
use super::hand_input::MouseHand;
use super::keymap::{Action, OrbitButton};
use super::lifecycle::{Next, Pending, PrimitiveForm, Session};
use super::live::{LiveInput, ViewAnchor};
use super::panels::{self, FrameRate, PANEL_WIDTH, Status};
use super::reach::Reach;
use super::scene::{Overlays, SurfaceDisplay, framing_points, model_lines};
use super::settings::Settings;
use super::stroke::LiveStroke;
use super::symmetry::MirrorToggle;
use super::tools::{DEPTH_RANGE, Edit, RADIUS_RANGE, Tool, ToolContext, ToolSettings, ToolState};
use crate::curve::Curve;
use crate::curve::json::DynCurve;
use crate::mesh::Tessellation;
use crate::model::Model;
use crate::model::ops::{op_to_json, parse_ops};
use crate::render::{LineBatch, SphereInstance, Style};
use crate::surface::{Op, Plane, refine};

/// Mouse buttons the viewport listens to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Button {
    /// Tools.
    Left,
    /// Orbit (with Shift: pan).
    Right,
    /// Pan.
    Middle,
}

/// Pointer input in viewport pixels (origin top-left of the 3D view), already filtered by
/// egui's `consumed` flag.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PointerInput {
    /// The cursor moved.
    Moved(Vec2),
    /// A button went down.
    Pressed(Button, Vec2),
    /// A button went up.
    Released(Button, Vec2),
    /// Wheel notches, positive away from the user.
    Wheel(f32),
    /// The cursor left the window.
    Left,
}

/// The pointer over the 3D view.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Pointer {
    /// Viewport size in pixels.
    viewport: Vec2,
    cursor: Option<Vec2>,
    /// Left, right, middle held (pressed in the view).
    buttons: [bool; 3],
    shift: bool,
    /// Ctrl held (inverts a stroke).
    ctrl: bool,
}

/// Frame timing, smoothed.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Timing {
    /// Wall time of a frame from its start to the present, ms (exponentially smoothed): UI,
    /// scene, recording, and waiting for the GPU — on a software adapter, the rasterisation
    /// itself.
    frame_ms: f64,
    /// Frames in the last full second.
    fps: u32,
    frames_this_second: u32,
    second_started: Option<Instant>,
}

/// Operations being replayed, one per frame.
#[derive(Debug, Clone)]
struct Replay {
    ops: Vec<Op>,
    next: usize,
}

/// The panels' own settings.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PanelSettings {
    /// The new-primitive form.
    form: PrimitiveForm,
    /// What to draw besides the clay.
    overlays: Overlays,
    /// The mesh export's tolerance.
    export_tolerance: f64,
    /// Refine where the finger reaches before each push, pull or draw-a-line (on by default).
    auto_refine: bool,
    /// Which button orbits.
    orbit: OrbitButton,
}

/// What F (radius) or Shift+F (depth) is adjusting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Adjusted {
    Radius,
    Depth,
}

/// A radius or depth being set by moving the mouse (F, Shift+F): the value doubles every
/// [`Adjust::PIXELS_PER_DOUBLING`] to the right of where the cursor was when it began.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Adjust {
    what: Adjusted,
    /// The value before: Esc or a right click restores it.
    start: f64,
    /// The cursor when it began (`None` until the cursor is seen in the view).
    anchor: Option<Vec2>,
}

impl Adjust {
    const PIXELS_PER_DOUBLING: f32 = 150.0;
}

/// The mouse tools: which is active, their settings and their gesture.
#[derive(Debug, Clone)]
struct Tools {
    active: Tool,
    settings: ToolSettings,
    state: ToolState,
}

/// Everything the window shows and edits.
pub struct Modeller {
    /// The document and its lifecycle.
    session: Session,
    camera: OrbitCamera,
    pointer: Pointer,
    /// The mouse tools.
    tools: Tools,
    /// The Hand tool.
    hand: MouseHand,
    /// Devices.
    live: LiveInput,
    /// The Devices panel is shown.
    devices_open: bool,
    /// The remembered settings as last written, and where (`None`: nothing is remembered).
    settings: Option<(PathBuf, Settings)>,
    /// What is derived from the document.
    cache: DisplayCache,
    /// Reframe the camera on the next refresh (new model).
    frame_pending: bool,
    panel: PanelSettings,
    /// The file dialog on screen.
    dialog: Option<FileDialog>,
    status: Option<Status>,
    timing: Timing,
    replay: Option<Replay>,
    /// A mesh export running in the background.
    export_job: Option<ExportJob>,
    /// The push, pull or line being drawn, deforming the surface live.
    stroke: Option<LiveStroke>,
    /// The stroke's gesture changed since its surface was last shown.
    stroke_dirty: bool,
    /// F or Shift+F in progress.
    adjust: Option<Adjust>,
    /// The help overlay is open.
    help: bool,
    /// The camera and surface generation the hover was last picked with (the brush ring is
    /// picked again when either changes, not only when the mouse moves).
    hover_view: Option<(OrbitCamera, u64)>,
    /// The patches the finger would reach (hover) or reaches (stroke).
    reach: Reach,
    /// Symmetry: every stroke mirrored across x = 0 (X).
    mirror: MirrorToggle,
}

impl Modeller {
    /// A modeller editing `doc`, autosaving to `autosave` (with a recovery prompt when an
    /// earlier session left one and `offer_recovery` is set).
    #[must_use]
    pub fn new(doc: Document, autosave: Option<PathBuf>, offer_recovery: bool) -> Self {
        Self {
            session: Session::new(doc, autosave, offer_recovery),
            camera: OrbitCamera::default(),
            pointer: Pointer {
                viewport: Vec2::ONE,
                cursor: None,
                buttons: [false; 3],
                shift: false,
                ctrl: false,
            },
            tools: Tools {
                active: Tool::Push,
                settings: ToolSettings::default(),
                state: ToolState::default(),
            },
            hand: MouseHand::default(),
            live: LiveInput::default(),
            devices_open: false,
            settings: None,
            cache: DisplayCache::default(),
            frame_pending: true,
            panel: PanelSettings {
                form: PrimitiveForm::defaults_for(crate::surface::Primitive::Plane),
                overlays: Overlays::default(),
                export_tolerance: Tessellation::EXPORT.tolerance,
                auto_refine: true,
                orbit: OrbitButton::default(),
            },
            dialog: None,
            status: None,
            timing: Timing::default(),
            replay: None,
            export_job: None,
            stroke: None,
            stroke_dirty: false,
            adjust: None,
            help: false,
            hover_view: None,
            reach: Reach::default(),
            mirror: MirrorToggle::new(Plane::X),
        }
    }

    /// The same modeller remembering its settings in `path` (see [`super::settings`]): they
    /// are read now (a file that cannot be used gives a warning on the status line and the
    /// defaults), the user's profile folder is listed, and every later change is written.
    #[must_use]
    pub fn with_settings(mut self, path: Option<PathBuf>) -> Self {
        self.live = LiveInput::with_profile_dir(super::settings::profile_dir());
        let Some(path) = path else {
            return self;
        };
        let (settings, warning) = Settings::load(&path);
        if let Some(w) = warning {
            eprintln!("nendo: {w}");
            self.set_status(w, true);
        }
        self.live.apply_settings(&settings);
        self.devices_open = settings.devices_open;
        self.panel.orbit = match settings.orbit.as_deref() {
            Some("middle") => OrbitButton::Middle,
            _ => OrbitButton::Right,
        };
        // What is in effect now, so only a real change writes the file.
        let current = self.current_settings(&settings);
        self.settings = Some((path, current));
        self
    }

    /// The settings in effect, on top of `base` (members this window does not know are kept).
    fn current_settings(&self, base: &Settings) -> Settings {
        let mut s = base.clone();
        self.live.store_settings(&mut s);
        s.orbit = Some(
            match self.panel.orbit {
                OrbitButton::Right => "right",
                OrbitButton::Middle => "middle",
            }
            .into(),
        );
        s.devices_open = self.devices_open;
        s
    }

    /// Writes the settings when they changed (a failure is shown once, then retried at the
    /// next change).
    fn remember_settings(&mut self) {
        let Some((path, last)) = &self.settings else {
            return;
        };
        let now = self.current_settings(last);
        if now == *last {
            return;
        }
        let path = path.clone();
        if let Err(e) = now.save(&path) {
            self.set_status(e.to_string(), true);
        }
        self.settings = Some((path, now));
    }

    /// Selects a device profile (a shipped name or a file) and connects to its devices, the
    /// Devices panel shown (`nendo --profile`).
    ///
    /// # Errors
    /// When the profile is neither shipped nor a readable profile file.
    pub fn connect_profile(
        &mut self,
        name_or_path: &str,
    ) -> Result<(), nendo_devices::DeviceError> {
        self.live.select_profile(name_or_path)?;
        self.devices_open = true;
        if let Some(mouse) = self.live.connect_or_mouse(&mut self.session.doc) {
            self.apply(Command::UseMouseHand(mouse));
        }
        Ok(())
    }

    /// The model point under the view centre (the orbit target when the centre misses the
    /// surface) and the model's size: what the Devices panel aligns the hand with.
    fn view_anchor(&self) -> ViewAnchor {
        let viewport = self.pointer.viewport;
        let ray = self.camera.ray(viewport * 0.5, viewport);
        let display = self.cache.display();
        let extent = display
            .mesh
            .bounds()
            .map_or(10.0, |(lo, hi)| f64::from((hi - lo).max_element()))
            .max(1e-6);
        match crate::mesh::pick(self.cache.patches(), &display.mesh, &ray) {
            Some(hit) => ViewAnchor {
                point: hit.point,
                normal: if hit.normal.dot(ray.direction) > 0.0 {
                    -hit.normal
                } else {
                    hit.normal
                },
                extent,
            },
            None => ViewAnchor {
                point: self.camera.target.as_dvec3(),
                normal: -ray.direction,
                extent,
            },
        }
    }

    /// The document.
    #[must_use]
    pub fn document(&self) -> &Document {
        &self.session.doc
    }

    /// The document's lifecycle and autosave.
    #[must_use]
    pub fn session(&self) -> &Session {
        &self.session
    }

    /// True once the user asked to close (and answered any question about unsaved work).
    #[must_use]
    pub fn wants_to_quit(&self) -> bool {
        self.session.wants_to_quit()
    }

    /// The window's close button: asks about unsaved changes first. Closing while the
    /// recovery question is open quits and leaves that autosave for the next start.
    pub fn request_close(&mut self) {
        self.request(Pending::Close);
    }

    /// Opens a model file into the window, asking first when the document has unsaved
    /// changes.
    pub fn open(&mut self, path: &Path) {
        self.request(Pending::Open(path.to_path_buf()));
    }

    /// Whether Shift and Ctrl are held (from the window's modifier events).
    pub fn set_modifiers(&mut self, shift: bool, ctrl: bool) {
        self.pointer.shift = shift;
        self.tools.state.set_smooth(shift);
        if ctrl != self.pointer.ctrl {
            self.pointer.ctrl = ctrl;
            self.tools.state.set_invert(ctrl);
            self.stroke_dirty |= self.stroke.is_some();
        }
    }

    /// Which mouse button orbits.
    pub fn set_orbit_button(&mut self, orbit: OrbitButton) {
        self.panel.orbit = orbit;
    }

    /// The exit: finishes a running export; the autosave is removed only when it is this
    /// session's and holds nothing unsaved (or the user chose to quit without saving).
    pub fn on_exit(&mut self) {
        if let Some(job) = self.export_job.take() {
            eprintln!("nendo: finishing the export of {}", job.path().display());
            match job.wait() {
                Ok(done) => eprintln!("nendo: {}", done.message()),
                Err(e) => eprintln!("nendo: {e}"),
            }
        }
        self.end_hand_contacts();
        self.live.disconnect_from(&mut self.session.doc);
        self.session.on_exit();
    }

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
                .exact_size(super::devices_panel::DEVICES_PANEL_WIDTH)
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
    fn side_panel_ui(&mut self, ui: &mut egui::Ui, commands: &mut Vec<Command>) {
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

    /// Carries out a command from the panels, a prompt, a dialog or a shortcut.
    pub fn apply(&mut self, command: Command) {
        match command {
            Command::Undo => self.undo(),
            Command::Redo => self.redo(),
            Command::Save => {
                let next = self.session.save_requested();
                self.follow(next);
            }
            Command::ShowDialog(purpose) => self.show_dialog(purpose),
            Command::DialogChosen(purpose, path) => {
                self.dialog = None;
                self.dialog_chosen(purpose, path);
            }
            Command::DialogCancelled => {
                self.dialog = None;
                self.session.save_dialog_closed();
            }
            Command::Create(form) => {
                self.panel.form = form;
                self.request(Pending::Create(form));
            }
            Command::AddCurve => self.add_curve(),
            Command::SelectTool(tool) => self.select_tool(tool),
            Command::SetRegulation(regulation) => {
                self.end_hand_contacts();
                self.session.doc.set_regulation(regulation);
                self.set_status(
                    format!(
                        "regulation {regulation}: applies to the next strokes (or Regulate now)"
                    ),
                    false,
                );
            }
            Command::RegulateNow => self.regulate_now(),
            Command::SetSymmetry(on) => self.set_symmetry(on),
            Command::Refine => {
                self.end_hand_contacts();
                let model = self.session.doc.model();
                match refine::uniform(&model.surface, 2) {
                    Ok(surface) => {
                        let (m, n) = (surface.patches_u(), surface.patches_v());
                        let mut refined = model.clone();
                        refined.surface = surface;
                        self.session.doc.replace("refine", refined);
                        self.set_status(format!("refined: {m} x {n} patches"), false);
                    }
                    Err(e) => self.set_status(format!("cannot refine: {e}"), true),
                }
            }
            Command::SetAutoRefine(on) => self.panel.auto_refine = on,
            Command::View(preset) => self.view_from(preset),
            Command::FrameAll => self.frame_all(),
            Command::ToggleHelp => self.help = !self.help,
            Command::StartRecording => self.session.doc.recording = Some(Vec::new()),
            Command::DiscardRecording => self.session.doc.recording = None,
            Command::StopReplay => self.replay = None,
            Command::AnswerUnsaved(answer) => {
                let next = self.session.answer_unsaved(answer);
                self.follow(next);
            }
            Command::Recover(path) => match self.session.recover(&path) {
                Ok(doc) => {
                    self.replace_document(doc);
                    self.set_status("recovered the autosave: save it to keep it", false);
                }
                Err(e) => self.set_status(format!("cannot recover: {e}"), true),
            },
            Command::DiscardRecovery => self.session.discard_recovery(),
            Command::UseMouseHand(profile) => {
                self.end_hand_contacts();
                self.hand.use_profile(profile);
                self.select_tool(Tool::Hand);
                self.set_status("the mouse drives the hand: Hand tool selected", false);
            }
        }
    }

    /// Asks the lifecycle for `action` (it may ask the user first) and follows its answer.
    fn request(&mut self, action: Pending) {
        let next = self.session.request(action);
        self.follow(next);
    }

    /// Carries out the lifecycle's next step, and the steps that follow from it.
    fn follow(&mut self, next: Next) {
        match next {
            Next::Wait => {}
            Next::Proceed(action) => self.carry_out(action),
            Next::ChooseSavePath => {
                // The lifecycle waits on this very dialog: no `show_dialog` (which would
                // drop a waiting action along with the dialog it replaces).
                self.dialog = Some(self.new_dialog(DialogPurpose::SaveModel));
            }
            Next::Save(path) => {
                let (next, result) = self.session.save_to(&path);
                match result {
                    Ok(()) => self.set_status(format!("saved {}", path.display()), false),
                    Err(e) => self.set_status(format!("cannot save: {e}"), true),
                }
                self.follow(next);
            }
        }
    }

    /// Closes, creates or opens, the question about unsaved changes answered.
    fn carry_out(&mut self, action: Pending) {
        match action {
            // The lifecycle has set `wants_to_quit`.
            Pending::Close => {}
            Pending::Create(form) => self.create_from(form),
            Pending::Open(path) => self.open_now(&path),
        }
    }

    /// Shows a file dialog the user asked for, in place of any other (a save dialog that an
    /// action waited on goes, and the action with it).
    fn show_dialog(&mut self, purpose: DialogPurpose) {
        if self.dialog.take().is_some() {
            self.session.save_dialog_closed();
        }
        self.dialog = Some(self.new_dialog(purpose));
    }

    fn new_dialog(&self, purpose: DialogPurpose) -> FileDialog {
        if let Some(dialog) = self.live.new_dialog(purpose) {
            return dialog;
        }
        let default = match purpose {
            DialogPurpose::SaveModel | DialogPurpose::OpenModel => "model.nendo.json",
            DialogPurpose::ExportMesh => "model.obj",
            DialogPurpose::SaveOps | DialogPurpose::ReplayOps => "ops.jsonl",
            // The Devices panel opens its own dialogs for these.
            DialogPurpose::OpenProfile => "profile.json",
            DialogPurpose::RecordTrace | DialogPurpose::ReplayTrace => "session.trace",
        };
        FileDialog::beside(purpose, self.session.doc.path.as_deref(), default)
    }

    /// A file dialog picked `path`.
    fn dialog_chosen(&mut self, purpose: DialogPurpose, path: PathBuf) {
        match purpose {
            DialogPurpose::OpenModel => self.open(&path),
            DialogPurpose::SaveModel => {
                let next = self.session.save_path_chosen(path);
                self.follow(next);
            }
            DialogPurpose::ExportMesh => self.export(&path),
            DialogPurpose::SaveOps => self.save_recording(&path),
            DialogPurpose::OpenProfile
            | DialogPurpose::RecordTrace
            | DialogPurpose::ReplayTrace => self.live.dialog_chosen(purpose, &path),
            DialogPurpose::ReplayOps => match std::fs::read_to_string(&path) {
                Ok(text) => match parse_ops(&text) {
                    Ok(ops) => self.replay = Some(Replay { ops, next: 0 }),
                    Err(e) => self.set_status(format!("{}: {e}", path.display()), true),
                },
                Err(e) => self.set_status(format!("{}: {e}", path.display()), true),
            },
        }
    }

    /// Ends the recording and writes it to `path` as JSON lines (kept on failure).
    fn save_recording(&mut self, path: &Path) {
        let ops = self.session.doc.recording.take().unwrap_or_default();
        let text: String = ops
            .iter()
            .map(|op| format!("{}\n", op_to_json(op)))
            .collect();
        match crate::model::write_atomically(path, text.as_bytes()) {
            Ok(()) => self.set_status(
                format!("saved {} operations to {}", ops.len(), path.display()),
                false,
            ),
            Err(e) => {
                self.session.doc.recording = Some(ops);
                self.set_status(format!("cannot save the recording: {e}"), true);
            }
        }
    }

    /// Starts exporting the surface to `path` on its own thread (see [`ExportJob`]).
    fn export(&mut self, path: &Path) {
        if let Some(job) = &self.export_job {
            let busy = format!("still exporting {}", job.path().display());
            return self.set_status(busy, true);
        }
        if let Some(format) = crate::cad::CadFormat::from_path(path) {
            let model = self.session.doc.model().clone();
            match ExportJob::start_cad(model, path.to_path_buf(), format) {
                Ok(job) => {
                    self.set_status(format!("exporting {}…", path.display()), false);
                    self.export_job = Some(job);
                }
                Err(e) => self.set_status(e.to_string(), true),
            }
            return;
        }
        let tolerance = self
            .panel
            .export_tolerance
            .clamp(*TOLERANCE_RANGE.start(), *TOLERANCE_RANGE.end());
        match ExportJob::start(
            self.cache.patches().to_vec(),
            path.to_path_buf(),
            Tessellation::with_tolerance(tolerance),
        ) {
            Ok(job) => {
                self.set_status(format!("exporting {}…", path.display()), false);
                self.export_job = Some(job);
            }
            Err(e) => self.set_status(e.to_string(), true),
        }
    }

    fn undo(&mut self) {
        self.cancel_stroke();
        self.end_hand_contacts();
        if !self.session.doc.undo() {
            self.set_status("nothing to undo", false);
        }
    }

    fn redo(&mut self) {
        self.cancel_stroke();
        self.end_hand_contacts();
        if !self.session.doc.redo() {
            self.set_status("nothing to redo", false);
        }
    }

    /// Adds a straight cubic above the surface and selects the curve grab.
    fn add_curve(&mut self) {
        let (lo, hi) = self
            .cache
            .display()
            .mesh
            .bounds()
            .unwrap_or((glam::Vec3::splat(-1.0), glam::Vec3::splat(1.0)));
        let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
        let z = hi.z + 0.25 * (hi - lo).length();
        let mid_y = 0.5 * (lo.y + hi.y);
        let curve = straight_cubic(DVec3::new(lo.x, mid_y, z), DVec3::new(hi.x, mid_y, z));
        self.end_hand_contacts();
        self.session.doc.begin_edit("add curve");
        self.session.doc.curves_mut().push(DynCurve::D3(curve));
        self.select_tool(Tool::GrabCurve);
    }

    /// The window title.
    #[must_use]
    pub fn title(&self) -> String {
        self.session.title()
    }

    /// When the window must run a frame even without input (a pending autosave, a background
    /// export to look in on).
    #[must_use]
    pub fn wake_at(&self, now: Instant) -> Option<Instant> {
        let autosave = self.session.autosave_due(now);
        let export = self
            .export_job
            .as_ref()
            .map(|_| now + std::time::Duration::from_millis(250));
        autosave.into_iter().chain(export).min()
    }

    /// True while something changes on its own (a replay, a live device), so the window
    /// should keep drawing.
    #[must_use]
    pub fn animating(&self) -> bool {
        self.replay.is_some() || self.live.is_connected()
    }

    fn set_status(&mut self, text: impl Into<String>, error: bool) {
        self.status = Some(Status {
            text: text.into(),
            error,
        });
    }

    /// Sets the viewport size (pixels) for this frame.
    pub fn set_viewport(&mut self, size: Vec2) {
        self.pointer.viewport = size.max(Vec2::ONE);
    }

    /// Viewport size in pixels.
    #[must_use]
    pub fn viewport(&self) -> Vec2 {
        self.pointer.viewport
    }

    /// Brings the cached tessellation, patches and continuity up to the document's revision.
    pub fn refresh(&mut self) {
        self.update_stroke();
        let busy = self.gesture_busy() || self.replay.is_some();
        self.cache.refresh(&self.session.doc, busy);
        if self.frame_pending {
            self.frame_all();
            self.frame_pending = false;
        }
        self.update_hover();
        self.update_reach();
        self.update_mirror();
    }

    /// Looks again whether the model allows the mirror, when it changed (not during a stroke:
    /// the stroke keeps its own mirror map).
    fn update_mirror(&mut self) {
        if self.stroke.is_none() && !self.gesture_busy() {
            let doc = &self.session.doc;
            self.mirror.update(doc.revision(), &doc.model().surface);
        }
    }

    /// The mirror a stroke begun now uses (`None`: symmetry off or not offered).
    fn active_mirror(&mut self) -> Option<crate::surface::Symmetry> {
        let doc = &self.session.doc;
        self.mirror.update(doc.revision(), &doc.model().surface);
        self.mirror.active(&doc.model().surface).cloned()
    }

    /// Turns symmetry on or off; says why when the model does not allow it.
    fn set_symmetry(&mut self, on: bool) {
        let doc = &self.session.doc;
        self.mirror.update(doc.revision(), &doc.model().surface);
        if on && let Some(why) = self.mirror.why_not() {
            self.set_status(why, true);
            return;
        }
        self.mirror.set_wanted(on);
        let text = if on {
            format!(
                "symmetry on: strokes are mirrored across {}",
                self.mirror.plane()
            )
        } else {
            "symmetry off".to_string()
        };
        self.set_status(text, false);
    }

    /// Applies the model's regulation to the whole surface as one undoable edit.
    fn regulate_now(&mut self) {
        self.cancel_stroke();
        self.end_hand_contacts();
        let model = self.session.doc.model();
        let regulation = model.regulation;
        let mut regulated = model.clone();
        let worked = crate::surface::regulate::regulate_all(&mut regulated.surface, regulation);
        if !regulated.surface.nodes().iter().all(|p| p.is_finite()) {
            self.set_status(
                format!("regulate now ({regulation}): the result is not finite; nothing changed"),
                true,
            );
        } else if regulated.surface == model.surface {
            self.set_status(
                format!("regulate now ({regulation}): the surface already satisfies it"),
                false,
            );
        } else {
            self.session.doc.replace("regulate now", regulated);
            self.set_status(
                format!("regulated the whole surface ({regulation}, {worked} groups and poles)"),
                false,
            );
        }
    }

    /// Shows the stroke in progress as its gesture now describes it (once per frame, however
    /// many input events came since).
    fn update_stroke(&mut self) {
        if !std::mem::take(&mut self.stroke_dirty) {
            return;
        }
        let Some(stroke) = &mut self.stroke else {
            return;
        };
        if let Some(dabs) = self.tools.state.stroke_dabs(&self.tools.settings) {
            stroke.show_dabs(&mut self.session.doc, &dabs);
            self.report_stroke();
            return;
        }
        let op = {
            let ctx = ToolContext {
                camera: &self.camera,
                viewport: self.pointer.viewport,
                patches: stroke.base_patches(),
                mesh: stroke.base_mesh(),
                curves: &[],
            };
            self.tools
                .state
                .stroke_op(self.tools.active, &ctx, &self.tools.settings)
        };
        stroke.show(&mut self.session.doc, op.as_ref());
        self.report_stroke();
    }

    /// Says on the status line why the stroke's last operation was refused, or that
    /// auto-refine was skipped to keep the grid symmetric.
    fn report_stroke(&mut self) {
        let Some(stroke) = &mut self.stroke else {
            return;
        };
        let refused = stroke.take_refused();
        let skipped = stroke.take_refine_skipped();
        if let Some(e) = refused {
            self.set_status(format!("stroke refused: {e}"), true);
        } else if skipped {
            self.set_status(
                "symmetry: auto-refine skipped for this stroke (refining would break the grid's symmetry)",
                false,
            );
        }
    }

    /// Picks the surface under the cursor again when the camera or the surface changed since
    /// the last pick (an orbit, a zoom, an undo): the brush ring stays on what is under the
    /// cursor.
    fn update_hover(&mut self) {
        let tool = self.tools.active;
        let Some(cursor) = self.pointer.cursor else {
            return;
        };
        if !tool.sculpts() || self.gesture_busy() || self.adjust.is_some() {
            return;
        }
        let key = (self.camera, self.cache.generation());
        if self.hover_view == Some(key) {
            return;
        }
        self.hover_view = Some(key);
        let ctx = ToolContext {
            camera: &self.camera,
            viewport: self.pointer.viewport,
            patches: self.cache.patches(),
            mesh: &self.cache.display().mesh,
            curves: &[],
        };
        self.tools.state.hover(tool, &ctx, cursor);
    }

    /// The patches the finger reaches: the live stroke's, or those a click at the hover would
    /// change.
    fn update_reach(&mut self) {
        if let Some(stroke) = &self.stroke {
            self.reach.set(stroke.touched());
            return;
        }
        let op = if self.gesture_busy() {
            None
        } else {
            let ctx = ToolContext {
                camera: &self.camera,
                viewport: self.pointer.viewport,
                patches: self.cache.patches(),
                mesh: &self.cache.display().mesh,
                curves: &[],
            };
            self.tools
                .state
                .hover_op(self.tools.active, &ctx, &self.tools.settings)
        };
        self.reach.update(op, &self.session.doc);
    }

    /// Cancels the stroke in progress (if any): the surface is exactly as before it.
    fn cancel_stroke(&mut self) {
        self.tools.state.cancel();
        if let Some(stroke) = self.stroke.take() {
            stroke.cancel(&mut self.session.doc);
        }
        self.stroke_dirty = false;
        self.hover_view = None;
    }

    /// Carries out a key's action (some need the modeller's state: what Esc cancels).
    fn key_action(&mut self, action: Action) -> Vec<Command> {
        match action {
            Action::Undo => vec![Command::Undo],
            Action::Redo => vec![Command::Redo],
            Action::Save => vec![Command::Save],
            Action::Open => vec![Command::ShowDialog(DialogPurpose::OpenModel)],
            Action::FrameAll => vec![Command::FrameAll],
            Action::Help => vec![Command::ToggleHelp],
            Action::Tool(tool) => vec![Command::SelectTool(tool)],
            Action::ToggleSymmetry => vec![Command::SetSymmetry(!self.mirror.wanted())],
            Action::AdjustRadius | Action::AdjustDepth => {
                if !self.gesture_busy() && self.session.prompt().is_none() {
                    let (what, start) = if action == Action::AdjustRadius {
                        (Adjusted::Radius, self.tools.settings.radius)
                    } else {
                        (Adjusted::Depth, self.tools.settings.depth)
                    };
                    self.adjust = Some(Adjust {
                        what,
                        start,
                        anchor: self.pointer.cursor,
                    });
                }
                Vec::new()
            }
            Action::Cancel => {
                if self.stroke.is_some() || self.tools.state.busy() {
                    self.cancel_stroke();
                    self.set_status("stroke cancelled", false);
                } else if let Some(adjust) = self.adjust.take() {
                    self.set_adjusted(adjust.what, adjust.start);
                } else if self.help {
                    self.help = false;
                } else if self.dialog.is_some() {
                    return vec![Command::DialogCancelled];
                }
                Vec::new()
            }
        }
    }

    fn set_adjusted(&mut self, what: Adjusted, value: f64) {
        let s = &mut self.tools.settings;
        match what {
            Adjusted::Radius => s.radius = value.clamp(*RADIUS_RANGE.start(), *RADIUS_RANGE.end()),
            Adjusted::Depth => s.depth = value.clamp(*DEPTH_RANGE.start(), *DEPTH_RANGE.end()),
        }
    }

    /// Pointer input while F or Shift+F is in progress: moves set the value, a left click
    /// keeps it, a right or middle click restores it.
    fn adjust_pointer(&mut self, input: PointerInput) {
        let Some(adjust) = &mut self.adjust else {
            return;
        };
        match input {
            PointerInput::Moved(p) => {
                self.pointer.cursor = Some(p);
                let anchor = *adjust.anchor.get_or_insert(p);
                let (what, start) = (adjust.what, adjust.start);
                let factor = 2f64.powf(f64::from((p.x - anchor.x) / Adjust::PIXELS_PER_DOUBLING));
                self.set_adjusted(what, start * factor);
            }
            PointerInput::Pressed(Button::Left, _) => self.adjust = None,
            PointerInput::Pressed(_, _) => {
                let (what, start) = (adjust.what, adjust.start);
                self.adjust = None;
                self.set_adjusted(what, start);
            }
            _ => {}
        }
    }

    /// The number by the cursor: a stroke's depth (and the patches it reaches), or the radius
    /// or depth F / Shift+F is setting.
    fn cursor_label_ui(&self, ctx_egui: &egui::Context, view: egui::Rect) {
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
    fn cursor_label(ctx: &egui::Context, view: egui::Rect, cursor: Vec2, text: String) {
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

    /// Frames the whole model.
    pub fn frame_all(&mut self) {
        let points = framing_points(
            self.session.doc.model(),
            self.cache.patches(),
            self.cache.display(),
            &self.panel.overlays,
        );
        let viewport = self.pointer.viewport;
        self.camera.frame(&points, viewport.x / viewport.y);
    }

    /// Looks from a named direction at the whole model.
    pub fn view_from(&mut self, preset: ViewPreset) {
        let (yaw, pitch) = preset.angles();
        self.camera.yaw = yaw;
        self.camera.pitch = pitch;
        self.frame_all();
    }

    /// Replaces the document (opened file, new primitive, recovery): clears the tool state
    /// and reframes.
    fn replace_document(&mut self, doc: Document) {
        self.cancel_stroke();
        self.end_hand_contacts();
        self.mirror.invalidate();
        self.session.replace(doc);
        self.frame_pending = true;
        self.cache.invalidate();
    }

    /// Opens a model file in place of the document (unsaved changes already dealt with).
    fn open_now(&mut self, path: &Path) {
        match Document::open(path) {
            Ok(doc) => {
                self.session.forget_autosave(Some(path));
                self.replace_document(doc);
                self.set_status(format!("opened {}", path.display()), false);
            }
            Err(e) => self.set_status(format!("cannot open {}", e.in_file(path)), true),
        }
    }

    /// Starts a new document from `form` (unsaved changes already dealt with). The fresh
    /// primitive holds no work of the user's yet: it is clean, like the starting plane.
    fn create_from(&mut self, form: PrimitiveForm) {
        match form.primitive.build(&form.params()) {
            Ok(grid) => {
                let mut model = Model::new(grid);
                model.regulation = self.session.doc.model().regulation;
                self.session.forget_autosave(None);
                self.replace_document(Document::new(model));
                self.set_status(format!("new {}", form.primitive.name()), false);
            }
            Err(e) => self.set_status(format!("cannot build the primitive: {e}"), true),
        }
    }

    /// Ends the contacts of the hands (the live one and the mouse hand) before anything else
    /// edits the surface, as the hand loop requires.
    fn end_hand_contacts(&mut self) {
        self.live.end_contact(&mut self.session.doc);
        self.hand.end_contact(&mut self.session.doc);
    }

    /// True while a gesture is in progress (a tool's or the mouse hand's).
    fn gesture_busy(&self) -> bool {
        self.tools.state.busy() || self.hand.is_pressed()
    }

    /// Feeds the mouse hand the view ray through `pixel` with the left button as held: the
    /// hand loop deforms the document (one undoable edit per contact). With no button held the
    /// fingertip hovers one finger radius in front of the surface under the cursor.
    fn drive_hand(&mut self, pixel: Vec2) {
        let ray = self.camera.ray(pixel, self.pointer.viewport);
        self.feed_hand(ray);
    }

    fn feed_hand(&mut self, ray: crate::mesh::Ray) {
        // The mirror a contact begun now presses with (looked for only between presses: during
        // one the surface changes every frame and the contact keeps its own).
        if !self.hand.is_pressed() {
            let doc = &self.session.doc;
            self.mirror.update(doc.revision(), &doc.model().surface);
            self.hand
                .set_mirror(self.mirror.active(&doc.model().surface));
        }
        let settings = &self.tools.settings;
        let hover = self.tools.state.hover_hit().map_or_else(
            || f64::from(self.camera.distance),
            |hit| (hit.t - settings.radius).max(0.0),
        );
        let result = self.hand.feed(
            &mut self.session.doc,
            ray,
            self.pointer.buttons[0],
            hover,
            settings.radius,
            settings.depth,
        );
        if let Err(e) = result {
            self.set_status(format!("the mouse hand: {e}"), true);
        } else if let Some(e) = self.hand.take_refused() {
            self.set_status(format!("stroke refused: {e}"), true);
        }
    }

    /// Selects a tool, ending whatever the previous one was doing.
    fn select_tool(&mut self, tool: Tool) {
        if tool != self.tools.active {
            self.cancel_stroke();
            self.end_hand_contacts();
            self.tools.active = tool;
        }
    }

    /// Applies the tools' edits to the document.
    fn apply_edits(&mut self, edits: Vec<Edit>) {
        if !edits.is_empty() {
            self.end_hand_contacts();
        }
        for edit in edits {
            match edit {
                Edit::Sculpt(op) => self.sculpt(&op),
                Edit::BeginCurveEdit(what) => self.session.doc.begin_edit(what),
                Edit::ReplaceCurve { index, with } => {
                    let curves = self.session.doc.curves_mut();
                    if index < curves.len() {
                        let mut with = with.into_iter().map(DynCurve::D3);
                        if let Some(first) = with.next() {
                            curves[index] = first;
                        }
                        for (k, extra) in with.enumerate() {
                            curves.insert(index + 1 + k, extra);
                        }
                    }
                }
            }
        }
    }

    /// Applies one sculpting operation, reporting failures on the status line. With symmetry
    /// on, together with its mirror image (one undo step, refined symmetrically).
    fn sculpt(&mut self, op: &Op) {
        if let Some(mirror) = self.active_mirror() {
            let mut stroke = LiveStroke::begin(
                &self.session.doc,
                &[],
                &crate::mesh::TriMesh::default(),
                self.panel.auto_refine,
            )
            .with_mirror(Some(mirror));
            stroke.show(&mut self.session.doc, Some(op));
            if stroke.take_refine_skipped() {
                self.set_status(
                    "symmetry: auto-refine skipped (refining would break the grid's symmetry)",
                    false,
                );
            }
            if let Some(e) = stroke.commit(&mut self.session.doc, Some(op)) {
                self.set_status(format!("operation refused: {e}"), true);
            }
            return;
        }
        if self.panel.auto_refine {
            // Refine where the finger reaches first (its own undo step); an invalid operation
            // is reported by the operation itself.
            let model = self.session.doc.model();
            if let Ok(f) = refine::for_finger(&model.surface, op) {
                if !f.refinement.is_empty()
                    && let Ok(surface) = f.refinement.apply(&model.surface)
                {
                    let mut refined = model.clone();
                    refined.surface = surface;
                    self.session.doc.replace("refine for the finger", refined);
                }
                if f.limited {
                    self.set_status("refinement for the finger stopped at the grid limit", true);
                }
            }
        }
        if let Err(e) = self.session.doc.apply(op) {
            self.set_status(format!("operation refused: {e}"), true);
        }
    }

    /// Per-frame work that is not input: replay, live device frames, export, autosave.
    pub fn tick(&mut self, now: Instant) {
        if let Some(replay) = &mut self.replay {
            match replay.ops.get(replay.next).cloned() {
                Some(op) => {
                    replay.next += 1;
                    self.sculpt(&op);
                }
                None => {
                    let n = replay.ops.len();
                    self.replay = None;
                    self.set_status(format!("replayed {n} operations"), false);
                }
            }
        }
        if let Some(e) = self.live.poll(&mut self.session.doc) {
            self.set_status(format!("stroke refused: {e}"), true);
        }
        if let Some(outcome) = self.export_job.as_ref().and_then(ExportJob::poll) {
            self.export_job = None;
            match outcome {
                Ok(done) => {
                    let warn = done.missed_tolerance();
                    self.set_status(done.message(), warn);
                }
                Err(e) => self.set_status(e.to_string(), true),
            }
        }
        self.session.tick_autosave(now);
        let t = &mut self.timing;
        t.frames_this_second += 1;
        match t.second_started {
            Some(s) if now.duration_since(s).as_secs_f64() >= 1.0 => {
                t.fps = t.frames_this_second;
                t.frames_this_second = 0;
                t.second_started = Some(now);
            }
            None => t.second_started = Some(now),
            _ => {}
        }
    }

    /// Records the CPU time of a frame.
    pub fn record_frame_time(&mut self, ms: f64) {
        let t = &mut self.timing;
        t.frame_ms = if t.frame_ms == 0.0 {
            ms
        } else {
            0.9 * t.frame_ms + 0.1 * ms
        };
    }

    /// The 3D curves of the document, owned (the tools read them while the document changes).
    fn curves_3d(&self) -> Vec<(usize, Curve<DVec3>)> {
        self.session
            .doc
            .curves_3d()
            .into_iter()
            .map(|(i, c)| (i, c.clone()))
            .collect()
    }

    /// Handles pointer input over the 3D view (egui did not consume it).
    pub fn pointer(&mut self, input: PointerInput) {
        if self.session.prompt().is_some() {
            return;
        }
        if self.adjust.is_some() {
            self.adjust_pointer(input);
            return;
        }
        let curves_owned = self.curves_3d();
        let curves: Vec<(usize, &Curve<DVec3>)> =
            curves_owned.iter().map(|(i, c)| (*i, c)).collect();
        let camera = self.camera;
        // During a stroke the tools pick on the surface as it was when it began.
        let (patches, mesh) = match &self.stroke {
            Some(s) => (s.base_patches(), s.base_mesh()),
            None => (self.cache.patches(), &self.cache.display().mesh),
        };
        let ctx = ToolContext {
            camera: &camera,
            viewport: self.pointer.viewport,
            patches,
            mesh,
            curves: &curves,
        };
        let tool = self.tools.active;
        match input {
            PointerInput::Moved(p) => {
                let previous = self.pointer.cursor.replace(p);
                let delta = previous.map_or(Vec2::ZERO, |q| p - q);
                let [left, right, middle] = self.pointer.buttons;
                let shift = self.pointer.shift;
                let (orbit, pan) = match self.panel.orbit {
                    OrbitButton::Right => (right && !shift, middle || (right && shift)),
                    OrbitButton::Middle => (middle && !shift, right || (middle && shift)),
                };
                if orbit {
                    self.camera.orbit(delta);
                } else if pan {
                    self.camera.pan(delta, self.pointer.viewport.y);
                } else if tool == Tool::Hand {
                    self.tools.state.hover(Tool::Hand, &ctx, p);
                    self.drive_hand(p);
                } else if left {
                    let edits = self.tools.state.drag(&ctx, &self.tools.settings, p);
                    self.stroke_dirty |= self.stroke.is_some();
                    self.apply_edits(edits);
                } else {
                    self.tools.state.hover(tool, &ctx, p);
                    self.hover_view = Some((camera, self.cache.generation()));
                }
            }
            PointerInput::Pressed(button, p) => {
                self.pointer.cursor = Some(p);
                match button {
                    Button::Left if tool == Tool::Hand => {
                        self.tools.state.hover(Tool::Hand, &ctx, p);
                        self.pointer.buttons[0] = true;
                        self.hand
                            .press(self.pointer.shift || self.tools.settings.ridge);
                        self.live.end_contact(&mut self.session.doc);
                        self.drive_hand(p);
                    }
                    Button::Left => {
                        self.pointer.buttons[0] = true;
                        let edits = self.tools.state.press(tool, &ctx, &self.tools.settings, p);
                        if self.tools.state.stroking() {
                            self.end_hand_contacts();
                            let mirror = self.active_mirror();
                            self.stroke = Some(
                                LiveStroke::begin(
                                    &self.session.doc,
                                    self.cache.patches(),
                                    &self.cache.display().mesh,
                                    self.panel.auto_refine,
                                )
                                .with_mirror(mirror),
                            );
                            self.stroke_dirty = true;
                        }
                        self.apply_edits(edits);
                    }
                    // A right click during a stroke cancels it (and orbits nothing).
                    Button::Right if self.stroke.is_some() || self.tools.state.stroking() => {
                        self.cancel_stroke();
                        self.set_status("stroke cancelled", false);
                    }
                    Button::Right => self.pointer.buttons[1] = true,
                    Button::Middle => self.pointer.buttons[2] = true,
                }
            }
            PointerInput::Released(button, p) => match button {
                Button::Left if tool == Tool::Hand => {
                    self.pointer.buttons[0] = false;
                    self.drive_hand(p);
                    self.hand.end_contact(&mut self.session.doc);
                }
                Button::Left => {
                    self.pointer.buttons[0] = false;
                    let smoothing = self.tools.state.smoothing();
                    let edits = self
                        .tools
                        .state
                        .release(tool, &ctx, &self.tools.settings, p);
                    match self.stroke.take() {
                        // Every dab of a smoothing stroke, the last ones shown now.
                        Some(mut stroke) if smoothing => {
                            let dabs: Vec<Op> = edits
                                .into_iter()
                                .filter_map(|e| match e {
                                    Edit::Sculpt(op) => Some(op),
                                    _ => None,
                                })
                                .collect();
                            self.stroke_dirty = false;
                            stroke.show_dabs(&mut self.session.doc, &dabs);
                            let refused = stroke.take_refused();
                            if let Some(e) = stroke.commit(&mut self.session.doc, None).or(refused)
                            {
                                self.set_status(format!("operation refused: {e}"), true);
                            }
                        }
                        Some(stroke) => {
                            let op = edits.into_iter().find_map(|e| match e {
                                Edit::Sculpt(op) => Some(op),
                                _ => None,
                            });
                            self.stroke_dirty = false;
                            if let Some(e) = stroke.commit(&mut self.session.doc, op.as_ref()) {
                                self.set_status(format!("operation refused: {e}"), true);
                            }
                        }
                        None => self.apply_edits(edits),
                    }
                }
                Button::Right => self.pointer.buttons[1] = false,
                Button::Middle => self.pointer.buttons[2] = false,
            },
            PointerInput::Wheel(steps) => {
                if tool == Tool::Hand && self.hand.is_pressed() {
                    self.hand.wheel(f64::from(steps));
                    if let Some(ray) = self.hand.last_ray() {
                        self.feed_hand(ray);
                    }
                } else if self.tools.state.wheel(&ctx, &self.tools.settings, steps) {
                    self.stroke_dirty |= self.stroke.is_some();
                    let edits = self.tools.state.regrab(&ctx);
                    self.apply_edits(edits);
                } else {
                    match self.pointer.cursor {
                        Some(c) => self.camera.zoom_toward(steps, c, self.pointer.viewport),
                        None => self.camera.zoom(steps),
                    }
                }
            }
            PointerInput::Left => {
                self.pointer.cursor = None;
                if !self.gesture_busy() {
                    self.tools.state.cancel();
                }
            }
        }
    }

    /// True while a button pressed in the viewport is held (the viewport owns the pointer
    /// until it is released, even over a panel).
    #[must_use]
    pub fn owns_pointer(&self) -> bool {
        self.pointer.buttons.iter().any(|b| *b)
    }

    /// Builds what the renderer draws this frame: lines, spheres and the style. The surface
    /// mesh is [`Modeller::surface`], re-uploaded when [`Modeller::surface_generation`] changes.
    pub fn scene(&self, lines: &mut LineBatch, spheres: &mut Vec<SphereInstance>) -> Style {
        lines.clear();
        spheres.clear();
        model_lines(
            self.session.doc.model(),
            self.cache.patches(),
            self.cache.display(),
            &self.panel.overlays,
            lines,
        );
        let curves_owned = self.curves_3d();
        let curves: Vec<(usize, &Curve<DVec3>)> =
            curves_owned.iter().map(|(i, c)| (*i, c)).collect();
        let ctx = ToolContext {
            camera: &self.camera,
            viewport: self.pointer.viewport,
            patches: self.cache.patches(),
            mesh: &self.cache.display().mesh,
            curves: &curves,
        };
        let tool = self.tools.active;
        let settings = &self.tools.settings;
        self.tools
            .state
            .preview(tool, &ctx, settings, lines, spheres);
        if tool.strokes() {
            self.reach.draw(&self.cache.display().mesh, lines);
            if self.mirror.wanted()
                && self.mirror.available()
                && let Some((lo, hi)) = self.cache.display().mesh.bounds()
            {
                super::scene::mirror_plane(self.mirror.plane(), lo, hi, lines);
            }
        }
        if tool == Tool::Hand {
            self.hand.draw(lines, spheres);
        }
        self.live.draw(lines, spheres);
        Style {
            heat_map: self.panel.overlays.heat_map,
            heat_max_deg: self.panel.overlays.heat_max_deg,
            tool: self.tools.state.footprint(tool, &ctx, settings),
            ..Style::default()
        }
    }

    /// The tessellated surface to draw.
    #[must_use]
    pub fn surface(&self) -> &SurfaceDisplay {
        self.cache.display()
    }

    /// Changes whenever [`Modeller::surface`] does (also across documents).
    #[must_use]
    pub fn surface_generation(&self) -> u64 {
        self.cache.generation()
    }

    /// The surface's vertex ranges that changed since display generation `generation`, for a
    /// partial upload; `None`: upload it whole (see
    /// [`DisplayCache::vertex_ranges_since`]).
    #[must_use]
    pub fn surface_ranges_since(&self, generation: u64) -> Option<Vec<std::ops::Range<u32>>> {
        self.cache.vertex_ranges_since(generation)
    }

    /// The camera.
    #[must_use]
    pub fn camera(&self) -> &OrbitCamera {
        &self.camera
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::autosave::Autosave;
    use crate::app::lifecycle::{Prompt, UnsavedAnswer};
    use crate::app::scene::SurfaceDisplay;
    use crate::surface::{Primitive, PrimitiveParams};

    fn plane_doc() -> Document {
        Document::new(Model::new(
            Primitive::Plane
                .build(&PrimitiveParams::default())
                .expect("plane"),
        ))
    }

    #[test]
    fn a_model_that_cannot_be_opened_is_named_once() {
        let dir = std::env::temp_dir().join(format!("nendo-open-once-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temporary folder");
        let missing = dir.join("missing.nendo.json");
        let bad = dir.join("bad.nendo.json");
        std::fs::write(&bad, "{ not json").expect("write");
        for path in [&missing, &bad] {
            let mut m = Modeller::new(plane_doc(), None, false);
            m.open(path);
            let status = m.status.as_ref().expect("a status");
            assert!(status.error);
            let name = path.display().to_string();
            assert!(
                status.text.starts_with(&format!("cannot open {name}: ")),
                "{}",
                status.text
            );
            assert_eq!(status.text.matches(&name).count(), 1, "{}", status.text);
        }
        std::fs::remove_dir_all(&dir).expect("clean up");
    }

    #[test]
    fn a_new_document_at_revision_zero_still_rebuilds_the_display() {
        let mut m = Modeller::new(plane_doc(), None, false);
        m.refresh();
        let first = m.surface_generation();
        let flat = m.surface().mesh.clone();
        // An opened or recovered document restarts at revision 0, like the one it replaces.
        let mut pushed = plane_doc();
        let op = Op::Push {
            at: DVec3::new(0.5, 0.5, 0.0),
            dir: -DVec3::Z,
            depth: 0.5,
            radius: 1.25,
        };
        pushed.apply(&op).expect("push");
        let mut opened = Document::new(pushed.model().clone());
        opened.path = None;
        assert_eq!(opened.revision(), 0);
        m.replace_document(opened);
        m.refresh();
        assert_ne!(m.surface_generation(), first);
        assert_ne!(m.surface().mesh.positions, flat.positions);
    }

    #[test]
    fn pointer_gestures_sculpt_and_camera_buttons_do_not() {
        let mut m = Modeller::new(plane_doc(), None, false);
        m.set_viewport(Vec2::new(800.0, 600.0));
        m.refresh();
        let centre = Vec2::new(400.0, 300.0);
        // Right drag orbits: the model is untouched.
        m.pointer(PointerInput::Pressed(Button::Right, centre));
        m.pointer(PointerInput::Moved(centre + Vec2::new(40.0, 10.0)));
        m.pointer(PointerInput::Released(
            Button::Right,
            centre + Vec2::new(40.0, 10.0),
        ));
        assert_eq!(m.document().revision(), 0);
        m.refresh();
        // A left click in the middle pushes.
        m.pointer(PointerInput::Moved(centre));
        m.pointer(PointerInput::Pressed(Button::Left, centre));
        m.pointer(PointerInput::Released(Button::Left, centre));
        // One edit: the push, on the grid auto-refined under the finger (on by default).
        assert_eq!(m.document().revision(), 1);
        assert_eq!(m.document().history().undo_name(), Some("push"));
        let surface = &m.document().model().surface;
        assert!(
            surface.patches_u() > 10 && surface.patches_v() > 10,
            "refined under the finger: {} x {}",
            surface.patches_u(),
            surface.patches_v()
        );
        assert!(m.session.doc.undo());
        assert_eq!(
            m.document().model().surface.patches_u(),
            10,
            "one undo step"
        );
    }

    /// Push deforms live while the button is held; Esc (or a right click) during the stroke
    /// restores the surface bit for bit; a released stroke is one undo step.
    #[test]
    fn strokes_are_live_and_cancel_exactly() {
        let mut m = Modeller::new(plane_doc(), None, false);
        m.set_viewport(Vec2::new(800.0, 600.0));
        m.refresh();
        let start = m.document().model().clone();
        let centre = Vec2::new(400.0, 300.0);
        m.pointer(PointerInput::Moved(centre));
        m.refresh();
        assert!(
            !m.reach.patches().is_empty(),
            "the reach is outlined on hover"
        );
        for cancel in [true, false] {
            m.pointer(PointerInput::Pressed(Button::Left, centre));
            m.pointer(PointerInput::Moved(centre + Vec2::new(0.0, 30.0)));
            m.refresh();
            assert!(
                lowest(&m) < -0.05,
                "pushed before the release: {}",
                lowest(&m)
            );
            let shallow = lowest(&m);
            m.pointer(PointerInput::Wheel(4.0));
            m.refresh();
            assert!(lowest(&m) < shallow, "the wheel goes deeper live");
            if cancel {
                let _ = m.key_action(Action::Cancel);
                assert_eq!(m.document().model(), &start, "Esc restores exactly");
                m.pointer(PointerInput::Released(Button::Left, centre));
                assert_eq!(m.document().model(), &start);
                assert!(m.document().history().undo_name().is_none());
            } else {
                m.pointer(PointerInput::Pressed(Button::Right, centre));
                m.pointer(PointerInput::Released(Button::Right, centre));
                assert_eq!(
                    m.document().model(),
                    &start,
                    "a right click restores exactly"
                );
                m.pointer(PointerInput::Released(Button::Left, centre));
            }
            m.refresh();
        }
        // Ctrl inverts: a Push drag pulls; release keeps it as one undo step.
        m.set_modifiers(false, true);
        m.pointer(PointerInput::Pressed(Button::Left, centre));
        m.pointer(PointerInput::Moved(centre + Vec2::new(0.0, 30.0)));
        m.pointer(PointerInput::Released(
            Button::Left,
            centre + Vec2::new(0.0, 30.0),
        ));
        m.set_modifiers(false, false);
        let highest = m
            .document()
            .model()
            .surface
            .patches()
            .iter()
            .flatten()
            .map(|p| p.z)
            .fold(0.0, f64::max);
        assert!(highest > 0.05, "Ctrl+Push pulls: {highest}");
        assert_eq!(m.document().history().undo_name(), Some("pull"));
        m.apply(Command::Undo);
        assert_eq!(m.document().model(), &start);
        // F then a move to the right grows the radius; Esc restores it.
        let radius = m.tools.settings.radius;
        let _ = m.key_action(Action::AdjustRadius);
        m.pointer(PointerInput::Moved(centre + Vec2::new(150.0, 0.0)));
        assert!((m.tools.settings.radius - 2.0 * radius).abs() < 1e-9);
        let _ = m.key_action(Action::Cancel);
        assert_eq!(m.tools.settings.radius, radius);
    }

    fn pushed_model() -> Model {
        let mut doc = plane_doc();
        doc.apply(&Op::Push {
            at: DVec3::new(0.5, 0.5, 0.0),
            dir: -DVec3::Z,
            depth: 0.5,
            radius: 1.25,
        })
        .expect("push");
        doc.model().clone()
    }

    fn temp_autosave(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("nendo-modeller-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("temp dir");
        dir.join("autosave.nendo.json")
    }

    /// A recovered autosave is unsaved work: closing asks, the autosave stays until the user
    /// saves or chooses to drop it.
    #[test]
    fn recovered_work_is_kept_until_saved_or_dropped() {
        let autosave = temp_autosave("recover");
        let work = pushed_model();
        work.write(&autosave)
            .expect("an earlier session's autosave");
        let mut m = Modeller::new(plane_doc(), Some(autosave.clone()), true);
        assert_eq!(
            m.session().prompt(),
            Some(Prompt::Recover(autosave.clone()))
        );
        m.apply(Command::Recover(autosave.clone()));
        assert_eq!(m.document().model(), &work);
        assert!(m.document().is_dirty(), "recovered work is unsaved");
        assert!(m.title().ends_with('*'));
        m.request_close();
        assert!(!m.wants_to_quit(), "closing asks first");
        assert_eq!(m.session().prompt(), Some(Prompt::Unsaved(Pending::Close)));
        m.apply(Command::AnswerUnsaved(UnsavedAnswer::Cancel));
        assert!(!m.wants_to_quit() && m.session().prompt().is_none());
        // An exit that nobody confirmed (the window going away) keeps the autosave.
        m.on_exit();
        assert!(autosave.is_file(), "unsaved work keeps its autosave");
        // Saving makes the document clean; then closing quits and drops the autosave.
        let saved = autosave.with_file_name("kept.nendo.json");
        m.apply(Command::DialogChosen(
            DialogPurpose::SaveModel,
            saved.clone(),
        ));
        assert!(!m.document().is_dirty());
        m.request_close();
        assert!(m.wants_to_quit());
        m.on_exit();
        assert!(!autosave.exists(), "a clean exit removes the autosave");
        assert_eq!(
            Model::read(&saved).expect("saved").model,
            work,
            "the work is in the file"
        );
        // Quitting without saving is the user's choice, and only then does a dirty
        // document's autosave go.
        work.write(&autosave).expect("autosave again");
        let mut m = Modeller::new(plane_doc(), Some(autosave.clone()), true);
        m.apply(Command::Recover(autosave.clone()));
        m.request_close();
        m.apply(Command::AnswerUnsaved(UnsavedAnswer::Discard));
        assert!(m.wants_to_quit());
        m.on_exit();
        assert!(!autosave.exists());
        let _ = std::fs::remove_dir_all(autosave.parent().expect("dir"));
    }

    /// An autosave nobody answered for (the recovery question still open, or not offered)
    /// survives a clean exit.
    #[test]
    fn an_unanswered_autosave_survives_the_exit() {
        let autosave = temp_autosave("unanswered");
        pushed_model().write(&autosave).expect("autosave");
        let mut m = Modeller::new(plane_doc(), Some(autosave.clone()), true);
        m.request_close();
        assert!(m.wants_to_quit(), "closing with the question open quits");
        m.on_exit();
        assert!(
            autosave.is_file(),
            "and leaves the autosave for the next start"
        );
        let mut m = Modeller::new(plane_doc(), Some(autosave.clone()), false);
        m.request_close();
        m.on_exit();
        assert!(autosave.is_file(), "--no-recover leaves it in place too");
        let _ = std::fs::remove_dir_all(autosave.parent().expect("dir"));
    }

    /// Create and Open replace a document with unsaved changes only once the user said so,
    /// and the autosave of that work is not overwritten while the question is open.
    #[test]
    fn create_and_open_ask_before_dropping_unsaved_work() {
        let autosave = temp_autosave("create");
        let mut m = Modeller::new(plane_doc(), Some(autosave.clone()), false);
        m.set_viewport(Vec2::new(800.0, 600.0));
        m.refresh();
        let centre = Vec2::new(400.0, 300.0);
        m.pointer(PointerInput::Moved(centre));
        m.pointer(PointerInput::Pressed(Button::Left, centre));
        m.pointer(PointerInput::Released(Button::Left, centre));
        assert!(m.document().is_dirty());
        let work = m.document().model().clone();
        let t0 = Instant::now();
        m.tick(t0);
        m.tick(t0 + Autosave::SETTLE * 2);
        assert_eq!(Model::read(&autosave).expect("autosaved").model, work);

        let sphere = PrimitiveForm::defaults_for(Primitive::Sphere);
        m.apply(Command::Create(sphere));
        assert_eq!(m.document().model(), &work, "nothing replaced yet");
        assert_eq!(
            m.session().prompt(),
            Some(Prompt::Unsaved(Pending::Create(sphere))),
            "Create asks"
        );
        m.tick(t0 + Autosave::INTERVAL * 3);
        assert_eq!(
            Model::read(&autosave).expect("autosave").model,
            work,
            "the earlier work's autosave stays while the question is open"
        );
        m.apply(Command::AnswerUnsaved(UnsavedAnswer::Cancel));
        assert_eq!(m.document().model(), &work, "cancel keeps the work");
        assert!(m.document().is_dirty());

        // Open asks too; saving first keeps the work in a file, then the file opens.
        let other = autosave.with_file_name("other.nendo.json");
        Model::new(
            Primitive::Torus
                .build(&PrimitiveParams::default())
                .expect("torus"),
        )
        .write(&other)
        .expect("write");
        m.open(&other);
        assert_eq!(m.document().model(), &work, "Open asks first");
        assert!(matches!(m.session().prompt(), Some(Prompt::Unsaved(_))));
        let kept = autosave.with_file_name("work.nendo.json");
        m.session.doc.path = Some(kept.clone());
        m.apply(Command::AnswerUnsaved(UnsavedAnswer::Save));
        assert_eq!(Model::read(&kept).expect("saved").model, work);
        assert_eq!(m.document().path.as_deref(), Some(other.as_path()));
        assert!(!m.document().is_dirty());

        // Opening the autosave file itself by name keeps it (it is the opened document).
        work.write(&autosave).expect("an autosave");
        m.open(&autosave);
        assert_eq!(m.document().path.as_deref(), Some(autosave.as_path()));
        assert!(autosave.is_file(), "the opened file is not removed");

        // With nothing unsaved, Create goes ahead without asking.
        m.apply(Command::Create(sphere));
        assert!(m.session().prompt().is_none());
        assert_eq!(
            m.document().model().surface.topology(),
            Primitive::Sphere.topology()
        );
        let _ = std::fs::remove_dir_all(autosave.parent().expect("dir"));
    }

    /// A modeller on the default plane, an 800 × 600 view, the Hand tool picked.
    fn hand_tool_on_the_plane() -> Modeller {
        let mut m = Modeller::new(plane_doc(), None, false);
        m.set_viewport(Vec2::new(800.0, 600.0));
        m.refresh();
        m.apply(Command::UseMouseHand(
            nendo_devices::profile::MouseProfile::default(),
        ));
        assert_eq!(m.tools.active, Tool::Hand);
        m
    }

    /// The Hand tool drives the mouse hand from the pointer: a press in the view pushes the
    /// plane through the document (one undoable "hand" edit), the hand is drawn, and the wheel
    /// while pressed goes deeper.
    #[test]
    fn the_hand_tool_sculpts_through_the_document() {
        let mut m = hand_tool_on_the_plane();
        let centre = Vec2::new(400.0, 300.0);
        m.pointer(PointerInput::Moved(centre));
        assert_eq!(m.document().revision(), 0, "hovering does not sculpt");
        let mut lines = LineBatch::new();
        let mut spheres = Vec::new();
        m.scene(&mut lines, &mut spheres);
        assert!(
            lines.len() >= 15 && spheres.len() >= 20,
            "the hand is drawn with its fingers"
        );
        m.pointer(PointerInput::Pressed(Button::Left, centre));
        m.pointer(PointerInput::Moved(centre));
        let shallow = lowest(&m);
        m.pointer(PointerInput::Wheel(10.0));
        let deeper = lowest(&m);
        m.pointer(PointerInput::Released(Button::Left, centre));
        assert!(shallow < -0.1, "the press pushed: {shallow}");
        assert!(
            deeper < shallow - 0.05,
            "the wheel pushed deeper: {deeper} vs {shallow}"
        );
        assert!(m.document().is_dirty());
        assert_eq!(m.document().history().undo_name(), Some("hand"));
        m.apply(Command::Undo);
        assert_eq!(
            m.document().model(),
            plane_doc().model(),
            "one undo for the contact"
        );
    }

    fn lowest(m: &Modeller) -> f64 {
        m.document()
            .model()
            .surface
            .patches()
            .iter()
            .flatten()
            .map(|p| p.z)
            .fold(0.0, f64::min)
    }

    /// With the control net shown, framing takes in the control points, which stand off the
    /// surface: framed on the surface alone, a coarse torus's net runs out of the view.
    #[test]
    fn framing_includes_the_control_net_when_it_is_drawn() {
        let grid = Primitive::Torus
            .build(&PrimitiveParams {
                patches: Some((4, 2)),
                ..PrimitiveParams::default()
            })
            .expect("torus");
        let model = Model::new(grid);
        let patches = model.surface.patches();
        let display = SurfaceDisplay::new(&patches, &Tessellation::DISPLAY);
        let aspect = 16.0 / 9.0;
        // The largest |NDC| of a control point, framed on what `overlays` draws.
        let worst = |overlays: &Overlays| {
            let points = framing_points(&model, &patches, &display, overlays);
            let view = OrbitCamera::framing(ViewPreset::Iso, &points, aspect).view(aspect);
            patches
                .iter()
                .flatten()
                .map(|q| {
                    let c = view.clip_from_world * q.as_vec3().extend(1.0);
                    (c.x / c.w).abs().max((c.y / c.w).abs())
                })
                .fold(0.0f32, f32::max)
        };
        let net = Overlays {
            control_net: true,
            ..Overlays::default()
        };
        assert!(worst(&net) <= 1.0, "the net is in view: {}", worst(&net));
        assert!(
            worst(&Overlays::default()) > 1.1,
            "framed on the surface alone the net runs out: {}",
            worst(&Overlays::default())
        );
    }

    /// A modeller whose plane has one push and no file yet.
    fn unsaved_work(name: &str) -> (Modeller, PathBuf) {
        let dir = temp_autosave(name).parent().expect("dir").to_path_buf();
        let mut m = Modeller::new(plane_doc(), None, false);
        m.set_viewport(Vec2::new(800.0, 600.0));
        m.refresh();
        m.sculpt(&Op::Push {
            at: DVec3::new(0.5, 0.5, 0.0),
            dir: -DVec3::Z,
            depth: 0.5,
            radius: 1.25,
        });
        assert!(m.document().is_dirty() && m.document().path.is_none());
        (m, dir)
    }

    /// "Save…" in the unsaved-changes question of a document with no file opens the save
    /// dialog; once it picked a file and the save worked, the action that asked (Close,
    /// Create, Open) goes on. It used to be lost: opening the dialog forgot it.
    #[test]
    fn save_in_the_unsaved_question_then_runs_the_waiting_action() {
        // Close.
        let (mut m, dir) = unsaved_work("save-close");
        let work = m.document().model().clone();
        m.request_close();
        m.apply(Command::AnswerUnsaved(UnsavedAnswer::Save));
        assert_eq!(
            m.dialog.as_ref().map(|d| d.purpose),
            Some(DialogPurpose::SaveModel),
            "Save… asks for a file"
        );
        assert!(!m.wants_to_quit(), "not before the save");
        let file = dir.join("closing.nendo.json");
        m.apply(Command::DialogChosen(
            DialogPurpose::SaveModel,
            file.clone(),
        ));
        assert_eq!(Model::read(&file).expect("saved").model, work);
        assert!(m.wants_to_quit(), "the Close went on after the save");
        assert!(m.dialog.is_none());

        // Create.
        let (mut m, dir) = unsaved_work("save-create");
        let torus = PrimitiveForm::defaults_for(Primitive::Torus);
        m.apply(Command::Create(torus));
        m.apply(Command::AnswerUnsaved(UnsavedAnswer::Save));
        let file = dir.join("before-torus.nendo.json");
        m.apply(Command::DialogChosen(
            DialogPurpose::SaveModel,
            file.clone(),
        ));
        assert!(file.is_file(), "saved");
        assert_eq!(
            m.document().model().surface.topology(),
            Primitive::Torus.topology(),
            "the Create went on after the save"
        );

        // Open.
        let (mut m, dir) = unsaved_work("save-open");
        let other = dir.join("other.nendo.json");
        let sphere = Model::new(
            Primitive::Sphere
                .build(&PrimitiveParams::default())
                .expect("sphere"),
        );
        sphere.write(&other).expect("write");
        m.open(&other);
        m.apply(Command::AnswerUnsaved(UnsavedAnswer::Save));
        let file = dir.join("before-open.nendo.json");
        m.apply(Command::DialogChosen(
            DialogPurpose::SaveModel,
            file.clone(),
        ));
        assert!(file.is_file(), "saved");
        assert_eq!(
            m.document().model(),
            &sphere,
            "the Open went on after the save"
        );
        assert_eq!(m.document().path.as_deref(), Some(other.as_path()));
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// Cancelling the save dialog that "Save…" opened keeps the work and drops the action;
    /// a failed save asks again; "Discard" goes on without writing anything.
    #[test]
    fn cancel_keeps_the_work_and_discard_drops_it() {
        let (mut m, dir) = unsaved_work("cancel");
        let work = m.document().model().clone();
        m.request_close();
        m.apply(Command::AnswerUnsaved(UnsavedAnswer::Save));
        m.apply(Command::DialogCancelled);
        assert!(!m.wants_to_quit());
        assert!(m.session().prompt().is_none() && m.dialog.is_none());
        assert_eq!(m.document().model(), &work);
        assert!(m.document().is_dirty());
        // A later plain "Save as…" does not close the window.
        let file = dir.join("plain.nendo.json");
        m.apply(Command::ShowDialog(DialogPurpose::SaveModel));
        m.apply(Command::DialogChosen(
            DialogPurpose::SaveModel,
            file.clone(),
        ));
        assert!(file.is_file() && !m.wants_to_quit());

        // A save that fails asks the question again.
        let (mut m, dir) = unsaved_work("fail");
        m.request_close();
        m.apply(Command::AnswerUnsaved(UnsavedAnswer::Save));
        let nowhere = dir.join("missing-folder").join("x.nendo.json");
        m.apply(Command::DialogChosen(DialogPurpose::SaveModel, nowhere));
        assert!(!m.wants_to_quit());
        assert_eq!(m.session().prompt(), Some(Prompt::Unsaved(Pending::Close)));
        assert!(m.status.as_ref().is_some_and(|s| s.error));

        // Discard creates without writing a file.
        let (mut m, dir) = unsaved_work("discard");
        m.apply(Command::Create(PrimitiveForm::defaults_for(
            Primitive::Torus,
        )));
        m.apply(Command::AnswerUnsaved(UnsavedAnswer::Discard));
        assert_eq!(
            m.document().model().surface.topology(),
            Primitive::Torus.topology()
        );
        assert!(!m.document().is_dirty());
        assert!(m.dialog.is_none());
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// "Refine" splits every patch into 2 × 2 as one undoable edit; with auto-refine (on by
    /// default) a push refines where its finger reaches first, and the stroke follows.
    #[test]
    fn refine_and_auto_refine_are_undoable_edits() {
        let mut m = Modeller::new(plane_doc(), None, false);
        assert!(m.panel.auto_refine);
        // Unmirrored: a mirrored operation refines within its own undo step.
        m.apply(Command::SetSymmetry(false));
        m.apply(Command::Refine);
        assert_eq!(m.document().model().surface.patch_count(), 400);
        assert_eq!(m.document().history().undo_name(), Some("refine"));
        m.apply(Command::Undo);
        assert_eq!(m.document().model(), plane_doc().model());
        m.sculpt(&Op::Push {
            at: DVec3::new(0.5, 0.5, 0.0),
            dir: -DVec3::Z,
            depth: 0.2,
            radius: 0.5,
        });
        let g = &m.document().model().surface;
        // Only the columns and rows around the finger: far fewer than uniform ×4 (40 × 40).
        assert!(
            g.patch_count() > 100 && g.patches_u() < 30 && g.patches_v() < 30,
            "{} x {}",
            g.patches_u(),
            g.patches_v()
        );
        assert_eq!(m.document().history().undo_name(), Some("push"));
        m.apply(Command::Undo);
        assert_eq!(
            m.document().history().undo_name(),
            Some("refine for the finger")
        );
        m.apply(Command::SetAutoRefine(false));
        m.apply(Command::Undo);
        m.sculpt(&Op::Push {
            at: DVec3::new(0.5, 0.5, 0.0),
            dir: -DVec3::Z,
            depth: 0.2,
            radius: 0.5,
        });
        assert_eq!(m.document().model().surface.patch_count(), 100);
    }

    /// A left-button stroke from `from` to `to` in eight moves, a frame after each.
    fn drag_stroke(m: &mut Modeller, from: Vec2, to: Vec2) {
        m.pointer(PointerInput::Moved(from));
        m.refresh();
        m.pointer(PointerInput::Pressed(Button::Left, from));
        for k in 1..=8 {
            m.pointer(PointerInput::Moved(from.lerp(to, k as f32 / 8.0)));
            m.refresh();
        }
        m.pointer(PointerInput::Released(Button::Left, to));
        m.refresh();
    }

    fn bits(model: &Model) -> Vec<[u64; 3]> {
        model
            .surface
            .nodes()
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect()
    }

    /// Symmetry is on for a symmetric model (every primitive), X toggles it; a model that is
    /// not symmetric about x = 0 does not get it, and the status line says why.
    #[test]
    fn symmetry_is_offered_only_for_a_symmetric_model() {
        let mut m = Modeller::new(plane_doc(), None, false);
        m.set_viewport(Vec2::new(800.0, 600.0));
        m.refresh();
        let grid = m.document().model().surface.clone();
        assert!(m.mirror.available() && m.mirror.active(&grid).is_some());
        for command in m.key_action(Action::ToggleSymmetry) {
            m.apply(command);
        }
        assert!(
            !m.mirror.wanted() && m.mirror.active(&grid).is_none(),
            "X: off"
        );
        for command in m.key_action(Action::ToggleSymmetry) {
            m.apply(command);
        }
        assert!(m.mirror.active(&grid).is_some(), "X: on again");

        let mut lopsided = plane_doc();
        lopsided
            .apply(&Op::Push {
                at: DVec3::new(2.5, 0.5, 0.0),
                dir: -DVec3::Z,
                depth: 0.4,
                radius: 1.0,
            })
            .expect("push");
        m.replace_document(Document::new(lopsided.model().clone()));
        m.refresh();
        assert!(!m.mirror.available());
        assert!(m.mirror.active(&m.document().model().surface).is_none());
        m.mirror.set_wanted(false);
        m.apply(Command::SetSymmetry(true));
        let status = m.status.as_ref().expect("a status");
        assert!(
            status.error && status.text.contains("not symmetric"),
            "{}",
            status.text
        );
        assert!(!m.mirror.wanted(), "refused");
    }

    /// With symmetry on (and auto-refine, the window's default), every live stroke — Push,
    /// Pull, Draw a line, Move, Smooth, and Shift+Push smoothing — changes both sides of the
    /// plane and leaves the model symmetric to 1e-12; each is one undo step back to the
    /// bit-identical model before it.
    #[test]
    fn mirrored_live_strokes_keep_the_model_symmetric() {
        use crate::surface::symmetry_error;
        let mut m = Modeller::new(plane_doc(), None, false);
        m.set_viewport(Vec2::new(800.0, 600.0));
        m.refresh();
        let (from, to) = (Vec2::new(250.0, 330.0), Vec2::new(310.0, 290.0));
        let cases = [
            (Tool::Push, false),
            (Tool::Pull, false),
            (Tool::DrawLine, false),
            (Tool::Move, false),
            (Tool::Smooth, false),
            (Tool::Push, true),
        ];
        for (tool, shift) in cases {
            m.apply(Command::SelectTool(tool));
            m.set_modifiers(shift, false);
            let before = m.document().model().clone();
            drag_stroke(&mut m, from, to);
            m.set_modifiers(false, false);
            let after = &m.document().model().surface;
            let asym = symmetry_error(after, Plane::X).relative;
            assert!(asym < 1e-12, "{tool:?} shift {shift}: asymmetry {asym:e}");
            // Changed on both sides of the plane (compared on the same surface points).
            let moved_on = |side: f64| {
                [0.5, 1.0, 1.5, 2.0, 2.5, 3.0].iter().any(|&x| {
                    [-1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5].iter().any(|&y| {
                        let q = DVec3::new(side * x, y, 0.0);
                        let a = crate::surface::nearest(&before.surface, q).expect("near");
                        let b = crate::surface::nearest(after, a.point).expect("near");
                        (a.point - b.point).length() > 1e-4
                    })
                })
            };
            assert!(
                moved_on(1.0) && moved_on(-1.0),
                "{tool:?} shift {shift}: both sides move"
            );
            assert!(m.document().history().undo_name().is_some());
            let after = m.document().model().clone();
            m.apply(Command::Undo);
            assert_eq!(
                bits(m.document().model()),
                bits(&before),
                "{tool:?}: one undo step"
            );
            m.apply(Command::Redo);
            assert!(bits(m.document().model()) == bits(&after), "{tool:?}: redo");
        }
    }

    /// With symmetry on, the Hand tool's contacts — a click (a push), a drag (a groove) and a
    /// pulled drag — change both sides of the plane as one contact, leave the model symmetric
    /// to 1e-12 relative, and undo to the bit-identical model before them. With symmetry off
    /// the same drag leaves it asymmetric.
    #[test]
    fn mirrored_hand_contacts_keep_the_model_symmetric() {
        use crate::surface::symmetry_error;
        let mut m = hand_tool_on_the_plane();
        let (from, to) = (Vec2::new(250.0, 330.0), Vec2::new(310.0, 290.0));
        for (what, end, pull) in [
            ("click", from, false),
            ("drag", to, false),
            ("pulled drag", to, true),
        ] {
            m.set_modifiers(pull, false);
            let before = m.document().model().clone();
            drag_stroke(&mut m, from, end);
            m.set_modifiers(false, false);
            // Off the button, the hand hovers again.
            m.pointer(PointerInput::Moved(Vec2::new(600.0, 100.0)));
            let after = m.document().model().clone();
            assert_eq!(m.document().history().undo_name(), Some("hand"), "{what}");
            let asym = symmetry_error(&after.surface, Plane::X);
            eprintln!("hand {what}: asymmetry {:e} relative", asym.relative);
            assert!(asym.relative < 1e-12, "{what}: asymmetry {asym:?}");
            let moved_on = |side: f64| {
                [0.5, 1.0, 1.5, 2.0, 2.5, 3.0].iter().any(|&x| {
                    [-1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5].iter().any(|&y| {
                        let q = DVec3::new(side * x, y, 0.0);
                        let a = crate::surface::nearest(&before.surface, q).expect("near");
                        let b = crate::surface::nearest(&after.surface, a.point).expect("near");
                        (a.point - b.point).length() > 1e-4
                    })
                })
            };
            assert!(moved_on(1.0) && moved_on(-1.0), "{what}: both sides move");
            m.apply(Command::Undo);
            assert_eq!(bits(m.document().model()), bits(&before), "{what}: undo");
            assert_eq!(m.document().model(), &before, "{what}: undo");
            m.apply(Command::Redo);
            assert_eq!(bits(m.document().model()), bits(&after), "{what}: redo");
        }
        m.apply(Command::SetSymmetry(false));
        drag_stroke(&mut m, from, to);
        let asym = symmetry_error(&m.document().model().surface, Plane::X).relative;
        assert!(asym > 1e-3, "symmetry off: one-sided ({asym:e})");
    }

    /// A move stroke puts the grabbed surface point on the target (the surface passes through
    /// it to 1e-9 of the model's size), with symmetry on or off.
    #[test]
    fn a_move_stroke_lands_the_grabbed_point_on_the_target() {
        for symmetric in [true, false] {
            let mut m = Modeller::new(plane_doc(), None, false);
            m.set_viewport(Vec2::new(800.0, 600.0));
            m.refresh();
            m.apply(Command::SetSymmetry(symmetric));
            m.apply(Command::SelectTool(Tool::Move));
            m.apply(Command::StartRecording);
            drag_stroke(&mut m, Vec2::new(260.0, 320.0), Vec2::new(280.0, 250.0));
            let recorded = m.document().recording.clone().unwrap_or_default();
            let [Op::Move { at, to, .. }] = recorded.as_slice() else {
                panic!("one move recorded: {recorded:?}")
            };
            assert!((*to - *at).length() > 0.3, "moved: {at} -> {to}");
            let surface = &m.document().model().surface;
            let near = crate::surface::nearest(surface, *to).expect("near");
            assert!(
                (near.point - *to).length() < 1e-9 * 5.0,
                "symmetric {symmetric}: the surface passes through the target: {}",
                (near.point - *to).length()
            );
            assert_eq!(m.document().history().undo_name(), Some("move"));
        }
    }

    /// "Regulate now" applies the chosen regulation to the whole surface as one undoable
    /// command; undo restores the model bit for bit, redo the regulated one.
    #[test]
    fn regulate_now_is_one_exact_undo_step() {
        let mut model = plane_doc().model().clone();
        model.regulation = crate::surface::Regulation::None;
        let mut m = Modeller::new(Document::new(model), None, false);
        m.set_viewport(Vec2::new(800.0, 600.0));
        m.refresh();
        m.apply(Command::SetSymmetry(false));
        m.apply(Command::SetAutoRefine(false));
        m.sculpt(&Op::Push {
            at: DVec3::new(0.7, 0.3, 0.0),
            dir: DVec3::new(0.3, 0.2, -1.0),
            depth: 0.6,
            radius: 1.3,
        });
        m.apply(Command::SetRegulation(crate::surface::Regulation::Exact));
        let creased = m.document().model().clone();
        let seam = |model: &Model| crate::surface::continuity::report(&model.surface, 8).g1_max_deg;
        m.apply(Command::RegulateNow);
        let regulated = m.document().model().clone();
        assert_ne!(regulated.surface, creased.surface, "regulated");
        assert!(
            seam(&regulated) < 0.01 && seam(&creased) > 0.1,
            "G1 after: {} (before {})",
            seam(&regulated),
            seam(&creased)
        );
        assert_eq!(m.document().history().undo_name(), Some("regulate now"));
        m.apply(Command::Undo);
        assert!(
            bits(m.document().model()) == bits(&creased),
            "undo: bit-identical"
        );
        m.apply(Command::Redo);
        assert!(bits(m.document().model()) == bits(&regulated), "redo");
    }
}
