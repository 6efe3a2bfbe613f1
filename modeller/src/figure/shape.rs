//! A metaball shape fitted to a few horizontal cross-sections (P0 §4.3, Fig. 12): "the
//! object is made of several sections; in each section metaballs are placed roughly, then
//! their positions are optimised so that the error at the sampling points on the sections'
//! contours is least" — and re-fitted after the sections' sampling points were dragged along by
//! curves ([`super::section`]).
//!
//! The shape's density is `F(X) = Σ_i q_i f(|X − C_i|² / R_i²)` ([`super::metaball`], Wyvill's
//! falloff). The parameters are `x = (C_i, ln R_i, q_i)` per ball — five numbers, the centre
//! free in 3D, the radius through its logarithm so that it stays positive — and the residuals
//! are those of the 2D fit ([`super::fit`]) at every section, plus what ties the sections
//! together:
//!
//! * on every section's contour, at samples `s_j` evenly spaced by arc length at the section's
//!   height `z`: `r_j = F(s_j, z) − T`;
//! * guards in every section's plane, so that `F ≥ T` is the inside there: on a grid over the
//!   plane's contours, points inside a contour (farther than half a cell from every contour)
//!   give `max(0, T + m − F)`, points outside all of them `max(0, F − (T − m))`, `m = T / 20`;
//!   the same at a ring of points half a cell inside and outside the contour samples. Sections
//!   at the same height (two legs) form one plane — their `z` must be equal, not merely close —
//!   and inside is inside any of them;
//! * bridges between consecutive planes `z_a < z_b`, at `(z_a + z_b) / 2`: points inside a
//!   contour of both planes are inside, points outside every contour of both are outside (the
//!   solid between two sections contains their common part and lies within their union — what
//!   any lofting of the sections gives, and what keeps the balls of sparse sections from
//!   pinching apart or bulging out between them);
//! * a hinge keeping every centre above a contour of its home plane (the plane nearest its
//!   height) and between the lowest and the highest section: `w · dist`, `w = T / h` for the
//!   guard cell side `h`;
//! * radius bounds `R⁰/4 ≤ R ≤ 1.5 R⁰` and the weak prior `10⁻³ (ln R − ln R⁰)`,
//!   `10⁻³ (q − q⁰)`, as in 2D.
//!
//! Seeds: the medial-axis discs of every section ([`super::medial`]), a ball of radius `2d` at
//! the section's height per disc of radius `d` (a lone ball of density 1 reaches `T = 0.5` at
//! `R/2`), the densities then scaled together so that the contour samples start near `T`. The
//! minimiser is the 2D fit's ([`super::optimise`]: Levenberg–Marquardt by default, or the
//! seed's steepest descent). Beyond its lowest and highest sections the shape closes where the
//! balls fade (nothing is measured there).

use glam::{DVec2, DVec3};

use crate::curve::Curve;
use crate::curve::warp::WarpParams;

use super::contour::Contour;
use super::error::FigureError;
use super::falloff::DEFAULT_THRESHOLD;
use super::fit::{BallProblem, FitSample, Home, SampleKind, contour_samples};
use super::medial::{SeedOptions, medial_discs};
use super::metaball::{Metaball, Shape};
use super::optimise::{Optimiser, Stopping, minimise};
use super::section::Section;

/// How a shape is fitted to its sections.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeFitOptions {
    /// Seeding on each section's medial axis (`max_seeds` is per section).
    pub seeds: SeedOptions,
    /// Samples along each contour (0: four per vertex, 100 to 400).
    pub samples: usize,
    /// Guard grid cells along the longer side of each plane's contours.
    pub guard_resolution: usize,
    /// Guards between consecutive planes.
    pub bridges: bool,
    /// The minimiser.
    pub optimiser: Optimiser,
    /// When it stops.
    pub stopping: Stopping,
    /// The threshold `T`.
    pub threshold: f64,
}

impl Default for ShapeFitOptions {
    fn default() -> Self {
        Self {
            seeds: SeedOptions {
                resolution: 64,
                max_seeds: 12,
                ..SeedOptions::default()
            },
            samples: 0,
            guard_resolution: 24,
            bridges: true,
            optimiser: Optimiser::LevenbergMarquardt,
            stopping: Stopping::default(),
            threshold: DEFAULT_THRESHOLD,
        }
    }
}

