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
//! | inflate, flatten, pinch, crease | press on the surface (a dab) and drag along it (a stroke, its path resampled as a drawn line's): the surface brush ([`Op::Sculpt`], [`crate::surface::sculpt_brush`]) with the panel's radius, depth (inflate, crease), brush and brush strength, live from the press; Ctrl deflates (inflate) or raises a ridge (crease) |
//! | hand | the mouse as the virtual hand ([`super::hand_input::MouseHandTool`], driven by the modeller): press pushes, drag draws a groove, with Shift (or "ridges") it grips and pulls; the wheel while pressed goes deeper |
//!
//! Tools read the surface, the curves and the camera through a [`ToolContext`] and answer with
//! [`Edit`]s for the document; they draw their previews into the scene.

use glam::DVec3;

mod context;
mod gesture;
#[cfg(test)]
mod tests;

pub use context::{PICK_PIXELS, ToolContext};
pub use gesture::ToolState;

use crate::curve::Curve;
use crate::curve::edit::GrabOptions;
use crate::surface::{Falloff, Op, SculptKind};

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
    /// Inflate the clay along its normals (Blender's I).
    Inflate,
    /// Flatten the clay toward the average plane under the brush (Blender's Shift+T).
    Flatten,
    /// Pinch the clay toward the stroke (Blender's P).
    Pinch,
    /// Crease: pinch and press in along the stroke (Blender's Shift+C).
    Crease,
}

impl Tool {
    /// Every tool, in panel order.
    /// The surface brushes come last, so that the number keys keep their tools.
    pub const ALL: [Tool; 13] = [
        Tool::Push,
        Tool::Pull,
        Tool::DrawLine,
        Tool::Move,
        Tool::Smooth,
        Tool::GrabCurve,
        Tool::SplitCurve,
        Tool::Tangent,
        Tool::Hand,
        Tool::Inflate,
        Tool::Flatten,
        Tool::Pinch,
        Tool::Crease,
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
            Tool::Inflate => "Inflate",
            Tool::Flatten => "Flatten",
            Tool::Pinch => "Pinch",
            Tool::Crease => "Crease",
        }
    }

    /// The surface brush the tool applies (inflate, flatten, pinch, crease).
    #[must_use]
    pub fn sculpt_kind(self) -> Option<SculptKind> {
        match self {
            Tool::Inflate => Some(SculptKind::Inflate),
            Tool::Flatten => Some(SculptKind::Flatten),
            Tool::Pinch => Some(SculptKind::Pinch),
            Tool::Crease => Some(SculptKind::Crease),
            _ => None,
        }
    }

    /// True for the tools that sculpt the surface.
    #[must_use]
    pub fn sculpts(self) -> bool {
        matches!(
            self,
            Tool::Push
                | Tool::Pull
                | Tool::DrawLine
                | Tool::Move
                | Tool::Smooth
                | Tool::Hand
                | Tool::Inflate
                | Tool::Flatten
                | Tool::Pinch
                | Tool::Crease
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

impl ToolSettings {
    /// `op` pressed with the panel's brush ([`Op::Brushed`]), or `op` itself for the finger
    /// brush at full strength.
    #[must_use]
    pub fn brushed(&self, op: Op) -> Op {
        if self.falloff == Falloff::Finger && self.press_strength == 1.0 {
            op
        } else {
            Op::Brushed {
                op: Box::new(op),
                brush: crate::surface::Brush {
                    falloff: self.falloff,
                    strength: self.press_strength,
                },
            }
        }
    }
}

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
    /// The brush of push, pull and draw a line ([`crate::surface::brush`]).
    pub falloff: Falloff,
    /// The fraction of the depth push, pull and draw a line press, `0 < s ≤ 1`.
    pub press_strength: f64,
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
            falloff: Falloff::Finger,
            press_strength: 1.0,
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
