//! The three-stage least-squares solve of a refinement (see the parent module's docs): hard
//! constraints exactly, then the similarity variables as weak terms, then the least change.

use super::model::{Model, Sparse, dot_sparse};
use super::{Constraint, Similarity};
use crate::curve::error::CurveError;
use glam::DVec2;
use nalgebra::{DMatrix, DVector, SVD};

/// Hard rows `(row, right-hand side)` of `A V = b`.
type HardRows = Vec<(Sparse, f64)>;

/// The two rows (`D` and `C`) of one similarity sample.
#[derive(Debug, Clone)]
pub(super) struct SimRow {
    pub(super) u: f64,
    pub(super) d: Sparse,
    pub(super) c: Sparse,
}

/// Singular values below this fraction of the largest count as zero.
const RANK_TOL: f64 = 1e-11;

/// Derivatives shorter than this fraction of their typical size count as vanishing.
const VANISHING: f64 = 1e-8;

fn err(msg: impl Into<String>) -> CurveError {
    CurveError::Refine(msg.into())
}

/// The similarity samples of the model and their rows (see the parent module's docs).
pub(super) fn similarity_rows(model: &Model, mode: Similarity) -> Result<Vec<SimRow>, CurveError> {
    let (a, b) = mode.orders();
    let extent = model.extent();
    let mut rows = Vec::new();
    for (start, end, degree) in model.spans() {
        if degree < b {
            return Err(err(format!(
                "{mode:?} similarity compares derivatives {a} and {b}: it needs degree {b} or more, the curve has degree {degree}"
            )));
        }
        let m = degree + 1 - b;
        let h = end - start;
        let typical = |k: usize| extent * (degree as f64 / h).powi(k as i32);
        for j in 1..=m {
            for delta in [0.0, 0.25, -0.25, 0.4, -0.4] {
                let s = (j as f64 + delta) / (m + 1) as f64;
                let u = start + s * h;
                let (qa, qb) = (
                    model.original_derivative(u, a)?,
                    model.original_derivative(u, b)?,
                );
                if qa.length() <= VANISHING * typical(a) || qb.length() <= VANISHING * typical(b) {
                    continue;
                }
                rows.push(sim_row(model, u, (a, qa), (b, qb))?);
                break;
            }
        }
    }
    if rows.is_empty() {
        return Err(err(
            "the original curve's derivatives vanish at every similarity sample (a straight line evenly parameterised has no curvature to keep)",
        ));
    }
    Ok(rows)
}

/// `D + iC = V^{(a)}/Q^{(a)} − V^{(b)}/Q^{(b)}` as two sparse rows over the unknowns.
fn sim_row(
    model: &Model,
    u: f64,
    (a, qa): (usize, DVec2),
    (b, qb): (usize, DVec2),
) -> Result<SimRow, CurveError> {
    let mut d = Vec::new();
    let mut c = Vec::new();
    for (order, q, sign) in [(a, qa, 1.0), (b, qb, -1.0)] {
        let q2 = q.length_squared();
        for (k, w) in model.weights(u, order)? {
            let f = sign * w / q2;
            // Real part: q·V; imaginary part: q × V = q.x V.y − q.y V.x.
            d.push((2 * k, f * q.x));
            d.push((2 * k + 1, f * q.y));
            c.push((2 * k, -f * q.y));
            c.push((2 * k + 1, f * q.x));
        }
    }
    Ok(SimRow { u, d, c })
}

/// Checks a constraint's parameter against the domain (with a rounding's slack) and clamps it.
fn param(model: &Model, u: f64, what: &str) -> Result<f64, CurveError> {
    let (a, b) = model.domain();
    let slack = 1e-12 * (b - a);
    if u.is_finite() && u >= a - slack && u <= b + slack {
        Ok(u.clamp(a, b))
    } else {
        Err(err(format!(
            "{what}: parameter {} is outside the curve's domain [{}, {}]",
            crate::num::Compact(u),
            crate::num::Compact(a),
            crate::num::Compact(b)
        )))
    }
}