/// How well a shape fits one section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionReport {
    /// The section's height.
    pub z: f64,
    /// Contour samples.
    pub samples: usize,
    /// Root mean square of `F − T` over the samples.
    pub rms_density: f64,
    /// Largest `|F − T|`.
    pub max_density: f64,
    /// Root mean square distance from the samples to the iso-surface.
    pub rms_distance: f64,
    /// Largest distance from a sample to the iso-surface (`∞` when the surface was not reached
    /// from some sample).
    pub max_distance: f64,
}

/// How well a shape fits its sections.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeFitReport {
    /// Metaballs in the shape.
    pub balls: usize,
    /// Contour samples over all sections.
    pub samples: usize,
    /// Guard points (planes, rings and bridges).
    pub guards: usize,
    /// Guard points on the wrong side of the iso-surface.
    pub guards_violated: usize,
    /// Optimiser iterations (0 when only measured).
    pub iterations: usize,
    /// Cost `½ Σ r²` before optimising (equal to the final cost when only measured).
    pub initial_cost: f64,
    /// Cost after.
    pub final_cost: f64,
    /// Root mean square distance from all samples to the iso-surface.
    pub rms_distance: f64,
    /// Largest distance from a sample to the iso-surface.
    pub max_distance: f64,
    /// Diagonal of the sections' 3D bounds, to read the distances relative to the size.
    pub size: f64,
    /// Per section, in the order given.
    pub sections: Vec<SectionReport>,
}

/// The sections at one height.
struct Plane {
    z: f64,
    contours: Vec<Contour>,
    /// Guard cell side.
    cell: f64,
}

impl Plane {
    fn contains(&self, p: DVec2) -> bool {
        self.contours.iter().any(|c| c.contains(p))
    }

    fn distance(&self, p: DVec2) -> f64 {
        self.contours
            .iter()
            .map(|c| c.distance(p))
            .fold(f64::INFINITY, f64::min)
    }

    fn bounds(&self) -> (DVec2, DVec2) {
        self.contours.iter().map(Contour::bounds).fold(
            (DVec2::INFINITY, DVec2::NEG_INFINITY),
            |(a, b), (lo, hi)| (a.min(lo), b.max(hi)),
        )
    }
}

/// The planes of the sections, lowest first.
fn planes(sections: &[Section], resolution: usize) -> Vec<Plane> {
    let mut zs: Vec<f64> = sections.iter().map(|s| s.z).collect();
    zs.sort_by(f64::total_cmp);
    zs.dedup();
    zs.into_iter()
        .map(|z| {
            let contours: Vec<Contour> = sections
                .iter()
                .filter(|s| s.z == z)
                .map(|s| s.contour.clone())
                .collect();
            let mut plane = Plane {
                z,
                contours,
                cell: 1.0,
            };
            let (lo, hi) = plane.bounds();
            plane.cell = (hi - lo).max_element() / resolution.max(2) as f64;
            plane
        })
        .collect()
}

/// Grid points over `[lo, hi]` grown by 15 %, at height `z`, classified by `kind` (`None`:
/// no guard there).
fn grid_guards(
    lo: DVec2,
    hi: DVec2,
    cell: f64,
    z: f64,
    kind: impl Fn(DVec2) -> Option<SampleKind>,
    out: &mut Vec<FitSample>,
) {
    let grow = 0.15 * (hi - lo).max_element();
    let (lo, hi) = (lo - DVec2::splat(grow), hi + DVec2::splat(grow));
    let nx = ((hi.x - lo.x) / cell).ceil() as usize;
    let ny = ((hi.y - lo.y) / cell).ceil() as usize;
    for j in 0..ny {
        for i in 0..nx {
            let p = lo + DVec2::new(i as f64 + 0.5, j as f64 + 0.5) * cell;
            if let Some(kind) = kind(p) {
                out.push(FitSample { p, z, kind });
            }
        }
    }
}

