//! Refinement: more patches, the same surface (issue 13).
//!
//! ## Knot insertion by de Casteljau
//! Splitting a cubic `Q₀…Q₃` at `t` gives the two cubics of the same curve on `[0, t]` and
//! `[t, 1]` (de Casteljau). On a grid, *inserting a patch column* at the global parameter `T`
//! (`0 < T < M`, not an integer) splits patch column `c = ⌊T⌋` at `t = T − c`: every lattice
//! row of control points `b` has its four points `(3c + i, b)` replaced by seven. Because each
//! row of the shared lattice is split once, shared points stay shared (C0 by construction),
//! the closed seam stays closed (the last column's `Q₃` *is* column 0) and the surface is
//! unchanged up to rounding — the tensor-product patch is a curve in `u` of curves in `v`.
//! Rows (`v`) likewise, splitting lattice columns. Several parameters in one patch column split
//! it into pieces `[t₀ = 0, t₁], …, [t_k, t_{k+1} = 1]` one after the other.
//!
//! - **Poles** collapse a whole lattice row into one node: splitting columns leaves it the one
//!   node (the pole, exactly); splitting the row of patches next to it keeps the pole as the
//!   first point of every meridian and moves the first ring to `(1 − t)·O + t·R`, so the ring
//!   stays in its plane through the pole: the pole patches stay degenerate and their tangent
//!   plane is unchanged.
//! - **Uniform ×K** inserts `c + j/K`, `j = 1…K−1`, in every column and row: `M·K × N·K`.
//! - **Counts.** Inserting `p` parameters along `u` gives `M + p` columns, along `v` `N + q`
//!   rows. Closed directions need an even count (every meridian at a pole has an opposite
//!   one), so an odd number of insertions around a closed direction is refused (insert `T`
//!   and `T + M/2`). The grid limit [`MAX_PATCHES`] holds: a refinement past it is refused
//!   ([`RefineError::TooLarge`]). The topology never changes.
//!
//! ## Parameters before and after
//! With `s_c` the number of parameters inserted in column `c` and `t_{c,1} < … < t_{c,s_c}`
//! their local values, old global `T = c + s` (`t_{c,i} ≤ s ≤ t_{c,i+1}`) becomes
//!
//! ```text
//! T' = c + Σ_{c' < c} s_{c'} + i + (s − t_{c,i}) / (t_{c,i+1} − t_{c,i})
//! ```
//!
//! ([`Refinement::map_u`], [`Refinement::unmap_u`]; `v` alike): the old point `S(T)` is the new
//! point `S'(T')`. Uniform ×K is simply `T' = K·T`.
//!
//! ## Spacing ratios
//! The exact regulation keeps every three-point row across a grid line at the line's reference
//! ratio `ρ = |P₊ − P₀| / |P₀ − P₋|` ([`crate::surface::regulate::exact`]). The piece of a cubic on
//! `[a, b]` has first leg `(b − a)/3 · C′(a)` and last leg `(b − a)/3 · C′(b)`, so with
//! `h_i = t_{i+1} − t_i` the widths of a column's pieces:
//!
//! ```text
//! new line inside a column, between pieces i−1 and i:   ρ' = h_i / h_{i−1}
//! existing line between columns L (left) and R (right): ρ' = ρ · h_first(R) / h_last(L)
//! ```
//!
//! (`h = 1` for a column that is not split; one split at `t`: `(1 − t)/t` on the new line,
//! `ρ·t` on the line to its left, `ρ/(1 − t)` on the line to its right). Every row's actual
//! ratio is scaled by exactly these factors, so a grid that satisfied its constraints before
//! satisfies the new ones after: regulating it right away moves nothing, and sculpting it keeps
//! exact G1. Open boundaries and pole rows keep ratio 1 (not shared).
//!
//! ## Refined lines
//! The refined grid marks the lines inserted as refined and keeps the marks of the old lines
//! ([`crate::surface::Grid::refined_u`]), so the primitive's own lines stay known however often
//! it is refined.
//!
//! ## Refinement where the finger needs it
//! [`for_finger`]: with `r_f` the finger radius, the target size is `h = r_f / 2`. A patch is
//! *reached* when its control-point box may come within `r_f` of the finger
//! ([`Finger::may_touch`], the test a stroke uses to pick its patches). A patch's size along
//! `u` is the longest of its four `u` rows' control-polygon lengths `max_j Σ_i |P_{i+1,j} −
//! P_{i,j}|`, which bounds the arc length of every `u` iso-curve of the patch (and `v` alike).
//! A reached patch is fine enough while its size is at most `σ·h` ([`FINGER_SLACK`]
//! `σ = 3/2`, so at most `3 r_f / 4`); every patch column holding a reached patch of `u` size
//! `L > σ·h` is split uniformly into `⌈L/h⌉` pieces (rows alike), each then at most `h`; on a
//! closed direction the opposite column (`c + M/2`) is split the same way, so the count stays
//! even and meridians keep their opposites. This repeats on the refined grid (at most
//! [`FINGER_PASSES`] passes) until every reached patch is at most `σ·h` across both ways.
//!
//! Why the slack: a tensor-product grid splits whole rows and columns across the model, so
//! every split is paid for far from the finger. Without it a column split for one finger
//! (pieces just under `r_f/2`) is split again into halves by the next finger only a little
//! smaller, and a session of strokes of mixed radii ends in bands of ever thinner patches.
//! With it, a column is split only when its patches are clearly coarser than the finger
//! needs — the bumps of radius `r_f` still span at least `2 r_f / (3 r_f/4) ≈ 2.7` patches
//! across and are represented as exactly as before to the eye (the regulation keeps G1 on any
//! grid). Measured on a scripted face-mask session on the 10 × 10 plane (20 operations of
//! radii 0.25 – 1.5, `sculpt --auto-refine`, as in `tests/it/export_size.rs`): 77 × 70 =
//! 5 390 patches without the slack, 59 × 57 = 3 363 with it. When a pass would pass [`MAX_PATCHES`], its pieces are scaled down
//! until it fits and the refinement stops there ([`FingerRefinement::limited`]).
//!
//! Limits: a stroke's reach is known before it starts only for the operations given (a
//! `Push` or the whole `Drag` path); a tensor-product grid refines whole rows and columns, so
//! patches far from the finger along them are split too (without any change of shape).

