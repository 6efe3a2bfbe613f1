//! Fitting metacircles to a closed contour (P0 §4.2 1)): seed circles on the contour's
//! medial axis ([`super::medial`]), then optimise every centre, radius and density so that the
//! iso-curve `F = T` passes through samples of the contour.
//!
//! The residuals, for metacircle parameters `x = (P_i, ln R_i, q_i)` (the radius through its
//! logarithm, so that it stays positive):
//!
//! * on the contour, at `m` samples `s_j` evenly spaced by arc length: `r_j = F(s_j) − T`
//!   (P0's error, "the difference between T and f at each sampling point");
//! * guards, so that the region `F ≥ T` is the inside and not some other set whose boundary
//!   also passes through the samples: on a coarse grid, inside points farther than half a cell
//!   from the contour give `max(0, T + m − F)` and outside points `max(0, F − (T − m))`, with
//!   the margin `m = T / 20` (zero when satisfied: hinges); the same hinges at a ring of points
//!   half a guard cell inside and outside the contour samples;
//! * a hinge keeping every centre inside the contour: `w · dist(P_i, contour)` when `P_i` is
//!   outside, `w = T / h` for the guard cell side `h` (a metacircle wandering out of the figure
//!   makes a blob of its own between the guard points);
//! * radius bounds `R_i⁰ / 4 ≤ R_i ≤ 1.5 R_i⁰` as hinges on `ln R_i` (without them a few
//!   metacircles grow far beyond the figure with tiny densities, a background offset that
//!   makes morphing between figures erratic);
//! * a weak prior `10⁻³ (ln R_i − ln R_i⁰)`, `10⁻³ (q_i − q_i⁰)` that keeps the normal
//!   equations regular where a parameter touches no sample.
//!
//! The same core fits 3D metaballs to horizontal sections ([`super::shape`]): each ball then
//! has five parameters `(P_i, z_i, ln R_i, q_i)`, the samples lie at their sections' heights,
//! and the density at `(p, z)` is `q f((|p − P_i|² + (z − z_i)²) / R_i²)`.

use glam::DVec2;

use super::contour::Contour;
use super::error::FigureError;
use super::falloff::{DEFAULT_THRESHOLD, density, density_and_ds};
use super::iso::{Lattice, iso_lines};
use super::medial::{SeedOptions, medial_discs};
use super::metacircle::{Figure, Metacircle, Rgb};
use super::optimise::{Jacobian, LeastSquares, Optimiser, Stopping, minimise};

/// Weight of the prior rows.
const PRIOR_WEIGHT: f64 = 1e-3;
/// A radius may grow to this multiple of its seed…
const RADIUS_GROWTH: f64 = 1.5;
/// …and shrink to its seed over this.
const RADIUS_SHRINK: f64 = 4.0;
/// Weight of the radius bounds (per unit of `ln R` beyond them).
const BOUND_WEIGHT: f64 = 1.0;
/// Guard margin as a fraction of the threshold.
const GUARD_MARGIN: f64 = 0.05;

/// What a fitting sample asks of the density.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SampleKind {
    /// On the iso-curve: `F = T`.
    On,
    /// Inside: `F ≥ T + m`.
    Above,
    /// Outside: `F ≤ T − m`.
    Below,
}

/// A point where the density is constrained, at height `z` (0 in 2D).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FitSample {
    pub p: DVec2,
    pub z: f64,
    pub kind: SampleKind,
}

/// Where a ball's centre must stay: inside one of `contours` (its section's level, in the
/// plane), and in 3D between the heights of `z_range`; `weight` per unit of distance outside.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Home<'a> {
    pub contours: &'a [Contour],
    pub z_range: Option<(f64, f64)>,
    pub weight: f64,
}

impl Home<'_> {
    /// The point of the nearest contour boundary when `c` is inside none of them.
    fn outside(&self, c: DVec2) -> Option<DVec2> {
        if self.contours.iter().any(|k| k.contains(c)) {
            return None;
        }
        self.contours
            .iter()
            .map(|k| k.closest_point(c))
            .min_by(|a, b| a.distance_squared(c).total_cmp(&b.distance_squared(c)))
    }
}

