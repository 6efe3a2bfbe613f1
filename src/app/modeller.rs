//! The modeller's state and its frame: the document, camera, tools and panels, independent of
//! winit and of the GPU (the window feeds it input and draws what it builds).

use glam::{DVec3, Vec2};
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::autosave::{Autosave, Recovery};
use super::camera::{OrbitCamera, ViewPreset};
use super::document::Document;
use super::file_dialog::FileDialog;
use super::live::LiveInput;
use super::scene::{Overlays, SurfaceDisplay, curve_control_points, model_lines};
use super::tools::{Edit, Tool, ToolContext, ToolSettings, ToolState};
use crate::curve::Curve;
use crate::curve::json::DynCurve;
use crate::mesh::{PatchPoints, Tessellation};
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
    /// Closing with unsaved changes.
    UnsavedOnClose,
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
    pub(super) prompt: Option<Prompt>,
    pub(super) dialog: Option<FileDialog>,
    pub(super) status: Option<Status>,
    pub(super) continuity: Option<ContinuityReport>,
    continuity_revision: Option<u64>,
    pub(super) continuity_ms: f64,
    pub(super) form: PrimitiveForm,
    pub(super) export_tolerance: f64,
    pub(super) timing: Timing,
    pub(super) replay: Option<Replay>,
    pub(super) live: LiveInput,
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
        let prompt = autosave
            .as_ref()
            .and_then(Autosave::pending_recovery)
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
            prompt,
            dialog: None,
            status: None,
            continuity: None,
            continuity_revision: None,
            continuity_ms: 0.0,
            form: PrimitiveForm::defaults_for(Primitive::Plane),
            export_tolerance: Tessellation::EXPORT.tolerance,
            timing: Timing::default(),
            replay: None,
            live: LiveInput::default(),
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

    /// The window's close button: asks about unsaved changes first.
    pub fn request_close(&mut self) {
        if self.doc.is_dirty() {
            self.prompt = Some(Prompt::UnsavedOnClose);
        } else {
            self.quit = true;
        }
    }

    /// A clean exit: the autosave is no longer needed.
    pub fn on_exit(&mut self) {
        self.live.disconnect_from(&mut self.doc);
        if let Some(a) = &mut self.autosave {
            a.discard();
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

    /// When the window must run a frame even without input (a pending autosave).
    #[must_use]
    pub fn wake_at(&self, now: Instant) -> Option<Instant> {
        self.autosave
            .as_ref()
            .filter(|_| self.prompt.is_none())?
            .due(self.doc.revision(), now)
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
        if self.continuity_revision != Some(revision) && !self.tools.busy() && self.replay.is_none()
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
        let mut points = self.display.mesh.positions.clone();
        for c in &self.doc.model().curves {
            points.extend(curve_control_points(c).into_iter().map(|p| p.as_vec3()));
        }
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
        self.doc = doc;
        self.tools.cancel();
        self.frame_pending = true;
        self.display_revision = None;
        self.continuity_revision = None;
        if let Some(a) = &mut self.autosave {
            a.mark_saved(self.doc.revision());
        }
    }

    /// Opens a model file into the window.
    pub fn open(&mut self, path: &Path) {
        match Document::open(path) {
            Ok(doc) => {
                self.replace_document(doc);
                self.set_status(format!("opened {}", path.display()), false);
            }
            Err(e) => self.set_status(format!("cannot open {}: {e}", path.display()), true),
        }
    }

    /// Applies the tools' edits to the document.
    fn apply_edits(&mut self, edits: Vec<Edit>) {
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
        let revision = self.doc.revision();
        if let Some(a) = &mut self.autosave {
            // Not while a prompt about the old autosave is open: it would be overwritten.
            if self.prompt.is_none() {
                a.tick(self.doc.model(), revision, now);
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
                Button::Left => {
                    self.buttons[0] = false;
                    let edits = self.tools.release(self.tool, &ctx, &self.settings, p);
                    self.apply_edits(edits);
                }
                Button::Right => self.buttons[1] = false,
                Button::Middle => self.buttons[2] = false,
            },
            PointerInput::Wheel(steps) => {
                if self.tools.wheel(&self.settings, steps) {
                    let edits = self.tools.regrab(&ctx);
                    self.apply_edits(edits);
                } else {
                    self.camera.zoom(steps);
                }
            }
            PointerInput::Left => {
                self.cursor = None;
                if !self.tools.busy() {
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

    /// Starts a new document from the primitive form.
    pub(super) fn new_from_form(&mut self) {
        match self.form.primitive.build(&self.form.params()) {
            Ok(grid) => {
                let mut model = Model::new(grid);
                model.regulation = self.doc.model().regulation;
                let mut doc = Document::new(model);
                doc.path = None;
                self.replace_document(doc);
                // The new document is unsaved work: let the autosave write it.
                if let Some(a) = &mut self.autosave {
                    a.mark_saved(u64::MAX);
                }
                self.set_status(format!("new {}", self.form.primitive.name()), false);
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
}
