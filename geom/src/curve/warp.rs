//! Curve-driven warping (P0 §4; docs/design.md §6): points, polygons and control nets carried along
//! by curves that the user deforms — Beier and Neely's field warping with curves in place of
//! line segments, in 2D and in 3D.
//!
//! ## Coordinates of a point relative to one curve
//! For a point `X` and an original curve `C_k`, let `u_k` be the parameter of the closest point
//! on `C_k` (Bezier clipping, [`Curve::closest`]) and `F(u) = (T, N₁, N₂)` an orthonormal frame
//! along the curve, `T` the unit tangent:
//!
//! `X = C_k(u_k) + w_k T(u_k) + v_k N₁(u_k) + z_k N₂(u_k)`.
//!
//! * In 2D `N₁ = T` turned by +90° and there is no `N₂`: `v_k` is the signed distance of seed
//!   000's eq. (5), `P = C_k(u_k) + v_k N(u_k)`.
//! * In 3D the frame is the rotation-minimising frame (double reflection: Wang, Jüttler, Zheng
//!   and Liu 2008) sampled along the curve, since a space curve has no single normal.
//! * `w_k` (along the tangent) is zero wherever the closest point is interior; it is the
//!   overshoot of a point beyond an end of an open curve, which is then carried rigidly with
//!   the end's frame (Beier and Neely extrapolate the line instead).
//!
//! When `C_k` is deformed into `C_k^d` (the same parameter domain), the point it carries is
//! (P0 eq. (6))
//!
//! `X_k^d = C_k^d(u_k) + w_k T^d(u_k) + v_k N₁^d(u_k) + z_k N₂^d(u_k)`,
//!
//! with the deformed curve's frame; in 3D the deformed curve's rotation-minimising frame starts
//! from the original's first frame turned by the smallest rotation that takes `T(u₀)` to
//! `T^d(u₀)` (so the result does not depend on how the original frame was started).
//!
//! ## Several curves: Beier–Neely weights
//! `X^d = X + Σ_k ŵ_k (X_k^d − X)`, `ŵ_k = w_k / (w₀ + Σ_j w_j)`, with the weights of Beier and
//! Neely (SIGGRAPH 1992, "Feature-based image metamorphosis"):
//!
//! `w_k = (L_k^p / (a + d_k))^b`
//!
//! * `d_k` — the distance from `X` to the original curve `C_k`;
//! * `L_k` — the arc length of `C_k`; `p ∈ [0, 1]` sets how much longer curves dominate
//!   (`p = 0`: all curves alike);
//! * `a ≥ 0` — the "stickiness": with `a = 0` (the default) a point *on* a curve has an
//!   infinite weight and follows that curve exactly; a small positive `a` gives a smoother
//!   field in which points on a curve follow it only nearly;
//! * `b ≥ 0` — how fast a curve's influence falls with distance (Beier and Neely use 0.5–2);
//! * `w₀ = (L̄^p / (a + reach))^b` — an optional still background (`L̄` the mean curve length):
//!   with a single curve, a point at distance `reach` from it moves half as far as the curve.
//!   With `reach = ∞` (the default) `w₀ = 0`, Beier and Neely's plain normalised average.
//!
//! Consequences (tested in `tests/it/curve_warp.rs` of the `nendo` crate): unchanged curves warp nothing (the identity,
//! exactly: unchanged curves are skipped); with `a = 0` a point on an unmoved curve stays put
//! and a point on a moved curve follows it exactly; moving all curves by one rigid motion in 2D
//! moves every point by it.
//!
//! ## Interactive use
//! [`CurveWarp::warp_point`] finds the closest points every time. During a drag the original
//! curves and the points stay the same; [`CurveWarp::bind`] computes every point's coordinates
//! and weights once, and [`Bound::apply`] then costs one curve evaluation and one frame per
//! point and moved curve (the 3D clay case: a patch grid's control net bound to the curves laid
//! on it, re-applied at every mouse move after [`CurveWarp::set_deformed`]).

use super::any::Curve;
use super::error::CurveError;
use super::point::Point;
use frames::Track;
use glam::{DVec2, DVec3};

