// Surface analysis: zebra stripes, curvature map, isophotes, per pixel from the patch's exact
// derivatives (see `render::display_mode` for the formulas; `nendo_geom`'s `shape_operator`
// is the CPU reference of the curvatures).
//
// Each fragment carries its patch index and (u, v); the 16 control points of the patch are
// read from a storage buffer and the bicubic's S_u, S_v, S_uu, S_uv, S_vv evaluated from the
// Bernstein basis. The tessellation only decides which pixels are covered.

// `Globals` and its binding `globals` come from `globals.wgsl`, prepended at build time.

// Keep in sync with `render::display_mode::AnalysisUniform`.
struct Analysis {
    e1: vec3<f32>,
    mode: u32,
    e2: vec3<f32>,
    kind: u32,
    stripes: f32,
    range_lo: f32,
    range_hi: f32,
    isophotes: f32,
};

@group(1) @binding(0) var<uniform> analysis: Analysis;
// 16 points per patch, P[4 i + j] (i along u, j along v); w unused.
@group(1) @binding(1) var<storage, read> points: array<vec4<f32>>;

// Locations 0–2: `render::gpu_data::SurfaceVertex`; 3–4: `render::display_mode::AnalysisVertex`.
struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) seam: vec2<f32>,
    @location(3) patch_index: u32,
    @location(4) uv: vec2<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) patch_index: u32,
    @location(3) uv: vec2<f32>,
};

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = globals.clip_from_world * vec4<f32>(in.position, 1.0);
    out.world = in.position;
    out.normal = in.normal;
    out.patch_index = in.patch_index;
    out.uv = in.uv;
    return out;
}

fn bernstein(t: f32) -> vec4<f32> {
    let s = 1.0 - t;
    return vec4<f32>(s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t);
}

fn bernstein_d(t: f32) -> vec4<f32> {
    let s = 1.0 - t;
    return vec4<f32>(-3.0 * s * s, 3.0 * s * s - 6.0 * t * s, 6.0 * t * s - 3.0 * t * t, 3.0 * t * t);
}

fn bernstein_dd(t: f32) -> vec4<f32> {
    let s = 1.0 - t;
    return vec4<f32>(6.0 * s, 6.0 * t - 12.0 * s, 6.0 * s - 12.0 * t, 6.0 * t);
}

struct Derivatives {
    su: vec3<f32>,
    sv: vec3<f32>,
    suu: vec3<f32>,
    suv: vec3<f32>,
    svv: vec3<f32>,
};

fn derivatives(patch_index: u32, uv: vec2<f32>) -> Derivatives {
    let bu = bernstein(uv.x);
    let du = bernstein_d(uv.x);
    let ddu = bernstein_dd(uv.x);
    let bv = bernstein(uv.y);
    let dv = bernstein_d(uv.y);
    let ddv = bernstein_dd(uv.y);
    var d: Derivatives;
    d.su = vec3<f32>(0.0);
    d.sv = vec3<f32>(0.0);
    d.suu = vec3<f32>(0.0);
    d.suv = vec3<f32>(0.0);
    d.svv = vec3<f32>(0.0);
    let base = patch_index * 16u;
    let count = arrayLength(&points);
    if base + 15u >= count {
        return d;
    }
    for (var i = 0u; i < 4u; i = i + 1u) {
        for (var j = 0u; j < 4u; j = j + 1u) {
            let x = points[base + 4u * i + j].xyz;
            d.su += x * (du[i] * bv[j]);
            d.sv += x * (bu[i] * dv[j]);
            d.suu += x * (ddu[i] * bv[j]);
            d.suv += x * (du[i] * dv[j]);
            d.svv += x * (bu[i] * ddv[j]);
        }
    }
    return d;
}

