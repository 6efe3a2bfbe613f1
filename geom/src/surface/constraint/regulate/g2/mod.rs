//! The `g2` regulation: **curvature-continuous across every regular seam**, on top of what
//! `exact` keeps (the grid lines' spacing ratios, the poles' tangent planes).
//!
//! ## The construction
//! After the exact projection ([`super::exact`]) every lattice row crossing a grid line keeps
//! the line's ratio `ρ`, so each row of control points along `u` (and each column along `v`)
//! is a C1 piecewise cubic whose segment widths have the ratios `ρ`. Such a row is
//! curvature-continuous at a seam when, besides, `D₂⁺ = ρ² D₂⁻ + 2α D₁⁻` for one number `α`
//! ([`line`]'s stencils: the two sides C2 after a quadratic reparametrisation, Farin's
//! β-constraints with `β₁ = ρ`, `β₂ = 2α`). If every row crossing a grid line meets it with
//! **the same** `α`, the two patches on either side are C2 after reparametrising the cross
//! direction by `s ↦ ρ s + α s²` along the whole seam, so every normal curvature agrees across
//! it: the seam is G2. With `α = 0` each row is the Bezier form of one C2 cubic spline with the
//! patch widths as knot spacing (the plane); the sphere's and torus's circle arcs have `α ≠ 0`.
//! `α` is measured per grid line from the net before the operation (least squares over its
//! rows), so it never drifts: every regulated state meets the conditions with the same `α`.
//!
//! The conditions are linear and the same along every row of one direction, so the admissible
//! nets of a rectangular window of patches are the tensor product of the two directions'
//! admissible rows, and the surface metric of `exact`, `Σ_p ∫|ΔS_p|²`, is the Kronecker product
//! of the two directions' metrics. The nearest admissible net is therefore one projection of
//! every `u` row followed by one of every `v` column ([`line::LineProjection`]): the window is
//! the rectangle of patches around what the exact step changed, widened by [`MARGIN`] patches
//! on each side (a C2 cubic bump needs four segments), whose outer nodes stay; a closed
//! direction the window would nearly span is taken whole (periodic). With the outer nodes
//! fixed, the result is admissible exactly when the net before the operation met the
//! conditions on the lines crossing the window. When one of those lines did not (a model made
//! with another regulation, the test tube's hemisphere-to-wall join), the window becomes the
//! whole grid and the surface is made G2 everywhere, `α` of such a line taken by least
//! squares: the first `g2` stroke on such a model moves the whole surface (by what its
//! curvature jumps need).
//!
//! ## Poles
//! The pole and its first ring stay as `exact` left them (the ring in the tangent plane); the
//! ring row is projected along `u` (an affine combination of ring points, so it stays in the
//! plane) and both are fixed for the `v` columns. Every regular seam is then G2, the meridian
//! seams of the pole's patch row included; at the pole itself the meridian curvatures are not
//! made to come from one quadratic form (what polar C2 constructions, e.g. Karčiauskas &
//! Peters' and Myles & Peters' bi-3 polar surfaces, get from special ring layouts the grid does
//! not have): the pole stays G1 with bounded curvature, its mismatch measured by
//! [`crate::surface::curvature::g2_report`].

mod line;

use std::collections::HashMap;

use glam::DVec3;

use crate::surface::grid::Grid;
use line::{LineProjection, Seam, Window};

/// Patches added on each side of what the exact step changed.
pub const MARGIN: usize = 2;

/// What the g2 step wants written.
#[derive(Debug, Clone, Default)]
pub(crate) struct G2Step {
    /// `(node id, new position)`: the window's free nodes whose projection differs from the grid.
    pub writes: Vec<(usize, DVec3)>,
    /// Every free node of the window (sorted), written or not.
    pub free: Vec<usize>,
    /// The window's patches (sorted); every patch when a line crossing the window was not
    /// G2 before the operation.
    pub patches: Vec<usize>,
}

/// The last projection of each direction and the window it was built for: a contact of the
/// hand projects the same window frame after frame, and building a projection (a dense solve
/// over the window's line) costs far more than applying it.
#[derive(Debug, Clone, Default)]
pub(crate) struct G2Cache {
    u: Option<(Window, LineProjection)>,
    v: Option<(Window, LineProjection)>,
}

