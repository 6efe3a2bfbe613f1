//! [`Sculptor`]: one operation of the shape functions at a time — a finger on the current grid
//! ([`FingerField`]) run through [`displace`], then the [`Commit`] transaction.

use glam::DVec3;

use super::commit::{Commit, other_grid};
use super::field::{DisplacementField, Envelope, displace, patch_update};
use crate::surface::Isometry;
use crate::surface::bounds::Aabb;
use crate::surface::error::SurfaceError;
use crate::surface::fairing::Fairing;
use crate::surface::grab::Hold;
use crate::surface::grid::Grid;
use crate::surface::group::PoleEnd;
use crate::surface::marks::Marks;
use crate::surface::mirror::Symmetry;
use crate::surface::nearest::nearest;
use crate::surface::regulate::Regulation;
use crate::surface::shape_fn::{Finger, Op};
use crate::surface::smooth::{EnergyDrop, HALVINGS, energy_of, patch_energy, thin_plate_matrix};
use crate::surface::topology::wrap;
use std::collections::HashMap;

/// What one operation changed.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Touched {
    /// Indices (`iv * M + iu`, increasing) of every patch whose control points may have
    /// changed: the patches the finger moved and their neighbours through regulated groups.
    pub patches: Vec<usize>,
    /// How many patches the finger itself moved.
    pub deformed: usize,
    /// How many patches the box pyramid let through for sampling (at least `deformed`).
    pub examined: usize,
    /// How many groups and poles were regulated.
    pub groups: usize,
}

/// Deforms grids; keeps the scratch buffers between operations so that an operation costs
/// what it touches (reuse one `Sculptor` for a stream of operations).
#[derive(Debug, Clone, Default)]
pub struct Sculptor {
    /// Nodes already moved by this operation's update (shared nodes move once).
    written: Marks,
    vertex_marks: Marks,
    candidates: Vec<usize>,
    updates: Vec<(usize, [DVec3; 16])>,
    segments: Vec<usize>,
    vertices: Vec<(usize, usize)>,
    poles: Vec<PoleEnd>,
    smoothing: Fairing,
    commit: Commit,
    last_energy: Option<EnergyDrop>,
}

/// One finger of the shape functions on the current grid, with its images under a symmetry
/// (all combined by the [`Envelope`]).
struct FingerField<'a> {
    finger: &'a Finger,
    /// How far behind its tip the finger reaches ([`Finger::reach_depth`]).
    depth: f64,
    /// The symmetry's images of the field ([`Symmetry::field_images`]; empty: none).
    images: &'a [Isometry],
    /// The finger's segments that may reach the patch at hand (one-sided only).
    segments: &'a mut Vec<usize>,
}

impl DisplacementField for FingerField<'_> {
    fn may_touch(&self, b: &Aabb) -> bool {
        self.finger.may_touch(b, self.depth)
            || self
                .images
                .iter()
                .any(|g| self.finger.may_touch(&g.inverse().apply_box(b), self.depth))
    }

    fn touches(&mut self, _patch: usize, bounds: &Aabb) -> bool {
        !self.images.is_empty() || self.finger.restricted_to(bounds, self.depth, self.segments)
    }

    fn flows(&mut self, _patch: usize, _bounds: &Aabb, r: &[DVec3; 16]) -> [DVec3; 16] {
        if self.images.is_empty() {
            return std::array::from_fn(|k| self.finger.flow_over(r[k], self.segments));
        }
        // g F(g⁻¹ x): the image of the field under g, for every g of the group.
        let pairs: Vec<(Isometry, Isometry)> =
            self.images.iter().map(|g| (*g, g.inverse())).collect();
        std::array::from_fn(|k| {
            let mut e = Envelope::default();
            e.add(self.finger.flow(r[k]));
            for (g, inv) in &pairs {
                e.add(g.apply(self.finger.flow(inv.apply(r[k]))));
            }
            e.flow()
        })
    }
}

/// Applies one operation to a grid with a fresh [`Sculptor`] (allocates buffers the size of
/// the grid; use a `Sculptor` for a stream of operations).
///
/// # Errors
/// [`SurfaceError::BadOp`] for an invalid operation; the grid is then unchanged.
pub fn deform(grid: &mut Grid, op: &Op, regulation: Regulation) -> Result<Touched, SurfaceError> {
    Sculptor::new().apply(grid, op, regulation)
}

