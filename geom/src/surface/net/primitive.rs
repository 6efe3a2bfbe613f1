//! The starting shapes: plane, cylinder, hemisphere, sphere, torus and the "test tube" of the
//! paper's Fig. 15 (units: side; normals `S_u × S_v` point outward, +z for the plane).
//!
//! Round shapes are built from circular arcs, each arc of angle `θ` drawn as the cubic with
//! handles of length `h = 4/3·tan(θ/4)` along the end tangents (exact at both ends and the
//! middle; the radial error is at most about `θ⁶/(2¹¹·3³)` of the radius: 4.2·10⁻⁶ at θ = 45°,
//! 2.7·10⁻⁴ at 90°). A surface
//! of revolution of a meridian `(ρ(v), z(v))` around the approximate circle `c(u)` is exactly
//! the tensor product of their control points, `P(a,b) = (ρ_b·c_a, z_b)`, so the sphere,
//! hemisphere, tube and torus are built that way. At a pole the first ring of control points
//! lies in the plane of the pole (the pole starts smooth).
//!
//! | primitive | topology | parametrisation |
//! |---|---|---|
//! | plane | plane | `M × N` unit squares centred on the origin in `z = 0`, `u` along +x, `v` along +y |
//! | cylinder | cylinder | radius R around z, `u` anticlockwise seen from +z, `v` from `z = 0` up to `z = H` |
//! | hemisphere | hemisphere | radius R, pole on +z at `v = 0`, rim in `z = 0` at `v = N`, `u` clockwise seen from +z |
//! | sphere | sphere | radius R about the origin, `v` from the pole on −z to the pole on +z, `u` anticlockwise |
//! | torus | torus | major radius R around z, minor r; `u` anticlockwise, `v` around the tube from the outer equator, upward first |
//! | tube | hemisphere | a round bottom of radius R (pole at the origin, `v = 0`) and straight walls of height H above it |

use glam::{DVec2, DVec3};
use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::fmt;
use std::str::FromStr;

use crate::surface::error::SurfaceError;
use crate::surface::grid::Grid;
use crate::surface::topology::Topology;

/// A starting shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Primitive {
    /// A flat grid of unit squares.
    Plane,
    /// An open cylinder.
    Cylinder,
    /// A hemisphere (a pole and a rim).
    Hemisphere,
    /// A sphere (two poles).
    Sphere,
    /// A torus.
    Torus,
    /// A "test tube": a round bottom and straight walls (hemisphere topology).
    Tube,
}

/// The size parameters of a primitive; `None` takes the default of [`Primitive::defaults`].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PrimitiveParams {
    /// Patch counts `(M, N)`.
    pub patches: Option<(usize, usize)>,
    /// Radius R (the major radius for a torus).
    pub radius: Option<f64>,
    /// Height H (cylinder; the walls of the tube).
    pub height: Option<f64>,
    /// Minor radius r (torus).
    pub minor_radius: Option<f64>,
}

/// A size parameter of [`PrimitiveParams`] (the patch counts shape every primitive; these
/// only some, see [`Primitive::uses`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PrimitiveSize {
    /// The radius R (the major radius of a torus).
    Radius,
    /// The height H.
    Height,
    /// The minor radius r.
    MinorRadius,
}

impl PrimitiveSize {
    /// Every size parameter.
    pub const ALL: [PrimitiveSize; 3] = [
        PrimitiveSize::Radius,
        PrimitiveSize::Height,
        PrimitiveSize::MinorRadius,
    ];
}

/// Fully resolved parameters of a primitive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resolved {
    /// Patch counts `(M, N)`.
    pub patches: (usize, usize),
    /// Radius R.
    pub radius: f64,
    /// Height H.
    pub height: f64,
    /// Minor radius r.
    pub minor_radius: f64,
}

