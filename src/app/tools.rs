//! The mouse tools: what a left-button gesture in the viewport does.
//!
//! | tool | gesture |
//! |---|---|
//! | push / pull | press on the surface; drag to set the depth (the drag length at the surface's distance), or click for the panel's depth; the wheel adds depth while pressed; the surface follows live (see [`super::stroke`]); release keeps it (one undo step), Esc or a right click cancels; Ctrl inverts |
//! | draw a line | press on the surface and drag along it: the groove grows behind the cursor, its path resampled at even spacing (a fifth of the finger radius, measured along the surface); release keeps it, Esc or a right click cancels; Ctrl draws a ridge (or a groove with "ridges" on) |
//! | grab curve | press near a curve (ray closest point) and drag: the grabbed point follows the cursor at its depth; the wheel moves it nearer / farther; the probe sphere shows the reach |
//! | split curve | click on a curve: it splits there |
//! | tangent | drag a control point next to a joint of two curves: the other side follows, collinear |
//! | move | press on the surface and drag: the grabbed surface point follows the cursor on the plane through it facing the camera (the wheel moves that plane nearer / farther), the clay within the finger radius following ([`Op::Move`]); release keeps it, Esc or a right click cancels |
//! | smooth | press and drag over the surface: smoothing dabs ([`Op::Smooth`], the panel's strength) at even spacing along the path, each on the surface the previous ones left; Shift held while pressing with Push, Pull or Draw a line smooths too |
//! | hand | the mouse as the virtual hand ([`super::hand_input::MouseHandTool`], driven by the modeller): press pushes, drag draws a groove, with Shift (or "ridges") it grips and pulls; the wheel while pressed goes deeper |
//!
//! Tools read the surface, the curves and the camera through a [`ToolContext`] and answer with
//! [`Edit`]s for the document; they draw their previews into the scene.

use glam::{DVec3, Vec2};

use super::camera::OrbitCamera;
use super::curve_edit::{Joint, joint_points, joints, tangent_edit};
use crate::curve::Curve;
use crate::curve::edit::{Grab, GrabOptions, split};
use crate::mesh::{PatchPoints, Ray, SurfaceHit, TriMesh, pick};
use crate::render::{LineBatch, Rgba, SphereInstance, ToolFootprint};
use crate::surface::{Dirs, Op};

/// The tools.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Tool {
    /// Press a dent.
    Push,
    /// Pull a bump.
    Pull,
    /// Draw a groove (or a ridge) along a stroke.
    DrawLine,
    /// Grab a curve anywhere and move it.
    GrabCurve,
    /// Split a curve where clicked.
    SplitCurve,
    /// Edit the tangent at a joint of two curves.
    Tangent,
    /// Grab the clay and move it (Blender's Grab, G).
    Move,
    /// Smooth the clay along a stroke.
    Smooth,
    /// The mouse as the virtual hand: the view ray is the finger (the modeller drives a
    /// [`super::hand_input::MouseHandTool`]; the gestures here ignore it).
    Hand,
}

impl Tool {
    /// Every tool, in panel order.
    pub const ALL: [Tool; 9] = [
        Tool::Push,
        Tool::Pull,
        Tool::DrawLine,
        Tool::Move,
        Tool::Smooth,
        Tool::GrabCurve,
        Tool::SplitCurve,
        Tool::Tangent,
        Tool::Hand,
    ];

    /// The tool's name in the panel.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Tool::Push => "Push",
            Tool::Pull => "Pull",
            Tool::DrawLine => "Draw a line",
            Tool::GrabCurve => "Grab curve",
            Tool::SplitCurve => "Split curve",
            Tool::Tangent => "Tangent",
            Tool::Move => "Move",
            Tool::Smooth => "Smooth",
            Tool::Hand => "Hand (the mouse as the hand)",
        }
    }

    /// True for the tools that sculpt the surface.
    #[must_use]
    pub fn sculpts(self) -> bool {
        matches!(
            self,
            Tool::Push | Tool::Pull | Tool::DrawLine | Tool::Move | Tool::Smooth | Tool::Hand
        )
    }

    /// True for the tools whose stroke deforms the surface live ([`super::stroke`]).
    #[must_use]
    pub fn strokes(self) -> bool {
        self.sculpts() && self != Tool::Hand
    }
}

/// The finger radius the panel and F allow (side).
pub const RADIUS_RANGE: std::ops::RangeInclusive<f64> = 0.05..=6.0;
/// The depth the panel and Shift+F allow (side).
pub const DEPTH_RANGE: std::ops::RangeInclusive<f64> = 0.01..=3.0;
/// The smoothing strength the panel allows (`0 < s ≤ 1`, [`Op::Smooth`]).
pub const STRENGTH_RANGE: std::ops::RangeInclusive<f64> = 0.01..=1.0;

/// The finger and probe sizes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToolSettings {
    /// Finger radius `r_f` (side).
    pub radius: f64,
    /// Depth of a click (push / pull) and of a stroke (side).
    pub depth: f64,
    /// Draw ridges instead of grooves.
    pub ridge: bool,
    /// Strength of each smoothing dab, `0 < s ≤ 1`.
    pub strength: f64,
    /// Radius of the probe sphere (side).
    pub probe_radius: f64,
    /// Which control points a curve grab moves.
    pub grab: GrabOptions,
}

impl Default for ToolSettings {
    fn default() -> Self {
        // The paper's deviation experiment uses r_f = 1.25 side.
        Self {
            radius: 1.25,
            depth: 0.3,
            ridge: false,
            strength: 0.5,
            probe_radius: 0.35,
            grab: GrabOptions::default(),
        }
    }
}

