//! A live stroke: a Push, Pull, Draw-a-line or Move that deforms the surface while the button
//! is held, is one undo step when released, and can be cancelled with the surface restored
//! bit for bit.
//!
//! The stroke is a [`Document`] stroke ([`Document::begin_stroke`]) opened on the model as it
//! was when the first operation was shown (`S₀`). Each frame the surface shown is
//! `apply(S₀, op_t)`, the operation the gesture describes *now* (its depth from the drag or
//! the wheel, its path so far) applied afresh to `S₀` — never an increment on the previous
//! frame's surface. The re-application is the deformation engine's own
//! ([`crate::surface::LiveOperation`], through [`Document::show_in_stroke`]), the same one the
//! hand's pinch uses: a frame
//! 1. puts `S₀` back from the live operation's journal (the first old position of every
//!    control point the previous frame wrote: bit for bit, at the cost of what it touched);
//! 2. applies `op_t`, noting the patches whose control points it changed (`T_t`) —
//!
//! as one revision noting `T_{t−1} ∪ T_t`, the patches whose control points may have changed
//! this frame, so the display cache re-tessellates only those (and the seam heat of the ring
//! around them) and the renderer re-uploads only their vertices ([`super::display_cache`]).
//! Hence
//! - the released stroke leaves exactly `apply(S₀, op_final)`: the same surface
//!   `nendo sculpt` or a replay of the recorded operation makes;
//! - a cancel puts `S₀` back bit for bit ([`Document::cancel_stroke`]);
//! - the undo step is the stroke's, named after its final operation, recorded on release.
//!
//! The document puts `S₀` back and then shows the new operation (a cancel and a show of the
//! live operation), where the pinch lets the live operation go from one move to the next in
//! one call, for two reasons: auto-refinement decides where to refine on the start, the
//! surface it refines; and a refused operation shows the start, as the window always did
//! (released there, the stroke records nothing), where the pinch keeps its last accepted
//! move. The price: a frame reports all the patches the previous operation may have changed,
//! not only those whose points differ from the last frame.
//!
//! The stroke also keeps the tessellation of `S₀`: the tools pick on it during the stroke, so a
//! groove being drawn does not pull the path down into itself.
//!
//! With auto-refine on (the window's setting), the working start `S₀'` is refined where the
//! operation's finger reaches ([`crate::surface::refine::for_finger`]) before it is applied
//! and the document's stroke moves onto it: the refinement changes the grid, not the surface,
//! so `S₀'` and `S₀` are the same surface, and a cancel or undo puts the original grid back.
//! A frame that refines rebuilds the whole display (the patch count changed); the frames after
//! it are partial again.
//!
//! **Mirror** ([`LiveStroke::with_mirror`]): each operation is applied together with its mirror
//! image ([`crate::surface::Sculptor::apply_mirrored`]); auto-refine then refines where the
//! finger reaches and at the mirror images of those grid parameters, and keeps the refinement
//! only when the refined grid is still symmetric ([`super::symmetry::refine_mirrored`]);
//! otherwise it stops refining for the rest of the stroke ([`LiveStroke::take_refine_skipped`]).
//!
//! **Dabs** ([`LiveStroke::show_dabs`], a smoothing stroke): the operations are applied one
//! after another, each on the surface the previous ones left, only the new ones each frame
//! ([`Document::add_to_stroke`]), never re-applied. The released stroke is one undo step
//! holding every dab, and the recording gets every dab.
//!
//! Limits: a frame re-applies the whole operation (a long Draw-a-line is re-applied along its
//! whole path each frame, so its frames grow with the path); the operation runs at most once
//! per frame (see [`LiveStroke::show`]), not once per input event. Should another edit end the
//! document's stroke while the gesture goes on (the regulation changed mid-stroke), what was
//! shown until then stays as that stroke's undo step and the gesture continues as a new
//! stroke from there. A frame whose patches need other segment counts is drawn with the old
//! counts until the gesture ends, and one that changes more than half the grid is redrawn
//! whole ([`super::display_cache`]). `nendo bench live` measures the window's frame (CPU time of the
//! measuring thread, on a machine loaded by other builds): on the 40 × 40 plane a live push
//! frame takes 1.3 ms and a growing groove's 3.5 ms — put back, deform and regulate,
//! re-tessellate the changed patches and their seam heat, write their vertices to the GPU —
//! against 44–52 ms for the same frames with the full rebuild the window did before.

