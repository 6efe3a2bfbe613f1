//! Regulation: restoring tangent continuity after the per-patch Bernstein inverse
//! (P2 §4; docs/design.md §12).
//!
//! The inverse mapping moves every patch on its own; C0 holds (the net is shared) but the
//! rows of control points that cross a grid line are no longer collinear, so the surface
//! creases along patch edges. Regulation works on the connected control-point groups
//! ([`crate::surface::group`]) around the grid vertices an operation touched: groups are disjoint, and
//! every tangent-continuity condition between bicubic patches (a three-point row across a
//! grid line; the first ring around a pole) lies inside one group. The paper's methods work
//! one group at a time; the exact one solves the touched groups together (its metric couples
//! groups that share a patch) but moves nothing beyond their patches. So regulation is local,
//! and its cost follows the touched area.
//!
//! | method | what it does | G1 |
//! |---|---|---|
//! | [`Regulation::None`] | the Bernstein inverse alone | no |
//! | [`Regulation::C1`] | the paper's "former method" baseline: C1 groups, rows equally spaced ([`c1`]) | at vertices, and along edges of uniform spacing |
//! | [`Regulation::G1`] | the paper's method, §4.2 and §4.3 with the misprints corrected ([`g1`]) | at vertices; along an edge only where its two end ratios agree |
//! | [`Regulation::Exact`] (default) | projection onto per-grid-line spacing constraints, the touched groups together, nearest to the unregulated surface in `Σ ∫\|ΔS\|²` over their patches; poles onto a fitted tangent plane ([`exact`]) | everywhere, to rounding |
//! | [`Regulation::G2`] | `exact`, then every row and column of a window around what moved projected onto the curvature-continuous piecewise cubics with the grid's spacing ([`g2`]; the engine's commit runs that step) | everywhere, to rounding; and G2 across every regular seam |

// Groups are small fixed arrays indexed by lattice offsets `(s, t)`; the index form follows
// the formulas.
#![allow(clippy::needless_range_loop)]

pub mod c1;
pub mod exact;
pub mod g1;
pub mod g2;

use glam::DVec3;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use crate::surface::grid::Grid;
use crate::surface::group::{Group, Pole, PoleEnd};
use crate::surface::topology::wrap;

/// How control points are regulated after the inverse mapping.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Regulation {
    /// The Bernstein inverse alone: C0, no tangent continuity.
    None,
    /// The paper's baseline ("former method"): C1 between patches.
    C1,
    /// The paper's G1 method (§4.2, §4.3), misprints corrected.
    G1,
    /// Exact G1 on every shared edge and a true tangent plane at every pole, by the
    /// least-squares projection of [`exact`]; the default.
    #[default]
    Exact,
    /// [`Regulation::Exact`], and curvature continuity (G2) across every regular seam
    /// ([`g2`]).
    G2,
}

impl Regulation {
    /// Every method, in the order of the tables.
    pub const ALL: [Regulation; 5] = [
        Regulation::None,
        Regulation::C1,
        Regulation::G1,
        Regulation::Exact,
        Regulation::G2,
    ];

    /// The name used on the command line and in model files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Regulation::None => "none",
            Regulation::C1 => "c1",
            Regulation::G1 => "g1",
            Regulation::Exact => "exact",
            Regulation::G2 => "g2",
        }
    }

    /// Whether the method promises exact G1 (verified after every operation).
    #[must_use]
    pub fn promises_g1(self) -> bool {
        matches!(self, Regulation::Exact | Regulation::G2)
    }
}

impl std::fmt::Display for Regulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Regulation {
    type Err = crate::surface::error::UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s == "default" {
            // The and the panel's name for our own method.
            return Ok(Regulation::default());
        }
        Regulation::ALL
            .into_iter()
            .find(|r| r.name() == s)
            .ok_or_else(|| crate::surface::error::UnknownName {
                kind: "regulation",
                given: s.to_owned(),
                expected: "none, c1, g1, exact (= default), g2",
            })
    }
}

/// The points of a non-degenerate group, `p[s + 1][t + 1]` for offsets `(s, t)`; `None`
/// beyond an open boundary.
pub type GroupPoints = [[Option<DVec3>; 3]; 3];