use glam::DVec3;

use crate::surface::SurfaceError;
use crate::surface::grid::Grid;
use crate::surface::limits::MAX_PATCHES;
use crate::surface::shape_fn::{Finger, Op};
use crate::surface::topology::Topology;

/// Smallest distance between an inserted parameter and a grid line or another inserted
/// parameter (in patch widths): closer pieces would have a spacing ratio near 0 or ∞.
pub const MIN_PIECE: f64 = 1e-6;

/// Most refinement passes [`for_finger`] makes before it stops.
pub const FINGER_PASSES: usize = 6;

/// How much coarser than the target `h = r_f / 2` a reached patch may be before
/// [`for_finger`] splits its column or row (the module docs' `σ`): patches up to `3 r_f / 4`
/// across are kept.
pub const FINGER_SLACK: f64 = 1.5;

/// Why a refinement is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RefineError {
    /// The refined grid would have more than [`MAX_PATCHES`] patches.
    #[error(
        "refining the {from_u} x {from_v} grid to {to_u} x {to_v} would pass the grid limit of {} patches; refused",
        MAX_PATCHES
    )]
    TooLarge {
        /// Patches along u before.
        from_u: usize,
        /// Patches along v before.
        from_v: usize,
        /// Patches along u the refinement asks for.
        to_u: usize,
        /// Patches along v the refinement asks for.
        to_v: usize,
    },
    /// A parameter that is not a finite number inside `(0, count)`.
    #[error(
        "{direction} parameter {} is outside (0, {count}): give a global grid parameter inside the grid",
        crate::num::Compact(*.value)
    )]
    OutOfRange {
        /// `"u"` or `"v"`.
        direction: &'static str,
        /// The value given.
        value: f64,
        /// The patch count along that direction.
        count: usize,
    },
    /// A parameter on an existing grid line (an integer, within [`MIN_PIECE`]).
    #[error(
        "{direction} parameter {} is on an existing grid line (an integer): nothing to split there",
        crate::num::Compact(*.value)
    )]
    OnGridLine {
        /// `"u"` or `"v"`.
        direction: &'static str,
        /// The value given.
        value: f64,
    },
    /// Two parameters equal or closer than [`MIN_PIECE`].
    #[error(
        "{direction} parameters {} and {} are closer than {MIN_PIECE:e}: give each split once",
        crate::num::Compact(*.a),
        crate::num::Compact(*.b)
    )]
    TooClose {
        /// `"u"` or `"v"`.
        direction: &'static str,
        /// One parameter.
        a: f64,
        /// The other.
        b: f64,
    },
    /// An odd number of insertions around a closed direction.
    #[error(
        "{topology} needs an even number of patches around its closed {direction} direction: \
         insert an even number of {direction} parameters (e.g. T and T + {half}), not {inserted}"
    )]
    OddClosed {
        /// The grid's topology.
        topology: Topology,
        /// `"u"` or `"v"`.
        direction: &'static str,
        /// How many parameters were given.
        inserted: usize,
        /// Half the patch count around that direction.
        half: usize,
    },
    /// A uniform factor below 1.
    #[error("the uniform factor must be at least 1, got {0}")]
    Factor(usize),
    /// The refinement was made for a grid of other counts or topology.
    #[error("the refinement was made for a {0} x {1} grid, not this one")]
    Mismatch(usize, usize),
    /// The finger operation is invalid, or the grid could not be rebuilt.
    #[error("{0}")]
    Surface(#[from] SurfaceError),
}

