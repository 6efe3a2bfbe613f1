//! Surface analysis display modes — zebra stripes, curvature map, isophotes — as settings, the
//! GPU data they are drawn from, and the CPU side of their formulas (the fragment shader
//! `modeller/shaders/analysis.wgsl` evaluates the same per pixel; the GPU side is
//! `render::analysis`, with the `gui` feature).
//!
//! All three are computed per pixel from the patch's exact derivatives: each fragment carries
//! its patch index and `(u, v)` (linear on a tessellation triangle, so exact in parameter
//! space), and the shader evaluates `S_u, S_v, S_uu, S_uv, S_vv` of the bicubic from the
//! patch's 16 control points. A coarse tessellation therefore shows no false breaks: what the
//! stripes and colours show is the surface's own normal and curvature.
//!
//! ## Zebra stripes (reflection lines)
//! The environment is a set of light and dark bands around an axis `A` in the screen plane
//! (the stripe direction, angle `θ` from the screen's vertical: `A = cos θ · up + sin θ ·
//! right`). With `e₁` the direction towards the viewer, `e₂ = A × e₁`, the unit normal `n`
//! (turned to the viewer) and the reflected view ray `r = 2 (n·w) n − w` (`w` the unit vector
//! from the point to the eye), the stripe phase is
//!
//! ```text
//! φ = atan2(r·e₂, r·e₁) · s / π,      light where fract(φ) < 1/2,
//! ```
//!
//! so `s` light stripes span 180° of reflected direction (the width control). A G1 seam keeps
//! `n`, so `φ` is continuous across it; a crease of angle `α` turns `r` by up to `2α`, a jump
//! of up to `2α s / 180°` periods ([`zebra_phase`] is the formula, in `f64`).
//!
//! ## Curvature map
//! The curvatures of [`nendo_geom::surface::shape_operator`], shown as convexity (positive on
//! a ball seen from outside): mean `−H`, Gaussian `K`, or the principal curvature of largest
//! magnitude `−κ` ([`CurvatureKind::value`]), mapped linearly from the range `[lo, hi]` onto
//! blue → cyan → yellow → red ([`legend_colour`]).
//!
//! ## Isophotes
//! Curves of constant illumination `n·L` from the key light `L`: the clay shading with a dark
//! line wherever `acos(n·L) · c / π` is a whole number (`c` lines over 180°). Like reflection
//! lines they break at a crease, and they kink where curvature jumps (a G2 break).

use glam::DVec3;

use nendo_geom::surface::shape_operator::{SurfaceCurvature, patch_curvature};
use nendo_geom::surface::{Patch, PatchPoints};

#[cfg(feature = "gui")]
use bytemuck::{Pod, Zeroable};

/// How the surface is coloured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SurfaceMode {
    /// The clay shading (with its overlays: seam heat map, tool footprint).
    #[default]
    Clay,
    /// Reflection lines.
    Zebra,
    /// A curvature map.
    Curvature,
    /// Lines of constant illumination.
    Isophotes,
}

impl SurfaceMode {
    /// Every mode, in the order the panel lists them.
    pub const ALL: [SurfaceMode; 4] = [
        SurfaceMode::Clay,
        SurfaceMode::Zebra,
        SurfaceMode::Curvature,
        SurfaceMode::Isophotes,
    ];

    /// The name on the command line and in the panel.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            SurfaceMode::Clay => "clay",
            SurfaceMode::Zebra => "zebra",
            SurfaceMode::Curvature => "curvature",
            SurfaceMode::Isophotes => "isophotes",
        }
    }

    /// The next mode (the key cycles through them).
    #[must_use]
    pub fn next(self) -> Self {
        let i = Self::ALL.iter().position(|m| *m == self).unwrap_or(0);
        Self::ALL[(i + 1) % Self::ALL.len()]
    }

    /// The shader's mode number (0 is clay: the analysis pass does not draw).
    fn code(self) -> u32 {
        match self {
            SurfaceMode::Clay => 0,
            SurfaceMode::Zebra => 1,
            SurfaceMode::Curvature => 2,
            SurfaceMode::Isophotes => 3,
        }
    }
}