impl Primitive {
    /// Every primitive.
    pub const ALL: [Primitive; 6] = [
        Primitive::Plane,
        Primitive::Cylinder,
        Primitive::Hemisphere,
        Primitive::Sphere,
        Primitive::Torus,
        Primitive::Tube,
    ];

    /// The name used on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Primitive::Plane => "plane",
            Primitive::Cylinder => "cylinder",
            Primitive::Hemisphere => "hemisphere",
            Primitive::Sphere => "sphere",
            Primitive::Torus => "torus",
            Primitive::Tube => "tube",
        }
    }

    /// The connection topology of the primitive.
    #[must_use]
    pub fn topology(self) -> Topology {
        match self {
            Primitive::Plane => Topology::Plane,
            Primitive::Cylinder => Topology::Cylinder,
            Primitive::Hemisphere | Primitive::Tube => Topology::Hemisphere,
            Primitive::Sphere => Topology::Sphere,
            Primitive::Torus => Topology::Torus,
        }
    }

    /// The defaults: plane 10 × 10; cylinder 8 × 4, R 3, H 4; hemisphere 8 × 2, R 3; sphere
    /// 8 × 4, R 3 (the paper's); torus 8 × 4, R 3, r 1; tube 16 × 8 (128 patches, the paper's
    /// Fig. 15 start), R 2, walls H 4.
    #[must_use]
    pub fn defaults(self) -> Resolved {
        let (patches, radius, height) = match self {
            Primitive::Plane => ((10, 10), 1.0, 1.0),
            Primitive::Cylinder => ((8, 4), 3.0, 4.0),
            Primitive::Hemisphere => ((8, 2), 3.0, 3.0),
            Primitive::Sphere => ((8, 4), 3.0, 6.0),
            Primitive::Torus => ((8, 4), 3.0, 2.0),
            Primitive::Tube => ((16, 8), 2.0, 4.0),
        };
        Resolved {
            patches,
            radius,
            height,
            minor_radius: 1.0,
        }
    }

    /// Whether `size` shapes the primitive, as [`Primitive::build`] uses it: the radius every
    /// primitive but the plane, the height the cylinder and the tube (its walls), the minor
    /// radius the torus. The others are only checked, never used.
    #[must_use]
    pub fn uses(self, size: PrimitiveSize) -> bool {
        match size {
            PrimitiveSize::Radius => self != Primitive::Plane,
            PrimitiveSize::Height => matches!(self, Primitive::Cylinder | Primitive::Tube),
            PrimitiveSize::MinorRadius => self == Primitive::Torus,
        }
    }

    /// The parameters with defaults filled in and checked.
    ///
    /// # Errors
    /// [`SurfaceError::BadParameter`] for a size that is not a positive finite number, or a
    /// torus whose minor radius is not below the major one.
    pub fn resolve(self, params: &PrimitiveParams) -> Result<Resolved, SurfaceError> {
        let d = self.defaults();
        let r = Resolved {
            patches: params.patches.unwrap_or(d.patches),
            radius: params.radius.unwrap_or(d.radius),
            height: params.height.unwrap_or(d.height),
            minor_radius: params.minor_radius.unwrap_or(d.minor_radius),
        };
        for (name, value) in [
            ("radius", r.radius),
            ("height", r.height),
            ("minor radius", r.minor_radius),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(SurfaceError::BadParameter { name, value });
            }
        }
        if self == Primitive::Torus && r.minor_radius >= r.radius {
            return Err(SurfaceError::BadParameter {
                name: "minor radius (must be below the radius)",
                value: r.minor_radius,
            });
        }
        Ok(r)
    }

    /// Builds the primitive.
    ///
    /// # Errors
    /// Bad parameters (see [`Primitive::resolve`]) or patch counts the topology rejects
    /// (see [`Grid::check_counts`]).
    pub fn build(self, params: &PrimitiveParams) -> Result<Grid, SurfaceError> {
        let r = self.resolve(params)?;
        let (m, n) = r.patches;
        Grid::check_counts(self.topology(), m, n)?;
        match self {
            Primitive::Plane => plane(m, n),
            Primitive::Cylinder => cylinder(m, n, r.radius, r.height),
            Primitive::Hemisphere => hemisphere(m, n, r.radius),
            Primitive::Sphere => sphere(m, n, r.radius),
            Primitive::Torus => torus(m, n, r.radius, r.minor_radius),
            Primitive::Tube => tube(m, n, r.radius, r.height),
        }
    }

    /// The ideal shape the primitive approximates.
    ///
    /// # Errors
    /// As [`Primitive::resolve`].
    pub fn ideal(self, params: &PrimitiveParams) -> Result<Ideal, SurfaceError> {
        let r = self.resolve(params)?;
        Ok(match self {
            Primitive::Plane => Ideal::Plane,
            Primitive::Cylinder => Ideal::Cylinder { radius: r.radius },
            Primitive::Hemisphere | Primitive::Sphere => Ideal::Sphere {
                center: DVec3::ZERO,
                radius: r.radius,
            },
            Primitive::Torus => Ideal::Torus {
                major: r.radius,
                minor: r.minor_radius,
            },
            Primitive::Tube => Ideal::Tube { radius: r.radius },
        })
    }
}