/// Where to split a grid: per patch column (row), the sorted local parameters in `(0, 1)`.
/// Made for one grid's counts and topology (see the module docs for the parameter mapping).
#[derive(Debug, Clone, PartialEq)]
pub struct Refinement {
    topology: Topology,
    m: usize,
    n: usize,
    u: Vec<Vec<f64>>,
    v: Vec<Vec<f64>>,
}

impl Refinement {
    /// The refinement that changes nothing.
    #[must_use]
    pub fn none(grid: &Grid) -> Self {
        Self {
            topology: grid.topology(),
            m: grid.patches_u(),
            n: grid.patches_v(),
            u: vec![Vec::new(); grid.patches_u()],
            v: vec![Vec::new(); grid.patches_v()],
        }
    }

    /// Inserts patch columns at the global parameters `u` (each in `(0, M)`, not an integer:
    /// column `⌊T⌋` is split at `T − ⌊T⌋`) and patch rows at `v` (in `(0, N)`), in any order.
    ///
    /// # Errors
    /// [`RefineError::OutOfRange`], [`RefineError::OnGridLine`], [`RefineError::TooClose`],
    /// [`RefineError::OddClosed`], [`RefineError::TooLarge`].
    pub fn new(grid: &Grid, u: &[f64], v: &[f64]) -> Result<Self, RefineError> {
        let mut r = Self::none(grid);
        r.u = per_segment("u", u, r.m)?;
        r.v = per_segment("v", v, r.n)?;
        for (direction, closed, given, count) in [
            ("u", r.topology.closed_u(), u.len(), r.m),
            ("v", r.topology.closed_v(), v.len(), r.n),
        ] {
            if closed && given % 2 == 1 {
                return Err(RefineError::OddClosed {
                    topology: r.topology,
                    direction,
                    inserted: given,
                    half: count / 2,
                });
            }
        }
        r.check_limit()?;
        Ok(r)
    }

