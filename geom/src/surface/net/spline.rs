//! The whole grid as **one** bicubic B-spline surface, exactly (issue 29's one-surface export).
//!
//! ## Why a regulated grid is one B-spline
//! Take one direction, say `u`, with `M` patches of parameter widths `h_0, …, h_{M−1}` and
//! break points `U_0 = 0`, `U_{k+1} = U_k + h_k`. A cubic B-spline on the knot vector
//!
//! ```text
//! U_0 U_0 U_0 U_0 | U_1 U_1 | U_2 U_2 | … | U_{M−1} U_{M−1} | U_M U_M U_M U_M
//! ```
//!
//! (double interior knots: C1 at every break) has `2M + 2` control points. Inserting each
//! interior knot once more (to multiplicity 3) gives the Bezier form, piece `k` on
//! `[U_k, U_{k+1}]`: the B-spline's points are the Bezier points `P_0, P_1, P_2, P_4, P_5,
//! P_7, …, P_{3M−2}, P_{3M−1}, P_{3M}` (every junction point `P_{3k}`, `0 < k < M`, left out),
//! and knot insertion puts the junction back at
//!
//! ```text
//! P_{3k} = (h_k P_{3k−1} + h_{k−1} P_{3k+1}) / (h_{k−1} + h_k),
//! ```
//!
//! i.e. `P_{3k+1} − P_{3k} = (h_k / h_{k−1}) (P_{3k} − P_{3k−1})`. That is exactly the condition
//! the `exact` regulation keeps on every row of control points crossing grid line `k`, with the
//! line's reference spacing ratio `ρ_k` ([`Grid::ratio_u`]). So with the widths
//!
//! ```text
//! h_0 = 1,   h_k = ρ_k h_{k−1}
//! ```
//!
//! (then scaled so that `Σ h_k = M`: a uniform grid gets the integer knots `0, 1, …, M`) the
//! Bezier grid *is* the B-spline on those knots whose control points are the grid's lattice
//! columns `0, 1, 2, 4, 5, 7, …, 3M` (and rows likewise along `v`): the tensor product of the
//! two one-dimensional statements, since the regulation's groups are bilinear lattices
//! `P(s, t) = P_O + s̃ a + t̃ b + s̃ t̃ c` with `s̃ ∈ {−1, 0, ρ_u}` (every row *and* column
//! crossing a vertex keeps its line's ratio).
//!
//! ## Closed directions and poles
//! A closed direction is written **clamped**, not periodic: its first and last control
//! columns are the same lattice column (column `3M` is column 0), so the surface closes on
//! itself with a seam at `U_0 = U_M` where the two ends meet G1 (the regulation keeps the seam
//! line's ratio) but the knot vector does not claim more. This is what OpenCASCADE reads as a
//! closed surface with a seam edge, and it needs no condition on the product of the ratios
//! around the loop (a periodic C1 spline would need `Π ρ_k = 1`). A pole row stays a row of
//! equal control points (a degenerate boundary), as in the patches.
//!
//! ## Exactness is checked, not assumed
//! [`Grid::one_spline`] measures every junction point against the formula above (the largest
//! distance is [`GridSpline::junction_error`]) and evaluates the spline against every patch at
//! a 3 × 3 set of parameters per patch by de Boor's algorithm ([`GridSpline::eval`]); the
//! largest distance is [`GridSpline::max_deviation`]. A grid whose deviation exceeds the
//! tolerance (regulated with another method, or edited by hand) is refused with
//! [`NotOneSpline`], naming the worst grid line.

use glam::DVec3;

use crate::surface::grid::Grid;

/// The relative tolerance [`Grid::one_spline`] uses by default: the spline may deviate from
/// the patches by this times the control net's bounding-box diagonal (the exact regulation
/// keeps it at rounding, ~1e-15).
pub const ONE_SPLINE_TOLERANCE: f64 = 1e-9;

