//! Nonlinear least squares with a sparse Jacobian: minimise `½ Σ r_j(x)²`.
//!
//! * [`Optimiser::LevenbergMarquardt`] (the default): at each step solve
//!   `(JᵀJ + λ (diag(JᵀJ) + μ I)) δ = −Jᵀr` (by nalgebra's Cholesky up to 256 parameters, beyond by
//!   Jacobi-preconditioned conjugate gradients with `JᵀJ` applied through `J`), accept `x + δ` when it lowers the cost
//!   (then `λ ← λ/3`), else raise `λ ← 4λ` and retry (Marquardt 1963, with Nielsen-style
//!   updates simplified).
//! * [`Optimiser::SteepestDescent`]: P0's method (P0 §4.2 1), §4.3), `x ← x − α D⁻¹ Jᵀr`
//!   with `D = diag(JᵀJ)` (each parameter scaled by its own curvature, since centres, radii and
//!   densities have different units) and a backtracking (Armijo) step `α`.
//!
//! The Jacobian is kept sparse: each row (a sample) touches only the few metacircles reaching it.

use nalgebra::{Cholesky, DMatrix, DVector};

/// Residuals and, row by row, the non-zeros of their Jacobian.
#[derive(Debug, Clone, Default)]
pub struct Jacobian {
    /// The residuals `r_j`.
    pub residuals: Vec<f64>,
    starts: Vec<usize>,
    cols: Vec<u32>,
    vals: Vec<f64>,
}

impl Jacobian {
    /// Empties the rows.
    pub fn clear(&mut self) {
        self.residuals.clear();
        self.starts.clear();
        self.cols.clear();
        self.vals.clear();
    }

    /// Appends a residual and the non-zero partial derivatives `(parameter, ∂r/∂x)` of its row.
    pub fn push(&mut self, residual: f64, entries: impl IntoIterator<Item = (usize, f64)>) {
        self.residuals.push(residual);
        self.starts.push(self.cols.len());
        for (c, v) in entries {
            self.cols.push(c as u32);
            self.vals.push(v);
        }
    }

    /// `½ Σ r²`.
    #[must_use]
    pub fn cost(&self) -> f64 {
        0.5 * self.residuals.iter().map(|r| r * r).sum::<f64>()
    }

    pub(crate) fn row(&self, j: usize) -> (&[u32], &[f64]) {
        let a = self.starts[j];
        let b = self.starts.get(j + 1).copied().unwrap_or(self.cols.len());
        (&self.cols[a..b], &self.vals[a..b])
    }

    /// The diagonal of `JᵀJ` and the gradient `Jᵀr`.
    fn diagonal_and_gradient(&self, n: usize) -> (Vec<f64>, Vec<f64>) {
        let mut d = vec![0.0; n];
        let mut g = vec![0.0; n];
        for j in 0..self.residuals.len() {
            let (cols, vals) = self.row(j);
            let r = self.residuals[j];
            for (&c, &v) in cols.iter().zip(vals) {
                d[c as usize] += v * v;
                g[c as usize] += v * r;
            }
        }
        (d, g)
    }

    /// `out = Jᵀ (J v)`.
    fn normal_product(&self, v: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for j in 0..self.residuals.len() {
            let (cols, vals) = self.row(j);
            let jv: f64 = cols
                .iter()
                .zip(vals)
                .map(|(&c, &x)| x * v[c as usize])
                .sum();
            if jv != 0.0 {
                for (&c, &x) in cols.iter().zip(vals) {
                    out[c as usize] += x * jv;
                }
            }
        }
    }

    /// The dense normal matrix `JᵀJ` (row-major, `n × n`) and gradient `Jᵀr`.
    fn normal_equations(&self, n: usize) -> (Vec<f64>, Vec<f64>) {
        let mut a = vec![0.0; n * n];
        let mut g = vec![0.0; n];
        for j in 0..self.residuals.len() {
            let (cols, vals) = self.row(j);
            let r = self.residuals[j];
            for (k, (&ck, &vk)) in cols.iter().zip(vals).enumerate() {
                let ck = ck as usize;
                g[ck] += vk * r;
                for (&cl, &vl) in cols[..=k].iter().zip(&vals[..=k]) {
                    let cl = cl as usize;
                    let (p, q) = if ck >= cl { (ck, cl) } else { (cl, ck) };
                    a[p * n + q] += vk * vl;
                }
            }
        }
        // Mirror the lower triangle.
        for p in 0..n {
            for q in 0..p {
                a[q * n + p] = a[p * n + q];
            }
        }
        (a, g)
    }
}

