// Coloured line segments: patch boundaries, control nets, curves and their control polygons,
// hand bones. Pulled towards the camera by a small depth bias (depth bias state does not apply
// to lines) so lines lying on the surface stay visible.

// `Globals` and its binding `globals` come from `globals.wgsl`, prepended at build time.

// Keep in sync with `render::gpu_data::LineVertex`.
struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) colour: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec4<f32>,
};

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    var clip = globals.clip_from_world * vec4<f32>(in.position, 1.0);
    // Reverse-free depth in [0, 1]: smaller is nearer.
    clip.z = clip.z - globals.line_depth_bias * clip.w;
    out.clip = clip;
    out.colour = in.colour;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    return in.colour;
}
