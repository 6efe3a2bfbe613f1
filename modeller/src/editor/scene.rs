//! Turning the document into what the renderer draws: the tessellated surface with its seam
//! angles, patch boundaries, the control net, curves with their control polygons, the hand and
//! the probe sphere. Shared by the window and `nendo render`.

use glam::{DVec3, Vec3};
use std::time::Instant;

use crate::curve::json::DynCurve;
use crate::curve::{Curve, Point};
use crate::mesh::{PatchPoints, Tessellation, TriMesh, seam_angles_deg, seam_bands, tessellate};
use crate::model::Model;
use crate::render::{LineBatch, Rgba};
use crate::surface::Grid;

/// What to draw besides the clay.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Overlays {
    /// Patch boundaries as lines (off by default in the window: after refinement they are
    /// dense bands across the model that read as stripes on the clay; the Display panel's
    /// "patch boundaries" shows them, the lines refinement made fainter than the primitive's).
    pub patch_edges: bool,
    /// The control net of the patches.
    pub control_net: bool,
    /// The G1 heat map along seams.
    pub heat_map: bool,
    /// Seam angle drawn red, degrees.
    pub heat_max_deg: f32,
    /// Curves' control polygons.
    pub control_polygons: bool,
}

impl Default for Overlays {
    fn default() -> Self {
        Self {
            patch_edges: false,
            control_net: false,
            heat_map: false,
            heat_max_deg: 1.0,
            control_polygons: true,
        }
    }
}

/// The tessellated surface and what was measured while making it.
#[derive(Debug, Clone, Default)]
pub struct SurfaceDisplay {
    /// The tessellation (with its patch blocks, for picking).
    pub mesh: TriMesh,
    /// Seam heat per vertex, `[angle°, weight]` (see [`seam_bands`]).
    pub seam_heat: Vec<[f32; 2]>,
    /// Largest seam angle, degrees.
    pub max_seam_deg: f32,
    /// Time spent tessellating, milliseconds.
    pub tessellate_ms: f64,
}

impl SurfaceDisplay {
    /// Width of the heat band on each side of a seam, as a fraction of the patch.
    pub const HEAT_BAND: f32 = 0.15;

    /// Tessellates `patches` and measures the seams.
    #[must_use]
    pub fn new(patches: &[PatchPoints], tessellation: &Tessellation) -> Self {
        let start = Instant::now();
        let mesh = tessellate(patches, tessellation);
        let tessellate_ms = start.elapsed().as_secs_f64() * 1e3;
        let seam_deg = seam_angles_deg(patches, &mesh);
        let max_seam_deg = seam_deg.iter().copied().fold(0.0, f32::max);
        let seam_heat = seam_bands(&mesh, &seam_deg, Self::HEAT_BAND);
        Self {
            mesh,
            seam_heat,
            max_seam_deg,
            tessellate_ms,
        }
    }

    /// Adds the patch boundaries (the tessellation's own edge vertices, so the lines lie exactly
    /// on the drawn surface), all as the primitive's own lines.
    pub fn patch_edges(&self, lines: &mut LineBatch) {
        self.edges(None, lines);
    }

    /// Adds the patch boundaries of `grid` (this display's tessellation of it), the lines
    /// refinement made ([`crate::surface::Grid::refined_u`]) fainter ([`Rgba::REFINED_EDGE`])
    /// than the primitive's own ([`Rgba::PATCH_EDGE`]). A tessellation of other patches than
    /// the grid's (a stroke's refinement not yet shown) draws every line as the primitive's.
    pub fn grid_edges(&self, grid: &Grid, lines: &mut LineBatch) {
        self.edges(Some(grid), lines);
    }

