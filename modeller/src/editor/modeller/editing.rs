//! The modeller's editing policy: the display refreshed from the document, symmetry, live
//! strokes and their report, the hover and the reach, the Hand tool's contacts, the tools'
//! edits applied to the document.

use glam::Vec2;

use crate::curve::json::DynCurve;
use crate::editor::stroke::LiveStroke;
use crate::editor::tools::{Edit, Tool, ToolContext};
use crate::surface::{Op, refine};

use super::*;

impl Modeller {
    /// Brings the cached tessellation, patches and continuity up to the document's revision.
    pub fn refresh(&mut self) {
        self.refresh_with(false);
    }

    /// [`Modeller::refresh`] on a frame's input path, between the latch and the submission
    /// (`editor::live` latency module docs): while a device session is connected, the work
    /// that settles the display once a contact is over — the continuity measure, segment
    /// counts gone stale — is left to [`Modeller::settle`], after the frame is presented, so
    /// that no device sample waits for it; the patches the hand changed are re-tessellated
    /// here as during a contact. Without a session it is [`Modeller::refresh`].
    pub fn refresh_for_frame(&mut self) {
        self.refresh_with(true);
    }

    /// The settling work [`Modeller::refresh_for_frame`] left, once the frame is presented;
    /// its display change (if any) is drawn by the next frame. Nothing without a session.
    pub fn settle(&mut self) {
        if self.live.is_connected() {
            let busy = self.gesture_busy() || self.replay.is_some() || self.live.in_contact();
            self.cache.refresh(&self.session.doc, busy);
        }
    }

