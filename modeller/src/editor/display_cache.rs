//! What the window derives from the document and keeps until the document changes: the
//! patches' control points, the tessellated surface, the continuity measure.
//!
//! ## Live updates
//!
//! When the document can say which patches changed since the revision shown
//! ([`Document::surface_changes_since`]: an operation, a stroke's frame, an undo), only those
//! are re-tessellated, in place ([`LiveTessellation`]), and the seam heat is recomputed only
//! around them: the seam angles of the changed patches and of their neighbours in the grid
//! (`R`, the ring: the patches sharing an edge or a corner, around a closed direction, and a
//! whole patch row at a pole), measured among `R` and its own neighbours — every vertex a
//! vertex of `R` can coincide with lies there, since patches of a grid meet only their grid
//! neighbours — and the heat bands of `R`. The result is the full rebuild's, bit for bit
//! (tested). The vertices of `R`'s blocks are what changed for the renderer:
//! [`DisplayCache::vertex_ranges_since`] gives them, so the window re-uploads only those.
//!
//! A full rebuild happens when the document cannot say (a new model, the hand loop), when
//! more than half the patches changed, or when a changed patch needs another segment count
//! and no gesture is in progress: the counts are tied along whole rows and columns of the
//! grid (see [`crate::mesh::LiveTessellation`]), so reserving room per patch would not spare
//! the rebuild. While a gesture is in progress (`busy`) the counts are kept instead — a dent
//! deepening frame by frame would otherwise rebuild at every step — and the changed patches
//! are drawn with the counts they had (on the exact surface, the tolerance possibly missed
//! there); the first refresh after the gesture rebuilds if counts went stale. Only then is
//! the display the full rebuild's bit for bit.
//!
//! Limits: the continuity measure waits while a gesture or a replay is in progress (it is
//! throttled to the end of a burst of edits on big grids).

use std::collections::VecDeque;
use std::ops::Range;
use std::time::Instant;

use super::document::Document;
use super::scene::SurfaceDisplay;
use crate::mesh::{
    LiveTessellation, MeshUpdate, PatchPoints, Tessellation, TriMesh, seam_angles_deg, seam_bands,
    update_seam_angles_deg, update_seam_bands,
};
use crate::surface::Grid;
use crate::surface::continuity::{self, ContinuityReport};

/// Display generations [`DisplayCache::vertex_ranges_since`] can look back over.
const UPLOAD_LOG_LEN: usize = 64;

/// The document's derived display data, rebuilt when its revision changes.
#[derive(Debug, Default)]
pub struct DisplayCache {
    /// The control points of every patch, at [`DisplayCache::revision`].
    patches: Vec<PatchPoints>,
    /// The tessellated surface.
    display: SurfaceDisplay,
    /// What updating the tessellation in place needs.
    live: Option<LiveTessellation>,
    /// Seam angle per vertex (degrees), the heat map's input.
    seam_deg: Vec<f32>,
    /// Largest seam angle per block.
    block_max_deg: Vec<f32>,
    /// The document revision the display shows (`None`: rebuild).
    revision: Option<u64>,
    /// Counts display changes across documents (a new document starts at revision 0 again).
    generation: u64,
    /// For recent generations, the vertex ranges that changed (`None`: everything).
    uploads: VecDeque<(u64, Option<Vec<Range<u32>>>)>,
    /// The continuity measure and the revision it is of.
    continuity: Option<ContinuityReport>,
    continuity_revision: Option<u64>,
    /// Time the last continuity measure took, ms.
    continuity_ms: f64,
}

impl DisplayCache {
    /// Forgets everything (a new document): the next [`DisplayCache::refresh`] rebuilds.
    pub fn invalidate(&mut self) {
        self.revision = None;
        self.continuity_revision = None;
    }

