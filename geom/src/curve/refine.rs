//! Curve refinement keeping similarity (Satoh and Miwa, P3; docs/design.md §7): a planar curve is
//! reshaped to meet the user's constraints while the pairs of derivative vectors along it change
//! by a similarity (a rotation and a scale) that may differ from place to place.
//!
//! ## Similarity variables (P3 §2.3–2.4)
//! Read 2D vectors as complex numbers. At a parameter `u`, with `Q^{(a)}, Q^{(b)}` the
//! derivatives of the *original* curve and `V^{(a)}, V^{(b)}` those of the refined one,
//!
//! `S(u) = D + iC = V^{(a)}(u) / Q^{(a)}(u) − V^{(b)}(u) / Q^{(b)}(u)`,
//!
//! i.e. (eqs. (3)–(4) and (7)–(8) of the paper, `×` the scalar cross product)
//!
//! `D = Q^{(a)}·V^{(a)} / |Q^{(a)}|² − Q^{(b)}·V^{(b)} / |Q^{(b)}|²`,
//! `C = Q^{(a)}×V^{(a)} / |Q^{(a)}|² − Q^{(b)}×V^{(b)} / |Q^{(b)}|²`.
//!
//! `S(u) = 0` says that both derivative vectors were turned and scaled by the same complex
//! factor there. [`Similarity::Curvature`] uses `(a, b) = (1, 2)` (the curvature's shape is
//! kept), [`Similarity::Variation`] uses `(a, b) = (2, 3)` (the curvature *variation*'s; the
//! first derivative is free, so the curve may open up into a straight line, §2.8). `S` is linear
//! in the refined control points, and vanishes for every similar copy `λR·V₀ + t` of the
//! original (for [`Similarity::Variation`] also after adding any straight line `c₀ + c₁u`).
//!
//! Sample parameters: on every Bezier segment (every knot span of a B-spline) of degree `n`,
//! `n − 1` samples `u = j/n` (curvature) or `n − 2` samples `u = j/(n−1)` (variation) — as many as
//! the paper's re-representation needs (its 2-segment cubic examples use `1/3, 2/3` and `1/2`).
//! A sample where an original derivative vanishes is moved within its span, or dropped.
//!
//! ## The solve (P3 §2.6–2.7)
//! The paper re-expresses the curve in the variables `U = (passing points, S)` through a square
//! matrix `M`, then solves the user's linear constraints with the `S` as weak terms. With the
//! passing points pinned by the constraints that is the same as the problem solved here, directly
//! on the control points `V`:
//!
//! 1. the hard constraints `A V = b` (passing points, tangents, derivatives, joins — see
//!    [`Constraint`]) hold exactly (in the least-squares sense if they contradict each other);
//! 2. among those curves, `Σ |S(u_j)|²` is least (the weak terms);
//! 3. among *those*, `|V − V₀|` is least (the refined curve stays as near the original as the
//!    first two allow, which makes the answer unique).
//!
//! Each step is a linear least-squares problem solved by SVD (nalgebra): `V_p = V₀ + A⁺(b − AV₀)`,
//! `N` an orthonormal basis of `ker A`, `y` the minimum-norm least-squares solution of
//! `S N y = −S V_p`, and `V = V_p + N y`.
//!
//! Consequences (tested in `tests/it/curve_refine.rs` of the `nendo` crate): when the constraints admit a similar copy of
//! the curve — an end point moved by a rotation and a scale about the other end — the result is
//! that copy; constraints the curve already meets leave it unchanged; in variation mode, pinning
//! the middle of an arch onto its chord with the end tangents along the chord straightens it, and
//! pinning it to the mirror position mirrors it (the paper's Fig. 5).
//!
//! ## Which constraints give the similar copy
//! The result is the similar copy exactly when the copy meets the constraints *and* no other
//! curve with `S = 0` everywhere does (stage 3 then has nothing to choose). The curves with
//! `S = 0` are, with `a = λe^{iθ}` (rotation and scale) and `b` (translation) complex:
//!
//! * [`Similarity::Curvature`]: `V = a V₀ + b` — 4 real degrees of freedom. The copy is found
//!   from any constraints that fix `a` and `b`: the two end points (`Point` at both ends,
//!   `b − a`, the tested case), any two `Point`s at parameters where the original's points
//!   differ, or one `Point` and one `Derivative` (where `Q'(u) ≠ 0`). One point and a `Tangent`
//!   leave the scale free (3 equations): the solver then keeps the scale nearest the original.
//! * [`Similarity::Variation`]: `V = a V₀ + b + c u` — the second and third derivatives do not
//!   see a linear term `c u` (`c` complex, `u` the curve's parameter: on a Bezier curve of
//!   degree `n` control point `k` moves by `c k/n`), so 6 real degrees of freedom. **The two end
//!   points alone do not give the copy**: they leave `c` free (2 degrees), and the solver
//!   returns the curve of that family nearest the original — the copy only if that has `c = 0`,
//!   which a rotated or scaled move generally does not (the mode leaves the first derivative
//!   free by design, §2.8). Two more equations that the copy meets fix `c`: the two end points
//!   with the `Tangent`s at both ends (the tested case), the end points with one `Derivative`
//!   (`C'(u) = a Q'(u)`), or three `Point`s at `u₀, u₁, u₂` whose original points are not in
//!   uniform motion along a line (`Q(u₂) ≠ Q(u₀) + (Q(u₁) − Q(u₀)) (u₂ − u₀)/(u₁ − u₀)`).
//!
//! For a piecewise curve `u` is the global parameter and the joints keep their continuity, so
//! the same counts hold for the whole curve.
//!
//! ## Curves
//! A Bezier curve, a B-spline (its control points are the unknowns, so its joins are kept by
//! construction), or a piecewise curve of Bezier segments ([`refine_piecewise`]) whose global
//! parameter runs over `[0, segments]` (segment `i` on `[i, i+1]`, the parameter `u = i` at a
//! joint belonging to segment `i`). The joints of a piecewise curve keep the continuity (C0, C1,
//! C2) they have in the original unless a [`Constraint::Join`] says otherwise.