/// A least-squares problem in `n` parameters.
pub trait LeastSquares {
    /// Number of parameters.
    fn parameters(&self) -> usize;
    /// Fills `out` with the residuals at `x` and, when `jacobian` is set, their rows.
    fn evaluate(&self, x: &[f64], jacobian: bool, out: &mut Jacobian);
}

/// Which method minimises.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Optimiser {
    /// Levenberg–Marquardt (damped Gauss–Newton).
    #[default]
    LevenbergMarquardt,
    /// Diagonally scaled steepest descent with backtracking, as in P0.
    SteepestDescent,
}

/// When to stop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stopping {
    /// Most iterations (accepted or rejected steps for LM; descent steps otherwise).
    pub max_iterations: usize,
    /// Stop when an accepted step lowers the cost by less than this fraction of it.
    pub relative_decrease: f64,
}

impl Default for Stopping {
    fn default() -> Self {
        Self {
            max_iterations: 200,
            relative_decrease: 1e-7,
        }
    }
}

/// What a minimisation did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    /// Iterations run.
    pub iterations: usize,
    /// Cost `½ Σ r²` at the start.
    pub initial_cost: f64,
    /// Cost at the end.
    pub final_cost: f64,
}

/// Minimises `problem` from `x` (updated in place).
pub fn minimise(
    problem: &impl LeastSquares,
    x: &mut [f64],
    method: Optimiser,
    stop: &Stopping,
) -> Outcome {
    match method {
        Optimiser::LevenbergMarquardt => levenberg_marquardt(problem, x, stop),
        Optimiser::SteepestDescent => steepest_descent(problem, x, stop),
    }
}

/// Parameter counts up to this solve the damped normal equations densely (Cholesky); larger
/// problems by conjugate gradients on `JᵀJ` applied through `J` (never formed).
const DENSE_LIMIT: usize = 256;

fn levenberg_marquardt(problem: &impl LeastSquares, x: &mut [f64], stop: &Stopping) -> Outcome {
    let n = problem.parameters();
    let mut jac = Jacobian::default();
    let mut trial = Jacobian::default();
    problem.evaluate(x, true, &mut jac);
    let initial_cost = jac.cost();
    let mut cost = initial_cost;
    let mut lambda = 1e-3;
    let mut iterations = 0;
    let mut x_new = x.to_vec();
    let mut step = vec![0.0; n];
    let mut cg = ConjugateGradient::new(n);
    'outer: while iterations < stop.max_iterations && cost > 0.0 {
        let (a, diag, g) = if n <= DENSE_LIMIT {
            let (a, g) = jac.normal_equations(n);
            let d = (0..n).map(|i| a[i * n + i]).collect();
            (a, d, g)
        } else {
            let (d, g) = jac.diagonal_and_gradient(n);
            (Vec::new(), d, g)
        };
        let max_diag = diag.iter().copied().fold(0.0, f64::max).max(1e-300);
        loop {
            iterations += 1;
            // Damping λ (diag(JᵀJ) + μ I), μ = 10⁻⁹ max diag.
            let damping: Vec<f64> = diag
                .iter()
                .map(|&d| lambda * (d + 1e-9 * max_diag))
                .collect();
            let solved = if n <= DENSE_LIMIT {
                let mut m = DMatrix::from_row_slice(n, n, &a);
                for i in 0..n {
                    m[(i, i)] += damping[i];
                    step[i] = -g[i];
                }
                cholesky_solve(m, &mut step)
            } else {
                cg.solve(&jac, &diag, &damping, &g, &mut step)
            };
            if solved {
                for i in 0..n {
                    x_new[i] = x[i] + step[i];
                }
                problem.evaluate(&x_new, false, &mut trial);
                let new_cost = trial.cost();
                if new_cost.is_finite() && new_cost < cost {
                    let decrease = (cost - new_cost) / cost;
                    x.copy_from_slice(&x_new);
                    cost = new_cost;
                    lambda = (lambda / 3.0).max(1e-12);
                    problem.evaluate(x, true, &mut jac);
                    if decrease < stop.relative_decrease {
                        break 'outer;
                    }
                    continue 'outer;
                }
            }
            lambda *= 4.0;
            if lambda > 1e14 || iterations >= stop.max_iterations {
                break 'outer;
            }
        }
    }
    Outcome {
        iterations,
        initial_cost,
        final_cost: cost,
    }
}

