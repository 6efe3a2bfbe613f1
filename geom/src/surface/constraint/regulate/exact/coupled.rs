//! The coupled projection ([`Coupled`], the default of the exact regulation): every touched
//! group at once and the metric whole. Among all nets whose touched groups are
//! bilinear lattices (4 free vectors `θ_g` each) and whose other nodes stay, the one nearest
//! to the unregulated net in `Σ_p ∫|ΔS_p|²` over every patch around the touched groups (the
//! touched patches and one ring: nothing else can move). Per patch the metric is
//! `δᵀ (m ⊗ m) δ` over its 16 nodes, `m` the full 4 × 4 Bernstein Gram matrix
//! `m_ik = ∫₀¹ B_i³ B_k³ = C(3,i) C(3,k) / (7 C(6,i+k))`, so neighbouring groups couple
//! through the patches they share. A node of group `g` at offsets `(s̃, t̃)` is
//! `φ(s̃, t̃)·θ_g`, `φ = (1, s̃, t̃, s̃ t̃)`, so the normal equations
//! `Σ_p Φ_pᵀ (m ⊗ m) Φ_p θ = Σ_p Φ_pᵀ (m ⊗ m) x_p` are a sparse SPD system with one 4 × 4
//! block per pair of groups sharing a patch (each block a Kronecker product of two 2 × 2
//! one-dimensional blocks), the same for the three coordinates. The system splits into the
//! **connected sets** of touched groups (two groups connected when they are corners of one
//! patch; [`crate::surface::regulate`] orders them so); each set is solved on its own by a Cholesky
//! factorisation in skyline storage, its groups ordered by grid vertex (row by row), so the
//! envelope is about one grid row of groups wide. The G1 conditions hold by construction
//! (any `θ` is a G1 net); poles are regulated first ([`super::regulate_pole`]) and their rings are fixed nodes
//! of the solve.
//!
//! **Frame by frame** (the hand's [`crate::surface::Presser`], which grows a contact frame by
//! frame and must equal the contact applied at once): a group's coupled solution is a
//! function of the unregulated net of its whole connected set (the inverse of the normal
//! matrix is dense there), so a frame re-regulates, besides the groups at the corners of the
//! patches it reaches, every touched group connected to them, from the contact's unregulated
//! net. A set the frame does not reach has the same groups and the same unregulated net as
//! when it was last solved, and keeps its points: the result is the contact at once, bit for
//! bit (the system of one set does not depend on the others). The price: a frame solves and
//! verifies the whole connected part of the contact it reaches — a long continuous stroke
//! costs each frame what the stroke so far touched (a one-shot operation, and the window's
//! live stroke, which re-applies its operation each frame, are unaffected).
//!
//! The factor of each solve is kept per shape of the solve ([`FactorCache`]): a push repeated,
//! or shifted by whole patches over a uniform region, only assembles its right-hand side.

use glam::DVec3;

use super::skyline::{skyline_cholesky, skyline_solve};
use crate::surface::grid::Grid;
use crate::surface::group::Group;
use crate::surface::topology::wrap;

/// The Bernstein Gram matrix of one direction, `m_ik = ∫₀¹ B_i³ B_k³ = C(3,i) C(3,k) / (7 C(6,i+k))`.
const GRAM_1D: [[f64; 4]; 4] = [
    [1.0 / 7.0, 1.0 / 14.0, 1.0 / 35.0, 1.0 / 140.0],
    [1.0 / 14.0, 3.0 / 35.0, 9.0 / 140.0, 1.0 / 35.0],
    [1.0 / 35.0, 9.0 / 140.0, 3.0 / 35.0, 1.0 / 14.0],
    [1.0 / 140.0, 1.0 / 35.0, 1.0 / 14.0, 1.0 / 7.0],
];

/// The rows of the right-hand side's one-dimensional factors: `RHS_GRAM[0][c]` = `m_r0 + m_r1`
/// and `RHS_GRAM[1][c]` = `m_r1` over the corner's vertex row `r0` and next row `r1`
/// (`(0, 1)` for the corner at `c = 0`, `(3, 2)` at `c = 1`): `Σ_(i ∈ {r0, r1}) φ_α(i) m_i`
/// with the offset `s̃` of `φ_1` taken out.
const RHS_GRAM: [[[f64; 4]; 2]; 2] = {
    let g = GRAM_1D;
    let mut out = [[[0.0; 4]; 2]; 2];
    let mut k = 0;
    while k < 4 {
        out[0][0][k] = g[0][k] + g[1][k];
        out[0][1][k] = g[3][k] + g[2][k];
        out[1][0][k] = g[1][k];
        out[1][1][k] = g[2][k];
        k += 1;
    }
    out
};