    fn edges(&self, grid: Option<&Grid>, lines: &mut LineBatch) {
        let grid = grid.filter(|g| g.patch_count() == self.mesh.blocks.len());
        // The colour of u line `k` (v line `q` with `along_v`), wrapping round a closed grid.
        let colour = |along_v: bool, k: usize| {
            let refined = grid.is_some_and(|g| {
                let marks = if along_v {
                    g.refined_v()
                } else {
                    g.refined_u()
                };
                !marks.is_empty() && marks[k % marks.len()]
            });
            if refined {
                Rgba::REFINED_EDGE
            } else {
                Rgba::PATCH_EDGE
            }
        };
        let columns = grid.map_or(1, Grid::patches_u);
        let at = |v: u32| self.mesh.positions[v as usize];
        for b in &self.mesh.blocks {
            let (iu, iv) = (b.patch as usize % columns, b.patch as usize / columns);
            lines.polyline((0..=b.m_u).map(|k| at(b.vertex(k, 0))), colour(true, iv));
            lines.polyline(
                (0..=b.m_u).map(|k| at(b.vertex(k, b.m_v))),
                colour(true, iv + 1),
            );
            lines.polyline((0..=b.m_v).map(|l| at(b.vertex(0, l))), colour(false, iu));
            lines.polyline(
                (0..=b.m_v).map(|l| at(b.vertex(b.m_u, l))),
                colour(false, iu + 1),
            );
        }
    }
}

/// Adds the control net of `patches`: every row and column of each patch's 4 × 4 points.
pub fn control_net(patches: &[PatchPoints], lines: &mut LineBatch) {
    for p in patches {
        for a in 0..4 {
            lines.polyline((0..4).map(|b| p[4 * a + b].as_vec3()), Rgba::CONTROL_NET);
            lines.polyline((0..4).map(|b| p[4 * b + a].as_vec3()), Rgba::CONTROL_NET);
        }
    }
}

/// Adds a curve drawn through `samples` and, optionally, its control polygon.
pub fn curve(samples: &[DVec3], control: Option<&[DVec3]>, highlight: bool, lines: &mut LineBatch) {
    let colour = if highlight {
        Rgba::HIGHLIGHT
    } else {
        Rgba::CURVE
    };
    lines.polyline(samples.iter().map(|p| p.as_vec3()), colour);
    if let Some(control) = control {
        lines.polyline(control.iter().map(|p| p.as_vec3()), Rgba::CONTROL_POLYGON);
    }
}

/// The colour of the mirror plane's outline.
pub const MIRROR_PLANE: Rgba = Rgba([0.3, 0.8, 1.0, 0.55]);

/// Outlines the mirror plane across the model's box `lo..hi` (enlarged by a tenth of its
/// diagonal each way, so a flat model still shows a rectangle), with a cross through it:
/// the lines are depth-tested, so the clay hides the parts behind it.
pub fn mirror_plane(plane: crate::surface::Plane, lo: Vec3, hi: Vec3, lines: &mut LineBatch) {
    let margin = Vec3::splat(0.1 * (hi - lo).length().max(1e-3));
    let (lo, hi) = (lo - margin, hi + margin);
    let k = plane.axis();
    // The two in-plane axes.
    let (a, b) = ((k + 1) % 3, (k + 2) % 3);
    let point = |s: f32, t: f32| {
        let mut p = Vec3::ZERO;
        p[a] = lo[a] + s * (hi[a] - lo[a]);
        p[b] = lo[b] + t * (hi[b] - lo[b]);
        p
    };
    lines.polyline(
        [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.0, 0.0)].map(|(s, t)| point(s, t)),
        MIRROR_PLANE,
    );
    lines.segment(point(0.5, 0.0), point(0.5, 1.0), MIRROR_PLANE);
    lines.segment(point(0.0, 0.5), point(1.0, 0.5), MIRROR_PLANE);
}

