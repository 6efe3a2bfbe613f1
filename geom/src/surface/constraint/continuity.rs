//! How continuous a grid is (docs/design.md §14): the G0 gap and the G1 angle along every shared edge,
//! and the tangent-plane spread at every pole.
//!
//! - **G0 gap**: the largest distance between the two patches' evaluations of the points of a
//!   shared edge (zero up to rounding: the net is shared).
//! - **G1 angle**: at `k` points along each shared edge (closed seams included), the angle
//!   between the unit normals of the two patches, `atan2(|n₁ × n₂|, n₁·n₂)`, in degrees; the
//!   maximum and the mean over all points. Points where a side has no tangent plane are
//!   counted apart ([`ContinuityReport::undefined_normals`]). At the pole end of a meridian
//!   the normals are the limits of [`crate::surface::Patch::normal`].
//! - **Pole spread**: the first-derivative directions out of the pole, `±S_v(u, pole)` at `k`
//!   parameters on every patch around it, fitted by a plane through the pole (least squares);
//!   the spread is the largest angle of a direction out of that plane, in degrees (0 when the
//!   pole has a true tangent plane).

use glam::DVec3;

use crate::surface::grid::Grid;
use crate::surface::group::PoleEnd;
use crate::surface::patch::Patch;
use crate::surface::plane_fit::plane_normal;

/// The smallest number of points per edge the measures use (docs/design.md §14 asks for ≥ 33).
pub const MIN_SAMPLES_PER_EDGE: usize = 33;

/// The continuity of a grid.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuityReport {
    /// Number of patches.
    pub patches: usize,
    /// Number of patch edges shared by two patches (closed seams included).
    pub shared_edges: usize,
    /// Points per shared edge.
    pub samples_per_edge: usize,
    /// Largest G0 gap along shared edges (side).
    pub g0_gap: f64,
    /// Largest angle between the normals of the two sides of a shared edge (degrees).
    pub g1_max_deg: f64,
    /// Mean of that angle over all points of all shared edges (degrees).
    pub g1_mean_deg: f64,
    /// Points where one side had no tangent plane (left out of the G1 figures).
    pub undefined_normals: usize,
    /// Every pole.
    pub poles: Vec<PoleReport>,
}

/// The tangent plane at one pole.
#[derive(Debug, Clone, PartialEq)]
pub struct PoleReport {
    /// Which end.
    pub end: PoleEnd,
    /// The pole's position.
    pub position: DVec3,
    /// The unit normal of the best-fit tangent plane (oriented like the surface's normals);
    /// `None` when the pole has no first-derivative direction at all.
    pub normal: Option<DVec3>,
    /// Largest angle of a first-derivative direction out of that plane (degrees).
    pub spread_deg: f64,
}

/// Angle between two unit vectors in degrees, accurate for small angles.
#[must_use]
pub fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// Measures a grid with `samples_per_edge` points per shared edge (raised to
/// [`MIN_SAMPLES_PER_EDGE`]).
#[must_use]
pub fn report(grid: &Grid, samples_per_edge: usize) -> ContinuityReport {
    let k = samples_per_edge.max(MIN_SAMPLES_PER_EDGE);
    let (m, n) = (grid.patches_u(), grid.patches_v());
    let patches: Vec<Patch> = (0..grid.patch_count())
        .map(|p| grid.patch_struct(p))
        .collect();
    let mut r = ContinuityReport {
        patches: grid.patch_count(),
        shared_edges: 0,
        samples_per_edge: k,
        g0_gap: 0.0,
        g1_max_deg: 0.0,
        g1_mean_deg: 0.0,
        undefined_normals: 0,
        poles: Vec::new(),
    };
    let mut sum = 0.0;
    let mut count = 0usize;
    let mut edge = |a: &Patch, b: &Patch, along_u: bool, r: &mut ContinuityReport| {
        r.shared_edges += 1;
        for i in 0..k {
            let t = i as f64 / (k - 1) as f64;
            // Across a u-edge: a at u = 1, b at u = 0; across a v-edge: a at v = 1, b at v = 0.
            let ((ua, va), (ub, vb)) = if along_u {
                ((1.0, t), (0.0, t))
            } else {
                ((t, 1.0), (t, 0.0))
            };
            r.g0_gap = r.g0_gap.max((a.eval(ua, va) - b.eval(ub, vb)).length());
            match (a.normal(ua, va), b.normal(ub, vb)) {
                (Some(na), Some(nb)) => {
                    let angle = angle_deg(na, nb);
                    r.g1_max_deg = r.g1_max_deg.max(angle);
                    sum += angle;
                    count += 1;
                }
                _ => r.undefined_normals += 1,
            }
        }
    };
    for kk in 0..grid.vertices_u() {
        if !grid.u_line_shared(kk) {
            continue;
        }
        for iv in 0..n {
            let left = (kk + m - 1) % m;
            let right = kk % m;
            edge(
                &patches[iv * m + left],
                &patches[iv * m + right],
                true,
                &mut r,
            );
        }
    }
    for q in 0..grid.vertices_v() {
        if !grid.v_line_shared(q) {
            continue;
        }
        for iu in 0..m {
            let below = (q + n - 1) % n;
            let above = q % n;
            edge(
                &patches[below * m + iu],
                &patches[above * m + iu],
                false,
                &mut r,
            );
        }
    }
    r.g1_mean_deg = if count > 0 { sum / count as f64 } else { 0.0 };
    for pole in grid.poles() {
        r.poles.push(pole_report(grid, &patches, pole.end, k));
    }
    r
}