/// The coupled projection of a set of groups (see the module docs): scratch space kept
/// between operations so that a stroke allocates nothing once the buffers have grown.
#[derive(Debug, Clone, Default)]
pub(crate) struct Coupled {
    /// The regulated groups, sorted by vertex key `q · V_u + k` (the unknowns' order).
    groups: Vec<Group>,
    /// `(q · V_u + k, index in groups)` of every group, sorted: finds a corner's group by its
    /// vertex without the modular key (a division per lookup).
    by_vertex: Vec<(usize, u32)>,
    /// The patches around them (ids `iv · M + iu`, sorted).
    patches: Vec<usize>,
    /// Per patch: the index in `groups` of each corner `(c_u, c_v)` (`2 c_v + c_u`), if
    /// regulated.
    corners: Vec<[Option<u32>; 4]>,
    /// Per group: the lowest group index it is coupled with (the envelope of its rows).
    first_group: Vec<usize>,
    /// Skyline storage of the lower triangle of the normal matrix: row `r` holds columns
    /// `first[r] ..= r` at `start[r]`.
    first: Vec<usize>,
    start: Vec<usize>,
    data: Vec<f64>,
    /// The right-hand side, then the solution `θ` (4 vectors per group).
    rhs: Vec<DVec3>,
    /// What the normal matrix depends on, for the present solve: per group its ratios' bits
    /// and which slots exist (the corners above give the rest).
    shape: Vec<(u64, u64, [bool; 9])>,
    /// Factored normal matrices of recent solves, by shape (see [`FactorCache`]).
    factors: FactorCache,
}

/// The Cholesky factors of recent coupled solves. The normal matrix depends only on the
/// patches' corner groups (`corners`, in the groups' order) and on each group's ratios and
/// slots, not on the displacement and not on where on the grid the groups are: a stroke that
/// moves by whole patches over a uniform region, or strokes repeated at the same place, find
/// their factor here and only assemble the right-hand side and solve.
#[derive(Debug, Clone, Default)]
struct FactorCache {
    entries: Vec<Factor>,
    /// The entry to overwrite next when full (round robin).
    next: usize,
}

/// One cached factor: its key and the skyline factor.
#[derive(Debug, Clone, Default)]
struct Factor {
    corners: Vec<[Option<u32>; 4]>,
    shape: Vec<(u64, u64, [bool; 9])>,
    first: Vec<usize>,
    start: Vec<usize>,
    data: Vec<f64>,
}

impl FactorCache {
    /// Most factors kept.
    const LIMIT: usize = 8;
    /// Largest factor kept (entries of the skyline, 512 KiB): a stroke over thousands of
    /// groups is not repeated often enough to be worth the memory.
    const LARGEST: usize = 1 << 16;

    fn find(&self, corners: &[[Option<u32>; 4]], shape: &[(u64, u64, [bool; 9])]) -> Option<usize> {
        self.entries
            .iter()
            .position(|f| f.corners == corners && f.shape == shape)
    }

    /// Stores a factor (reusing an old entry's buffers when full).
    fn store(
        &mut self,
        corners: &[[Option<u32>; 4]],
        shape: &[(u64, u64, [bool; 9])],
        (first, start, data): (&[usize], &[usize], &[f64]),
    ) {
        if data.len() > Self::LARGEST {
            return;
        }
        let i = if self.entries.len() < Self::LIMIT {
            self.entries.push(Factor::default());
            self.entries.len() - 1
        } else {
            let i = self.next;
            self.next = (self.next + 1) % Self::LIMIT;
            i
        };
        let f = &mut self.entries[i];
        for (dst, src) in [(&mut f.first, first), (&mut f.start, start)] {
            dst.clear();
            dst.extend_from_slice(src);
        }
        f.corners.clear();
        f.corners.extend_from_slice(corners);
        f.shape.clear();
        f.shape.extend_from_slice(shape);
        f.data.clear();
        f.data.extend_from_slice(data);
    }
}