impl std::str::FromStr for SurfaceMode {
    type Err = UnknownDisplayName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == s.trim())
            .ok_or_else(|| UnknownDisplayName {
                value: s.to_owned(),
                expected: "clay, zebra, curvature or isophotes",
            })
    }
}

impl std::fmt::Display for SurfaceMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Which curvature the map shows (signs: see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CurvatureKind {
    /// Mean curvature, as convexity `−H`.
    #[default]
    Mean,
    /// Gaussian curvature `K`.
    Gaussian,
    /// The principal curvature of largest magnitude, as convexity `−κ`.
    MaxPrincipal,
}

impl CurvatureKind {
    /// Every kind, in the order the panel lists them.
    pub const ALL: [CurvatureKind; 3] = [
        CurvatureKind::Mean,
        CurvatureKind::Gaussian,
        CurvatureKind::MaxPrincipal,
    ];

    /// The name on the command line and in the panel.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            CurvatureKind::Mean => "mean",
            CurvatureKind::Gaussian => "gaussian",
            CurvatureKind::MaxPrincipal => "max",
        }
    }

    /// The value the map shows for these curvatures.
    #[must_use]
    pub fn value(self, c: &SurfaceCurvature) -> f64 {
        match self {
            CurvatureKind::Mean => -c.mean,
            CurvatureKind::Gaussian => c.gaussian,
            CurvatureKind::MaxPrincipal => -c.max_abs_principal(),
        }
    }

    fn code(self) -> u32 {
        match self {
            CurvatureKind::Mean => 0,
            CurvatureKind::Gaussian => 1,
            CurvatureKind::MaxPrincipal => 2,
        }
    }
}

impl std::str::FromStr for CurvatureKind {
    type Err = UnknownDisplayName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == s.trim())
            .ok_or_else(|| UnknownDisplayName {
                value: s.to_owned(),
                expected: "mean, gaussian or max",
            })
    }
}

impl std::fmt::Display for CurvatureKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A display mode or curvature name that is not one.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{value:?}: expected {expected}")]
pub struct UnknownDisplayName {
    /// What was given.
    pub value: String,
    /// What is accepted.
    pub expected: &'static str,
}

/// The settings of the analysis display.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceAnalysis {
    /// The mode.
    pub mode: SurfaceMode,
    /// Stripe direction, degrees from the screen's vertical.
    pub stripe_angle_deg: f32,
    /// Light stripes per 180° of reflected direction (more: narrower stripes).
    pub stripes: f32,
    /// The curvature the map shows.
    pub kind: CurvatureKind,
    /// The map's range `[lo, hi]` (1 / model units; squared for Gaussian).
    pub range: [f32; 2],
    /// Isophote lines per 180° of light angle.
    pub isophotes: f32,
    /// The clay's seam heat map shows the relative G2 (curvature) mismatch across the seams,
    /// in percent, instead of the G1 angle ([`nendo_geom::mesh::seam_g2_percent`]).
    pub seam_g2: bool,
    /// The G2 mismatch drawn red by the heat map, percent.
    pub g2_red_percent: f32,
}

impl Default for SurfaceAnalysis {
    fn default() -> Self {
        Self {
            mode: SurfaceMode::Clay,
            stripe_angle_deg: 0.0,
            stripes: 12.0,
            kind: CurvatureKind::Mean,
            range: [-1.0, 1.0],
            isophotes: 18.0,
            seam_g2: false,
            g2_red_percent: 10.0,
        }
    }
}