impl fmt::Display for Primitive {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Primitive {
    type Err = crate::surface::error::UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Primitive::ALL
            .into_iter()
            .find(|p| p.name() == s)
            .ok_or_else(|| crate::surface::error::UnknownName {
                kind: "primitive",
                given: s.to_owned(),
                expected: "plane, cylinder, hemisphere, sphere, torus or tube",
            })
    }
}

/// An ideal shape, for measuring how far a primitive (or any grid) is from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Ideal {
    /// The plane `z = 0`.
    Plane,
    /// The infinite cylinder of this radius around the z axis.
    Cylinder {
        /// Radius.
        radius: f64,
    },
    /// A sphere.
    Sphere {
        /// Centre.
        center: DVec3,
        /// Radius.
        radius: f64,
    },
    /// A torus around the z axis, centred on the origin.
    Torus {
        /// Major radius.
        major: f64,
        /// Minor radius.
        minor: f64,
    },
    /// The tube: the sphere of this radius centred at `(0, 0, R)` below `z = R`, the cylinder
    /// of this radius above.
    Tube {
        /// Radius.
        radius: f64,
    },
}

impl Ideal {
    /// Distance from `p` to the ideal surface.
    #[must_use]
    pub fn distance(&self, p: DVec3) -> f64 {
        let rho = p.truncate().length();
        match *self {
            Ideal::Plane => p.z.abs(),
            Ideal::Cylinder { radius } => (rho - radius).abs(),
            Ideal::Sphere { center, radius } => ((p - center).length() - radius).abs(),
            Ideal::Torus { major, minor } => (DVec2::new(rho - major, p.z).length() - minor).abs(),
            Ideal::Tube { radius } => {
                if p.z >= radius {
                    (rho - radius).abs()
                } else {
                    ((p - DVec3::new(0.0, 0.0, radius)).length() - radius).abs()
                }
            }
        }
    }

    /// The largest distance from the ideal over `k × k` samples per patch (`u, v = 0, 1/(k−1),
    /// …, 1`).
    #[must_use]
    pub fn max_distance(&self, grid: &Grid, k: usize) -> f64 {
        let k = k.max(2);
        let mut worst = 0.0f64;
        for p in 0..grid.patch_count() {
            let patch = grid.patch_struct(p);
            for a in 0..k {
                for b in 0..k {
                    let (u, v) = (a as f64 / (k - 1) as f64, b as f64 / (k - 1) as f64);
                    worst = worst.max(self.distance(patch.eval(u, v)));
                }
            }
        }
        worst
    }
}

