// The patch surface shaded as clay: soft, matte, readable form.
//
// Lighting (linear colour; the sRGB target encodes it): a hemisphere ambient (sky above, warm
// ground below, world up = +Z), a key light fixed relative to the camera with wrapped diffuse
// (no hard terminator), a faint rim, no specular. Normals are turned to the side seen (by the
// triangle's facing, see `seen_normal`), so the surface reads the same from either side. Optional overlays: the G1 seam heat map and the
// tool footprint (the ring where the distance to the finger axis equals the finger radius —
// exactly the samples the push shape function reaches).
//
// With a matcap chosen (`globals.matcap` 1, 2, 3) the lights are replaced by the matcap's
// formula of the view-space normal (`render::matcap`, which evaluates the same on the CPU).

// `Globals` and its binding `globals` come from `globals.wgsl`, prepended at build time.

// Keep in sync with `render::gpu_data::SurfaceVertex`.
struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // [G1 angle of the nearest seam in degrees, weight of the heat band].
    @location(2) seam: vec2<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) seam: vec2<f32>,
};

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = globals.clip_from_world * vec4<f32>(in.position, 1.0);
    out.world = in.position;
    out.normal = in.normal;
    out.seam = in.seam;
    return out;
}

// Blue → cyan → yellow → red for t in [0, 1].
fn heat_ramp(t: f32) -> vec3<f32> {
    let c0 = vec3<f32>(0.05, 0.15, 0.85);
    let c1 = vec3<f32>(0.0, 0.75, 0.8);
    let c2 = vec3<f32>(0.95, 0.85, 0.1);
    let c3 = vec3<f32>(0.9, 0.05, 0.02);
    if t < 0.3333 {
        return mix(c0, c1, t * 3.0);
    } else if t < 0.6667 {
        return mix(c1, c2, (t - 0.3333) * 3.0);
    }
    return mix(c2, c3, (t - 0.6667) * 3.0);
}

// The normal shaded: the interpolated vertex normal, turned to the side of the surface seen.
//
// Which side is seen is the triangle's own: its winding (the mesh is counter-clockwise seen
// from `S_u × S_v`, the side the vertex normals point to), so `front_facing` says whether to
// flip. Deciding it per pixel from the sign of `n · (eye − x)` instead breaks the shading
// wherever a visible triangle's interpolated normal leans a little past perpendicular to the
// view — along a groove's rim seen edge-on, at a fold — where single pixels flipped to face
// away and the ground ambient (issue 27's dark specks). Where the interpolated normal still
// points behind the visible face `f` (the triangle's plane, `f = ±(∂x/∂X × ∂x/∂Y)` towards
// the eye), it is bent into that plane, `n − min(n·f, 0) f`: continuous, never a flip.
fn seen_normal(normal: vec3<f32>, world: vec3<f32>, to_eye: vec3<f32>, front: bool) -> vec3<f32> {
    var n = normalize(normal);
    if !front {
        n = -n;
    }
    let cross_f = cross(dpdx(world), dpdy(world));
    let len = length(cross_f);
    if len > 0.0 {
        var f = cross_f / len;
        if dot(f, to_eye) < 0.0 {
            f = -f;
        }
        let behind = min(dot(n, f), 0.0);
        n = normalize(n - behind * f + 1e-4 * f);
    }
    return n;
}

// The matcap `code` (1 clay, 2 red wax, 3 soft grey) for the view-space unit normal `n`: the
// formulas of `render::matcap` (keep in sync with `Matcap::colour`).
fn matcap_colour(code: f32, n: vec3<f32>) -> vec3<f32> {
    let l = normalize(vec3<f32>(-0.45, 0.55, 0.70));
    let h = normalize(l + vec3<f32>(0.0, 0.0, 1.0));
    let nl = dot(n, l);
    let spec_base = max(dot(n, h), 0.0);
    let facing = max(n.z, 0.0);
    if code < 1.5 {
        let wrap = max((nl + 0.5) / 1.5, 0.0);
        return vec3<f32>(0.62, 0.42, 0.31) * (0.16 + 0.9 * wrap) * (0.6 + 0.4 * facing)
            + vec3<f32>(0.05 * pow(spec_base, 10.0));
    } else if code < 2.5 {
        let wrap = max((nl + 0.3) / 1.3, 0.0);
        let rim = pow(1.0 - facing, 4.0);
        return vec3<f32>(0.50, 0.045, 0.035) * (0.08 + 0.85 * wrap)
            + vec3<f32>(0.9 * pow(spec_base, 90.0))
            + vec3<f32>(0.45, 0.12, 0.10) * rim;
    }
    let wrap = max((nl + 1.0) / 2.0, 0.0);
    return vec3<f32>(0.66 * (0.32 + 0.48 * wrap + 0.2 * (0.5 + 0.5 * n.y)));
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let to_eye = to_viewer(in.world);
    let n = seen_normal(in.normal, in.world, to_eye, front);
    var albedo = globals.clay.rgb;

    if globals.heat_on > 0.5 && in.seam.x > 0.0 {
        let t = clamp(in.seam.x / max(globals.heat_max_deg, 1e-6), 0.0, 1.0);
        // Errors below 1 % of the scale fade out (rounding noise on G1 seams); above, the
        // colour says how large the error is and the band fades away from the seam.
        let visible = clamp(in.seam.x / max(0.01 * globals.heat_max_deg, 1e-9), 0.0, 1.0);
        albedo = mix(albedo, heat_ramp(t), 0.9 * visible * clamp(in.seam.y * 1.5, 0.0, 1.0));
    }

    let up = n.z;
    let sky = vec3<f32>(0.58, 0.6, 0.66);
    let ground = vec3<f32>(0.26, 0.22, 0.2);
    let ambient = mix(ground, sky, 0.5 + 0.5 * up);
    let wrap = 0.35;
    let diffuse = max((dot(n, globals.key_light) + wrap) / (1.0 + wrap), 0.0);
    let rim = pow(1.0 - max(dot(n, to_eye), 0.0), 3.0) * 0.12;
    var colour = albedo * (0.42 * ambient + 0.95 * diffuse) + vec3<f32>(rim);
    if globals.matcap > 0.5 {
        let back = cross(globals.view_right, globals.view_up);
        let nv = vec3<f32>(dot(n, globals.view_right), dot(n, globals.view_up), dot(n, back));
        colour = matcap_colour(globals.matcap, nv);
        if globals.heat_on > 0.5 && in.seam.x > 0.0 {
            let t = clamp(in.seam.x / max(globals.heat_max_deg, 1e-6), 0.0, 1.0);
            let visible = clamp(in.seam.x / max(0.01 * globals.heat_max_deg, 1e-9), 0.0, 1.0);
            colour = mix(colour, heat_ramp(t), 0.9 * visible * clamp(in.seam.y * 1.5, 0.0, 1.0));
        }
    }

    if globals.tool_on > 0.5 {
        let d = in.world - globals.tool_center;
        let along = dot(d, globals.tool_axis);
        let r = length(d - along * globals.tool_axis);
        let width = max(fwidth(r) * 1.5, 1e-5);
        let ring = 1.0 - smoothstep(0.0, width, abs(r - globals.tool_radius));
        let inside = select(0.0, 0.12, r < globals.tool_radius);
        let tint = vec3<f32>(0.15, 0.45, 0.95);
        colour = mix(colour, tint, max(ring * 0.9, inside));
    }
    return vec4<f32>(colour, 1.0);
}
