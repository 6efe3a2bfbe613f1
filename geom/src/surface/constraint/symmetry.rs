//! The symmetry group a model is sculpted with ([`Symmetry`]): its isometries with their maps
//! of the grid, and how a net is made exactly invariant under them.

use glam::DVec3;

use super::isometry::Isometry;
use super::mirror::{
    Asymmetry, LATHE_TURNS, LatticeMap, MirrorError, Plane, SYMMETRY_TOLERANCE, SymmetrySpec,
    best_map, spacing_maps,
};
use crate::surface::grid::Grid;
use crate::surface::group::PoleEnd;
use crate::surface::plane_fit::plane_normal;

/// One isometry of a symmetry group with its maps of the grid.
#[derive(Debug, Clone, PartialEq)]
struct Element {
    iso: Isometry,
    inverse: Isometry,
    mu: LatticeMap,
    mv: LatticeMap,
    nodes: Vec<usize>,
    patches: Vec<usize>,
}

/// The symmetry group of a symmetric grid (mirrors and turns about the z axis, see
/// [`SymmetrySpec`]): for each isometry `g` of the group, each control point's, patch's and
/// grid vertex's image. Made once per grid shape ([`Symmetry::of`], [`Symmetry::group`]) and
/// reused for every operation.
///
/// **The group.** The mirrors `S` and the turns `R_{2πk/N}` generate `{S R_{2πk/N}}` (a
/// mirror of x or y conjugates a turn into its inverse, so the turns form a normal subgroup;
/// two such mirrors make the half turn). Each element's node map is the lattice map
/// (identity, shift `a ↦ a + 3M k / N` around the closed direction, or reflection) with the
/// smallest error, as for one mirror.
///
/// **Enforcing.** Each orbit `{σ_g(n)}` of control points is replaced by the images of its
/// mean pulled back,
///
/// ```text
/// x̄ = (1/|G|) Σ_g g⁻¹ x_σ_g(n),   x'_σ_g(n) = g x̄,
/// ```
///
/// which for one mirror is the pair mean of the module docs. The G1 conditions are linear in
/// the control points with coefficients (the spacing ratios) that every `σ_g` keeps (checked
/// when the group is made) and invariant under isometries, so the mean of `|G|` nets that
/// satisfy them satisfies them. A pole's ring is put in a tangent plane the pole's stabiliser
/// keeps: the normal along the axis when a turn of order ≥ 3 fixes the pole; otherwise, for
/// each diagonal sign matrix fixing it, the normal within the span of the negated or of the
/// kept coordinates, whichever holds more of it.
#[derive(Debug, Clone, PartialEq)]
pub struct Symmetry {
    spec: SymmetrySpec,
    /// `N` of the turns (1: none).
    turns: u32,
    counts: (usize, usize),
    /// Every element but the identity.
    elements: Vec<Element>,
    /// Every isometry the displacement field is combined over, but the identity.
    field: Vec<Isometry>,
}

impl Symmetry {
    /// The mirror map of a grid symmetric about `plane`.
    ///
    /// # Errors
    /// [`MirrorError::NotSymmetric`] (with the worst node) beyond [`SYMMETRY_TOLERANCE`];
    /// [`MirrorError::Spacing`] when a reversed grid line's spacing ratio does not mirror.
    pub fn of(grid: &Grid, plane: Plane) -> Result<Symmetry, MirrorError> {
        Symmetry::group(grid, &SymmetrySpec::mirror(plane))
    }