/// What the document should do.
#[derive(Debug, Clone, PartialEq)]
pub enum Edit {
    /// Apply a sculpting operation.
    Sculpt(Op),
    /// Record the model for undo before the curve edits that follow.
    BeginCurveEdit(&'static str),
    /// Replace the model's curve `index` by `with` (two curves: a split).
    ReplaceCurve {
        /// Index in the model's curves.
        index: usize,
        /// The new curve(s).
        with: Vec<Curve<DVec3>>,
    },
}

/// What the tools may look at.
#[derive(Debug, Clone, Copy)]
pub struct ToolContext<'a> {
    /// The camera.
    pub camera: &'a OrbitCamera,
    /// Viewport size in pixels.
    pub viewport: Vec2,
    /// The surface's patches.
    pub patches: &'a [PatchPoints],
    /// Their tessellation (for picking).
    pub mesh: &'a TriMesh,
    /// The model's 3D curves with their indices in the model.
    pub curves: &'a [(usize, &'a Curve<DVec3>)],
}

impl ToolContext<'_> {
    fn ray(&self, pixel: Vec2) -> Ray {
        self.camera.ray(pixel, self.viewport)
    }

    fn pick_surface(&self, pixel: Vec2) -> Option<SurfaceHit> {
        pick(self.patches, self.mesh, &self.ray(pixel))
    }

    /// World units per pixel at distance `t` from the eye.
    fn units_per_pixel_at(&self, t: f64) -> f64 {
        2.0 * t * f64::from((0.5 * self.camera.fov_y).tan()) / f64::from(self.viewport.y.max(1.0))
    }

    /// The nearest curve to the ray through `pixel`, within `PICK_PIXELS` on screen:
    /// `(position in `curves`, u, point, ray parameter)`.
    fn pick_curve(&self, pixel: Vec2) -> Option<(usize, f64, DVec3, f64)> {
        let ray = self.ray(pixel);
        let mut best: Option<(f64, (usize, f64, DVec3, f64))> = None;
        for (slot, (_, curve)) in self.curves.iter().enumerate() {
            let Some(near) = curve.ray_closest(ray.origin, ray.direction) else {
                continue;
            };
            let score = near.distance / self.units_per_pixel_at(near.ray_t.max(1e-6));
            if score <= PICK_PIXELS && best.is_none_or(|(s, _)| score < s) {
                best = Some((score, (slot, near.u, near.point, near.ray_t)));
            }
        }
        best.map(|(_, b)| b)
    }

    /// Projects a world point to viewport pixels (`None` behind the camera).
    fn project(&self, p: DVec3) -> Option<Vec2> {
        let view = self.camera.view(self.viewport.x / self.viewport.y.max(1.0));
        let clip = view.clip_from_world * p.as_vec3().extend(1.0);
        (clip.w > 0.0).then(|| {
            let ndc = clip.truncate() / clip.w;
            Vec2::new(
                (ndc.x + 1.0) * 0.5 * self.viewport.x,
                (1.0 - ndc.y) * 0.5 * self.viewport.y,
            )
        })
    }

    /// The joint handle nearest to `pixel` within `PICK_PIXELS`: `(joint, left side)`, with
    /// joints indexed in `curves`.
    fn pick_handle(&self, pixel: Vec2) -> Option<(Joint, bool)> {
        let curves: Vec<Curve<DVec3>> = self.curves.iter().map(|(_, c)| (*c).clone()).collect();
        let mut best: Option<(f32, (Joint, bool))> = None;
        for joint in joints(&curves) {
            let Some((ql, _, qr)) = joint_points(&curves, joint) else {
                continue;
            };
            for (p, left) in [(ql, true), (qr, false)] {
                let Some(s) = self.project(p) else { continue };
                let d = s.distance(pixel);
                if d <= PICK_PIXELS as f32 && best.is_none_or(|(b, _)| d < b) {
                    best = Some((d, (joint, left)));
                }
            }
        }
        best.map(|(_, b)| b)
    }
}

/// How close (in pixels) the cursor must be to a curve or a handle to pick it.
pub const PICK_PIXELS: f64 = 10.0;

/// A drag shorter than this (pixels) is a click.
const CLICK_PIXELS: f32 = 4.0;

/// The gesture in progress.
#[derive(Debug, Clone, PartialEq, Default)]
enum Gesture {
    /// Nothing pressed.
    #[default]
    Idle,
    /// Push or pull: pressed on the surface at `hit`.
    Press {
        hit: SurfaceHit,
        facing: DVec3,
        start: Vec2,
        cursor: Vec2,
        wheel_depth: f64,
    },
    /// Draw a line: the stroke so far, evenly spaced, and how far the surface runs on past
    /// its last point to the last surface point under the cursor.
    Stroke {
        path: Vec<DVec3>,
        facing: DVec3,
        wheel_depth: f64,
        /// The cursor's last pixel and the surface point under it.
        last: (Vec2, DVec3),
        /// Length along the surface from the path's last point to `last.1`.
        carry: f64,
    },
    /// Move: the clay grabbed at `at` (a point of the surface) follows the cursor on the plane
    /// `(x − eye)·forward = depth`, facing the camera as it was at the press.
    Move {
        at: DVec3,
        eye: DVec3,
        forward: DVec3,
        depth: f64,
        start: Vec2,
        cursor: Vec2,
        /// The wheel moved the plane.
        wheeled: bool,
    },
    /// Smooth: the dab points so far, evenly spaced along the surface (as a drawn line's).
    Smooth {
        path: Vec<DVec3>,
        facing: DVec3,
        last: (Vec2, DVec3),
        carry: f64,
    },
    /// A curve grabbed: its index in the model, the grab, the depth along the view ray.
    Grab {
        index: usize,
        grab: Grab<DVec3>,
        ray_t: f64,
        cursor: Vec2,
    },
    /// A joint handle dragged: model indices of the two curves.
    Tangent {
        left_index: usize,
        right_index: usize,
        left_side: bool,
        ray_t: f64,
        pair: [Curve<DVec3>; 2],
    },
}

