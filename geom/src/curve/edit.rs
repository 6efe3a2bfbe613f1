//! Editing curves where they are grabbed (P0 §3, P4 §3(2); docs/design.md §5): grab anywhere, split,
//! tangent edit at a joint, insert a control point.
//!
//! ## Grab
//! A curve `C(u) = Σ_k P_k B_k(u)` (Bernstein polynomials `B_k^n` of a Bezier curve, B-spline basis
//! functions `N_{k,p}` of a B-spline) is grabbed at the parameter `u` of its closest point to the
//! hand. Moving the control points by `ΔP_k = c_k ΔP` moves the grabbed point by
//! `Σ_k B_k(u) c_k ΔP`, so the grabbed point follows the hand *exactly* when `Σ_k B_k(u) c_k = 1`:
//!
//! * [`GrabMethod::LargestWeight`] (P4; the default): only the control point `k` with the
//!   largest `B_k(u)` moves, `ΔP_k = ΔP / B_k(u)`;
//! * [`GrabMethod::NearestParameter`] (P0 eq. (4)): only the control point whose own
//!   parameter is nearest `u` moves — `k = round(u·n)` on a Bezier curve, the nearest Greville
//!   abscissa `(t_{k+1} + … + t_{k+p})/p` on a B-spline;
//! * [`GrabMethod::LeastChange`]: every control point moves, by the smallest total change
//!   `Σ |ΔP_k|²` that still carries `C(u)` by exactly `ΔP`: `ΔP_k = B_k(u) ΔP / Σ_j B_j(u)²`
//!   (the minimum-norm solution of the one linear condition), which spreads the move smoothly.
//!
//! With [`GrabOptions::keep_ends`] (P4) the first and last control points never move: on a
//! Bezier curve or a clamped B-spline the curve's end points stay where they are.
//!
//! ## Split, tangent edit, insertion
//! * [`split`]: de Casteljau subdivision of a Bezier curve, knot insertion up to multiplicity `p`
//!   for a B-spline; the halves share the split point `Q`.
//! * [`tangent_edit`] at a joint `Q` of two curves (the left curve's last control point is the
//!   right curve's first): moving `Q_L`, the left neighbour of `Q`, to a target puts `Q_R` on the
//!   line from the target through `Q`, so that `Q_L, Q, Q_R` stay collinear (the joint stays G1);
//!   `Q_R` keeps its distance to `Q` ([`Follow::KeepLength`]) or scales with `Q_L`'s
//!   ([`Follow::KeepRatio`], which keeps a C1 joint C1). Symmetrically for the right side.
//! * [`insert_control_point`]: degree elevation of a Bezier curve, knot insertion at `u` in a
//!   B-spline; the curve is unchanged and has one more control point to grab.

use super::any::Curve;
use super::bezier::Bezier;
use super::bspline::BSpline;
use super::error::CurveError;
use super::point::Point;

/// The weights `w_i` of the control points in the `order`-th derivative at `u`:
/// `C^{(order)}(u) = Σ_i w_i P_i` — the basis functions (order 0) or their derivatives. `u` is
/// the curve's own parameter (a B-spline's global parameter).
///
/// Computed by the triangular scheme of the B-spline basis and its derivatives (Piegl and
/// Tiller, *The NURBS Book*, algorithm A2.3), a Bezier curve of degree `n` being the B-spline
/// with the knots `0^{n+1} 1^{n+1}`.
///
/// ```
/// use glam::DVec2;
/// use nendo_geom::curve::{Bezier, Curve};
/// use nendo_geom::curve::edit::control_weights;
/// let c: Curve<DVec2> = Bezier::new(vec![DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::ONE]).into();
/// let w = control_weights(&c, 0.5, 0)?;
/// assert_eq!(w, vec![0.125, 0.375, 0.375, 0.125]);
/// # Ok::<(), nendo_geom::curve::CurveError>(())
/// ```
///
/// # Errors
/// [`CurveError::OutOfDomain`] for a `u` outside the domain (or not finite).
pub fn control_weights<P: Point>(
    curve: &Curve<P>,
    u: f64,
    order: usize,
) -> Result<Vec<f64>, CurveError> {
    let u = in_domain(curve, u)?;
    let mut out = vec![0.0; curve.points().len()];
    match curve {
        Curve::Bezier(c) => {
            let n = c.degree();
            if n == 0 {
                out[0] = if order == 0 { 1.0 } else { 0.0 };
                return Ok(out);
            }
            let mut knots = vec![0.0; n + 1];
            knots.extend(std::iter::repeat_n(1.0, n + 1));
            let ders = basis_derivatives(&knots, n, n, u, order);
            out.copy_from_slice(&ders[order]);
        }
        Curve::BSpline(s) => {
            let p = s.degree();
            let k = s.span(u);
            let ders = basis_derivatives(s.knots(), p, k, u, order);
            out[k - p..=k].copy_from_slice(&ders[order]);
        }
    }
    Ok(out)
}

