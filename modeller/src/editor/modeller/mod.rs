//! The modeller: everything the window shows and edits, and what changes it — independent of
//! winit, egui and the GPU. The window's shell (`app`) feeds it plain input
//! ([`PointerInput`], the modifiers, [`Command`]s from its panels and keys) and draws what it
//! builds ([`Modeller::scene`], [`Modeller::surface`], the state its panels show).
//!
//! The state is split by concern: the document and its lifecycle ([`DocumentSession`]: unsaved
//! changes, the questions, the action waiting on them, autosave), the camera and the pointer,
//! each tool's state ([`ToolState`] for the mouse tools, [`HandToolState`] for the Hand tool,
//! [`LiveInput`] for devices), what is derived from the document ([`DisplayCache`]), the
//! panels' settings, and what the shell is asked to show (the status line, a file dialog, the
//! help). The parts:
//!
//! | module | what it is |
//! |---|---|
//! | this one | the state, its getters, the per-frame work (replay, devices, export, autosave), the scene |
//! | `commands` | [`Modeller::apply`]: the commands carried out, the lifecycle's next steps, files |
//! | `editing` | the editing policy: the display refreshed, symmetry, live strokes and their report, the hover and the reach, the Hand tool's contacts, the tools' edits applied |
//! | `pointer` | the pointer state machine: buttons, cursor and modifiers routed to the camera, the tools, the Hand tool or a radius / depth being set |

use glam::{DVec3, Vec2};
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::camera::{OrbitCamera, ViewPreset};
use super::command::{Command, DialogPurpose};
use super::display_cache::DisplayCache;
use super::document::Document;
use super::export_job::{ExportEstimate, ExportJob, TOLERANCE_RANGE, estimate_export};
use super::hand_input::HandToolState;
use super::input::{OrbitButton, PointerInput};
use super::lifecycle::{DocumentSession, Pending, PrimitiveForm};
use super::live::{LatencySummary, LiveInput, ViewAnchor};
use super::reach::ReachedPatches;
use super::scene::{Overlays, SurfaceDisplay, framing_points, model_lines};
use super::settings::{Brushes, Settings};
use super::stroke::LiveStroke;
use super::symmetry::MirrorToggle;
use super::tools::{Tool, ToolContext, ToolSettings, ToolState};
use crate::curve::Curve;
use crate::mesh::{MeshFormat, Tessellation};
use crate::render::{LineBatch, SphereInstance, Style};
use crate::surface::{Op, Plane, SculptKind};

mod commands;
mod editing;
mod pointer;
#[cfg(test)]
mod tests;

/// A message for the status line.
#[derive(Debug, Clone, PartialEq)]
pub struct Status {
    /// The message.
    pub text: String,
    /// Shown as an error.
    pub error: bool,
}

/// A file the modeller asks the user for: the shell shows a file dialog for it until a
/// [`Command::DialogChosen`] or [`Command::DialogCancelled`] answers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FileRequest {
    /// What the file is for.
    pub purpose: DialogPurpose,
    /// The file to start beside (its folder; its name too when saving one).
    pub current: Option<PathBuf>,
    /// The name offered when `current` gives none.
    pub default_name: String,
    /// Tells one request from the next (a dialog asked for again starts afresh).
    pub id: u64,
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

/// The panels' own settings: plain values the panels edit in place.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PanelSettings {
    /// The new-primitive form.
    pub form: PrimitiveForm,
    /// What to draw besides the clay.
    pub overlays: Overlays,
    /// The mesh export's tolerance.
    pub export_tolerance: f64,
    /// Which button orbits.
    pub orbit: OrbitButton,
    /// The Devices panel is shown.
    pub devices_open: bool,
    /// How the surface is drawn: clay or an analysis mode, and the seam heat map's measure.
    pub analysis: crate::render::SurfaceAnalysis,
    /// The clay shaded with a matcap instead of the lights (`None`: lit).
    pub matcap: Option<crate::render::Matcap>,
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

/// Everything the window shows and edits (see the module docs).
pub struct Modeller {
    /// The document and its lifecycle.
    session: DocumentSession,
    camera: OrbitCamera,
    pointer: Pointer,
    /// The mouse tools.
    tools: Tools,
    /// The Hand tool.
    hand: HandToolState,
    /// Devices.
    live: LiveInput,
    /// The remembered settings as last written, and where (`None`: nothing is remembered).
    settings: Option<(PathBuf, Settings)>,
    /// Every sculpting tool's brush but the active one's (which is the panel's).
    brushes: Brushes,
    /// What is derived from the document.
    cache: DisplayCache,
    /// Reframe the camera on the next refresh (new model).
    frame_pending: bool,
    panel: PanelSettings,
    /// Refine where the finger reaches before each push, pull or draw-a-line (on by default).
    auto_refine: bool,
    /// The file asked of the user (the shell's file dialog is open for it).
    dialog: Option<FileRequest>,
    /// File requests made so far (the last one's id).
    requests: u64,
    status: Option<Status>,
    timing: Timing,
    replay: Option<Replay>,
    /// A mesh export running in the background.
    export_job: Option<ExportJob>,
    /// The export tolerance last proposed for the model's size: while the panel still holds
    /// it (the user has not set one), the next export proposes the size's own again.
    proposed_tolerance: f64,
    /// The export dialog's estimate, for (display generation, tolerance bits, format).
    export_estimate: Option<(u64, u64, MeshFormat, ExportEstimate)>,
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
    reach: ReachedPatches,
    /// Symmetry: every stroke mirrored across x = 0 (X), radial (Shift+X), the lathe, other
    /// mirrors (the tool panel).
    mirror: MirrorToggle,
}