/// What is under the cursor while nothing is pressed.
#[derive(Debug, Clone, PartialEq, Default)]
struct Hover {
    surface: Option<SurfaceHit>,
    /// `(model index, u, point)` of the curve under the cursor.
    curve: Option<(usize, f64, DVec3)>,
}

/// The active tool and its gesture.
#[derive(Debug, Clone, Default)]
pub struct ToolState {
    gesture: Gesture,
    hover: Hover,
    /// Ctrl held: push pulls, pull pushes, a groove becomes a ridge and back.
    invert: bool,
    /// Shift held: a press with Push, Pull or Draw a line smooths instead (Blender's habit).
    smooth: bool,
}

impl ToolState {
    /// True while a gesture is in progress (the tool then owns the wheel).
    #[must_use]
    pub fn busy(&self) -> bool {
        self.gesture != Gesture::Idle
    }

    /// True while a sculpting stroke (push, pull, draw a line, move, smooth) is in progress.
    #[must_use]
    pub fn stroking(&self) -> bool {
        matches!(
            self.gesture,
            Gesture::Press { .. }
                | Gesture::Stroke { .. }
                | Gesture::Move { .. }
                | Gesture::Smooth { .. }
        )
    }

    /// True while a smoothing stroke is in progress: its operations are dabs applied one
    /// after another ([`ToolState::stroke_dabs`]), not one operation redone from the start.
    #[must_use]
    pub fn smoothing(&self) -> bool {
        matches!(self.gesture, Gesture::Smooth { .. })
    }

    /// Shift held or not: a press with Push, Pull or Draw a line smooths instead (read live;
    /// it counts when the button goes down).
    pub fn set_smooth(&mut self, smooth: bool) {
        self.smooth = smooth;
    }

    /// The tool a press with `tool` acts as now: Smooth for Push, Pull or Draw a line with
    /// Shift held.
    #[must_use]
    pub fn acting_tool(&self, tool: Tool) -> Tool {
        match tool {
            Tool::Push | Tool::Pull | Tool::DrawLine if self.smooth => Tool::Smooth,
            t => t,
        }
    }

    /// Ctrl held or not: inverts push / pull and groove / ridge (read live, every frame).
    pub fn set_invert(&mut self, invert: bool) {
        self.invert = invert;
    }

    /// The sign of the depth for `tool`: +1 into the surface (push, groove), −1 out of it.
    fn sign(&self, tool: Tool, settings: &ToolSettings) -> f64 {
        let out = match tool {
            Tool::Pull => true,
            Tool::DrawLine => settings.ridge,
            _ => false,
        };
        if out != self.invert { -1.0 } else { 1.0 }
    }

    /// The depth the stroke in progress presses now (not signed), if a stroke is in progress.
    #[must_use]
    pub fn stroke_depth(&self, ctx: &ToolContext<'_>, settings: &ToolSettings) -> Option<f64> {
        match &self.gesture {
            Gesture::Press {
                hit,
                start,
                cursor,
                wheel_depth,
                ..
            } => Some((press_depth(ctx, settings, hit, *start, *cursor) + wheel_depth).max(0.0)),
            Gesture::Stroke { wheel_depth, .. } => Some((settings.depth + wheel_depth).max(0.0)),
            _ => None,
        }
    }

    /// The operation the stroke in progress describes now (`None`: none yet, or pressed back
    /// to nothing). The window shows it live; release applies the same.
    #[must_use]
    pub fn stroke_op(
        &self,
        tool: Tool,
        ctx: &ToolContext<'_>,
        settings: &ToolSettings,
    ) -> Option<Op> {
        if let Gesture::Move {
            at,
            eye,
            forward,
            depth,
            start,
            cursor,
            wheeled,
        } = &self.gesture
        {
            // Not moved yet: nothing to show (and a click is no edit).
            if cursor == start && !wheeled {
                return None;
            }
            let to = plane_point(ctx, *eye, *forward, *depth, *cursor)?;
            return Some(Op::Move {
                at: *at,
                to,
                radius: settings.radius,
            });
        }
        let depth = self.stroke_depth(ctx, settings)?;
        // The wheel can take a stroke back to nothing, never past it (a push never turns
        // into a pull).
        if depth <= 0.0 {
            return None;
        }
        let sign = self.sign(tool, settings);
        match &self.gesture {
            Gesture::Press { hit, facing, .. } => Some(Op::Push {
                at: hit.point,
                dir: -*facing,
                depth: sign * depth,
                radius: settings.radius,
            }),
            // Each path point presses along the surface's inward normal at the point nearest
            // to it (outward for a ridge): the groove follows the clay (issue 12).
            Gesture::Stroke { path, .. } if path.len() >= 2 => Some(Op::Groove {
                path: path.clone(),
                dirs: Dirs::Normal,
                depth: sign * depth,
                radius: settings.radius,
            }),
            _ => None,
        }
    }

    /// The smoothing dabs of the stroke in progress, in order (`None`: no smoothing stroke).
    /// The list only grows while the stroke goes on; each dab applies to the surface the
    /// previous ones left.
    #[must_use]
    pub fn stroke_dabs(&self, settings: &ToolSettings) -> Option<Vec<Op>> {
        match &self.gesture {
            Gesture::Smooth { path, .. } => Some(
                path.iter()
                    .map(|&at| Op::Smooth {
                        at,
                        radius: settings.radius,
                        strength: settings.strength,
                    })
                    .collect(),
            ),
            _ => None,
        }
    }