/// The points of a pole group: the pole and its first ring (see [`Pole::ring`]).
#[derive(Debug, Clone, PartialEq)]
pub struct PolePoints {
    /// The pole `P_O`.
    pub pole: DVec3,
    /// The first ring, `ring[a]` for lattice column `a`.
    pub ring: Vec<DVec3>,
}

fn read_group(grid: &Grid, g: &Group) -> GroupPoints {
    g.nodes.map(|col| col.map(|id| id.map(|i| grid.nodes()[i])))
}

fn write_group(grid: &mut Grid, g: &Group, p: &GroupPoints) {
    let nodes = grid.nodes_mut();
    for s in 0..3 {
        for t in 0..3 {
            if let (Some(id), Some(x)) = (g.nodes[s][t], p[s][t]) {
                nodes[id] = x;
            }
        }
    }
}

fn read_pole(grid: &Grid, pole: &Pole) -> PolePoints {
    PolePoints {
        pole: grid.nodes()[pole.node],
        ring: pole.ring.iter().map(|&i| grid.nodes()[i]).collect(),
    }
}

fn write_pole(grid: &mut Grid, pole: &Pole, p: &PolePoints) {
    let nodes = grid.nodes_mut();
    for (&id, &x) in pole.ring.iter().zip(&p.ring) {
        nodes[id] = x;
    }
}

/// The [`exact::Projection`]s computed so far, by spacing ratios and slots (a group's
/// projection depends on nothing else). Lookups only: iteration order never matters.
#[derive(Debug, Clone)]
pub(crate) struct Projections {
    map: HashMap<ProjectionKey, Option<exact::Projection>, BuildHasherDefault<KeyHasher>>,
    /// The coupled projection's scratch space.
    solver: exact::Coupled,
    /// The groups the coupled projection works on.
    groups: Vec<Group>,
    /// Each connected set's range in `groups` (see [`components`]).
    ranges: Vec<std::ops::Range<usize>>,
    /// Scratch for [`components`] and [`widest_gap_end`].
    scratch: Scratch,
    /// Whether [`Regulation::Exact`] projects each connected set of groups together in the
    /// surface metric ([`exact::Coupled`], the default) instead of group by group.
    pub(crate) coupled: bool,
}

impl Default for Projections {
    fn default() -> Self {
        Self {
            map: HashMap::default(),
            solver: exact::Coupled::default(),
            groups: Vec::new(),
            ranges: Vec::new(),
            scratch: Scratch::default(),
            coupled: true,
        }
    }
}

/// The first occupied index after the longest cyclic run of unoccupied ones among `0..len`
/// (0 when every index or none is occupied): where a set on a closed grid line begins.
fn widest_gap_end(
    len: usize,
    occupied: impl Iterator<Item = usize>,
    seen: &mut Vec<bool>,
) -> usize {
    seen.clear();
    seen.resize(len, false);
    for i in occupied {
        seen[i % len.max(1)] = true;
    }
    let Some(first) = seen.iter().position(|&x| x) else {
        return 0;
    };
    let (mut best, mut best_len, mut run) = (0, 0, 0);
    for step in 1..=len {
        let i = (first + step) % len;
        if seen[i] {
            if run > best_len {
                (best, best_len) = (i, run);
            }
            run = 0;
        } else {
            run += 1;
        }
    }
    best
}