/// The fitting problem over balls: `x[k i .. k i + k]` is `(x, y, ln R, q)` in the plane
/// (`k = 4`, every ball and sample at height 0) or `(x, y, z, ln R, q)` in space (`k = 5`).
pub(crate) struct BallProblem<'a> {
    /// Five parameters per ball (3D) instead of four (2D).
    pub spatial: bool,
    pub samples: &'a [FitSample],
    pub threshold: f64,
    /// `(ln R⁰, q⁰)` per ball.
    pub prior: Vec<(f64, f64)>,
    /// Per ball, where its centre must stay.
    pub homes: Vec<Option<Home<'a>>>,
}

impl BallProblem<'_> {
    /// Parameters per ball.
    pub fn stride(&self) -> usize {
        if self.spatial { 5 } else { 4 }
    }

    /// Ball `i`'s centre `(x, y)`, height, `ln R` and `q`.
    fn ball(&self, x: &[f64], i: usize) -> (DVec2, f64, f64, f64) {
        let k = self.stride();
        let b = &x[k * i..k * i + k];
        if self.spatial {
            (DVec2::new(b[0], b[1]), b[2], b[3], b[4])
        } else {
            (DVec2::new(b[0], b[1]), 0.0, b[2], b[3])
        }
    }

    /// The density at a sample, and (when asked) its partial derivatives.
    fn field(&self, x: &[f64], s: &FitSample, grads: Option<&mut Vec<(usize, f64)>>) -> f64 {
        let k = self.stride();
        let balls = x.len() / k;
        let mut f = 0.0;
        match grads {
            None => {
                for i in 0..balls {
                    let (c, z, lr, q) = self.ball(x, i);
                    let dz = s.z - z;
                    let d = s.p - c;
                    let sh = (d.length_squared() + dz * dz) * (-2.0 * lr).exp();
                    f += q * density(sh);
                }
            }
            Some(g) => {
                g.clear();
                for i in 0..balls {
                    let (c, z, lr, q) = self.ball(x, i);
                    let dz = s.z - z;
                    let d = s.p - c;
                    let inv_r2 = (-2.0 * lr).exp();
                    let sh = (d.length_squared() + dz * dz) * inv_r2;
                    if sh >= 1.0 {
                        continue;
                    }
                    let (fv, df) = density_and_ds(sh);
                    f += q * fv;
                    // ∂s/∂P = −2 (X − P) / R²,  ∂s/∂ln R = −2 s.
                    let w = -2.0 * inv_r2 * q * df;
                    g.push((k * i, w * d.x));
                    g.push((k * i + 1, w * d.y));
                    if self.spatial {
                        g.push((k * i + 2, w * dz));
                    }
                    g.push((k * i + k - 2, -2.0 * sh * q * df));
                    g.push((k * i + k - 1, fv));
                }
            }
        }
        f
    }
}

impl LeastSquares for BallProblem<'_> {
    fn parameters(&self) -> usize {
        self.stride() * self.prior.len()
    }

    fn evaluate(&self, x: &[f64], jacobian: bool, out: &mut Jacobian) {
        out.clear();
        let k = self.stride();
        let t = self.threshold;
        let m = GUARD_MARGIN * t;
        let mut grads: Vec<(usize, f64)> = Vec::new();
        for s in self.samples {
            let f = self.field(x, s, jacobian.then_some(&mut grads));
            let (r, sign) = match s.kind {
                SampleKind::On => (f - t, 1.0),
                SampleKind::Above => ((t + m - f).max(0.0), -1.0),
                SampleKind::Below => ((f - (t - m)).max(0.0), 1.0),
            };
            if jacobian && (s.kind == SampleKind::On || r > 0.0) {
                out.push(r, grads.iter().map(|&(c, v)| (c, sign * v)));
            } else {
                out.push(r, std::iter::empty());
            }
        }
        for (i, home) in self.homes.iter().enumerate() {
            let Some(home) = home else { continue };
            let w = home.weight;
            let c = DVec2::new(x[k * i], x[k * i + 1]);
            match home.outside(c) {
                None => out.push(0.0, std::iter::empty()),
                Some(near) => {
                    let d = c.distance(near);
                    let dir = if d > 0.0 { (c - near) / d } else { DVec2::ZERO };
                    out.push(
                        w * d,
                        if jacobian {
                            vec![(k * i, w * dir.x), (k * i + 1, w * dir.y)]
                        } else {
                            Vec::new()
                        },
                    );
                }
            }
            if let (true, Some((lo, hi))) = (self.spatial, home.z_range) {
                let z = x[k * i + 2];
                if z < lo {
                    out.push(w * (lo - z), jacobian.then_some((k * i + 2, -w)));
                } else if z > hi {
                    out.push(w * (z - hi), jacobian.then_some((k * i + 2, w)));
                } else {
                    out.push(0.0, None);
                }
            }
        }
        for (i, &(lr0, q0)) in self.prior.iter().enumerate() {
            // Radius bounds as hinges on ln R.
            let (il, iq) = (k * i + k - 2, k * i + k - 1);
            let lr = x[il];
            let over = lr - (lr0 + RADIUS_GROWTH.ln());
            let under = (lr0 - RADIUS_SHRINK.ln()) - lr;
            if over > 0.0 {
                out.push(BOUND_WEIGHT * over, jacobian.then_some((il, BOUND_WEIGHT)));
            } else if under > 0.0 {
                out.push(
                    BOUND_WEIGHT * under,
                    jacobian.then_some((il, -BOUND_WEIGHT)),
                );
            } else {
                out.push(0.0, None);
            }
            out.push(
                PRIOR_WEIGHT * (lr - lr0),
                jacobian.then_some((il, PRIOR_WEIGHT)),
            );
            out.push(
                PRIOR_WEIGHT * (x[iq] - q0),
                jacobian.then_some((iq, PRIOR_WEIGHT)),
            );
        }
    }
}

