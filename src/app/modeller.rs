//! The modeller's state and its frame: the document, camera, tools and panels, independent of
//! winit and of the GPU (the window feeds it input and draws what it builds).

use glam::{DVec3, Vec2};
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::autosave::{Autosave, Recovery};
use super::camera::{OrbitCamera, ViewPreset};
use super::document::Document;
use super::export_job::ExportJob;
use super::file_dialog::FileDialog;
use super::hand_input::MouseHandTool;
use super::live::LiveInput;
use super::scene::{Overlays, SurfaceDisplay, framing_points, model_lines};
use super::tools::{Edit, Tool, ToolContext, ToolSettings, ToolState};
use crate::curve::Curve;
use crate::curve::json::DynCurve;
use crate::mesh::{PatchPoints, Ray, Tessellation};
use crate::model::Model;
use crate::render::{LineBatch, SphereInstance, Style};
use crate::surface::continuity::{self, ContinuityReport};
use crate::surface::{Op, Primitive, PrimitiveParams};

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

/// A message for the status line.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Status {
    pub(super) text: String,
    pub(super) error: bool,
}

/// The form for a new primitive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct PrimitiveForm {
    pub(super) primitive: Primitive,
    pub(super) patches: (usize, usize),
    pub(super) radius: f64,
    pub(super) height: f64,
    pub(super) minor_radius: f64,
}

impl PrimitiveForm {
    pub(super) fn defaults_for(primitive: Primitive) -> Self {
        let d = primitive.defaults();
        Self {
            primitive,
            patches: d.patches,
            radius: d.radius,
            height: d.height,
            minor_radius: d.minor_radius,
        }
    }

    pub(super) fn params(&self) -> PrimitiveParams {
        PrimitiveParams {
            patches: Some(self.patches),
            radius: Some(self.radius),
            height: Some(self.height),
            minor_radius: Some(self.minor_radius),
        }
    }
}

/// Frame timing, smoothed.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Timing {
    /// Wall time of a frame from its start to the present, ms (exponentially smoothed): UI,
    /// scene, recording, and waiting for the GPU — on a software adapter, the rasterisation
    /// itself.
    pub(super) frame_ms: f64,
    /// Frames in the last full second.
    pub(super) fps: u32,
    frames_this_second: u32,
    second_started: Option<Instant>,
}

/// A modal question on screen.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Prompt {
    /// An autosave from a session that did not close cleanly.
    Recover(PathBuf),
    /// The model has unsaved changes and `Pending` would drop them.
    Unsaved(Pending),
}

/// Something that replaces or closes the document: it waits for the answer to
/// [`Prompt::Unsaved`] when the document has unsaved changes.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Pending {
    /// Close the window.
    Close,
    /// Start a new document from the primitive form.
    Create(PrimitiveForm),
    /// Open a model file.
    Open(PathBuf),
}

/// The answers to [`Prompt::Unsaved`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum UnsavedAnswer {
    /// Save first (asking for a file when the document has none), then go on.
    Save,
    /// Go on and drop the changes.
    Discard,
    /// Do nothing.
    Cancel,
}

/// Operations being replayed, one per frame.
#[derive(Debug, Clone)]
pub(super) struct Replay {
    pub(super) ops: Vec<Op>,
    pub(super) next: usize,
}