/// The analysis pass's uniform (`@group(1) @binding(0)`). Keep in sync with `struct Analysis`
/// in `modeller/shaders/analysis.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "gui", derive(Pod, Zeroable))]
pub struct AnalysisUniform {
    /// `e₁`: towards the viewer.
    pub e1: [f32; 3],
    /// [`SurfaceMode`] code: 1 zebra, 2 curvature, 3 isophotes.
    pub mode: u32,
    /// `e₂ = A × e₁`.
    pub e2: [f32; 3],
    /// [`CurvatureKind`] code: 0 mean, 1 Gaussian, 2 largest principal.
    pub kind: u32,
    /// Light stripes per 180°.
    pub stripes: f32,
    /// Curvature at the blue end.
    pub range_lo: f32,
    /// Curvature at the red end.
    pub range_hi: f32,
    /// Isophote lines per 180°.
    pub isophotes: f32,
}
const _: () = assert!(std::mem::size_of::<AnalysisUniform>() == 48);

/// Per vertex of the tessellation, what the analysis pass adds to [`super::gpu_data::SurfaceVertex`]:
/// its patch and parameters. Keep in sync with `AnalysisIn` in `modeller/shaders/analysis.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "gui", derive(Pod, Zeroable))]
pub struct AnalysisVertex {
    /// Patch index (into the control point buffer, 16 points each).
    pub patch: u32,
    /// `(u, v)` of the vertex in its patch.
    pub uv: [f32; 2],
}
const _: () = assert!(std::mem::size_of::<AnalysisVertex>() == 12);

#[cfg(feature = "gui")]
impl AnalysisVertex {
    /// Vertex attributes at locations 3, 4 (after `SurfaceVertex`'s 0–2).
    pub const ATTRIBUTES: [wgpu::VertexAttribute; 2] =
        wgpu::vertex_attr_array![3 => Uint32, 4 => Float32x2];
}

/// The analysis vertices of a tessellation: patch and `(u, v)` of every vertex, from its
/// blocks (empty for a mesh without blocks, which the analysis pass then does not draw).
#[must_use]
pub fn analysis_vertices(mesh: &crate::mesh::TriMesh) -> Vec<AnalysisVertex> {
    let mut out = vec![
        AnalysisVertex {
            patch: 0,
            uv: [0.0, 0.0]
        };
        mesh.positions.len()
    ];
    for b in &mesh.blocks {
        for vertex in b.first_vertex..b.first_vertex + b.vertex_count() {
            let (u, v) = b.uv_of(vertex);
            if let Some(slot) = out.get_mut(vertex as usize) {
                *slot = AnalysisVertex {
                    patch: b.patch,
                    uv: [u as f32, v as f32],
                };
            }
        }
    }
    if mesh.blocks.is_empty() {
        out.clear();
    }
    out
}

/// The control points as the shader reads them: 16 `vec4`s per patch, `P[4i + j]` in the
/// order of [`PatchPoints`] (`w` unused).
#[must_use]
pub fn patch_points_f32(patches: &[PatchPoints]) -> Vec<[f32; 4]> {
    patches
        .iter()
        .flat_map(|p| p.iter().map(|x| [x.x as f32, x.y as f32, x.z as f32, 0.0]))
        .collect()
}

impl SurfaceAnalysis {
    /// The uniform for a camera `world_from_view` (its x axis is the screen's right, y its
    /// up, z towards the viewer).
    #[must_use]
    pub fn uniform(&self, world_from_view: glam::Mat4) -> AnalysisUniform {
        let (e1, e2) = zebra_basis(world_from_view, self.stripe_angle_deg);
        AnalysisUniform {
            e1: e1.as_vec3().to_array(),
            mode: self.mode.code(),
            e2: e2.as_vec3().to_array(),
            kind: self.kind.code(),
            stripes: self.stripes.max(0.5),
            range_lo: self.range[0],
            range_hi: self.range[1],
            isophotes: self.isophotes.max(1.0),
        }
    }
}

/// `(e₁, e₂)` of the stripe environment (module docs) for a camera and a stripe angle.
#[must_use]
pub fn zebra_basis(world_from_view: glam::Mat4, angle_deg: f32) -> (DVec3, DVec3) {
    let right = world_from_view.x_axis.truncate().as_dvec3();
    let up = world_from_view.y_axis.truncate().as_dvec3();
    let back = world_from_view.z_axis.truncate().as_dvec3();
    let t = f64::from(angle_deg).to_radians();
    let axis = (up * t.cos() + right * t.sin()).normalize_or(DVec3::Z);
    let e1 = back.normalize_or(DVec3::Z);
    (e1, axis.cross(e1).normalize_or(DVec3::X))
}

