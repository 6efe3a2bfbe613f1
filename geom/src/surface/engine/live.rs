//! [`LiveOperation`]: one operation shown live — re-applied to the surface it started from
//! each time it changes (a pinch following the hand, a stroke following the mouse), never
//! accumulated on the previous frame's result.
//!
//! Each application is a [`Sculptor`] operation, whose [`super::commit::Commit`] journals the
//! first old position of every control point it wrote. Showing the next operation first puts
//! those back (the start `S₀`, bit for bit, at the cost of what the last one touched), then
//! applies the new one: the grid is always exactly `apply(S₀, op)` — what the same operation
//! applied once makes — and a cancel restores `S₀` exactly. A refused operation leaves the
//! last accepted one shown (its positions, kept when they were put back, are written again).

use glam::DVec3;

use super::sculptor::{Sculptor, Touched};
use crate::surface::error::SurfaceError;
use crate::surface::grid::Grid;
use crate::surface::mirror::Symmetry;
use crate::surface::regulate::Regulation;
use crate::surface::shape_fn::Op;

/// An operation shown live on a grid (see the module docs).
#[derive(Debug, Clone, Default)]
pub struct LiveOperation {
    sculptor: Sculptor,
    /// The operation shown, with what it changed and the old positions of what it wrote.
    shown: Option<Shown>,
    /// The patches the last [`LiveOperation::show`] changed.
    frame: Vec<usize>,
    /// The shown positions of what the last rewind put back (to show it again on a refusal).
    redo: Vec<(usize, DVec3)>,
}

#[derive(Debug, Clone)]
struct Shown {
    op: Op,
    touched: Touched,
    journal: Vec<(usize, DVec3)>,
}

impl LiveOperation {
    /// A live operation with nothing shown yet: the grid it is given next is its start.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The operation shown (`None` before the first accepted one or after a cancel).
    #[must_use]
    pub fn shown(&self) -> Option<&Op> {
        self.shown.as_ref().map(|s| &s.op)
    }

    /// Makes `grid` its start deformed by `op` (with its mirror image when `symmetry` is
    /// given, as [`Sculptor::apply_mirrored`]). Returns the patches with a control point this
    /// call changed, sorted (among those the last operation had changed, put back, and those
    /// the new one changed). `grid` must be the grid the last call left (or the start).
    ///
    /// # Errors
    /// As [`Sculptor::apply`] and [`Sculptor::apply_mirrored`]; the last accepted operation
    /// then stays shown.
    pub fn show(
        &mut self,
        grid: &mut Grid,
        op: &Op,
        regulation: Regulation,
        symmetry: Option<&Symmetry>,
    ) -> Result<&[usize], SurfaceError> {
        let last = self.rewind(grid);
        match self.sculptor.apply_with(grid, op, regulation, symmetry) {
            Ok(touched) => {
                let journal = self.sculptor.journal().to_vec();
                // Exactly the patches with a control point that differs from the last frame:
                // a node written by the last operation against its shown position, one
                // written only by the new operation against its start position.
                let mut before: std::collections::HashMap<usize, DVec3> =
                    journal.iter().copied().collect();
                before.extend(self.redo.iter().copied());
                let m = grid.patches_u();
                self.frame.clear();
                self.frame.extend_from_slice(&touched.patches);
                if let Some(last) = &last {
                    self.frame.extend_from_slice(&last.touched.patches);
                }
                self.frame.sort_unstable();
                self.frame.dedup();
                self.frame.retain(|&p| {
                    grid.patch_node_ids(p % m, p / m).iter().any(|id| {
                        before
                            .get(id)
                            .is_some_and(|x| x.to_array() != grid.nodes()[*id].to_array())
                    })
                });
                self.shown = Some(Shown {
                    op: op.clone(),
                    touched,
                    journal,
                });
                Ok(&self.frame)
            }
            Err(e) => {
                // The sculptor put back what it wrote: the start. The last operation's
                // positions, kept by the rewind, make it the last frame again.
                if let Some(last) = last {
                    let nodes = grid.nodes_mut();
                    for &(id, x) in &self.redo {
                        nodes[id] = x;
                    }
                    grid.refit(&last.touched.patches, &mut self.frame);
                    self.shown = Some(last);
                }
                Err(e)
            }
        }
    }

    /// Puts the start back exactly (nothing shown afterwards). Returns the patches it changed.
    pub fn cancel(&mut self, grid: &mut Grid) -> Vec<usize> {
        self.rewind(grid)
            .map(|s| s.touched.patches)
            .unwrap_or_default()
    }

    /// Keeps what is shown as the grid's new state: the next operation starts from it.
    pub fn settle(&mut self) {
        self.shown = None;
    }

    /// Puts back what the shown operation wrote; returns it.
    fn rewind(&mut self, grid: &mut Grid) -> Option<Shown> {
        let shown = self.shown.take()?;
        let nodes = grid.nodes_mut();
        self.redo.clear();
        for &(id, x) in &shown.journal {
            self.redo.push((id, nodes[id]));
            nodes[id] = x;
        }
        grid.refit(&shown.touched.patches, &mut self.frame);
        Some(shown)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Plane, Primitive, PrimitiveParams};

    #[test]
    fn each_frame_is_the_operation_applied_once_to_the_start_and_a_cancel_restores_it() {
        for primitive in [Primitive::Plane, Primitive::Sphere, Primitive::Torus] {
            let start = primitive.build(&PrimitiveParams::default()).unwrap();
            let symmetry = Symmetry::of(&start, Plane::X).ok();
            let b = start.bounds();
            let grab = crate::surface::nearest(&start, DVec3::new(0.4, 0.2, b.max.z)).unwrap();
            let mut grid = start.clone();
            let mut live = LiveOperation::new();
            let mut previous = start.clone();
            for (k, mirror) in [None, symmetry.as_ref()]
                .into_iter()
                .cycle()
                .take(8)
                .enumerate()
            {
                let lift = 0.1 * (k as f64 + 1.0);
                let op = Op::Move {
                    at: grab.point,
                    to: grab.point + DVec3::new(0.05 * k as f64, 0.0, lift),
                    radius: 1.2,
                };
                let frame = live
                    .show(&mut grid, &op, Regulation::Exact, mirror)
                    .unwrap()
                    .to_vec();
                let mut once = start.clone();
                let touched = match mirror {
                    Some(s) => Sculptor::new().apply_mirrored(&mut once, &op, Regulation::Exact, s),
                    None => Sculptor::new().apply(&mut once, &op, Regulation::Exact),
                }
                .unwrap();
                assert_eq!(grid, once, "{primitive} frame {k}");
                let changed: Vec<usize> = (0..grid.patch_count())
                    .filter(|&p| {
                        let m = grid.patches_u();
                        grid.patch_node_ids(p % m, p / m)
                            .iter()
                            .any(|&id| grid.nodes()[id] != previous.nodes()[id])
                    })
                    .collect();
                assert_eq!(frame, changed, "{primitive} frame {k}");
                assert!(!touched.patches.is_empty());
                previous = grid.clone();
            }
            // A refused operation keeps the last one shown.
            let shown = grid.clone();
            let bad = Op::Move {
                at: grab.point,
                to: DVec3::splat(f64::NAN),
                radius: 1.2,
            };
            assert!(live.show(&mut grid, &bad, Regulation::Exact, None).is_err());
            assert_eq!(grid, shown, "{primitive}: a refusal changed the grid");
            assert!(!live.cancel(&mut grid).is_empty());
            assert_eq!(
                grid, start,
                "{primitive}: the cancel did not restore the start"
            );
        }
    }
}
