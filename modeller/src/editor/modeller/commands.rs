//! The modeller carrying out [`Command`]s: the unsaved-changes questions and the action waiting
//! on them, the files asked of the user, saving, export, undo, what Esc cancels, replacing the
//! document.

use glam::DVec3;
use std::path::{Path, PathBuf};

use crate::curve::json::DynCurve;
use crate::editor::command::{Command, DialogPurpose};
use crate::editor::curve_edit::straight_cubic;
use crate::editor::document::Document;
use crate::editor::export_job::{ExportJob, TOLERANCE_RANGE};
use crate::editor::lifecycle::{Next, Pending, PrimitiveForm, SaveError};
use crate::editor::tools::Tool;
use crate::mesh::Tessellation;
use crate::model::Model;
use crate::model::ops::{OpsFileError, op_to_json, read_ops};
use crate::surface::refine;

use super::*;

impl Modeller {
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
            Command::SetAutoRefine(on) => self.auto_refine = on,
            Command::View(preset) => self.view_from(preset),
            Command::FrameAll => self.frame_all(),
            Command::ToggleHelp => self.help = !self.help,
            Command::ToggleSymmetry => self.set_symmetry(!self.mirror.wanted()),
            Command::SetSymmetrySpec(spec) => self.set_symmetry_spec(spec),
            Command::ToggleRadial => {
                // Off → radial N → lathe → off.
                let spec = self.mirror.spec();
                let next = if spec.lathe {
                    self.mirror.with_radial(false)
                } else if spec.radial > 1 {
                    let mut lathe = self.mirror.with_radial(false);
                    lathe.lathe = true;
                    lathe
                } else {
                    self.mirror.with_radial(true)
                };
                self.set_symmetry_spec(next);
            }
            Command::ToggleProjection => {
                self.set_projection(self.camera.projection.toggled());
            }
            Command::SetProjection(projection) => self.set_projection(projection),
            Command::CycleSurfaceMode => {
                let mode = self.panel.analysis.mode.next();
                self.panel.analysis.mode = mode;
                self.set_status(format!("display: {mode}"), false);
            }
            Command::AdjustRadius => self.begin_adjust(Adjusted::Radius),
            Command::AdjustDepth => self.begin_adjust(Adjusted::Depth),
            Command::Cancel => self.cancel(),
            Command::StartRecording => self.session.doc.recording = Some(Vec::new()),
            Command::DiscardRecording => self.session.doc.recording = None,
            Command::StopReplay => self.replay = None,
            Command::AnswerUnsaved(answer) => {
                let next = self.session.answer_unsaved(answer);
                self.follow(next);
            }
            Command::AnswerConflict(answer) => {
                let next = self.session.answer_conflict(answer);
                self.follow(next);
            }
            Command::Recover(path) => match self.session.recover(&path) {
                Ok(doc) => {
                    self.replace_document(doc);
                    let left = self.session.left_for_next_start();
                    let more = if left == 0 {
                        String::new()
                    } else {
                        format!(
                            "; {left} more autosave(s) of earlier sessions are kept for the next start"
                        )
                    };
                    self.set_status(
                        format!("recovered the autosave: save it to keep it{more}"),
                        false,
                    );
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
    pub(super) fn request(&mut self, action: Pending) {
        let next = self.session.request(action);
        self.follow(next);
    }

    /// Carries out the lifecycle's next step, and the steps that follow from it.
    pub(super) fn follow(&mut self, next: Next) {
        match next {
            Next::Wait => {}
            Next::Proceed(action) => self.carry_out(action),
            Next::ChooseSavePath => {
                // The lifecycle waits on this very dialog: no `show_dialog` (which would
                // drop a waiting action along with the dialog it replaces).
                self.dialog = Some(self.new_file_request(DialogPurpose::SaveModel));
            }
            Next::Save(path) => self.save_now(&path, false),
            Next::Overwrite(path) => self.save_now(&path, true),
        }
    }

    /// Saves to `path` (over a file changed on disk when `overwrite`), then follows on.
    fn save_now(&mut self, path: &Path, overwrite: bool) {
        let (next, result) = if overwrite {
            self.session.save_overwriting(path)
        } else {
            self.session.save_to(path)
        };
        match result {
            Ok(()) => self.set_status(format!("saved {}", path.display()), false),
            Err(e @ SaveError::ChangedOnDisk { .. }) => {
                self.set_status(format!("not saved: {e}"), true);
            }
            Err(e) => self.set_status(format!("cannot save: {e}"), true),
        }
        self.follow(next);
    }

    /// Closes, creates or opens, the question about unsaved changes answered.
    pub(super) fn carry_out(&mut self, action: Pending) {
        match action {
            // The lifecycle has set `wants_to_quit`.
            Pending::Close => {}
            Pending::Create(form) => self.create_from(form),
            Pending::Open(path) => self.open_now(&path),
        }
    }

    /// Asks for a file the user asked to pick, in place of any other (a save dialog that an
    /// action waited on goes, and the action with it).
    pub(super) fn show_dialog(&mut self, purpose: DialogPurpose) {
        if self.dialog.take().is_some() {
            self.session.save_dialog_closed();
        }
        self.dialog = Some(self.new_file_request(purpose));
    }

    /// A new request for a file for `purpose`: beside the document, or where the Devices
    /// panel's files are.
    pub(super) fn new_file_request(&mut self, purpose: DialogPurpose) -> FileRequest {
        self.requests += 1;
        if purpose == DialogPurpose::ExportMesh {
            self.propose_export_tolerance();
        }
        let (current, default) = match self.live.dialog_start(purpose) {
            Some((current, default)) => (current, default),
            None => (
                self.session.doc.path.clone(),
                match purpose {
                    DialogPurpose::SaveModel | DialogPurpose::OpenModel => "model.nendo.json",
                    DialogPurpose::ExportMesh => {
                        return FileRequest {
                            purpose,
                            current: self.session.doc.path.clone(),
                            default_name: export_name(self.session.doc.path.as_deref()),
                            id: self.requests,
                        };
                    }
                    DialogPurpose::SaveOps | DialogPurpose::ReplayOps => "ops.jsonl",
                    // The Devices panel asks for these itself.
                    DialogPurpose::OpenProfile => "profile.json",
                    DialogPurpose::RecordTrace | DialogPurpose::ReplayTrace => "session.trace",
                },
            ),
        };
        FileRequest {
            purpose,
            current,
            default_name: default.to_string(),
            id: self.requests,
        }
    }

    /// Sets the export tolerance to the model's own ([`Tessellation::export_tolerance_for`],
    /// within the range the window offers) unless the user has set one since it was last
    /// proposed.
    pub(super) fn propose_export_tolerance(&mut self) {
        if self.panel.export_tolerance.to_bits() != self.proposed_tolerance.to_bits() {
            return;
        }
        let proposed = Tessellation::export_tolerance_for(self.cache.patches())
            .clamp(*TOLERANCE_RANGE.start(), *TOLERANCE_RANGE.end());
        self.panel.export_tolerance = proposed;
        self.proposed_tolerance = proposed;
    }

    /// A file dialog picked `path`.
    pub(super) fn dialog_chosen(&mut self, purpose: DialogPurpose, path: PathBuf) {
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
            // Streamed within the limits of `nendo sculpt --ops` (`read_ops`).
            DialogPurpose::ReplayOps => match std::fs::File::open(&path)
                .map_err(OpsFileError::from)
                .and_then(|f| read_ops(std::io::BufReader::with_capacity(1 << 16, f)))
            {
                Ok(ops) => {
                    let ops = ops.into_iter().map(|(op, _)| op).collect();
                    self.replay = Some(Replay { ops, next: 0 });
                }
                Err(e) => self.set_status(format!("{}: {e}", path.display()), true),
            },
        }
    }

    /// Ends the recording and writes it to `path` as JSON lines (kept on failure).
    pub(super) fn save_recording(&mut self, path: &Path) {
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
    pub(super) fn export(&mut self, path: &Path) {
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

    /// Projects the view in perspective or orthographically, the framing at the orbit target
    /// kept (see [`crate::editor::camera`]).
    fn set_projection(&mut self, projection: crate::editor::camera::Projection) {
        if self.camera.projection != projection {
            self.camera.projection = projection;
            self.set_status(format!("view: {}", projection.name()), false);
        }
    }

    pub(super) fn undo(&mut self) {
        self.cancel_stroke();
        self.end_hand_contacts();
        if !self.session.doc.undo() {
            self.set_status("nothing to undo", false);
        }
    }

    pub(super) fn redo(&mut self) {
        self.cancel_stroke();
        self.end_hand_contacts();
        if !self.session.doc.redo() {
            self.set_status("nothing to redo", false);
        }
    }

    /// Adds a straight cubic above the surface and selects the curve grab.
    pub(super) fn add_curve(&mut self) {
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

    /// Starts setting the radius or the depth by moving the mouse (F, Shift+F), unless a
    /// gesture or a question is in progress.
    pub(super) fn begin_adjust(&mut self, what: Adjusted) {
        if self.gesture_busy() || self.session.prompt().is_some() {
            return;
        }
        let start = match what {
            Adjusted::Radius => self.tools.settings.radius,
            Adjusted::Depth => self.tools.settings.depth,
        };
        self.adjust = Some(Adjust {
            what,
            start,
            anchor: self.pointer.cursor,
        });
    }

    /// Esc: cancels the stroke in progress, else the radius or depth being set, else closes
    /// the help, else the file dialog.
    pub(super) fn cancel(&mut self) {
        if self.stroke.is_some() || self.tools.state.busy() {
            self.cancel_stroke();
            self.set_status("stroke cancelled", false);
        } else if let Some(adjust) = self.adjust.take() {
            self.set_adjusted(adjust.what, adjust.start);
        } else if self.help {
            self.help = false;
        } else if self.dialog.is_some() {
            self.apply(Command::DialogCancelled);
        }
    }

    /// Replaces the document (opened file, new primitive, recovery): clears the tool state
    /// and reframes.
    pub(super) fn replace_document(&mut self, doc: Document) {
        self.cancel_stroke();
        self.end_hand_contacts();
        self.mirror.invalidate();
        self.live.forget_symmetry();
        self.session.replace(doc);
        self.frame_pending = true;
        self.cache.invalidate();
    }

    /// Opens a model file in place of the document (unsaved changes already dealt with).
    pub(super) fn open_now(&mut self, path: &Path) {
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
    pub(super) fn create_from(&mut self, form: PrimitiveForm) {
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
}

/// The name the export dialog proposes: the model file's own name with `.obj` for its
/// `.nendo.json` (or `.json`) ending, `model.obj` for a model never saved.
#[must_use]
pub fn export_name(model: Option<&Path>) -> String {
    let stem = model
        .and_then(Path::file_name)
        .map(|n| n.to_string_lossy().into_owned())
        .map(|n| {
            let lower = n.to_ascii_lowercase();
            let cut = [".nendo.json", ".json"]
                .iter()
                .find(|e| lower.ends_with(*e))
                .map_or(n.len(), |e| n.len() - e.len());
            n[..cut].to_string()
        })
        .filter(|s| !s.trim().is_empty());
    format!("{}.obj", stem.as_deref().unwrap_or("model"))
}