/// Every guard point: planes, rings and (optionally) bridges.
fn guard_points(
    sections: &[Section],
    planes: &[Plane],
    on: &[Vec<DVec2>],
    bridges: bool,
    resolution: usize,
) -> Vec<FitSample> {
    let mut out = Vec::new();
    for plane in planes {
        let (lo, hi) = plane.bounds();
        let half = 0.5 * plane.cell;
        grid_guards(
            lo,
            hi,
            plane.cell,
            plane.z,
            |p| {
                (plane.distance(p) >= half).then(|| {
                    if plane.contains(p) {
                        SampleKind::Above
                    } else {
                        SampleKind::Below
                    }
                })
            },
            &mut out,
        );
    }
    // Rings half a cell off the samples, along the normal of the samples' polyline.
    for (s, samples) in sections.iter().zip(on) {
        let Some(plane) = planes.iter().find(|p| p.z == s.z) else {
            continue;
        };
        let n = samples.len();
        for j in 0..n {
            let t = samples[(j + 1) % n] - samples[(j + n - 1) % n];
            let normal = t.perp().normalize_or_zero();
            if normal == DVec2::ZERO {
                continue;
            }
            for sign in [1.0, -1.0] {
                let p = samples[j] + normal * (sign * 0.5 * plane.cell);
                if plane.distance(p) < 0.25 * plane.cell {
                    continue;
                }
                let kind = if plane.contains(p) {
                    SampleKind::Above
                } else {
                    SampleKind::Below
                };
                out.push(FitSample { p, z: s.z, kind });
            }
        }
    }
    if bridges {
        for pair in planes.windows(2) {
            let (a, b) = (&pair[0], &pair[1]);
            let (la, ha) = a.bounds();
            let (lb, hb) = b.bounds();
            let (lo, hi) = (la.min(lb), ha.max(hb));
            // The finer plane's cell, but never more cells than the resolution over the union
            // (a tiny section next to a large one must not make a huge grid).
            let cell = a
                .cell
                .min(b.cell)
                .max((hi - lo).max_element() / resolution as f64);
            let half = 0.5 * cell;
            grid_guards(
                lo,
                hi,
                cell,
                0.5 * (a.z + b.z),
                |p| {
                    if a.distance(p) < half || b.distance(p) < half {
                        return None;
                    }
                    match (a.contains(p), b.contains(p)) {
                        (true, true) => Some(SampleKind::Above),
                        (false, false) => Some(SampleKind::Below),
                        _ => None,
                    }
                },
                &mut out,
            );
        }
    }
    out
}

fn check(sections: &[Section], options: &ShapeFitOptions) -> Result<(), FigureError> {
    if sections.is_empty() {
        return Err(FigureError::Empty(
            "a shape needs at least one section".into(),
        ));
    }
    if !(options.threshold.is_finite() && options.threshold > 0.0) {
        return Err(FigureError::Threshold(options.threshold));
    }
    if options.seeds.max_seeds == 0 {
        return Err(FigureError::Option(
            "at least one metaball per section must be seeded".into(),
        ));
    }
    if !(2..=1024).contains(&options.guard_resolution)
        || !(4..=4096).contains(&options.seeds.resolution)
    {
        return Err(FigureError::Option(
            "grid resolutions must be 2..=1024 (guards) and 4..=4096 (seeds)".into(),
        ));
    }
    if let Some(i) = sections.iter().position(|s| !s.z.is_finite()) {
        return Err(FigureError::NotFinite {
            what: format!("section {i} height"),
        });
    }
    Ok(())
}

/// The contour samples of every section.
fn section_samples(sections: &[Section], n: usize) -> Vec<Vec<DVec2>> {
    let n = |s: &Section| {
        if n > 0 {
            n
        } else {
            (4 * s.contour.len()).clamp(100, 400)
        }
    };
    sections
        .iter()
        .map(|s| contour_samples(&s.contour, n(s)))
        .collect()
}

/// Fits metaballs to the sections: seeds on their medial axes, then optimises.
///
/// # Errors
/// [`FigureError::Empty`] without sections, [`FigureError::Option`] / [`FigureError::Threshold`]
/// for bad options, and the errors of [`refit_sections`].
pub fn fit_sections(
    sections: &[Section],
    options: &ShapeFitOptions,
) -> Result<(Shape, ShapeFitReport), FigureError> {
    check(sections, options)?;
    let mut balls: Vec<Metaball> = Vec::new();
    for s in sections {
        for d in medial_discs(&s.contour, &options.seeds) {
            balls.push(Metaball::new(
                DVec3::new(d.centre.x, d.centre.y, s.z),
                2.0 * d.radius,
                1.0,
            ));
        }
    }
    let mut shape = Shape {
        balls,
        threshold: options.threshold,
    };
    // Overlapping seeds (within a section and across sections) add up: scale the densities
    // together so that the contour samples start near T.
    let on = section_samples(sections, options.samples);
    let (sum, count) = sections
        .iter()
        .zip(&on)
        .flat_map(|(s, pts)| pts.iter().map(move |p| DVec3::new(p.x, p.y, s.z)))
        .fold((0.0, 0usize), |(f, n), x| (f + shape.field(x), n + 1));
    let mean = sum / count.max(1) as f64;
    if mean > 0.0 {
        let k = options.threshold / mean;
        for b in &mut shape.balls {
            b.density = (b.density * k).min(4.0 * options.threshold);
        }
    }
    refit_sections(&shape, sections, options)
}