    /// The symmetry group of `spec` on `grid`: each generator is checked first (a mirror,
    /// then the turn by `2π / N`), so a refusal names the one that fails. Every map is listed
    /// once, whatever products name it; mirrors across x and y together with an odd `N` hold
    /// the half turn, so their group turns by `2π / 2N` ([`Symmetry::turns`] says `2N`).
    ///
    /// # Errors
    /// [`MirrorError::NotSymmetric`] or [`MirrorError::Spacing`] for a mirror the grid does
    /// not have; [`MirrorError::NotRotational`] for radial symmetry on a grid not closed
    /// around the axis, [`MirrorError::Columns`] when `N` does not divide its patch columns
    /// (refused, not refined), [`MirrorError::NotRadial`] or [`MirrorError::RadialSpacing`]
    /// when the turn does not map it to itself.
    pub fn group(grid: &Grid, spec: &SymmetrySpec) -> Result<Symmetry, MirrorError> {
        let t = grid.topology();
        let (m, n) = (grid.patches_u(), grid.patches_v());
        let turns = if spec.lathe && spec.radial <= 1 {
            if !t.closed_u() {
                return Err(MirrorError::NotRotational);
            }
            u32::try_from(m).unwrap_or(u32::MAX)
        } else {
            spec.radial.max(1)
        };
        // Mirrors across x and y together make the half turn: with an odd `N` the group they
        // generate with the `N`-fold turn holds the `2N`-fold one.
        let both = spec.planes.contains(&Plane::X) && spec.planes.contains(&Plane::Y);
        let turns = if both && turns > 1 && turns % 2 == 1 {
            2 * turns
        } else {
            turns
        };
        if turns > 1 {
            if !t.closed_u() {
                return Err(MirrorError::NotRotational);
            }
            if !m.is_multiple_of(turns as usize) {
                return Err(MirrorError::Columns {
                    n: turns,
                    columns: m,
                });
            }
        }
        // The generators, then every product.
        let mut isos: Vec<Isometry> = Vec::new();
        let mut generators: Vec<Isometry> = spec
            .planes
            .iter()
            .map(|p| Isometry::reflection(p.axis()))
            .collect();
        if turns > 1 {
            generators.push(Isometry::new(1, turns, [false; 3]));
        }
        for k in 0..turns {
            for mask in 0..(1u32 << spec.planes.len()) {
                let mut flip = [false; 3];
                for (i, p) in spec.planes.iter().enumerate() {
                    if mask & (1 << i) != 0 {
                        flip[p.axis()] = true;
                    }
                }
                let mut k = k;
                if flip[0] && flip[1] && turns.is_multiple_of(2) {
                    // Both mirrors across x and y make the half turn.
                    (flip[0], flip[1]) = (false, false);
                    k = (k + turns / 2) % turns;
                }
                let g = Isometry::new(k, turns, flip);
                // One element per map: a product may be another's map under another name
                // (the mirror across y is the mirror across x after a half turn), and a map
                // listed twice would be enforced from two lattice maps.
                if !g.is_identity() && !isos.iter().any(|h| same_map(h, &g)) {
                    isos.push(g);
                }
            }
        }
        // Generators first: their errors name what fails.
        isos.sort_by_key(|g| !generators.contains(g));
        let mut elements = Vec::with_capacity(isos.len());
        for iso in isos {
            let (mu, mv, relative, node) = best_map(grid, &iso);
            let plane = single_plane(&iso);
            if relative.is_nan() || relative > SYMMETRY_TOLERANCE {
                return Err(match plane {
                    Some(plane) => MirrorError::NotSymmetric(Asymmetry {
                        plane,
                        relative,
                        node,
                    }),
                    None => MirrorError::NotRadial {
                        n: turns,
                        relative,
                        node,
                    },
                });
            }
            let spacing = |(ratio, partner): (f64, f64)| match plane {
                Some(plane) => MirrorError::Spacing {
                    plane,
                    ratio,
                    partner,
                },
                None => MirrorError::RadialSpacing { n: turns },
            };
            spacing_maps(grid.vertices_u(), mu, &|k| grid.ratio_u(k)).map_err(spacing)?;
            spacing_maps(grid.vertices_v(), mv, &|q| grid.ratio_v(q)).map_err(spacing)?;
            elements.push(Element::new(grid, iso, mu, mv));
        }
        let field = if spec.lathe {
            let q = LATHE_TURNS.div_ceil(turns);
            let mut field = Vec::new();
            for g in std::iter::once(Isometry::IDENTITY).chain(elements.iter().map(|e| e.iso)) {
                for j in 0..q {
                    let h = g.then_after(&Isometry::new(j, turns * q, [false; 3]));
                    if !h.is_identity() && !field.contains(&h) {
                        field.push(h);
                    }
                }
            }
            field
        } else {
            elements.iter().map(|e| e.iso).collect()
        };
        let mut spec = spec.clone();
        spec.radial = turns;
        spec.planes.sort_by_key(|p| p.axis());
        spec.planes.dedup();
        Ok(Symmetry {
            spec,
            turns,
            counts: (m, n),
            elements,
            field,
        })
    }

