//! Verification of an operation's result (docs/design.md §11, step 5): every control point of the touched
//! patches finite and within [`COORDINATE_LIMIT`]; under [`Regulation::Exact`] (the method
//! that promises G1) every edge of a touched patch with a changed control point G1 within
//! [`G1_TOLERANCE_DEG`].
//!
//! An edge is first tried with an algebraic certificate on its 12 control points
//! ([`certified_g1`]: the rows crossing it keep one positive ratio, `Q_k − X_k = λ (X_k − P_k)`,
//! up to a residual whose bound on the normals' angle along the whole edge is below the
//! tolerance, and that side has a tangent plane all along); only the edges it does not prove
//! (at poles, creased, or with ratios varying along the edge) have their normals compared at
//! sampled points. An edge creased before the operation is not the operation's failure.
//! Under [`Regulation::G2`] the same edges must also be curvature-continuous: the normal
//! curvatures across the edge at 5 points inside it agree within [`G2_TOLERANCE`]
//! ([`verify_g2`]).
//! [`Regulation::None`], [`Regulation::C1`] and [`Regulation::G1`] are documented baselines
//! that do not promise G1 everywhere: only the coordinate check applies to them.

use glam::DVec3;

use crate::surface::continuity::angle_deg;
use crate::surface::error::SurfaceError;
use crate::surface::grid::Grid;
use crate::surface::limits::{COORDINATE_LIMIT, G1_TOLERANCE_DEG};
use crate::surface::marks::Marks;
use crate::surface::patch::{Patch, cubic_basis, cubic_basis_derivative};
use crate::surface::regulate::Regulation;
use crate::surface::verify_g2::verify_g2;

/// Points per edge at which [`verify`] compares the normals of the two sides: both ends and
/// the middle (9 points cost about 3× more; the folds seen so far show at these three).
const VERIFY_SAMPLES: usize = 3;

/// Checks what an operation produced on `patches` (sorted patch indices): every control point
/// finite and within [`COORDINATE_LIMIT`]; under [`Regulation::Exact`], every shared edge of
/// those patches with a control point changed (one whose position differs, bit for bit, from
/// an old position listed in `before`) G1 within [`G1_TOLERANCE_DEG`]: proved along the whole edge from its control
/// points (`certified_g1`, which holds on every edge the exact regulation made G1 away from
/// the poles), or else with the normals compared at both ends and the middle of the edge
/// (points where a side has no tangent plane are skipped, as in [`crate::surface::continuity`]).
///
/// `before` lists `(node id, old position)` for every control point the operation wrote (in
/// the order written; repeats allowed). An edge that creases beyond the tolerance is only a
/// failure if it was G1 before the operation: an edge creased already (a model made with
/// another method) is not the operation's doing. To tell, the old positions are put back for
/// the measure and the new ones restored afterwards, so `grid` is unchanged on return.
///
/// # Errors
/// [`SurfaceError::OutOfRange`] for the first bad point; [`SurfaceError::NotG1`] naming the
/// worst edge the operation creased and its angle.
pub fn verify(
    grid: &mut Grid,
    patches: &[usize],
    regulation: Regulation,
    before: &[(usize, DVec3)],
) -> Result<(), SurfaceError> {
    verify_marked(grid, patches, regulation, before, &mut Marks::default())
}