/// Re-optimises an existing shape against the sections (warm start: after the sections were
/// deformed).
///
/// # Errors
/// [`FigureError`] for an invalid shape, one without a ball of positive radius, or bad options.
pub fn refit_sections(
    shape: &Shape,
    sections: &[Section],
    options: &ShapeFitOptions,
) -> Result<(Shape, ShapeFitReport), FigureError> {
    check(sections, options)?;
    shape.validate()?;
    let balls: Vec<&Metaball> = shape.balls.iter().filter(|b| b.radius > 0.0).collect();
    if balls.is_empty() {
        return Err(FigureError::Empty(
            "the shape has no metaball of positive radius to fit".into(),
        ));
    }
    let planes = planes(sections, options.guard_resolution);
    let on = section_samples(sections, options.samples);
    let mut samples: Vec<FitSample> = sections
        .iter()
        .zip(&on)
        .flat_map(|(s, pts)| {
            pts.iter().map(move |&p| FitSample {
                p,
                z: s.z,
                kind: SampleKind::On,
            })
        })
        .collect();
    samples.extend(guard_points(
        sections,
        &planes,
        &on,
        options.bridges,
        options.guard_resolution,
    ));
    let (z_lo, z_hi) = (
        planes.first().map_or(0.0, |p| p.z),
        planes.last().map_or(0.0, |p| p.z),
    );
    let homes = balls
        .iter()
        .map(|b| {
            let plane = planes.iter().min_by(|p, q| {
                (p.z - b.centre.z)
                    .abs()
                    .total_cmp(&(q.z - b.centre.z).abs())
            })?;
            Some(Home {
                contours: &plane.contours,
                z_range: Some((z_lo, z_hi)),
                weight: options.threshold / plane.cell,
            })
        })
        .collect();
    let mut x: Vec<f64> = balls
        .iter()
        .flat_map(|b| [b.centre.x, b.centre.y, b.centre.z, b.radius.ln(), b.density])
        .collect();
    let problem = BallProblem {
        spatial: true,
        samples: &samples,
        threshold: options.threshold,
        prior: balls.iter().map(|b| (b.radius.ln(), b.density)).collect(),
        homes,
    };
    let outcome = minimise(&problem, &mut x, options.optimiser, &options.stopping);
    let fitted = Shape {
        balls: (0..balls.len())
            .map(|i| Metaball {
                centre: DVec3::new(x[5 * i], x[5 * i + 1], x[5 * i + 2]),
                radius: x[5 * i + 3].exp(),
                density: x[5 * i + 4],
            })
            .collect(),
        threshold: options.threshold,
    };
    fitted.validate()?;
    let mut report = measure_sections(&fitted, sections, options);
    report.iterations = outcome.iterations;
    report.initial_cost = outcome.initial_cost;
    report.final_cost = outcome.final_cost;
    Ok((fitted, report))
}

/// A shape deformed through its sections: the sections after their curves moved, the shape
/// re-fitted to them, and what moved.
#[derive(Debug, Clone, PartialEq)]
pub struct Deformed {
    /// The re-fitted shape (the input shape when no curve moved).
    pub shape: Shape,
    /// The sections, those whose curves moved warped along.
    pub sections: Vec<Section>,
    /// Per section, whether any of its curves moved.
    pub moved: Vec<bool>,
    /// The fit after the re-fit; `None` when nothing moved (nothing was re-fitted).
    pub report: Option<ShapeFitReport>,
}

/// Deforms a shape through its sections (P0 §4.3): section `i`'s curves move to
/// `deformed[i]`, its contour follows ([`Section::warped`], edges divided to `max_edge`), and
/// the shape is re-fitted to all the sections from its current balls. When no curve moved the
/// shape and the sections are returned exactly as they were, without a re-fit.
///
/// # Errors
/// [`FigureError::Mismatch`] when `deformed` does not have one list per section, the errors of
/// [`Section::warped`] and of [`refit_sections`].
pub fn deform(
    shape: &Shape,
    sections: &[Section],
    deformed: &[Vec<Curve<DVec2>>],
    params: WarpParams,
    max_edge: Option<f64>,
    options: &ShapeFitOptions,
) -> Result<Deformed, FigureError> {
    if deformed.len() != sections.len() {
        return Err(FigureError::Mismatch {
            what: "sections and their deformed curves".into(),
            left: sections.len(),
            right: deformed.len(),
        });
    }
    let mut out = Vec::with_capacity(sections.len());
    let mut moved = Vec::with_capacity(sections.len());
    for (s, d) in sections.iter().zip(deformed) {
        let (w, m) = s.warped(d, params, max_edge)?;
        out.push(w);
        moved.push(m);
    }
    if !moved.iter().any(|&m| m) {
        return Ok(Deformed {
            shape: shape.clone(),
            sections: out,
            moved,
            report: None,
        });
    }
    let (shape, report) = refit_sections(shape, &out, options)?;
    Ok(Deformed {
        shape,
        sections: out,
        moved,
        report: Some(report),
    })
}

