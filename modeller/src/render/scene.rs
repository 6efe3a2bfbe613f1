//! What the renderer is given each frame: the view, the style, and batches of lines.

use glam::{Mat4, Vec3};

use super::gpu_data::LineVertex;

/// The camera as the renderer needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Clip space (wgpu: depth 0..1) from world space.
    pub clip_from_world: Mat4,
    /// World space from view space (the camera's pose; the key light turns with it).
    pub world_from_view: Mat4,
}

/// The finger footprint drawn on the surface: a ring where the distance to the finger axis
/// equals the radius.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ToolFootprint {
    /// A point on the finger axis (where it meets the surface).
    pub center: Vec3,
    /// The finger axis direction.
    pub axis: Vec3,
    /// The finger radius `r_f`.
    pub radius: f32,
}

/// How the surface is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Style {
    /// Clay albedo, linear RGB (alpha unused).
    pub clay: [f32; 4],
    /// Colour the surface along seams by their G1 error.
    pub heat_map: bool,
    /// Seam angle (degrees) drawn red.
    pub heat_max_deg: f32,
    /// The tool footprint, if one is shown.
    pub tool: Option<ToolFootprint>,
    /// Clip-space depth by which lines are pulled towards the camera (times `w`).
    pub line_depth_bias: f32,
    /// Shade the clay with a matcap instead of the lights ([`super::matcap`]); `None`: lit.
    pub matcap: Option<super::matcap::Matcap>,
}

impl Default for Style {
    fn default() -> Self {
        Self {
            clay: [0.52, 0.32, 0.21, 1.0],
            heat_map: false,
            heat_max_deg: 1.0,
            tool: None,
            line_depth_bias: 2e-5,
            matcap: None,
        }
    }
}

/// A linear RGBA colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rgba(pub [f32; 4]);

impl Rgba {
    /// Patch boundaries: a dark line on the clay.
    pub const PATCH_EDGE: Rgba = Rgba([0.05, 0.035, 0.03, 0.85]);
    /// Patch boundaries made by refinement: the same line, fainter (a third of the opacity),
    /// so the primitive's own grid still reads through the bands a refinement adds.
    pub const REFINED_EDGE: Rgba = Rgba([0.05, 0.035, 0.03, 0.28]);
    /// The control net.
    pub const CONTROL_NET: Rgba = Rgba([0.1, 0.35, 0.9, 0.9]);
    /// Curves.
    pub const CURVE: Rgba = Rgba([0.95, 0.75, 0.1, 1.0]);
    /// Control polygons of curves.
    pub const CONTROL_POLYGON: Rgba = Rgba([0.55, 0.55, 0.6, 0.9]);
    /// The virtual hand's bones.
    pub const HAND: Rgba = Rgba([0.9, 0.9, 0.92, 1.0]);
    /// Highlights (the picked item, the stroke being drawn).
    pub const HIGHLIGHT: Rgba = Rgba([1.0, 0.25, 0.1, 1.0]);

    /// 8-bit channels for a [`LineVertex`].
    #[must_use]
    pub fn to_unorm8(self) -> [u8; 4] {
        self.0.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8)
    }
}

/// Line segments to draw, each with its colour: most are depth-tested like the clay; a few
/// (a push's travel into the surface) are drawn on top of everything.
#[derive(Debug, Clone, Default)]
pub struct LineBatch {
    vertices: Vec<LineVertex>,
    on_top: Vec<LineVertex>,
}

impl LineBatch {
    /// An empty batch.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Removes every segment, keeping the allocation.
    pub fn clear(&mut self) {
        self.vertices.clear();
        self.on_top.clear();
    }

    /// Adds the segment `a`–`b`.
    pub fn segment(&mut self, a: Vec3, b: Vec3, colour: Rgba) {
        push_segment(&mut self.vertices, a, b, colour);
    }

    /// Adds the segment `a`–`b` drawn over everything (no depth test): for what lies inside
    /// or behind the surface and must still be seen.
    pub fn segment_on_top(&mut self, a: Vec3, b: Vec3, colour: Rgba) {
        push_segment(&mut self.on_top, a, b, colour);
    }

    /// Adds a polyline through `points` (nothing for fewer than two points).
    pub fn polyline(&mut self, points: impl IntoIterator<Item = Vec3>, colour: Rgba) {
        let mut previous: Option<Vec3> = None;
        for p in points {
            if let Some(q) = previous {
                self.segment(q, p, colour);
            }
            previous = Some(p);
        }
    }

    /// The vertices, two per segment.
    #[must_use]
    pub fn vertices(&self) -> &[LineVertex] {
        &self.vertices
    }

    /// The vertices of the segments drawn on top, two per segment.
    #[must_use]
    pub fn on_top_vertices(&self) -> &[LineVertex] {
        &self.on_top
    }

    /// Number of segments drawn on top.
    #[must_use]
    pub fn on_top_len(&self) -> usize {
        self.on_top.len() / 2
    }

    /// Number of segments.
    #[must_use]
    pub fn len(&self) -> usize {
        self.vertices.len() / 2
    }

    /// True when there is no segment (of either kind).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty() && self.on_top.is_empty()
    }
}

fn push_segment(vertices: &mut Vec<LineVertex>, a: Vec3, b: Vec3, colour: Rgba) {
    let colour = colour.to_unorm8();
    vertices.push(LineVertex {
        position: a.to_array(),
        colour,
    });
    vertices.push(LineVertex {
        position: b.to_array(),
        colour,
    });
}
