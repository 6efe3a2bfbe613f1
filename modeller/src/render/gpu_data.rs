//! Data laid out for the GPU: `#[repr(C)]`, `bytemuck::Pod`, sizes asserted at compile time.
//! The layouts build without the `gui` feature (the editor fills line and sphere batches); the
//! `Pod` derives and the wgpu vertex attributes come with it.
//!
//! **Keep in sync with the `.wgsl` files in `modeller/shaders/`.**
//! `tests/it/shader_validation.rs` checks `Globals` member by member (offsets and size) against
//! naga's layout of the one WGSL block, `modeller/shaders/globals.wgsl`.

#[cfg(feature = "gui")]
use bytemuck::{Pod, Zeroable};

/// Per-frame uniform shared by every pass (`@group(0) @binding(0)`).
/// Keep in sync with `struct Globals` in `modeller/shaders/globals.wgsl` (the one definition,
/// prepended to the clay, lines and spheres shaders).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "gui", derive(Pod, Zeroable))]
pub struct Globals {
    /// Column-major `clip_from_world` (wgpu's 0..1 depth).
    pub clip_from_world: [[f32; 4]; 4],
    /// The eye in homogeneous world coordinates `(eye, eye_w)`: the camera position with
    /// `eye_w = 1`, or with `eye_w = 0` the unit direction towards an orthographic camera; the
    /// shaders' direction to the viewer is `normalize(eye − eye_w · x)`.
    pub eye: [f32; 3],
    /// Seam angle (degrees) at the red end of the heat map.
    pub heat_max_deg: f32,
    /// Unit direction towards the key light, world space.
    pub key_light: [f32; 3],
    /// 1.0 to show the seam heat map.
    pub heat_on: f32,
    /// Clay albedo (linear RGB, alpha unused).
    pub clay: [f32; 4],
    /// A point on the finger axis (tool footprint overlay).
    pub tool_center: [f32; 3],
    /// Finger radius `r_f`.
    pub tool_radius: f32,
    /// Unit finger axis.
    pub tool_axis: [f32; 3],
    /// 1.0 to show the tool footprint.
    pub tool_on: f32,
    /// Viewport size in pixels.
    pub viewport: [f32; 2],
    /// Clip-space depth subtracted from lines (times `w`).
    pub line_depth_bias: f32,
    /// 1 for a perspective camera, 0 for an orthographic one (see `eye`).
    pub eye_w: f32,
    /// The camera's right, world space (a matcap's view-space x).
    pub view_right: [f32; 3],
    /// The matcap's number ([`crate::render::Matcap::code`]); 0 for the lit shading.
    pub matcap: f32,
    /// The camera's up, world space (a matcap's view-space y).
    pub view_up: [f32; 3],
    /// Padding to a multiple of 16 bytes.
    pub pad: f32,
}
const _: () = assert!(std::mem::size_of::<Globals>() == 192);

/// A vertex of the tessellated surface. Keep in sync with `VertexIn` in
/// `modeller/shaders/clay.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "gui", derive(Pod, Zeroable))]
pub struct SurfaceVertex {
    /// Position, world space.
    pub position: [f32; 3],
    /// Unit normal.
    pub normal: [f32; 3],
    /// G1 error of the nearest seam, degrees, and the heat map's weight here (1 on the seam,
    /// falling to 0 across its band).
    pub seam: [f32; 2],
}
const _: () = assert!(std::mem::size_of::<SurfaceVertex>() == 32);

#[cfg(feature = "gui")]
impl SurfaceVertex {
    /// Vertex attributes at locations 0, 1, 2.
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 3] =
        wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2];
}

/// An end of a line segment. Keep in sync with `VertexIn` in `modeller/shaders/lines.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "gui", derive(Pod, Zeroable))]
pub struct LineVertex {
    /// Position, world space.
    pub position: [f32; 3],
    /// Linear RGBA in 8 bits per channel, read as `Unorm8x4`.
    pub colour: [u8; 4],
}
const _: () = assert!(std::mem::size_of::<LineVertex>() == 16);

#[cfg(feature = "gui")]
impl LineVertex {
    /// Vertex attributes at locations 0, 1.
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 2] =
        wgpu::vertex_attr_array![0 => Float32x3, 1 => Unorm8x4];
}

/// A vertex of the unit sphere mesh. Keep in sync with `VertexIn.unit` in
/// `modeller/shaders/spheres.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "gui", derive(Pod, Zeroable))]
pub struct SphereVertex {
    /// Point of the unit sphere (its own normal).
    pub unit: [f32; 3],
}
const _: () = assert!(std::mem::size_of::<SphereVertex>() == 12);

#[cfg(feature = "gui")]
impl SphereVertex {
    /// Vertex attribute at location 0.
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![0 => Float32x3];
}

/// One sphere to draw. Keep in sync with `VertexIn` locations 1–3 in
/// `modeller/shaders/spheres.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "gui", derive(Pod, Zeroable))]
pub struct SphereInstance {
    /// Centre, world space.
    pub center: [f32; 3],
    /// Radius.
    pub radius: f32,
    /// Linear RGBA; alpha below 1 draws the sphere translucent.
    pub colour: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<SphereInstance>() == 32);

#[cfg(feature = "gui")]
impl SphereInstance {
    /// Instance attributes at locations 1, 2, 3.
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 3] =
        wgpu::vertex_attr_array![1 => Float32x3, 2 => Float32, 3 => Float32x4];
}
