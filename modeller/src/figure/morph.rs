//! Morphing between two figures of metacircles (P0 §4.2 2)–3), Fig. 7 and 11).
//!
//! Corresponding curves are laid on both figures (curve `k` of the source matches curve `k` of
//! the destination: a spine, the legs…). The metacircles are matched through the curves'
//! coordinates:
//!
//! 1. each source metacircle's centre is carried to the destination by the curve warp from the
//!    source curves to the destination curves (`P = C_k(u_k) + v_k N(u_k)` → eq. (6), (7));
//! 2. it is paired with the destination metacircle nearest to that position;
//! 3. destination metacircles left unpaired are carried back to the source by the reverse warp
//!    and paired with the nearest source metacircle.
//!
//! A metacircle may be paired several times; when nothing lies within the matching distance, a
//! dummy of radius zero is created at the carried position, so that the metacircle grows from
//! (or shrinks to) nothing there. A metacircle paired `k` times gives each pair `1/k` of its
//! density at its end, so that the pairs sum exactly to the figure at either end (the density
//! is linear in `q`).
//!
//! At time `t ∈ [0, 1]` each pair's radius, density, colour and the threshold are interpolated
//! linearly, `(1 − t) a + t b`, so `t = 0` gives the source and `t = 1` the destination. The
//! centres either move on straight lines, or (option "skeleton", §4.2 3)) ride on the
//! interpolated curves: the curves' control points are interpolated, `C_k(t)`, and a pair's
//! centre is `(1 − t) W_s(t)(P_a) + t W_d(t)(P_b)` where `W_s(t)` warps from the source curves to
//! `C_k(t)` and `W_d(t)` from the destination curves (each the identity at its own end).

use glam::DVec2;

use crate::curve::warp::WarpParams;
use crate::curve::{BSpline, Bezier, Curve};

use super::error::FigureError;
use super::metacircle::{Figure, Metacircle, Rgb};
use super::warp::curve_warp;

/// How two figures are matched and interpolated.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MorphOptions {
    /// Pairs farther apart than this (after carrying one end across) get a dummy instead;
    /// `None`: twice the median radius of all the metacircles of both figures (on the shipped
    /// horse and tiger, a smaller distance leaves dummies in the middle of the bodies, whose
    /// growing and shrinking open gaps in the frames between).
    pub match_distance: Option<f64>,
    /// Move centres along the interpolated curves instead of straight lines.
    pub skeleton: bool,
    /// The Beier–Neely weights of the curve warps.
    pub params: WarpParams,
}

/// One end of a pair: a metacircle (its density already divided among its pairs), or a dummy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairEnd {
    /// The metacircle at this end (a dummy has radius 0).
    pub circle: Metacircle,
    /// Index of the metacircle in its figure, `None` for a dummy.
    pub index: Option<usize>,
}

/// Counts of a matching.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MatchStats {
    /// Pairs found carrying source metacircles to the destination (step 2).
    pub forward: usize,
    /// Pairs found carrying unpaired destination metacircles back (step 3).
    pub backward: usize,
    /// Dummies created at the destination end.
    pub dummies_destination: usize,
    /// Dummies created at the source end.
    pub dummies_source: usize,
}

/// A morph between two figures: their matched metacircles and curves.
#[derive(Debug, Clone)]
pub struct Morph {
    pairs: Vec<(PairEnd, PairEnd)>,
    thresholds: (f64, f64),
    curves: (Vec<Curve<DVec2>>, Vec<Curve<DVec2>>),
    options: MorphOptions,
    stats: MatchStats,
}