/// The projection of `w`, from `slot` when it was built for the same window.
fn projection(
    slot: &mut Option<(Window, LineProjection)>,
    w: Window,
) -> Result<&LineProjection, line::LineFailure> {
    let entry = match slot.take() {
        Some(cached) if cached.0 == w => cached,
        _ => {
            let p = LineProjection::new(&w)?;
            (w, p)
        }
    };
    Ok(&slot.insert(entry).1)
}

/// Why the g2 step found nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct G2Singular {
    /// Patches in the window.
    pub patches: usize,
}

/// One grid direction, seen from the g2 step.
struct Axis {
    /// Patches along it.
    n: usize,
    closed: bool,
    /// Lattice nodes along it.
    lattice: usize,
    /// Pole at the start / end (only along v).
    poles: (bool, bool),
    /// Per grid line: shared by two patches.
    shared: Vec<bool>,
    /// Per grid line: the reference ratio.
    ratios: Vec<f64>,
}

/// Patches `[start, start + width)` along an axis (modulo `n` when closed), or the whole axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Span {
    start: usize,
    width: usize,
    whole: bool,
}

fn span(axis: &Axis, occupied: &[bool], margin: usize) -> Span {
    let n = axis.n;
    let whole = Span {
        start: 0,
        width: n,
        whole: true,
    };
    let Some(first) = occupied.iter().position(|&x| x) else {
        return whole;
    };
    if !axis.closed {
        let last = occupied.iter().rposition(|&x| x).unwrap_or(first);
        let start = first.saturating_sub(margin);
        let end = (last + 1 + margin).min(n);
        return Span {
            start,
            width: end - start,
            whole: start == 0 && end == n,
        };
    }
    // The widest cyclic gap; the span starts after it.
    let (mut best_end, mut best_len, mut run) = (first, 0, 0);
    for step in 1..=n {
        let i = (first + step) % n;
        if occupied[i] {
            if run > best_len {
                (best_end, best_len) = (i, run);
            }
            run = 0;
        } else {
            run += 1;
        }
    }
    let width = n - best_len + 2 * margin;
    if width + 2 > n {
        return whole;
    }
    Span {
        start: (best_end + n - margin % n) % n,
        width,
        whole: false,
    }
}

/// The window of an axis over `span`, and the lattice index of each of its positions.
fn window(axis: &Axis, span: Span, alphas: &[f64]) -> (Window, Vec<usize>) {
    let n = axis.n;
    if span.whole && axis.closed {
        let len = axis.lattice;
        return (
            Window {
                len,
                cyclic: true,
                free: vec![true; len],
                segments: (0..n).map(|s| 3 * s).collect(),
                seams: (0..n)
                    .filter(|&k| axis.shared[k])
                    .map(|k| Seam {
                        position: 3 * k,
                        rho: axis.ratios[k],
                        alpha: alphas[k],
                    })
                    .collect(),
            },
            (0..len).collect(),
        );
    }
    let (start, end) = (span.start as isize, (span.start + span.width) as isize);
    let mut lo = 3 * start - 2;
    let mut hi = 3 * end + 2;
    if !axis.closed {
        lo = lo.max(0);
        hi = hi.min(3 * n as isize);
    }
    let len = (hi - lo + 1) as usize;
    let la = axis.lattice as isize;
    let lattice: Vec<usize> = (lo..=hi).map(|l| l.rem_euclid(la) as usize).collect();
    let free = (lo..=hi)
        .map(|l| {
            let inside = l > 3 * start && l < 3 * end;
            let open_start = !axis.closed && start == 0 && l == 0;
            let open_end = !axis.closed && end == n as isize && l == 3 * n as isize;
            let pole = (axis.poles.0 && l <= 1) || (axis.poles.1 && l >= 3 * n as isize - 1);
            (inside || open_start || open_end) && !pole
        })
        .collect();
    let segments = (start..end).map(|s| (3 * s - lo) as usize).collect();
    let seams = (start..=end)
        .filter_map(|k| {
            let line = k.rem_euclid(axis.shared.len() as isize) as usize;
            (axis.shared[line] && 3 * k - 2 >= lo && 3 * k + 2 <= hi).then(|| Seam {
                position: (3 * k - lo) as usize,
                rho: axis.ratios[line],
                alpha: alphas[line],
            })
        })
        .collect();
    (
        Window {
            len,
            cyclic: false,
            free,
            segments,
            seams,
        },
        lattice,
    )
}