    /// Brings the patches and tessellation up to `doc`'s revision — only the changed patches
    /// when the document says which (see the module docs) — and the continuity measure too
    /// unless `busy` (a gesture or replay in progress). True when the surface display changed.
    pub fn refresh(&mut self, doc: &Document, busy: bool) -> bool {
        let revision = doc.revision();
        let mut changed_display = false;
        if self.revision != Some(revision) || self.stale_after(busy) {
            let grid = &doc.model().surface;
            let changes = self
                .revision
                .filter(|_| self.live.is_some() && self.patches.len() == grid.patch_count())
                .and_then(|shown| doc.surface_changes_since(shown));
            match changes {
                Some(patches) if patches.is_empty() && !self.stale_after(busy) => {}
                Some(patches) if 2 * patches.len() <= grid.patch_count() => {
                    self.update_patches(grid, &patches, busy);
                    changed_display = true;
                }
                _ => {
                    self.rebuild(grid);
                    changed_display = true;
                }
            }
            self.revision = Some(revision);
        }
        // The continuity measure (33 points per shared edge) is cheap for the paper's sizes.
        if self.continuity_revision != Some(revision) && !busy {
            let start = Instant::now();
            self.continuity = Some(continuity::report(
                &doc.model().surface,
                continuity::MIN_SAMPLES_PER_EDGE,
            ));
            self.continuity_ms = start.elapsed().as_secs_f64() * 1e3;
            self.continuity_revision = Some(revision);
        }
        changed_display
    }

    /// Rebuilds everything from `grid`.
    fn rebuild(&mut self, grid: &Grid) {
        self.patches = grid.patches();
        let start = Instant::now();
        let (live, mesh) = LiveTessellation::new(&self.patches, &Tessellation::DISPLAY);
        let tessellate_ms = start.elapsed().as_secs_f64() * 1e3;
        self.live = Some(live);
        self.seam_deg = seam_angles_deg(&self.patches, &mesh);
        self.display = SurfaceDisplay {
            seam_heat: seam_bands(&mesh, &self.seam_deg, SurfaceDisplay::HEAT_BAND),
            mesh,
            max_seam_deg: 0.0,
            tessellate_ms,
        };
        self.block_max_deg = vec![0.0; self.display.mesh.blocks.len()];
        let all: Vec<usize> = (0..self.block_max_deg.len()).collect();
        self.note_block_maxima(&all);
        self.log_upload(None);
    }

    /// Re-tessellates the changed patches (sorted) in place, and the seam heat around them.
    /// True when the counts went stale during a gesture that is over.
    fn stale_after(&self, busy: bool) -> bool {
        !busy
            && self
                .live
                .as_ref()
                .is_some_and(LiveTessellation::counts_stale)
    }

    fn update_patches(&mut self, grid: &Grid, changed: &[usize], keep_counts: bool) {
        let start = Instant::now();
        for &p in changed {
            self.patches[p] = grid.patch_at(p);
        }
        let Some(live) = &mut self.live else {
            self.rebuild(grid);
            return;
        };
        match live.update(&mut self.display.mesh, &self.patches, changed, keep_counts) {
            MeshUpdate::Rebuilt => {
                let mesh = &self.display.mesh;
                self.seam_deg = seam_angles_deg(&self.patches, mesh);
                self.display.seam_heat =
                    seam_bands(mesh, &self.seam_deg, SurfaceDisplay::HEAT_BAND);
                self.block_max_deg = vec![0.0; mesh.blocks.len()];
                let all: Vec<usize> = (0..self.block_max_deg.len()).collect();
                self.note_block_maxima(&all);
                self.display.tessellate_ms = start.elapsed().as_secs_f64() * 1e3;
                self.log_upload(None);
            }
            MeshUpdate::InPlace(blocks) => {
                let ring = patch_ring(grid, &blocks);
                let context = patch_ring(grid, &ring);
                let mesh = &self.display.mesh;
                update_seam_angles_deg(&self.patches, mesh, &context, &ring, &mut self.seam_deg);
                update_seam_bands(
                    mesh,
                    &self.seam_deg,
                    SurfaceDisplay::HEAT_BAND,
                    &ring,
                    &mut self.display.seam_heat,
                );
                self.note_block_maxima(&ring);
                self.display.tessellate_ms = start.elapsed().as_secs_f64() * 1e3;
                let ranges = vertex_ranges(&self.display.mesh, &ring);
                self.log_upload(Some(ranges));
            }
        }
    }

    /// Updates the per-block largest seam angles of `blocks` and the overall largest.
    fn note_block_maxima(&mut self, blocks: &[usize]) {
        let mesh = &self.display.mesh;
        for &b in blocks {
            let block = mesh.blocks[b];
            let range =
                block.first_vertex as usize..(block.first_vertex + block.vertex_count()) as usize;
            self.block_max_deg[b] = self
                .seam_deg
                .get(range)
                .map_or(0.0, |a| a.iter().copied().fold(0.0, f32::max));
        }
        self.display.max_seam_deg = self.block_max_deg.iter().copied().fold(0.0, f32::max);
    }

