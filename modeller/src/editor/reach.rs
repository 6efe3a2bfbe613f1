//! The finger's reach as the window outlines it: the patches an operation changes.
//!
//! A shape function's support is a ball of radius `r_f` around the finger, but what moves is
//! every patch whose control points move: the patches the finger's flow touches at any of
//! their 16 sample points, and the ring of neighbours the regulation adjusts to keep G1. On a
//! coarse grid that is much more than the ball (a radius-0.6 push on the 8 × 4 torus changes
//! 20 of its 32 patches), so the ring drawn around the cursor would understate it.
//!
//! For a hover the window runs the click's operation on a copy of the grid (a dry run, the
//! exact answer) when the grid has at most [`ReachedPatches::DRY_RUN_MAX_PATCHES`]; on bigger grids it
//! falls back to the patches whose boxes the finger may touch
//! ([`nendo_geom::surface::Finger::may_touch`], conservative: it may outline a few patches the
//! flow misses, and it leaves out the regulation's ring). During a stroke the outline is the
//! stroke's own changed patches ([`super::stroke::LiveStroke::touched`]).

use crate::mesh::TriMesh;
use crate::render::{LineBatch, Rgba};
use crate::surface::{Grid, Op, Regulation, Sculptor};

use super::document::Document;

/// The colour of the reached patches' outlines.
const REACH: Rgba = Rgba([1.0, 0.62, 0.15, 0.95]);

/// The reached patches, cached for the operation and model revision they were found for.
#[derive(Debug, Default)]
pub struct ReachedPatches {
    key: Option<(Op, u64)>,
    patches: Vec<usize>,
}

impl ReachedPatches {
    /// Largest grid a hover dry-runs its operation on.
    pub const DRY_RUN_MAX_PATCHES: usize = 4096;

    /// Finds the patches `op` would change on `doc`'s surface (none for `None`); cached while
    /// the operation and the revision stay the same.
    pub fn update(&mut self, op: Option<Op>, doc: &Document) {
        let Some(op) = op else {
            self.key = None;
            self.patches.clear();
            return;
        };
        let key = (op, doc.revision());
        if self.key.as_ref() == Some(&key) {
            return;
        }
        let model = doc.model();
        self.patches = reached(&model.surface, &key.0, model.regulation);
        self.key = Some(key);
    }

    /// Takes the patches a stroke changed.
    pub fn set(&mut self, patches: &[usize]) {
        self.key = None;
        self.patches.clear();
        self.patches.extend_from_slice(patches);
    }

    /// The reached patches.
    #[must_use]
    pub fn patches(&self) -> &[usize] {
        &self.patches
    }

    /// Outlines the reached patches on the tessellation `mesh`.
    pub fn draw(&self, mesh: &TriMesh, lines: &mut LineBatch) {
        if self.patches.is_empty() {
            return;
        }
        let at = |v: u32| mesh.positions[v as usize];
        for b in &mesh.blocks {
            if !self.patches.contains(&(b.patch as usize)) {
                continue;
            }
            lines.polyline((0..=b.m_u).map(|k| at(b.vertex(k, 0))), REACH);
            lines.polyline((0..=b.m_u).map(|k| at(b.vertex(k, b.m_v))), REACH);
            lines.polyline((0..=b.m_v).map(|l| at(b.vertex(0, l))), REACH);
            lines.polyline((0..=b.m_v).map(|l| at(b.vertex(b.m_u, l))), REACH);
        }
    }
}

/// The patches `op` changes on `grid` (sorted): by a dry run on a copy up to
/// [`ReachedPatches::DRY_RUN_MAX_PATCHES`], else those whose boxes the finger may touch. None for an
/// invalid or refused operation.
#[must_use]
pub fn reached(grid: &Grid, op: &Op, regulation: Regulation) -> Vec<usize> {
    let Ok(finger) = op.finger() else {
        return Vec::new();
    };
    let mut out = if grid.patch_count() <= ReachedPatches::DRY_RUN_MAX_PATCHES {
        let mut copy = grid.clone();
        match Sculptor::new().apply(&mut copy, op, regulation) {
            Ok(touched) => touched.patches,
            Err(_) => Vec::new(),
        }
    } else {
        let depth = finger.reach_depth(&grid.bounds());
        let mut out = Vec::new();
        grid.patches_where(|b| finger.may_touch(b, depth), &mut out);
        out
    };
    out.sort_unstable();
    out.dedup();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Primitive, PrimitiveParams};

    /// A radius-0.6 push on the 8 × 4 torus: the outline is exactly the patches the push
    /// changes, far more than the one under the finger.
    #[test]
    fn the_reach_is_what_the_push_changes() {
        let grid = Primitive::Torus
            .build(&PrimitiveParams {
                patches: Some((8, 4)),
                ..PrimitiveParams::default()
            })
            .expect("torus");
        let p = grid.patches()[0][5];
        let op = Op::Push {
            at: p,
            dir: -p.normalize(),
            depth: 0.2,
            radius: 0.6,
        };
        let reach = reached(&grid, &op, Regulation::default());
        assert!(
            reach.len() > 4,
            "more than the patch under the finger: {reach:?}"
        );
        let mut pushed = grid.clone();
        Sculptor::new()
            .apply(&mut pushed, &op, Regulation::default())
            .expect("push");
        let (before, after) = (grid.patches(), pushed.patches());
        for k in 0..grid.patch_count() {
            assert_eq!(
                before[k] != after[k],
                reach.contains(&k),
                "patch {k}: changed iff outlined"
            );
        }
    }
}