/// Draws a symmetry across the model's box `lo..hi`: each mirror plane ([`mirror_plane`]) and,
/// with radial symmetry or the lathe, the z axis (the turns' axis) through the box, with a
/// spoke on the box's bottom for each of the `N` turns.
pub fn symmetry(spec: &crate::surface::SymmetrySpec, lo: Vec3, hi: Vec3, lines: &mut LineBatch) {
    for &plane in &spec.planes {
        mirror_plane(plane, lo, hi, lines);
    }
    if spec.radial <= 1 && !spec.lathe {
        return;
    }
    let margin = 0.1 * (hi - lo).length().max(1e-3);
    let (bottom, top) = (lo.z - margin, hi.z + margin);
    lines.segment(
        Vec3::new(0.0, 0.0, bottom),
        Vec3::new(0.0, 0.0, top),
        MIRROR_PLANE,
    );
    let reach = lo.x.abs().max(hi.x.abs()).max(lo.y.abs()).max(hi.y.abs()) + margin;
    // The lathe's N is the patch columns (not known here): 24 spokes stand for "all round".
    let n = if spec.lathe { 24 } else { spec.radial.min(64) };
    for k in 0..n {
        let a = std::f32::consts::TAU * k as f32 / n as f32;
        lines.segment(
            Vec3::new(0.0, 0.0, bottom),
            Vec3::new(reach * a.cos(), reach * a.sin(), bottom),
            MIRROR_PLANE,
        );
    }
}

/// The bounds of `mesh` and of extra points (curves), `None` when there is nothing.
#[must_use]
pub fn scene_bounds(mesh: &TriMesh, extra: &[DVec3]) -> Option<(Vec3, Vec3)> {
    let extra = extra.iter().map(|p| p.as_vec3());
    let mut all = mesh.positions.iter().copied().chain(extra);
    let first = all.next()?;
    Some(all.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
}

/// The points a camera framing the drawn model must see: the surface, the curves' control
/// points and, when the control net is drawn, the patches' control points (which can stand
/// well off the surface).
#[must_use]
pub fn framing_points(
    model: &Model,
    patches: &[PatchPoints],
    display: &SurfaceDisplay,
    overlays: &Overlays,
) -> Vec<Vec3> {
    let mut points = display.mesh.positions.clone();
    for c in &model.curves {
        points.extend(curve_control_points(c).into_iter().map(|p| p.as_vec3()));
    }
    if overlays.control_net {
        points.extend(patches.iter().flatten().map(|p| p.as_vec3()));
    }
    points
}

/// Adds the lines of a model: patch boundaries, the control net, and the curves with their
/// control polygons, as `overlays` asks.
pub fn model_lines(
    model: &Model,
    patches: &[PatchPoints],
    display: &SurfaceDisplay,
    overlays: &Overlays,
    lines: &mut LineBatch,
) {
    if overlays.patch_edges {
        display.grid_edges(&model.surface, lines);
    }
    if overlays.control_net {
        control_net(patches, lines);
    }
    for c in &model.curves {
        let samples = curve_samples(c, 24);
        let control = curve_control_points(c);
        curve(
            &samples,
            overlays.control_polygons.then_some(control.as_slice()),
            false,
            lines,
        );
    }
}

/// Points along a curve, `per_segment` per Bezier segment (2D curves in the plane z = 0).
#[must_use]
pub fn curve_samples(c: &DynCurve, per_segment: usize) -> Vec<DVec3> {
    fn samples<P: Point>(
        c: &Curve<P>,
        per_segment: usize,
        lift: impl Fn(P) -> DVec3,
    ) -> Vec<DVec3> {
        let per_segment = per_segment.max(1);
        let segments = c.segments();
        let mut out = Vec::with_capacity(segments.len() * per_segment + 1);
        for (k, seg) in segments.iter().enumerate() {
            let first = if k == 0 { 0 } else { 1 };
            for i in first..=per_segment {
                out.push(lift(seg.bezier.eval(i as f64 / per_segment as f64)));
            }
        }
        out
    }
    match c {
        DynCurve::D2(c) => samples(c, per_segment, |p| p.extend(0.0)),
        DynCurve::D3(c) => samples(c, per_segment, |p| p),
    }
}

/// The control points of a curve (2D curves in the plane z = 0).
#[must_use]
pub fn curve_control_points(c: &DynCurve) -> Vec<DVec3> {
    match c {
        DynCurve::D2(c) => c.points().iter().map(|p| p.extend(0.0)).collect(),
        DynCurve::D3(c) => c.points().to_vec(),
    }
}