impl Modeller {
    /// A modeller editing `doc`, autosaving to `autosave` (with a recovery prompt when an
    /// earlier session left one and `offer_recovery` is set).
    #[must_use]
    pub fn new(doc: Document, autosave: Option<PathBuf>, offer_recovery: bool) -> Self {
        Self {
            session: DocumentSession::new(doc, autosave, offer_recovery),
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
            hand: HandToolState::default(),
            live: LiveInput::default(),
            settings: None,
            brushes: Brushes::default(),
            cache: DisplayCache::default(),
            frame_pending: true,
            panel: PanelSettings {
                form: PrimitiveForm::defaults_for(crate::surface::Primitive::Plane),
                overlays: Overlays::default(),
                export_tolerance: Tessellation::EXPORT.tolerance,
                orbit: OrbitButton::default(),
                devices_open: false,
                analysis: crate::render::SurfaceAnalysis::default(),
                matcap: None,
            },
            auto_refine: true,
            dialog: None,
            requests: 0,
            status: None,
            timing: Timing::default(),
            replay: None,
            export_job: None,
            proposed_tolerance: Tessellation::EXPORT.tolerance,
            export_estimate: None,
            stroke: None,
            stroke_dirty: false,
            adjust: None,
            help: false,
            hover_view: None,
            reach: ReachedPatches::default(),
            mirror: MirrorToggle::new(Plane::X),
        }
    }

    /// The same modeller remembering its settings in `path` (see [`crate::editor::settings`]): they
    /// are read now (a file that cannot be used gives a warning on the status line and the
    /// defaults), the user's profile folder is listed, and every later change is written.
    #[must_use]
    pub fn with_settings(mut self, path: Option<PathBuf>) -> Self {
        self.live = LiveInput::with_profile_dir(crate::editor::settings::profile_dir());
        let Some(path) = path else {
            return self;
        };
        // An unusable file is kept aside as `.bad` first; one that could not be is never
        // written over (nothing is remembered then).
        let loaded = Settings::load_keeping(&path);
        let settings = loaded.settings;
        if let Some(w) = loaded.warning {
            eprintln!("nendo: {w}");
            self.set_status(w, true);
        }
        self.live.apply_settings(&settings);
        self.panel.devices_open = settings.devices_open;
        self.brushes = settings.brush.clone();
        self.brushes
            .restore(self.tools.active, &mut self.tools.settings);
        self.panel.orbit = match settings.orbit.as_deref() {
            Some("middle") => OrbitButton::Middle,
            _ => OrbitButton::Right,
        };
        self.panel.matcap = settings
            .matcap
            .as_deref()
            .and_then(crate::render::Matcap::from_name);
        // What is in effect now, so only a real change writes the file.
        let current = self.current_settings(&settings);
        self.settings = loaded.writable.then_some((path, current));
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
        s.devices_open = self.panel.devices_open;
        s.matcap = self.panel.matcap.map(|m| m.name().to_string());
        s.brush = self.brushes.clone();
        s.brush.store(self.tools.active, &self.tools.settings);
        s
    }

    /// Writes the settings when they changed (a failure is shown once, then retried at the
    /// next change); the shell calls it after each frame's commands.
    pub fn remember_settings(&mut self) {
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
        self.panel.devices_open = true;
        let anchor = self.view_anchor();
        self.live.set_view_anchor(anchor);
        self.sync_window_symmetry();
        if let Some(mouse) = self.live.connect_or_mouse(&mut self.session.doc) {
            self.apply(Command::UseMouseHand(mouse));
        }
        Ok(())
    }