/// Everything the window shows and edits.
pub struct Modeller {
    pub(super) doc: Document,
    pub(super) camera: OrbitCamera,
    pub(super) tool: Tool,
    pub(super) settings: ToolSettings,
    pub(super) tools: ToolState,
    pub(super) overlays: Overlays,
    pub(super) display: SurfaceDisplay,
    /// The document revision the display shows (`None`: rebuild).
    display_revision: Option<u64>,
    /// Counts display rebuilds across documents (a new document starts at revision 0 again).
    display_generation: u64,
    pub(super) patches: Vec<PatchPoints>,
    pub(super) autosave: Option<Autosave>,
    /// The autosave file is this session's: it did not exist at start-up, or this session
    /// wrote it, or the user answered the recovery question. Only then may a clean exit remove
    /// it (an earlier session's autosave nobody looked at stays for the next start).
    owns_autosave: bool,
    /// What to do once the save the user chose in [`Prompt::Unsaved`] succeeds.
    pub(super) after_save: Option<Pending>,
    /// The user chose to quit without saving: the exit may remove the autosave.
    quit_discarding: bool,
    pub(super) prompt: Option<Prompt>,
    pub(super) dialog: Option<FileDialog>,
    pub(super) status: Option<Status>,
    pub(super) continuity: Option<ContinuityReport>,
    continuity_revision: Option<u64>,
    pub(super) continuity_ms: f64,
    pub(super) form: PrimitiveForm,
    pub(super) export_tolerance: f64,
    /// A mesh export running in the background.
    pub(super) export_job: Option<ExportJob>,
    pub(super) timing: Timing,
    pub(super) replay: Option<Replay>,
    pub(super) live: LiveInput,
    /// The mouse as the hand ([`Tool::Hand`]), made when the tool is first used.
    pub(super) hand: Option<MouseHandTool>,
    /// The mouse profile the hand is made with (the Devices panel's "mouse" profile).
    pub(super) hand_profile: nendo_devices::profile::MouseProfile,
    /// The view ray of the hand's last event (for a wheel step while pressed).
    hand_ray: Option<Ray>,
    /// The hand's press grips and pulls (Shift, or "ridges", at the press).
    hand_pull: bool,
    /// Viewport size in pixels.
    viewport: Vec2,
    cursor: Option<Vec2>,
    buttons: [bool; 3],
    pub(super) shift: bool,
    /// Reframe the camera on the next frame (new model).
    frame_pending: bool,
    /// The window should close.
    pub(super) quit: bool,
}

impl Modeller {
    /// A modeller editing `doc`, autosaving to `autosave` (with a recovery prompt when an
    /// earlier session left one and `offer_recovery` is set).
    #[must_use]
    pub fn new(doc: Document, autosave: Option<PathBuf>, offer_recovery: bool) -> Self {
        let autosave = autosave.map(|path| {
            let mut a = Autosave::new(path);
            // The model as opened (or the starting plane) is not worth writing.
            a.mark_saved(doc.revision());
            a
        });
        let earlier = autosave.as_ref().and_then(Autosave::pending_recovery);
        let owns_autosave = earlier.is_none();
        let prompt = earlier
            .filter(|_| offer_recovery)
            .map(|Recovery { path, .. }| Prompt::Recover(path));
        Self {
            doc,
            camera: OrbitCamera::default(),
            tool: Tool::Push,
            settings: ToolSettings::default(),
            tools: ToolState::default(),
            overlays: Overlays::default(),
            display: SurfaceDisplay::default(),
            display_revision: None,
            display_generation: 0,
            patches: Vec::new(),
            autosave,
            owns_autosave,
            after_save: None,
            quit_discarding: false,
            prompt,
            dialog: None,
            status: None,
            continuity: None,
            continuity_revision: None,
            continuity_ms: 0.0,
            form: PrimitiveForm::defaults_for(Primitive::Plane),
            export_tolerance: Tessellation::EXPORT.tolerance,
            export_job: None,
            timing: Timing::default(),
            replay: None,
            live: LiveInput::default(),
            hand: None,
            hand_profile: nendo_devices::profile::MouseProfile::default(),
            hand_ray: None,
            hand_pull: false,
            viewport: Vec2::new(1.0, 1.0),
            cursor: None,
            buttons: [false; 3],
            shift: false,
            frame_pending: true,
            quit: false,
        }
    }

    /// The document.
    #[must_use]
    pub fn document(&self) -> &Document {
        &self.doc
    }

    /// True once the user asked to close (and answered any question about unsaved work).
    #[must_use]
    pub fn wants_to_quit(&self) -> bool {
        self.quit
    }

    /// The window's close button: asks about unsaved changes first. Closing while the
    /// recovery question is open quits and leaves that autosave for the next start.
    pub fn request_close(&mut self) {
        if matches!(self.prompt, Some(Prompt::Recover(_))) {
            self.quit = true;
            return;
        }
        self.proceed(Pending::Close);
    }

    /// The exit: the autosave is removed only when it is this session's and holds nothing
    /// unsaved (or the user chose to quit without saving).
    pub fn on_exit(&mut self) {
        if let Some(job) = self.export_job.take() {
            eprintln!("nendo: finishing the export of {}", job.path().display());
            match job.wait() {
                Ok(done) => eprintln!("nendo: {}", done.message()),
                Err(e) => eprintln!("nendo: {e}"),
            }
        }
        self.end_hand_contacts();
        self.live.disconnect_from(&mut self.doc);
        let nothing_unsaved = !self.doc.is_dirty() || self.quit_discarding;
        if self.owns_autosave
            && nothing_unsaved
            && let Some(a) = &mut self.autosave
        {
            a.discard();
        }
    }