    /// Every patch into `k × k` (`k = 1`: nothing).
    ///
    /// # Errors
    /// [`RefineError::Factor`] for `k = 0`, [`RefineError::TooLarge`].
    pub fn uniform(grid: &Grid, k: usize) -> Result<Self, RefineError> {
        if k == 0 {
            return Err(RefineError::Factor(k));
        }
        let mut r = Self::none(grid);
        let (m, n) = (r.m, r.n);
        let to = (m.checked_mul(k), n.checked_mul(k));
        let (Some(to_u), Some(to_v)) = to else {
            return Err(RefineError::TooLarge {
                from_u: m,
                from_v: n,
                to_u: usize::MAX,
                to_v: usize::MAX,
            });
        };
        if to_u.checked_mul(to_v).is_none_or(|c| c > MAX_PATCHES) {
            return Err(RefineError::TooLarge {
                from_u: m,
                from_v: n,
                to_u,
                to_v,
            });
        }
        // Only now, with k known to fit the grid limit, the split parameters.
        let pieces: Vec<f64> = (1..k).map(|j| j as f64 / k as f64).collect();
        r.u = vec![pieces.clone(); m];
        r.v = vec![pieces; n];
        Ok(r)
    }

    /// True when nothing is inserted.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.u.iter().chain(&self.v).all(Vec::is_empty)
    }

    /// The patch counts `(M', N')` after refinement.
    #[must_use]
    pub fn counts(&self) -> (usize, usize) {
        (
            self.m + self.u.iter().map(Vec::len).sum::<usize>(),
            self.n + self.v.iter().map(Vec::len).sum::<usize>(),
        )
    }

    /// The inserted `u` parameters, global (`c + t`), increasing.
    #[must_use]
    pub fn inserted_u(&self) -> Vec<f64> {
        global(&self.u)
    }

    /// The inserted `v` parameters, global, increasing.
    #[must_use]
    pub fn inserted_v(&self) -> Vec<f64> {
        global(&self.v)
    }

    /// The new global `u` parameter of the old one `t ∈ [0, M]` (see the module docs).
    #[must_use]
    pub fn map_u(&self, t: f64) -> f64 {
        map(&self.u, t)
    }

    /// The new global `v` parameter of the old one `t ∈ [0, N]`.
    #[must_use]
    pub fn map_v(&self, t: f64) -> f64 {
        map(&self.v, t)
    }

    /// The old global `u` parameter of the new one `t ∈ [0, M']` (the inverse of
    /// [`Refinement::map_u`]).
    #[must_use]
    pub fn unmap_u(&self, t: f64) -> f64 {
        unmap(&self.u, t)
    }

    /// The old global `v` parameter of the new one `t ∈ [0, N']`.
    #[must_use]
    pub fn unmap_v(&self, t: f64) -> f64 {
        unmap(&self.v, t)
    }

    /// The refined grid: the same surface on more patches, the same topology, the spacing
    /// ratios carried over (see the module docs).
    ///
    /// # Errors
    /// [`RefineError::Mismatch`] for a grid of other counts or topology;
    /// [`RefineError::TooLarge`].
    pub fn apply(&self, grid: &Grid) -> Result<Grid, RefineError> {
        if grid.topology() != self.topology
            || grid.patches_u() != self.m
            || grid.patches_v() != self.n
        {
            return Err(RefineError::Mismatch(self.m, self.n));
        }
        self.check_limit()?;
        if self.is_empty() {
            return Ok(grid.clone());
        }
        let t = self.topology;
        let (la, lb) = grid.lattice_size();
        // The full lattice, `lat[b * la + a]`.
        let mut lat = Vec::with_capacity(la * lb);
        for b in 0..lb {
            for a in 0..la {
                let id = grid.node_id(a as isize, b as isize).unwrap_or(0);
                lat.push(grid.nodes()[id]);
            }
        }
        // Along u: every lattice row.
        let mut line = Vec::new();
        let mut rows: Vec<DVec3> = Vec::new();
        for b in 0..lb {
            split_line(&lat[b * la..(b + 1) * la], t.closed_u(), &self.u, &mut line);
            rows.extend_from_slice(&line);
        }
        let la2 = line.len();
        // Along v: every lattice column.
        let mut column = Vec::with_capacity(lb);
        let mut cols: Vec<Vec<DVec3>> = Vec::with_capacity(la2);
        for a in 0..la2 {
            column.clear();
            column.extend((0..lb).map(|b| rows[b * la2 + a]));
            split_line(&column, t.closed_v(), &self.v, &mut line);
            cols.push(line.clone());
        }
        let lb2 = cols.first().map_or(0, Vec::len);
        let (m2, n2) = self.counts();
        let mut nodes = Vec::with_capacity(Grid::net_len(t, m2, n2));
        let first = grid.nodes()[0];
        let last = grid.nodes()[grid.nodes().len() - 1];
        for b in 0..lb2 {
            if b == 0 && t.pole_at_start() {
                nodes.push(first);
            } else if b + 1 == lb2 && t.pole_at_end() {
                nodes.push(last);
            } else {
                nodes.extend(cols.iter().map(|c| c[b]));
            }
        }
        let mut out = Grid::from_net(t, m2, n2, nodes)?;
        let ru = new_ratios(grid.ratios_u(), &self.u, t.closed_u());
        let rv = new_ratios(grid.ratios_v(), &self.v, t.closed_v());
        out.set_ratios(&ru, &rv)?;
        let mu = new_marks(grid.refined_u(), &self.u, t.closed_u());
        let mv = new_marks(grid.refined_v(), &self.v, t.closed_v());
        out.set_refined(&mu, &mv)?;
        Ok(out)
    }

    fn check_limit(&self) -> Result<(), RefineError> {
        let (to_u, to_v) = self.counts();
        if to_u.checked_mul(to_v).is_none_or(|c| c > MAX_PATCHES) {
            return Err(RefineError::TooLarge {
                from_u: self.m,
                from_v: self.n,
                to_u,
                to_v,
            });
        }
        Ok(())
    }

    /// This refinement followed by `then` (made for the grid this one produces), as one
    /// refinement of the original grid: the union of their parameters.
    fn compose(&self, then: &Refinement) -> Self {
        let mut out = self.clone();
        for t in then.inserted_u() {
            insert_global(&mut out.u, self.unmap_u(t));
        }
        for t in then.inserted_v() {
            insert_global(&mut out.v, self.unmap_v(t));
        }
        out
    }
}

