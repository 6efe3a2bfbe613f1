// The per-frame uniform every pass but the background reads, defined once: the renderer
// prepends this file to `clay.wgsl`, `lines.wgsl` and `spheres.wgsl` when it builds them
// (`render::renderer`), and `tests/it/shader_validation.rs` checks this block against
// `render::gpu_data::Globals` (members, offsets, size).
//
// Keep in sync with `render::gpu_data::Globals`.
struct Globals {
    clip_from_world: mat4x4<f32>,
    eye: vec3<f32>,
    heat_max_deg: f32,
    key_light: vec3<f32>,
    heat_on: f32,
    clay: vec4<f32>,
    tool_center: vec3<f32>,
    tool_radius: f32,
    tool_axis: vec3<f32>,
    tool_on: f32,
    viewport: vec2<f32>,
    line_depth_bias: f32,
    pad: f32,
};

@group(0) @binding(0) var<uniform> globals: Globals;