/// The grid as one bicubic B-spline surface (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct GridSpline {
    /// Break points along `u`, `U_0 = 0 < U_1 < … < U_M` (`Σ h_k = M`).
    pub breaks_u: Vec<f64>,
    /// Break points along `v`, `V_0 = 0 < … < V_N`.
    pub breaks_v: Vec<f64>,
    /// Lattice columns of the control points along `u` (`0, 1, 2, 4, 5, …, 3M`).
    pub columns: Vec<usize>,
    /// Lattice rows of the control points along `v` (`0, 1, 2, 4, 5, …, 3N`).
    pub rows: Vec<usize>,
    /// Control-net node id of control point `(i, j)` at `i * rows.len() + j` (`i` along `u`).
    pub node_ids: Vec<usize>,
    /// The control points, in the order of `node_ids`.
    pub points: Vec<DVec3>,
    /// True when the first and last control columns are the same (closed along `u`).
    pub closed_u: bool,
    /// True when the first and last control rows are the same (closed along `v`).
    pub closed_v: bool,
    /// Largest distance of a junction point from its knot-insertion value.
    pub junction_error: f64,
    /// Largest distance between the spline and the patches at the sampled parameters.
    pub max_deviation: f64,
}

/// Why a grid is not one B-spline surface within the tolerance.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "the surface is not one B-spline within {tolerance:.3e}: the rows crossing {line} miss its \
     spacing ratio by up to {deviation:.3e} (a surface regulated with `exact` always is one)"
)]
pub struct NotOneSpline {
    /// The worst grid line, e.g. `u line 3`.
    pub line: String,
    /// The largest deviation found (spline against patches, or a junction point).
    pub deviation: f64,
    /// The tolerance (absolute, model units).
    pub tolerance: f64,
}

/// The B-spline basis of one direction: knots (double interior), break points.
#[derive(Debug, Clone)]
struct Direction {
    breaks: Vec<f64>,
    knots: Vec<f64>,
}

impl Direction {
    /// Break points from the reference ratios of the `count` patches' interior lines.
    fn new(count: usize, ratio: impl Fn(usize) -> f64) -> Self {
        let mut widths = Vec::with_capacity(count);
        let mut h = 1.0;
        for k in 0..count {
            if k > 0 {
                h *= ratio(k);
            }
            widths.push(h);
        }
        let total: f64 = widths.iter().sum();
        let scale = count as f64 / total;
        let mut breaks = Vec::with_capacity(count + 1);
        let mut at = 0.0;
        breaks.push(0.0);
        for (k, w) in widths.iter().enumerate() {
            at += w * scale;
            breaks.push(if k + 1 == count { count as f64 } else { at });
        }
        let mut knots = vec![0.0; 4];
        for &b in &breaks[1..count] {
            knots.extend([b, b]);
        }
        knots.extend([count as f64; 4]);
        Self { breaks, knots }
    }

    /// The lattice indices kept as control points: all but the interior junctions.
    fn lattice(count: usize) -> Vec<usize> {
        (0..=3 * count)
            .filter(|&a| a == 0 || a == 3 * count || !a.is_multiple_of(3))
            .collect()
    }

    /// The knot span `s` (with `knots[s] ≤ t < knots[s+1]`, the last span at the end) and the
    /// four non-zero cubic basis values there (Cox–de Boor).
    fn basis(&self, t: f64) -> (usize, [f64; 4]) {
        let n = self.knots.len() - 4; // control points
        // The last span `s ∈ 3..n` with `knots[s] ≤ t` (binary search).
        let s = (3 + self.knots[4..n].partition_point(|&k| k <= t)).min(n - 1);
        let k = &self.knots;
        let mut b = [1.0, 0.0, 0.0, 0.0];
        let mut left = [0.0; 4];
        let mut right = [0.0; 4];
        for d in 1..=3 {
            left[d] = t - k[s + 1 - d];
            right[d] = k[s + d] - t;
            let mut saved = 0.0;
            for r in 0..d {
                let denom = right[r + 1] + left[d - r];
                let temp = if denom == 0.0 { 0.0 } else { b[r] / denom };
                b[r] = saved + right[r + 1] * temp;
                saved = left[d - r] * temp;
            }
            b[d] = saved;
        }
        (s, b)
    }
}