/// Beier–Neely weight parameters (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WarpParams {
    /// `a ≥ 0`: added to the distance; 0 makes points on a curve follow it exactly.
    pub a: f64,
    /// `b ≥ 0`: the fall-off exponent of a curve's influence with distance.
    pub b: f64,
    /// `p ≥ 0`: the exponent of the curve length in the weight.
    pub p: f64,
    /// Distance at which a lone curve's pull is halved by the still background (`> 0`;
    /// `f64::INFINITY`, the default, for none).
    pub reach: f64,
}

impl Default for WarpParams {
    /// `a = 0`, `b = 2`, `p = 0.5`, no still background.
    fn default() -> Self {
        Self {
            a: 0.0,
            b: 2.0,
            p: 0.5,
            reach: f64::INFINITY,
        }
    }
}

impl WarpParams {
    /// Checks the parameters: `a`, `b`, `p` finite and non-negative, `reach` positive (infinity
    /// allowed).
    ///
    /// # Errors
    /// [`CurveError::NotFinite`] or [`CurveError::Negative`] naming the parameter.
    pub fn check(&self) -> Result<(), CurveError> {
        for (what, v) in [
            ("warp parameter a", self.a),
            ("warp parameter b", self.b),
            ("warp parameter p", self.p),
        ] {
            if !v.is_finite() {
                return Err(CurveError::NotFinite {
                    what: what.to_string(),
                });
            }
            if v < 0.0 {
                return Err(CurveError::Negative { what, value: v });
            }
        }
        if self.reach.is_nan() || self.reach <= 0.0 {
            return Err(CurveError::Negative {
                what: "warp reach (must be positive)",
                value: self.reach,
            });
        }
        Ok(())
    }

    /// The Beier–Neely weight `(L^p / (a + d))^b` (infinite for `a + d = 0`).
    #[must_use]
    pub fn weight(&self, length: f64, distance: f64) -> f64 {
        (length.powf(self.p) / (self.a + distance)).powf(self.b)
    }
}

/// The spaces curves warp in: `DVec2` (normal frames) and `DVec3` (rotation-minimising frames).
/// Sealed: implemented for those two only.
pub trait WarpSpace: Point + frames::FrameConstruction {}
impl WarpSpace for DVec2 {}
impl WarpSpace for DVec3 {}

/// A point's coordinates relative to one original curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveCoords {
    /// Parameter of the closest point `C(u)` on the original curve.
    pub u: f64,
    /// `(w, v, z)`: the offset `X − C(u)` along the frame `(T, N₁, N₂)` (`z = 0` in 2D).
    pub offset: [f64; 3],
    /// Distance from the point to the original curve.
    pub distance: f64,
    /// The normalised weight `ŵ` of this curve for the point (the weights of all curves and the
    /// still background sum to 1).
    pub weight: f64,
}

/// One curve of a warp: the original, its deformed state, and what evaluating them needs.
#[derive(Debug, Clone)]
struct Pair<P: WarpSpace> {
    original: Curve<P>,
    orig_track: Track<P>,
    orig_frames: P::Frames,
    deformed: Curve<P>,
    def_track: Track<P>,
    def_frames: P::Frames,
    length: f64,
    /// The deformed curve equals the original: it moves nothing.
    still: bool,
}

/// A warp by several curves, each given as its original and its deformed state (see the module
/// docs for the formulas and the parameters).
///
/// ```
/// use glam::DVec2;
/// use nendo_geom::curve::{Bezier, Curve};
/// use nendo_geom::curve::warp::{CurveWarp, WarpParams};
/// let original: Curve<DVec2> = Bezier::new(vec![DVec2::ZERO, DVec2::new(1.0, 1.0), DVec2::new(2.0, 0.0)]).into();
/// // The deformed curve: the same one lifted by 0.5.
/// let lifted: Curve<DVec2> = Bezier::new(vec![DVec2::new(0.0, 0.5), DVec2::new(1.0, 1.5), DVec2::new(2.0, 0.5)]).into();
/// let warp = CurveWarp::new(vec![(original, lifted)], WarpParams::default())?;
/// let moved = warp.warp_point(DVec2::new(1.0, -2.0));
/// assert!((moved - DVec2::new(1.0, -1.5)).length() < 1e-9);
/// # Ok::<(), nendo_geom::curve::CurveError>(())
/// ```
#[derive(Debug, Clone)]
pub struct CurveWarp<P: WarpSpace> {
    pairs: Vec<Pair<P>>,
    params: WarpParams,
    still_weight: f64,
}

