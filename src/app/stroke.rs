//! A live stroke: a Push, Pull or Draw-a-line that deforms the surface while the button is
//! held, is one undo step when released, and can be cancelled with the surface restored
//! bit for bit.
//!
//! The stroke keeps the model as it was when the button went down (`S₀`). Each frame the
//! surface shown is `apply(S₀, op_t)`, the operation the gesture describes *now* (its depth
//! from the drag or the wheel, its path so far) applied afresh to `S₀` — never an increment
//! on the previous frame's surface. So
//! - the released stroke leaves exactly `apply(S₀, op_final)`: the same surface `nendo sculpt`
//!   or a replay of the recorded operation makes;
//! - a cancel puts `S₀` back (a copy of it, so bit-identical);
//! - the undo step records `S₀` once, on release.
//!
//! The stroke also keeps the tessellation of `S₀`: the tools pick on it during the stroke, so a
//! groove being drawn does not pull the path down into itself.
//!
//! With auto-refine on (the window's setting), the working start `S₀'` is refined where the
//! operation's finger reaches ([`crate::surface::refine::for_finger`]) before it is applied:
//! the refinement changes the grid, not the surface, so `S₀'` and `S₀` are the same surface
//! and a cancel or undo puts the original grid back.
//!
//! **Mirror** ([`LiveStroke::with_mirror`]): each operation is applied together with its mirror
//! image ([`Sculptor::apply_mirrored`]); auto-refine then refines where the finger reaches and
//! at the mirror images of those grid parameters, and keeps the refinement only when the
//! refined grid is still symmetric ([`super::symmetry::refine_mirrored`]); otherwise it stops
//! refining for the rest of the stroke ([`LiveStroke::take_refine_skipped`]).
//!
//! **Dabs** ([`LiveStroke::show_dabs`], a smoothing stroke): the operations are applied one
//! after another, each on the surface the previous ones left, only the new ones each frame.
//! The released stroke is one undo step holding every dab, and the recording gets every dab.
//!
//! Limits: a frame costs one copy of the grid plus the whole operation (a long Draw-a-line
//! is re-applied along its whole path each frame); the operation runs at most once per frame
//! (see [`LiveStroke::show`]), not once per input event.

use crate::mesh::{PatchPoints, TriMesh};
use crate::model::Model;
use crate::surface::{Grid, Op, Sculptor, SurfaceError, Symmetry, refine};

use super::document::Document;

/// A stroke in progress.
#[derive(Debug)]
pub struct LiveStroke {
    /// The model when the stroke began.
    before: Model,
    /// The surface each frame's operation is applied to: `before`'s, refined where the
    /// operations reached when auto-refine is on (the same surface on a finer grid).
    base: Grid,
    /// Whether to refine `base` where each operation's finger reaches.
    auto_refine: bool,
    /// Its patches and tessellation, for picking during the stroke.
    base_patches: Vec<PatchPoints>,
    base_mesh: TriMesh,
    sculptor: Sculptor,
    /// The operation the surface shows now (`None`: the surface is `before`'s).
    shown: Option<Op>,
    /// The patches the shown operation changed.
    touched: Vec<usize>,
    /// Why the last operation was refused, if it was (the surface then shows `before`).
    refused: Option<SurfaceError>,
    /// The mirror every operation is applied with, if any.
    mirror: Option<Symmetry>,
    /// Auto-refine was skipped because it would have broken the grid's symmetry (not yet
    /// reported).
    refine_skipped: bool,
    /// The dabs made part of `base` so far (a smoothing stroke), in order.
    done: Vec<Op>,
    /// How many dabs [`LiveStroke::show_dabs`] has taken (applied or refused).
    dabs_seen: usize,
}