/// How a contour is fitted.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// Seeding on the medial axis.
    pub seeds: SeedOptions,
    /// Samples along the contour (0: one per 1/200 of the perimeter, at least 4 per vertex up
    /// to 1 000).
    pub samples: usize,
    /// Guard grid cells along the longer side of the contour's bounds.
    pub guard_resolution: usize,
    /// The minimiser.
    pub optimiser: Optimiser,
    /// When it stops.
    pub stopping: Stopping,
    /// The colour of the metacircles.
    pub colour: Rgb,
    /// The threshold `T`.
    pub threshold: f64,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            seeds: SeedOptions::default(),
            samples: 0,
            guard_resolution: 64,
            optimiser: Optimiser::LevenbergMarquardt,
            stopping: Stopping::default(),
            colour: Rgb::CLAY,
            threshold: DEFAULT_THRESHOLD,
        }
    }
}

/// How well a figure fits a contour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitReport {
    /// Metacircles in the figure.
    pub metacircles: usize,
    /// Contour samples.
    pub samples: usize,
    /// Optimiser iterations (0 when only measured).
    pub iterations: usize,
    /// Cost `½ Σ r²` before and after optimising (equal when only measured).
    pub initial_cost: f64,
    /// Cost after.
    pub final_cost: f64,
    /// Root mean square of `F − T` over the contour samples.
    pub rms_density: f64,
    /// Largest `|F − T|` over the contour samples.
    pub max_density: f64,
    /// Root mean square distance from the samples to the iso-curve (figure units).
    pub rms_distance: f64,
    /// Largest distance from a sample to the iso-curve (`∞` when the iso-curve was not reached
    /// from some sample).
    pub max_distance: f64,
    /// Largest distance from the traced iso-curve (on a lattice of step `size / 1024`, vertices
    /// refined onto the curve) to the contour: large when the figure has parts the contour
    /// does not (stray blobs, bulges between samples); `∞` when there is no iso-curve.
    pub boundary_distance: f64,
    /// Diagonal of the contour's bounds, to read the distances relative to the figure's size.
    pub size: f64,
    /// Guard points on the wrong side of the iso-curve (inside points outside the figure and
    /// outside points inside it).
    pub guards_violated: usize,
}

/// Fits metacircles to a contour: seeds on its medial axis, then optimises.
///
/// # Errors
/// [`FigureError::Option`] for a non-positive threshold or zero seeds.
pub fn fit_contour(
    contour: &Contour,
    options: &FitOptions,
) -> Result<(Figure, FitReport), FigureError> {
    check(options)?;
    let seeds = medial_discs(contour, &options.seeds);
    // A lone metacircle of density 1 reaches T = 0.5 at R/2: start at R = 2 d.
    let mut figure = Figure {
        metacircles: seeds
            .iter()
            .map(|d| Metacircle {
                colour: options.colour,
                ..Metacircle::new(d.centre, 2.0 * d.radius, 1.0)
            })
            .collect(),
        threshold: options.threshold,
    };
    // Overlapping seeds add up: scale the densities so that the contour starts near T.
    let samples = contour_samples(contour, options.samples);
    let mean: f64 = samples.iter().map(|&p| figure.field(p)).sum::<f64>() / samples.len() as f64;
    if mean > 0.0 {
        let k = options.threshold / mean;
        for m in &mut figure.metacircles {
            m.density = (m.density * k).min(options.threshold * 4.0);
        }
    }
    refit(&figure, contour, options)
}

