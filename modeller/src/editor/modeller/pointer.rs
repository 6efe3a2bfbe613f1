//! The pointer state machine: the plain pointer events of [`crate::editor::input`] over the 3D
//! view — the buttons, the cursor and the modifiers — routed to the camera, the mouse tools
//! (their live strokes begun, shown, released or cancelled), the Hand tool or a radius / depth
//! being adjusted (F, Shift+F).

use glam::{DVec3, Vec2};

use crate::curve::Curve;
use crate::editor::input::Button;
use crate::editor::stroke::LiveStroke;
use crate::editor::tools::{DEPTH_RANGE, Edit, RADIUS_RANGE, Tool, ToolContext};
use crate::surface::Op;

use super::*;

impl Modeller {
    pub(super) fn set_adjusted(&mut self, what: Adjusted, value: f64) {
        let s = &mut self.tools.settings;
        match what {
            Adjusted::Radius => s.radius = value.clamp(*RADIUS_RANGE.start(), *RADIUS_RANGE.end()),
            Adjusted::Depth => s.depth = value.clamp(*DEPTH_RANGE.start(), *DEPTH_RANGE.end()),
        }
    }

    /// Pointer input while F or Shift+F is in progress: moves set the value, a left click
    /// keeps it, a right or middle click restores it.
    pub(super) fn adjust_pointer(&mut self, input: PointerInput) {
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
                let left = self.pointer.buttons[0];
                let (orbit, pan) = self
                    .panel
                    .orbit
                    .camera_drag(self.pointer.buttons, self.pointer.shift);
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
                                    self.auto_refine,
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
}