/// Control points of `count` cubic arcs of the unit circle from angle `from` to `to` (either
/// direction), as `3·count + 1` points; the handles have length `4/3·tan(θ/4)`.
fn arcs(from: f64, to: f64, count: usize) -> Vec<DVec2> {
    let theta = (to - from) / count as f64;
    let h = 4.0 / 3.0 * (theta / 4.0).tan();
    let at = |phi: f64| DVec2::new(phi.cos(), phi.sin());
    let tangent = |phi: f64| DVec2::new(-phi.sin(), phi.cos());
    let mut out = Vec::with_capacity(3 * count + 1);
    for k in 0..count {
        let (p0, p1) = (from + k as f64 * theta, from + (k + 1) as f64 * theta);
        out.push(at(p0));
        out.push(at(p0) + h * tangent(p0));
        out.push(at(p1) - h * tangent(p1));
    }
    out.push(at(to));
    out
}

/// The closed version of [`arcs`] around the full circle: `3·count` points (the last equals
/// the first and is dropped).
fn circle(clockwise: bool, count: usize) -> Vec<DVec2> {
    let to = if clockwise { -TAU } else { TAU };
    let mut c = arcs(0.0, to, count);
    c.pop();
    c
}

/// A surface of revolution: nodes `(ρ_b c_a, z_b)`, with collapsed rows where `ρ_b = 0` at a
/// pole end.
fn revolve(
    topology: Topology,
    m: usize,
    n: usize,
    ring: &[DVec2],
    meridian: &[DVec2],
) -> Result<Grid, SurfaceError> {
    let mut nodes = Vec::with_capacity(Grid::net_len(topology, m, n));
    let lb = meridian.len();
    for (b, mb) in meridian.iter().enumerate() {
        let pole = (b == 0 && topology.pole_at_start()) || (b + 1 == lb && topology.pole_at_end());
        if pole {
            nodes.push(DVec3::new(0.0, 0.0, mb.y));
            continue;
        }
        for c in ring {
            nodes.push(DVec3::new(mb.x * c.x, mb.x * c.y, mb.y));
        }
    }
    Grid::from_net(topology, m, n, nodes)
}

/// `M × N` unit squares centred on the origin in `z = 0`, normal +z.
///
/// # Errors
/// Zero counts.
pub fn plane(m: usize, n: usize) -> Result<Grid, SurfaceError> {
    Grid::check_counts(Topology::Plane, m, n)?;
    let (la, lb) = (3 * m + 1, 3 * n + 1);
    let mut nodes = Vec::with_capacity(la * lb);
    for b in 0..lb {
        for a in 0..la {
            nodes.push(DVec3::new(
                a as f64 / 3.0 - m as f64 / 2.0,
                b as f64 / 3.0 - n as f64 / 2.0,
                0.0,
            ));
        }
    }
    Grid::from_net(Topology::Plane, m, n, nodes)
}

/// An open cylinder of radius R around the z axis from `z = 0` to `z = H`, `M` patches around
/// (even), `N` along.
///
/// # Errors
/// Bad counts or sizes.
pub fn cylinder(m: usize, n: usize, radius: f64, height: f64) -> Result<Grid, SurfaceError> {
    check_sizes(&[("radius", radius), ("height", height)])?;
    Grid::check_counts(Topology::Cylinder, m, n)?;
    let ring: Vec<DVec2> = circle(false, m).into_iter().map(|c| c * radius).collect();
    let meridian: Vec<DVec2> = (0..=3 * n)
        .map(|b| DVec2::new(1.0, height * b as f64 / (3 * n) as f64))
        .collect();
    revolve(Topology::Cylinder, m, n, &ring, &meridian)
}

/// A hemisphere of radius R: pole on +z (at `v = 0`), rim in `z = 0`.
///
/// # Errors
/// Bad counts or sizes.
pub fn hemisphere(m: usize, n: usize, radius: f64) -> Result<Grid, SurfaceError> {
    check_sizes(&[("radius", radius)])?;
    Grid::check_counts(Topology::Hemisphere, m, n)?;
    let ring = circle(true, m);
    let meridian: Vec<DVec2> = arcs(FRAC_PI_2, 0.0, n)
        .into_iter()
        .map(|p| p * radius)
        .collect();
    revolve(Topology::Hemisphere, m, n, &ring, &meridian)
}