    /// The operation a click at the hover would make (push, pull, or for Draw a line the
    /// push of its depth; a smoothing dab for Smooth and Move, whose reach is the same ball):
    /// what the window outlines as the finger's reach.
    #[must_use]
    pub fn hover_op(
        &self,
        tool: Tool,
        ctx: &ToolContext<'_>,
        settings: &ToolSettings,
    ) -> Option<Op> {
        if !tool.strokes() || self.busy() {
            return None;
        }
        let hit = self.hover.surface?;
        if matches!(self.acting_tool(tool), Tool::Move | Tool::Smooth) {
            return Some(Op::Smooth {
                at: hit.point,
                radius: settings.radius,
                strength: settings.strength,
            });
        }
        Some(Op::Push {
            at: hit.point,
            dir: -facing_normal(&hit, ctx),
            depth: self.sign(tool, settings) * settings.depth,
            radius: settings.radius,
        })
    }

    /// Forgets the gesture and the hover (tool change, model change).
    pub fn cancel(&mut self) {
        self.gesture = Gesture::Idle;
        self.hover = Hover::default();
    }

    /// The cursor moved to `pixel` with nothing pressed.
    pub fn hover(&mut self, tool: Tool, ctx: &ToolContext<'_>, pixel: Vec2) {
        self.hover = Hover::default();
        if tool.sculpts() {
            self.hover.surface = ctx.pick_surface(pixel);
        } else if let Some((slot, u, point, _)) = ctx.pick_curve(pixel) {
            self.hover.curve = Some((ctx.curves[slot].0, u, point));
        }
    }

    /// The left button went down at `pixel`.
    pub fn press(
        &mut self,
        tool: Tool,
        ctx: &ToolContext<'_>,
        settings: &ToolSettings,
        pixel: Vec2,
    ) -> Vec<Edit> {
        self.gesture = Gesture::Idle;
        match self.acting_tool(tool) {
            // The modeller drives the mouse hand itself.
            Tool::Hand => Vec::new(),
            Tool::Move => {
                let Some(hit) = ctx.pick_surface(pixel) else {
                    return Vec::new();
                };
                let eye = ctx.camera.eye().as_dvec3();
                let forward = -ctx.camera.to_eye().as_dvec3();
                self.gesture = Gesture::Move {
                    at: hit.point,
                    eye,
                    forward,
                    depth: (hit.point - eye).dot(forward),
                    start: pixel,
                    cursor: pixel,
                    wheeled: false,
                };
                Vec::new()
            }
            Tool::Smooth => {
                let Some(hit) = ctx.pick_surface(pixel) else {
                    return Vec::new();
                };
                self.gesture = Gesture::Smooth {
                    path: vec![hit.point],
                    facing: facing_normal(&hit, ctx),
                    last: (pixel, hit.point),
                    carry: 0.0,
                };
                Vec::new()
            }
            Tool::Push | Tool::Pull | Tool::DrawLine => {
                let Some(hit) = ctx.pick_surface(pixel) else {
                    return Vec::new();
                };
                let facing = facing_normal(&hit, ctx);
                self.gesture = if tool == Tool::DrawLine {
                    Gesture::Stroke {
                        path: vec![hit.point],
                        facing,
                        wheel_depth: 0.0,
                        last: (pixel, hit.point),
                        carry: 0.0,
                    }
                } else {
                    Gesture::Press {
                        hit,
                        facing,
                        start: pixel,
                        cursor: pixel,
                        wheel_depth: 0.0,
                    }
                };
                Vec::new()
            }
            Tool::GrabCurve => {
                let Some((slot, u, _, ray_t)) = ctx.pick_curve(pixel) else {
                    return Vec::new();
                };
                let (index, curve) = ctx.curves[slot];
                // A grab the options refuse (an end point while the ends are kept) does nothing.
                let Ok(grab) = Grab::new(curve, u, settings.grab) else {
                    return Vec::new();
                };
                self.gesture = Gesture::Grab {
                    index,
                    grab,
                    ray_t,
                    cursor: pixel,
                };
                vec![Edit::BeginCurveEdit("grab curve")]
            }
            Tool::SplitCurve => {
                let Some((slot, u, _, _)) = ctx.pick_curve(pixel) else {
                    return Vec::new();
                };
                let (index, curve) = ctx.curves[slot];
                match split(curve, u) {
                    Ok((a, b)) => vec![
                        Edit::BeginCurveEdit("split curve"),
                        Edit::ReplaceCurve {
                            index,
                            with: vec![a, b],
                        },
                    ],
                    Err(_) => Vec::new(),
                }
            }
            Tool::Tangent => {
                let Some((joint, left_side)) = ctx.pick_handle(pixel) else {
                    return Vec::new();
                };
                let (left_index, left) = ctx.curves[joint.left];
                let (right_index, right) = ctx.curves[joint.right];
                let Some((ql, _, qr)) =
                    joint_points(&[left.clone(), right.clone()], Joint { left: 0, right: 1 })
                else {
                    return Vec::new();
                };
                let handle = if left_side { ql } else { qr };
                let ray_t = (handle - ctx.camera.eye().as_dvec3()).length();
                self.gesture = Gesture::Tangent {
                    left_index,
                    right_index,
                    left_side,
                    ray_t,
                    pair: [left.clone(), right.clone()],
                };
                vec![Edit::BeginCurveEdit("tangent")]
            }
        }
    }