mod model;
mod solve;

use super::any::Curve;
use super::bezier::Bezier;
use super::error::CurveError;
use glam::DVec2;
use model::Model;

/// Which pair of derivatives the refinement keeps similar.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Similarity {
    /// First and second derivatives (P3 §2.3, §2.6): the curvature's shape. Needs degree ≥ 2.
    #[default]
    Curvature,
    /// Second and third derivatives (§2.4, §2.7): the curvature variation's shape; the first
    /// derivative is free (§2.8). Needs degree ≥ 3.
    Variation,
}

impl Similarity {
    /// The derivative orders `(a, b)` compared.
    #[must_use]
    pub fn orders(self) -> (usize, usize) {
        match self {
            Similarity::Curvature => (1, 2),
            Similarity::Variation => (2, 3),
        }
    }
}

/// A hard constraint of a refinement. Parameters are the curve's own (a B-spline's knot
/// parameter; `[0, segments]` for a piecewise curve).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Constraint {
    /// The curve passes through `point` at `u`: `C(u) = point` (two equations).
    Point {
        /// Parameter.
        u: f64,
        /// Where `C(u)` must be.
        point: DVec2,
    },
    /// The tangent at `u` is parallel to `direction`: `direction × C'(u) = 0` (one equation; the
    /// length, and which way along the line, stay free).
    Tangent {
        /// Parameter.
        u: f64,
        /// A non-zero direction.
        direction: DVec2,
    },
    /// The first derivative at `u` is `vector`: `C'(u) = vector` (two equations).
    Derivative {
        /// Parameter.
        u: f64,
        /// The derivative.
        vector: DVec2,
    },
    /// Segments `at` and `at + 1` of a piecewise curve meet with continuity `C^order`
    /// (`order` 0, 1 or 2): `C_at^{(r)}(1) = C_{at+1}^{(r)}(0)` for `r ≤ order` (P3 eqs.
    /// (11)–(12)). Replaces the continuity the joint has in the original.
    Join {
        /// The joint between segments `at` and `at + 1`.
        at: usize,
        /// 0, 1 or 2.
        order: usize,
    },
}

/// A refined curve and how well it met its terms.
#[derive(Debug, Clone, PartialEq)]
pub struct Refined<C> {
    /// The refined curve.
    pub curve: C,
    /// `|A V − b|`: zero (to rounding) unless the hard constraints contradict each other.
    pub constraint_residual: f64,
    /// Root mean square of the similarity variables `|S(u_j)|` over the samples (0 for a similar
    /// copy of the original).
    pub similarity_rms: f64,
    /// Number of similarity samples used.
    pub samples: usize,
}