impl GridSpline {
    /// The full knot vector along `u` (`4, 2, …, 2, 4` copies of the break points).
    #[must_use]
    pub fn knots_u(&self) -> Vec<f64> {
        full_knots(&self.breaks_u)
    }

    /// The full knot vector along `v`.
    #[must_use]
    pub fn knots_v(&self) -> Vec<f64> {
        full_knots(&self.breaks_v)
    }

    /// Number of control points along `u` (`2M + 2`).
    #[must_use]
    pub fn count_u(&self) -> usize {
        self.columns.len()
    }

    /// Number of control points along `v` (`2N + 2`).
    #[must_use]
    pub fn count_v(&self) -> usize {
        self.rows.len()
    }

    /// Control point `(i, j)`.
    #[must_use]
    pub fn point(&self, i: usize, j: usize) -> DVec3 {
        self.points[i * self.rows.len() + j]
    }

    /// The spline's parameters of patch `(iu, iv)`'s point `(s, t) ∈ [0, 1]²`.
    #[must_use]
    pub fn parameter(&self, iu: usize, iv: usize, s: f64, t: f64) -> (f64, f64) {
        let (bu, bv) = (&self.breaks_u, &self.breaks_v);
        (
            bu[iu] + s * (bu[iu + 1] - bu[iu]),
            bv[iv] + t * (bv[iv + 1] - bv[iv]),
        )
    }

    /// `S(u, v)` by de Boor (the basis of each direction, then the tensor sum), `u ∈ [0, M]`,
    /// `v ∈ [0, N]` (clamped into the range).
    #[must_use]
    pub fn eval(&self, u: f64, v: f64) -> DVec3 {
        let du = Direction {
            breaks: Vec::new(),
            knots: self.knots_u(),
        };
        let dv = Direction {
            breaks: Vec::new(),
            knots: self.knots_v(),
        };
        eval_with(self, &du, &dv, u, v)
    }
}

fn full_knots(breaks: &[f64]) -> Vec<f64> {
    let n = breaks.len() - 1;
    let mut knots = vec![breaks[0]; 4];
    for &b in &breaks[1..n] {
        knots.extend([b, b]);
    }
    knots.extend([breaks[n]; 4]);
    knots
}

fn eval_with(sp: &GridSpline, du: &Direction, dv: &Direction, u: f64, v: f64) -> DVec3 {
    let u = u.clamp(du.knots[0], du.knots[du.knots.len() - 1]);
    let v = v.clamp(dv.knots[0], dv.knots[dv.knots.len() - 1]);
    let (su, bu) = du.basis(u);
    let (sv, bv) = dv.basis(v);
    let mut p = DVec3::ZERO;
    for (a, wa) in bu.iter().enumerate() {
        for (b, wb) in bv.iter().enumerate() {
            p += sp.point(su - 3 + a, sv - 3 + b) * (wa * wb);
        }
    }
    p
}