/// Refines a grid (see [`Refinement::apply`]).
///
/// # Errors
/// As [`Refinement::apply`].
pub fn refine(grid: &Grid, refinement: &Refinement) -> Result<Grid, RefineError> {
    refinement.apply(grid)
}

/// Every patch of a grid into `k × k`: an `M·k × N·k` grid of the same surface.
///
/// # Errors
/// [`RefineError::Factor`], [`RefineError::TooLarge`].
pub fn uniform(grid: &Grid, k: usize) -> Result<Grid, RefineError> {
    Refinement::uniform(grid, k)?.apply(grid)
}

/// What [`for_finger`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct FingerRefinement {
    /// The refinement of the grid given (empty when the patches are already small enough).
    pub refinement: Refinement,
    /// True when the grid limit stopped it short of the target size.
    pub limited: bool,
    /// The target patch size `r_f / 2` (side).
    pub target: f64,
}

/// The refinement that makes every patch the operation's finger reaches at most
/// [`FINGER_SLACK`]` · r_f / 2` across, splitting coarser ones into pieces of at most `r_f / 2`
/// (the rule of the module docs), never past [`MAX_PATCHES`].
///
/// Operations whose direction follows the surface (`"normal"`) get their finger on `grid`
/// ([`Op::finger_on`]); a move or a smooth reaches like a push of its radius at its point
/// along the inward normal there (as deep as the move is long; a tenth of the radius for a
/// smooth); a surface brush (inflate, flatten, pinch, crease) like a push or a groove along
/// the normals of its stroke, `max(|h|, R/10)` deep.
///
/// # Errors
/// [`RefineError::Surface`] with [`SurfaceError::BadOp`] for an invalid operation (or one whose
/// point has no surface near it).
pub fn for_finger(grid: &Grid, op: &Op) -> Result<FingerRefinement, RefineError> {
    op.validate()?;
    let reach = match op {
        Op::Move { at, to, radius } => Some((*at, (*to - *at).length(), *radius)),
        Op::Smooth { at, radius, .. } => Some((*at, 0.1 * radius, *radius)),
        _ => None,
    };
    let finger = match (reach, op) {
        (_, Op::Sculpt(b)) => {
            let depth = b.depth.abs().max(0.1 * b.radius);
            match b.path.as_slice() {
                [at] => Op::PushNormal {
                    at: *at,
                    depth,
                    radius: b.radius,
                },
                path => Op::Groove {
                    path: path.to_vec(),
                    dirs: crate::surface::shape_fn::Dirs::Normal,
                    depth,
                    radius: b.radius,
                },
            }
            .finger_on(grid)?
        }
        (Some((at, depth, radius)), _) => Op::PushNormal {
            at,
            depth: depth.max(1e-3 * radius),
            radius,
        }
        .finger_on(grid)?,
        (None, _) => op.finger_on(grid)?,
    };
    let target = finger.radius() / 2.0;
    let mut total = Refinement::none(grid);
    let mut current = grid.clone();
    let mut limited = false;
    for _ in 0..FINGER_PASSES {
        let (pass, cut) = finger_pass(&current, &finger, target);
        limited |= cut;
        if pass.is_empty() {
            break;
        }
        total = total.compose(&pass);
        if cut {
            break;
        }
        current = pass.apply(&current)?;
    }
    Ok(FingerRefinement {
        refinement: total,
        limited,
        target,
    })
}