/// A sphere of radius R about the origin, poles on ±z (`v = 0` at −z).
///
/// # Errors
/// Bad counts or sizes.
pub fn sphere(m: usize, n: usize, radius: f64) -> Result<Grid, SurfaceError> {
    check_sizes(&[("radius", radius)])?;
    Grid::check_counts(Topology::Sphere, m, n)?;
    let ring = circle(false, m);
    let meridian: Vec<DVec2> = arcs(-FRAC_PI_2, FRAC_PI_2, n)
        .into_iter()
        .map(|p| p * radius)
        .collect();
    revolve(Topology::Sphere, m, n, &ring, &meridian)
}

/// A torus around the z axis: major radius R, minor radius r < R.
///
/// # Errors
/// Bad counts or sizes.
pub fn torus(m: usize, n: usize, major: f64, minor: f64) -> Result<Grid, SurfaceError> {
    check_sizes(&[("radius", major), ("minor radius", minor)])?;
    if minor >= major {
        return Err(SurfaceError::BadParameter {
            name: "minor radius (must be below the radius)",
            value: minor,
        });
    }
    Grid::check_counts(Topology::Torus, m, n)?;
    let ring = circle(false, m);
    let meridian: Vec<DVec2> = circle(false, n)
        .into_iter()
        .map(|c| DVec2::new(major + minor * c.x, minor * c.y))
        .collect();
    revolve(Topology::Torus, m, n, &ring, &meridian)
}

/// The "test tube": a round bottom of radius R with its pole at the origin (`v = 0`) and
/// straight walls of height H above it, up to `z = R + H`. The `N` patches along `v` are
/// shared between the bottom quarter circle and the walls in proportion to their lengths (at
/// least one each).
///
/// # Errors
/// Bad counts or sizes (the tube needs `N ≥ 2`).
pub fn tube(m: usize, n: usize, radius: f64, height: f64) -> Result<Grid, SurfaceError> {
    check_sizes(&[("radius", radius), ("height", height)])?;
    Grid::check_counts(Topology::Hemisphere, m, n)?;
    if n < 2 {
        return Err(SurfaceError::TooFewPatches {
            topology: Topology::Hemisphere,
            direction: "v",
            min: 2,
            got: n,
        });
    }
    let quarter = PI / 2.0 * radius;
    let n_bottom = ((n as f64 * quarter / (quarter + height)).round() as usize).clamp(1, n - 1);
    let n_wall = n - n_bottom;
    let mut meridian: Vec<DVec2> = arcs(-FRAC_PI_2, 0.0, n_bottom)
        .into_iter()
        .map(|p| DVec2::new(p.x * radius, radius + p.y * radius))
        .collect();
    meridian[0] = DVec2::new(0.0, 0.0);
    for b in 1..=3 * n_wall {
        meridian.push(DVec2::new(
            radius,
            radius + height * b as f64 / (3 * n_wall) as f64,
        ));
    }
    revolve(Topology::Hemisphere, m, n, &circle(false, m), &meridian)
}

fn check_sizes(sizes: &[(&'static str, f64)]) -> Result<(), SurfaceError> {
    for &(name, value) in sizes {
        if !(value.is_finite() && value > 0.0) {
            return Err(SurfaceError::BadParameter { name, value });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arcs_hit_the_circle_at_their_ends() {
        let a = arcs(0.3, -1.2, 3);
        assert_eq!(a.len(), 10);
        for k in 0..=3 {
            let phi = 0.3 + k as f64 * (-1.5 / 3.0);
            assert!((a[3 * k] - DVec2::new(phi.cos(), phi.sin())).length() < 1e-15);
        }
    }
}