impl Sculptor {
    /// A sculptor with empty buffers.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// A sculptor whose [`Regulation::Exact`] projects group by group, each group nearest to
    /// the unregulated net in its own control points, instead of the default coupled
    /// projection (every connected set of touched groups together, nearest in `∫|ΔS|²` over
    /// the patches around them: [`crate::surface::regulate`]). Kept for comparison:
    /// `nendo bench regulation` and `nendo bench sculpt` measure it next to the default.
    #[must_use]
    pub fn with_group_by_group_exact() -> Self {
        let mut s = Self::default();
        s.commit.projections.coupled = false;
        s
    }

    /// Applies one operation: push, pull, draw a line (along a fixed direction, per-point
    /// directions or the surface normals), move, smooth, or a surface brush (inflate, flatten,
    /// pinch, crease).
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] for an invalid operation; [`SurfaceError::OutOfRange`] or
    /// [`SurfaceError::NotG1`] for a result that is refused (see [`crate::surface::verify()`]).
    /// The grid is then exactly as it was.
    pub fn apply(
        &mut self,
        grid: &mut Grid,
        op: &Op,
        regulation: Regulation,
    ) -> Result<Touched, SurfaceError> {
        self.apply_with(grid, op, regulation, None)
    }

    /// Applies one operation together with its images under the symmetry (its mirror image
    /// across a plane; every image under a group of mirrors and turns; the operation turned
    /// all the way round for a lathe), as one operation: the displacement fields combined by
    /// the engine's one envelope rule (each sample moves by the strongest flow; by the mean
    /// of the equally strongest), regulated once, then made exactly symmetric
    /// ([`Symmetry::enforce`]); a move lands every image of the grabbed point, a smoothing
    /// stroke relaxes every image of its region.
    ///
    /// # Errors
    /// As [`Sculptor::apply`]; [`SurfaceError::BadOp`] when the symmetry was made for a grid
    /// of other patch counts.
    pub fn apply_mirrored(
        &mut self,
        grid: &mut Grid,
        op: &Op,
        regulation: Regulation,
        symmetry: &Symmetry,
    ) -> Result<Touched, SurfaceError> {
        self.apply_with(grid, op, regulation, Some(symmetry))
    }

    /// How far the last mirrored operation's result was from symmetric before it was made
    /// exactly symmetric (relative to the model's size; 0 after an unmirrored operation).
    #[must_use]
    pub fn last_asymmetry(&self) -> f64 {
        self.commit.asymmetry()
    }

    /// `(node, old position)` of every control point the last operation wrote, each once.
    pub(crate) fn journal(&self) -> &[(usize, DVec3)] {
        self.commit.journal()
    }

    /// The thin-plate energy of the patches the last smoothing stroke touched, before and
    /// after it (`None` until a smoothing stroke ran).
    #[must_use]
    pub fn last_energy(&self) -> Option<EnergyDrop> {
        self.last_energy
    }

    /// [`Sculptor::apply`] without a mirror, [`Sculptor::apply_mirrored`] with one.
    pub(crate) fn apply_with(
        &mut self,
        grid: &mut Grid,
        op: &Op,
        regulation: Regulation,
        symmetry: Option<&Symmetry>,
    ) -> Result<Touched, SurfaceError> {
        if symmetry.is_some_and(|s| !s.fits(grid)) {
            return Err(other_grid());
        }
        op.validate()?;
        self.commit.begin(grid);
        match op {
            Op::Move { at, to, radius } => {
                let near = nearest(grid, *at)
                    .ok_or_else(|| SurfaceError::BadOp("no surface point to grab".to_string()))?;
                let finger = Finger::ball(near.point, *to - near.point, *radius);
                let hold = Hold {
                    patch: near.patch,
                    u: near.u,
                    v: near.v,
                    to: *to,
                };
                self.apply_field(grid, &finger, regulation, symmetry, Some(hold))
            }
            Op::Smooth {
                at,
                radius,
                strength,
            } => self.apply_smooth(grid, *at, *radius, *strength, regulation, symmetry),
            Op::Sculpt(brush) => self.apply_sculpt(grid, brush, regulation, symmetry),
            _ => {
                let finger = op.finger_on(grid)?;
                self.apply_field(grid, &finger, regulation, symmetry, None)
            }
        }
    }

    /// Applies a validated finger.
    ///
    /// # Errors
    /// [`SurfaceError::OutOfRange`] or [`SurfaceError::NotG1`] (see
    /// [`crate::surface::verify()`]); the grid is then exactly as it was.
    pub fn apply_finger(
        &mut self,
        grid: &mut Grid,
        finger: &Finger,
        regulation: Regulation,
    ) -> Result<Touched, SurfaceError> {
        self.apply_field(grid, finger, regulation, None, None)
    }

    fn apply_field(
        &mut self,
        grid: &mut Grid,
        finger: &Finger,
        regulation: Regulation,
        symmetry: Option<&Symmetry>,
        hold: Option<Hold>,
    ) -> Result<Touched, SurfaceError> {
        let mut segments = std::mem::take(&mut self.segments);
        let mut field = FingerField {
            finger,
            depth: finger.reach_depth(&grid.bounds()),
            images: symmetry.map_or(&[], Symmetry::field_images),
            segments: &mut segments,
        };
        let examined = self.gather(grid, &mut field, symmetry, hold.as_ref());
        self.segments = segments;
        self.commit_updates(grid, regulation, symmetry, hold.as_ref(), examined)
    }

    /// Steps 1–3 of the engine for one field on the unchanged `grid`: the patches it may
    /// reach, their flows and control-point updates into `self.updates` (a move's grabbed
    /// patches included); returns how many patches were examined.
    pub(super) fn gather(
        &mut self,
        grid: &Grid,
        field: &mut impl DisplacementField,
        symmetry: Option<&Symmetry>,
        hold: Option<&Hold>,
    ) -> usize {
        // 1. Reach (and the mirror image's).
        self.candidates.clear();
        grid.hierarchy()
            .query(&|b| field.may_touch(b), &mut self.candidates);
        // 2–3. Flows and control-point updates, from the unchanged net.
        self.updates.clear();
        let updates = &mut self.updates;
        displace(grid, &self.candidates, field, |p, delta| {
            if let Some(delta) = delta {
                updates.push((p, delta));
            }
        });
        // A move lands on its grabbed patch (and its mirror image's) even where the falloff
        // moved none of its samples.
        if let Some(h) = hold {
            let mut held = vec![h.patch];
            if let Some(s) = symmetry {
                held.extend(s.patch_images(h.patch));
            }
            for p in held {
                if !self.updates.iter().any(|(q, _)| *q == p) {
                    self.updates.push((p, [DVec3::ZERO; 16]));
                }
            }
        }
        self.candidates.len()
    }

    /// Writes the updates in `self.updates` and commits them: the groups around the moved
    /// patches regulated, the mirror, the move's landing, verification (restoring the grid
    /// on a refusal), boxes.
    pub(super) fn commit_updates(
        &mut self,
        grid: &mut Grid,
        regulation: Regulation,
        symmetry: Option<&Symmetry>,
        hold: Option<&Hold>,
        examined: usize,
    ) -> Result<Touched, SurfaceError> {
        let (m, n) = (grid.patches_u(), grid.patches_v());
        let topology = grid.topology();
        let nodes_changed = !self.updates.is_empty();
        let deformed = self.updates.len();
        self.commit.begin(grid);
        for (p, _) in &self.updates {
            self.commit.include(*p);
        }
        // The groups around the moved patches, and every patch their regulation (or a move's
        // landing) may change.
        let regulating = nodes_changed && regulation != Regulation::None;
        self.vertices.clear();
        self.poles.clear();
        if regulating || (nodes_changed && hold.is_some()) {
            self.collect_groups(grid);
            for &(k, q) in &self.vertices {
                for (du, dv) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let Some(iu) = wrap(k as isize - du, m, topology.closed_u()) else {
                        continue;
                    };
                    let Some(iv) = wrap(q as isize - dv, n, topology.closed_v()) else {
                        continue;
                    };
                    self.commit.include(iv * m + iu);
                }
            }
            for &end in &self.poles {
                let iv = if end == PoleEnd::Start { 0 } else { n - 1 };
                for iu in 0..m {
                    self.commit.include(iv * m + iu);
                }
            }
        }
        // Everything that may change, kept aside to restore on a refusal, then the update.
        self.commit.keep_included(grid);
        self.written.start(grid.nodes().len());
        {
            let shape = grid.shape();
            let nodes = grid.nodes_mut();
            for (p, delta) in &self.updates {
                let (iu, iv) = (p % m, p / m);
                for i in 0..4 {
                    for j in 0..4 {
                        let id = shape.local_id(iu, iv, i, j);
                        if self.written.mark(id) {
                            nodes[id] += delta[4 * i + j];
                        }
                    }
                }
            }
        }
        let (vertices, poles): (&[(usize, usize)], &[PoleEnd]) = if regulating {
            (&self.vertices, &self.poles)
        } else {
            (&[], &[])
        };
        let groups = self
            .commit
            .finish(grid, regulation, vertices, poles, symmetry, hold)?;
        Ok(Touched {
            patches: self.commit.changed().to_vec(),
            deformed,
            examined,
            groups,
        })
    }

    /// A smoothing dab: the implicit fairing of the samples under the brush
    /// ([`crate::surface::fairing`]) taken through the Bernstein inverse
    /// ([`patch_update`]), then committed like every operation; a dab whose regulated result
    /// does not lower the thin-plate energy of what it touched ([`crate::surface::smooth`]) is
    /// taken again at half the strength.
    fn apply_smooth(
        &mut self,
        grid: &mut Grid,
        at: DVec3,
        radius: f64,
        strength: f64,
        regulation: Regulation,
        symmetry: Option<&Symmetry>,
    ) -> Result<Touched, SurfaceError> {
        let h = thin_plate_matrix();
        let centres: Vec<DVec3> = std::iter::once(at)
            .chain(
                symmetry
                    .map_or(&[][..], Symmetry::field_images)
                    .iter()
                    .map(|g| g.apply(at)),
            )
            .collect();
        let mut step = strength;
        let mut last = EnergyDrop::default();
        let (m, n, topology) = (grid.patches_u(), grid.patches_v(), grid.topology());
        for halvings in 0..=HALVINGS {
            self.smoothing
                .flows(grid, &centres, radius, step, &mut self.updates);
            for (p, flows) in &mut self.updates {
                *flows = patch_update(flows, *p / m, n, topology);
            }
            if self.updates.is_empty() {
                break;
            }
            let examined = self.smoothing.candidates.len();
            let touched = self.commit_updates(grid, regulation, symmetry, None, examined)?;
            let after = energy_of(grid, &touched.patches);
            let before = {
                let old: HashMap<usize, DVec3> = self.commit.journal().iter().copied().collect();
                let m = grid.patches_u();
                touched
                    .patches
                    .iter()
                    .map(|&p| {
                        let pts = grid
                            .patch_node_ids(p % m, p / m)
                            .map(|id| old.get(&id).copied().unwrap_or(grid.nodes()[id]));
                        patch_energy(&h, &pts)
                    })
                    .sum::<f64>()
            };
            last = EnergyDrop {
                before,
                after: before,
                halvings,
            };
            if after < before {
                last.after = after;
                self.last_energy = Some(last);
                return Ok(touched);
            }
            self.commit.rollback(grid);
            grid.refit(&touched.patches, &mut self.candidates);
            step *= 0.5;
        }
        // Nothing in reach, or no step the regulation kept lowered the energy: no change.
        self.last_energy = Some(last);
        Ok(Touched::default())
    }

    /// The grid vertices at the corners of the moved patches (deduplicated, in a fixed
    /// order), and the poles they touch.
    fn collect_groups(&mut self, grid: &Grid) {
        let m = grid.patches_u();
        let vu = grid.vertices_u();
        let vv = grid.vertices_v();
        self.vertex_marks.start(vu * vv);
        self.vertices.clear();
        self.poles.clear();
        for (p, _) in &self.updates {
            let (iu, iv) = (p % m, p / m);
            for (du, dv) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let k = (iu + du) % vu;
                let q = (iv + dv) % vv;
                if grid.is_pole_line(q) {
                    let end = if q == 0 { PoleEnd::Start } else { PoleEnd::End };
                    if !self.poles.contains(&end) {
                        self.poles.push(end);
                    }
                    continue;
                }
                if self.vertex_marks.mark(q * vu + k) {
                    self.vertices.push((k, q));
                }
            }
        }
        self.poles.sort_unstable_by_key(|e| *e == PoleEnd::End);
    }
}