    /// What the group was made from.
    #[must_use]
    pub fn spec(&self) -> &SymmetrySpec {
        &self.spec
    }

    /// `N` of the turns about the z axis (1: none; the patch columns for a lathe).
    #[must_use]
    pub fn turns(&self) -> u32 {
        self.turns
    }

    /// The number of isometries in the group (the identity included).
    #[must_use]
    pub fn order(&self) -> usize {
        self.elements.len() + 1
    }

    /// The mirror plane when the group is one mirror, else `None`.
    #[must_use]
    pub fn plane(&self) -> Option<Plane> {
        match self.elements.as_slice() {
            [e] => single_plane(&e.iso),
            _ => None,
        }
    }

    /// Every isometry of the group but the identity.
    pub fn isometries(&self) -> impl Iterator<Item = &Isometry> + '_ {
        self.elements.iter().map(|e| &e.iso)
    }

    /// Every isometry an operation's displacement field is combined over, but the identity:
    /// the group's, and for a lathe the turns between them (see [`SymmetrySpec::lathe`]).
    #[must_use]
    pub fn field_images(&self) -> &[Isometry] {
        &self.field
    }

    /// The partner of node `id` under the group's first isometry (the mirror, for one
    /// mirror).
    #[must_use]
    pub fn node_partner(&self, id: usize) -> usize {
        self.elements.first().map_or(id, |e| e.nodes[id])
    }

    /// The partner of patch `p` (`iv * M + iu`) under the first isometry.
    #[must_use]
    pub fn patch_partner(&self, p: usize) -> usize {
        self.elements.first().map_or(p, |e| e.patches[p])
    }

    /// The images of patch `p` under every isometry but the identity.
    pub fn patch_images(&self, p: usize) -> impl Iterator<Item = usize> + '_ {
        self.elements.iter().map(move |e| e.patches[p])
    }

    /// The partner of grid vertex `(k, q)` under the first isometry.
    #[must_use]
    pub fn vertex_partner(&self, grid: &Grid, k: usize, q: usize) -> (usize, usize) {
        self.elements
            .first()
            .map_or((k, q), |e| e.vertex_image(grid, k, q))
    }

    /// The partner of a pole under the first isometry.
    #[must_use]
    pub fn pole_partner(&self, end: PoleEnd) -> PoleEnd {
        self.elements.first().map_or(end, |e| e.pole_image(end))
    }

    /// The images of the global grid parameter `T` along u (`along_v` false) or v under every
    /// isometry, `T` included.
    #[must_use]
    pub fn parameter_images(&self, grid: &Grid, t: f64, along_v: bool) -> Vec<f64> {
        let top = grid.topology();
        let mut out = vec![t];
        for e in &self.elements {
            out.push(if along_v {
                e.mv.parameter(t, grid.patches_v(), top.closed_v())
            } else {
                e.mu.parameter(t, grid.patches_u(), top.closed_u())
            });
        }
        out
    }

    /// Whether this map was made for a grid of these counts.
    #[must_use]
    pub fn fits(&self, grid: &Grid) -> bool {
        self.counts == (grid.patches_u(), grid.patches_v())
            && self
                .elements
                .first()
                .is_none_or(|e| e.nodes.len() == grid.nodes().len())
    }

    /// Makes the listed nodes and their images exactly symmetric (see the module docs), and
    /// the listed poles and their images' first rings (where the regulation keeps a tangent
    /// plane).
    ///
    /// # Errors
    /// [`MirrorError::OtherGrid`] when the map does not fit the grid.
    pub fn enforce(
        &self,
        grid: &mut Grid,
        ids: &[usize],
        poles: &[PoleEnd],
    ) -> Result<(), MirrorError> {
        if !self.fits(grid) {
            return Err(MirrorError::OtherGrid);
        }
        let mut done = vec![false; grid.nodes().len()];
        self.enforce_nodes(grid.nodes_mut(), ids, &mut done);
        if !poles.is_empty() {
            if self.plane().is_some() {
                self.enforce_poles(grid, poles);
            } else {
                self.enforce_poles_group(grid, poles);
            }
        }
        Ok(())
    }

    /// The orbit means of the module docs, each orbit once (`done` marks the nodes written).
    fn enforce_nodes(&self, nodes: &mut [DVec3], ids: &[usize], done: &mut [bool]) {
        let inv = 1.0 / self.order() as f64;
        for &id in ids {
            if done[id] {
                continue;
            }
            let mut sum = nodes[id];
            for e in &self.elements {
                sum += e.inverse.apply(nodes[e.nodes[id]]);
            }
            let mean = sum * inv;
            nodes[id] = mean;
            done[id] = true;
            for e in &self.elements {
                let p = e.nodes[id];
                if !done[p] {
                    nodes[p] = e.iso.apply(mean);
                    done[p] = true;
                }
            }
        }
    }

    /// Makes the whole grid exactly symmetric.
    ///
    /// # Errors
    /// [`MirrorError::OtherGrid`] when the map does not fit the grid.
    pub fn enforce_all(&self, grid: &mut Grid, poles: bool) -> Result<(), MirrorError> {
        let ids: Vec<usize> = (0..grid.nodes().len()).collect();
        let ends: Vec<PoleEnd> = if poles {
            grid.poles().iter().map(|p| p.end).collect()
        } else {
            Vec::new()
        };
        self.enforce(grid, &ids, &ends)?;
        let all: Vec<usize> = (0..grid.patch_count()).collect();
        grid.refit(&all, &mut Vec::new());
        Ok(())
    }

    /// A pole's ring for a group (see [`Symmetry`]): the orbit means, the ring of the orbit's
    /// first pole projected onto a tangent plane its stabiliser keeps, its images written to
    /// the other pole, the orbit means again.
    fn enforce_poles_group(&self, grid: &mut Grid, listed: &[PoleEnd]) {
        for pole in grid.poles() {
            let images: Vec<PoleEnd> = self
                .elements
                .iter()
                .map(|e| e.pole_image(pole.end))
                .collect();
            if !listed.contains(&pole.end) && !images.iter().any(|e| listed.contains(e)) {
                continue;
            }
            if pole.end == PoleEnd::End && images.contains(&PoleEnd::Start) {
                continue; // set from its partner
            }
            let ids: Vec<usize> = std::iter::once(pole.node)
                .chain(pole.ring.iter().copied())
                .collect();
            let mut done = vec![false; grid.nodes().len()];
            self.enforce_nodes(grid.nodes_mut(), &ids, &mut done);
            let o = grid.nodes()[pole.node];
            let Some(n) = plane_normal(pole.ring.iter().map(|&id| grid.nodes()[id] - o)) else {
                continue;
            };
            let stabiliser: Vec<&Isometry> = self
                .elements
                .iter()
                .filter(|e| e.pole_image(pole.end) == pole.end)
                .map(|e| &e.iso)
                .collect();
            let Some(n) = symmetric_normal(n, &stabiliser) else {
                continue;
            };
            let nodes = grid.nodes_mut();
            for &id in &pole.ring {
                nodes[id] -= n * n.dot(nodes[id] - o);
            }
            if let Some(e) = self
                .elements
                .iter()
                .find(|e| e.pole_image(pole.end) != pole.end)
            {
                for &id in &ids {
                    nodes[e.nodes[id]] = e.iso.apply(nodes[id]);
                }
            }
            done.iter_mut().for_each(|d| *d = false);
            self.enforce_nodes(nodes, &ids, &mut done);
        }
    }

    fn enforce_poles(&self, grid: &mut Grid, listed: &[PoleEnd]) {
        let Some(plane) = self.plane() else {
            return;
        };
        for pole in grid.poles() {
            let partner_end = self.pole_partner(pole.end);
            if !listed.contains(&pole.end) && !listed.contains(&partner_end) {
                continue;
            }
            if partner_end != pole.end && pole.end == PoleEnd::End {
                continue; // set from its partner
            }
            let o = grid.nodes()[pole.node];
            let Some(mut n) = plane_normal(pole.ring.iter().map(|&id| grid.nodes()[id] - o)) else {
                continue;
            };
            if partner_end == pole.end {
                // A symmetric plane: its normal in the mirror plane or along its axis.
                let mut a = n.to_array();
                let k = plane.axis();
                if a[k].abs() <= (1.0 - a[k] * a[k]).max(0.0).sqrt() {
                    a[k] = 0.0;
                } else {
                    a = [0.0; 3];
                    a[k] = 1.0;
                }
                let Some(sym) = DVec3::from_array(a).try_normalize() else {
                    continue;
                };
                n = sym;
            }
            let nodes = grid.nodes_mut();
            for &id in &pole.ring {
                nodes[id] -= n * n.dot(nodes[id] - o);
            }
            // Exact partners again.
            for &id in &pole.ring {
                let partner = self.node_partner(id);
                if partner == id {
                    nodes[id] = (nodes[id] + plane.reflect(nodes[id])) * 0.5;
                } else if partner_end != pole.end || id < partner {
                    nodes[partner] = plane.reflect(nodes[id]);
                }
            }
            if partner_end != pole.end {
                let p = self.node_partner(pole.node);
                nodes[p] = plane.reflect(nodes[pole.node]);
            }
        }
    }
}