    /// The model point under the view centre (the orbit target when the centre misses the
    /// surface) and the model's size: what the Devices panel aligns the hand with.
    #[must_use]
    pub fn view_anchor(&self) -> ViewAnchor {
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
    pub fn session(&self) -> &DocumentSession {
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

    /// Holds the clutch key or lets it go: a device hand moves without touching the clay
    /// while it is held (see [`LiveInput::set_clutch`]).
    pub fn set_clutch(&mut self, held: bool) {
        self.live.set_clutch(held);
    }

    /// The status line's hand part, while a device hand is clutched or presses: `clutch
    /// (Space held)`, `clutch (fist)`, or the contact's feedback
    /// ([`crate::editor::hand_input::Feedback::describe`]).
    #[must_use]
    pub fn hand_status(&self) -> Option<String> {
        if self.live.clutched() {
            let why = if self.live.clutch_key() {
                "Space held"
            } else {
                "fist"
            };
            return Some(format!("clutch ({why}): the hand moves without touching"));
        }
        self.live.feedback().map(|f| f.describe())
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
        self.poll_devices();
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

    /// Runs the device samples received so far through the hand: at the frame's start
    /// ([`Modeller::tick`]) and again just before the display refresh ([`Modeller::refresh`]),
    /// so that a sample arriving during the UI pass is shown by this frame.
    pub(super) fn poll_devices(&mut self) {
        self.sync_window_symmetry();
        if let Some(e) = self.live.poll(&mut self.session.doc) {
            self.set_status(format!("stroke refused: {e}"), true);
        }
    }

    /// Calls `waker` whenever device samples arrive (the window asks for a redraw, so that
    /// the next frame takes them at once).
    pub fn set_device_waker(&mut self, waker: super::live::DeviceWaker) {
        self.live.set_waker(waker);
    }

    /// Latches the device input for this frame, after the window acquired its surface texture:
    /// while a device session streams, waits at most `within` for one more sample (then
    /// [`Modeller::refresh`] takes it), so that the frame shows a fresh sample at submission
    /// (`editor::live` latency module docs). Returns whether a sample came; at once without a
    /// session.
    pub fn latch_devices(&self, within: std::time::Duration) -> bool {
        self.live.latch(within)
    }

    /// The frame was submitted to the GPU at `at` (the window, once `queue.submit` returned):
    /// the device samples it shows have their CPU-side latency ([`super::live::LatencyMeter`]).
    pub fn frame_submitted(&mut self, at: Instant) {
        self.live.latency_mut().submitted(at);
    }

    /// The frame submitted last was presented at `at` (once `queue.present` returned).
    pub fn frame_presented(&mut self, at: Instant) {
        self.live.latency_mut().presented(at);
    }

    /// The device samples' latency over the latest samples shown, while a device session runs.
    #[must_use]
    pub fn hand_latency(&self) -> Option<LatencySummary> {
        self.live
            .is_connected()
            .then(|| self.live.latency().summary())
            .flatten()
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
        }
        // The symmetry's planes and axis, under every tool (the Hand's contacts and the Move
        // tool's grabs are applied with it too).
        if self.mirror.wanted()
            && self.mirror.available()
            && let Some((lo, hi)) = self.cache.display().mesh.bounds()
        {
            crate::editor::scene::symmetry(self.mirror.spec(), lo, hi, lines);
        }
        if tool == Tool::Hand {
            self.hand.draw(lines, spheres);
        }
        self.live.draw(lines, spheres);
        Style {
            heat_map: self.panel.overlays.heat_map,
            heat_max_deg: if self.panel.analysis.seam_g2 {
                self.panel.analysis.g2_red_percent
            } else {
                self.panel.overlays.heat_max_deg
            },
            tool: self.tools.state.footprint(tool, &ctx, settings),
            matcap: self.panel.matcap,
            ..Style::default()
        }
    }

    /// The tessellated surface to draw.
    #[must_use]
    pub fn surface(&self) -> &SurfaceDisplay {
        self.cache.display()
    }

    /// The control points of the patches [`Modeller::surface`] was tessellated from.
    #[must_use]
    pub fn surface_patches(&self) -> &[crate::mesh::PatchPoints] {
        self.cache.patches()
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

    /// The status line's message, if any.
    #[must_use]
    pub fn status(&self) -> Option<&Status> {
        self.status.as_ref()
    }

    /// The file asked of the user, while the shell's file dialog should be open for it.
    #[must_use]
    pub fn file_request(&self) -> Option<&FileRequest> {
        self.dialog.as_ref()
    }

    /// True while the help overlay is open.
    #[must_use]
    pub fn help_open(&self) -> bool {
        self.help
    }

    /// The panels' settings.
    #[must_use]
    pub fn panel(&self) -> &PanelSettings {
        &self.panel
    }

    /// The panels' settings, for the panels to edit in place.
    pub fn panel_mut(&mut self) -> &mut PanelSettings {
        &mut self.panel
    }

    /// Whether a push, pull or draw-a-line first refines where its finger reaches.
    #[must_use]
    pub fn auto_refine(&self) -> bool {
        self.auto_refine
    }

    /// The tool panel's part: the active tool, its settings to edit in place, the symmetry
    /// toggle (whether it is on, offered, and why not), and what the toggle does not govern
    /// now (a recording's or a replayed trace's group: [`LiveInput::symmetry_note`]).
    pub fn tool_panel(&mut self) -> (Tool, &mut ToolSettings, &MirrorToggle, Option<String>) {
        let note = self.live.symmetry_note();
        (
            self.tools.active,
            &mut self.tools.settings,
            &self.mirror,
            note,
        )
    }

    /// The export panel's part: the tolerance to edit in place and the export running, if
    /// one is.
    pub fn export_panel(&mut self) -> (&mut f64, Option<&ExportJob>) {
        (&mut self.panel.export_tolerance, self.export_job.as_ref())
    }

    /// The export dialog's part: the tolerance it edits and what exporting the surface to
    /// `name` (its extension picks the format) will write, `None` for a name that is no mesh
    /// format (STEP and IGES write the exact patches: no tolerance applies).
    pub fn export_dialog(&mut self, name: &str) -> (&mut f64, Option<ExportEstimate>) {
        let format = MeshFormat::from_path(Path::new(name)).ok();
        let tolerance = self
            .panel
            .export_tolerance
            .clamp(*TOLERANCE_RANGE.start(), *TOLERANCE_RANGE.end());
        let estimate = format.map(|format| {
            let key = (self.cache.generation(), tolerance.to_bits(), format);
            match self.export_estimate {
                Some((g, t, f, e)) if (g, t, f) == key => e,
                _ => {
                    let e = estimate_export(self.cache.patches(), tolerance, format);
                    self.export_estimate = Some((key.0, key.1, key.2, e));
                    e
                }
            }
        });
        (&mut self.panel.export_tolerance, estimate)
    }

    /// The Devices panel's part: the device loop and the document it deforms.
    pub fn devices_mut(&mut self) -> (&mut LiveInput, &mut Document) {
        self.sync_window_symmetry();
        (&mut self.live, &mut self.session.doc)
    }

    /// What is derived from the document: the continuity measure, the display.
    #[must_use]
    pub fn display_cache(&self) -> &DisplayCache {
        &self.cache
    }

    /// The frame time (ms, smoothed) and the frames in the last full second.
    #[must_use]
    pub fn frame_rate(&self) -> (f64, u32) {
        (self.timing.frame_ms, self.timing.fps)
    }

    /// The replay in progress: operations applied so far and in all.
    #[must_use]
    pub fn replay_progress(&self) -> Option<(usize, usize)> {
        self.replay.as_ref().map(|r| (r.next, r.ops.len()))
    }

    /// The cursor and the number shown beside it: a stroke's depth (and the patches it
    /// reaches), how far a move went, or the radius or depth F / Shift+F is setting.
    #[must_use]
    pub fn cursor_label(&self) -> Option<(Vec2, String)> {
        let cursor = self.pointer.cursor?;
        if let Some(adjust) = &self.adjust {
            let text = match adjust.what {
                Adjusted::Radius => format!("radius {:.3}", self.tools.settings.radius),
                Adjusted::Depth => format!("depth {:.3}", self.tools.settings.depth),
            };
            return Some((cursor, text));
        }
        let stroke = self.stroke.as_ref()?;
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
                Some(Op::Move { at, to, radius }) => {
                    let folds = self.mirror.wanted()
                        && self.mirror.available()
                        && self.mirror.spec().planes.iter().any(|&plane| {
                            super::move_fold::mirrored_move_folds(*at, *to, *radius, plane)
                        });
                    let warning = if folds {
                        format!(" · {}", super::move_fold::FOLD_WARNING)
                    } else {
                        String::new()
                    };
                    format!(
                        "move {:.3} · {} patches{warning}",
                        (*to - *at).length(),
                        stroke.touched().len()
                    )
                }
                _ if self.tools.state.smoothing() => "smooth".to_string(),
                _ => return None,
            };
            return Some((cursor, text));
        };
        fn signed_depth(op: &Op) -> f64 {
            match op {
                Op::Push { depth, .. }
                | Op::PushNormal { depth, .. }
                | Op::Drag { depth, .. }
                | Op::Groove { depth, .. } => *depth,
                Op::Brushed { op, brush } => brush.strength * signed_depth(op),
                // A crease presses in for a positive depth, an inflate out.
                Op::Sculpt(b) if b.kind == SculptKind::Inflate => -b.brush.strength * b.depth,
                Op::Sculpt(b) => b.brush.strength * b.depth,
                Op::Move { .. } | Op::Smooth { .. } => 0.0,
            }
        }
        let signed = stroke.shown().map_or(0.0, signed_depth);
        let way = if signed < 0.0 { "out" } else { "in" };
        let text = format!(
            "depth {depth:.3} {way} · {} patches",
            stroke.touched().len()
        );
        Some((cursor, text))
    }
}