/// `α` of every grid line of one direction, by least squares over its rows in the net
/// `before`, and whether the line met its conditions there. `node(line_offset, row)` gives the
/// node id of lattice index `3k + offset` along the direction, `row` across it.
fn alphas(
    axis: &Axis,
    rows: usize,
    node: impl Fn(isize, usize) -> Option<usize>,
    before: &impl Fn(usize) -> DVec3,
    wanted: impl Fn(usize) -> bool,
) -> (Vec<f64>, Vec<bool>) {
    let lines = axis.shared.len();
    let mut alpha = vec![0.0; lines];
    let mut g2 = vec![true; lines];
    for k in 0..lines {
        if !axis.shared[k] || !wanted(k) {
            continue;
        }
        let rho = axis.ratios[k];
        let mut samples = Vec::with_capacity(rows);
        for b in 0..rows {
            let at = |o: isize| node(3 * k as isize + o, b).map(before);
            let (Some(m2), Some(m1), Some(x0), Some(p1), Some(p2)) =
                (at(-2), at(-1), at(0), at(1), at(2))
            else {
                continue;
            };
            let plus = p2 - 2.0 * p1 + x0;
            let minus = (x0 - 2.0 * m1 + m2) * (rho * rho);
            let d = x0 - m1;
            samples.push((plus - minus, d, plus.length() + minus.length()));
        }
        let (num, den) = samples.iter().fold((0.0, 0.0), |(a, b), (r, d, _)| {
            (a + r.dot(*d), b + d.dot(*d))
        });
        let a = if den > 0.0 { num / den } else { 0.0 };
        alpha[k] = a;
        g2[k] = samples.iter().all(|(r, d, scale)| {
            (*r - *d * a).length() <= 1e-9 * (scale + d.length() * (1.0 + a.abs()))
        });
    }
    (alpha, g2)
}