/// The plane of an isometry that is one mirror.
/// Whether `a` and `b` are the same linear map (equal on the basis, to rounding).
fn same_map(a: &Isometry, b: &Isometry) -> bool {
    [DVec3::X, DVec3::Y, DVec3::Z]
        .iter()
        .all(|&e| (a.apply(e) - b.apply(e)).length() < 1e-9)
}

fn single_plane(iso: &Isometry) -> Option<Plane> {
    if iso.turns() {
        return None;
    }
    match iso.flips() {
        [true, false, false] => Some(Plane::X),
        [false, true, false] => Some(Plane::Y),
        [false, false, true] => Some(Plane::Z),
        _ => None,
    }
}

/// A unit normal near `n` whose plane every isometry of `stabiliser` keeps (see
/// [`Symmetry`]).
fn symmetric_normal(n: DVec3, stabiliser: &[&Isometry]) -> Option<DVec3> {
    let mut a = n.to_array();
    for g in stabiliser {
        let (turn, of) = g.turn();
        let quarter = (4 * u64::from(turn)).is_multiple_of(u64::from(of));
        let half = quarter && (4 * u64::from(turn) / u64::from(of)) % 2 == 0;
        if !half {
            // A turn of order ≥ 3 (or a quarter turn) fixes only the axis.
            a = [0.0, 0.0, if a[2] < 0.0 { -1.0 } else { 1.0 }];
            continue;
        }
        // A diagonal sign matrix: the normal within the negated or the kept coordinates.
        let m = g.matrix();
        let negated = [m.x_axis.x < 0.0, m.y_axis.y < 0.0, m.z_axis.z < 0.0];
        let (mut neg, mut kept) = (0.0, 0.0);
        for k in 0..3 {
            if negated[k] {
                neg += a[k] * a[k];
            } else {
                kept += a[k] * a[k];
            }
        }
        for k in 0..3 {
            if negated[k] == (neg < kept) {
                a[k] = 0.0;
            }
        }
    }
    DVec3::from_array(a).try_normalize()
}

