//! Saved spacing ratios checked against the control points they describe.
//!
//! A shared grid line's reference spacing ratio `ρ` ([`Grid::ratio_u`]) is what the exact
//! regulation holds every row crossing the line to: `P₊ − P₀ = ρ·(P₀ − P₋)`. A model file
//! saves the ratios beside the points; when the two disagree (a ratio edited to `1.00001`, or
//! rounded to four decimals after a refinement at `u = 4.3`), the file reads, `check` finds
//! the surface G1, and every exact push near the line is refused for a reason the user cannot
//! see. So a loaded model is checked:
//!
//! for each shared line, every row crossing it with both arms longer than `1e-9 · max(1, |P|)`
//! gives `r_i = |P₊ − P₀| / |P₀ − P₋|`, and `r̄` is their mean (as the grid measures it when
//! built). When the rows agree — `|r_i − r̄| ≤ τ · r̄` for all `i`, the line is kept exactly —
//! the saved ratio must agree too: `|ρ − r̄| ≤ τ · r̄`, with `τ` = [`RATIO_TOLERANCE`] = `1e-7`
//! relative (a model written and read keeps its ratios to about `1e-15`; a ratio rounded to
//! four decimals is off by up to `5e-5`). A line whose rows disagree among themselves (sculpted
//! under `g1`, `c1` or `none`, which keep no common ratio) has no ratio its points determine,
//! and its saved reference is kept as it is.

use glam::DVec3;

use super::grid::Grid;

/// Relative tolerance between a saved ratio and the ratio its control points have.
pub const RATIO_TOLERANCE: f64 = 1e-7;

/// A saved ratio that is not the ratio of its line's control points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RatioMismatch {
    /// `'u'` or `'v'`: the grid line's direction (a u line is lattice column `3k`).
    pub direction: char,
    /// The grid line's index `k` (or `q`).
    pub line: usize,
    /// The ratio saved.
    pub saved: f64,
    /// The ratio of the rows crossing the line.
    pub measured: f64,
}

/// The common ratio of `rows`, when they have one within `tolerance` (see the module docs);
/// `None` when no row counts or the rows disagree.
fn common_ratio(
    rows: impl Iterator<Item = (Option<DVec3>, Option<DVec3>, Option<DVec3>)>,
    tolerance: f64,
) -> Option<f64> {
    let mut ratios = Vec::new();
    for r in rows {
        let (Some(m), Some(o), Some(p)) = r else {
            continue;
        };
        let (lm, lp) = ((o - m).length(), (p - o).length());
        let scale = m.length().max(o.length()).max(p.length()).max(1.0);
        if lm > 1e-9 * scale && lp > 1e-9 * scale {
            ratios.push(lp / lm);
        }
    }
    if ratios.is_empty() {
        return None;
    }
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    (mean.is_finite() && ratios.iter().all(|r| (r - mean).abs() <= tolerance * mean))
        .then_some(mean)
}

impl Grid {
    /// The first shared grid line (u lines first) whose saved ratio disagrees with the common
    /// ratio of its control-point rows by more than `tolerance` (relative; see the module docs).
    #[must_use]
    pub fn ratio_mismatch(&self, tolerance: f64) -> Option<RatioMismatch> {
        let t = self.topology();
        let la = 3 * self.patches_u() + usize::from(!t.closed_u());
        let lb = 3 * self.patches_v() + usize::from(!t.closed_v());
        let nodes = self.nodes();
        let at = |a: isize, b: isize| self.node_id(a, b).map(|id| nodes[id]);
        let check = |direction, line, saved: f64, measured: Option<f64>| {
            measured
                .filter(|&r| (saved - r).abs() > tolerance * r)
                .map(|measured| RatioMismatch {
                    direction,
                    line,
                    saved,
                    measured,
                })
        };
        for k in (0..self.vertices_u()).filter(|&k| self.u_line_shared(k)) {
            let a = 3 * k as isize;
            let rows = (0..lb as isize).map(|b| (at(a - 1, b), at(a, b), at(a + 1, b)));
            if let Some(m) = check('u', k, self.ratio_u(k), common_ratio(rows, tolerance)) {
                return Some(m);
            }
        }
        for q in (0..self.vertices_v()).filter(|&q| self.v_line_shared(q)) {
            let b = 3 * q as isize;
            let cols = (0..la as isize).map(|a| (at(a, b - 1), at(a, b), at(a, b + 1)));
            if let Some(m) = check('v', q, self.ratio_v(q), common_ratio(cols, tolerance)) {
                return Some(m);
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Primitive, PrimitiveParams};

    #[test]
    fn a_changed_ratio_is_found_and_the_measured_ones_pass() {
        let mut grid = Primitive::Plane
            .build(&PrimitiveParams {
                patches: Some((4, 3)),
                ..PrimitiveParams::default()
            })
            .expect("plane");
        assert_eq!(grid.ratio_mismatch(RATIO_TOLERANCE), None);
        let mut u = grid.ratios_u().to_vec();
        let v = grid.ratios_v().to_vec();
        u[2] *= 1.00001;
        grid.set_ratios(&u, &v).expect("set");
        let m = grid.ratio_mismatch(RATIO_TOLERANCE).expect("found");
        assert_eq!((m.direction, m.line), ('u', 2));
        assert!((m.saved / m.measured - 1.00001).abs() < 1e-12, "{m:?}");
    }
}