/// [`verify`] with its node marks kept by the caller. Only the edges with a control point
/// that differs from its old position in `before` (bit for bit) are examined: an edge whose
/// 12 control points are all as they were is as G1 as it was, and an edge creased before the
/// operation is not its failure (see [`verify`]), so leaving them out changes no result.
pub(crate) fn verify_marked(
    grid: &mut Grid,
    patches: &[usize],
    regulation: Regulation,
    before: &[(usize, DVec3)],
    marks: &mut Marks,
) -> Result<(), SurfaceError> {
    let m = grid.patches_u();
    let shape = grid.shape();
    let nodes = grid.nodes();
    for &p in patches {
        let ids = shape.patch_ids(p % m, p / m);
        for (k, &id) in ids.iter().enumerate() {
            let x = nodes[id];
            // False for NaN as well as for infinities and points beyond the limit.
            let within = |c: f64| c.abs() <= COORDINATE_LIMIT;
            if !(within(x.x) && within(x.y) && within(x.z)) {
                return Err(SurfaceError::OutOfRange {
                    patch: p,
                    point: k,
                    limit: COORDINATE_LIMIT,
                });
            }
        }
    }
    if !regulation.promises_g1() {
        return Ok(());
    }
    // The nodes that differ from their old positions (a node written twice is marked when
    // either old position differs: its first, the true old one, is among them).
    marks.start(nodes.len());
    for &(id, old) in before {
        let x = nodes[id];
        if x.x.to_bits() != old.x.to_bits()
            || x.y.to_bits() != old.y.to_bits()
            || x.z.to_bits() != old.z.to_bits()
        {
            marks.set(id);
        }
    }
    let mut creased = Vec::new();
    shared_edges(grid, patches, |pa, pb, along_u| {
        let ids = shape.edge_ids(pa, pb, along_u);
        if !ids.iter().flatten().any(|&id| marks.get(id)) {
            return;
        }
        let (a, b) = (pa.1 * m + pa.0, pb.1 * m + pb.0);
        if certified_g1(grid.nodes(), &ids) {
            return;
        }
        let angle = edge_angle(grid, a, b, along_u);
        if angle.is_nan() || angle > G1_TOLERANCE_DEG {
            creased.push((a, b, along_u, angle));
        }
    });
    if creased.is_empty() {
        if regulation == Regulation::G2 {
            return verify_g2(grid, patches, before, marks);
        }
        return Ok(());
    }
    // Which of them were G1 before the operation?
    let after: Vec<DVec3> = before.iter().map(|&(id, _)| grid.nodes()[id]).collect();
    {
        let nodes = grid.nodes_mut();
        for &(id, x) in before.iter().rev() {
            nodes[id] = x;
        }
    }
    creased.retain(|&(a, b, along_u, _)| edge_angle(grid, a, b, along_u) <= G1_TOLERANCE_DEG);
    {
        let nodes = grid.nodes_mut();
        for (&(id, _), &x) in before.iter().zip(&after) {
            nodes[id] = x;
        }
    }
    if let Some(&(patch, other, _, angle_deg)) = creased
        .iter()
        .max_by(|x, y| x.3.partial_cmp(&y.3).unwrap_or(std::cmp::Ordering::Greater))
    {
        return Err(SurfaceError::NotG1 {
            regulation,
            patch,
            other,
            angle_deg,
            tolerance_deg: G1_TOLERANCE_DEG,
        });
    }
    if regulation == Regulation::G2 {
        return verify_g2(grid, patches, before, marks);
    }
    Ok(())
}

/// `C(3, j) C(2, k) / C(5, j + k)`: the weight of `B³_j B²_k = w B⁵_(j+k)` (degree elevation
/// of a product of Bernstein polynomials).
const PRODUCT_WEIGHTS: [[f64; 3]; 4] = [
    [1.0, 2.0 / 5.0, 1.0 / 10.0],
    [3.0 / 5.0, 6.0 / 10.0, 3.0 / 10.0],
    [3.0 / 10.0, 6.0 / 10.0, 3.0 / 5.0],
    [1.0 / 10.0, 2.0 / 5.0, 1.0],
];

/// `C(2, j) C(2, k) / C(4, j + k)`: the weight of `B²_j B²_k = w B⁴_(j+k)`.
const QUADRATIC_WEIGHTS: [[f64; 3]; 3] = [
    [1.0, 1.0 / 2.0, 1.0 / 6.0],
    [1.0 / 2.0, 2.0 / 3.0, 1.0 / 2.0],
    [1.0 / 6.0, 1.0 / 2.0, 1.0],
];