impl Element {
    fn new(grid: &Grid, iso: Isometry, mu: LatticeMap, mv: LatticeMap) -> Self {
        let (m, n) = (grid.patches_u(), grid.patches_v());
        let (la, lb) = grid.lattice_size();
        let mut nodes = vec![0usize; grid.nodes().len()];
        for b in 0..lb {
            for a in 0..la {
                if let (Some(id), Some(p)) = (
                    grid.node_id(a as isize, b as isize),
                    grid.node_id(mu.apply(a), mv.apply(b)),
                ) {
                    nodes[id] = p;
                }
            }
        }
        let patch_of = |map: LatticeMap, i: usize, count: usize, closed: bool| -> usize {
            match map {
                LatticeMap::Identity => i,
                LatticeMap::Shift { s, .. } => (i + s / 3) % count,
                // Columns 3i..3i+3 go to c − 3i − 3 .. c − 3i.
                LatticeMap::Reflect { c, .. } => {
                    let start = c as isize - 3 * i as isize - 3;
                    let p = start.div_euclid(3);
                    if closed {
                        p.rem_euclid(count as isize) as usize
                    } else {
                        p as usize
                    }
                }
            }
        };
        let t = grid.topology();
        let mut patches = vec![0usize; m * n];
        for iv in 0..n {
            for iu in 0..m {
                let pu = patch_of(mu, iu, m, t.closed_u());
                let pv = patch_of(mv, iv, n, t.closed_v());
                patches[iv * m + iu] = pv * m + pu;
            }
        }
        Element {
            iso,
            inverse: iso.inverse(),
            mu,
            mv,
            nodes,
            patches,
        }
    }

