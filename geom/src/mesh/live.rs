//! Live re-tessellation: keeping a mesh up to date patch by patch while a stroke changes a
//! few patches, in place as long as the segment counts hold ([`LiveTessellation`]).

use std::collections::HashMap;

use super::plan::{Plan, Tessellation};
#[cfg(doc)]
use super::tessellate::tessellate;
use super::tessellate::{PatchPoints, build_with_bounds, write_patch_vertices};
use super::trimesh::TriMesh;

/// What it takes to keep a tessellation up to date patch by patch while a few patches change
/// (a live stroke): only the changed patches are evaluated again, in place in the mesh, as
/// long as the segment counts stay what they were. The mesh itself stays the caller's (it is
/// what the display draws); it must be the one [`LiveTessellation::new`] returned, as the
/// updates since left it.
///
/// The counts of a patch come from the largest own count of its tied class (a row or column
/// of the grid, tied through the edges its patches share). After an update the own counts of the changed patches
/// are measured again and the maxima of their classes recomputed; if any class's count
/// changes, the block layout changes with it: the whole mesh is rebuilt
/// ([`MeshUpdate::Rebuilt`]) — or, when the caller asks to keep the counts (a live stroke,
/// where a dent deepening frame by frame would otherwise rebuild at every step), the changed
/// patches are evaluated again with the counts they had and the mesh is marked
/// [`LiveTessellation::counts_stale`]: its vertices lie on the exact surface but the
/// tolerance may be exceeded there ([`TriMesh::error_bound`] says by how much) until the
/// next update that does not keep counts rebuilds it. No capacity is reserved per patch:
/// a changed count changes every patch of the row or column anyway. The classes themselves
/// are those of the last full build: they follow from which edges the patches share, which
/// sculpting does not change (a rebuild re-derives them).
///
/// An update in place that did not keep stale counts gives the mesh [`tessellate`] would
/// give for the same patches, bit for bit: the same per-patch evaluation writes the same
/// vertices.
#[derive(Debug, Clone)]
pub struct LiveTessellation {
    settings: Tessellation,
    plan: Plan,
    /// Members of each class, by class representative (CSR: `members[starts[r]..starts[r+1]]`
    /// for the representative's position `r` in `representatives`).
    class_index: HashMap<usize, (usize, usize)>,
    class_members: Vec<usize>,
    /// The error bound of every patch.
    bounds: Vec<f64>,
    /// Some counts are not those the patches need (kept during a live stroke).
    stale: bool,
}

/// What [`LiveTessellation::update`] did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MeshUpdate {
    /// The vertices of these blocks (patch indices, sorted) were written again in place;
    /// the indices and every other block are unchanged.
    InPlace(Vec<usize>),
    /// The segment counts changed: the whole mesh was rebuilt (new block layout).
    Rebuilt,
}

impl LiveTessellation {
    /// Tessellates `patches` (the mesh [`tessellate`] makes) and keeps what updating needs.
    #[must_use]
    pub fn new(patches: &[PatchPoints], settings: &Tessellation) -> (Self, TriMesh) {
        let plan = Plan::new(patches, settings);
        let (mesh, bounds) = build_with_bounds(patches, &plan);
        let mut live = Self {
            settings: *settings,
            plan,
            class_index: HashMap::new(),
            class_members: Vec::new(),
            bounds,
            stale: false,
        };
        live.index_classes();
        (live, mesh)
    }

    fn index_classes(&mut self) {
        let mut by_class: HashMap<usize, Vec<usize>> = HashMap::new();
        for (x, &c) in self.plan.classes.iter().enumerate() {
            by_class.entry(c).or_default().push(x);
        }
        self.class_index.clear();
        self.class_members.clear();
        for (c, members) in by_class {
            let start = self.class_members.len();
            self.class_members.extend(members);
            self.class_index
                .insert(c, (start, self.class_members.len()));
        }
    }

    /// Brings `mesh` up to `patches`, of which only those listed in `changed` differ from
    /// the patches last given (the same number of patches; otherwise, or when the segment
    /// counts change, everything is rebuilt). Afterwards `mesh` is what [`tessellate`] makes
    /// of `patches`. Costs what the changed patches and their rows and columns cost when the
    /// counts hold.
    ///
    /// With `keep_counts`, a change of segment counts does not rebuild: see the type's docs.
    pub fn update(
        &mut self,
        mesh: &mut TriMesh,
        patches: &[PatchPoints],
        changed: &[usize],
        keep_counts: bool,
    ) -> MeshUpdate {
        if self.stale && !keep_counts {
            return self.rebuild(mesh, patches);
        }
        if patches.len() != self.plan.own.len()
            || mesh.blocks.len() != patches.len()
            || changed.iter().any(|&p| p >= patches.len())
        {
            return self.rebuild(mesh, patches);
        }
        for &p in changed {
            self.plan.own[p] = self.settings.own_counts(&patches[p]);
        }
        // The classes of the changed patches' directions, each once.
        let mut classes: Vec<usize> = changed
            .iter()
            .flat_map(|&p| [self.plan.classes[2 * p], self.plan.classes[2 * p + 1]])
            .collect();
        classes.sort_unstable();
        classes.dedup();
        for c in classes {
            let Some(&(a, b)) = self.class_index.get(&c) else {
                return self.rebuild(mesh, patches);
            };
            let members = &self.class_members[a..b];
            let max = members
                .iter()
                .map(|&x| self.plan.own[x / 2].0[x % 2])
                .max()
                .unwrap_or(0);
            if members
                .iter()
                .any(|&x| self.plan.counts[x / 2][x % 2] != max)
            {
                if keep_counts {
                    self.stale = true;
                } else {
                    return self.rebuild(mesh, patches);
                }
            }
        }
        let mut blocks: Vec<usize> = changed.to_vec();
        blocks.sort_unstable();
        blocks.dedup();
        for &p in &blocks {
            let block = mesh.blocks[p];
            let [a, b] = self.plan.own[p].1;
            let (m_u, m_v) = (f64::from(block.m_u), f64::from(block.m_v));
            self.bounds[p] = (a / (m_u * m_u) + b / (m_v * m_v)) / 8.0;
            let range =
                block.first_vertex as usize..(block.first_vertex + block.vertex_count()) as usize;
            write_patch_vertices(
                &patches[p],
                &block,
                &mut mesh.positions[range.clone()],
                &mut mesh.normals[range],
            );
        }
        mesh.error_bound = self.bounds.iter().fold(0.0, |m: f64, b| m.max(*b));
        MeshUpdate::InPlace(blocks)
    }