use crate::mesh::{PatchPoints, TriMesh};
use crate::surface::{Grid, Op, SurfaceError, Symmetry, refine};

use super::document::Document;

/// A stroke in progress.
#[derive(Debug)]
pub struct LiveStroke {
    /// Whether to refine the start where each operation's finger reaches.
    auto_refine: bool,
    /// The start's patches and tessellation, for picking during the stroke.
    base_patches: Vec<PatchPoints>,
    base_mesh: TriMesh,
    /// True once this stroke opened the document's stroke.
    opened: bool,
    /// The operation the surface shows now (`None`: the surface is the start's).
    shown: Option<Op>,
    /// The patches the shown operation changed.
    touched: Vec<usize>,
    /// The patches whose control points the last [`LiveStroke::show`] changed (`None`: the
    /// whole grid, a refinement).
    frame: Option<Vec<usize>>,
    /// Why the last operation was refused, if it was (the surface then shows the start).
    refused: Option<SurfaceError>,
    /// The mirror every operation is applied with, if any (its map follows the grid when
    /// auto-refine refines it).
    mirror: Option<Symmetry>,
    /// Auto-refine was skipped because it would have broken the grid's symmetry (not yet
    /// reported).
    refine_skipped: bool,
    /// How many dabs [`LiveStroke::show_dabs`] has taken (applied or refused).
    dabs_seen: usize,
    /// The name of the first dab applied (a smoothing stroke), if any was.
    dabbed: Option<&'static str>,
}

impl LiveStroke {
    /// Begins a stroke on `doc` as it is now; `patches` and `mesh` are its current display.
    /// With `auto_refine`, the grid is refined where each frame's operation reaches before it
    /// is applied. The document's stroke opens with the first operation shown.
    #[must_use]
    pub fn begin(
        doc: &Document,
        patches: &[PatchPoints],
        mesh: &TriMesh,
        auto_refine: bool,
    ) -> Self {
        // A stroke that never picks (a one-off mirrored operation) passes no display.
        debug_assert!(patches.is_empty() || patches.len() == doc.model().surface.patch_count());
        Self {
            auto_refine,
            base_patches: patches.to_vec(),
            base_mesh: mesh.clone(),
            opened: false,
            shown: None,
            touched: Vec::new(),
            frame: Some(Vec::new()),
            refused: None,
            mirror: None,
            refine_skipped: false,
            dabs_seen: 0,
            dabbed: None,
        }
    }

    /// Applies every operation of the stroke together with its mirror image across
    /// `mirror`'s plane (a map made for the document's grid; `None`: no mirror).
    #[must_use]
    pub fn with_mirror(mut self, mirror: Option<Symmetry>) -> Self {
        self.mirror = mirror;
        self
    }

    /// Takes whether auto-refine was skipped to keep the grid symmetric.
    pub fn take_refine_skipped(&mut self) -> bool {
        std::mem::take(&mut self.refine_skipped)
    }

    /// What a frame works on, given the surface it starts from: the finer grid to move onto
    /// when auto-refine asks for one, and the mirror map to apply `op` with.
    fn prepare(&mut self, grid: &Grid, op: Option<&Op>) -> (Option<Grid>, Option<&Symmetry>) {
        let finer = match op.filter(|_| self.auto_refine) {
            None => None,
            Some(op) => match &self.mirror {
                Some(mirror) => match super::symmetry::refine_mirrored(grid, op, mirror) {
                    super::symmetry::MirroredRefinement::Refined(found) => {
                        let (refined, mirror) = *found;
                        self.mirror = Some(mirror);
                        Some(refined)
                    }
                    super::symmetry::MirroredRefinement::Unchanged => None,
                    super::symmetry::MirroredRefinement::Asymmetric => {
                        self.auto_refine = false;
                        self.refine_skipped = true;
                        None
                    }
                },
                None => refine::for_finger(grid, op)
                    .ok()
                    .filter(|f| !f.refinement.is_empty())
                    .and_then(|f| f.refinement.apply(grid).ok()),
            },
        };
        (finer, self.mirror.as_ref())
    }