    /// Does `action` now when the document has no unsaved changes, else asks first.
    pub(super) fn proceed(&mut self, action: Pending) {
        if self.doc.is_dirty() {
            self.prompt = Some(Prompt::Unsaved(action));
        } else {
            self.carry_out(action);
        }
    }

    /// The answer to [`Prompt::Unsaved`] for `action`.
    pub(super) fn answer_unsaved(&mut self, action: Pending, answer: UnsavedAnswer) {
        self.prompt = None;
        match answer {
            UnsavedAnswer::Cancel => {}
            UnsavedAnswer::Discard => {
                if action == Pending::Close {
                    self.quit_discarding = true;
                }
                self.carry_out(action);
            }
            UnsavedAnswer::Save => match self.doc.path.clone() {
                Some(path) => {
                    if self.save_to(&path) {
                        self.carry_out(action);
                    }
                }
                None => {
                    self.after_save = Some(action);
                    self.open_dialog(super::file_dialog::DialogPurpose::SaveModel);
                }
            },
        }
    }

    /// Closes, creates or opens, the question about unsaved changes answered.
    pub(super) fn carry_out(&mut self, action: Pending) {
        match action {
            Pending::Close => self.quit = true,
            Pending::Create(form) => self.create_from(form),
            Pending::Open(path) => self.open_now(&path),
        }
    }

    /// Saves to `path`, reporting on the status line; true when it worked.
    pub(super) fn save_to(&mut self, path: &Path) -> bool {
        match self.doc.save(path) {
            Ok(()) => {
                self.set_status(format!("saved {}", path.display()), false);
                true
            }
            Err(e) => {
                self.set_status(format!("cannot save: {e}"), true);
                false
            }
        }
    }

    /// Recovers the autosave at `path`: the model comes back as unsaved work (dirty until
    /// saved; the autosave stays until then).
    pub(super) fn recover(&mut self, path: &Path) {
        self.prompt = None;
        match Document::open(path) {
            Ok(mut doc) => {
                doc.path = None;
                doc.mark_unsaved();
                self.replace_document(doc);
                self.owns_autosave = true;
                self.set_status("recovered the autosave: save it to keep it", false);
            }
            Err(e) => self.set_status(format!("cannot recover: {e}"), true),
        }
    }

    /// Declines the recovery: the earlier autosave is removed.
    pub(super) fn discard_recovery(&mut self) {
        self.prompt = None;
        if let Some(a) = &mut self.autosave {
            a.discard();
        }
        self.owns_autosave = true;
    }

    /// Removes this session's autosave before the document is replaced by one that holds no
    /// unsaved work (the old one was saved, or the user chose to drop it) — unless the new
    /// document is the autosave file itself (opened by name), which must stay.
    fn forget_autosave(&mut self, new_path: Option<&Path>) {
        if !self.owns_autosave {
            return;
        }
        if let Some(a) = &mut self.autosave {
            let same = |p: &Path| {
                p == a.path()
                    || matches!(
                        (std::fs::canonicalize(p), std::fs::canonicalize(a.path())),
                        (Ok(x), Ok(y)) if x == y
                    )
            };
            if !new_path.is_some_and(same) {
                a.discard();
            }
        }
    }