/// Whether the edge between patches `a` and `b` (`b` after `a` along u when `along_u`, else
/// along v) is **proved** G1 within [`G1_TOLERANCE_DEG`] at every point of the edge, from its
/// 12 control points alone (no sampling), given by their ids `ids` (`a`'s row next to the
/// edge, the edge, `b`'s row next to it: [`crate::surface::grid::Shape::edge_ids`]); `false` means
/// "not proved" (the caller then measures the normals, [`edge_angle`]).
///
/// Name the rows crossing the edge `k = 0..3` along it: `X_k` on the edge (shared),
/// `d_k = X_k − P_k` with `P_k` the row of `a` next to the edge, `e_k = Q_k − X_k` with `Q_k`
/// the row of `b` next to it, and `a_k = X_(k+1) − X_k` (`k = 0..2`). On the edge, both
/// patches have the same derivative along it, `E(t) = 3 Σ_k B²_k(t) a_k`, and the
/// cross-boundary derivatives `D_a(t) = 3 Σ_k B³_k(t) d_k`, `D_b(t) = 3 Σ_k B³_k(t) e_k`
/// (both towards increasing parameter). Both normals are `D × E` (`E × D` on a v-edge) with
/// their own `D`. The certificate:
///
/// 1. **One ratio.** `λ = Σ e_k·d_k / Σ |d_k|²` must be positive; the residuals
///    `r_k = e_k − λ d_k` give `D_b = λ D_a + R`, `R(t) = 3 Σ B³_k r_k`, so
///    `|R(t)| ≤ 3 max_k |r_k|` (the basis sums to one). This is the condition the exact
///    regulation builds (every row crossing a grid line keeps the line's ratio:
///    `e_k = ρ d_k` exactly, so `r_k` is rounding).
/// 2. **A tangent plane all along.** `N(t) = D_a(t) × E(t) = 9 Σ_(i=0..5) B⁵_i(t) N_i` with
///    `N_i = Σ_(j+k=i) C(3,j) C(2,k) / C(5,i) · d_j × a_k` (the product of a cubic and a
///    quadratic in Bernstein form). With `ŵ` the unit mean of the `N_i`,
///    `|N(t)| ≥ ŵ·N(t) ≥ 9 min_i ŵ·N_i = 9 c` for every `t ∈ [0, 1]` (convex hull), so
///    `c > 0` proves that side has a tangent plane at every point of the edge.
/// 3. **The angle.** Only the parts of `D` across `E` set the normal (`n` is `D⊥` turned by
///    90° about `E`), so the angle `θ` between the normals is the angle between `D_a⊥` and
///    `D_b⊥ = λ D_a⊥ + R⊥`; a vector moved by at most `ε` of its length turns by at most
///    `asin ε`:
///
/// ```text
/// sin θ(t) ≤ |R⊥| / (λ |D_a⊥|) = |R × E| / (λ |D_a × E|) ≤ (3 max|r_k|)(3 max|a_k|) / (9 λ c)
///          = max|r_k| max|a_k| / (λ c)
/// ```
///
/// The edge is certified when that bound is at most `½ · G1_TOLERANCE_DEG` in radians
/// (`x / 2 < sin x`, so `θ` stays below the tolerance), after allowing for the rounding of
/// the computation itself: each `|r_k|` is raised by `10⁻¹⁵ (|e_k| + λ |d_k|)` and `c` lowered
/// by `10⁻¹³ max|d_k| max|a_k|` (a few units in the last place of each difference, product
/// and sum; `|N_i| ≤ max|d| max|a|` since the weights of each `N_i` sum to one).
///
/// **A row collapsed to a point** (a meridian edge at a pole: `d_0 = e_0 = 0` exactly, so
/// `N_0 = 0` and step 2 fails as it stands): then `D_a`, `D_b` and `R` all carry a factor `t`,
/// since `B³_j(t) = t · (3/j) B²_(j−1)(t)`, so `D_a = t D̃_a` with
/// `D̃_a = 3 Σ_(j=0..2) B²_j (3/(j+1)) d_(j+1)`, and likewise `R̃` with `(3/(j+1)) r_(j+1)`
/// (at the end row: `B³_j = (1 − t) (3/(3−j)) B²_j`, the factor `1 − t`). The factor cancels
/// from the bound, which is taken with the quadratics `D̃_a`, `R̃` and
/// `Ñ = D̃_a × E = 9 Σ_(i=0..4) B⁴_i Ñ_i`, `Ñ_i = Σ_(j+k=i) C(2,j) C(2,k) / C(4,i) · d̃_j × a_k`:
/// it holds for every `t` in `(0, 1]`, and at the pole for the limits of both normals along
/// the edge (which [`Patch::normal`] returns there).
///
/// Edges where a side has no tangent plane somewhere, or where the ratio varies along the
/// edge (the paper's construction), or that simply crease, are not certified; then [`verify`]
/// measures them as before, so the certificate can only accept what is provably G1 along the
/// whole edge — more than the three sampled points.
fn certified_g1(nodes: &[DVec3], ids: &[[usize; 4]; 3]) -> bool {
    let mut x = [DVec3::ZERO; 4];
    let mut d = [DVec3::ZERO; 4];
    let mut e = [DVec3::ZERO; 4];
    let (mut de, mut dd) = (0.0, 0.0);
    for k in 0..4 {
        x[k] = nodes[ids[1][k]];
        d[k] = x[k] - nodes[ids[0][k]];
        e[k] = nodes[ids[2][k]] - x[k];
        de += e[k].dot(d[k]);
        dd += d[k].length_squared();
    }
    let lambda = de / dd;
    if !(lambda > 0.0 && lambda.is_finite()) {
        return false;
    }
    // Per row: the residual's length, raised by the rounding of its computation.
    let r: [f64; 4] = std::array::from_fn(|k| {
        (e[k] - d[k] * lambda).length() + 1e-15 * (e[k].length() + lambda * d[k].length())
    });
    let along: [DVec3; 3] = std::array::from_fn(|k| x[k + 1] - x[k]);
    // A row collapsed to a point (a pole: both differences exactly zero) takes out a factor
    // `t` (`1 − t` at the end) of `D_a`, `D_b` and `R`: the quadratics left
    // (`B³_j = t · 3/j · B²_(j−1)`, `B³_j = (1 − t) · 3/(3−j) · B²_j`) take their place.
    let collapsed = |k: usize| d[k] == DVec3::ZERO && e[k] == DVec3::ZERO;
    match (collapsed(0), collapsed(3)) {
        (false, false) => bound_holds(&d, &r, &along, &PRODUCT_WEIGHTS, lambda),
        (true, false) => {
            let s = |j: usize| 3.0 / (j + 1) as f64;
            let dt: [DVec3; 3] = std::array::from_fn(|j| d[j + 1] * s(j));
            let rt: [f64; 3] = std::array::from_fn(|j| r[j + 1] * s(j));
            bound_holds(&dt, &rt, &along, &QUADRATIC_WEIGHTS, lambda)
        }
        (false, true) => {
            let s = |j: usize| 3.0 / (3 - j) as f64;
            let dt: [DVec3; 3] = std::array::from_fn(|j| d[j] * s(j));
            let rt: [f64; 3] = std::array::from_fn(|j| r[j] * s(j));
            bound_holds(&dt, &rt, &along, &QUADRATIC_WEIGHTS, lambda)
        }
        (true, true) => false,
    }
}