impl<P: WarpSpace> CurveWarp<P> {
    /// A warp from pairs `(original, deformed)`. Each deformed curve must have its original's
    /// parameter domain (points correspond by parameter).
    ///
    /// # Errors
    /// Bad parameters ([`WarpParams::check`]); [`CurveError::OutOfDomain`] when a deformed
    /// curve's domain differs from its original's.
    pub fn new(pairs: Vec<(Curve<P>, Curve<P>)>, params: WarpParams) -> Result<Self, CurveError> {
        params.check()?;
        let mut out = Vec::with_capacity(pairs.len());
        for (original, deformed) in pairs {
            check_domains(&original, &deformed)?;
            let orig_track = Track::new(&original);
            let orig_frames = P::frames(&orig_track, None);
            let def_track = Track::new(&deformed);
            let def_frames = P::frames(&def_track, Some((&orig_track, &orig_frames)));
            let length = orig_track.length();
            let still = original == deformed;
            out.push(Pair {
                original,
                orig_track,
                orig_frames,
                deformed,
                def_track,
                def_frames,
                length,
                still,
            });
        }
        let still_weight = if params.reach.is_finite() && !out.is_empty() {
            let mean = out.iter().map(|p| p.length).sum::<f64>() / out.len() as f64;
            params.weight(mean, params.reach)
        } else {
            0.0
        };
        Ok(Self {
            pairs: out,
            params,
            still_weight,
        })
    }

    /// A warp whose curves have not moved yet (each deformed curve is its original): move them
    /// with [`Self::set_deformed`].
    ///
    /// # Errors
    /// Bad parameters ([`WarpParams::check`]).
    pub fn still(originals: &[Curve<P>], params: WarpParams) -> Result<Self, CurveError> {
        Self::new(
            originals.iter().map(|c| (c.clone(), c.clone())).collect(),
            params,
        )
    }

    /// Number of curves.
    #[must_use]
    pub fn len(&self) -> usize {
        self.pairs.len()
    }

    /// True when the warp has no curve (it is then the identity).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// The weight parameters.
    #[must_use]
    pub fn params(&self) -> WarpParams {
        self.params
    }

    /// Original curve `k`.
    ///
    /// # Panics
    /// If `k ≥ len()`.
    #[must_use]
    pub fn original(&self, k: usize) -> &Curve<P> {
        &self.pairs[k].original
    }

    /// Deformed curve `k`.
    ///
    /// # Panics
    /// If `k ≥ len()`.
    #[must_use]
    pub fn deformed(&self, k: usize) -> &Curve<P> {
        &self.pairs[k].deformed
    }

    /// Replaces the deformed state of curve `k` (e.g. at every mouse move of a drag).
    ///
    /// # Errors
    /// [`CurveError::Index`] for a bad `k`; [`CurveError::OutOfDomain`] when the curve's domain
    /// differs from its original's.
    pub fn set_deformed(&mut self, k: usize, curve: Curve<P>) -> Result<(), CurveError> {
        let len = self.pairs.len();
        let pair = self
            .pairs
            .get_mut(k)
            .ok_or(CurveError::Index { index: k, len })?;
        check_domains(&pair.original, &curve)?;
        pair.def_track = Track::new(&curve);
        pair.def_frames = P::frames(&pair.def_track, Some((&pair.orig_track, &pair.orig_frames)));
        pair.still = pair.original == curve;
        pair.deformed = curve;
        Ok(())
    }