impl Morph {
    /// Matches the metacircles of `source` and `destination` through their curves.
    ///
    /// # Errors
    /// [`FigureError::Mismatch`] when the curve lists differ in length (or, with `skeleton`,
    /// when corresponding curves cannot be interpolated), [`FigureError::Warp`] when the curve
    /// warp refuses them, [`FigureError::WarpTooLarge`] when a warp's work (curves × the
    /// metacircles it carries) is over the cap, [`FigureError::Option`] for a bad matching
    /// distance, and the validation errors of the figures.
    pub fn new(
        source: (&Figure, &[Curve<DVec2>]),
        destination: (&Figure, &[Curve<DVec2>]),
        options: MorphOptions,
    ) -> Result<Self, FigureError> {
        let (src, src_curves) = source;
        let (dst, dst_curves) = destination;
        src.validate()?;
        dst.validate()?;
        // Each warp carries at most every metacircle of its side.
        let forward = curve_warp(
            src_curves,
            dst_curves,
            options.params,
            src.metacircles.len() as u64,
        )?;
        let backward = curve_warp(
            dst_curves,
            src_curves,
            options.params,
            dst.metacircles.len() as u64,
        )?;
        if options.skeleton {
            for (k, (a, b)) in src_curves.iter().zip(dst_curves).enumerate() {
                lerp_curve(a, b, 0.5).ok_or_else(|| FigureError::Mismatch {
                    what: format!("curve {k}: control points of source and destination (skeleton interpolation needs the same kind, degree and knots)"),
                    left: a.points().len(),
                    right: b.points().len(),
                })?;
            }
        }
        let live = |f: &Figure| -> Vec<usize> {
            (0..f.metacircles.len())
                .filter(|&i| f.metacircles[i].radius > 0.0)
                .collect()
        };
        let (src_live, dst_live) = (live(src), live(dst));
        let distance = match options.match_distance {
            Some(d) if d.is_finite() && d >= 0.0 => d,
            Some(d) => {
                return Err(FigureError::Option(format!(
                    "matching distance must be a non-negative number, got {d}"
                )));
            }
            None => {
                let mut r: Vec<f64> = src_live
                    .iter()
                    .map(|&i| src.metacircles[i].radius)
                    .chain(dst_live.iter().map(|&j| dst.metacircles[j].radius))
                    .collect();
                r.sort_by(f64::total_cmp);
                match r.len() {
                    0 => 0.0,
                    n if n % 2 == 1 => 2.0 * r[n / 2],
                    n => r[n / 2 - 1] + r[n / 2],
                }
            }
        };
        let nearest = |fig: &Figure, live: &[usize], p: DVec2| -> Option<usize> {
            live.iter()
                .copied()
                .map(|i| (i, fig.metacircles[i].centre.distance_squared(p)))
                .filter(|&(_, d2)| d2 <= distance * distance)
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(i, _)| i)
        };
        // (source index or dummy, destination index or dummy)
        let mut raw: Vec<(Result<usize, DVec2>, Result<usize, DVec2>)> = Vec::new();
        let mut stats = MatchStats::default();
        let mut dst_used = vec![false; dst.metacircles.len()];
        for &i in &src_live {
            let p = forward.warp_point(src.metacircles[i].centre);
            match nearest(dst, &dst_live, p) {
                Some(j) => {
                    dst_used[j] = true;
                    stats.forward += 1;
                    raw.push((Ok(i), Ok(j)));
                }
                None => {
                    stats.dummies_destination += 1;
                    raw.push((Ok(i), Err(p)));
                }
            }
        }
        for &j in dst_live.iter().filter(|&&j| !dst_used[j]) {
            let p = backward.warp_point(dst.metacircles[j].centre);
            match nearest(src, &src_live, p) {
                Some(i) => {
                    stats.backward += 1;
                    raw.push((Ok(i), Ok(j)));
                }
                None => {
                    stats.dummies_source += 1;
                    raw.push((Err(p), Ok(j)));
                }
            }
        }
        let mut src_count = vec![0usize; src.metacircles.len()];
        let mut dst_count = vec![0usize; dst.metacircles.len()];
        for (a, b) in &raw {
            if let Ok(i) = a {
                src_count[*i] += 1;
            }
            if let Ok(j) = b {
                dst_count[*j] += 1;
            }
        }
        let end = |fig: &Figure, count: &[usize], e: &Result<usize, DVec2>, other: &Metacircle| {
            match *e {
                Ok(i) => {
                    let m = fig.metacircles[i];
                    PairEnd {
                        circle: Metacircle {
                            density: m.density / count[i] as f64,
                            ..m
                        },
                        index: Some(i),
                    }
                }
                Err(p) => PairEnd {
                    circle: Metacircle {
                        centre: p,
                        radius: 0.0,
                        ..*other
                    },
                    index: None,
                },
            }
        };
        let pairs = raw
            .iter()
            .map(|(a, b)| {
                // A dummy takes the other end's (shared) density and colour: it only grows.
                let (sa, db) = match (a, b) {
                    (Ok(i), Ok(j)) => {
                        let s = src.metacircles[*i];
                        let d = dst.metacircles[*j];
                        (
                            end(
                                src,
                                &src_count,
                                a,
                                &Metacircle {
                                    density: d.density / dst_count[*j] as f64,
                                    ..d
                                },
                            ),
                            end(
                                dst,
                                &dst_count,
                                b,
                                &Metacircle {
                                    density: s.density / src_count[*i] as f64,
                                    ..s
                                },
                            ),
                        )
                    }
                    (Ok(i), Err(_)) => {
                        let sa = end(src, &src_count, a, &src.metacircles[*i]);
                        let db = end(dst, &dst_count, b, &sa.circle);
                        (sa, db)
                    }
                    (Err(_), Ok(j)) => {
                        let db = end(dst, &dst_count, b, &dst.metacircles[*j]);
                        let sa = end(src, &src_count, a, &db.circle);
                        (sa, db)
                    }
                    (Err(_), Err(_)) => unreachable_pair(),
                };
                (sa, db)
            })
            .collect();
        Ok(Self {
            pairs,
            thresholds: (src.threshold, dst.threshold),
            curves: (src_curves.to_vec(), dst_curves.to_vec()),
            options,
            stats,
        })
    }

    /// The matched pairs `(source end, destination end)`.
    #[must_use]
    pub fn pairs(&self) -> &[(PairEnd, PairEnd)] {
        &self.pairs
    }

    /// How the pairs were found.
    #[must_use]
    pub fn stats(&self) -> MatchStats {
        self.stats
    }

    /// The curves at time `t`: control points interpolated (the source's at `t = 0`, the
    /// destination's at `t = 1`; the source's throughout when they cannot be interpolated).
    #[must_use]
    pub fn curves_at(&self, t: f64) -> Vec<Curve<DVec2>> {
        self.curves
            .0
            .iter()
            .zip(&self.curves.1)
            .map(|(a, b)| lerp_curve(a, b, t).unwrap_or_else(|| a.clone()))
            .collect()
    }

    /// The figure at time `t` (clamped to `[0, 1]`): one metacircle per pair.
    ///
    /// # Errors
    /// [`FigureError::NotFinite`] for a NaN `t`; [`FigureError::Warp`] if a skeleton warp fails,
    /// [`FigureError::WarpTooLarge`] if its work (curves × pairs) is over the cap.
    pub fn at(&self, t: f64) -> Result<Figure, FigureError> {
        if t.is_nan() {
            return Err(FigureError::NotFinite {
                what: "morph time".into(),
            });
        }
        let t = t.clamp(0.0, 1.0);
        let lerp = |a: f64, b: f64| (1.0 - t) * a + t * b;
        let lerp2 = |a: DVec2, b: DVec2| (1.0 - t) * a + t * b;
        let skeleton = if self.options.skeleton && !self.curves.0.is_empty() {
            let mid = self.curves_at(t);
            // Each carries one centre per pair.
            let n = self.pairs.len() as u64;
            Some((
                curve_warp(&self.curves.0, &mid, self.options.params, n)?,
                curve_warp(&self.curves.1, &mid, self.options.params, n)?,
            ))
        } else {
            None
        };
        let metacircles = self
            .pairs
            .iter()
            .map(|(a, b)| {
                let (ca, cb) = (a.circle, b.circle);
                let centre = match &skeleton {
                    Some((ws, wd)) => lerp2(ws.warp_point(ca.centre), wd.warp_point(cb.centre)),
                    None => lerp2(ca.centre, cb.centre),
                };
                let colour = Rgb(std::array::from_fn(|k| {
                    lerp(ca.colour.0[k] as f64, cb.colour.0[k] as f64)
                        .round()
                        .clamp(0.0, 255.0) as u8
                }));
                Metacircle {
                    centre,
                    radius: lerp(ca.radius, cb.radius),
                    density: lerp(ca.density, cb.density),
                    colour,
                }
            })
            .collect();
        Ok(Figure {
            metacircles,
            threshold: lerp(self.thresholds.0, self.thresholds.1),
        })
    }
}