    /// True when some segment counts were kept that the patches no longer need (see the
    /// type's docs): the mesh is on the surface but may miss the tolerance.
    #[must_use]
    pub fn counts_stale(&self) -> bool {
        self.stale
    }

    fn rebuild(&mut self, mesh: &mut TriMesh, patches: &[PatchPoints]) -> MeshUpdate {
        (*self, *mesh) = Self::new(patches, &self.settings);
        MeshUpdate::Rebuilt
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{eval_patch, tessellate};
    use glam::DVec3;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn a_live_update_gives_the_full_tessellation_bit_for_bit() {
        use crate::mesh::{seam_angles_deg, update_seam_angles_deg};
        use crate::surface::{Op, Primitive, PrimitiveParams, Regulation, Sculptor};
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        let (mut in_place, mut rebuilt) = (0, 0);
        for primitive in [Primitive::Plane, Primitive::Sphere, Primitive::Torus] {
            let mut grid = primitive.build(&PrimitiveParams::default()).unwrap();
            let (mut live, mut mesh) =
                LiveTessellation::new(&grid.patches(), &Tessellation::DISPLAY);
            let mut sculptor = Sculptor::new();
            let nodes = grid.nodes().to_vec();
            for _ in 0..25 {
                let at = nodes[rng.gen_range(0..nodes.len())];
                let op = Op::Push {
                    at,
                    dir: DVec3::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), 1.0),
                    depth: rng.gen_range(-0.3..0.3),
                    radius: rng.gen_range(0.4..1.5),
                };
                let Ok(touched) = sculptor.apply(&mut grid, &op, Regulation::Exact) else {
                    continue;
                };
                let patches = grid.patches();
                match live.update(&mut mesh, &patches, &touched.patches, false) {
                    MeshUpdate::InPlace(blocks) => {
                        in_place += 1;
                        assert_eq!(blocks, touched.patches);
                    }
                    MeshUpdate::Rebuilt => rebuilt += 1,
                }
                let full = tessellate(&patches, &Tessellation::DISPLAY);
                assert_eq!(mesh, full, "{primitive:?}");
                // Seam angles recomputed on a few blocks, in the context of all of them.
                let want = seam_angles_deg(&patches, &full);
                let mut got = want.clone();
                let targets: Vec<usize> = touched.patches.clone();
                for &t in &targets {
                    let b = full.blocks[t];
                    got[b.first_vertex as usize..(b.first_vertex + b.vertex_count()) as usize]
                        .fill(-1.0);
                }
                let all: Vec<usize> = (0..full.blocks.len()).collect();
                update_seam_angles_deg(&patches, &full, &all, &targets, &mut got);
                assert_eq!(got, want);
            }
        }
        assert!(
            in_place > 10 && rebuilt > 0,
            "{in_place} in place, {rebuilt} rebuilt"
        );
    }

    #[test]
    fn kept_counts_stay_on_the_surface_until_the_next_full_update() {
        use crate::surface::{Op, Primitive, PrimitiveParams, Regulation, Sculptor};
        let mut grid = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
        let (mut live, mut mesh) = LiveTessellation::new(&grid.patches(), &Tessellation::DISPLAY);
        let blocks = mesh.blocks.clone();
        let mut sculptor = Sculptor::new();
        for k in 1..=4 {
            let op = Op::Push {
                at: DVec3::new(0.2, 0.1, 0.0),
                dir: -DVec3::Z,
                depth: 0.3 * f64::from(k),
                radius: 1.25,
            };
            let touched = sculptor.apply(&mut grid, &op, Regulation::Exact).unwrap();
            let patches = grid.patches();
            let update = live.update(&mut mesh, &patches, &touched.patches, true);
            assert!(matches!(update, MeshUpdate::InPlace(_)));
            assert_eq!(mesh.blocks, blocks, "the layout is kept");
            for b in &mesh.blocks {
                for v in b.first_vertex..b.first_vertex + b.vertex_count() {
                    let (u, w) = b.uv_of(v);
                    let exact = eval_patch(&patches[b.patch as usize], u, w).0;
                    assert!((mesh.positions[v as usize].as_dvec3() - exact).length() < 1e-5);
                }
            }
        }
        assert!(live.counts_stale(), "a deepening dent needs more segments");
        let patches = grid.patches();
        assert_eq!(
            live.update(&mut mesh, &patches, &[], false),
            MeshUpdate::Rebuilt
        );
        assert!(!live.counts_stale());
        assert_eq!(mesh, tessellate(&patches, &Tessellation::DISPLAY));
    }
}