    fn refresh_with(&mut self, defer_settling: bool) {
        self.update_stroke();
        self.poll_devices();
        let busy = self.gesture_busy()
            || self.replay.is_some()
            || self.live.in_contact()
            || (defer_settling && self.live.is_connected());
        self.cache.refresh(&self.session.doc, busy);
        self.live
            .latency_mut()
            .display_refreshed(std::time::Instant::now());
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
    pub(super) fn update_mirror(&mut self) {
        if self.stroke.is_none() && !self.gesture_busy() {
            let doc = &self.session.doc;
            self.mirror.update(doc.revision(), &doc.model().surface);
        }
    }

    /// Tells the device loop the symmetry the window asks for (before it polls and before the
    /// Devices panel can Connect): a device session that follows the window takes it up between
    /// contacts, a recording starts with it (`editor::live` `symmetry` module docs).
    pub(super) fn sync_window_symmetry(&mut self) {
        let wanted = self.mirror.wanted().then(|| self.mirror.spec().clone());
        self.live.set_window_symmetry(wanted);
    }

    /// The mirror a stroke begun now uses (`None`: symmetry off or not offered).
    pub(super) fn active_mirror(&mut self) -> Option<crate::surface::Symmetry> {
        let doc = &self.session.doc;
        self.mirror.update(doc.revision(), &doc.model().surface);
        self.mirror.active(&doc.model().surface).cloned()
    }

    /// Turns symmetry on or off; says why when the model does not allow it.
    pub(super) fn set_symmetry(&mut self, on: bool) {
        let doc = &self.session.doc;
        self.mirror.update(doc.revision(), &doc.model().surface);
        if on && let Some(why) = self.mirror.why_not() {
            self.set_status(why, true);
            return;
        }
        self.mirror.set_wanted(on);
        let text = if on {
            format!("symmetry on: {}", self.mirror.spec())
        } else {
            "symmetry off".to_string()
        };
        self.set_symmetry_status(text);
    }

    /// Asks for another symmetry (mirrors, radial, lathe) and turns symmetry on with it; when
    /// the model does not have it, says why and keeps the one before.
    pub(super) fn set_symmetry_spec(&mut self, spec: crate::surface::SymmetrySpec) {
        let before = self.mirror.spec().clone();
        // A lathe on a model sculpted with radial symmetry turns by its `N`.
        let spec = crate::editor::symmetry::lathe_for(
            &self.session.doc.model().surface,
            spec,
            self.mirror.radial_n(),
        );
        self.mirror.set_spec(spec);
        let doc = &self.session.doc;
        self.mirror.update(doc.revision(), &doc.model().surface);
        if let Some(why) = self.mirror.why_not() {
            self.mirror.set_spec(before);
            self.update_mirror();
            self.set_status(why, true);
            return;
        }
        self.mirror.set_wanted(true);
        self.set_symmetry_status(format!("symmetry on: {}", self.mirror.spec()));
    }

    /// The status line after a symmetry change: the change, and, while a device session's group
    /// is fixed (a recording, a replayed trace), that the session keeps its own.
    fn set_symmetry_status(&mut self, text: String) {
        let text = match self.live.symmetry_note() {
            Some(note) => format!("{text}; {note}"),
            None => text,
        };
        self.set_status(text, false);
    }

    /// Applies the model's regulation to the whole surface as one undoable edit.
    pub(super) fn regulate_now(&mut self) {
        self.cancel_stroke();
        self.end_hand_contacts();
        let model = self.session.doc.model();
        let regulation = model.regulation;
        let mut regulated = model.clone();
        let worked =
            match crate::surface::regulate::regulate_all(&mut regulated.surface, regulation) {
                Ok(worked) => worked,
                Err(e) => {
                    self.set_status(
                        format!("regulate now ({regulation}): {e}; nothing changed"),
                        true,
                    );
                    return;
                }
            };
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
    pub(super) fn update_stroke(&mut self) {
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
    pub(super) fn report_stroke(&mut self) {
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
    pub(super) fn update_hover(&mut self) {
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
    pub(super) fn update_reach(&mut self) {
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
    pub(super) fn cancel_stroke(&mut self) {
        self.tools.state.cancel();
        if let Some(stroke) = self.stroke.take() {
            stroke.cancel(&mut self.session.doc);
        }
        self.stroke_dirty = false;
        self.hover_view = None;
    }

    /// Ends the contacts of the hands (the live one and the mouse hand) before anything else
    /// edits the surface, as the hand loop requires.
    pub(super) fn end_hand_contacts(&mut self) {
        self.live.end_contact(&mut self.session.doc);
        self.hand.end_contact(&mut self.session.doc);
    }

    /// True while a gesture is in progress (a tool's or the mouse hand's).
    pub(super) fn gesture_busy(&self) -> bool {
        self.tools.state.busy() || self.hand.is_pressed()
    }

    /// Feeds the mouse hand the view ray through `pixel` with the left button as held: the
    /// hand loop deforms the document (one undoable edit per contact). With no button held the
    /// fingertip hovers one finger radius in front of the surface under the cursor.
    pub(super) fn drive_hand(&mut self, pixel: Vec2) {
        let ray = self.camera.ray(pixel, self.pointer.viewport);
        self.feed_hand(ray);
    }

    pub(super) fn feed_hand(&mut self, ray: crate::mesh::Ray) {
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
            || self.camera.ray_parameter(self.camera.target.as_dvec3()),
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
    pub(super) fn select_tool(&mut self, tool: Tool) {
        if tool != self.tools.active {
            self.cancel_stroke();
            self.end_hand_contacts();
            // Each sculpting tool keeps its own brush (curve tools leave the panel as it is).
            self.brushes.store(self.tools.active, &self.tools.settings);
            self.brushes.restore(tool, &mut self.tools.settings);
            self.tools.active = tool;
        }
    }

    /// Applies the tools' edits to the document.
    pub(super) fn apply_edits(&mut self, edits: Vec<Edit>) {
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
    pub(super) fn sculpt(&mut self, op: &Op) {
        if let Some(mirror) = self.active_mirror() {
            let mut stroke = LiveStroke::begin(
                &self.session.doc,
                &[],
                &crate::mesh::TriMesh::default(),
                self.auto_refine,
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
        if self.auto_refine {
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
}