impl Coupled {
    /// The largest factorisation done, in `Σ_r w_r²` over the skyline rows of width `w_r`
    /// (about twice its multiply–adds): 2²⁴, some 10 ms. A connected set whose envelope is
    /// wider — hundreds of groups across, e.g. a palm on a finely refined grid, or
    /// [`crate::surface::regulate_all`] on a large grid — is regulated group by group instead.
    const MOST_WORK: usize = 1 << 24;

    fn assemble(&mut self, grid: &Grid, factor: bool) {
        let m = grid.patches_u();
        let shape = grid.shape();
        let nodes = grid.nodes();
        // Assembly, patch by patch.
        for (pi, &p) in self.patches.iter().enumerate() {
            let (iu, iv) = (p % m, p / m);
            let ids = shape.patch_ids(iu, iv);
            let corners = self.corners[pi];
            // Node offsets s̃ (along u) and t̃ (along v) of the local rows, per corner.
            let mut su = [[0.0f64; 4]; 4];
            let mut tv = [[0.0f64; 4]; 4];
            let mut offsets = [(0.0f64, 0.0f64); 4];
            // Which halves of the patch's rows (`i < 2`, `i ≥ 2`) and columns hold regulated
            // nodes (every other node of the patch stays: it adds nothing).
            let (mut rows, mut cols) = ([false; 2], [false; 2]);
            let mut x = [[DVec3::ZERO; 4]; 4];
            for (slot, g) in corners.iter().enumerate() {
                let Some(g) = g else { continue };
                let (cu, cv) = (slot % 2, slot / 2);
                let (ru, rv) = self.groups[*g as usize].ratios;
                // Local rows of the corner: vertex row first.
                let (iu0, iu1, off_u) = if cu == 0 { (0, 1, ru) } else { (3, 2, -1.0) };
                let (jv0, jv1, off_v) = if cv == 0 { (0, 1, rv) } else { (3, 2, -1.0) };
                su[slot][iu1] = off_u;
                tv[slot][jv1] = off_v;
                offsets[slot] = (off_u, off_v);
                rows[cu] = true;
                cols[cv] = true;
                for i in [iu0, iu1] {
                    for j in [jv0, jv1] {
                        x[i][j] = nodes[ids[4 * i + j]];
                    }
                }
            }
            // Right-hand side, per regulated corner `(c_u, c_v)`: `Φ_cᵀ (m ⊗ m) x` with
            // `Φ_c = φ_u ⊗ φ_v` (`φ = (1, s̃)` on the corner's two rows), i.e.
            // `b[α][β] = s̃^α t̃^β Σ_l G_α[c_u][l] Σ_k G_β[c_v][k] x[l][k]` ([`RHS_GRAM`]), the
            // inner sums shared by the corners of one `c_v`, over the halves that hold nodes.
            // The present halves as one range (two halves are contiguous).
            let halves = |h: [bool; 2]| (if h[0] { 0 } else { 2 })..(if h[1] { 4 } else { 2 });
            let mut w = [[[DVec3::ZERO; 4]; 2]; 2];
            for cv in 0..2 {
                if !cols[cv] {
                    continue;
                }
                for (beta, wb) in w[cv].iter_mut().enumerate() {
                    let gv = &RHS_GRAM[beta][cv];
                    for l in halves(rows) {
                        let mut sum = DVec3::ZERO;
                        for k in halves(cols) {
                            sum += x[l][k] * gv[k];
                        }
                        wb[l] = sum;
                    }
                }
            }
            for (cs, gc) in corners.iter().enumerate() {
                let Some(gc) = gc else { continue };
                let gc = *gc as usize;
                let (cu, cv) = (cs % 2, cs / 2);
                let (off_u, off_v) = (offsets[cs].0, offsets[cs].1);
                for e in 0..4 {
                    let (alpha, beta) = (e % 2, e / 2);
                    let gu = &RHS_GRAM[alpha][cu];
                    let mut sum = DVec3::ZERO;
                    for l in halves(rows) {
                        sum += w[cv][beta][l] * gu[l];
                    }
                    let scale = match e {
                        0 => 1.0,
                        1 => off_u,
                        2 => off_v,
                        _ => off_u * off_v,
                    };
                    self.rhs[4 * gc + e] += sum * scale;
                }
            }
            if !factor {
                continue;
            }
            // Per corner: its local rows and columns and the basis rows φ(node) = (1, s̃).
            let rows_u = |cu: usize| if cu == 0 { [0usize, 1] } else { [3, 2] };
            for (cs, gc) in corners.iter().enumerate() {
                let Some(gc) = gc else { continue };
                let gc = *gc as usize;
                let (cu, cv) = (cs % 2, cs / 2);
                let (ci, cj) = (rows_u(cu), rows_u(cv));
                // Normal-matrix blocks with every regulated corner at or before it.
                for (ds, gd) in corners.iter().enumerate() {
                    let Some(gd) = gd else { continue };
                    let gd = *gd as usize;
                    if gd > gc {
                        continue;
                    }
                    let (du, dv) = (ds % 2, ds / 2);
                    let (di, dj) = (rows_u(du), rows_u(dv));
                    // U[α][α'] = Σ φ_α(i) m_ii' φ_α'(i'), likewise V along v.
                    let mut uu = [[0.0f64; 2]; 2];
                    let mut vvm = [[0.0f64; 2]; 2];
                    for &i in &ci {
                        let fa = [1.0, su[cs][i]];
                        for &i2 in &di {
                            let fb = [1.0, su[ds][i2]];
                            let w = GRAM_1D[i][i2];
                            for a in 0..2 {
                                for b in 0..2 {
                                    uu[a][b] += fa[a] * w * fb[b];
                                }
                            }
                        }
                    }
                    for &j in &cj {
                        let fa = [1.0, tv[cs][j]];
                        for &j2 in &dj {
                            let fb = [1.0, tv[ds][j2]];
                            let w = GRAM_1D[j][j2];
                            for a in 0..2 {
                                for b in 0..2 {
                                    vvm[a][b] += fa[a] * w * fb[b];
                                }
                            }
                        }
                    }
                    // Parameter e = α + 2β: (P_O, a, b, c).
                    for e in 0..4 {
                        let r = 4 * gc + e;
                        let hi = if gd == gc { e } else { 3 };
                        for e2 in 0..=hi {
                            let col = 4 * gd + e2;
                            let v = uu[e % 2][e2 % 2] * vvm[e / 2][e2 / 2];
                            self.data[self.start[r] + col - self.first[r]] += v;
                        }
                    }
                }
            }
        }
    }