    fn log_upload(&mut self, ranges: Option<Vec<Range<u32>>>) {
        self.generation += 1;
        if self.uploads.len() == UPLOAD_LOG_LEN {
            self.uploads.pop_front();
        }
        self.uploads.push_back((self.generation, ranges));
    }

    /// True when the display kept segment counts during a gesture that the surface no
    /// longer needs (see the module docs): until the next refresh outside a gesture, it is on
    /// the exact surface but not the full rebuild's layout.
    #[must_use]
    pub fn counts_stale(&self) -> bool {
        self.live
            .as_ref()
            .is_some_and(LiveTessellation::counts_stale)
    }

    /// The patches' control points.
    #[must_use]
    pub fn patches(&self) -> &[PatchPoints] {
        &self.patches
    }

    /// The tessellated surface.
    #[must_use]
    pub fn display(&self) -> &SurfaceDisplay {
        &self.display
    }

    /// Changes whenever [`DisplayCache::display`] does (also across documents).
    #[must_use]
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The vertex ranges of [`DisplayCache::display`]'s mesh (sorted, disjoint) that changed
    /// after display generation `generation` up to [`DisplayCache::generation`] — what a
    /// renderer holding the mesh of `generation` must upload again
    /// ([`crate::render::Renderer::update_surface_vertices`]); the indices did not change.
    /// `None` when the whole surface must be uploaded (a rebuild, a generation too far back).
    #[must_use]
    pub fn vertex_ranges_since(&self, generation: u64) -> Option<Vec<Range<u32>>> {
        if generation == self.generation {
            return Some(Vec::new());
        }
        if generation > self.generation {
            return None;
        }
        let first = self
            .uploads
            .iter()
            .position(|(g, _)| *g == generation + 1)?;
        let mut ranges = Vec::new();
        for (_, r) in self.uploads.iter().skip(first) {
            ranges.extend_from_slice(r.as_ref()?);
        }
        Some(merge_ranges(ranges))
    }

    /// The last continuity measure and how long it took (ms).
    #[must_use]
    pub fn continuity(&self) -> (Option<&ContinuityReport>, f64) {
        (self.continuity.as_ref(), self.continuity_ms)
    }
}

/// The patches of `patches` and their grid neighbours (sharing an edge or a corner, around
/// closed directions; the whole patch row at a pole), sorted.
#[must_use]
pub fn patch_ring(grid: &Grid, patches: &[usize]) -> Vec<usize> {
    let (m, n) = (grid.patches_u(), grid.patches_v());
    let topology = grid.topology();
    let mut mark = vec![false; m * n];
    let wrap = |i: isize, len: usize, closed: bool| -> Option<usize> {
        if closed {
            Some(i.rem_euclid(len as isize) as usize)
        } else {
            usize::try_from(i).ok().filter(|&i| i < len)
        }
    };
    for &p in patches.iter().filter(|&&p| p < m * n) {
        let (iu, iv) = ((p % m) as isize, (p / m) as isize);
        for dv in -1..=1 {
            let Some(jv) = wrap(iv + dv, n, topology.closed_v()) else {
                continue;
            };
            for du in -1..=1 {
                if let Some(ju) = wrap(iu + du, m, topology.closed_u()) {
                    mark[jv * m + ju] = true;
                }
            }
        }
        for (at_pole, row) in [
            (iv == 0 && topology.pole_at_start(), 0),
            (iv as usize + 1 == n && topology.pole_at_end(), n - 1),
        ] {
            if at_pole {
                mark[row * m..(row + 1) * m].fill(true);
            }
        }
    }
    mark.iter()
        .enumerate()
        .filter_map(|(p, &on)| on.then_some(p))
        .collect()
}

/// The vertex ranges of the given blocks (sorted), merged where they touch.
fn vertex_ranges(mesh: &TriMesh, blocks: &[usize]) -> Vec<Range<u32>> {
    merge_ranges(
        blocks
            .iter()
            .filter_map(|&b| mesh.blocks.get(b))
            .map(|b| b.first_vertex..b.first_vertex + b.vertex_count())
            .collect(),
    )
}