    /// The cursor moved to `pixel` with the left button down.
    pub fn drag(
        &mut self,
        ctx: &ToolContext<'_>,
        settings: &ToolSettings,
        pixel: Vec2,
    ) -> Vec<Edit> {
        match &mut self.gesture {
            Gesture::Idle => Vec::new(),
            Gesture::Press { cursor, .. } => {
                *cursor = pixel;
                Vec::new()
            }
            Gesture::Stroke {
                path, last, carry, ..
            }
            | Gesture::Smooth {
                path, last, carry, ..
            } => {
                extend_evenly(ctx, stroke_spacing(settings), path, last, carry, pixel);
                Vec::new()
            }
            Gesture::Move { cursor, .. } => {
                *cursor = pixel;
                Vec::new()
            }
            Gesture::Grab {
                index,
                grab,
                ray_t,
                cursor,
            } => {
                *cursor = pixel;
                let target = ctx.ray(pixel).at(*ray_t);
                match grab.moved_to(target) {
                    Ok(curve) => vec![Edit::ReplaceCurve {
                        index: *index,
                        with: vec![curve],
                    }],
                    Err(_) => Vec::new(),
                }
            }
            Gesture::Tangent {
                left_index,
                right_index,
                left_side,
                ray_t,
                pair,
            } => {
                let target = ctx.ray(pixel).at(*ray_t);
                match tangent_edit(pair, Joint { left: 0, right: 1 }, *left_side, target) {
                    Ok((l, r)) => {
                        *pair = [l.clone(), r.clone()];
                        vec![
                            Edit::ReplaceCurve {
                                index: *left_index,
                                with: vec![l],
                            },
                            Edit::ReplaceCurve {
                                index: *right_index,
                                with: vec![r],
                            },
                        ]
                    }
                    Err(_) => Vec::new(),
                }
            }
        }
    }

    /// The left button went up at `pixel`.
    pub fn release(
        &mut self,
        tool: Tool,
        ctx: &ToolContext<'_>,
        settings: &ToolSettings,
        pixel: Vec2,
    ) -> Vec<Edit> {
        if self.stroking() {
            // The release point counts as the last move.
            let _ = self.drag(ctx, settings, pixel);
        }
        let edits = match self.stroke_dabs(settings) {
            Some(dabs) => dabs.into_iter().map(Edit::Sculpt).collect(),
            None => self
                .stroke_op(tool, ctx, settings)
                .map(Edit::Sculpt)
                .into_iter()
                .collect(),
        };
        self.gesture = Gesture::Idle;
        self.hover(tool, ctx, pixel);
        edits
    }

    /// Wheel notches (positive: away from the user) during a gesture; false when no gesture
    /// takes the wheel (the camera zooms then). The wheel adds depth to a press or a stroke,
    /// or takes it away down to nothing: never past the depth the drag (or the click, or the
    /// panel for a stroke) gives, so a push never becomes a pull.
    pub fn wheel(&mut self, ctx: &ToolContext<'_>, settings: &ToolSettings, steps: f32) -> bool {
        let step = 0.05 * settings.radius * f64::from(steps);
        match &mut self.gesture {
            Gesture::Press {
                hit,
                start,
                cursor,
                wheel_depth,
                ..
            } => {
                let base = press_depth(ctx, settings, hit, *start, *cursor);
                *wheel_depth = (*wheel_depth + step).max(-base);
                true
            }
            Gesture::Stroke { wheel_depth, .. } => {
                *wheel_depth = (*wheel_depth + step).max(-settings.depth);
                true
            }
            Gesture::Grab { ray_t, .. } | Gesture::Tangent { ray_t, .. } => {
                *ray_t *= (-0.04 * f64::from(steps)).exp();
                true
            }
            Gesture::Move { depth, wheeled, .. } => {
                *depth *= (-0.04 * f64::from(steps)).exp();
                *wheeled = true;
                true
            }
            // The wheel does nothing during a smoothing stroke (and does not zoom).
            Gesture::Smooth { .. } => true,
            Gesture::Idle => false,
        }
    }

    /// The surface under the cursor, as the last hover found it (sculpting tools).
    #[must_use]
    pub fn hover_hit(&self) -> Option<SurfaceHit> {
        self.hover.surface
    }

    /// For a grab in progress, the edit that moves the curve after a wheel step.
    pub fn regrab(&mut self, ctx: &ToolContext<'_>) -> Vec<Edit> {
        match &self.gesture {
            Gesture::Grab { cursor, .. } => {
                let cursor = *cursor;
                self.drag(ctx, &ToolSettings::default(), cursor)
            }
            _ => Vec::new(),
        }
    }

    /// The footprint to draw on the surface, if the tool shows one now.
    #[must_use]
    pub fn footprint(
        &self,
        tool: Tool,
        ctx: &ToolContext<'_>,
        settings: &ToolSettings,
    ) -> Option<ToolFootprint> {
        let (point, facing) = match &self.gesture {
            Gesture::Press { hit, facing, .. } => (hit.point, *facing),
            Gesture::Stroke { path, facing, .. } | Gesture::Smooth { path, facing, .. } => {
                (*path.last()?, *facing)
            }
            Gesture::Move {
                at,
                eye,
                forward,
                depth,
                cursor,
                ..
            } => (
                plane_point(ctx, *eye, *forward, *depth, *cursor).unwrap_or(*at),
                -*forward,
            ),
            Gesture::Idle if tool.sculpts() => {
                let hit = self.hover.surface?;
                (hit.point, facing_normal(&hit, ctx))
            }
            _ => return None,
        };
        Some(ToolFootprint {
            center: point.as_vec3(),
            axis: facing.as_vec3(),
            radius: settings.radius as f32,
        })
    }