    fn write(&self, grid: &mut Grid) {
        // Write the regulated nodes.
        let nodes = grid.nodes_mut();
        for (gi, g) in self.groups.iter().enumerate() {
            let th = &self.rhs[4 * gi..4 * gi + 4];
            let su = [-1.0, 0.0, g.ratios.0];
            let tv = [-1.0, 0.0, g.ratios.1];
            for s in 0..3 {
                for t in 0..3 {
                    if let Some(id) = g.nodes[s][t] {
                        nodes[id] = th[0] + th[1] * su[s] + th[2] * tv[t] + th[3] * (su[s] * tv[t]);
                    }
                }
            }
        }
    }

    /// Regulates `groups` (each with at least two patches) together: the G1 net nearest to the
    /// present one in `∫|ΔS|²` over every patch around them, every other node fixed. `false`
    /// (and nothing written) if the normal matrix is not numerically positive definite.
    ///
    /// The unknowns are ordered row by row from the vertex `origin` on (`(k − k₀) mod V_u`
    /// within `(q − q₀) mod V_v`): on a closed grid, an origin just past the set's widest gap
    /// keeps a set that straddles the seam from spanning the whole ring in the envelope.
    pub(crate) fn regulate(
        &mut self,
        grid: &mut Grid,
        groups: &[Group],
        origin: (usize, usize),
    ) -> bool {
        let (m, n) = (grid.patches_u(), grid.patches_v());
        let (vu, vv) = (grid.vertices_u(), grid.vertices_v());
        let topology = grid.topology();
        // `(x − x₀) mod n` for `x < n` without a division.
        let (o_u, o_v) = (origin.0 % vu, origin.1 % vv);
        let vkey = move |g: &Group| {
            let from = |x: usize, o: usize, n: usize| if x >= o { x - o } else { x + n - o };
            from(g.vertex.1, o_v, vv) * vu + from(g.vertex.0, o_u, vu)
        };
        self.groups.clear();
        self.groups.extend_from_slice(groups);
        // The sets come ordered by `q · V_u + k`, the same order unless they cross a seam.
        if !self.groups.is_sorted_by_key(vkey) {
            self.groups.sort_by_key(vkey);
        }
        self.groups.dedup_by_key(|g| g.vertex);
        let count = self.groups.len();
        if count == 0 {
            return true;
        }
        self.by_vertex.clear();
        self.by_vertex.extend(
            self.groups
                .iter()
                .enumerate()
                .map(|(i, g)| (g.vertex.1 * vu + g.vertex.0, i as u32)),
        );
        self.by_vertex.sort_unstable();
        // The patches around the groups.
        self.patches.clear();
        for g in &self.groups {
            let (k, q) = g.vertex;
            for (du, dv) in [(1usize, 1usize), (0, 1), (1, 0), (0, 0)] {
                let Some(iu) = wrap(k as isize - du as isize, m, topology.closed_u()) else {
                    continue;
                };
                let Some(iv) = wrap(q as isize - dv as isize, n, topology.closed_v()) else {
                    continue;
                };
                self.patches.push(iv * m + iu);
            }
        }
        self.patches.sort_unstable();
        self.patches.dedup();
        // Corner groups and the envelope.
        self.corners.clear();
        self.first_group.clear();
        self.first_group.extend(0..count);
        let by_vertex = &self.by_vertex;
        let find = |k: usize, q: usize| -> Option<u32> {
            if grid.is_pole_line(q) {
                return None;
            }
            by_vertex
                .binary_search_by_key(&(q * vu + k), |e| e.0)
                .ok()
                .map(|i| by_vertex[i].1)
        };
        for &p in &self.patches {
            let (iu, iv) = (p % m, p / m);
            let mut c = [None; 4];
            for (slot, corner) in c.iter_mut().enumerate() {
                let (cu, cv) = (slot % 2, slot / 2);
                // (iu + c_u) mod V_u without a division: iu < M ≤ V_u and c_u ≤ 1.
                let wrap_once = |x: usize, n: usize| if x >= n { x - n } else { x };
                *corner = find(wrap_once(iu + cu, vu), wrap_once(iv + cv, vv));
            }
            let lo = c.iter().flatten().min().copied();
            if let Some(lo) = lo {
                for &g in c.iter().flatten() {
                    let f = &mut self.first_group[g as usize];
                    *f = (*f).min(lo as usize);
                }
            }
            self.corners.push(c);
        }
        // The matrix's key; a factor of the same shape is reused.
        self.shape.clear();
        for g in &self.groups {
            let present = std::array::from_fn(|k| g.nodes[k / 3][k % 3].is_some());
            self.shape
                .push((g.ratios.0.to_bits(), g.ratios.1.to_bits(), present));
        }
        let cached = self.factors.find(&self.corners, &self.shape);
        // Skyline layout (a cached factor has its own).
        let rows = 4 * count;
        if cached.is_none() {
            self.first.clear();
            self.start.clear();
            let mut len = 0;
            let mut work = 0usize;
            for r in 0..rows {
                let f = 4 * self.first_group[r / 4];
                self.first.push(f);
                self.start.push(len);
                len += r + 1 - f;
                work = work.saturating_add((r + 1 - f) * (r + 1 - f));
            }
            if work > Self::MOST_WORK {
                return false;
            }
            self.data.clear();
            self.data.resize(len, 0.0);
        }
        self.rhs.clear();
        self.rhs.resize(rows, DVec3::ZERO);
        self.assemble(grid, cached.is_none());
        match cached {
            Some(i) => {
                let f = &self.factors.entries[i];
                skyline_solve(&f.first, &f.start, &f.data, &mut self.rhs);
            }
            None => {
                if !skyline_cholesky(&self.first, &self.start, &mut self.data) {
                    return false;
                }
                self.factors.store(
                    &self.corners,
                    &self.shape,
                    (&self.first, &self.start, &self.data),
                );
                skyline_solve(&self.first, &self.start, &self.data, &mut self.rhs);
            }
        }
        if self.rhs.iter().any(|x| !x.is_finite()) {
            return false;
        }
        self.write(grid);
        true
    }
}