    fn vertex_image(&self, grid: &Grid, k: usize, q: usize) -> (usize, usize) {
        let wrap = |x: isize, len: usize| x.rem_euclid(len as isize) as usize;
        let (vu, vv) = (grid.vertices_u(), grid.vertices_v());
        (
            wrap(self.mu.apply(3 * k) / 3, vu),
            wrap(self.mv.apply(3 * q) / 3, vv),
        )
    }

    fn pole_image(&self, end: PoleEnd) -> PoleEnd {
        match (self.mv.reverses(), end) {
            (false, e) => e,
            (true, PoleEnd::Start) => PoleEnd::End,
            (true, PoleEnd::End) => PoleEnd::Start,
        }
    }
}

/// The node, patch, vertex and pole maps of one isometry, for the engine's landing of a move
/// ([`crate::surface::grab`]).
impl Symmetry {
    /// The image of grid vertex `(k, q)` under element `e` (an index into
    /// [`Symmetry::isometries`]).
    pub(crate) fn vertex_image(&self, e: usize, grid: &Grid, k: usize, q: usize) -> (usize, usize) {
        self.elements[e].vertex_image(grid, k, q)
    }

    /// The image of a pole under element `e`.
    pub(crate) fn pole_image(&self, e: usize, end: PoleEnd) -> PoleEnd {
        self.elements[e].pole_image(end)
    }

    /// The image of node `id` under element `e`.
    pub(crate) fn node_image(&self, e: usize, id: usize) -> usize {
        self.elements[e].nodes[id]
    }
}

/// How far `grid` is from being invariant under every isometry of `symmetry`'s group, with
/// the node maps it was made with (relative to the model's size, as [`Asymmetry::relative`]).
#[must_use]
pub fn group_error(grid: &Grid, symmetry: &Symmetry) -> f64 {
    if !symmetry.fits(grid) {
        return f64::INFINITY;
    }
    let nodes = grid.nodes();
    let scale = nodes
        .iter()
        .map(|x| x.length())
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    let mut worst = 0.0f64;
    for e in &symmetry.elements {
        for (id, x) in nodes.iter().enumerate() {
            worst = worst.max((e.iso.apply(*x) - nodes[e.nodes[id]]).length());
        }
    }
    worst / scale
}