impl Grid {
    /// The grid as one bicubic B-spline surface, checked against the patches with the
    /// tolerance `relative` × the control net's bounding-box diagonal (see the module docs;
    /// [`ONE_SPLINE_TOLERANCE`] is the usual value).
    ///
    /// # Errors
    /// [`NotOneSpline`] when a junction point or a sampled point misses by more.
    pub fn one_spline(&self, relative: f64) -> Result<GridSpline, NotOneSpline> {
        let (m, n) = (self.patches_u(), self.patches_v());
        let dir_u = Direction::new(m, |k| self.ratio_u(k));
        let dir_v = Direction::new(n, |q| self.ratio_v(q));
        let columns = Direction::lattice(m);
        let rows = Direction::lattice(n);
        let node = |a: usize, b: usize| {
            // Every lattice point of the patches exists (indices wrap around closed ones).
            self.node_id(a as isize, b as isize)
                .unwrap_or_else(|| unreachable!("lattice point ({a}, {b}) of a patch"))
        };
        let mut node_ids = Vec::with_capacity(columns.len() * rows.len());
        for &a in &columns {
            for &b in &rows {
                node_ids.push(node(a, b));
            }
        }
        let points = node_ids.iter().map(|&id| self.nodes()[id]).collect();
        let bounds = self.bounds();
        let tolerance = relative * (bounds.max - bounds.min).length().max(f64::MIN_POSITIVE);

        // Junction points against knot insertion: u lines over every lattice row, v lines
        // over every lattice column.
        let (la, lb) = self.lattice_size();
        let mut worst = (0.0f64, String::new());
        let mut note = |d: f64, line: &dyn Fn() -> String| {
            if worst.1.is_empty() || d > worst.0 {
                worst = (d, line());
            }
        };
        for k in 1..m {
            let (h0, h1) = width_pair(&dir_u.breaks, k);
            for b in 0..lb {
                let at = |a: usize| self.nodes()[node(a, b)];
                let d = junction(at(3 * k - 1), at(3 * k), at(3 * k + 1), h0, h1);
                note(d, &|| format!("u line {k}"));
            }
        }
        for q in 1..n {
            let (h0, h1) = width_pair(&dir_v.breaks, q);
            for a in 0..la {
                let at = |b: usize| self.nodes()[node(a, b)];
                let d = junction(at(3 * q - 1), at(3 * q), at(3 * q + 1), h0, h1);
                note(d, &|| format!("v line {q}"));
            }
        }
        let junction_error = worst.0;
        let mut spline = GridSpline {
            breaks_u: dir_u.breaks.clone(),
            breaks_v: dir_v.breaks.clone(),
            columns,
            rows,
            node_ids,
            points,
            closed_u: self.topology().closed_u(),
            closed_v: self.topology().closed_v(),
            junction_error,
            max_deviation: 0.0,
        };
        // The spline against every patch.
        const S: [f64; 3] = [0.0, 0.37, 1.0];
        let mut deviation = 0.0f64;
        let mut worst_patch = (0, 0);
        for iv in 0..n {
            for iu in 0..m {
                let patch = crate::surface::patch::Patch::new(self.patch(iu, iv));
                for s in S {
                    for t in S {
                        let (u, v) = spline.parameter(iu, iv, s, t);
                        let d =
                            (eval_with(&spline, &dir_u, &dir_v, u, v) - patch.eval(s, t)).length();
                        // A NaN distance is the worst of all.
                        if d.is_nan() || d > deviation {
                            deviation = d;
                            worst_patch = (iu, iv);
                        }
                    }
                }
            }
        }
        spline.max_deviation = deviation;
        if junction_error.is_nan() || junction_error > tolerance {
            return Err(NotOneSpline {
                line: worst.1,
                deviation: junction_error.max(deviation),
                tolerance,
            });
        }
        if deviation.is_nan() || deviation > tolerance {
            return Err(NotOneSpline {
                line: format!("the lines of patch ({}, {})", worst_patch.0, worst_patch.1),
                deviation,
                tolerance,
            });
        }
        Ok(spline)
    }
}

/// The widths `(h_{k−1}, h_k)` either side of break `k`.
fn width_pair(breaks: &[f64], k: usize) -> (f64, f64) {
    (breaks[k] - breaks[k - 1], breaks[k + 1] - breaks[k])
}