/// `u` clamped to the curve's domain when it lies within a rounding (`1e-12` of the domain's
/// length) of it.
///
/// # Errors
/// [`CurveError::OutOfDomain`] beyond that, or for a non-finite `u`.
pub fn in_domain<P: Point>(curve: &Curve<P>, u: f64) -> Result<f64, CurveError> {
    let (a, b) = curve.domain();
    let slack = 1e-12 * (b - a);
    if u >= a - slack && u <= b + slack {
        Ok(u.clamp(a, b))
    } else {
        Err(CurveError::OutOfDomain {
            t: u,
            range: format!(
                "the domain [{}, {}]",
                crate::num::Compact(a),
                crate::num::Compact(b)
            ),
        })
    }
}

/// The `order`-th derivative `C^{(order)}(u)` of a curve of either kind (`Σ w_i P_i` with the
/// weights of [`control_weights`]).
///
/// # Errors
/// As [`control_weights`].
pub fn derivative<P: Point>(curve: &Curve<P>, u: f64, order: usize) -> Result<P, CurveError> {
    let w = control_weights(curve, u, order)?;
    Ok(curve
        .points()
        .iter()
        .zip(&w)
        .fold(P::ZERO, |acc, (&p, &w)| acc + p * w))
}

/// The non-zero basis functions `N_{k−p..=k, p}` at `t` (in span `k`, `t_k ≤ t ≤ t_{k+1}`,
/// `t_k < t_{k+1}`) and their derivatives up to `order`: `ders[j][r] = N^{(j)}_{k−p+r, p}(t)`
/// (The NURBS Book, A2.3). Derivatives above `p` are zero.
fn basis_derivatives(knots: &[f64], p: usize, k: usize, t: f64, order: usize) -> Vec<Vec<f64>> {
    let mut ndu = vec![vec![0.0; p + 1]; p + 1];
    let mut left = vec![0.0; p + 1];
    let mut right = vec![0.0; p + 1];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = t - knots[k + 1 - j];
        right[j] = knots[k + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            // Lower triangle: knot differences; upper: the basis functions.
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let mut ders = vec![vec![0.0; p + 1]; order + 1];
    for (j, d) in ders[0].iter_mut().enumerate() {
        *d = ndu[j][p];
    }
    let top = order.min(p);
    let mut a = [vec![0.0; p + 1], vec![0.0; p + 1]];
    for r in 0..=p {
        let (mut s1, mut s2) = (0, 1);
        a[0][0] = 1.0;
        for kk in 1..=top {
            let mut d = 0.0;
            let rk = r as isize - kk as isize;
            let pk = p - kk;
            if r >= kk {
                let rk = rk as usize;
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                d = a[s2][0] * ndu[rk][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if r as isize - 1 <= pk as isize {
                kk - 1
            } else {
                p - r
            };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                d += a[s2][j] * ndu[idx][pk];
            }
            if r <= pk {
                a[s2][kk] = -a[s1][kk - 1] / ndu[pk + 1][r];
                d += a[s2][kk] * ndu[r][pk];
            }
            ders[kk][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut factor = p as f64;
    for (kk, row) in ders.iter_mut().enumerate().take(top + 1).skip(1) {
        for d in row.iter_mut() {
            *d *= factor;
        }
        factor *= (p - kk) as f64;
    }
    ders
}

/// Which control points a grab moves (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GrabMethod {
    /// The control point with the largest basis weight at `u` (P4).
    #[default]
    LargestWeight,
    /// The control point whose parameter (`k/n`, or the Greville abscissa) is nearest `u`
    /// (P0).
    NearestParameter,
    /// Every control point, with the least total change `Σ |ΔP_k|²`.
    LeastChange,
}

/// How a grab moves the curve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct GrabOptions {
    /// Which control points move.
    pub method: GrabMethod,
    /// Never move the first and last control points (P4).
    pub keep_ends: bool,
}

/// Smallest weight sum a grab accepts: below it the control points would have to move more than
/// a billion times as far as the grabbed point.
const MIN_WEIGHT: f64 = 1e-9;

/// A grab: the curve as grabbed, the parameter, and how far each control point moves per unit
/// move of the grabbed point.
///
/// ```
/// use glam::DVec3;
/// use nendo_geom::curve::{Bezier, Curve};
/// use nendo_geom::curve::edit::{Grab, GrabOptions};
/// let c: Curve<DVec3> = Bezier::new(vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::ONE]).into();
/// let grab = Grab::new(&c, 0.3, GrabOptions::default())?;
/// let moved = grab.moved_by(DVec3::new(0.0, 0.0, 0.5))?;
/// assert!((moved.eval(0.3) - (c.eval(0.3) + DVec3::new(0.0, 0.0, 0.5))).length() < 1e-12);
/// # Ok::<(), nendo_geom::curve::CurveError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Grab<P> {
    original: Curve<P>,
    u: f64,
    start: P,
    /// `(k, c_k)`: control point `k` moves by `c_k ΔP`.
    factors: Vec<(usize, f64)>,
}

impl<P: Point> Grab<P> {
    /// Grabs `curve` at parameter `u`.
    ///
    /// # Errors
    /// [`CurveError::OutOfDomain`] for `u` outside the domain; [`CurveError::Edit`] when no
    /// movable control point carries `C(u)` (e.g. an end point with `keep_ends`, or a degree-1
    /// curve with `keep_ends`); [`CurveError::NotFinite`] when the control points are too far
    /// apart to compute with ([`check_extent`]).
    pub fn new(curve: &Curve<P>, u: f64, options: GrabOptions) -> Result<Self, CurveError> {
        check_extent(curve)?;
        let u = in_domain(curve, u)?;
        let w = control_weights(curve, u, 0)?;
        let last = w.len() - 1;
        let movable = |k: usize| !options.keep_ends || (k != 0 && k != last);
        let refuse = || {
            CurveError::Edit(format!(
                "no movable control point carries the point at u = {}{}",
                crate::num::Compact(u),
                if options.keep_ends {
                    " while the end points are kept"
                } else {
                    ""
                }
            ))
        };
        let factors = match options.method {
            GrabMethod::LargestWeight => {
                let k = (0..w.len())
                    .filter(|&k| movable(k))
                    .max_by(|&i, &j| w[i].total_cmp(&w[j]))
                    .ok_or_else(refuse)?;
                if w[k] < MIN_WEIGHT {
                    return Err(refuse());
                }
                vec![(k, 1.0 / w[k])]
            }
            GrabMethod::NearestParameter => {
                let params = control_parameters(curve);
                let k = (0..w.len())
                    .filter(|&k| movable(k) && w[k] >= MIN_WEIGHT)
                    .min_by(|&i, &j| (params[i] - u).abs().total_cmp(&(params[j] - u).abs()))
                    .ok_or_else(refuse)?;
                vec![(k, 1.0 / w[k])]
            }
            GrabMethod::LeastChange => {
                let sum: f64 = (0..w.len())
                    .filter(|&k| movable(k))
                    .map(|k| w[k] * w[k])
                    .sum();
                if sum < MIN_WEIGHT * MIN_WEIGHT {
                    return Err(refuse());
                }
                (0..w.len())
                    .filter(|&k| movable(k) && w[k] != 0.0)
                    .map(|k| (k, w[k] / sum))
                    .collect()
            }
        };
        Ok(Self {
            original: curve.clone(),
            u,
            start: curve.eval(u),
            factors,
        })
    }

    /// Grabs the closest point of `curve` to `from` within `r_max` (`None` when nothing of the
    /// curve lies that close).
    ///
    /// # Errors
    /// As [`Self::new`]; [`CurveError::NotFinite`] when no closest point can be computed
    /// (the curve's coordinates overflow: with `r_max = ∞` a closest point always exists).
    pub fn at_point(
        curve: &Curve<P>,
        from: P,
        r_max: f64,
        options: GrabOptions,
    ) -> Result<Option<Self>, CurveError> {
        check_extent(curve)?;
        match curve.closest(from, r_max) {
            Some(n) if n.u.is_finite() => Self::new(curve, n.u, options).map(Some),
            Some(_) => Err(CurveError::NotFinite {
                what: "the parameter of the closest point".into(),
            }),
            // Within an infinite reach every curve has a closest point: not finding one means
            // the arithmetic overflowed.
            None if r_max == f64::INFINITY => Err(CurveError::NotFinite {
                what: "the distance to the curve".into(),
            }),
            None => Ok(None),
        }
    }

    /// The curve as it was grabbed.
    #[must_use]
    pub fn original(&self) -> &Curve<P> {
        &self.original
    }

    /// The grabbed parameter.
    #[must_use]
    pub fn u(&self) -> f64 {
        self.u
    }

    /// The grabbed point `C(u)` before the move.
    #[must_use]
    pub fn start(&self) -> P {
        self.start
    }

    /// `(k, c_k)` for every control point that moves: by `c_k ΔP` when the grabbed point moves
    /// by `ΔP`.
    #[must_use]
    pub fn factors(&self) -> &[(usize, f64)] {
        &self.factors
    }

    /// The curve with the grabbed point moved by `delta`: `C'(u) = C(u) + delta`.
    ///
    /// # Errors
    /// [`CurveError::NotFinite`] when the result is not finite.
    pub fn moved_by(&self, delta: P) -> Result<Curve<P>, CurveError> {
        let mut points = self.original.points().to_vec();
        for &(k, c) in &self.factors {
            points[k] = points[k] + delta * c;
        }
        with_points(&self.original, points)
    }

    /// The curve with the grabbed point moved to `target`.
    ///
    /// # Errors
    /// As [`Self::moved_by`].
    pub fn moved_to(&self, target: P) -> Result<Curve<P>, CurveError> {
        self.moved_by(target - self.start)
    }
}

/// One grab: `curve` grabbed at `u` and its point there moved by `delta`.
///
/// # Errors
/// As [`Grab::new`] and [`Grab::moved_by`].
pub fn grab<P: Point>(
    curve: &Curve<P>,
    u: f64,
    delta: P,
    options: GrabOptions,
) -> Result<Curve<P>, CurveError> {
    Grab::new(curve, u, options)?.moved_by(delta)
}

/// The parameter each control point is associated with: `k/n` mapped to the domain for a Bezier
/// curve, the Greville abscissa `(t_{k+1} + … + t_{k+p})/p` for a B-spline.
#[must_use]
pub fn control_parameters<P: Point>(curve: &Curve<P>) -> Vec<f64> {
    match curve {
        Curve::Bezier(b) => {
            let n = b.degree().max(1) as f64;
            (0..b.points().len()).map(|k| k as f64 / n).collect()
        }
        Curve::BSpline(s) => {
            let p = s.degree();
            let t = s.knots();
            (0..s.points().len())
                .map(|k| t[k + 1..=k + p].iter().sum::<f64>() / p as f64)
                .collect()
        }
    }
}

/// The curve of the same kind (same degree, same knots) with new control points.
///
/// # Errors
/// [`CurveError::Index`] for a different number of points; [`CurveError::NotFinite`] for a
/// non-finite point.
pub fn with_points<P: Point>(curve: &Curve<P>, points: Vec<P>) -> Result<Curve<P>, CurveError> {
    let len = curve.points().len();
    if points.len() != len {
        return Err(CurveError::Index {
            index: points.len(),
            len,
        });
    }
    Ok(match curve {
        Curve::Bezier(_) => Curve::Bezier(Bezier::try_new(points)?),
        Curve::BSpline(s) => {
            Curve::BSpline(BSpline::try_new(s.degree(), s.knots().to_vec(), points)?)
        }
    })
}

/// Splits a curve at `u`, strictly inside its domain, into the curves before and after it, which
/// share the split point (de Casteljau for a Bezier curve, knot insertion for a B-spline).
///
/// # Errors
/// [`CurveError::OutOfDomain`] at or beyond the ends of the domain; [`CurveError::NotFinite`]
/// when a control point of either half is not finite (control points so far apart that the
/// subdivision overflows, e.g. `±10³⁰⁸`).
pub fn split<P: Point>(curve: &Curve<P>, u: f64) -> Result<(Curve<P>, Curve<P>), CurveError> {
    let (a, b) = curve.domain();
    if !(u > a && u < b) {
        return Err(CurveError::OutOfDomain {
            t: u,
            range: format!(
                "the open domain ({}, {})",
                crate::num::Compact(a),
                crate::num::Compact(b)
            ),
        });
    }
    let (left, right) = match curve {
        Curve::Bezier(c) => {
            let (l, r) = c.split(u);
            (Curve::Bezier(l), Curve::Bezier(r))
        }
        Curve::BSpline(s) => {
            let (l, r) = s.split(u)?;
            (Curve::BSpline(l), Curve::BSpline(r))
        }
    };
    for (side, half) in [("left", &left), ("right", &right)] {
        if let Some(i) = half.points().iter().position(|p| !p.is_finite_coeff()) {
            return Err(CurveError::NotFinite {
                what: format!(
                    "control point {i} of the {side} half (the curve's coordinates overflow when subdivided)"
                ),
            });
        }
    }
    Ok((left, right))
}

/// Checks that the differences between a curve's control points are finite: beyond that (control
/// points near `±f64::MAX`) evaluating the curve or its distances overflows.
///
/// # Errors
/// [`CurveError::NotFinite`] naming the extent.
pub fn check_extent<P: Point>(curve: &Curve<P>) -> Result<(), CurveError> {
    let (lo, hi) = curve.control_bounds();
    if (hi - lo).is_finite_coeff() {
        Ok(())
    } else {
        Err(CurveError::NotFinite {
            what: "the extent of the control points (they are too far apart to compute with)"
                .into(),
        })
    }
}

/// Which neighbour of a joint the user moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointSide {
    /// `Q_L`, the left curve's last-but-one control point.
    Left,
    /// `Q_R`, the right curve's second control point.
    Right,
}

/// How the other neighbour of a joint follows a tangent edit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Follow {
    /// It keeps its distance to `Q` (the joint stays G1).
    #[default]
    KeepLength,
    /// Its distance to `Q` scales by the moved neighbour's: the ratio `|Q_R − Q| / |Q − Q_L|`
    /// stays, so a C1 joint stays C1.
    KeepRatio,
}