impl LiveStroke {
    /// Begins a stroke on `doc` as it is now; `patches` and `mesh` are its current display.
    /// With `auto_refine`, the grid is refined where each frame's operation reaches before it
    /// is applied.
    #[must_use]
    pub fn begin(
        doc: &Document,
        patches: &[PatchPoints],
        mesh: &TriMesh,
        auto_refine: bool,
    ) -> Self {
        Self {
            before: doc.model().clone(),
            base: doc.model().surface.clone(),
            auto_refine,
            base_patches: patches.to_vec(),
            base_mesh: mesh.clone(),
            sculptor: Sculptor::new(),
            shown: None,
            touched: Vec::new(),
            refused: None,
            mirror: None,
            refine_skipped: false,
            done: Vec::new(),
            dabs_seen: 0,
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

    /// Shows the dabs of a smoothing stroke: those not taken yet are applied one after another
    /// on the surface as it is (each a step of the stroke); `dabs` is the whole list so far
    /// (it only grows). A refused dab is skipped (see [`LiveStroke::take_refused`]).
    pub fn show_dabs(&mut self, doc: &mut Document, dabs: &[Op]) {
        for dab in dabs.iter().skip(self.dabs_seen) {
            self.dabs_seen += 1;
            self.show(doc, Some(dab));
            if let Some(op) = self.shown.take() {
                self.base.clone_from(&doc.model().surface);
                self.done.push(op);
            }
        }
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

    /// The patches the shown operation changed (the finger's reach and the ring of patches
    /// the regulation adjusted).
    #[must_use]
    pub fn touched(&self) -> &[usize] {
        &self.touched
    }

    /// Takes why the last operation was refused, if it was.
    pub fn take_refused(&mut self) -> Option<SurfaceError> {
        self.refused.take()
    }

    /// Makes the document's surface `apply(S₀, op)` (`S₀` itself for `None`). Does nothing
    /// when `op` is what is already shown. A refused operation leaves `S₀` shown.
    pub fn show(&mut self, doc: &mut Document, op: Option<&Op>) {
        if self.shown.as_ref() == op {
            return;
        }
        if self.auto_refine
            && let Some(op) = op
        {
            match &self.mirror {
                Some(mirror) => match super::symmetry::refine_mirrored(&self.base, op, mirror) {
                    super::symmetry::MirroredRefinement::Refined(found) => {
                        let (refined, mirror) = *found;
                        self.base = refined;
                        self.mirror = Some(mirror);
                    }
                    super::symmetry::MirroredRefinement::Unchanged => {}
                    super::symmetry::MirroredRefinement::Asymmetric => {
                        self.auto_refine = false;
                        self.refine_skipped = true;
                    }
                },
                None => {
                    if let Ok(f) = refine::for_finger(&self.base, op)
                        && !f.refinement.is_empty()
                        && let Ok(refined) = f.refinement.apply(&self.base)
                    {
                        self.base = refined;
                    }
                }
            }
        }
        let base = &self.base;
        let sculptor = &mut self.sculptor;
        let mirror = self.mirror.as_ref();
        let result = doc.sculpt_surface(|grid, regulation| {
            grid.clone_from(base);
            let result = op.map(|op| match mirror {
                Some(m) => sculptor.apply_mirrored(grid, op, regulation, m),
                None => sculptor.apply(grid, op, regulation),
            });
            // Always a change for the display: the surface was something else before.
            let changed = match &result {
                Some(Ok(t)) => t.patches.len().max(1),
                _ => 1,
            };
            (result, changed)
        });
        match result {
            Some(Ok(touched)) => {
                self.touched = touched.patches;
                self.shown = op.cloned();
            }
            Some(Err(e)) => {
                self.refused = Some(e);
                self.touched.clear();
                self.shown = None;
            }
            None => {
                self.touched.clear();
                self.shown = None;
            }
        }
    }

    /// Ends the stroke with `op` applied: one undo step named after it, and the operation in
    /// the recording. Without an operation (nothing pressed in) the surface is restored and
    /// nothing is recorded. Returns why the operation was refused, if it was.
    pub fn commit(mut self, doc: &mut Document, op: Option<&Op>) -> Option<SurfaceError> {
        self.show(doc, op);
        let mut ops = std::mem::take(&mut self.done);
        ops.extend(self.shown.take());
        match ops.first() {
            Some(first) => {
                doc.record_undo(edit_name(first), self.before);
                doc.record_ops(&ops);
            }
            None => {
                // Nothing applied: make sure the surface is exactly the start's.
                self.show_start(doc);
            }
        }
        self.refused
    }

    /// Cancels the stroke: the surface is exactly as it was when the stroke began, and nothing
    /// is recorded.
    pub fn cancel(mut self, doc: &mut Document) {
        self.show_start(doc);
    }

    fn show_start(&mut self, doc: &mut Document) {
        if self.shown.is_some() || doc.model().surface != self.before.surface {
            let base = &self.before.surface;
            doc.sculpt_surface(|grid, _| {
                grid.clone_from(base);
                ((), 1)
            });
        }
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
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Tessellation;
    use crate::surface::{Primitive, PrimitiveParams};

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
        stroke.show(&mut doc, Some(&push(0.1)));
        stroke.show(&mut doc, Some(&push(0.2)));
        let counts = |d: &Document| (d.model().surface.patches_u(), d.model().surface.patches_v());
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
}
