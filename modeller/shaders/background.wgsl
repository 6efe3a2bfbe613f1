// A soft vertical gradient behind the model: one full-screen triangle, no buffers.

struct VertexOut {
    @builtin(position) position: vec4<f32>,
    @location(0) height: f32,
};

@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> VertexOut {
    // (-1,-1), (3,-1), (-1,3): covers the viewport.
    let x = f32(i32(index & 1u) * 4 - 1);
    let y = f32(i32(index >> 1u) * 4 - 1);
    var out: VertexOut;
    out.position = vec4<f32>(x, y, 1.0, 1.0);
    out.height = 0.5 * (y + 1.0);
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    // Linear colours; the sRGB target encodes them.
    let bottom = vec3<f32>(0.16, 0.165, 0.18);
    let top = vec3<f32>(0.42, 0.44, 0.48);
    let t = clamp(in.height, 0.0, 1.0);
    return vec4<f32>(mix(bottom, top, t * t), 1.0);
}