// Blue → cyan → yellow → red for t in [0, 1] (`display_mode::legend_colour`).
fn analysis_ramp(t: f32) -> vec3<f32> {
    let c0 = vec3<f32>(0.05, 0.15, 0.85);
    let c1 = vec3<f32>(0.0, 0.75, 0.8);
    let c2 = vec3<f32>(0.95, 0.85, 0.1);
    let c3 = vec3<f32>(0.9, 0.05, 0.02);
    let s = clamp(t, 0.0, 1.0) * 3.0;
    if s < 1.0 {
        return mix(c0, c1, s);
    } else if s < 2.0 {
        return mix(c1, c2, s - 1.0);
    }
    return mix(c2, c3, s - 2.0);
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let w = to_viewer(in.world);
    let d = derivatives(in.patch_index, in.uv);
    let e = dot(d.su, d.su);
    let f = dot(d.su, d.sv);
    let g = dot(d.sv, d.sv);
    let det = e * g - f * f;
    let cross_uv = cross(d.su, d.sv);
    // At a pole (no tangent plane) the mesh's normal is the limit from inside the patch.
    var n_oriented = normalize(in.normal);
    let regular = det > 1e-12 * e * g && length(cross_uv) > 0.0;
    if regular {
        n_oriented = normalize(cross_uv);
    }
    var n = n_oriented;
    if dot(n, w) < 0.0 {
        n = -n;
    }
    let diffuse = max((dot(n, globals.key_light) + 0.35) / 1.35, 0.0);

    if analysis.mode == 1u {
        // Zebra: the reflected view ray's angle around the stripe axis.
        let r = 2.0 * dot(n, w) * n - w;
        let phase = atan2(dot(r, analysis.e2), dot(r, analysis.e1)) * analysis.stripes / 3.14159265;
        let x = fract(phase);
        let aa = max(fwidth(phase), 1e-4);
        // Light on [0, 1/2), dark on [1/2, 1), edges smoothed over one pixel.
        let light = smoothstep(-aa, aa, x) * (1.0 - smoothstep(0.5 - aa, 0.5 + aa, x))
            + smoothstep(1.0 - aa, 1.0 + aa, x);
        let shade = 0.85 + 0.15 * diffuse;
        return vec4<f32>(vec3<f32>(mix(0.02, 0.92, light) * shade), 1.0);
    }
    if analysis.mode == 2u {
        var value = 0.0;
        if regular {
            let l = dot(d.suu, n_oriented);
            let m = dot(d.suv, n_oriented);
            let nn = dot(d.svv, n_oriented);
            let gaussian = (l * nn - m * m) / det;
            let mean = (e * nn - 2.0 * f * m + g * l) / (2.0 * det);
            // II in the orthonormal basis t1 = S_u/|S_u|, t2 = N × t1 (no cancellation at
            // an umbilic), as `shape_operator` does.
            let t1 = d.su / sqrt(e);
            let t2 = cross(n_oriented, t1);
            let c1 = vec2<f32>(g * dot(t1, d.su) - f * dot(t1, d.sv), e * dot(t1, d.sv) - f * dot(t1, d.su)) / det;
            let c2 = vec2<f32>(g * dot(t2, d.su) - f * dot(t2, d.sv), e * dot(t2, d.sv) - f * dot(t2, d.su)) / det;
            let a = c1.x * c1.x * l + 2.0 * c1.x * c1.y * m + c1.y * c1.y * nn;
            let b = c1.x * c2.x * l + (c1.x * c2.y + c2.x * c1.y) * m + c1.y * c2.y * nn;
            let c = c2.x * c2.x * l + 2.0 * c2.x * c2.y * m + c2.y * c2.y * nn;
            let spread = sqrt(0.25 * (a - c) * (a - c) + b * b);
            if analysis.kind == 1u {
                value = gaussian;
            } else if analysis.kind == 2u {
                // −κ of largest magnitude: −(H ± spread), the sign of H choosing.
                value = -(mean + select(-spread, spread, mean >= 0.0));
            } else {
                value = -mean;
            }
        }
        let t = (value - analysis.range_lo) / max(analysis.range_hi - analysis.range_lo, 1e-30);
        let albedo = analysis_ramp(t);
        return vec4<f32>(albedo * (0.45 + 0.55 * diffuse), 1.0);
    }
    // Isophotes: clay-grey shading with a dark line at every whole step of acos(n·L).
    let angle = acos(clamp(dot(n, globals.key_light), -1.0, 1.0)) * analysis.isophotes / 3.14159265;
    let dist = abs(angle - round(angle));
    let aa = max(fwidth(angle), 1e-4);
    let line = 1.0 - smoothstep(0.5 * aa, 1.5 * aa, dist);
    let grey = vec3<f32>(0.78, 0.76, 0.72) * (0.25 + 0.75 * diffuse);
    return vec4<f32>(mix(grey, vec3<f32>(0.03, 0.05, 0.25), line), 1.0);
}