/// One pass of the finger rule on `grid`: the pieces each column and row needs, scaled down
/// to fit the grid limit (then `true`).
fn finger_pass(grid: &Grid, finger: &Finger, target: f64) -> (Refinement, bool) {
    let (m, n) = (grid.patches_u(), grid.patches_v());
    let depth = finger.reach_depth(&grid.bounds());
    let mut reached = Vec::new();
    grid.patches_where(|b| finger.may_touch(b, depth), &mut reached);
    // The pieces each column (row) needs; at most MAX_PATCHES (a count past it is refused
    // anyway).
    let mut ku = vec![1usize; m];
    let mut kv = vec![1usize; n];
    let need = |len: f64| -> usize {
        // Fine enough up to σ·h: no split (the NaN of a broken patch splits nothing either).
        if len.is_nan() || len <= FINGER_SLACK * target {
            return 1;
        }
        let k = (len / target).ceil();
        if k.is_finite() && k > 1.0 {
            (k.min(MAX_PATCHES as f64)) as usize
        } else {
            1
        }
    };
    for &p in &reached {
        let (iu, iv) = (p % m, p / m);
        let (lu, lv) = polygon_sizes(&grid.patch(iu, iv));
        ku[iu] = ku[iu].max(need(lu));
        kv[iv] = kv[iv].max(need(lv));
    }
    let t = grid.topology();
    symmetrise(&mut ku, t.closed_u());
    symmetrise(&mut kv, t.closed_v());
    let count = |ku: &[usize], kv: &[usize]| -> f64 {
        ku.iter().sum::<usize>() as f64 * kv.iter().sum::<usize>() as f64
    };
    let mut cut = false;
    if count(&ku, &kv) > MAX_PATCHES as f64 {
        cut = true;
        // The largest scale s of the extra pieces, k' = 1 + ⌊(k − 1)·s⌋, that fits.
        let scaled = |k: &[usize], s: f64| -> Vec<usize> {
            k.iter()
                .map(|&k| 1 + ((k - 1) as f64 * s).floor() as usize)
                .collect()
        };
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if count(&scaled(&ku, mid), &scaled(&kv, mid)) <= MAX_PATCHES as f64 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        ku = scaled(&ku, lo);
        kv = scaled(&kv, lo);
        // Scaling may break the pairing on a closed direction: keep the smaller of a pair.
        unsymmetrise(&mut ku, t.closed_u());
        unsymmetrise(&mut kv, t.closed_v());
    }
    let pieces = |k: usize| (1..k).map(|j| j as f64 / k as f64).collect::<Vec<f64>>();
    let mut r = Refinement::none(grid);
    r.u = ku.into_iter().map(pieces).collect();
    r.v = kv.into_iter().map(pieces).collect();
    (r, cut)
}