    /// The coordinates of `x` relative to every original curve, with the normalised weights.
    #[must_use]
    pub fn coordinates(&self, x: P) -> Vec<CurveCoords> {
        let mut out: Vec<CurveCoords> = self
            .pairs
            .iter()
            .map(|pair| {
                let (u, c, distance) = pair.orig_track.closest(x);
                let f = P::frame_at(&pair.orig_track, &pair.orig_frames, u);
                let d = x - c;
                CurveCoords {
                    u,
                    offset: [d.dot(f[0]), d.dot(f[1]), d.dot(f[2])],
                    distance,
                    weight: self.params.weight(pair.length, distance),
                }
            })
            .collect();
        normalise(&mut out, self.still_weight);
        out
    }

    /// The warped position of `x` (`X^d` of the module docs).
    #[must_use]
    pub fn warp_point(&self, x: P) -> P {
        if self.pairs.iter().all(|p| p.still) {
            return x;
        }
        let coords = self.coordinates(x);
        self.apply_coords(x, coords.iter().enumerate())
    }

    /// Every point warped.
    #[must_use]
    pub fn warp_points(&self, xs: &[P]) -> Vec<P> {
        xs.iter().map(|&x| self.warp_point(x)).collect()
    }

    /// A closed polygon warped: every edge longer than `max_edge` is first divided evenly so
    /// that the warped outline follows the curves' bending (`max_edge = f64::INFINITY` warps
    /// the vertices only). Returns the vertices of the warped, refined polygon.
    ///
    /// # Errors
    /// [`CurveError::Negative`] unless `max_edge` is positive (infinity allowed).
    pub fn warp_polygon(&self, vertices: &[P], max_edge: f64) -> Result<Vec<P>, CurveError> {
        if max_edge.is_nan() || max_edge <= 0.0 {
            return Err(CurveError::Negative {
                what: "max_edge (must be positive)",
                value: max_edge,
            });
        }
        let mut refined = Vec::with_capacity(vertices.len());
        for (i, &a) in vertices.iter().enumerate() {
            let b = vertices[(i + 1) % vertices.len()];
            let pieces = if max_edge.is_finite() {
                ((b - a).length() / max_edge).ceil().clamp(1.0, 1e6) as usize
            } else {
                1
            };
            for s in 0..pieces {
                refined.push(a.lerp_to(b, s as f64 / pieces as f64));
            }
        }
        Ok(self.warp_points(&refined))
    }

    /// The coordinates and weights of every point relative to the original curves, computed
    /// once for repeated [`Bound::apply`] while the curves are dragged.
    #[must_use]
    pub fn bind(&self, xs: &[P]) -> Bound<P> {
        let mut per_curve: Vec<Vec<BoundEntry>> = vec![Vec::new(); self.pairs.len()];
        for (i, &x) in xs.iter().enumerate() {
            for (k, c) in self.coordinates(x).into_iter().enumerate() {
                if c.weight > 0.0 {
                    per_curve[k].push(BoundEntry {
                        point: i as u32,
                        u: c.u,
                        offset: c.offset,
                        weight: c.weight,
                    });
                }
            }
        }
        // Along each curve in parameter order: the deformed curve is then read in order.
        for list in &mut per_curve {
            list.sort_by(|a, b| a.u.total_cmp(&b.u));
        }
        Bound {
            points: xs.to_vec(),
            per_curve,
        }
    }

    fn apply_coords<'a>(&self, x: P, coords: impl Iterator<Item = (usize, &'a CurveCoords)>) -> P {
        let mut moved = P::ZERO;
        for (k, c) in coords {
            let pair = &self.pairs[k];
            if pair.still || c.weight == 0.0 {
                continue;
            }
            moved = moved + (carried(pair, c.u, c.offset) - x) * c.weight;
        }
        x + moved
    }
}

/// `X_k^d`: the point at `offset` in the deformed curve's frame at `u`.
#[inline]
fn carried<P: WarpSpace>(pair: &Pair<P>, u: f64, offset: [f64; 3]) -> P {
    let at = pair.def_track.locate(u);
    let (c, t) = pair.def_track.point_tangent_at(at);
    let f = P::frame_with(&pair.def_track, &pair.def_frames, at, c, t);
    c + f[0] * offset[0] + f[1] * offset[1] + f[2] * offset[2]
}