    /// Adds the gesture's preview: the finger's travel, the stroke, the probe sphere, handles.
    pub fn preview(
        &self,
        tool: Tool,
        ctx: &ToolContext<'_>,
        settings: &ToolSettings,
        lines: &mut LineBatch,
        spheres: &mut Vec<SphereInstance>,
    ) {
        let marker = |p: DVec3, r: f64, colour: [f32; 4]| SphereInstance {
            center: p.as_vec3().to_array(),
            radius: r as f32,
            colour,
        };
        match &self.gesture {
            Gesture::Press {
                hit,
                facing,
                start,
                cursor,
                wheel_depth,
            } => {
                let depth =
                    (press_depth(ctx, settings, hit, *start, *cursor) + wheel_depth).max(0.0);
                let sign = self.sign(tool, settings);
                let tip = hit.point - *facing * (sign * depth);
                // A push goes into the surface, where the clay would hide it: the finger's
                // travel is drawn on top.
                lines.segment_on_top(hit.point.as_vec3(), tip.as_vec3(), Rgba::HIGHLIGHT);
                spheres.push(marker(tip, 0.06 * settings.radius, [0.95, 0.3, 0.1, 1.0]));
            }
            Gesture::Stroke { path, .. } | Gesture::Smooth { path, .. } => {
                lines.polyline(path.iter().map(|p| p.as_vec3()), Rgba::HIGHLIGHT);
            }
            Gesture::Move {
                at,
                eye,
                forward,
                depth,
                cursor,
                ..
            } => {
                // Where the grabbed point was and where it goes, drawn on top of the clay.
                let to = plane_point(ctx, *eye, *forward, *depth, *cursor).unwrap_or(*at);
                lines.segment_on_top(at.as_vec3(), to.as_vec3(), Rgba::HIGHLIGHT);
                spheres.push(marker(to, 0.06 * settings.radius, [0.95, 0.3, 0.1, 1.0]));
            }
            Gesture::Grab { ray_t, cursor, .. } => {
                let at = ctx.ray(*cursor).at(*ray_t);
                spheres.push(marker(at, settings.probe_radius, [0.35, 0.6, 1.0, 0.3]));
            }
            Gesture::Tangent { pair, .. } => {
                if let Some((ql, q, qr)) = joint_points(pair, Joint { left: 0, right: 1 }) {
                    lines.polyline([ql, q, qr].map(|p| p.as_vec3()), Rgba::HIGHLIGHT);
                }
            }
            Gesture::Idle => {
                if let Some((index, _, point)) = self.hover.curve {
                    if matches!(tool, Tool::GrabCurve) {
                        spheres.push(marker(point, settings.probe_radius, [0.35, 0.6, 1.0, 0.3]));
                        // The parts of the curve inside the probe sphere.
                        if let Some((_, curve)) = ctx.curves.iter().find(|(i, _)| *i == index) {
                            for (a, b) in curve.sphere_intervals(point, settings.probe_radius) {
                                let samples = (0..=16)
                                    .map(|k| curve.eval(a + (b - a) * k as f64 / 16.0).as_vec3());
                                lines.polyline(samples, Rgba::HIGHLIGHT);
                            }
                        }
                    } else {
                        spheres.push(marker(point, 0.08, [0.95, 0.3, 0.1, 1.0]));
                    }
                }
            }
        }
        if tool == Tool::Tangent {
            let curves: Vec<Curve<DVec3>> = ctx.curves.iter().map(|(_, c)| (*c).clone()).collect();
            for joint in joints(&curves) {
                if let Some((ql, q, qr)) = joint_points(&curves, joint) {
                    for p in [ql, qr] {
                        spheres.push(marker(p, 0.07, [0.2, 0.5, 1.0, 1.0]));
                    }
                    spheres.push(marker(q, 0.09, [0.95, 0.75, 0.1, 1.0]));
                }
            }
        }
    }
}

/// The surface normal at a hit, turned towards the viewer.
fn facing_normal(hit: &SurfaceHit, ctx: &ToolContext<'_>) -> DVec3 {
    let to_eye = ctx.camera.eye().as_dvec3() - hit.point;
    if hit.normal.dot(to_eye) >= 0.0 {
        hit.normal
    } else {
        -hit.normal
    }
}

/// Where the ray through `pixel` meets the plane `(x − eye)·forward = depth` (`None` when it
/// runs along the plane or meets it behind the eye).
fn plane_point(
    ctx: &ToolContext<'_>,
    eye: DVec3,
    forward: DVec3,
    depth: f64,
    pixel: Vec2,
) -> Option<DVec3> {
    let ray = ctx.ray(pixel);
    let along = ray.direction.dot(forward);
    if along.abs() < 1e-9 {
        return None;
    }
    let t = (depth - (ray.origin - eye).dot(forward)) / along;
    (t > 0.0 && t.is_finite()).then(|| ray.at(t))
}

/// Spacing of a drawn line's path points: a fifth of the finger radius.
fn stroke_spacing(settings: &ToolSettings) -> f64 {
    0.2 * settings.radius
}

/// Pixels between the surface samples taken along a cursor move.
const SAMPLE_PIXELS: f32 = 2.0;

/// Extends a drawn `path` towards the surface under `pixel`, at even `spacing` measured along
/// the surface: the move from `last` is sampled every [`SAMPLE_PIXELS`] on the surface
/// (at most 256 samples a move), and a path point is put wherever the length walked since the
/// path's last point (`carry` before this move) reaches `spacing` (on the chord between two
/// samples, which lies on the surface to within the chord's sag).
fn extend_evenly(
    ctx: &ToolContext<'_>,
    spacing: f64,
    path: &mut Vec<DVec3>,
    last: &mut (Vec2, DVec3),
    carry: &mut f64,
    pixel: Vec2,
) {
    let (from_pixel, mut a) = *last;
    let steps = ((from_pixel.distance(pixel) / SAMPLE_PIXELS).ceil() as usize).clamp(1, 256);
    for k in 1..=steps {
        let at = from_pixel.lerp(pixel, k as f32 / steps as f32);
        let Some(hit) = ctx.pick_surface(at) else {
            continue;
        };
        let b = hit.point;
        let mut length = (b - a).length();
        let mut from = a;
        while *carry + length >= spacing && length > 0.0 {
            let need = spacing - *carry;
            let point = from + (b - from) * (need / length);
            path.push(point);
            length -= need;
            from = point;
            *carry = 0.0;
        }
        *carry += length;
        a = b;
        *last = (at, b);
    }
}