fn finite(p: DVec2, what: &str) -> Result<DVec2, CurveError> {
    if p.is_finite() {
        Ok(p)
    } else {
        Err(CurveError::NotFinite {
            what: what.to_string(),
        })
    }
}

/// One row per coordinate of `Σ w_k P_k = target`.
fn vector_rows(w: &[(usize, f64)], target: DVec2, rows: &mut Vec<(Sparse, f64)>) {
    rows.push((w.iter().map(|&(k, x)| (2 * k, x)).collect(), target.x));
    rows.push((w.iter().map(|&(k, x)| (2 * k + 1, x)).collect(), target.y));
}

/// The hard constraint rows `A V = b`, joints included, and which joints are held together
/// (at least C0).
fn hard_rows(
    model: &Model,
    constraints: &[Constraint],
) -> Result<(HardRows, Vec<bool>), CurveError> {
    let mut rows = Vec::new();
    let mut join_override: Vec<Option<usize>> = vec![None; model.joints()];
    for (i, c) in constraints.iter().enumerate() {
        let what = format!("constraint {i}");
        match *c {
            Constraint::Point { u, point } => {
                let u = param(model, u, &what)?;
                vector_rows(&model.weights(u, 0)?, finite(point, &what)?, &mut rows);
            }
            Constraint::Derivative { u, vector } => {
                let u = param(model, u, &what)?;
                vector_rows(&model.weights(u, 1)?, finite(vector, &what)?, &mut rows);
            }
            Constraint::Tangent { u, direction } => {
                let u = param(model, u, &what)?;
                let d = finite(direction, &what)?
                    .try_normalize()
                    .ok_or_else(|| err(format!("{what}: the tangent direction has zero length")))?;
                let w = model.weights(u, 1)?;
                rows.push((
                    w.iter()
                        .flat_map(|&(k, x)| [(2 * k, -d.y * x), (2 * k + 1, d.x * x)])
                        .collect(),
                    0.0,
                ));
            }
            Constraint::Join { at, order } => {
                if order > 2 {
                    return Err(err(format!(
                        "{what}: join order {order}; only C0, C1 and C2 joins exist"
                    )));
                }
                let slot = join_override.get_mut(at).ok_or_else(|| {
                    err(format!(
                        "{what}: no joint {at} (the curve has {} joints between segments)",
                        model.joints()
                    ))
                })?;
                *slot = Some(order);
            }
        }
    }
    let mut joined = Vec::with_capacity(join_override.len());
    for (at, over) in join_override.into_iter().enumerate() {
        let level = match over {
            Some(order) => Some(order),
            None => model.original_continuity(at)?,
        };
        joined.push(level.is_some());
        if let Some(order) = level {
            for r in 0..=order {
                vector_rows(&model.join_weights(at, r)?, DVec2::ZERO, &mut rows);
            }
        }
    }
    Ok((rows, joined))
}

fn svd(m: DMatrix<f64>) -> Result<SVD<f64, nalgebra::Dyn, nalgebra::Dyn>, CurveError> {
    SVD::try_new_unordered(m, true, true, f64::EPSILON * 5.0, 100_000)
        .ok_or_else(|| err("the singular value decomposition did not converge"))
}

/// The outcome of [`refine_model`].
pub(super) struct Solved {
    /// The refined control points, flattened.
    pub(super) v: Vec<f64>,
    /// `|A V − b|`.
    pub(super) residual: f64,
    /// Root mean square of `|S(u_j)|`.
    pub(super) rms: f64,
    /// Number of similarity samples.
    pub(super) samples: usize,
    /// Per joint of a piecewise curve: held together (C0 or better).
    pub(super) joined: Vec<bool>,
}

/// Most control points a refinement solves for at once.
pub const MAX_REFINE_POINTS: usize = 256;