/// Distance of the junction point `p0` from `(h1 p_minus + h0 p_plus) / (h0 + h1)`.
fn junction(p_minus: DVec3, p0: DVec3, p_plus: DVec3, h0: f64, h1: f64) -> f64 {
    (p0 - (p_minus * h1 + p_plus * h0) / (h0 + h1)).length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Op, Primitive, PrimitiveParams, Regulation, Sculptor};

    fn built(primitive: Primitive) -> Grid {
        primitive
            .build(&PrimitiveParams::default())
            .unwrap_or_else(|e| panic!("{primitive:?}: {e}"))
    }

    fn sculpted(primitive: Primitive, regulation: Regulation) -> Grid {
        let mut g = built(primitive);
        let b = g.bounds();
        let c = (b.min + b.max) * 0.5;
        let op = Op::Push {
            at: DVec3::new(c.x + 0.3, c.y + 0.2, b.max.z),
            dir: DVec3::NEG_Z,
            depth: 0.4,
            radius: 1.2,
        };
        Sculptor::new()
            .apply(&mut g, &op, regulation)
            .unwrap_or_else(|e| panic!("push on {primitive:?}: {e}"));
        g
    }

    #[test]
    fn uniform_knots_and_lattice() {
        let d = Direction::new(3, |_| 1.0);
        assert_eq!(d.breaks, [0.0, 1.0, 2.0, 3.0]);
        assert_eq!(
            d.knots,
            [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 3.0, 3.0, 3.0, 3.0]
        );
        assert_eq!(Direction::lattice(3), [0, 1, 2, 4, 5, 7, 8, 9]);
        // Partition of unity everywhere.
        for t in [0.0, 0.3, 1.0, 1.5, 2.999, 3.0] {
            let (_, b) = d.basis(t);
            assert!((b.iter().sum::<f64>() - 1.0).abs() < 1e-14, "{t}");
        }
    }

    #[test]
    fn ratios_give_widths() {
        let d = Direction::new(3, |k| [1.0, 2.0, 0.5][k]);
        // Widths 1, 2, 1 scaled to sum 3.
        let w: Vec<f64> = d.breaks.windows(2).map(|w| w[1] - w[0]).collect();
        assert!((w[1] / w[0] - 2.0).abs() < 1e-14 && (w[2] / w[1] - 0.5).abs() < 1e-14);
    }

    #[test]
    fn sculpted_exact_primitives_are_one_spline() {
        for p in [
            Primitive::Plane,
            Primitive::Sphere,
            Primitive::Torus,
            Primitive::Cylinder,
            Primitive::Hemisphere,
            Primitive::Tube,
        ] {
            let g = sculpted(p, Regulation::Exact);
            let s = g
                .one_spline(ONE_SPLINE_TOLERANCE)
                .unwrap_or_else(|e| panic!("{p:?}: {e}"));
            assert_eq!(s.count_u(), 2 * g.patches_u() + 2, "{p:?}");
            assert_eq!(s.count_v(), 2 * g.patches_v() + 2, "{p:?}");
            assert!(s.max_deviation < 1e-12, "{p:?} {}", s.max_deviation);
            // Random interior points too (seeded).
            let mut x = 0x2545_F491_4F6C_DD1Du64;
            let mut r = || {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                (x >> 11) as f64 / (1u64 << 53) as f64
            };
            for _ in 0..200 {
                let iu = (r() * g.patches_u() as f64) as usize % g.patches_u();
                let iv = (r() * g.patches_v() as f64) as usize % g.patches_v();
                let (a, b) = (r(), r());
                let (u, v) = s.parameter(iu, iv, a, b);
                let d = (s.eval(u, v) - g.eval(iu, iv, a, b)).length();
                assert!(d < 1e-12, "{p:?} patch ({iu},{iv}) at ({a},{b}): {d}");
            }
        }
    }

    #[test]
    fn the_tube_has_unequal_knots() {
        let g = built(Primitive::Tube);
        assert!(g.ratios_v().iter().any(|&r| (r - 1.0).abs() > 1e-6));
        let s = g
            .one_spline(ONE_SPLINE_TOLERANCE)
            .unwrap_or_else(|e| panic!("{e}"));
        let w: Vec<f64> = s.breaks_v.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(w.iter().any(|&x| (x - 1.0).abs() > 1e-6), "{w:?}");
    }

    #[test]
    fn a_grid_regulated_otherwise_is_refused_with_its_line() {
        let g = sculpted(Primitive::Plane, Regulation::None);
        let e = g
            .one_spline(ONE_SPLINE_TOLERANCE)
            .err()
            .unwrap_or_else(|| panic!("an unregulated dent is not one spline"));
        assert!(e.deviation > e.tolerance, "{e}");
        assert!(e.line.contains("line"), "{e}");
    }
}
