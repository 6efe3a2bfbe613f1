// Instanced spheres: the probe sphere (translucent), finger joints and tips, control points.
// One unit-sphere mesh, scaled and moved per instance; matte shading like the clay.

// `Globals` and its binding `globals` come from `globals.wgsl`, prepended at build time.

// Keep in sync with `render::gpu_data::SphereVertex` and `render::gpu_data::SphereInstance`.
struct VertexIn {
    @location(0) unit: vec3<f32>,
    @location(1) center: vec3<f32>,
    @location(2) radius: f32,
    @location(3) colour: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) colour: vec4<f32>,
};

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    let world = in.center + in.radius * in.unit;
    out.clip = globals.clip_from_world * vec4<f32>(world, 1.0);
    out.world = world;
    out.normal = in.unit;
    out.colour = in.colour;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let to_eye = to_viewer(in.world);
    let diffuse = max((dot(n, globals.key_light) + 0.4) / 1.4, 0.0);
    let ambient = mix(0.25, 0.45, 0.5 + 0.5 * n.z);
    let rim = pow(1.0 - max(dot(n, to_eye), 0.0), 2.0) * 0.25;
    let colour = in.colour.rgb * (ambient + 0.7 * diffuse) + vec3<f32>(rim);
    // Translucent spheres thicken towards their outline, so their shape reads.
    let alpha = select(in.colour.a, min(1.0, in.colour.a + rim), in.colour.a < 1.0);
    return vec4<f32>(colour, alpha);
}