/// Orders `groups` by connected set — two groups are connected when they are corners of one
/// patch (vertices at most one apart along `u` and `v`, across closed seams) — and writes each
/// set's range to `ranges`. Within a set the order is by vertex.
fn components(
    grid: &Grid,
    groups: &mut [Group],
    scratch: &mut Scratch,
    ranges: &mut Vec<std::ops::Range<usize>>,
) {
    let Scratch {
        labels,
        stack,
        order,
        keyed,
        sorted,
        ..
    } = scratch;
    let vu = grid.vertices_u();
    let topology = grid.topology();
    // The groups by vertex key `q · V_u + k` (sorting the keys, not the groups).
    keyed.clear();
    keyed.extend(
        groups
            .iter()
            .enumerate()
            .map(|(i, g)| (g.vertex.1 * vu + g.vertex.0, i)),
    );
    keyed.sort_unstable();
    let count = groups.len();
    labels.clear();
    labels.resize(count, usize::MAX);
    stack.clear();
    let mut sets = 0;
    for seed in 0..count {
        if labels[seed] != usize::MAX {
            continue;
        }
        labels[seed] = sets;
        stack.push(seed);
        while let Some(i) = stack.pop() {
            let (k, q) = groups[keyed[i].1].vertex;
            for dq in -1..=1isize {
                for dk in -1..=1isize {
                    let Some(k2) = wrap(k as isize + dk, vu, topology.closed_u()) else {
                        continue;
                    };
                    let Some(q2) = wrap(q as isize + dq, grid.vertices_v(), topology.closed_v())
                    else {
                        continue;
                    };
                    let want = q2 * vu + k2;
                    if let Ok(j) = keyed.binary_search_by_key(&want, |e| e.0)
                        && labels[j] == usize::MAX
                    {
                        labels[j] = sets;
                        stack.push(j);
                    }
                }
            }
        }
        sets += 1;
    }
    // Stable by set: the vertex order within each set is kept.
    order.clear();
    order.extend(0..count);
    if sets > 1 {
        order.sort_by_key(|&i| labels[i]);
    }
    sorted.clear();
    sorted.extend(order.iter().map(|&i| groups[keyed[i].1]));
    groups.copy_from_slice(sorted);
    ranges.clear();
    let mut start = 0;
    for i in 1..=count {
        if i == count || labels[order[i]] != labels[order[start]] {
            ranges.push(start..i);
            start = i;
        }
    }
}

/// Buffers of the connected-set search, kept between operations.
#[derive(Debug, Clone, Default)]
struct Scratch {
    /// Per group: its connected set.
    labels: Vec<usize>,
    stack: Vec<usize>,
    order: Vec<usize>,
    /// `(vertex key, index)` of every group, sorted.
    keyed: Vec<(usize, usize)>,
    sorted: Vec<Group>,
    /// Per vertex along a grid line: whether a group of the set lies on it.
    seen: Vec<bool>,
}

/// The ratios' bits and the slots that exist.
type ProjectionKey = (u64, u64, [bool; 9]);

/// A small multiplicative hasher for the projection keys (the default SipHash costs more than
/// the projection it looks up).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7C_C1_B7_27_22_0A_95);
    }

    fn write_u8(&mut self, x: u8) {
        self.write_u64(u64::from(x));
    }

    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
}

impl Projections {
    /// Most projections kept before the cache starts over.
    const LIMIT: usize = 1 << 16;

    fn get(&mut self, ratios: (f64, f64), present: [bool; 9]) -> Option<exact::Projection> {
        if self.map.len() >= Self::LIMIT {
            self.map.clear();
        }
        *self
            .map
            .entry((ratios.0.to_bits(), ratios.1.to_bits(), present))
            .or_insert_with(|| exact::Projection::new(ratios, present))
    }
}