/// The refined control points and how well they meet the terms.
pub(super) fn refine_model(
    model: &Model,
    mode: Similarity,
    constraints: &[Constraint],
) -> Result<Solved, CurveError> {
    // The solve is dense (SVDs of the stacked rows): its cost grows as the cube of the
    // unknowns, about a second at this size. Longer curves are refined in pieces.
    let unknowns = model.original().len();
    if unknowns > 2 * MAX_REFINE_POINTS {
        return Err(CurveError::Refine(format!(
            "{} control points is too many to refine at once (at most {MAX_REFINE_POINTS}); refine the curve in pieces",
            unknowns / 2
        )));
    }
    let sims = similarity_rows(model, mode)?;
    let (hard, joined) = hard_rows(model, constraints)?;
    let v0 = model.original();
    let n = v0.len();
    let z0 = DVector::from_column_slice(&v0);

    // Stage 1: V_p = V₀ + A⁺(b − A V₀); N = ker A. Rows are normalised (the solution of a
    // consistent system does not change; the rank test becomes scale-free).
    let (zp, null) = if hard.is_empty() {
        (z0.clone(), DMatrix::<f64>::identity(n, n))
    } else {
        let m = hard.len().max(n);
        let mut a = DMatrix::<f64>::zeros(m, n);
        let mut r = DVector::<f64>::zeros(m);
        for (i, (row, rhs)) in hard.iter().enumerate() {
            let norm = row.iter().map(|x| x.1 * x.1).sum::<f64>().sqrt();
            if norm == 0.0 {
                continue;
            }
            for &(k, x) in row {
                a[(i, k)] += x / norm;
            }
            r[i] = (rhs - dot_sparse(row, &v0)) / norm;
        }
        let dec = svd(a)?;
        let (Some(u), Some(vt)) = (&dec.u, &dec.v_t) else {
            return Err(err("the singular vectors were not computed"));
        };
        let smax = dec.singular_values.iter().copied().fold(0.0, f64::max);
        let tol = RANK_TOL * smax;
        let mut zp = z0.clone();
        let mut null_cols = Vec::new();
        for (i, &s) in dec.singular_values.iter().enumerate() {
            let v = vt.row(i).transpose();
            if s > tol {
                zp += v * (u.column(i).dot(&r) / s);
            } else {
                null_cols.push(v);
            }
        }
        let null = if null_cols.is_empty() {
            DMatrix::<f64>::zeros(n, 0)
        } else {
            DMatrix::from_columns(&null_cols)
        };
        (zp, null)
    };

    // Stage 2: the least-squares similarity in ker A, minimum-norm (stage 3).
    let s_rows: Vec<&Sparse> = sims.iter().flat_map(|s| [&s.d, &s.c]).collect();
    let mut smat = DMatrix::<f64>::zeros(s_rows.len(), n);
    for (i, row) in s_rows.iter().enumerate() {
        for &(k, x) in row.iter() {
            smat[(i, k)] += x;
        }
    }
    let z = if null.ncols() == 0 {
        zp
    } else {
        let g = &smat * &null;
        let h = -(&smat * &zp);
        let dec = svd(g)?;
        let smax = dec.singular_values.iter().copied().fold(0.0, f64::max);
        let y = dec.solve(&h, RANK_TOL * smax).map_err(err)?;
        zp + &null * y
    };
    if z.iter().any(|x| !x.is_finite()) {
        return Err(CurveError::NotFinite {
            what: "the refined curve".into(),
        });
    }
    let v: Vec<f64> = z.iter().copied().collect();
    // Folded from +0.0: an empty sum of floats is −0.0, which would print as a residual of
    // "-0.0" when there are no constraints.
    let residual = hard
        .iter()
        .map(|(row, rhs)| (dot_sparse(row, &v) - rhs).powi(2))
        .fold(0.0, |acc, x| acc + x)
        .sqrt();
    let sim = (&smat * &z).norm_squared();
    let rms = (sim / sims.len() as f64).sqrt();
    Ok(Solved {
        v,
        residual,
        rms,
        samples: sims.len(),
        joined,
    })
}