    /// The window title.
    #[must_use]
    pub fn title(&self) -> String {
        let name = self
            .doc
            .path
            .as_ref()
            .and_then(|p| p.file_name())
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "untitled".into());
        format!(
            "nendo — {name}{}",
            if self.doc.is_dirty() { " *" } else { "" }
        )
    }

    /// When the window must run a frame even without input (a pending autosave, a background
    /// export to look in on).
    #[must_use]
    pub fn wake_at(&self, now: Instant) -> Option<Instant> {
        let autosave = self
            .autosave
            .as_ref()
            .filter(|_| self.prompt.is_none())
            .and_then(|a| a.due(self.doc.revision(), now));
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

    pub(super) fn set_status(&mut self, text: impl Into<String>, error: bool) {
        self.status = Some(Status {
            text: text.into(),
            error,
        });
    }

    /// Sets the viewport size (pixels) for this frame.
    pub fn set_viewport(&mut self, size: Vec2) {
        self.viewport = size.max(Vec2::ONE);
    }

    /// Viewport size in pixels.
    #[must_use]
    pub fn viewport(&self) -> Vec2 {
        self.viewport
    }

    /// Brings the cached tessellation, patches and continuity up to the document's revision.
    pub fn refresh(&mut self) {
        let revision = self.doc.revision();
        if self.display_revision != Some(revision) {
            self.patches = self.doc.model().surface.patches();
            self.display = SurfaceDisplay::new(&self.patches, &Tessellation::DISPLAY);
            self.display_revision = Some(revision);
            self.display_generation += 1;
        }
        if self.frame_pending {
            self.frame_all();
            self.frame_pending = false;
        }
        // The continuity measure (33 points per shared edge) is cheap for the paper's sizes;
        // on big grids it is throttled to the end of a burst of edits.
        if self.continuity_revision != Some(revision)
            && !self.gesture_busy()
            && self.replay.is_none()
        {
            let start = Instant::now();
            self.continuity = Some(continuity::report(
                &self.doc.model().surface,
                continuity::MIN_SAMPLES_PER_EDGE,
            ));
            self.continuity_ms = start.elapsed().as_secs_f64() * 1e3;
            self.continuity_revision = Some(revision);
        }
    }

    /// Frames the whole model.
    pub fn frame_all(&mut self) {
        let points = framing_points(
            self.doc.model(),
            &self.patches,
            &self.display,
            &self.overlays,
        );
        self.camera
            .frame(&points, self.viewport.x / self.viewport.y);
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
    pub(super) fn replace_document(&mut self, doc: Document) {
        self.end_hand_contacts();
        self.doc = doc;
        self.tools.cancel();
        self.frame_pending = true;
        self.display_revision = None;
        self.continuity_revision = None;
        if let Some(a) = &mut self.autosave {
            a.mark_saved(self.doc.revision());
        }
    }

    /// Opens a model file into the window, asking first when the document has unsaved
    /// changes.
    pub fn open(&mut self, path: &Path) {
        self.proceed(Pending::Open(path.to_path_buf()));
    }

    /// Opens a model file in place of the document (unsaved changes already dealt with).
    fn open_now(&mut self, path: &Path) {
        match Document::open(path) {
            Ok(doc) => {
                self.forget_autosave(Some(path));
                self.replace_document(doc);
                self.set_status(format!("opened {}", path.display()), false);
            }
            Err(e) => self.set_status(format!("cannot open {}: {e}", path.display()), true),
        }
    }

    /// Ends the contacts of the hands (the live one and the mouse hand) before anything else
    /// edits the surface, as the hand loop requires.
    pub(super) fn end_hand_contacts(&mut self) {
        self.live.end_contact(&mut self.doc);
        if let Some(h) = &mut self.hand {
            h.end_contact(&mut self.doc);
        }
    }

    /// True while a gesture is in progress (a tool's or the mouse hand's).
    fn gesture_busy(&self) -> bool {
        self.tools.busy() || self.hand.as_ref().is_some_and(MouseHandTool::is_pressed)
    }

    /// Makes the mouse hand for the current finger radius and click depth (a new one when the
    /// radius changed and no button holds it); false, with a status message, when the hand
    /// refuses the settings.
    fn ensure_mouse_hand(&mut self) -> bool {
        let radius = self.settings.radius;
        let stale = self
            .hand
            .as_ref()
            .is_none_or(|h| !h.is_pressed() && h.radius() != radius);
        if stale {
            self.end_hand_contacts();
            match MouseHandTool::with_profile(self.hand_profile, radius, self.settings.depth) {
                Ok(h) => self.hand = Some(h),
                Err(e) => {
                    self.hand = None;
                    self.set_status(format!("the mouse hand: {e}"), true);
                    return false;
                }
            }
        }
        match &mut self.hand {
            Some(h) => {
                if !h.is_pressed() {
                    h.set_click_depth(self.settings.depth);
                }
                true
            }
            None => false,
        }
    }

    /// Feeds the mouse hand the view ray through `pixel` with the left button as held: the
    /// hand loop deforms the document (one undoable edit per contact). With no button held the
    /// fingertip hovers one finger radius in front of the surface under the cursor.
    fn drive_hand(&mut self, pixel: Vec2) {
        let ray = self.camera.ray(pixel, self.viewport);
        self.feed_hand(ray);
    }

    fn feed_hand(&mut self, ray: Ray) {
        self.hand_ray = Some(ray);
        if !self.ensure_mouse_hand() {
            return;
        }
        let left = self.buttons[0];
        let hover = self.tools.hover_hit().map_or_else(
            || f64::from(self.camera.distance),
            |hit| (hit.t - self.settings.radius).max(0.0),
        );
        let pull = self.hand_pull;
        let Some(hand) = &mut self.hand else { return };
        let result = if left {
            hand.event(&mut self.doc, &ray, !pull, pull)
        } else {
            hand.hover_at(&mut self.doc, &ray, hover)
        };
        if let Err(e) = result {
            self.set_status(format!("the mouse hand: {e}"), true);
        }
    }

    /// The Devices panel's "mouse" profile: the mouse drives the virtual hand through the
    /// Hand tool (there is no device stream to open).
    pub(super) fn use_mouse_hand(&mut self, profile: nendo_devices::profile::MouseProfile) {
        self.end_hand_contacts();
        self.hand_profile = profile;
        self.hand = None;
        self.select_tool(Tool::Hand);
        self.set_status("the mouse drives the hand: Hand tool selected", false);
    }

    /// Selects a tool, ending whatever the previous one was doing.
    pub(super) fn select_tool(&mut self, tool: Tool) {
        if tool != self.tool {
            self.tools.cancel();
            self.end_hand_contacts();
            self.tool = tool;
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
                Edit::BeginCurveEdit(what) => self.doc.begin_edit(what),
                Edit::ReplaceCurve { index, with } => {
                    let curves = self.doc.curves_mut();
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

    /// Applies one sculpting operation, reporting failures on the status line.
    pub(super) fn sculpt(&mut self, op: &Op) {
        if let Err(e) = self.doc.apply(op) {
            self.set_status(format!("operation refused: {e}"), true);
        }
    }

    /// Per-frame work that is not input: replay, live device frames, autosave.
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
        self.live.poll(&mut self.doc);
        if let Some(outcome) = self.export_job.as_ref().and_then(ExportJob::poll) {
            self.export_job = None;
            match outcome {
                Ok(done) => {
                    let warn = done.missed_tolerance();
                    self.set_status(done.message(), warn);
                }
                Err(e) => self.set_status(e, true),
            }
        }
        let revision = self.doc.revision();
        if let Some(a) = &mut self.autosave {
            // Not while a prompt is open: the recovery question is about the file this would
            // overwrite.
            if self.prompt.is_none() && a.tick(self.doc.model(), revision, now) {
                self.owns_autosave = true;
            }
        }
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

    /// Handles pointer input over the 3D view (egui did not consume it).
    pub fn pointer(&mut self, input: PointerInput) {
        if self.prompt.is_some() {
            return;
        }
        let curves_owned: Vec<(usize, Curve<DVec3>)> = self
            .doc
            .curves_3d()
            .into_iter()
            .map(|(i, c)| (i, c.clone()))
            .collect();
        let curves: Vec<(usize, &Curve<DVec3>)> =
            curves_owned.iter().map(|(i, c)| (*i, c)).collect();
        let camera = self.camera;
        let ctx = ToolContext {
            camera: &camera,
            viewport: self.viewport,
            patches: &self.patches,
            mesh: &self.display.mesh,
            curves: &curves,
        };
        match input {
            PointerInput::Moved(p) => {
                let previous = self.cursor.replace(p);
                let delta = previous.map_or(Vec2::ZERO, |q| p - q);
                if self.buttons[1] && !self.shift {
                    self.camera.orbit(delta);
                } else if self.buttons[2] || (self.buttons[1] && self.shift) {
                    self.camera.pan(delta, self.viewport.y);
                } else if self.tool == Tool::Hand {
                    self.tools.hover(Tool::Hand, &ctx, p);
                    self.drive_hand(p);
                } else if self.buttons[0] {
                    let edits = self.tools.drag(&ctx, &self.settings, p);
                    self.apply_edits(edits);
                } else {
                    self.tools.hover(self.tool, &ctx, p);
                }
            }
            PointerInput::Pressed(button, p) => {
                self.cursor = Some(p);
                match button {
                    Button::Left if self.tool == Tool::Hand => {
                        self.tools.hover(Tool::Hand, &ctx, p);
                        self.buttons[0] = true;
                        self.hand_pull = self.shift || self.settings.ridge;
                        self.live.end_contact(&mut self.doc);
                        self.drive_hand(p);
                    }
                    Button::Left => {
                        self.buttons[0] = true;
                        let edits = self.tools.press(self.tool, &ctx, &self.settings, p);
                        self.apply_edits(edits);
                    }
                    Button::Right => self.buttons[1] = true,
                    Button::Middle => self.buttons[2] = true,
                }
            }
            PointerInput::Released(button, p) => match button {
                Button::Left if self.tool == Tool::Hand => {
                    self.buttons[0] = false;
                    self.drive_hand(p);
                    if let Some(h) = &mut self.hand {
                        h.end_contact(&mut self.doc);
                    }
                }
                Button::Left => {
                    self.buttons[0] = false;
                    let edits = self.tools.release(self.tool, &ctx, &self.settings, p);
                    self.apply_edits(edits);
                }
                Button::Right => self.buttons[1] = false,
                Button::Middle => self.buttons[2] = false,
            },
            PointerInput::Wheel(steps) => {
                let hand_pressed = self.tool == Tool::Hand
                    && self.hand.as_ref().is_some_and(MouseHandTool::is_pressed);
                if hand_pressed {
                    if let Some(h) = &mut self.hand {
                        h.wheel(f64::from(steps));
                    }
                    if let Some(ray) = self.hand_ray {
                        self.feed_hand(ray);
                    }
                } else if self.tools.wheel(&ctx, &self.settings, steps) {
                    let edits = self.tools.regrab(&ctx);
                    self.apply_edits(edits);
                } else {
                    self.camera.zoom(steps);
                }
            }
            PointerInput::Left => {
                self.cursor = None;
                if !self.gesture_busy() {
                    self.tools.cancel();
                }
            }
        }
    }

    /// True while a button pressed in the viewport is held (the viewport owns the pointer
    /// until it is released, even over a panel).
    #[must_use]
    pub fn owns_pointer(&self) -> bool {
        self.buttons.iter().any(|b| *b)
    }

    /// Builds what the renderer draws this frame: lines, spheres and the style. The surface
    /// mesh is [`Modeller::surface`], re-uploaded when [`Modeller::surface_generation`] changes.
    pub fn scene(&self, lines: &mut LineBatch, spheres: &mut Vec<SphereInstance>) -> Style {
        lines.clear();
        spheres.clear();
        model_lines(
            self.doc.model(),
            &self.patches,
            &self.display,
            &self.overlays,
            lines,
        );
        let curves_owned: Vec<(usize, Curve<DVec3>)> = self
            .doc
            .curves_3d()
            .into_iter()
            .map(|(i, c)| (i, c.clone()))
            .collect();
        let curves: Vec<(usize, &Curve<DVec3>)> =
            curves_owned.iter().map(|(i, c)| (*i, c)).collect();
        let ctx = ToolContext {
            camera: &self.camera,
            viewport: self.viewport,
            patches: &self.patches,
            mesh: &self.display.mesh,
            curves: &curves,
        };
        self.tools
            .preview(self.tool, &ctx, &self.settings, lines, spheres);
        if self.tool == Tool::Hand
            && let Some(h) = &self.hand
        {
            h.draw(lines, spheres);
        }
        self.live.draw(lines, spheres);
        Style {
            heat_map: self.overlays.heat_map,
            heat_max_deg: self.overlays.heat_max_deg,
            tool: self.tools.footprint(self.tool, &ctx, &self.settings),
            ..Style::default()
        }
    }

    /// The tessellated surface to draw.
    #[must_use]
    pub fn surface(&self) -> &SurfaceDisplay {
        &self.display
    }

    /// Changes whenever [`Modeller::surface`] does (also across documents).
    #[must_use]
    pub fn surface_generation(&self) -> u64 {
        self.display_generation
    }

    /// The camera.
    #[must_use]
    pub fn camera(&self) -> &OrbitCamera {
        &self.camera
    }

    /// Starts a new document from the primitive form, asking first when the document has
    /// unsaved changes.
    pub(super) fn new_from_form(&mut self) {
        self.proceed(Pending::Create(self.form));
    }

    /// Starts a new document from `form` (unsaved changes already dealt with). The fresh
    /// primitive holds no work of the user's yet: it is clean, like the starting plane.
    fn create_from(&mut self, form: PrimitiveForm) {
        match form.primitive.build(&form.params()) {
            Ok(grid) => {
                let mut model = Model::new(grid);
                model.regulation = self.doc.model().regulation;
                self.forget_autosave(None);
                self.replace_document(Document::new(model));
                self.set_status(format!("new {}", form.primitive.name()), false);
            }
            Err(e) => self.set_status(format!("cannot build the primitive: {e}"), true),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane_doc() -> Document {
        Document::new(Model::new(
            Primitive::Plane
                .build(&PrimitiveParams::default())
                .expect("plane"),
        ))
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
        assert_eq!(m.document().revision(), 1);
        assert_eq!(m.document().history().undo_name(), Some("push"));
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
        assert_eq!(m.prompt, Some(Prompt::Recover(autosave.clone())));
        m.recover(&autosave);
        assert_eq!(m.document().model(), &work);
        assert!(m.document().is_dirty(), "recovered work is unsaved");
        assert!(m.title().ends_with('*'));
        m.request_close();
        assert!(!m.wants_to_quit(), "closing asks first");
        assert_eq!(m.prompt, Some(Prompt::Unsaved(Pending::Close)));
        m.answer_unsaved(Pending::Close, UnsavedAnswer::Cancel);
        assert!(!m.wants_to_quit() && m.prompt.is_none());
        // An exit that nobody confirmed (the window going away) keeps the autosave.
        m.on_exit();
        assert!(autosave.is_file(), "unsaved work keeps its autosave");
        // Saving makes the document clean; then closing quits and drops the autosave.
        let saved = autosave.with_file_name("kept.nendo.json");
        assert!(m.save_to(&saved));
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
        m.recover(&autosave);
        m.request_close();
        m.answer_unsaved(Pending::Close, UnsavedAnswer::Discard);
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

        m.form = PrimitiveForm::defaults_for(Primitive::Sphere);
        m.new_from_form();
        assert_eq!(m.document().model(), &work, "nothing replaced yet");
        assert_eq!(
            m.prompt,
            Some(Prompt::Unsaved(Pending::Create(m.form))),
            "Create asks"
        );
        m.tick(t0 + Autosave::INTERVAL * 3);
        assert_eq!(
            Model::read(&autosave).expect("autosave").model,
            work,
            "the earlier work's autosave stays while the question is open"
        );
        m.answer_unsaved(Pending::Create(m.form), UnsavedAnswer::Cancel);
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
        let Some(Prompt::Unsaved(action)) = m.prompt.clone() else {
            panic!("{:?}", m.prompt)
        };
        let kept = autosave.with_file_name("work.nendo.json");
        m.doc.path = Some(kept.clone());
        m.answer_unsaved(action, UnsavedAnswer::Save);
        assert_eq!(Model::read(&kept).expect("saved").model, work);
        assert_eq!(m.document().path.as_deref(), Some(other.as_path()));
        assert!(!m.document().is_dirty());

        // Opening the autosave file itself by name keeps it (it is the opened document).
        work.write(&autosave).expect("an autosave");
        m.answer_unsaved(Pending::Open(autosave.clone()), UnsavedAnswer::Discard);
        assert_eq!(m.document().path.as_deref(), Some(autosave.as_path()));
        assert!(autosave.is_file(), "the opened file is not removed");

        // With nothing unsaved, Create goes ahead without asking.
        m.new_from_form();
        assert!(m.prompt.is_none());
        assert_eq!(
            m.document().model().surface.topology(),
            Primitive::Sphere.topology()
        );
        let _ = std::fs::remove_dir_all(autosave.parent().expect("dir"));
    }

    /// The Hand tool drives the mouse hand from the pointer: a press in the view pushes the
    /// plane through the document (one undoable "hand" edit), the hand is drawn, and the wheel
    /// while pressed goes deeper.
    #[test]
    fn the_hand_tool_sculpts_through_the_document() {
        let mut m = Modeller::new(plane_doc(), None, false);
        m.set_viewport(Vec2::new(800.0, 600.0));
        m.refresh();
        m.use_mouse_hand(nendo_devices::profile::MouseProfile::default());
        assert_eq!(m.tool, Tool::Hand);
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
        m.undo();
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
}