/// Around a closed direction, column `c` and `c + M/2` get the larger of their piece counts.
fn symmetrise(k: &mut [usize], closed: bool) {
    if !closed {
        return;
    }
    let half = k.len() / 2;
    for c in 0..half {
        let most = k[c].max(k[c + half]);
        k[c] = most;
        k[c + half] = most;
    }
}

/// Around a closed direction, column `c` and `c + M/2` get the smaller of their piece counts
/// (after a scaling that may have rounded them apart).
fn unsymmetrise(k: &mut [usize], closed: bool) {
    if !closed {
        return;
    }
    let half = k.len() / 2;
    for c in 0..half {
        let least = k[c].min(k[c + half]);
        k[c] = least;
        k[c + half] = least;
    }
}

/// The patch's size along `u` and `v`: the longest control-polygon row (column), which bounds
/// the arc length of every iso-curve that way.
#[must_use]
pub fn polygon_sizes(p: &[DVec3; 16]) -> (f64, f64) {
    let mut lu = 0.0f64;
    let mut lv = 0.0f64;
    for j in 0..4 {
        let mut su = 0.0;
        let mut sv = 0.0;
        for i in 0..3 {
            su += (p[4 * (i + 1) + j] - p[4 * i + j]).length();
            sv += (p[4 * j + i + 1] - p[4 * j + i]).length();
        }
        lu = lu.max(su);
        lv = lv.max(sv);
    }
    (lu, lv)
}

/// Global parameters → per-segment sorted local parameters, validated.
fn per_segment(
    direction: &'static str,
    params: &[f64],
    count: usize,
) -> Result<Vec<Vec<f64>>, RefineError> {
    let mut sorted = Vec::with_capacity(params.len());
    for &t in params {
        if !(t.is_finite() && t > 0.0 && t < count as f64) {
            return Err(RefineError::OutOfRange {
                direction,
                value: t,
                count,
            });
        }
        let s = t - t.floor();
        if !(MIN_PIECE..=1.0 - MIN_PIECE).contains(&s) {
            return Err(RefineError::OnGridLine {
                direction,
                value: t,
            });
        }
        sorted.push(t);
    }
    sorted.sort_by(f64::total_cmp);
    for w in sorted.windows(2) {
        if w[1] - w[0] < MIN_PIECE {
            return Err(RefineError::TooClose {
                direction,
                a: w[0],
                b: w[1],
            });
        }
    }
    let mut out = vec![Vec::new(); count];
    for t in sorted {
        let c = t.floor() as usize;
        out[c].push(t - c as f64);
    }
    Ok(out)
}

/// Inserts an old-grid global parameter into per-segment lists (kept sorted; a parameter at a
/// grid line or on one already there is dropped).
fn insert_global(segments: &mut [Vec<f64>], t: f64) {
    let count = segments.len();
    if !(t.is_finite() && t > 0.0 && t < count as f64) {
        return;
    }
    let c = (t.floor() as usize).min(count - 1);
    let s = t - c as f64;
    if !(MIN_PIECE * 1e-3..=1.0 - MIN_PIECE * 1e-3).contains(&s) {
        return;
    }
    let list = &mut segments[c];
    let at = list.partition_point(|&x| x < s);
    let near = |i: usize| {
        list.get(i)
            .is_some_and(|&x| (x - s).abs() < MIN_PIECE * 1e-3)
    };
    if near(at) || (at > 0 && near(at - 1)) {
        return;
    }
    list.insert(at, s);
}

fn global(segments: &[Vec<f64>]) -> Vec<f64> {
    segments
        .iter()
        .enumerate()
        .flat_map(|(c, ts)| ts.iter().map(move |t| c as f64 + t))
        .collect()
}

/// The breaks `0, t₁, …, t_k, 1` of a segment's piece `i`: `(start, width)`.
fn piece(ts: &[f64], i: usize) -> (f64, f64) {
    let a = if i == 0 { 0.0 } else { ts[i - 1] };
    let b = if i == ts.len() { 1.0 } else { ts[i] };
    (a, b - a)
}