/// The joint between `left` and `right`: `(Q_L, Q, Q_R)`, where `Q` is the left curve's last
/// control point and must be the right curve's first.
///
/// # Errors
/// [`CurveError::Edit`] when the curves do not meet that way or either has a single point.
pub fn joint<P: Point>(left: &Curve<P>, right: &Curve<P>) -> Result<(P, P, P), CurveError> {
    let (l, r) = (left.points(), right.points());
    if l.len() < 2 || r.len() < 2 {
        return Err(CurveError::Edit(
            "a joint needs two control points on each side".into(),
        ));
    }
    let q = l[l.len() - 1];
    if q != r[0] {
        return Err(CurveError::Edit(format!(
            "the left curve's last control point is {:.6} from the right curve's first: not a joint",
            crate::num::Compact((q - r[0]).length())
        )));
    }
    Ok((l[l.len() - 2], q, r[1]))
}

/// Tangent edit at the joint of `left` and `right` (see the module docs): the neighbour on
/// `side` moves to `target`, the other follows on the line through `Q`. Returns the edited
/// `(left, right)`.
///
/// # Errors
/// [`CurveError::Edit`] for curves that do not meet ([`joint`]) or a `target` at `Q` itself
/// (no direction); [`CurveError::NotFinite`] for a non-finite result.
pub fn tangent_edit<P: Point>(
    left: &Curve<P>,
    right: &Curve<P>,
    side: JointSide,
    target: P,
    follow: Follow,
) -> Result<(Curve<P>, Curve<P>), CurveError> {
    let (ql, q, qr) = joint(left, right)?;
    let (moved_old, other_old) = match side {
        JointSide::Left => (ql, qr),
        JointSide::Right => (qr, ql),
    };
    let arm = q - target;
    let arm_len = arm.length();
    if arm_len == 0.0 || !arm_len.is_finite() {
        return Err(CurveError::Edit(
            "the tangent target is the joint itself: no direction".into(),
        ));
    }
    let old_len = (moved_old - q).length();
    let mut other_len = (other_old - q).length();
    if follow == Follow::KeepRatio && old_len > 0.0 {
        other_len *= arm_len / old_len;
    }
    let other = q + arm * (other_len / arm_len);
    let (new_l, new_r) = match side {
        JointSide::Left => (target, other),
        JointSide::Right => (other, target),
    };
    let mut lp = left.points().to_vec();
    let n = lp.len();
    lp[n - 2] = new_l;
    let mut rp = right.points().to_vec();
    rp[1] = new_r;
    Ok((with_points(left, lp)?, with_points(right, rp)?))
}

