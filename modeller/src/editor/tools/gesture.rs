//! The state of a left-button gesture of the mouse tools: press, drag, wheel, release and
//! cancel, the hover, the operation a live stroke applies, and the previews drawn.

use glam::{DVec3, Vec2};

use crate::curve::Curve;
use crate::curve::edit::{Grab, split};
use crate::editor::curve_edit::{CurveJoint, joint_points, joints, tangent_edit};
use crate::mesh::SurfaceHit;
use crate::render::{LineBatch, Rgba, SphereInstance, ToolFootprint};
use crate::surface::{Brush, Dirs, Op, SculptBrush};

use super::{Edit, Tool, ToolContext, ToolSettings};

/// A drag shorter than this (pixels) is a click.
const CLICK_PIXELS: f32 = 4.0;

/// How far one wheel notch moves the plane a Move drags the clay on: this fraction of the
/// plane's distance from the eye (towards the eye for a notch away from the user), as
/// `d ← d·e^(−0.02·notches)`. On the framed 10 × 10 plane (the eye about 20 sides away) a
/// notch is about 0.4 side.
pub const MOVE_WHEEL_STEP: f64 = 0.02;

/// The gesture in progress.
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) enum Gesture {
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
    pub(super) gesture: Gesture,
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
            Gesture::Press { hit, facing, .. } => Some(settings.brushed(Op::Push {
                at: hit.point,
                dir: -*facing,
                depth: sign * depth,
                radius: settings.radius,
            })),
            // Each path point presses along the surface's inward normal at the point nearest
            // to it (outward for a ridge): the groove follows the clay (issue 12).
            Gesture::Stroke { path, .. } if tool.sculpt_kind().is_some() => {
                sculpt_op(tool, path.clone(), sign * depth, settings)
            }
            Gesture::Stroke { path, .. } if path.len() >= 2 => Some(settings.brushed(Op::Groove {
                path: path.clone(),
                dirs: Dirs::Normal,
                depth: sign * depth,
                radius: settings.radius,
            })),
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
        if tool.sculpt_kind().is_some() {
            return sculpt_op(tool, vec![hit.point], settings.depth, settings);
        }
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
            Tool::Push
            | Tool::Pull
            | Tool::DrawLine
            | Tool::Inflate
            | Tool::Flatten
            | Tool::Pinch
            | Tool::Crease => {
                let Some(hit) = ctx.pick_surface(pixel) else {
                    return Vec::new();
                };
                let facing = facing_normal(&hit, ctx);
                self.gesture = if tool == Tool::DrawLine || tool.sculpt_kind().is_some() {
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
                let Some((ql, _, qr)) = joint_points(
                    &[left.clone(), right.clone()],
                    CurveJoint { left: 0, right: 1 },
                ) else {
                    return Vec::new();
                };
                let handle = if left_side { ql } else { qr };
                let ray_t = ctx.camera.ray_parameter(handle);
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
                match tangent_edit(pair, CurveJoint { left: 0, right: 1 }, *left_side, target) {
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
            // The plane the grabbed clay follows moves by a fraction of its distance from
            // the eye per notch, [`MOVE_WHEEL_STEP`] (2 %): a fine step at any zoom.
            Gesture::Move { depth, wheeled, .. } => {
                *depth *= (-MOVE_WHEEL_STEP * f64::from(steps)).exp();
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
                if let Some((ql, q, qr)) = joint_points(pair, CurveJoint { left: 0, right: 1 }) {
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

/// The surface brush of `tool` along `path` (one point: a dab) with the panel's radius, brush
/// and brush strength; `depth` (signed: Ctrl inverts) for inflate and crease only.
fn sculpt_op(tool: Tool, path: Vec<DVec3>, depth: f64, settings: &ToolSettings) -> Option<Op> {
    let kind = tool.sculpt_kind()?;
    let depth = if kind.has_depth() { depth } else { 0.0 };
    let brush = Brush {
        falloff: settings.falloff,
        strength: settings.press_strength,
    };
    SculptBrush::try_new(kind, path, settings.radius, depth, brush)
        .ok()
        .map(Op::Sculpt)
}

/// The surface normal at a hit, turned towards the viewer.
fn facing_normal(hit: &SurfaceHit, ctx: &ToolContext<'_>) -> DVec3 {
    let to_eye = ctx.camera.towards_viewer(hit.point);
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