/// Turns raw weights into `ŵ_k = w_k / (w₀ + Σ w_j)`; points on curves (infinite weights) take
/// the mean of those curves only.
fn normalise(coords: &mut [CurveCoords], still_weight: f64) {
    let on_curve = coords.iter().filter(|c| !c.weight.is_finite()).count();
    if on_curve > 0 {
        for c in coords.iter_mut() {
            c.weight = if c.weight.is_finite() {
                0.0
            } else {
                1.0 / on_curve as f64
            };
        }
        return;
    }
    let total = still_weight + coords.iter().map(|c| c.weight).sum::<f64>();
    for c in coords.iter_mut() {
        c.weight = if total > 0.0 && total.is_finite() {
            c.weight / total
        } else {
            0.0
        };
    }
}

fn check_domains<P: Point>(original: &Curve<P>, deformed: &Curve<P>) -> Result<(), CurveError> {
    let (a, b) = original.domain();
    let (c, d) = deformed.domain();
    if a != c || b != d {
        let t = if a != c { c } else { d };
        return Err(CurveError::OutOfDomain {
            t,
            range: format!(
                "the original curve's domain [{}, {}] (a deformed curve must keep it)",
                crate::num::Compact(a),
                crate::num::Compact(b)
            ),
        });
    }
    Ok(())
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct BoundEntry {
    point: u32,
    u: f64,
    offset: [f64; 3],
    weight: f64,
}

/// Points bound to the original curves of a [`CurveWarp`]: their closest parameters, frame
/// offsets and normalised weights, ready to be carried by the deformed curves.
#[derive(Debug, Clone, PartialEq)]
pub struct Bound<P> {
    points: Vec<P>,
    /// Per curve, the points it carries with a non-zero weight, in parameter order.
    per_curve: Vec<Vec<BoundEntry>>,
}

impl<P: WarpSpace> Bound<P> {
    /// The points as they were bound.
    #[must_use]
    pub fn points(&self) -> &[P] {
        &self.points
    }

    /// The bound points carried by the warp's current deformed curves. `warp` must have the
    /// original curves the points were bound to (the one that bound them, its deformed curves
    /// changed since with [`CurveWarp::set_deformed`]).
    ///
    /// # Errors
    /// [`CurveError::Index`] when `warp` has a different number of curves.
    pub fn apply(&self, warp: &CurveWarp<P>) -> Result<Vec<P>, CurveError> {
        let mut out = self.points.clone();
        self.apply_into(warp, &mut out)?;
        Ok(out)
    }

    /// [`Self::apply`] into `out` (which must hold one entry per bound point).
    ///
    /// # Errors
    /// As [`Self::apply`]; [`CurveError::Index`] when `out` has the wrong length.
    pub fn apply_into(&self, warp: &CurveWarp<P>, out: &mut [P]) -> Result<(), CurveError> {
        if warp.len() != self.per_curve.len() {
            return Err(CurveError::Index {
                index: self.per_curve.len(),
                len: warp.len(),
            });
        }
        if out.len() != self.points.len() {
            return Err(CurveError::Index {
                index: out.len(),
                len: self.points.len(),
            });
        }
        out.copy_from_slice(&self.points);
        // Only the moved curves' points are touched; each adds ŵ_k (X_k^d − X).
        for (pair, list) in warp.pairs.iter().zip(&self.per_curve) {
            if pair.still {
                continue;
            }
            for e in list {
                let i = e.point as usize;
                let x = self.points[i];
                out[i] = out[i] + (carried(pair, e.u, e.offset) - x) * e.weight;
            }
        }
        Ok(())
    }
}

/// The frames along curves: per space, how they are built and read.
mod frames {
    use crate::curve::any::Curve;
    use crate::curve::bezier::{Bezier, MAX_DEGREE};
    use crate::curve::closest::closest_bezier;
    use crate::curve::point::Point;
    use glam::{DQuat, DVec2, DVec3};
    use std::fmt::Debug;

    /// A curve as Bezier segments over its parameter domain, for evaluation with tangents,
    /// closest points and arc length.
    #[derive(Debug, Clone)]
    pub struct Track<P> {
        pub(super) segs: Vec<Bezier<P>>,
        /// Segment `i` covers `[bounds[i], bounds[i+1]]`.
        pub(super) bounds: Vec<f64>,
        /// A length scale of the control points (for degeneracy tests).
        scale: f64,
    }

    impl<P: Point> Track<P> {
        pub fn new(curve: &Curve<P>) -> Self {
            let segments = curve.segments();
            let mut segs = Vec::with_capacity(segments.len());
            let mut bounds = Vec::with_capacity(segments.len() + 1);
            for s in segments.iter() {
                if bounds.is_empty() {
                    bounds.push(s.start);
                }
                segs.push(s.bezier.clone());
                bounds.push(s.end);
            }
            let (lo, hi) = curve.control_bounds();
            Self {
                segs,
                bounds,
                scale: (hi - lo).length(),
            }
        }

        pub fn domain(&self) -> (f64, f64) {
            (self.bounds[0], self.bounds[self.bounds.len() - 1])
        }

        /// The segment holding `u` (clamped to the domain) and the local parameter.
        #[inline]
        pub(super) fn locate(&self, u: f64) -> (usize, f64) {
            let (a, b) = self.domain();
            let u = u.clamp(a, b);
            let n = self.segs.len();
            // Last segment whose start is ≤ u.
            let i = self.bounds[1..n].partition_point(|&s| s <= u);
            let (s0, s1) = (self.bounds[i], self.bounds[i + 1]);
            (
                i,
                if s1 > s0 {
                    ((u - s0) / (s1 - s0)).clamp(0.0, 1.0)
                } else {
                    0.0
                },
            )
        }

        /// `C(u)` and the unit tangent there (see [`unit_tangent`] for degenerate points).
        #[inline]
        pub fn point_tangent(&self, u: f64) -> (P, P) {
            self.point_tangent_at(self.locate(u))
        }

        /// [`Self::point_tangent`] at a located parameter (segment, local parameter).
        #[inline]
        pub fn point_tangent_at(&self, (i, s): (usize, f64)) -> (P, P) {
            let seg = &self.segs[i];
            let (c, d) = point_and_derivative(seg.points(), s);
            (c, unit_tangent(seg, s, d, self.scale))
        }

        /// Closest parameter, point and distance to `q` over all segments.
        pub fn closest(&self, q: P) -> (f64, P, f64) {
            let mut best = (
                self.bounds[0],
                self.segs[0].points()[0],
                (self.segs[0].points()[0] - q).length(),
            );
            let mut r = best.2;
            for (i, seg) in self.segs.iter().enumerate() {
                if let Some(n) = closest_bezier(seg, q, r)
                    && (n.distance < best.2 || i == 0)
                {
                    let (s0, s1) = (self.bounds[i], self.bounds[i + 1]);
                    best = (s0 + n.u * (s1 - s0), n.point, n.distance);
                    r = n.distance;
                }
            }
            best
        }

        /// Arc length by 8-point Gauss–Legendre quadrature on four pieces of every segment.
        pub fn length(&self) -> f64 {
            const X: [f64; 4] = [
                0.183_434_642_495_649_8,
                0.525_532_409_916_329,
                0.796_666_477_413_626_7,
                0.960_289_856_497_536_3,
            ];
            const W: [f64; 4] = [
                0.362_683_783_378_362,
                0.313_706_645_877_887_3,
                0.222_381_034_453_374_5,
                0.101_228_536_290_376_3,
            ];
            let mut total = 0.0;
            for seg in &self.segs {
                for piece in 0..4 {
                    let (a, b) = (piece as f64 / 4.0, (piece + 1) as f64 / 4.0);
                    let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
                    for (x, w) in X.iter().zip(W) {
                        for s in [m - h * x, m + h * x] {
                            total += w * h * point_and_derivative(seg.points(), s).1.length();
                        }
                    }
                }
            }
            total
        }
    }

    /// `C(s)` and `C'(s)` of a Bezier segment by one de Casteljau run (the last level's two points
    /// give the derivative `n (b₁ − b₀)`).
    #[inline]
    pub fn point_and_derivative<P: Point>(pts: &[P], s: f64) -> (P, P) {
        macro_rules! fixed {
            ($($n:literal)*) => {
                match pts.len() {
                    1 => (pts[0], P::ZERO),
                    $($n => {
                        let mut buf: [P; $n] = pts.try_into().unwrap_or([P::ZERO; $n]);
                        casteljau_last_two(&mut buf, s)
                    })*
                    len => {
                        let mut buf = [P::ZERO; MAX_DEGREE + 1];
                        buf[..len].copy_from_slice(pts);
                        casteljau_last_two(&mut buf[..len], s)
                    }
                }
            };
        }
        fixed!(2 3 4 5 6 7 8 9 10)
    }

    /// De Casteljau down to the last two points `b₀, b₁`: `(lerp(b₀, b₁, s), n (b₁ − b₀))`.
    #[inline(always)]
    fn casteljau_last_two<P: Point>(buf: &mut [P], s: f64) -> (P, P) {
        let n = buf.len() - 1;
        for r in 1..n {
            for i in 0..=n - r {
                buf[i] = buf[i].lerp_to(buf[i + 1], s);
            }
        }
        (buf[0].lerp_to(buf[1], s), (buf[1] - buf[0]) * n as f64)
    }

    /// The unit tangent of a segment at `s` from its derivative `d`; where `d` vanishes (repeated
    /// control points at an end, a cusp) the direction of a short secant, then of the chord, then
    /// the first axis.
    #[inline]
    pub fn unit_tangent<P: Point>(seg: &Bezier<P>, s: f64, d: P, scale: f64) -> P {
        let tiny = 1e-12 * scale.max(f64::MIN_POSITIVE);
        let len = d.length();
        if len > tiny {
            return d * (1.0 / len);
        }
        let h = 1e-4;
        let (a, b) = ((s - h).max(0.0), (s + h).min(1.0));
        let secant = seg.eval(b) - seg.eval(a);
        if secant.length() > tiny * 1e-4 {
            return secant * (1.0 / secant.length());
        }
        let pts = seg.points();
        let chord = pts[pts.len() - 1] - pts[0];
        if chord.length() > 0.0 {
            return chord * (1.0 / chord.length());
        }
        let mut axis = [0.0; 3];
        axis[0] = 1.0;
        P::from_coords(&axis[..P::DIM]).unwrap_or(P::ZERO)
    }

    /// Frame construction for one space (sealed into [`super::WarpSpace`]).
    pub trait FrameConstruction: Point {
        /// Whatever the frames along a curve need precomputed.
        type Frames: Clone + Debug + Send + Sync;
        /// The frames along `track`; `like` gives the original curve's track and frames when
        /// `track` is its deformed state.
        fn frames(track: &Track<Self>, like: Option<(&Track<Self>, &Self::Frames)>)
        -> Self::Frames;
        /// `(T, N₁, N₂)` at the located parameter `at` (segment, local parameter; see
        /// [`Track::locate`]), given the point `c` and unit tangent `t` there.
        fn frame_with(
            track: &Track<Self>,
            frames: &Self::Frames,
            at: (usize, f64),
            c: Self,
            t: Self,
        ) -> [Self; 3];
        /// `(T, N₁, N₂)` at `u`.
        fn frame_at(track: &Track<Self>, frames: &Self::Frames, u: f64) -> [Self; 3] {
            let at = track.locate(u);
            let (c, t) = track.point_tangent_at(at);
            Self::frame_with(track, frames, at, c, t)
        }
    }

    impl FrameConstruction for DVec2 {
        type Frames = ();
        fn frames(_: &Track<Self>, _: Option<(&Track<Self>, &())>) {}
        #[inline]
        fn frame_with(_: &Track<Self>, _: &(), _: (usize, f64), _: Self, t: Self) -> [Self; 3] {
            [t, t.perp(), DVec2::ZERO]
        }
    }

    /// A rotation-minimising frame sampled along a curve: at each sample parameter, the point,
    /// the unit tangent and the first normal `r` (the second is `t × r`).
    #[derive(Debug, Clone)]
    pub struct Rmf {
        us: Vec<f64>,
        xs: Vec<DVec3>,
        ts: Vec<DVec3>,
        rs: Vec<DVec3>,
    }

    /// Samples per Bezier segment.
    const SAMPLES: usize = 32;

    /// One double-reflection step (Wang, Jüttler, Zheng, Liu 2008): the normal `r0` at `x0`
    /// (tangent `t0`) carried to `x1` (tangent `t1`) by the reflection in the bisecting plane of
    /// `x0 x1` and then the one taking the reflected tangent to `t1`.
    #[inline]
    fn reflect_step(x0: DVec3, t0: DVec3, r0: DVec3, x1: DVec3, t1: DVec3) -> DVec3 {
        let v1 = x1 - x0;
        let c1 = v1.dot(v1);
        let (rl, tl) = if c1 > 0.0 {
            (
                r0 - v1 * (2.0 / c1 * v1.dot(r0)),
                t0 - v1 * (2.0 / c1 * v1.dot(t0)),
            )
        } else {
            (r0, t0)
        };
        let v2 = t1 - tl;
        let c2 = v2.dot(v2);
        let r = if c2 > 0.0 {
            rl - v2 * (2.0 / c2 * v2.dot(rl))
        } else {
            rl
        };
        // The reflections are orthogonal maps: `r` is a unit vector perpendicular to `t1` up to
        // rounding; remove the rounding's component along `t1`.
        r - t1 * r.dot(t1)
    }

    impl FrameConstruction for DVec3 {
        type Frames = Rmf;

        fn frames(track: &Track<Self>, like: Option<(&Track<Self>, &Rmf)>) -> Rmf {
            let (a, b) = track.domain();
            let count = track.segs.len() * SAMPLES + 1;
            let mut rmf = Rmf {
                us: Vec::with_capacity(count),
                xs: Vec::with_capacity(count),
                ts: Vec::with_capacity(count),
                rs: Vec::with_capacity(count),
            };
            for i in 0..track.segs.len() {
                let (s0, s1) = (track.bounds[i], track.bounds[i + 1]);
                let last = if i + 1 == track.segs.len() {
                    SAMPLES
                } else {
                    SAMPLES - 1
                };
                for j in 0..=last {
                    rmf.us.push(s0 + (s1 - s0) * j as f64 / SAMPLES as f64);
                }
            }
            if let Some(u) = rmf.us.last_mut() {
                *u = b;
            }
            if rmf.us.is_empty() {
                rmf.us.push(a);
            }
            for &u in &rmf.us {
                let (x, t) = track.point_tangent(u);
                rmf.xs.push(x);
                rmf.ts.push(t);
            }
            let t0 = rmf.ts[0];
            let r0 = match like {
                // Turn the original's first normal by the smallest rotation taking its first
                // tangent onto ours.
                Some((_, orig)) => {
                    let q = DQuat::from_rotation_arc(orig.ts[0], t0);
                    let r = q * orig.rs[0];
                    (r - t0 * r.dot(t0))
                        .try_normalize()
                        .unwrap_or_else(|| t0.any_orthonormal_vector())
                }
                None => t0.any_orthonormal_vector(),
            };
            rmf.rs.push(r0);
            for k in 1..rmf.us.len() {
                let r = reflect_step(
                    rmf.xs[k - 1],
                    rmf.ts[k - 1],
                    rmf.rs[k - 1],
                    rmf.xs[k],
                    rmf.ts[k],
                )
                .try_normalize()
                .unwrap_or_else(|| rmf.ts[k].any_orthonormal_vector());
                rmf.rs.push(r);
            }
            rmf
        }

        #[inline]
        fn frame_with(
            _: &Track<Self>,
            rmf: &Rmf,
            (i, s): (usize, f64),
            c: Self,
            t: Self,
        ) -> [Self; 3] {
            // Segment i's samples start at index i·SAMPLES, evenly spaced in its parameter.
            let k = (i * SAMPLES + (s * SAMPLES as f64) as usize).min(rmf.us.len() - 1);
            let r = reflect_step(rmf.xs[k], rmf.ts[k], rmf.rs[k], c, t);
            [t, r, t.cross(r)]
        }
    }
}

#[cfg(test)]
mod tests;