/// A similarity variable `S(u) = D + iC` of a curve relative to its original (see the module
/// docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimilaritySample {
    /// The sample parameter.
    pub u: f64,
    /// `D`, the real part.
    pub d: f64,
    /// `C`, the imaginary part.
    pub c: f64,
}

/// Refines a planar Bezier curve or B-spline (see the module docs).
///
/// ```
/// use glam::DVec2;
/// use nendo_geom::curve::{Bezier, Curve};
/// use nendo_geom::curve::refine::{refine, Constraint, Similarity};
/// let arch: Curve<DVec2> = Bezier::new(vec![DVec2::ZERO, DVec2::new(0.5, 1.0), DVec2::new(2.0, 1.2), DVec2::new(3.0, 0.0)]).into();
/// // Move the end from (3, 0) to (0, 3) — a quarter turn about the start: the result is the
/// // arch turned a quarter.
/// let constraints = [
///     Constraint::Point { u: 0.0, point: DVec2::ZERO },
///     Constraint::Point { u: 1.0, point: DVec2::new(0.0, 3.0) },
/// ];
/// let r = refine(&arch, Similarity::Curvature, &constraints)?;
/// let p = r.curve.points()[1];
/// assert!((p - DVec2::new(-1.0, 0.5)).length() < 1e-9);
/// # Ok::<(), nendo_geom::curve::CurveError>(())
/// ```
///
/// # Errors
/// [`CurveError::Refine`] for a degree too low for the mode, a constraint outside the domain or
/// with a zero direction, a [`Constraint::Join`] (a single curve has no joints), derivatives
/// that vanish at every sample, or a solver failure.
pub fn refine(
    curve: &Curve<DVec2>,
    mode: Similarity,
    constraints: &[Constraint],
) -> Result<Refined<Curve<DVec2>>, CurveError> {
    let model = Model::from_curve(curve);
    let s = solve::refine_model(&model, mode, constraints)?;
    let curve = model.curve_with(curve, &s.v)?;
    Ok(Refined {
        curve,
        constraint_residual: s.residual,
        similarity_rms: s.rms,
        samples: s.samples,
    })
}

/// Refines a piecewise curve of Bezier segments placed end to end (see the module docs: the
/// global parameter, the joints).
///
/// # Errors
/// As [`refine`]; also for no segments, or a [`Constraint::Join`] with a bad joint or order.
pub fn refine_piecewise(
    segments: &[Bezier<DVec2>],
    mode: Similarity,
    constraints: &[Constraint],
) -> Result<Refined<Vec<Bezier<DVec2>>>, CurveError> {
    let model = Model::from_segments(segments)?;
    let s = solve::refine_model(&model, mode, constraints)?;
    let curve = model.segments_with(&s.v, &s.joined)?;
    Ok(Refined {
        curve,
        constraint_residual: s.residual,
        similarity_rms: s.rms,
        samples: s.samples,
    })
}

/// The similarity variables of `curve` relative to `original` at the refinement's samples (the
/// original's knots or degree must be `curve`'s: same kind, same number of control points).
///
/// # Errors
/// [`CurveError::Refine`] when the curves do not match, as for [`refine`] otherwise.
pub fn similarity_variables(
    original: &Curve<DVec2>,
    curve: &Curve<DVec2>,
    mode: Similarity,
) -> Result<Vec<SimilaritySample>, CurveError> {
    let same = match (original, curve) {
        (Curve::Bezier(a), Curve::Bezier(b)) => a.degree() == b.degree(),
        (Curve::BSpline(a), Curve::BSpline(b)) => {
            a.degree() == b.degree() && a.knots() == b.knots()
        }
        _ => false,
    } && original.points().len() == curve.points().len();
    if !same {
        return Err(CurveError::Refine(
            "the curves differ in kind, degree, knots or number of control points".into(),
        ));
    }
    let model = Model::from_curve(original);
    let rows = solve::similarity_rows(&model, mode)?;
    let v = model::flatten(curve.points());
    Ok(rows
        .iter()
        .map(|r| SimilaritySample {
            u: r.u,
            d: model::dot_sparse(&r.d, &v),
            c: model::dot_sparse(&r.c, &v),
        })
        .collect())
}