/// Diagonal of the sections' bounds in 3D.
fn sections_size(sections: &[Section]) -> f64 {
    let (lo, hi) = sections
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(a, b), s| {
            let (lo, hi) = s.contour.bounds();
            (
                a.min(DVec3::new(lo.x, lo.y, s.z)),
                b.max(DVec3::new(hi.x, hi.y, s.z)),
            )
        });
    (hi - lo).length()
}

/// How well `shape` fits `sections`, without optimising (the samples and guards of `options`).
#[must_use]
pub fn measure_sections(
    shape: &Shape,
    sections: &[Section],
    options: &ShapeFitOptions,
) -> ShapeFitReport {
    let t = shape.threshold;
    let size = sections_size(sections);
    let on = section_samples(sections, options.samples);
    let mut reports = Vec::with_capacity(sections.len());
    let (mut all_d2, mut all_n, mut all_max) = (0.0, 0usize, 0.0f64);
    let mut cost = 0.0;
    for (s, pts) in sections.iter().zip(&on) {
        let (mut r2, mut rmax, mut d2, mut dmax) = (0.0, 0.0f64, 0.0, 0.0f64);
        for p in pts {
            let x = DVec3::new(p.x, p.y, s.z);
            let r = shape.field(x) - t;
            r2 += r * r;
            rmax = rmax.max(r.abs());
            match shape.distance_to_surface(x, size) {
                Some(d) => {
                    d2 += d * d;
                    dmax = dmax.max(d);
                }
                None => dmax = f64::INFINITY,
            }
        }
        cost += 0.5 * r2;
        let n = pts.len().max(1) as f64;
        all_d2 += d2;
        all_n += pts.len();
        all_max = all_max.max(dmax);
        reports.push(SectionReport {
            z: s.z,
            samples: pts.len(),
            rms_density: (r2 / n).sqrt(),
            max_density: rmax,
            rms_distance: (d2 / n).sqrt(),
            max_distance: dmax,
        });
    }
    let planes = planes(sections, options.guard_resolution);
    let guards = guard_points(
        sections,
        &planes,
        &on,
        options.bridges,
        options.guard_resolution,
    );
    let guards_violated = guards
        .iter()
        .filter(|g| {
            let f = shape.field(DVec3::new(g.p.x, g.p.y, g.z));
            match g.kind {
                SampleKind::Above => f < t,
                SampleKind::Below => f >= t,
                SampleKind::On => false,
            }
        })
        .count();
    ShapeFitReport {
        balls: shape.balls.len(),
        samples: all_n,
        guards: guards.len(),
        guards_violated,
        iterations: 0,
        initial_cost: cost,
        final_cost: cost,
        rms_distance: (all_d2 / all_n.max(1) as f64).sqrt(),
        max_distance: all_max,
        size,
        sections: reports,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn circle(r: f64, n: usize) -> Contour {
        Contour::new(
            (0..n)
                .map(|k| DVec2::from_angle(k as f64 * std::f64::consts::TAU / n as f64) * r)
                .collect(),
            "circle",
        )
        .unwrap()
    }

    #[test]
    fn a_lone_section_is_fitted_in_its_plane() {
        let s = [Section::new(0.0, circle(1.0, 64), Vec::new()).unwrap()];
        let (shape, report) = fit_sections(&s, &ShapeFitOptions::default()).unwrap();
        assert!(report.final_cost <= report.initial_cost);
        assert!(report.max_distance < 0.02, "{report:?}");
        assert!(shape.contains(DVec3::ZERO));
        assert!(!shape.contains(DVec3::new(1.2, 0.0, 0.0)));
    }

    #[test]
    fn bad_input_is_refused() {
        let o = ShapeFitOptions::default();
        assert!(fit_sections(&[], &o).is_err());
        let s = [Section::new(0.0, circle(1.0, 16), Vec::new()).unwrap()];
        let bad = ShapeFitOptions {
            threshold: -1.0,
            ..o
        };
        assert!(fit_sections(&s, &bad).is_err());
        assert!(refit_sections(&Shape::default(), &s, &o).is_err());
    }
}