/// Re-optimises an existing figure against a contour (warm start: after the contour moved).
///
/// # Errors
/// [`FigureError`] for an invalid figure, an empty one, or invalid options.
pub fn refit(
    figure: &Figure,
    contour: &Contour,
    options: &FitOptions,
) -> Result<(Figure, FitReport), FigureError> {
    check(options)?;
    figure.validate()?;
    let balls: Vec<&Metacircle> = figure
        .metacircles
        .iter()
        .filter(|m| m.radius > 0.0)
        .collect();
    if balls.is_empty() {
        return Err(FigureError::Empty(
            "the figure has no metacircle of positive radius to fit".into(),
        ));
    }
    let on = contour_samples(contour, options.samples);
    let mut samples: Vec<FitSample> = on
        .iter()
        .map(|&p| FitSample {
            p,
            z: 0.0,
            kind: SampleKind::On,
        })
        .collect();
    samples.extend(guard_samples(contour, options.guard_resolution, 0.0));
    samples.extend(ring_samples(contour, &on, options.guard_resolution, 0.0));
    let home = Home {
        contours: std::slice::from_ref(contour),
        z_range: None,
        weight: options.threshold / guard_cell(contour, options.guard_resolution),
    };
    let mut x: Vec<f64> = balls
        .iter()
        .flat_map(|m| [m.centre.x, m.centre.y, m.radius.ln(), m.density])
        .collect();
    let problem = BallProblem {
        spatial: false,
        samples: &samples,
        threshold: options.threshold,
        prior: balls.iter().map(|m| (m.radius.ln(), m.density)).collect(),
        homes: vec![Some(home); balls.len()],
    };
    let outcome = minimise(&problem, &mut x, options.optimiser, &options.stopping);
    let fitted = Figure {
        metacircles: balls
            .iter()
            .enumerate()
            .map(|(i, m)| Metacircle {
                centre: DVec2::new(x[4 * i], x[4 * i + 1]),
                radius: x[4 * i + 2].exp(),
                density: x[4 * i + 3],
                colour: m.colour,
            })
            .collect(),
        threshold: options.threshold,
    };
    fitted.validate()?;
    let mut report = measure(&fitted, contour, options.samples, options.guard_resolution);
    report.iterations = outcome.iterations;
    report.initial_cost = outcome.initial_cost;
    report.final_cost = outcome.final_cost;
    Ok((fitted, report))
}

/// How well `figure` fits `contour`, without optimising.
#[must_use]
pub fn measure(
    figure: &Figure,
    contour: &Contour,
    samples: usize,
    guard_resolution: usize,
) -> FitReport {
    let on = contour_samples(contour, samples);
    let t = figure.threshold;
    let mut sum2 = 0.0;
    let mut max_d = 0.0f64;
    let mut dist2 = 0.0;
    let mut max_dist = 0.0f64;
    let (lo, hi) = contour.bounds();
    let size = (hi - lo).length();
    for &p in &on {
        let r = figure.field(p) - t;
        sum2 += r * r;
        max_d = max_d.max(r.abs());
        match distance_to_iso(figure, p, size) {
            Some(d) => {
                dist2 += d * d;
                max_dist = max_dist.max(d);
            }
            None => max_dist = f64::INFINITY,
        }
    }
    let guards_violated = guard_samples(contour, guard_resolution, 0.0)
        .chain(ring_samples(contour, &on, guard_resolution, 0.0))
        .filter(|g| {
            let f = figure.field(g.p);
            match g.kind {
                SampleKind::Above => f < t,
                SampleKind::Below => f >= t,
                SampleKind::On => false,
            }
        })
        .count();
    let boundary_distance = match Lattice::around(figure, size / 1024.0) {
        Some(lattice) => {
            let lines = iso_lines(figure, &lattice, 3);
            let pts: Vec<DVec2> = lines
                .iter()
                .flat_map(|l| l.points.iter().copied())
                .collect();
            if pts.is_empty() {
                f64::INFINITY
            } else {
                pts.iter().map(|&p| contour.distance(p)).fold(0.0, f64::max)
            }
        }
        None => f64::INFINITY,
    };
    let n = on.len().max(1) as f64;
    let cost = 0.5 * sum2;
    FitReport {
        metacircles: figure.metacircles.len(),
        samples: on.len(),
        iterations: 0,
        initial_cost: cost,
        final_cost: cost,
        rms_density: (sum2 / n).sqrt(),
        max_density: max_d,
        rms_distance: (dist2 / n).sqrt(),
        max_distance: max_dist,
        boundary_distance,
        size,
        guards_violated,
    }
}