/// Sorts ranges and merges those that overlap or touch.
fn merge_ranges(mut ranges: Vec<Range<u32>>) -> Vec<Range<u32>> {
    ranges.sort_unstable_by_key(|r| r.start);
    let mut out: Vec<Range<u32>> = Vec::with_capacity(ranges.len());
    for r in ranges {
        match out.last_mut() {
            Some(last) if r.start <= last.end => last.end = last.end.max(r.end),
            _ => out.push(r),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;
    use crate::surface::{Op, Primitive, PrimitiveParams};
    use glam::DVec3;

    /// During a stroke (busy) every frame updates in place and the ranges cover every vertex
    /// that changed; after it the display is the full rebuild's, bit for bit, on every
    /// topology, poles and closed seams included.
    #[test]
    fn live_updates_give_the_full_rebuild() {
        for primitive in Primitive::ALL {
            let grid = primitive
                .build(&PrimitiveParams::default())
                .expect("primitive");
            let mut doc = Document::new(Model::new(grid));
            let mut cache = DisplayCache::default();
            cache.refresh(&doc, false);
            let nodes = doc.model().surface.nodes().to_vec();
            let mut partial = 0;
            for k in 0..10 {
                let at = nodes[(k * 7919) % nodes.len()];
                doc.begin_stroke("push");
                for step in 0..3 {
                    let shown = cache.display().clone();
                    let generation = cache.generation();
                    let op = Op::Push {
                        at,
                        dir: DVec3::new(0.3, -0.2, 1.0),
                        depth: 0.05 * f64::from(step + 1) * if k % 2 == 0 { 1.0 } else { -1.0 },
                        radius: 0.8,
                    };
                    let revision = doc.revision();
                    if doc.apply(&op).is_err() {
                        continue;
                    }
                    cache.refresh(&doc, true);
                    let changed = doc.surface_changes_since(revision).expect("an operation");
                    if 2 * changed.len() > doc.model().surface.patch_count() {
                        continue; // rebuilt whole: more than half the patches changed
                    }
                    let got = cache.display();
                    let ranges = cache
                        .vertex_ranges_since(generation)
                        .expect("a frame of a stroke updates in place");
                    assert_eq!(got.mesh.blocks, shown.mesh.blocks);
                    partial += 1;
                    let inside = |v: usize| ranges.iter().any(|r| r.contains(&(v as u32)));
                    for v in 0..got.mesh.positions.len() {
                        if got.mesh.positions[v] != shown.mesh.positions[v]
                            || got.mesh.normals[v] != shown.mesh.normals[v]
                            || got.seam_heat[v] != shown.seam_heat[v]
                        {
                            assert!(inside(v), "{primitive:?}: vertex {v} changed outside");
                        }
                    }
                }
                doc.end_stroke();
                cache.refresh(&doc, false);
                let full =
                    SurfaceDisplay::new(&doc.model().surface.patches(), &Tessellation::DISPLAY);
                let got = cache.display();
                assert_eq!(got.mesh, full.mesh, "{primitive:?}");
                assert!(got.seam_heat == full.seam_heat, "{primitive:?} seam heat");
                assert_eq!(got.max_seam_deg, full.max_seam_deg, "{primitive:?}");
            }
            assert!(partial >= 5, "{primitive:?}: {partial} partial updates");
        }
    }

    #[test]
    fn undo_updates_the_display_in_place() {
        let grid = Primitive::Plane
            .build(&PrimitiveParams {
                patches: Some((40, 40)),
                ..PrimitiveParams::default()
            })
            .expect("plane");
        let mut doc = Document::new(Model::new(grid));
        let mut cache = DisplayCache::default();
        cache.refresh(&doc, false);
        let start = cache.display().clone();
        doc.apply(&Op::Push {
            at: DVec3::new(0.3, 0.2, 0.0),
            dir: -DVec3::Z,
            // Shallow: the segment counts stay (a deeper dent would rebuild once, not busy).
            depth: 0.02,
            radius: 1.25,
        })
        .expect("push");
        cache.refresh(&doc, false);
        let generation = cache.generation();
        assert!(doc.undo());
        cache.refresh(&doc, false);
        let ranges = cache.vertex_ranges_since(generation).expect("in place");
        let uploaded: u32 = ranges.iter().map(|r| r.end - r.start).sum();
        assert!(uploaded * 10 < cache.display().mesh.positions.len() as u32);
        assert_eq!(cache.display().mesh, start.mesh);
        assert!(cache.display().seam_heat == start.seam_heat);
    }

    #[test]
    fn ranges_merge_where_they_touch() {
        assert_eq!(merge_ranges(vec![5..7, 0..2, 2..3, 6..9]), vec![0..3, 5..9]);
    }
}