/// Steps 2 and 3 of `certified_g1` for a cross derivative with the `L` control vectors
/// `d` (degree `L − 1`), residual bounds `r` and ratio `λ`, along an edge with the
/// differences `along`: `N_i = Σ_(j+k=i) weights[j][k] d_j × a_k`, `c = min ŵ·N_i` (less the
/// rounding allowance), and `max r · max |a| ≤ ½ tol · λ c`.
#[inline(always)]
fn bound_holds<const L: usize>(
    d: &[DVec3; L],
    r: &[f64; L],
    along: &[DVec3; 3],
    weights: &[[f64; 3]; L],
    lambda: f64,
) -> bool {
    let r_max = r.iter().fold(0.0f64, |acc, &x| acc.max(x));
    let d_max = d.iter().fold(0.0f64, |acc, x| acc.max(x.length()));
    let a_max = along.iter().fold(0.0f64, |acc, v| acc.max(v.length()));
    let mut n = [DVec3::ZERO; 6];
    for (j, dj) in d.iter().enumerate() {
        for (k, ak) in along.iter().enumerate() {
            n[j + k] += dj.cross(*ak) * weights[j][k];
        }
    }
    let n = &n[..L + 2];
    let Some(w) = n.iter().copied().sum::<DVec3>().try_normalize() else {
        return false;
    };
    let c = n.iter().map(|ni| w.dot(*ni)).fold(f64::INFINITY, f64::min) - 1e-13 * d_max * a_max;
    // NaN anywhere fails one of these comparisons.
    c > 0.0 && r_max * a_max <= 0.5 * G1_TOLERANCE_DEG.to_radians() * lambda * c
}

/// The largest angle (degrees) between the normals of the two sides of the edge between
/// patches `a` and `b` (`b` after `a` along u when `along_u`, else along v), at
/// `VERIFY_SAMPLES` points; NaN when a normal is not finite.
///
/// The normals are [`Patch::normal`]'s: where both derivatives on the edge are clearly
/// regular (its first branch) they come from the two rows next to the edge
/// ([`edge_derivatives`]) and the patch's size taken once per edge; anywhere else (collapsed
/// rows, singular points) from [`Patch::normal`] itself.
fn edge_angle(grid: &Grid, a: usize, b: usize, along_u: bool) -> f64 {
    let (pa, pb) = (grid.patch_struct(a), grid.patch_struct(b));
    let (sa, sb) = (pa.size(), pb.size());
    let mut worst = 0.0f64;
    for i in 0..VERIFY_SAMPLES {
        let t = i as f64 / (VERIFY_SAMPLES - 1) as f64;
        let ((ua, va), (ub, vb)) = if along_u {
            ((1.0, t), (0.0, t))
        } else {
            ((t, 1.0), (t, 0.0))
        };
        let na = regular_normal(edge_derivatives(&pa, along_u, true, t), sa)
            .or_else(|| pa.normal(ua, va));
        let nb = regular_normal(edge_derivatives(&pb, along_u, false, t), sb)
            .or_else(|| pb.normal(ub, vb));
        if let (Some(na), Some(nb)) = (na, nb) {
            let angle = angle_deg(na, nb);
            // A NaN angle (a degenerate normal pair) stays the worst.
            if angle.is_nan() || angle > worst {
                worst = angle;
            }
        }
    }
    worst
}

/// `(S_u, S_v)` of a patch on its boundary `u = 0` / `u = 1` (`along_u`; `at_end` picks 1) or
/// `v = 0` / `v = 1`, at parameter `t` along that boundary: the derivative along the edge from
/// the boundary row, the one across it from the boundary row and the next,
/// `3 Σ_k B_k(t) (P_edge,k − P_next,k)` (signed towards increasing parameter).
fn edge_derivatives(p: &Patch, along_u: bool, at_end: bool, t: f64) -> (DVec3, DVec3) {
    let b = cubic_basis(t);
    let d = cubic_basis_derivative(t);
    let (edge, next, sign) = if at_end { (3, 2, 3.0) } else { (0, 1, -3.0) };
    let point = |r: usize, k: usize| {
        if along_u {
            p.points[4 * r + k]
        } else {
            p.points[4 * k + r]
        }
    };
    let mut along = DVec3::ZERO;
    let mut across = DVec3::ZERO;
    for k in 0..4 {
        let e = point(edge, k);
        along += e * d[k];
        across += (e - point(next, k)) * b[k];
    }
    across *= sign;
    if along_u {
        (across, along)
    } else {
        (along, across)
    }
}