/// Depth of a push: the drag length at the hit's distance, or the panel's depth for a click.
fn press_depth(
    ctx: &ToolContext<'_>,
    settings: &ToolSettings,
    hit: &SurfaceHit,
    start: Vec2,
    cursor: Vec2,
) -> f64 {
    let drag = start.distance(cursor);
    if drag < CLICK_PIXELS {
        settings.depth
    } else {
        f64::from(drag) * ctx.units_per_pixel_at(hit.t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::camera::ViewPreset;
    use crate::mesh::{Tessellation, tessellate};
    use crate::surface::{Primitive, PrimitiveParams};

    /// The default plane seen from the iso view in an 800 × 600 viewport.
    struct PlaneScene {
        patches: Vec<PatchPoints>,
        mesh: TriMesh,
        camera: OrbitCamera,
        viewport: Vec2,
    }

    impl PlaneScene {
        fn new() -> Self {
            let patches = Primitive::Plane
                .build(&PrimitiveParams::default())
                .expect("plane")
                .patches();
            let mesh = tessellate(&patches, &Tessellation::DISPLAY);
            let viewport = Vec2::new(800.0, 600.0);
            let camera =
                OrbitCamera::framing(ViewPreset::Iso, &mesh.positions, viewport.x / viewport.y);
            Self {
                patches,
                mesh,
                camera,
                viewport,
            }
        }

        fn context(&self) -> ToolContext<'_> {
            ToolContext {
                camera: &self.camera,
                viewport: self.viewport,
                patches: &self.patches,
                mesh: &self.mesh,
                curves: &[],
            }
        }
    }

    #[test]
    fn a_click_on_the_plane_pushes_it_away_from_the_viewer() {
        let scene = PlaneScene::new();
        let ctx = scene.context();
        let viewport = scene.viewport;
        let settings = ToolSettings::default();
        let mut state = ToolState::default();
        let centre = viewport / 2.0;
        assert!(state.press(Tool::Push, &ctx, &settings, centre).is_empty());
        let edits = state.release(Tool::Push, &ctx, &settings, centre);
        let [
            Edit::Sculpt(Op::Push {
                at,
                dir,
                depth,
                radius,
            }),
        ] = edits.as_slice()
        else {
            panic!("one push expected, got {edits:?}");
        };
        assert!(at.z.abs() < 1e-9 && *depth == settings.depth && *radius == settings.radius);
        assert!(
            dir.dot(DVec3::Z) < -0.999,
            "into the plane, away from a viewer above: {dir}"
        );
        // A drag sets the depth from its length; pull reverses it.
        state.press(Tool::Pull, &ctx, &settings, centre);
        let edits = state.release(Tool::Pull, &ctx, &settings, centre + Vec2::new(0.0, 80.0));
        let [Edit::Sculpt(Op::Push { depth, .. })] = edits.as_slice() else {
            panic!("{edits:?}")
        };
        assert!(*depth < -0.1, "{depth}");
        // Outside the surface nothing happens.
        assert!(
            state
                .press(Tool::Push, &ctx, &settings, Vec2::new(2.0, 2.0))
                .is_empty()
        );
        assert!(
            state
                .release(Tool::Push, &ctx, &settings, Vec2::new(2.0, 2.0))
                .is_empty()
        );
    }

    /// A drawn line's path is evenly spaced along the surface (a fifth of the radius), however
    /// the cursor moved (a few long jumps, many short steps), and the live operation is a drag
    /// along it; Ctrl turns the groove into a ridge.
    #[test]
    fn a_drawn_line_is_evenly_spaced() {
        let scene = PlaneScene::new();
        let ctx = scene.context();
        let settings = ToolSettings::default();
        let spacing = 0.2 * settings.radius;
        let mut state = ToolState::default();
        let start = Vec2::new(300.0, 300.0);
        state.press(Tool::DrawLine, &ctx, &settings, start);
        assert_eq!(
            state.stroke_op(Tool::DrawLine, &ctx, &settings),
            None,
            "one point: no op yet"
        );
        for (k, step) in [(3, 60.0f32), (40, 2.5)] {
            for _ in 0..k {
                let Gesture::Stroke { last, .. } = &state.gesture else {
                    panic!("a stroke")
                };
                let to = last.0 + Vec2::new(step, 0.3 * step);
                state.drag(&ctx, &settings, to);
            }
        }
        let Some(Op::Groove {
            path, depth, dirs, ..
        }) = state.stroke_op(Tool::DrawLine, &ctx, &settings)
        else {
            panic!("a groove")
        };
        assert_eq!(dirs, Dirs::Normal, "the line follows the clay");
        assert!(path.len() > 10, "{}", path.len());
        assert!(depth > 0.0, "a groove");
        for w in path.windows(2) {
            let d = (w[1] - w[0]).length();
            assert!(
                (d - spacing).abs() < 1e-9 * spacing.max(1.0),
                "spacing {d} vs {spacing}"
            );
        }
        state.set_invert(true);
        let Some(Op::Groove { depth, .. }) = state.stroke_op(Tool::DrawLine, &ctx, &settings)
        else {
            panic!("a groove")
        };
        assert!(depth < 0.0, "Ctrl: a ridge");
    }

    #[test]
    fn the_wheel_never_turns_a_dragged_push_into_a_pull() {
        let scene = PlaneScene::new();
        let ctx = scene.context();
        let viewport = scene.viewport;
        // A deep click depth, a short drag: the drag's depth is far below the panel's.
        let settings = ToolSettings {
            depth: 3.0,
            ..ToolSettings::default()
        };
        let centre = viewport / 2.0;
        let end = centre + Vec2::new(0.0, 10.0);
        let mut state = ToolState::default();
        state.press(Tool::Push, &ctx, &settings, centre);
        state.drag(&ctx, &settings, end);
        for _ in 0..40 {
            assert!(state.wheel(&ctx, &settings, -1.0));
        }
        let mut lines = LineBatch::new();
        let mut spheres = Vec::new();
        state.preview(Tool::Push, &ctx, &settings, &mut lines, &mut spheres);
        assert_eq!(lines.on_top_len(), 1, "the push's travel is drawn on top");
        let edits = state.release(Tool::Push, &ctx, &settings, end);
        assert!(
            edits.iter().all(|e| match e {
                Edit::Sculpt(Op::Push { depth, .. }) => *depth > 0.0,
                _ => false,
            }),
            "wheeled back to nothing, a push is no pull: {edits:?}"
        );
        // One notch forward from the floor pushes again, by one notch.
        state.press(Tool::Push, &ctx, &settings, centre);
        state.drag(&ctx, &settings, end);
        for _ in 0..40 {
            state.wheel(&ctx, &settings, -1.0);
        }
        state.wheel(&ctx, &settings, 1.0);
        let edits = state.release(Tool::Push, &ctx, &settings, end);
        let [Edit::Sculpt(Op::Push { depth, .. })] = edits.as_slice() else {
            panic!("{edits:?}")
        };
        assert!(
            (*depth - 0.05 * settings.radius).abs() < 1e-9,
            "one notch: {depth}"
        );
    }

    /// Move: a press grabs the surface point under the cursor, a drag takes it to the cursor
    /// on the plane through it facing the camera, the wheel moves that plane nearer; a click
    /// without a move is no edit.
    #[test]
    fn move_takes_the_grabbed_point_to_the_cursor_on_the_facing_plane() {
        let scene = PlaneScene::new();
        let ctx = scene.context();
        let settings = ToolSettings::default();
        let mut state = ToolState::default();
        let centre = scene.viewport / 2.0;
        assert!(state.press(Tool::Move, &ctx, &settings, centre).is_empty());
        assert!(state.stroking() && !state.smoothing());
        assert_eq!(
            state.stroke_op(Tool::Move, &ctx, &settings),
            None,
            "not moved yet"
        );
        let hit = ctx
            .pick_surface(centre)
            .expect("the plane is under the centre");
        let end = centre + Vec2::new(60.0, -40.0);
        state.drag(&ctx, &settings, end);
        let Some(Op::Move { at, to, radius }) = state.stroke_op(Tool::Move, &ctx, &settings) else {
            panic!("a move")
        };
        assert_eq!(at, hit.point);
        assert_eq!(radius, settings.radius);
        let eye = scene.camera.eye().as_dvec3();
        let forward = -scene.camera.to_eye().as_dvec3();
        assert!(
            (to - at).dot(forward).abs() < 1e-9 * (at - eye).length(),
            "on the plane facing the camera"
        );
        let ray = ctx.ray(end);
        assert!(
            (to - ray.origin).cross(ray.direction).length() < 1e-9 * (to - eye).length(),
            "under the cursor"
        );
        // The wheel away from the user brings the plane nearer the eye.
        assert!(state.wheel(&ctx, &settings, 3.0));
        let Some(Op::Move { to: nearer, .. }) = state.stroke_op(Tool::Move, &ctx, &settings) else {
            panic!("a move")
        };
        assert!((nearer - eye).dot(forward) < (to - eye).dot(forward) - 1e-3);
        let edits = state.release(Tool::Move, &ctx, &settings, end);
        assert!(matches!(edits.as_slice(), [Edit::Sculpt(Op::Move { .. })]));
        // A click is nothing.
        state.press(Tool::Move, &ctx, &settings, centre);
        assert!(
            state
                .release(Tool::Move, &ctx, &settings, centre)
                .is_empty()
        );
    }

    /// Smooth, and Push / Pull / Draw a line with Shift held: dabs of the panel's radius and
    /// strength at even spacing along the path, all of them released as edits in order.
    #[test]
    fn smoothing_strokes_are_evenly_spaced_dabs() {
        let scene = PlaneScene::new();
        let ctx = scene.context();
        let settings = ToolSettings::default();
        let spacing = 0.2 * settings.radius;
        for (tool, shift) in [
            (Tool::Smooth, false),
            (Tool::Push, true),
            (Tool::Pull, true),
            (Tool::DrawLine, true),
        ] {
            let mut state = ToolState::default();
            state.set_smooth(shift);
            assert_eq!(state.acting_tool(tool), Tool::Smooth);
            let start = Vec2::new(300.0, 300.0);
            state.press(tool, &ctx, &settings, start);
            assert!(state.smoothing(), "{tool:?}");
            assert_eq!(state.stroke_op(tool, &ctx, &settings), None);
            for k in 1..=20 {
                state.drag(
                    &ctx,
                    &settings,
                    start + Vec2::new(6.0 * k as f32, 2.0 * k as f32),
                );
            }
            let dabs = state.stroke_dabs(&settings).expect("dabs");
            assert!(dabs.len() > 5, "{}", dabs.len());
            let points: Vec<DVec3> = dabs
                .iter()
                .map(|d| match d {
                    Op::Smooth {
                        at,
                        radius,
                        strength,
                    } => {
                        assert_eq!((*radius, *strength), (settings.radius, settings.strength));
                        *at
                    }
                    other => panic!("a smoothing dab: {other:?}"),
                })
                .collect();
            for w in points.windows(2) {
                let d = (w[1] - w[0]).length();
                assert!((d - spacing).abs() < 1e-9, "spacing {d} vs {spacing}");
            }
            let edits = state.release(tool, &ctx, &settings, start + Vec2::new(120.0, 40.0));
            assert!(edits.len() >= dabs.len());
            assert!(
                edits
                    .iter()
                    .all(|e| matches!(e, Edit::Sculpt(Op::Smooth { .. })))
            );
        }
        // Without Shift, Push pushes.
        let mut state = ToolState::default();
        assert_eq!(state.acting_tool(Tool::Push), Tool::Push);
        state.press(Tool::Push, &ctx, &settings, Vec2::new(300.0, 300.0));
        assert!(!state.smoothing());
        assert!(state.stroke_dabs(&settings).is_none());
    }
}