/// Distance from `p` to the iso-curve `F = T`, by Newton steps along the gradient
/// (`p ← p − (F − T) ∇F / |∇F|²`, each step at most `size / 20`); `None` when the iteration
/// does not settle on the curve (no density gradient near `p`).
#[must_use]
pub fn distance_to_iso(figure: &Figure, p: DVec2, size: f64) -> Option<f64> {
    super::falloff::distance_to_level(|q| figure.field_and_gradient(q), figure.threshold, p, size)
}

fn check(options: &FitOptions) -> Result<(), FigureError> {
    if !(options.threshold.is_finite() && options.threshold > 0.0) {
        return Err(FigureError::Threshold(options.threshold));
    }
    if options.seeds.max_seeds == 0 {
        return Err(FigureError::Option(
            "at least one metacircle must be seeded".into(),
        ));
    }
    if !(2..=4096).contains(&options.guard_resolution)
        || !(4..=8192).contains(&options.seeds.resolution)
    {
        return Err(FigureError::Option(
            "grid resolutions must be 2..=4096 (guards) and 4..=8192 (seeds)".into(),
        ));
    }
    Ok(())
}

/// The contour's samples: `n`, or by default one per 1/200 of the perimeter and at least four
/// per vertex, at most 1 000.
pub(crate) fn contour_samples(contour: &Contour, n: usize) -> Vec<DVec2> {
    let n = if n > 0 {
        n
    } else {
        (4 * contour.len()).clamp(200, 1000)
    };
    contour.resample(n)
}

/// Side of the guard grid's cells.
pub(crate) fn guard_cell(contour: &Contour, resolution: usize) -> f64 {
    let (lo, hi) = contour.bounds();
    (hi - lo).max_element() / resolution.max(2) as f64
}

/// Guard points half a guard cell off each contour sample, along the normal of the samples'
/// polyline, on either side: `Above` inside, `Below` outside (none nearer the contour than a
/// quarter cell, as happens in narrow parts).
pub(crate) fn ring_samples<'a>(
    contour: &'a Contour,
    on: &'a [DVec2],
    resolution: usize,
    z: f64,
) -> impl Iterator<Item = FitSample> + 'a {
    let cell = guard_cell(contour, resolution);
    let n = on.len();
    (0..n).flat_map(move |j| {
        let t = on[(j + 1) % n] - on[(j + n - 1) % n];
        let normal = t.perp().normalize_or_zero();
        [1.0, -1.0].into_iter().filter_map(move |sign| {
            let p = on[j] + normal * (sign * 0.5 * cell);
            if normal == DVec2::ZERO || contour.distance(p) < 0.25 * cell {
                return None;
            }
            let kind = if contour.contains(p) {
                SampleKind::Above
            } else {
                SampleKind::Below
            };
            Some(FitSample { p, z, kind })
        })
    })
}