/// Jacobi-preconditioned conjugate gradients for `(JᵀJ + D) δ = −g`, `D` the damping
/// (Steihaug-style truncated: stops at a relative residual of 10⁻⁴ or after `2n`, at most
/// 500, iterations — an inexact step, which the LM acceptance test covers).
struct ConjugateGradient {
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    ap: Vec<f64>,
}

impl ConjugateGradient {
    fn new(n: usize) -> Self {
        Self {
            r: vec![0.0; n],
            z: vec![0.0; n],
            p: vec![0.0; n],
            ap: vec![0.0; n],
        }
    }

    fn solve(
        &mut self,
        jac: &Jacobian,
        diag: &[f64],
        damping: &[f64],
        g: &[f64],
        x: &mut [f64],
    ) -> bool {
        let n = g.len();
        let precond: Vec<f64> = (0..n)
            .map(|i| 1.0 / (diag[i] + damping[i]).max(1e-300))
            .collect();
        x.fill(0.0);
        for i in 0..n {
            self.r[i] = -g[i];
            self.z[i] = self.r[i] * precond[i];
            self.p[i] = self.z[i];
        }
        let norm0: f64 = self.r.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm0 == 0.0 {
            return false;
        }
        let mut rz: f64 = self.r.iter().zip(&self.z).map(|(a, b)| a * b).sum();
        for _ in 0..(2 * n).min(500) {
            jac.normal_product(&self.p, &mut self.ap);
            for ((ap, d), p) in self.ap.iter_mut().zip(damping).zip(&self.p) {
                *ap += d * p;
            }
            let pap: f64 = self.p.iter().zip(&self.ap).map(|(a, b)| a * b).sum();
            if !(pap > 0.0 && pap.is_finite()) {
                break;
            }
            let alpha = rz / pap;
            for (((x, r), p), ap) in x.iter_mut().zip(&mut self.r).zip(&self.p).zip(&self.ap) {
                *x += alpha * p;
                *r -= alpha * ap;
            }
            let norm: f64 = self.r.iter().map(|v| v * v).sum::<f64>().sqrt();
            if norm <= 1e-4 * norm0 {
                break;
            }
            for ((z, r), m) in self.z.iter_mut().zip(&self.r).zip(&precond) {
                *z = r * m;
            }
            let rz_new: f64 = self.r.iter().zip(&self.z).map(|(a, b)| a * b).sum();
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..n {
                self.p[i] = self.z[i] + beta * self.p[i];
            }
        }
        x.iter().all(|v| v.is_finite())
    }
}

fn steepest_descent(problem: &impl LeastSquares, x: &mut [f64], stop: &Stopping) -> Outcome {
    let n = problem.parameters();
    let mut jac = Jacobian::default();
    let mut trial = Jacobian::default();
    problem.evaluate(x, true, &mut jac);
    let initial_cost = jac.cost();
    let mut cost = initial_cost;
    let mut alpha = 1.0;
    let mut x_new = x.to_vec();
    let mut iterations = 0;
    while iterations < stop.max_iterations && cost > 0.0 {
        iterations += 1;
        let (d, g) = jac.diagonal_and_gradient(n);
        let max_diag = d.iter().copied().fold(0.0, f64::max).max(1e-300);
        let dir: Vec<f64> = (0..n).map(|i| -g[i] / (d[i] + 1e-9 * max_diag)).collect();
        let slope: f64 = g.iter().zip(&dir).map(|(g, d)| g * d).sum();
        if slope >= 0.0 {
            break;
        }
        alpha *= 2.0;
        let mut accepted = false;
        for _ in 0..40 {
            for i in 0..n {
                x_new[i] = x[i] + alpha * dir[i];
            }
            problem.evaluate(&x_new, false, &mut trial);
            let c = trial.cost();
            if c.is_finite() && c <= cost + 1e-4 * alpha * slope {
                let decrease = (cost - c) / cost;
                x.copy_from_slice(&x_new);
                cost = c;
                accepted = decrease >= stop.relative_decrease;
                break;
            }
            alpha *= 0.5;
        }
        if !accepted {
            break;
        }
        problem.evaluate(x, true, &mut jac);
    }
    Outcome {
        iterations,
        initial_cost,
        final_cost: cost,
    }
}