/// Regulates the groups around the grid vertices `(k, q)` and the poles listed; returns how
/// many groups and poles were worked on. Groups where only one patch meets (grid corners)
/// carry no continuity condition and are left alone.
pub(crate) fn regulate(
    grid: &mut Grid,
    method: Regulation,
    vertices: &[(usize, usize)],
    poles: &[PoleEnd],
    projections: &mut Projections,
) -> usize {
    if method == Regulation::None {
        return 0;
    }
    let mut count = 0;
    if method.promises_g1() && projections.coupled {
        // Poles first (their rings are fixed nodes of the groups' projection), then every
        // group together in the surface metric.
        for &end in poles {
            let Some(pole) = grid.pole(end) else { continue };
            let mut p = read_pole(grid, &pole);
            if exact::regulate_pole(&mut p, &pole.ratios) {
                write_pole(grid, &pole, &p);
            }
            count += 1;
        }
        projections.groups.clear();
        for &(k, q) in vertices {
            let Some(g) = grid.group(k, q) else { continue };
            if g.patch_count() >= 2 {
                projections.groups.push(g);
            }
        }
        count += projections.groups.len();
        let mut groups = std::mem::take(&mut projections.groups);
        let mut ranges = std::mem::take(&mut projections.ranges);
        components(grid, &mut groups, &mut projections.scratch, &mut ranges);
        for range in ranges.iter().cloned() {
            let set = &groups[range];
            let seen = &mut projections.scratch.seen;
            let origin = (
                widest_gap_end(grid.vertices_u(), set.iter().map(|g| g.vertex.0), seen),
                widest_gap_end(grid.vertices_v(), set.iter().map(|g| g.vertex.1), seen),
            );
            if !projections.solver.regulate(grid, set, origin) {
                // A set too large to factor in time, or (not expected: the normal matrix is
                // positive definite) a failed factorisation: group by group.
                for g in set {
                    let mut p = read_group(grid, g);
                    if let Some(proj) = projections.get(g.ratios, exact::present(&p)) {
                        proj.apply(&mut p);
                        write_group(grid, g, &p);
                    }
                }
            }
        }
        projections.groups = groups;
        projections.ranges = ranges;
        return count;
    }
    for &(k, q) in vertices {
        let Some(g) = grid.group(k, q) else { continue };
        if g.patch_count() < 2 {
            continue;
        }
        let mut p = read_group(grid, &g);
        let changed = match method {
            Regulation::None => false,
            Regulation::C1 => c1::regulate_group(&mut p),
            Regulation::G1 => g1::regulate_group(&mut p),
            Regulation::Exact | Regulation::G2 => {
                match projections.get(g.ratios, exact::present(&p)) {
                    Some(proj) => {
                        proj.apply(&mut p);
                        true
                    }
                    None => false,
                }
            }
        };
        if changed {
            write_group(grid, &g, &p);
        }
        count += 1;
    }
    for &end in poles {
        let Some(pole) = grid.pole(end) else { continue };
        let mut p = read_pole(grid, &pole);
        let changed = match method {
            Regulation::None => false,
            Regulation::C1 => c1::regulate_pole(&mut p),
            Regulation::G1 => g1::regulate_pole(&mut p),
            Regulation::Exact | Regulation::G2 => exact::regulate_pole(&mut p, &pole.ratios),
        };
        if changed {
            write_pole(grid, &pole, &p);
        }
        count += 1;
    }
    count
}

/// [`Regulation::Exact`] group by group — each group the member of its family nearest to its
/// own points in the metric of its four patches with the neighbouring groups held
/// ([`exact::Projection`]) — on the groups around the grid vertices `(k, q)` listed (then
/// the bounding boxes refitted); returns how many were worked on. The exact regulation's
/// former default, kept for comparison (`nendo bench regulation`): the coupled projection
/// that replaced it ([`exact`]) comes nearer to the finger's shape.
pub fn exact_group_by_group(grid: &mut Grid, vertices: &[(usize, usize)]) -> usize {
    let mut projections = Projections {
        coupled: false,
        ..Projections::default()
    };
    let n = regulate(grid, Regulation::Exact, vertices, &[], &mut projections);
    let all: Vec<usize> = (0..grid.patch_count()).collect();
    grid.refit(&all, &mut Vec::new());
    n
}

/// Regulates every group and pole of a grid (e.g. after reading a model made elsewhere);
/// returns how many were worked on. [`Regulation::G2`] then projects the whole grid onto
/// the G2 nets ([`g2`]).
///
/// # Errors
/// [`crate::surface::SurfaceError::G2Singular`] when the G2 projection finds no admissible
/// net (the grid is then regulated by `exact` only).
pub fn regulate_all(
    grid: &mut Grid,
    method: Regulation,
) -> Result<usize, crate::surface::SurfaceError> {
    let vertices: Vec<(usize, usize)> = grid.groups().iter().map(|g| g.vertex).collect();
    let poles: Vec<PoleEnd> = grid.poles().iter().map(|p| p.end).collect();
    let n = regulate(grid, method, &vertices, &poles, &mut Projections::default());
    let all: Vec<usize> = (0..grid.patch_count()).collect();
    let mut failed = None;
    if method == Regulation::G2 {
        let now = grid.nodes().to_vec();
        let at = |id: usize| now[id];
        match g2::regulate(grid, &at, &at, &all, &mut g2::G2Cache::default()) {
            Ok(step) => {
                let nodes = grid.nodes_mut();
                for (id, x) in step.writes {
                    nodes[id] = x;
                }
            }
            Err(e) => failed = Some(e),
        }
    }
    grid.refit(&all, &mut Vec::new());
    match failed {
        None => Ok(n),
        Some(e) => Err(crate::surface::SurfaceError::G2Singular { patches: e.patches }),
    }
}