    /// Shows the dabs of a smoothing stroke: those not taken yet are applied one after another
    /// on the surface as it is ([`Document::add_to_stroke`]); `dabs` is the whole list so far
    /// (it only grows). A refused dab is skipped (see [`LiveStroke::take_refused`]).
    pub fn show_dabs(&mut self, doc: &mut Document, dabs: &[Op]) {
        let revision = doc.revision();
        for dab in dabs.iter().skip(self.dabs_seen) {
            self.dabs_seen += 1;
            if !(self.opened && doc.in_stroke()) {
                doc.begin_stroke(edit_name(dab));
                self.opened = true;
            }
            let result = doc.add_to_stroke(dab, |grid| self.prepare(grid, Some(dab)));
            match result {
                Some(Ok(touched)) => {
                    self.dabbed.get_or_insert(edit_name(dab));
                    self.touched.extend(touched.patches);
                    self.touched.sort_unstable();
                    self.touched.dedup();
                }
                Some(Err(e)) => self.refused = Some(e),
                None => {}
            }
        }
        self.frame = doc.surface_changes_since(revision);
    }

    /// The patches of the surface as it was when the stroke began.
    #[must_use]
    pub fn base_patches(&self) -> &[PatchPoints] {
        &self.base_patches
    }

    /// The tessellation of the surface as it was when the stroke began.
    #[must_use]
    pub fn base_mesh(&self) -> &TriMesh {
        &self.base_mesh
    }

    /// The operation the surface shows.
    #[must_use]
    pub fn shown(&self) -> Option<&Op> {
        self.shown.as_ref()
    }

    /// The patches whose control points the shown operation changed (the finger's reach and
    /// the ring of patches the regulation adjusted), sorted.
    #[must_use]
    pub fn touched(&self) -> &[usize] {
        &self.touched
    }

    /// The patches whose control points the last [`LiveStroke::show`] changed, sorted: those
    /// the previous operation had changed (put back) and those the new one changed — what the
    /// display must redraw. `None` when that frame changed the grid itself (a refinement).
    #[must_use]
    pub fn frame_changes(&self) -> Option<&[usize]> {
        self.frame.as_deref()
    }

    /// Takes why the last operation was refused, if it was.
    pub fn take_refused(&mut self) -> Option<SurfaceError> {
        self.refused.take()
    }

    /// Makes the document's surface `apply(S₀, op)` (`S₀` itself for `None`), changing only
    /// the patches the previous and the new operation touch (see the module docs). Does
    /// nothing when `op` is what is already shown. A refused operation leaves `S₀` shown.
    pub fn show(&mut self, doc: &mut Document, op: Option<&Op>) {
        if self.shown.as_ref() == op {
            return;
        }
        let revision = doc.revision();
        if !(self.opened && doc.in_stroke()) {
            if op.is_none() {
                // No stroke open and nothing to show: the surface is as it is.
                self.shown = None;
                self.touched.clear();
                self.frame = Some(Vec::new());
                return;
            }
            doc.begin_stroke(op.map_or("stroke", edit_name));
            self.opened = true;
        }
        let result = doc.show_in_stroke(op, |grid| self.prepare(grid, op));
        self.touched.clear();
        self.shown = None;
        match result {
            Some(Ok(changed)) => {
                self.touched = changed;
                self.shown = op.cloned();
            }
            Some(Err(e)) => self.refused = Some(e),
            None => {}
        }
        self.frame = doc.surface_changes_since(revision);
    }

    /// Ends the stroke with `op` applied: one undo step named after it, and the operation in
    /// the recording. Without an operation (nothing pressed in) the surface is restored and
    /// nothing is recorded. Returns why the operation was refused, if it was.
    ///
    /// A smoothing stroke ([`LiveStroke::show_dabs`]) is committed with `op` `None`: its dabs
    /// stay, one undo step named after them.
    pub fn commit(mut self, doc: &mut Document, op: Option<&Op>) -> Option<SurfaceError> {
        if op.is_some() || self.dabbed.is_none() {
            self.show(doc, op);
        }
        match self.shown.take().map(|op| edit_name(&op)).or(self.dabbed) {
            Some(name) => {
                doc.rename_stroke(name);
                doc.end_stroke();
            }
            None => self.cancel_open(doc),
        }
        self.refused
    }

    /// Cancels the stroke: the surface is exactly as it was when the stroke began, and nothing
    /// is recorded.
    pub fn cancel(mut self, doc: &mut Document) {
        self.cancel_open(doc);
    }