/// The g2 step on `grid` (after the exact step): the nearest net, in the window around the
/// patches `changed`, whose seams are all G2 (see the module docs). `before(id)` is node `id`
/// before the operation (where each line's `α` is measured), `base(id)` the net to project
/// (the grid as the exact step left it; a contact of the hand gives its exact net, which the
/// grid no longer holds where an earlier frame's g2 step wrote). Nothing is written: the
/// caller writes [`G2Step::writes`], which differ from the grid's present nodes.
pub(crate) fn regulate(
    grid: &Grid,
    before: &impl Fn(usize) -> DVec3,
    base: &impl Fn(usize) -> DVec3,
    changed: &[usize],
    cache: &mut G2Cache,
) -> Result<G2Step, G2Singular> {
    let (m, n) = (grid.patches_u(), grid.patches_v());
    let topology = grid.topology();
    let (la, lb) = grid.lattice_size();
    let axis_u = Axis {
        n: m,
        closed: topology.closed_u(),
        lattice: la,
        poles: (false, false),
        shared: (0..grid.vertices_u())
            .map(|k| grid.u_line_shared(k))
            .collect(),
        ratios: grid.ratios_u().to_vec(),
    };
    let axis_v = Axis {
        n,
        closed: topology.closed_v(),
        lattice: lb,
        poles: (topology.pole_at_start(), topology.pole_at_end()),
        shared: (0..grid.vertices_v())
            .map(|q| grid.v_line_shared(q))
            .collect(),
        ratios: grid.ratios_v().to_vec(),
    };
    let (mut occ_u, mut occ_v) = (vec![false; m], vec![false; n]);
    for &p in changed {
        occ_u[p % m] = true;
        occ_v[p / m] = true;
    }
    let (mut su, mut sv) = (span(&axis_u, &occ_u, MARGIN), span(&axis_v, &occ_v, MARGIN));
    // Whether grid line `k` of an axis crosses its span.
    let crosses = |axis: &Axis, s: Span, k: usize| {
        let lines = axis.shared.len();
        s.whole || (k + lines - s.start % lines) % lines <= s.width
    };
    let node_u = |a: isize, b: usize| grid.node_id(a, b as isize);
    let node_v = |b: isize, a: usize| grid.node_id(a as isize, b);
    let (mut alpha_u, g2_u) = alphas(&axis_u, lb, node_u, before, |k| crosses(&axis_u, su, k));
    let (mut alpha_v, g2_v) = alphas(&axis_v, la, node_v, before, |q| crosses(&axis_v, sv, q));
    let whole = g2_u.iter().chain(&g2_v).any(|ok| !ok);
    if whole {
        // The whole grid, every line's `α` measured.
        su = span(&axis_u, &[], 0);
        sv = span(&axis_v, &[], 0);
        alpha_u = alphas(&axis_u, lb, node_u, before, |_| true).0;
        alpha_v = alphas(&axis_v, la, node_v, before, |_| true).0;
    }
    let (wu, lat_u) = window(&axis_u, su, &alpha_u);
    let (wv, lat_v) = window(&axis_v, sv, &alpha_v);
    let window_patches = su.width * sv.width;
    let fail = |_| G2Singular {
        patches: window_patches,
    };
    let pu = projection(&mut cache.u, wu).map_err(fail)?;
    let pv = projection(&mut cache.v, wv).map_err(fail)?;
    let (ulen, vlen) = (lat_u.len(), lat_v.len());
    let nodes = grid.nodes();
    let id = |i: usize, j: usize| grid.node_id(lat_u[i] as isize, lat_v[j] as isize);
    // The window's nodes, row by row (v position j, u position i).
    let mut y: Vec<Vec<DVec3>> = (0..vlen)
        .map(|j| {
            (0..ulen)
                .map(|i| id(i, j).map_or(DVec3::ZERO, base))
                .collect()
        })
        .collect();
    let pole_row =
        |b: usize| (axis_v.poles.0 && b == 0) || (axis_v.poles.1 && b + 1 == lb && !axis_v.closed);
    let ring_row = |b: usize| (axis_v.poles.0 && b == 1) || (axis_v.poles.1 && b + 2 == lb);
    let v_free: Vec<bool> = (0..vlen)
        .map(|j| pv.free.binary_search(&j).is_ok())
        .collect();
    let u_rows: Vec<usize> = (0..vlen)
        .filter(|&j| (v_free[j] || ring_row(lat_v[j])) && !pole_row(lat_v[j]))
        .collect();
    let mut scratch = Vec::new();
    for &j in &u_rows {
        pu.apply(&mut y[j], &mut scratch);
    }
    let mut column = vec![DVec3::ZERO; vlen];
    for &i in &pu.free {
        for (j, c) in column.iter_mut().enumerate() {
            *c = y[j][i];
        }
        pv.apply(&mut column, &mut scratch);
        for (j, c) in column.iter().enumerate() {
            y[j][i] = *c;
        }
    }
    let mut writes: HashMap<usize, DVec3> = HashMap::new();
    let mut free = Vec::new();
    for &j in &u_rows {
        for &i in &pu.free {
            if let Some(node) = id(i, j) {
                free.push(node);
                if nodes[node] != y[j][i] {
                    writes.insert(node, y[j][i]);
                }
            }
        }
    }
    let mut writes: Vec<(usize, DVec3)> = writes.into_iter().collect();
    writes.sort_unstable_by_key(|w| w.0);
    free.sort_unstable();
    free.dedup();
    let mut patches = Vec::with_capacity(window_patches);
    for dv in 0..sv.width {
        for du in 0..su.width {
            patches.push(((sv.start + dv) % n) * m + (su.start + du) % m);
        }
    }
    patches.sort_unstable();
    patches.dedup();
    Ok(G2Step {
        writes,
        free,
        patches,
    })
}