/// The zebra stripe phase `φ` (module docs) at a point with unit normal `n`, seen from `eye`;
/// `n` is turned towards the eye first.
#[must_use]
pub fn zebra_phase(point: DVec3, n: DVec3, eye: DVec3, basis: (DVec3, DVec3), stripes: f64) -> f64 {
    let w = (eye - point).normalize_or(DVec3::Z);
    let n = if n.dot(w) < 0.0 { -n } else { n };
    let r = 2.0 * n.dot(w) * n - w;
    r.dot(basis.1).atan2(r.dot(basis.0)) * stripes / std::f64::consts::PI
}

/// The map's colour at `t ∈ [0, 1]`: blue → cyan → yellow → red (the legend's ramp; the
/// shader's `analysis_ramp`).
#[must_use]
pub fn legend_colour(t: f32) -> [f32; 3] {
    let stops = [
        [0.05, 0.15, 0.85],
        [0.0, 0.75, 0.8],
        [0.95, 0.85, 0.1],
        [0.9, 0.05, 0.02],
    ];
    let t = t.clamp(0.0, 1.0) * 3.0;
    let i = (t.floor() as usize).min(2);
    let f = t - i as f32;
    let (a, b) = (stops[i], stops[i + 1]);
    // WGSL's `mix`: `a (1 − f) + b f`, exactly the stops at f = 0 and 1.
    [
        a[0] * (1.0 - f) + b[0] * f,
        a[1] * (1.0 - f) + b[1] * f,
        a[2] * (1.0 - f) + b[2] * f,
    ]
}

/// A range for the curvature map: the 2nd to 98th percentile of the value over 5 × 5 points
/// inside every patch (widened around a constant value), or `None` without any regular point.
#[must_use]
pub fn auto_range(patches: &[PatchPoints], kind: CurvatureKind) -> Option<[f32; 2]> {
    let mut values: Vec<f64> = Vec::with_capacity(patches.len() * 25);
    for points in patches {
        let p = Patch::new(*points);
        for i in 0..5 {
            for j in 0..5 {
                let (u, v) = (0.1 + 0.2 * f64::from(i), 0.1 + 0.2 * f64::from(j));
                if let Some(c) = patch_curvature(&p, u, v) {
                    let x = kind.value(&c);
                    if x.is_finite() {
                        values.push(x);
                    }
                }
            }
        }
    }
    if values.is_empty() {
        return None;
    }
    values.sort_by(f64::total_cmp);
    let at = |q: f64| values[((values.len() - 1) as f64 * q).round() as usize];
    let (lo, hi) = (at(0.02), at(0.98));
    let spread = hi - lo;
    let floor = 0.25 * lo.abs().max(hi.abs()).max(1e-9);
    Some(if spread < floor {
        let mid = 0.5 * (lo + hi);
        [(mid - floor) as f32, (mid + floor) as f32]
    } else {
        [lo as f32, hi as f32]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_bad_ones_fail_with_the_choices() {
        for m in SurfaceMode::ALL {
            assert_eq!(m.name().parse::<SurfaceMode>().ok(), Some(m));
        }
        for k in CurvatureKind::ALL {
            assert_eq!(k.name().parse::<CurvatureKind>().ok(), Some(k));
        }
        let e = "stripes".parse::<SurfaceMode>().unwrap_err();
        assert_eq!(
            e.to_string(),
            "\"stripes\": expected clay, zebra, curvature or isophotes"
        );
        assert_eq!(SurfaceMode::Isophotes.next(), SurfaceMode::Clay);
    }

    #[test]
    fn legend_runs_from_blue_to_red() {
        assert_eq!(legend_colour(0.0), [0.05, 0.15, 0.85]);
        assert_eq!(legend_colour(1.0), [0.9, 0.05, 0.02]);
        assert_eq!(legend_colour(-3.0), legend_colour(0.0));
    }
}