    fn cancel_open(&mut self, doc: &mut Document) {
        if self.opened && doc.in_stroke() {
            doc.cancel_stroke();
        }
        self.opened = false;
        self.shown = None;
        self.touched.clear();
    }
}

/// The undo step's name for a sculpting operation.
#[must_use]
pub fn edit_name(op: &Op) -> &'static str {
    match op {
        Op::Push { depth, .. } | Op::PushNormal { depth, .. } if *depth < 0.0 => "pull",
        Op::Push { .. } | Op::PushNormal { .. } => "push",
        Op::Drag { .. } | Op::Groove { .. } => "draw a line",
        Op::Move { .. } => "move",
        Op::Smooth { .. } => "smooth",
        Op::Brushed { op, .. } => edit_name(op),
        Op::Sculpt(b) => b.kind.name(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::display_cache::DisplayCache;
    use crate::editor::scene::SurfaceDisplay;
    use crate::mesh::Tessellation;
    use crate::model::Model;
    use crate::surface::{Primitive, PrimitiveParams};
    use glam::DVec3;

    fn torus_doc() -> Document {
        Document::new(Model::new(
            Primitive::Torus
                .build(&PrimitiveParams {
                    patches: Some((8, 4)),
                    ..PrimitiveParams::default()
                })
                .expect("torus"),
        ))
    }

    fn push(depth: f64) -> Op {
        let grid = torus_doc().model().surface.clone();
        let p = grid.patches()[0][5];
        Op::Push {
            at: p,
            dir: -p.normalize(),
            depth,
            radius: 0.6,
        }
    }

    fn begin(doc: &Document) -> LiveStroke {
        let patches = doc.model().surface.patches();
        let mesh = crate::mesh::tessellate(&patches, &Tessellation::DISPLAY);
        LiveStroke::begin(doc, &patches, &mesh, false)
    }

    /// With auto-refine the stroke refines the grid where the finger reaches (a radius-0.6
    /// push on the 8 × 4 torus), the released surface is one undo step back to the original
    /// grid, and a cancel restores the original grid bit for bit.
    #[test]
    fn an_auto_refined_stroke_undoes_and_cancels_to_the_original_grid() {
        let mut doc = torus_doc();
        let start = doc.model().clone();
        let patches = start.surface.patches();
        let mesh = crate::mesh::tessellate(&patches, &Tessellation::DISPLAY);
        let mut stroke = LiveStroke::begin(&doc, &patches, &mesh, true);
        let counts = |d: &Document| (d.model().surface.patches_u(), d.model().surface.patches_v());
        // Once refined, a frame needing no further refinement changes only its patches.
        let mut partial = 0;
        for depth in [0.1, 0.2, 0.15, 0.25, 0.2] {
            let grid_before = counts(&doc);
            stroke.show(&mut doc, Some(&push(depth)));
            if grid_before != (8, 4) && counts(&doc) == grid_before {
                let frame = stroke.frame_changes().expect("a frame on the refined grid");
                let total = counts(&doc).0 * counts(&doc).1;
                assert!(frame.len() < total, "{} of {total} patches", frame.len());
                partial += 1;
            }
        }
        assert!(
            partial >= 2,
            "{partial} partial frames after the refinement"
        );
        assert!(
            counts(&doc).0 * counts(&doc).1 > 32,
            "refined: {:?}",
            counts(&doc)
        );
        assert!(stroke.commit(&mut doc, Some(&push(0.2))).is_none());
        assert!(doc.undo());
        assert_eq!(
            doc.model(),
            &start,
            "one undo step back to the original grid"
        );
        assert!(!doc.undo());

        let mut stroke = LiveStroke::begin(&doc, &patches, &mesh, true);
        stroke.show(&mut doc, Some(&push(0.2)));
        assert_ne!(counts(&doc), (8, 4));
        stroke.cancel(&mut doc);
        assert_eq!(doc.model(), &start, "a cancel restores the original grid");
    }

    /// Frames re-apply from the start, so the released stroke equals one application of the
    /// final operation, bit for bit; it is one undo step.
    #[test]
    fn a_released_stroke_is_one_application_of_its_last_operation() {
        let mut doc = torus_doc();
        let start = doc.model().clone();
        let mut stroke = begin(&doc);
        for k in 1..=6 {
            stroke.show(&mut doc, Some(&push(0.05 * f64::from(k))));
            assert!(!stroke.touched().is_empty());
        }
        assert!(stroke.commit(&mut doc, Some(&push(0.3))).is_none());
        let mut once = torus_doc();
        once.apply(&push(0.3)).expect("push");
        assert_eq!(doc.model(), once.model(), "bit-identical to one push");
        assert_eq!(doc.history().undo_name(), Some("push"));
        assert!(doc.undo());
        assert_eq!(doc.model(), &start, "one undo step");
        assert!(!doc.undo(), "and only one");
    }

    /// A cancel restores the surface bit for bit and records nothing.
    #[test]
    fn a_cancelled_stroke_restores_the_surface_exactly() {
        let mut doc = torus_doc();
        let start = doc.model().clone();
        let mut stroke = begin(&doc);
        stroke.show(&mut doc, Some(&push(0.2)));
        assert_ne!(doc.model(), &start);
        // The patches said to be touched are exactly those that changed.
        let (before, after) = (start.surface.patches(), doc.model().surface.patches());
        for k in 0..before.len() {
            assert_eq!(
                before[k] != after[k],
                stroke.touched().contains(&k),
                "patch {k}"
            );
        }
        stroke.show(&mut doc, Some(&push(-0.4)));
        stroke.cancel(&mut doc);
        assert_eq!(doc.model(), &start);
        assert!(doc.history().undo_name().is_none(), "nothing to undo");
        // A stroke released with no operation changes nothing either.
        let mut stroke = begin(&doc);
        stroke.show(&mut doc, Some(&push(0.2)));
        stroke.commit(&mut doc, None);
        assert_eq!(doc.model(), &start);
        assert!(doc.history().undo_name().is_none());
    }

    /// A refused operation (a NaN depth) leaves the start's surface shown and says why.
    #[test]
    fn a_refused_operation_shows_the_start() {
        let mut doc = torus_doc();
        let start = doc.model().clone();
        let mut stroke = begin(&doc);
        stroke.show(&mut doc, Some(&push(0.2)));
        stroke.show(&mut doc, Some(&push(f64::NAN)));
        assert_eq!(doc.model(), &start);
        assert!(stroke.take_refused().is_some());
    }

    fn plane_doc(n: usize) -> Document {
        Document::new(Model::new(
            Primitive::Plane
                .build(&PrimitiveParams {
                    patches: Some((n, n)),
                    ..PrimitiveParams::default()
                })
                .expect("plane"),
        ))
    }

    /// Patches whose control points differ, bit for bit, between two grids of one shape.
    fn differing(a: &[PatchPoints], b: &[PatchPoints]) -> Vec<usize> {
        (0..a.len())
            .filter(|&k| {
                a[k].iter()
                    .zip(b[k].iter())
                    .any(|(p, q)| p.to_array().map(f64::to_bits) != q.to_array().map(f64::to_bits))
            })
            .collect()
    }

    /// Each frame of a live push (depth growing, then the finger sliding) says which patches
    /// it changed — at least those the previous and the new operation changed, a small part
    /// of the grid, every patch whose points moved among them; the display cache
    /// then updates only those in place, and after every frame the display is the full
    /// rebuild of the model, vertex for vertex. Releasing gives one application of the final
    /// operation.
    #[test]
    fn a_frame_changes_only_the_patches_its_operations_touch() {
        let mut doc = plane_doc(16);
        let start = doc.model().surface.patches();
        let mut cache = DisplayCache::default();
        cache.refresh(&doc, false);
        let mut stroke = LiveStroke::begin(&doc, cache.patches(), &cache.display().mesh, false);
        let op = |k: usize| Op::Push {
            at: DVec3::new(-2.0 + 0.3 * k as f64, 0.7 - 0.1 * k as f64, 0.0),
            dir: DVec3::new(0.1, 0.0, -1.0),
            depth: 0.004 * (k.min(4) + 1) as f64,
            radius: 1.25,
        };
        let mut previous: Vec<usize> = Vec::new();
        let (mut partial, mut exact) = (0, 0);
        for k in 0..10 {
            let before = doc.model().surface.patches();
            let generation = cache.generation();
            stroke.show(&mut doc, Some(&op(k)));
            let after = doc.model().surface.patches();
            let mut union: Vec<usize> = previous.iter().chain(stroke.touched()).copied().collect();
            union.sort_unstable();
            union.dedup();
            let frame = stroke.frame_changes().expect("no refinement").to_vec();
            assert!(
                union.iter().all(|p| frame.contains(p)),
                "frame {k}: the previous and the new operation's patches"
            );
            assert_eq!(
                stroke.touched(),
                differing(&start, &after),
                "frame {k}: the new operation's patches are those that differ from the start"
            );
            let changed = differing(&before, &after);
            assert!(
                changed.iter().all(|p| frame.contains(p)),
                "frame {k}: a changed patch is reported"
            );
            assert!(
                frame.len() * 4 < after.len(),
                "frame {k}: {} patches",
                frame.len()
            );
            previous = stroke.touched().to_vec();

            cache.refresh(&doc, true);
            let ranges = cache
                .vertex_ranges_since(generation)
                .expect("a live frame updates the display in place");
            let uploaded: u32 = ranges.iter().map(|r| r.end - r.start).sum();
            assert!(
                (uploaded as usize) * 2 < cache.display().mesh.positions.len(),
                "frame {k}: {uploaded} vertices uploaded"
            );
            partial += 1;
            // While the counts hold, the display is the full rebuild's, vertex for vertex.
            if !cache.counts_stale() {
                let full = SurfaceDisplay::new(&after, &Tessellation::DISPLAY);
                let shown = cache.display();
                assert!(
                    shown.mesh == full.mesh,
                    "frame {k}: the full rebuild's vertices"
                );
                assert!(shown.seam_heat == full.seam_heat, "frame {k}: seam heat");
                assert_eq!(shown.max_seam_deg, full.max_seam_deg, "frame {k}");
                exact += 1;
            }
        }
        assert_eq!(partial, 10);
        assert!(exact >= 5, "{exact} frames kept their counts");
        // After the gesture, the display is the full rebuild's whatever the counts did.
        cache.refresh(&doc, false);
        let full = SurfaceDisplay::new(&doc.model().surface.patches(), &Tessellation::DISPLAY);
        assert!(cache.display().mesh == full.mesh, "after the frames");
        assert!(cache.display().seam_heat == full.seam_heat);
        assert!(stroke.commit(&mut doc, Some(&op(9))).is_none());
        let mut once = plane_doc(16);
        once.apply(&op(9)).expect("push");
        assert_eq!(
            doc.model(),
            once.model(),
            "one application of the last push"
        );
        assert_eq!(doc.history().undo_len(), 1);
    }

    /// A cancel after frames that updated the display in place puts the surface and the
    /// display back exactly, patch by patch.
    #[test]
    fn a_cancel_after_partial_frames_restores_the_display_exactly() {
        let mut doc = plane_doc(16);
        let start = doc.model().clone();
        let mut cache = DisplayCache::default();
        cache.refresh(&doc, false);
        let shown_at_start = cache.display().clone();
        let mut stroke = LiveStroke::begin(&doc, cache.patches(), &cache.display().mesh, false);
        for k in 1..=5 {
            let generation = cache.generation();
            stroke.show(
                &mut doc,
                Some(&Op::Push {
                    at: DVec3::new(1.0 + 0.2 * f64::from(k), -0.5, 0.0),
                    dir: -DVec3::Z,
                    depth: -0.03 * f64::from(k),
                    radius: 1.25,
                }),
            );
            cache.refresh(&doc, true);
            assert!(
                cache.vertex_ranges_since(generation).is_some(),
                "frame {k} in place"
            );
        }
        assert_ne!(doc.model(), &start);
        let generation = cache.generation();
        let stale = cache.counts_stale();
        stroke.cancel(&mut doc);
        assert_eq!(doc.model(), &start, "the surface bit for bit");
        cache.refresh(&doc, false);
        assert_eq!(
            cache.vertex_ranges_since(generation).is_some(),
            !stale,
            "the cancel is drawn in place unless the counts went stale"
        );
        let shown = cache.display();
        assert!(shown.mesh == shown_at_start.mesh, "the display's vertices");
        assert!(shown.seam_heat == shown_at_start.seam_heat, "the seam heat");
        assert_eq!(shown.max_seam_deg, shown_at_start.max_seam_deg);
        assert!(doc.history().undo_name().is_none(), "nothing to undo");
    }
}
