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
    // The eye is homogeneous: (eye, 1) a camera position, (eye, 0) the direction towards an
    // orthographic camera. The direction to the viewer is `to_viewer(x)` below.
    eye_w: f32,
    view_right: vec3<f32>,
    // 0: the lit shading; 1, 2, 3: a matcap (`render::matcap`).
    matcap: f32,
    view_up: vec3<f32>,
    pad: f32,
};

@group(0) @binding(0) var<uniform> globals: Globals;

// The unit vector from the world point `x` towards the viewer: towards the eye of a
// perspective camera, the view direction's opposite for an orthographic one.
fn to_viewer(x: vec3<f32>) -> vec3<f32> {
    return normalize(globals.eye - globals.eye_w * x);
}