/// Moves the joint `Q` of `left` and `right` to `target`, its two neighbours with it (the
/// tangent is kept).
///
/// # Errors
/// As [`joint`]; [`CurveError::NotFinite`] for a non-finite result.
pub fn move_joint<P: Point>(
    left: &Curve<P>,
    right: &Curve<P>,
    target: P,
) -> Result<(Curve<P>, Curve<P>), CurveError> {
    let (_, q, _) = joint(left, right)?;
    let d = target - q;
    let mut lp = left.points().to_vec();
    let n = lp.len();
    lp[n - 1] = target;
    lp[n - 2] = lp[n - 2] + d;
    let mut rp = right.points().to_vec();
    rp[0] = target;
    rp[1] = rp[1] + d;
    Ok((with_points(left, lp)?, with_points(right, rp)?))
}

/// One more control point without changing the curve: degree elevation of a Bezier curve (`u`
/// then only chooses which point is reported), insertion of the knot `u` in a B-spline. Returns
/// the new curve and the index of its control point with the largest weight at `u` (the one a
/// grab there would move).
///
/// # Errors
/// [`CurveError::OutOfDomain`] for `u` outside the domain; [`CurveError::DegreeTooHigh`] for a
/// Bezier curve already of the largest degree; [`CurveError::KnotMultiplicity`] where `u` is
/// already a knot of full multiplicity.
pub fn insert_control_point<P: Point>(
    curve: &Curve<P>,
    u: f64,
) -> Result<(Curve<P>, usize), CurveError> {
    let u = in_domain(curve, u)?;
    let new = match curve {
        Curve::Bezier(c) => Curve::Bezier(c.elevate()?),
        Curve::BSpline(s) => Curve::BSpline(s.insert_knot(u)?),
    };
    let w = control_weights(&new, u, 0)?;
    let k = (0..w.len())
        .max_by(|&i, &j| w[i].total_cmp(&w[j]))
        .unwrap_or(0);
    Ok((new, k))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn bspline_weights_match_unit_curves() {
        let s = BSpline::try_new(
            3,
            vec![0.0, 0.1, 0.2, 0.3, 0.5, 0.5, 0.9, 1.0, 1.1, 1.3],
            vec![
                DVec2::ZERO,
                DVec2::X,
                DVec2::Y,
                DVec2::ONE,
                DVec2::new(2.0, 0.0),
                DVec2::new(3.0, 1.0),
            ],
        )
        .expect("valid");
        let c = Curve::BSpline(s.clone());
        let count = s.points().len();
        for i in 0..=20 {
            let (a, b) = s.domain();
            let u = a + (b - a) * i as f64 / 20.0;
            let w = control_weights(&c, u, 0).expect("inside");
            for (k, wk) in w.iter().enumerate() {
                let unit: Vec<DVec2> = (0..count)
                    .map(|j| if j == k { DVec2::X } else { DVec2::ZERO })
                    .collect();
                let e = BSpline::try_new(3, s.knots().to_vec(), unit).expect("valid");
                assert!((wk - e.eval(u).x).abs() < 1e-14, "u={u} k={k}");
            }
        }
    }
}
