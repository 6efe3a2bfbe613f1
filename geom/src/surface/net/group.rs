//! Connected control-point groups (P2 §4.1, Fig. 3; docs/design.md §9).
//!
//! The control net partitions into groups, one around each grid vertex: the vertex node `P_O`,
//! its neighbours on the patch boundaries through it, and the interior corner points of the
//! adjacent patches — a 3 × 3 block of lattice points `(3k + s, 3q + t)`, `s, t ∈ {−1, 0, 1}`.
//! At an open boundary the block is cut (two patches: 3 × 2; a corner of the grid: 2 × 2). At
//! a pole the group is the pole node and the whole first ring of control points around it.
//!
//! Every three-point row of control points that crosses a grid line lies inside one group, so
//! tangent continuity is a condition on each group separately: this is what regulation works on.

use crate::surface::grid::Grid;

/// A connected control-point group around a non-degenerate grid vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Group {
    /// The grid vertex `(k, q)`: lattice point `(3k, 3q)`.
    pub vertex: (usize, usize),
    /// Node ids, `nodes[s + 1][t + 1]` for the lattice point `(3k + s, 3q + t)`, `s` along `u`,
    /// `t` along `v`; `None` beyond an open boundary.
    pub nodes: [[Option<usize>; 3]; 3],
    /// Reference spacing ratios `(ρ_u, ρ_v)` of the two grid lines through the vertex (see
    /// [`Grid::ratio_u`]): `P(+1) − P(0) = ρ·(P(0) − P(−1))` along a regulated row.
    pub ratios: (f64, f64),
}

impl Group {
    /// The node id at offsets `(s, t) ∈ {−1, 0, 1}²`.
    #[must_use]
    pub fn node(&self, s: isize, t: isize) -> Option<usize> {
        self.nodes[(s + 1) as usize][(t + 1) as usize]
    }

    /// The vertex node `P_O`.
    #[must_use]
    pub fn center(&self) -> usize {
        self.nodes[1][1].unwrap_or_default()
    }

    /// How many patches meet at the vertex: 4 inside, 2 on an open boundary, 1 at a corner.
    #[must_use]
    pub fn patch_count(&self) -> usize {
        let su = usize::from(self.nodes[0][1].is_some()) + usize::from(self.nodes[2][1].is_some());
        let sv = usize::from(self.nodes[1][0].is_some()) + usize::from(self.nodes[1][2].is_some());
        su * sv
    }
}

/// Which end of the `v` direction a pole is at.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PoleEnd {
    /// Row `v = 0`.
    Start,
    /// Row `v = N`.
    End,
}

/// A degenerate point: the pole node and its first ring of control points.
#[derive(Debug, Clone, PartialEq)]
pub struct Pole {
    /// Which end.
    pub end: PoleEnd,
    /// The pole's node id.
    pub node: usize,
    /// The first ring, `ring[a]` for lattice column `a ∈ 0..3M` (row 1, or row `3N − 1` at the
    /// end pole). Meridian `k` (the patch boundary `u = k`) passes through `ring[3k]`; the
    /// meridian opposite `k` is `k + M/2`.
    pub ring: Vec<usize>,
    /// Reference spacing ratio of each meridian `k` (see [`Grid::ratio_u`]).
    pub ratios: Vec<f64>,
}

impl Grid {
    /// The group around grid vertex `(k, q)`; `None` for a pole row (see [`Grid::pole`]) or a
    /// vertex out of range.
    #[must_use]
    pub fn group(&self, k: usize, q: usize) -> Option<Group> {
        if k >= self.vertices_u() || q >= self.vertices_v() || self.is_pole_line(q) {
            return None;
        }
        let (a, b) = (3 * k as isize, 3 * q as isize);
        let mut nodes = [[None; 3]; 3];
        for (si, s) in (-1..=1).enumerate() {
            for (ti, t) in (-1..=1).enumerate() {
                nodes[si][ti] = self.node_id(a + s, b + t);
            }
        }
        Some(Group {
            vertex: (k, q),
            nodes,
            ratios: (self.ratio_u(k), self.ratio_v(q)),
        })
    }

    /// Every group around a non-degenerate vertex, `q` major, `k` minor.
    #[must_use]
    pub fn groups(&self) -> Vec<Group> {
        let mut out = Vec::with_capacity(self.vertices_u() * self.vertices_v());
        for q in 0..self.vertices_v() {
            for k in 0..self.vertices_u() {
                if let Some(g) = self.group(k, q) {
                    out.push(g);
                }
            }
        }
        out
    }

    /// The pole at one end, if the topology has it.
    #[must_use]
    pub fn pole(&self, end: PoleEnd) -> Option<Pole> {
        let t = self.topology();
        let (la, lb) = self.lattice_size();
        let (b_pole, b_ring) = match end {
            PoleEnd::Start if t.pole_at_start() => (0, 1),
            PoleEnd::End if t.pole_at_end() => (lb - 1, lb - 2),
            _ => return None,
        };
        let node = self.node_id(0, b_pole as isize)?;
        let ring = (0..la)
            .filter_map(|a| self.node_id(a as isize, b_ring as isize))
            .collect();
        let ratios = (0..self.vertices_u()).map(|k| self.ratio_u(k)).collect();
        Some(Pole {
            end,
            node,
            ring,
            ratios,
        })
    }

    /// Every pole (0, 1 or 2).
    #[must_use]
    pub fn poles(&self) -> Vec<Pole> {
        [PoleEnd::Start, PoleEnd::End]
            .into_iter()
            .filter_map(|e| self.pole(e))
            .collect()
    }
}