/// Guard points at height `z` on a grid of `resolution` cells along the longer side of the
/// contour's bounds (grown by 15 % on each side): `Above` inside, `Below` outside, none within
/// half a cell of the contour.
pub(crate) fn guard_samples(
    contour: &Contour,
    resolution: usize,
    z: f64,
) -> impl Iterator<Item = FitSample> + '_ {
    let (lo, hi) = contour.bounds();
    let size = hi - lo;
    let cell = size.max_element() / resolution.max(2) as f64;
    let grow = 0.15 * size.max_element();
    let (lo, hi) = (lo - DVec2::splat(grow), hi + DVec2::splat(grow));
    let nx = ((hi.x - lo.x) / cell).ceil() as usize;
    let ny = ((hi.y - lo.y) / cell).ceil() as usize;
    (0..ny)
        .flat_map(move |j| (0..nx).map(move |i| (i, j)))
        .filter_map(move |(i, j)| {
            let p = lo + DVec2::new(i as f64 + 0.5, j as f64 + 0.5) * cell;
            if contour.distance(p) < 0.5 * cell {
                return None;
            }
            let kind = if contour.contains(p) {
                SampleKind::Above
            } else {
                SampleKind::Below
            };
            Some(FitSample { p, z, kind })
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ellipse(a: f64, b: f64, n: usize) -> Contour {
        Contour::new(
            (0..n)
                .map(|k| {
                    let t = k as f64 * std::f64::consts::TAU / n as f64;
                    DVec2::new(a * t.cos(), b * t.sin())
                })
                .collect(),
            "ellipse",
        )
        .unwrap()
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let home = [Contour::new(
            vec![
                DVec2::new(-0.2, -0.2),
                DVec2::new(0.2, -0.2),
                DVec2::new(0.0, 0.2),
            ],
            "home",
        )
        .unwrap()];
        for spatial in [false, true] {
            let z = |v: f64| if spatial { v } else { 0.0 };
            let samples = [
                FitSample {
                    p: DVec2::new(0.3, 0.2),
                    z: z(0.1),
                    kind: SampleKind::On,
                },
                FitSample {
                    p: DVec2::new(-0.4, 0.5),
                    z: z(0.0),
                    kind: SampleKind::Above,
                },
                FitSample {
                    p: DVec2::new(0.9, -0.2),
                    z: z(0.2),
                    kind: SampleKind::Below,
                },
            ];
            let problem = BallProblem {
                spatial,
                samples: &samples,
                threshold: 0.5,
                prior: vec![(0.0, 1.0); 3],
                homes: vec![
                    Some(Home {
                        contours: &home,
                        z_range: Some((-0.1, 0.1)),
                        weight: 0.7,
                    });
                    3
                ],
            };
            let x: Vec<f64> = if spatial {
                vec![
                    0.0, 0.1, 0.0, 0.2, 1.2, 0.5, -0.2, 0.3, 0.4, 0.9, 0.1, 0.3, -0.2, 0.1, -0.4,
                ]
            } else {
                vec![0.0, 0.1, 0.2, 1.2, 0.5, -0.2, 0.4, 0.9, 0.1, 0.3, 0.1, -0.4]
            };
            let n = x.len();
            let mut jac = Jacobian::default();
            problem.evaluate(&x, true, &mut jac);
            let mut dense = vec![vec![0.0; n]; jac.residuals.len()];
            for (j, row) in dense.iter_mut().enumerate() {
                let (c, v) = jac.row(j);
                for (&c, &v) in c.iter().zip(v) {
                    row[c as usize] += v;
                }
            }
            let h = 1e-7;
            for k in 0..n {
                let (mut xp, mut xm) = (x.clone(), x.clone());
                xp[k] += h;
                xm[k] -= h;
                let (mut jp, mut jm) = (Jacobian::default(), Jacobian::default());
                problem.evaluate(&xp, false, &mut jp);
                problem.evaluate(&xm, false, &mut jm);
                for (j, row) in dense.iter().enumerate() {
                    let fd = (jp.residuals[j] - jm.residuals[j]) / (2.0 * h);
                    assert!(
                        (fd - row[k]).abs() < 1e-6,
                        "spatial {spatial} row {j} col {k}: {fd} vs {}",
                        row[k]
                    );
                }
            }
        }
    }

    #[test]
    fn fits_an_ellipse_within_a_small_fraction_of_its_size() {
        let c = ellipse(100.0, 40.0, 80);
        let (fig, report) = fit_contour(&c, &FitOptions::default()).unwrap();
        assert!(report.final_cost < report.initial_cost);
        assert!(report.max_distance < 0.01 * report.size, "{report:?}");
        assert!(report.boundary_distance < 0.01 * report.size, "{report:?}");
        assert_eq!(report.guards_violated, 0, "{report:?}");
        assert!(fig.contains(DVec2::ZERO) && !fig.contains(DVec2::new(0.0, 60.0)));
    }

    #[test]
    fn distance_to_iso_of_a_lone_circle_is_exact() {
        let fig = Figure::new(vec![Metacircle::new(DVec2::ZERO, 2.0, 1.0)]);
        for r in [0.2, 0.7, 1.0, 1.5, 1.9] {
            let d = distance_to_iso(&fig, DVec2::new(r * 0.6, r * 0.8), 4.0).unwrap();
            assert!((d - (r - 1.0f64).abs()).abs() < 1e-9, "r {r}: {d}");
        }
        assert!(distance_to_iso(&fig, DVec2::new(3.0, 0.0), 4.0).is_none());
    }
}