/// Solves `M y = b` for a symmetric positive-definite `M` by [`nalgebra::Cholesky`]; `b`
/// becomes `y`. False (and `b` unchanged) when `M` has an entry that is not finite, is not
/// positive definite (a pivot that is zero, negative or NaN), or the solution overflows: the
/// caller then raises the damping.
fn cholesky_solve(m: DMatrix<f64>, b: &mut [f64]) -> bool {
    if !m.iter().all(|v| v.is_finite()) {
        return false;
    }
    let Some(factor) = Cholesky::new(m) else {
        return false;
    };
    let y = factor.solve(&DVector::from_column_slice(b));
    if !y.iter().all(|v| v.is_finite()) {
        return false;
    }
    b.copy_from_slice(y.as_slice());
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rosenbrock as least squares: r = (10 (y − x²), 1 − x).
    struct Rosenbrock;
    impl LeastSquares for Rosenbrock {
        fn parameters(&self) -> usize {
            2
        }
        fn evaluate(&self, x: &[f64], jacobian: bool, out: &mut Jacobian) {
            out.clear();
            let j = |e: [(usize, f64); 2]| if jacobian { e.to_vec() } else { Vec::new() };
            out.push(
                10.0 * (x[1] - x[0] * x[0]),
                j([(0, -20.0 * x[0]), (1, 10.0)]),
            );
            out.push(1.0 - x[0], j([(0, -1.0), (1, 0.0)]));
        }
    }

    #[test]
    fn lm_solves_rosenbrock() {
        let mut x = [-1.2, 1.0];
        let o = minimise(
            &Rosenbrock,
            &mut x,
            Optimiser::LevenbergMarquardt,
            &Stopping::default(),
        );
        assert!(
            (x[0] - 1.0).abs() < 1e-6 && (x[1] - 1.0).abs() < 1e-6,
            "{x:?} {o:?}"
        );
        assert!(o.final_cost < 1e-12);
    }

    #[test]
    fn descent_lowers_the_cost() {
        let mut x = [-1.2, 1.0];
        let o = minimise(
            &Rosenbrock,
            &mut x,
            Optimiser::SteepestDescent,
            &Stopping {
                max_iterations: 2000,
                relative_decrease: 0.0,
            },
        );
        assert!(o.final_cost < 0.5 * o.initial_cost, "{o:?}");
    }

    /// Many independent Rosenbrocks: beyond the dense limit, through conjugate gradients.
    struct ManyRosenbrocks(usize);
    impl LeastSquares for ManyRosenbrocks {
        fn parameters(&self) -> usize {
            2 * self.0
        }
        fn evaluate(&self, x: &[f64], jacobian: bool, out: &mut Jacobian) {
            out.clear();
            for k in 0..self.0 {
                let (a, b) = (2 * k, 2 * k + 1);
                let j = |e: [(usize, f64); 2]| if jacobian { e.to_vec() } else { Vec::new() };
                out.push(
                    10.0 * (x[b] - x[a] * x[a]),
                    j([(a, -20.0 * x[a]), (b, 10.0)]),
                );
                out.push(1.0 - x[a], j([(a, -1.0), (b, 0.0)]));
            }
        }
    }

    #[test]
    fn lm_with_conjugate_gradients_solves_a_large_problem() {
        let p = ManyRosenbrocks(200);
        let mut x: Vec<f64> = (0..400)
            .map(|i| if i % 2 == 0 { -1.2 } else { 1.0 })
            .collect();
        let o = minimise(
            &p,
            &mut x,
            Optimiser::LevenbergMarquardt,
            &Stopping {
                max_iterations: 500,
                relative_decrease: 0.0,
            },
        );
        assert!(o.final_cost < 1e-10, "{o:?}");
        assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-4));
    }

    #[test]
    fn cholesky_matches_a_known_solution() {
        // M = [[4, 2], [2, 3]], b = M [1, 2] = [8, 8].
        let m = DMatrix::from_row_slice(2, 2, &[4.0, 2.0, 2.0, 3.0]);
        let mut b = vec![8.0, 8.0];
        assert!(cholesky_solve(m, &mut b));
        assert!((b[0] - 1.0).abs() < 1e-14 && (b[1] - 2.0).abs() < 1e-14);
        // Indefinite, singular, NaN and infinite matrices are refused and leave b alone.
        for bad in [
            [1.0, 2.0, 2.0, 1.0],
            [1.0, 1.0, 1.0, 1.0],
            [0.0, 0.0, 0.0, 0.0],
            [f64::NAN, 0.0, 0.0, 1.0],
            [f64::INFINITY, 0.0, 0.0, 1.0],
        ] {
            let mut b = [1.0, 1.0];
            assert!(
                !cholesky_solve(DMatrix::from_row_slice(2, 2, &bad), &mut b),
                "{bad:?}"
            );
            assert_eq!(b, [1.0, 1.0]);
        }
    }
}