/// The unit normal `unit(S_u × S_v)` when [`Patch::normal`] would take its regular branch
/// (both derivatives longer than `10⁻⁹ · size`, their cross product not degenerate); `None`
/// otherwise (the caller then asks [`Patch::normal`]).
fn regular_normal((du, dv): (DVec3, DVec3), size: f64) -> Option<DVec3> {
    if size.is_nan() || size <= 0.0 {
        return None;
    }
    let tiny = 1e-9 * size;
    let (lu, lv) = (du.length(), dv.length());
    if lu > tiny && lv > tiny {
        let n = du.cross(dv);
        if n.length() > 1e-10 * lu * lv {
            return n.try_normalize();
        }
    }
    None
}

/// Calls `f(a, b, along_u)` once for every shared edge of the listed patches (sorted), with
/// the patches as `(iu, iv)`.
pub(crate) fn shared_edges(
    grid: &Grid,
    patches: &[usize],
    mut f: impl FnMut((usize, usize), (usize, usize), bool),
) {
    let (m, n) = (grid.patches_u(), grid.patches_v());
    let topology = grid.topology();
    let listed = |p: usize| patches.binary_search(&p).is_ok();
    for &p in patches {
        let (iu, iv) = (p % m, p / m);
        // The edges on the right (u = 1) and above (v = 1) of every listed patch, and those on
        // the left and below when the neighbour there is not listed.
        if (iu + 1 < m || topology.closed_u()) && grid.u_line_shared(iu + 1) {
            let right = if iu + 1 == m { 0 } else { iu + 1 };
            f((iu, iv), (right, iv), true);
        }
        if (iv + 1 < n || topology.closed_v()) && grid.v_line_shared(iv + 1) {
            let above = if iv + 1 == n { 0 } else { iv + 1 };
            f((iu, iv), (iu, above), false);
        }
        if (iu > 0 || topology.closed_u()) && grid.u_line_shared(iu) {
            let left = if iu == 0 { m - 1 } else { iu - 1 };
            if !listed(iv * m + left) {
                f((left, iv), (iu, iv), true);
            }
        }
        if (iv > 0 || topology.closed_v()) && grid.v_line_shared(iv) {
            let below = if iv == 0 { n - 1 } else { iv - 1 };
            if !listed(below * m + iu) {
                f((iu, below), (iu, iv), false);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::grid::Shape;
    use crate::surface::{Op, Primitive, PrimitiveParams, Sculptor};

    /// [`certified_g1`] for the edge between patches `a` and `b` given by index.
    fn certified_g1_between(
        nodes: &[DVec3],
        shape: &Shape,
        m: usize,
        a: usize,
        b: usize,
        along_u: bool,
    ) -> bool {
        let ids = shape.edge_ids((a % m, a / m), (b % m, b / m), along_u);
        certified_g1(nodes, &ids)
    }

    #[test]
    fn edge_normals_are_the_patch_normals() {
        // The verification's edge normals against `Patch::normal` (the full frame), on
        // random patches, at both boundaries in both directions.
        let mut u = crate::seeded::unit(17u64);
        let mut r = move || u() - 0.5;
        for _ in 0..200 {
            let points: [DVec3; 16] = std::array::from_fn(|k| {
                DVec3::new((k / 4) as f64, (k % 4) as f64, 0.0) + DVec3::new(r(), r(), r())
            });
            let p = Patch::new(points);
            for along_u in [true, false] {
                for at_end in [true, false] {
                    for t in [0.0, 0.3, 0.5, 1.0] {
                        let side = if at_end { 1.0 } else { 0.0 };
                        let (u, v) = if along_u { (side, t) } else { (t, side) };
                        let fast =
                            regular_normal(edge_derivatives(&p, along_u, at_end, t), p.size());
                        let f = p.frame(u, v);
                        assert!(
                            (edge_derivatives(&p, along_u, at_end, t).0 - f.du).length() < 1e-12
                        );
                        assert!(
                            (edge_derivatives(&p, along_u, at_end, t).1 - f.dv).length() < 1e-12
                        );
                        if let (Some(a), Some(b)) = (fast, p.normal(u, v)) {
                            assert!((a - b).length() < 1e-12);
                        }
                    }
                }
            }
        }
    }

    /// A fixed-seed generator of numbers in `[0, 1)`.
    fn lcg(seed: u64) -> impl FnMut() -> f64 {
        let mut u = crate::seeded::unit(seed);
        move || u()
    }

    /// The largest angle (degrees) between the two sides' normals ([`Patch::normal`]) at 65
    /// points along an edge; NaN when a normal pair gives none; points where a side has no
    /// normal are skipped (as in [`crate::surface::continuity`]).
    fn dense_angle(grid: &Grid, a: usize, b: usize, along_u: bool) -> f64 {
        let (pa, pb) = (grid.patch_struct(a), grid.patch_struct(b));
        let mut worst = 0.0f64;
        for i in 0..65 {
            let t = f64::from(i) / 64.0;
            let ((ua, va), (ub, vb)) = if along_u {
                ((1.0, t), (0.0, t))
            } else {
                ((t, 1.0), (t, 0.0))
            };
            if let (Some(na), Some(nb)) = (pa.normal(ua, va), pb.normal(ub, vb)) {
                let angle = angle_deg(na, nb);
                if angle.is_nan() || angle > worst {
                    worst = angle;
                }
            }
        }
        worst
    }

    /// Whether a side of the edge has a collapsed (pole) row.
    fn at_pole(grid: &Grid, a: usize, b: usize) -> bool {
        let n = grid.patches_v();
        let t = grid.topology();
        [a, b].iter().any(|&p| {
            let iv = p / grid.patches_u();
            (iv == 0 && t.pole_at_start()) || (iv + 1 == n && t.pole_at_end())
        })
    }

    /// Random pushes on every primitive with every method: wherever the certificate holds,
    /// the normals measured densely along the edge (65 points, both sides) agree within the
    /// tolerance, and so do the three sampled points of `verify`; wherever they differ beyond
    /// it, the certificate does not hold. After the exact regulation (group by group or
    /// coupled) every edge is certified, the meridians at the poles included.
    #[test]
    fn the_certificate_agrees_with_the_sampled_normals() {
        let mut certified_total = 0;
        let mut creased_total = 0;
        let mut pole_edges = 0;
        for (pi, primitive) in Primitive::ALL.into_iter().enumerate() {
            for (mi, method) in (0..5).enumerate() {
                let mut r = lcg(1000 + 37 * pi as u64 + mi as u64);
                let mut grid = primitive
                    .build(&PrimitiveParams::default())
                    .expect("primitive");
                let (regulation, mut sculptor) = match method {
                    4 => (Regulation::Exact, Sculptor::with_group_by_group_exact()),
                    k => (Regulation::ALL[k], Sculptor::new()),
                };
                for _ in 0..6 {
                    let (m, n) = (grid.patches_u(), grid.patches_v());
                    let iu = ((r() * m as f64) as usize).min(m - 1);
                    let iv = ((r() * n as f64) as usize).min(n - 1);
                    let (u, v) = (0.1 + 0.8 * r(), 0.1 + 0.8 * r());
                    let at = grid.eval(iu, iv, u, v);
                    let Some(normal) = grid.normal(iu, iv, u, v) else {
                        continue;
                    };
                    let depth = (r() - 0.4) * 0.6;
                    let radius = 0.5 + r();
                    let op = Op::Push {
                        at,
                        dir: -normal,
                        depth,
                        radius,
                    };
                    // A refused push (exact, at a folding pole) leaves the grid as it was.
                    let _ = sculptor.apply(&mut grid, &op, regulation);
                }
                let all: Vec<usize> = (0..grid.patch_count()).collect();
                let shape = grid.shape();
                let m = grid.patches_u();
                shared_edges(&grid, &all, |a, b, along_u| {
                    let (a, b) = (a.1 * m + a.0, b.1 * m + b.0);
                    let certified = certified_g1_between(grid.nodes(), &shape, m, a, b, along_u);
                    let dense = dense_angle(&grid, a, b, along_u);
                    let sampled = edge_angle(&grid, a, b, along_u);
                    let what = format!("{primitive} {method}: edge {a}-{b} {along_u}");
                    if certified {
                        certified_total += 1;
                        assert!(dense <= G1_TOLERANCE_DEG, "{what}: dense {dense}");
                        assert!(sampled <= G1_TOLERANCE_DEG, "{what}: sampled {sampled}");
                    }
                    if dense.is_nan() || dense > G1_TOLERANCE_DEG {
                        creased_total += 1;
                        assert!(!certified, "{what}");
                    }
                    if regulation == Regulation::Exact {
                        assert!(certified, "{what}: dense {dense}");
                        if at_pole(&grid, a, b) && along_u {
                            pole_edges += 1;
                        }
                    }
                });
            }
        }
        // Both kinds were met.
        assert!(certified_total > 1000, "{certified_total}");
        assert!(creased_total > 100, "{creased_total}");
        // Meridian edges at a pole (a collapsed row) were met and certified.
        assert!(pole_edges > 50, "{pole_edges}");
    }

    /// An exactly regulated grid whose one node is then moved off by a tiny amount: the crease
    /// (above the tolerance, far below a visible angle) is not certified and `verify` refuses
    /// it; a change well inside the tolerance is accepted.
    /// The verification of every shared edge of the patches, as before edges were picked by
    /// their changed control points: `true` when it accepts.
    fn every_edge_accepts(grid: &mut Grid, patches: &[usize], before: &[(usize, DVec3)]) -> bool {
        let (m, shape) = (grid.patches_u(), grid.shape());
        let mut creased = Vec::new();
        shared_edges(grid, patches, |a, b, along_u| {
            let (a, b) = (a.1 * m + a.0, b.1 * m + b.0);
            if !certified_g1_between(grid.nodes(), &shape, m, a, b, along_u) {
                let angle = edge_angle(grid, a, b, along_u);
                if angle.is_nan() || angle > G1_TOLERANCE_DEG {
                    creased.push((a, b, along_u));
                }
            }
        });
        let after: Vec<DVec3> = before.iter().map(|&(id, _)| grid.nodes()[id]).collect();
        for &(id, x) in before.iter().rev() {
            grid.nodes_mut()[id] = x;
        }
        let fault = creased
            .iter()
            .any(|&(a, b, along_u)| edge_angle(grid, a, b, along_u) <= G1_TOLERANCE_DEG);
        for (&(id, _), &x) in before.iter().zip(&after) {
            grid.nodes_mut()[id] = x;
        }
        !fault
    }

    #[test]
    fn only_edges_with_a_changed_point_are_examined_and_no_result_changes() {
        // Random control points of the touched patches moved (or listed but kept), on grids
        // with edges creased before (a g1 stroke) and G1 ones (exact): the verification of
        // the changed edges decides as the verification of every edge of the patches.
        let mut r = lcg(17);
        let (mut accepted, mut refused) = (0, 0);
        for primitive in [Primitive::Plane, Primitive::Sphere, Primitive::Torus] {
            let mut grid = primitive
                .build(&PrimitiveParams::default())
                .expect("primitive");
            let (iu, iv) = (1, grid.patches_v() / 2);
            let at = grid.eval(iu, iv, 0.4, 0.7);
            let dir = -grid.normal(iu, iv, 0.4, 0.7).expect("a normal");
            let mut sculptor = Sculptor::new();
            for (method, shift) in [(Regulation::G1, 0.0), (Regulation::Exact, 0.3)] {
                let push = Op::Push {
                    at: at + DVec3::splat(shift),
                    dir,
                    depth: 0.3,
                    radius: 1.2,
                };
                sculptor.apply(&mut grid, &push, method).expect("a push");
            }
            let push = Op::Push {
                at,
                dir,
                depth: -0.2,
                radius: 1.3,
            };
            let touched = sculptor
                .apply(&mut grid.clone(), &push, Regulation::Exact)
                .expect("an exact push");
            let m = grid.patches_u();
            let mut marks = Marks::default();
            for trial in 0..60 {
                let mut g = grid.clone();
                let mut before = Vec::new();
                for _ in 0..1 + trial % 3 {
                    let p = touched.patches[(r() * touched.patches.len() as f64) as usize];
                    let k = (r() * 16.0) as usize;
                    let id = g.patch_node_ids(p % m, p / m)[k];
                    before.push((id, g.nodes()[id]));
                    let size = [0.0, 1e-13, 1e-4][trial % 3];
                    let d = DVec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * size;
                    g.nodes_mut()[id] += d;
                }
                let want = every_edge_accepts(&mut g, &touched.patches, &before);
                let got = verify_marked(
                    &mut g,
                    &touched.patches,
                    Regulation::Exact,
                    &before,
                    &mut marks,
                );
                assert_eq!(got.is_ok(), want, "{primitive} {trial}: {got:?}");
                if want {
                    accepted += 1;
                } else {
                    refused += 1;
                }
            }
        }
        assert!(accepted > 20 && refused > 20, "{accepted} {refused}");
    }

    #[test]
    fn a_tiny_g1_break_is_still_refused() {
        // On the plane: patch (5, 4)'s point (1, 1), next to its corner (5, 4), inside the
        // dent; on the sphere: patch (1, 3)'s point (1, 2), on the ring around the north pole,
        // next to the meridian between patches 0 and 1.
        for (primitive, (iu, iv), (i, j)) in [
            (Primitive::Plane, (5, 4), (1, 1)),
            (Primitive::Sphere, (1, 3), (1, 2)),
        ] {
            let mut grid = primitive
                .build(&PrimitiveParams::default())
                .expect("primitive");
            let push = Op::Push {
                at: grid.eval(iu, iv, 0.3, 0.6),
                dir: -grid.normal(iu, iv, 0.3, 0.6).expect("a normal"),
                depth: 0.4,
                radius: 1.25,
            };
            let touched = Sculptor::new()
                .apply(&mut grid, &push, Regulation::Exact)
                .expect("an exact push");
            let m = grid.patches_u();
            let me = iv * m + iu;
            let left = iv * m + iu - 1;
            assert!(touched.patches.contains(&me));
            let id = grid.shape().local_id(iu, iv, i, j);
            let old = grid.nodes()[id];
            for (offset, refused) in [(1e-5, true), (1e-6, true), (1e-12, false)] {
                let what = format!("{primitive} {offset}");
                let mut g = grid.clone();
                g.nodes_mut()[id] = old + DVec3::new(0.3, -0.5, 1.0) * offset;
                let angle = dense_angle(&g, left, me, true);
                let certified = certified_g1_between(g.nodes(), &g.shape(), m, left, me, true);
                let got = verify(&mut g, &touched.patches, Regulation::Exact, &[(id, old)]);
                if refused {
                    assert!(angle > G1_TOLERANCE_DEG && angle < 1e-2, "{what}: {angle}");
                    assert!(!certified, "{what}");
                    assert!(
                        matches!(got, Err(SurfaceError::NotG1 { .. })),
                        "{what}: {got:?}"
                    );
                } else {
                    assert!(angle < G1_TOLERANCE_DEG, "{what}: {angle}");
                    got.expect("a change within the tolerance");
                }
            }
        }
    }

    fn sphere() -> Grid {
        Primitive::Sphere
            .build(&PrimitiveParams::default())
            .expect("the default sphere")
    }

    fn pole_pull(depth: f64, radius: f64) -> Op {
        Op::Push {
            at: DVec3::new(0.0, 0.0, 3.0),
            dir: -DVec3::Z,
            depth,
            radius,
        }
    }

    #[test]
    fn a_result_beyond_the_limit_is_refused_and_the_grid_kept() {
        for depth in [1e308, -1e307, 1e302, 2.0 * COORDINATE_LIMIT] {
            for reg in Regulation::ALL {
                let before = sphere();
                let mut grid = before.clone();
                let mut sculptor = Sculptor::new();
                let got = sculptor.apply(&mut grid, &pole_pull(depth, 0.5), reg);
                assert!(
                    matches!(got, Err(SurfaceError::OutOfRange { .. })),
                    "{depth}, {reg}: {got:?}"
                );
                assert_eq!(grid, before, "{depth}, {reg}");
                // The same sculptor goes on working on the kept grid.
                sculptor
                    .apply(&mut grid, &pole_pull(0.2, 1.0), reg)
                    .expect("a small push");
                let mut want = before.clone();
                Sculptor::new()
                    .apply(&mut want, &pole_pull(0.2, 1.0), reg)
                    .expect("a small push");
                assert_eq!(grid, want, "{depth}, {reg}");
            }
        }
        // Accumulation: repeated pulls stop at the limit instead of overflowing.
        let mut grid = sphere();
        let mut sculptor = Sculptor::new();
        let mut refused = false;
        for _ in 0..20 {
            let before = grid.clone();
            if sculptor
                .apply(&mut grid, &pole_pull(-2e49, 0.5), Regulation::None)
                .is_err()
            {
                assert_eq!(grid, before);
                refused = true;
            }
        }
        assert!(refused);
        assert!(
            grid.nodes()
                .iter()
                .all(|x| x.abs().max_element() <= COORDINATE_LIMIT)
        );
    }

    #[test]
    fn exact_regulation_that_cannot_keep_g1_is_refused() {
        let before = sphere();
        let mut grid = before.clone();
        let got = Sculptor::new().apply(&mut grid, &pole_pull(-30.0, 0.5), Regulation::Exact);
        match got {
            Err(SurfaceError::NotG1 { angle_deg, .. }) => {
                assert!(angle_deg > 60.0, "{angle_deg}");
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(grid, before);
        // At 10 sides the construction holds and the pull goes through, G1.
        Sculptor::new()
            .apply(&mut grid, &pole_pull(-10.0, 0.5), Regulation::Exact)
            .expect("a 10-side pull");
        assert!(crate::surface::continuity::report(&grid, 33).g1_max_deg < 1e-9);
        // The baselines promise no G1 and are not refused for it.
        let mut grid = before.clone();
        Sculptor::new()
            .apply(&mut grid, &pole_pull(-30.0, 0.5), Regulation::G1)
            .expect("a baseline is not checked for G1");
    }

    #[test]
    fn an_edge_creased_before_the_operation_is_not_its_fault() {
        // Sculpted with no regulation: creases everywhere the finger went.
        let mut grid = Primitive::Plane
            .build(&PrimitiveParams::default())
            .expect("plane");
        let push = |x: f64| Op::Push {
            at: DVec3::new(x, 0.3, 0.0),
            dir: -DVec3::Z,
            depth: 0.3,
            radius: 0.8,
        };
        Sculptor::new()
            .apply(&mut grid, &push(0.0), Regulation::None)
            .expect("unregulated push");
        assert!(crate::surface::continuity::report(&grid, 33).g1_max_deg > 1.0);
        // Exact regulation next to it is accepted.
        Sculptor::new()
            .apply(&mut grid, &push(1.5), Regulation::Exact)
            .expect("a push next to old creases");
    }

    #[test]
    fn a_net_beyond_the_limit_is_refused() {
        let g = sphere();
        let mut nodes = g.nodes().to_vec();
        nodes[3].x = 2.0 * COORDINATE_LIMIT;
        let got = Grid::from_net(g.topology(), g.patches_u(), g.patches_v(), nodes);
        assert!(
            matches!(got, Err(SurfaceError::OutOfRange { .. })),
            "{got:?}"
        );
    }
}