fn map(segments: &[Vec<f64>], t: f64) -> f64 {
    let count = segments.len();
    let c = (t.floor().max(0.0) as usize).min(count - 1);
    let s = t - c as f64;
    let before: usize = c + segments[..c].iter().map(Vec::len).sum::<usize>();
    let ts = &segments[c];
    let i = ts.partition_point(|&x| x <= s);
    let (a, h) = piece(ts, i);
    before as f64 + i as f64 + (s - a) / h
}

fn unmap(segments: &[Vec<f64>], t: f64) -> f64 {
    let mut start = 0usize;
    let last = segments.len() - 1;
    for (c, ts) in segments.iter().enumerate() {
        let pieces = ts.len() + 1;
        if t < (start + pieces) as f64 || c == last {
            let i = ((t - start as f64).floor().max(0.0) as usize).min(pieces - 1);
            let local = t - (start + i) as f64;
            let (a, h) = piece(ts, i);
            return c as f64 + a + local * h;
        }
        start += pieces;
    }
    t
}

/// The spacing ratios after refinement (see the module docs): `old[k]` is grid line `k`'s.
fn new_ratios(old: &[f64], segments: &[Vec<f64>], closed: bool) -> Vec<f64> {
    let count = segments.len();
    let first = |c: usize| piece(&segments[c], 0).1;
    let last = |c: usize| piece(&segments[c], segments[c].len()).1;
    let mut out = Vec::with_capacity(old.len() + segments.iter().map(Vec::len).sum::<usize>());
    for c in 0..count {
        // Line c, between column c − 1 and column c.
        let left = if c > 0 {
            Some(c - 1)
        } else if closed {
            Some(count - 1)
        } else {
            None
        };
        out.push(match left {
            Some(l) => old[c] * first(c) / last(l),
            None => old[c],
        });
        for i in 1..=segments[c].len() {
            out.push(piece(&segments[c], i).1 / piece(&segments[c], i - 1).1);
        }
    }
    if !closed {
        out.push(old[count]);
    }
    out
}

/// The refined-line marks after splitting each segment `c` at `segments[c]`: line `c` keeps
/// its mark, the lines inserted inside segment `c` are marked (in the order of
/// [`new_ratios`]).
fn new_marks(old: &[bool], segments: &[Vec<f64>], closed: bool) -> Vec<bool> {
    let mut out = Vec::with_capacity(old.len() + segments.iter().map(Vec::len).sum::<usize>());
    for (c, inserted) in segments.iter().enumerate() {
        out.push(old.get(c).copied().unwrap_or(false));
        out.extend(std::iter::repeat_n(true, inserted.len()));
    }
    if !closed {
        out.push(old.get(segments.len()).copied().unwrap_or(false));
    }
    out
}

/// One lattice line (`3S` points closed, `3S + 1` open) with each segment `c` split at its
/// local parameters: written to `out`.
fn split_line(line: &[DVec3], closed: bool, segments: &[Vec<f64>], out: &mut Vec<DVec3>) {
    out.clear();
    let len = line.len();
    for (c, ts) in segments.iter().enumerate() {
        let q: [DVec3; 4] = std::array::from_fn(|i| line[(3 * c + i) % len]);
        let mut rest = q;
        let mut done = 0.0;
        for &t in ts {
            let local = (t - done) / (1.0 - done);
            let (left, right) = split(rest, local);
            out.extend_from_slice(&left[..3]);
            rest = right;
            done = t;
        }
        out.extend_from_slice(&rest[..3]);
    }
    if !closed {
        out.push(line[len - 1]);
    }
}

/// de Casteljau: the cubic `q` on `[0, t]` and on `[t, 1]`.
fn split(q: [DVec3; 4], t: f64) -> ([DVec3; 4], [DVec3; 4]) {
    let lerp = |a: DVec3, b: DVec3| a + (b - a) * t;
    let a1 = lerp(q[0], q[1]);
    let b1 = lerp(q[1], q[2]);
    let c1 = lerp(q[2], q[3]);
    let a2 = lerp(a1, b1);
    let b2 = lerp(b1, c1);
    let mid = lerp(a2, b2);
    ([q[0], a1, a2, mid], [mid, b2, c1, q[3]])
}

#[cfg(test)]
mod tests;