/// The first-derivative directions out of a pole (unit vectors) at `k` parameters per patch,
/// and a surface normal next to the pole for orientation.
pub(crate) fn pole_directions(grid: &Grid, end: PoleEnd, k: usize) -> (Vec<DVec3>, DVec3) {
    let (m, n) = (grid.patches_u(), grid.patches_v());
    let (iv, v, sign) = if end == PoleEnd::Start {
        (0, 0.0, 1.0)
    } else {
        (n - 1, 1.0, -1.0)
    };
    let mut dirs = Vec::with_capacity(m * k);
    let mut orient = DVec3::ZERO;
    for iu in 0..m {
        let p = grid.patch_struct(iv * m + iu);
        for i in 0..k {
            let u = i as f64 / (k - 1).max(1) as f64;
            if let Some(d) = (p.frame(u, v).dv * sign).try_normalize() {
                dirs.push(d);
            }
        }
        if let Some(nrm) = p.normal(0.5, if end == PoleEnd::Start { 0.05 } else { 0.95 }) {
            orient += nrm;
        }
    }
    (dirs, orient)
}

fn pole_report(grid: &Grid, _patches: &[Patch], end: PoleEnd, k: usize) -> PoleReport {
    let node = grid.pole(end).map(|p| p.node).unwrap_or_default();
    let position = grid.nodes()[node];
    let (dirs, orient) = pole_directions(grid, end, k);
    let Some(mut normal) = plane_normal(dirs.iter().copied()) else {
        return PoleReport {
            end,
            position,
            normal: None,
            spread_deg: 0.0,
        };
    };
    if normal.dot(orient) < 0.0 {
        normal = -normal;
    }
    let spread_deg = dirs
        .iter()
        .map(|d| d.dot(normal).abs().min(1.0).asin().to_degrees())
        .fold(0.0, f64::max);
    PoleReport {
        end,
        position,
        normal: Some(normal),
        spread_deg,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::primitive::{Primitive, PrimitiveParams};

    #[test]
    fn primitives_are_g1_with_smooth_poles() {
        for p in Primitive::ALL {
            let g = p.build(&PrimitiveParams::default()).unwrap();
            let r = report(&g, 33);
            assert_eq!(r.g0_gap, 0.0, "{p}");
            assert!(r.g1_max_deg < 1e-9, "{p}: {}", r.g1_max_deg);
            assert_eq!(r.undefined_normals, 0, "{p}");
            assert_eq!(r.poles.len(), p.topology().pole_count());
            for pole in &r.poles {
                assert!(pole.spread_deg < 1e-9, "{p}: {pole:?}");
            }
        }
    }

    #[test]
    fn shared_edges_are_counted_per_topology() {
        let count = |p: Primitive, m: usize, n: usize| {
            let g = p
                .build(&PrimitiveParams {
                    patches: Some((m, n)),
                    ..PrimitiveParams::default()
                })
                .unwrap();
            report(&g, 33).shared_edges
        };
        assert_eq!(count(Primitive::Plane, 10, 10), 2 * 9 * 10);
        assert_eq!(count(Primitive::Cylinder, 8, 4), 8 * 4 + 8 * 3);
        assert_eq!(count(Primitive::Hemisphere, 8, 2), 8 * 2 + 8);
        assert_eq!(count(Primitive::Sphere, 8, 4), 8 * 4 + 8 * 3);
        assert_eq!(count(Primitive::Torus, 8, 4), 2 * 8 * 4);
    }

    #[test]
    fn a_kinked_net_is_measured() {
        let mut g = Primitive::Plane
            .build(&PrimitiveParams {
                patches: Some((2, 1)),
                ..PrimitiveParams::default()
            })
            .unwrap();
        // Lift the column just right of the shared edge: a crease along it.
        for b in 0..4 {
            let id = g.node_id(4, b).unwrap();
            g.nodes_mut()[id].z += 1.0 / 3.0;
        }
        let r = report(&g, 33);
        assert!((r.g1_max_deg - 45.0).abs() < 1e-9, "{}", r.g1_max_deg);
    }
}