/// Never built: a pair always has at least one real metacircle.
fn unreachable_pair() -> (PairEnd, PairEnd) {
    let m = Metacircle::new(DVec2::ZERO, 0.0, 0.0);
    (
        PairEnd {
            circle: m,
            index: None,
        },
        PairEnd {
            circle: m,
            index: None,
        },
    )
}

/// `(1 − t) a + t b` on control points, for curves of the same kind, degree, count (and knots
/// for B-splines); `None` otherwise.
#[must_use]
pub fn lerp_curve(a: &Curve<DVec2>, b: &Curve<DVec2>, t: f64) -> Option<Curve<DVec2>> {
    let mix = |p: &[DVec2], q: &[DVec2]| -> Vec<DVec2> {
        p.iter()
            .zip(q)
            .map(|(&p, &q)| (1.0 - t) * p + t * q)
            .collect()
    };
    match (a, b) {
        (Curve::Bezier(p), Curve::Bezier(q)) if p.points().len() == q.points().len() => {
            Bezier::try_new(mix(p.points(), q.points()))
                .ok()
                .map(Curve::Bezier)
        }
        (Curve::BSpline(p), Curve::BSpline(q))
            if p.points().len() == q.points().len()
                && p.degree() == q.degree()
                && p.knots() == q.knots() =>
        {
            BSpline::try_new(p.degree(), p.knots().to_vec(), mix(p.points(), q.points()))
                .ok()
                .map(Curve::BSpline)
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(a: DVec2, b: DVec2) -> Curve<DVec2> {
        Bezier::new(vec![a, a.lerp(b, 1.0 / 3.0), a.lerp(b, 2.0 / 3.0), b]).into()
    }

    fn blob(offset: DVec2, n: usize) -> Figure {
        Figure::new(
            (0..n)
                .map(|k| Metacircle::new(offset + DVec2::new(10.0 * k as f64, 0.0), 12.0, 1.0))
                .collect(),
        )
    }

    #[test]
    fn ends_reproduce_the_figures_even_with_shared_and_dummy_circles() {
        let src = blob(DVec2::ZERO, 5);
        let mut dst = blob(DVec2::new(0.0, 40.0), 3);
        dst.metacircles
            .push(Metacircle::new(DVec2::new(100.0, 100.0), 6.0, 0.8)); // far: a dummy at the source end
        let sc = vec![line(DVec2::new(-5.0, 0.0), DVec2::new(45.0, 0.0))];
        let dc = vec![line(DVec2::new(-5.0, 40.0), DVec2::new(25.0, 40.0))];
        for skeleton in [false, true] {
            let m = Morph::new(
                (&src, &sc),
                (&dst, &dc),
                MorphOptions {
                    skeleton,
                    ..Default::default()
                },
            )
            .unwrap();
            assert!(m.stats().dummies_source >= 1);
            let (f0, f1) = (m.at(0.0).unwrap(), m.at(1.0).unwrap());
            for k in 0..400 {
                let p = DVec2::new(-20.0 + (k % 20) as f64 * 7.0, -20.0 + (k / 20) as f64 * 7.0);
                assert!(
                    (f0.field(p) - src.field(p)).abs() < 1e-12,
                    "{skeleton} t=0 at {p}"
                );
                assert!(
                    (f1.field(p) - dst.field(p)).abs() < 1e-12,
                    "{skeleton} t=1 at {p}"
                );
            }
        }
    }

    #[test]
    fn matching_follows_the_curves_not_the_plane() {
        // The destination's curve runs the other way: each source circle must pair with the
        // circle at the same curve parameter, not with the one at the same place.
        let src = Figure::new(vec![
            Metacircle::new(DVec2::new(0.0, 10.0), 5.0, 1.0),
            Metacircle::new(DVec2::new(20.0, 10.0), 5.0, 1.0),
        ]);
        let mut dst = src.clone();
        dst.metacircles.swap(0, 1);
        let sc = vec![line(DVec2::new(0.0, 10.0), DVec2::new(20.0, 10.0))];
        let dc = vec![line(DVec2::new(20.0, 10.0), DVec2::new(0.0, 10.0))];
        let m = Morph::new((&src, &sc), (&dst, &dc), MorphOptions::default()).unwrap();
        // Source circle 0 at x = 0 is carried to x = 20 = destination circle 0.
        assert_eq!(m.pairs().len(), 2);
        for (a, b) in m.pairs() {
            let (i, j) = (a.index.unwrap(), b.index.unwrap());
            assert_eq!(i, j);
        }
    }

    #[test]
    fn mismatched_curves_are_refused() {
        let f = blob(DVec2::ZERO, 2);
        let a = vec![line(DVec2::ZERO, DVec2::X)];
        assert!(matches!(
            Morph::new((&f, &a), (&f, &[]), MorphOptions::default()),
            Err(FigureError::Mismatch { .. })
        ));
        let quad: Curve<DVec2> = Bezier::new(vec![DVec2::ZERO, DVec2::X, DVec2::ONE]).into();
        assert!(
            Morph::new(
                (&f, &a),
                (&f, std::slice::from_ref(&quad)),
                MorphOptions::default()
            )
            .is_ok()
        );
        assert!(
            Morph::new(
                (&f, &a),
                (&f, &[quad]),
                MorphOptions {
                    skeleton: true,
                    ..Default::default()
                }
            )
            .is_err()
        );
        assert!(
            Morph::new((&f, &a), (&f, &a), MorphOptions::default())
                .unwrap()
                .at(f64::NAN)
                .is_err()
        );
    }
}
