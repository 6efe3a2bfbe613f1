//! Undo and redo as a stack of what each edit changed.
//!
//! The history keeps one copy of the model as it was after the last recorded edit, the
//! *base*. An edit is made on the document's model, then *committed*: the history compares
//! the model with the base where the edit may have changed it (the patches it touched, or
//! everything when it cannot tell) and stores the difference as one [`Step`]:
//!
//! - **Control points** that changed, as the bitwise XOR `before ^ after` of each coordinate
//!   (`f64::to_bits`), node ids delta-coded as variable-length integers. The same XOR turns
//!   the before state into the after state and back (`x ^ d ^ d = x`), so undo and redo are
//!   exact — bit-identical models — and need no inverse of any operation. A coordinate the
//!   edit left alone XORs to 0 and takes half a byte; one it moved keeps only its low
//!   non-zero bytes (nearby numbers share sign, exponent and leading mantissa bytes).
//!   Putting a step back costs what it changed: the nodes are set through
//!   [`Grid::set_nodes`](crate::surface::Grid::set_nodes), which refits only their patches.
//! - **Curves** and the **regulation**, before and after, when they changed (small).
//! - **A whole model** (the other side of a swap) when the edit changed the grid's shape —
//!   patch counts, topology or spacing ratios (a refinement, a new primitive): nothing finer
//!   applies then.
//!
//! Memory: the steps' encoded sizes are summed ([`History::bytes`]); past
//! [`History::DEFAULT_LIMIT_BYTES`] the oldest steps are dropped first (the newest one always
//! stays). The base is one more model ([`History::base_bytes`]).
//!
//! Limits: an edit made without telling which patches it touched (the hand loop through
//! [`Document::sculpt_surface`](super::Document::sculpt_surface)) is found by comparing the
//! whole net, once per step.

use std::collections::VecDeque;

use glam::DVec3;

use crate::curve::json::DynCurve;
use crate::model::Model;
use crate::surface::{Grid, Regulation, SurfaceError};

/// Undo and redo stacks of edits, with the base they apply to.
#[derive(Debug, Clone)]
pub struct History {
    undo: VecDeque<Step>,
    redo: Vec<Step>,
    /// Bytes held by the steps of both stacks.
    bytes: usize,
    limit_bytes: usize,
    /// The model as of the last committed step.
    base: Model,
    /// The name of the edit in progress (begun, not yet committed).
    open: Option<String>,
    /// What changed since the base.
    dirty: Dirty,
    /// The model the open edit started from, when the base was moved onto a finer grid of
    /// it during the edit ([`History::rebase_open`]).
    origin: Option<Box<Model>>,
}

/// What may have changed since the base.
#[derive(Debug, Clone, Default)]
struct Dirty {
    /// Anything on the surface (compare the whole net).
    everything: bool,
    /// Patches that may have changed (unsorted, with repeats).
    patches: Vec<usize>,
    /// How many patches were left after the list was last freed of repeats.
    distinct: usize,
}

impl Dirty {
    fn is_empty(&self) -> bool {
        !self.everything && self.patches.is_empty()
    }
}

/// One recorded edit.
#[derive(Debug, Clone)]
struct Step {
    what: String,
    change: Change,
}

#[derive(Debug, Clone)]
enum Change {
    /// Differences on a grid of unchanged shape.
    Delta {
        nodes: NodeDelta,
        /// Regulation before and after, when it changed.
        regulation: Option<(Regulation, Regulation)>,
        /// Curves before and after, when they changed.
        curves: Option<Box<(Vec<DynCurve>, Vec<DynCurve>)>>,
    },
    /// The model on the other side of the step (swapped in on undo and on redo).
    Whole(Box<Model>),
}

/// Changed control points: ids (delta-coded varints) and the XOR of their coordinates (see the
/// module docs).
#[derive(Debug, Clone, Default, PartialEq)]
struct NodeDelta {
    count: usize,
    ids: Vec<u8>,
    xor: Vec<u8>,
}

impl NodeDelta {
    /// The nodes of `ids` (sorted, distinct) whose bits differ between `before` and `after`.
    fn between(before: &[DVec3], after: &[DVec3], ids: impl Iterator<Item = usize>) -> Self {
        let mut delta = Self::default();
        let mut last = 0usize;
        for id in ids {
            let (b, a) = (before[id], after[id]);
            let x = [
                b.x.to_bits() ^ a.x.to_bits(),
                b.y.to_bits() ^ a.y.to_bits(),
                b.z.to_bits() ^ a.z.to_bits(),
            ];
            if x == [0; 3] {
                continue;
            }
            write_varint(&mut delta.ids, (id - last) as u64);
            last = id;
            let lens = x.map(|c| 8 - (c.leading_zeros() / 8) as u8);
            delta.xor.push(lens[0] | (lens[1] << 4));
            delta.xor.push(lens[2]);
            for (c, len) in x.iter().zip(lens) {
                delta
                    .xor
                    .extend_from_slice(&c.to_le_bytes()[..usize::from(len)]);
            }
            delta.count += 1;
        }
        delta.ids.shrink_to_fit();
        delta.xor.shrink_to_fit();
        delta
    }

    /// `(node id, XOR of its coordinate bits)` for every changed node, in id order.
    fn entries(&self) -> impl Iterator<Item = (usize, [u64; 3])> + '_ {
        let mut ids = self.ids.as_slice();
        let mut xor = self.xor.as_slice();
        let mut id = 0usize;
        (0..self.count).map(move |_| {
            id += read_varint(&mut ids) as usize;
            let lens = [xor[0] & 15, xor[0] >> 4, xor[1]];
            xor = &xor[2..];
            let x = lens.map(|len| {
                let mut bytes = [0u8; 8];
                let len = usize::from(len);
                bytes[..len].copy_from_slice(&xor[..len]);
                xor = &xor[len..];
                u64::from_le_bytes(bytes)
            });
            (id, x)
        })
    }

    /// Applies the XOR to `grid` (turning either side of the step into the other).
    fn apply(&self, grid: &mut Grid) -> Result<Vec<usize>, SurfaceError> {
        let nodes = grid.nodes();
        let changes: Vec<(usize, DVec3)> = self
            .entries()
            .map(|(id, x)| {
                let p = nodes[id];
                (
                    id,
                    DVec3::new(
                        f64::from_bits(p.x.to_bits() ^ x[0]),
                        f64::from_bits(p.y.to_bits() ^ x[1]),
                        f64::from_bits(p.z.to_bits() ^ x[2]),
                    ),
                )
            })
            .collect();
        grid.set_nodes(&changes)
    }

    fn bytes(&self) -> usize {
        self.ids.capacity() + self.xor.capacity() + std::mem::size_of::<Self>()
    }
}

fn write_varint(out: &mut Vec<u8>, mut v: u64) {
    while v >= 0x80 {
        out.push((v as u8) | 0x80);
        v >>= 7;
    }
    out.push(v as u8);
}

fn read_varint(bytes: &mut &[u8]) -> u64 {
    let mut v = 0u64;
    let mut shift = 0;
    while let Some((&b, rest)) = bytes.split_first() {
        *bytes = rest;
        v |= u64::from(b & 0x7f) << shift;
        shift += 7;
        if b < 0x80 {
            break;
        }
    }
    v
}

/// What undo or redo changed on the surface.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Restored {
    /// The control points of these patches (sorted) changed; an empty list: only curves or
    /// the regulation did.
    Patches(Vec<usize>),
    /// The whole model was swapped.
    Everything,
}

impl Step {
    /// Turns the model on one side of the step into the one on the other side; `to_before`
    /// says which way (for the regulation and the curves).
    fn swap(&mut self, model: &mut Model, to_before: bool) -> Result<Restored, SurfaceError> {
        match &mut self.change {
            Change::Delta {
                nodes,
                regulation,
                curves,
            } => {
                let patches = nodes.apply(&mut model.surface)?;
                if let Some((before, after)) = regulation {
                    model.regulation = if to_before { *before } else { *after };
                }
                if let Some(c) = curves {
                    model.curves = if to_before { c.0.clone() } else { c.1.clone() };
                }
                Ok(Restored::Patches(patches))
            }
            Change::Whole(other) => {
                std::mem::swap(model, other);
                Ok(Restored::Everything)
            }
        }
    }

    fn bytes(&self) -> usize {
        let change = match &self.change {
            Change::Delta { nodes, curves, .. } => {
                nodes.bytes()
                    + curves
                        .as_ref()
                        .map_or(0, |c| curves_bytes(&c.0) + curves_bytes(&c.1))
            }
            Change::Whole(model) => model_bytes(model),
        };
        std::mem::size_of::<Self>() + self.what.capacity() + change
    }
}

/// Heap bytes a model holds, about: its net, the box pyramid (4/3 of a box per patch), the
/// ratios and the curves.
#[must_use]
pub fn model_bytes(model: &Model) -> usize {
    let g = &model.surface;
    std::mem::size_of_val(g.nodes())
        + g.patch_count() * 2 * std::mem::size_of::<DVec3>() * 4 / 3
        + (g.ratios_u().len() + g.ratios_v().len()) * 8
        + curves_bytes(&model.curves)
        + std::mem::size_of::<Model>()
}

fn curves_bytes(curves: &[DynCurve]) -> usize {
    curves
        .iter()
        .map(|c| match c {
            DynCurve::D2(c) => c.points().len() * 16 + 64,
            DynCurve::D3(c) => c.points().len() * 24 + 64,
        })
        .sum()
}

/// True when two grids have the same patch layout (topology, counts, spacing ratios): only
/// then can a step be a difference of control points.
fn same_shape(a: &Grid, b: &Grid) -> bool {
    a.topology() == b.topology()
        && a.patches_u() == b.patches_u()
        && a.patches_v() == b.patches_v()
        && a.ratios_u() == b.ratios_u()
        && a.ratios_v() == b.ratios_v()
}

impl History {
    /// Memory the steps may hold before the oldest are dropped: 100 MB.
    pub const DEFAULT_LIMIT_BYTES: usize = 100_000_000;

    /// An empty history whose base is `model` (the model as the document starts).
    #[must_use]
    pub fn new(model: &Model) -> Self {
        Self {
            undo: VecDeque::new(),
            redo: Vec::new(),
            bytes: 0,
            limit_bytes: Self::DEFAULT_LIMIT_BYTES,
            base: model.clone(),
            open: None,
            dirty: Dirty::default(),
            origin: None,
        }
    }

    /// Sets the memory limit of the steps (the newest step is kept whatever its size).
    pub fn set_limit_bytes(&mut self, limit: usize) {
        self.limit_bytes = limit;
        self.enforce_limit();
    }

    /// The memory limit of the steps.
    #[must_use]
    pub fn limit_bytes(&self) -> usize {
        self.limit_bytes
    }

    /// Notes that these patches' control points may have changed since the last commit.
    /// A long live stroke notes the same patches frame after frame: the list is kept free of
    /// repeats whenever it has doubled, so it stays about the size of what the edit touched.
    pub fn touch_patches(&mut self, patches: &[usize]) {
        if !self.dirty.everything {
            let dirty = &mut self.dirty;
            dirty.patches.extend_from_slice(patches);
            if dirty.patches.len() > 2 * dirty.distinct.max(256) {
                dirty.patches.sort_unstable();
                dirty.patches.dedup();
                dirty.distinct = dirty.patches.len();
            }
        }
    }

    /// Notes that anything on the surface may have changed since the last commit.
    pub fn touch_everything(&mut self) {
        self.dirty.everything = true;
        self.dirty.patches = Vec::new();
    }

    /// Begins the edit `what`: commits the edit in progress (given the current `model`), then
    /// names what changes from here on until the next commit. Clears redo at the commit.
    pub fn begin(&mut self, what: impl Into<String>, model: &Model) {
        self.commit(model);
        self.open = Some(what.into());
        self.drop_redo();
    }

    /// Begins the edit `what` that started from `before` (an edit noticed only after it began
    /// changing the model, like a hand contact): commits the edit in progress, then takes
    /// `before` as the base, so that the step recorded at the next commit leads from `before`
    /// to the model then. Compares whole nets at that commit.
    ///
    /// Should `before` differ from the base (changes made since the last commit and before
    /// `before`), those become a step of their own, kept whole, so that every step still leads
    /// exactly from the state of the one below it.
    pub fn begin_from(&mut self, what: impl Into<String>, before: Model) {
        let earlier = self.open.take();
        self.dirty = Dirty::default();
        self.drop_redo();
        if let Some(origin) = self.origin.take() {
            // A re-gridded edit leads from its origin to `before`, kept whole.
            self.base = before;
            self.push_undo(Step {
                what: earlier.unwrap_or_else(|| "edit".to_string()),
                change: Change::Whole(origin),
            });
        } else if before != self.base {
            let old = std::mem::replace(&mut self.base, before);
            self.push_undo(Step {
                what: earlier.unwrap_or_else(|| "edit".to_string()),
                change: Change::Whole(Box::new(old)),
            });
        }
        self.open = Some(what.into());
        self.touch_everything();
    }

    /// True while an edit is begun and not yet committed.
    #[must_use]
    pub fn is_open(&self) -> bool {
        self.open.is_some()
    }

    /// Commits the edit in progress: what `model` changed since the base becomes one undo
    /// step (changes made with no edit begun join it, or make a step "edit" of their own).
    /// Costs what the touched patches hold.
    pub fn commit(&mut self, model: &Model) {
        let Some(what) = self.open.take().or_else(|| {
            let changed = !self.dirty.is_empty()
                || model.regulation != self.base.regulation
                || model.curves != self.base.curves;
            changed.then(|| "edit".to_string())
        }) else {
            return;
        };
        let dirty = std::mem::take(&mut self.dirty);
        let change = if let Some(origin) = self.origin.take() {
            // The edit moved onto a finer grid: the step leads from the model it started from.
            self.base = model.clone();
            Change::Whole(origin)
        } else if same_shape(&self.base.surface, &model.surface) {
            let before = self.base.surface.nodes();
            let after = model.surface.nodes();
            let nodes = if dirty.everything {
                NodeDelta::between(before, after, 0..after.len())
            } else {
                let grid = &model.surface;
                let m = grid.patches_u();
                let mut ids: Vec<usize> = dirty
                    .patches
                    .iter()
                    .filter(|&&p| p < grid.patch_count())
                    .flat_map(|&p| grid.patch_node_ids(p % m, p / m))
                    .collect();
                ids.sort_unstable();
                ids.dedup();
                NodeDelta::between(before, after, ids.into_iter())
            };
            let regulation = (self.base.regulation != model.regulation)
                .then_some((self.base.regulation, model.regulation));
            let curves = (self.base.curves != model.curves)
                .then(|| Box::new((self.base.curves.clone(), model.curves.clone())));
            let change = Change::Delta {
                nodes,
                regulation,
                curves,
            };
            // Bring the base up to the model where it changed.
            let mut forward = Step {
                what: String::new(),
                change,
            };
            if forward.swap(&mut self.base, false).is_err() {
                // Only a model the grid itself refused could get here; keep exactness by
                // falling back to the whole model.
                let before = std::mem::replace(&mut self.base, model.clone());
                Change::Whole(Box::new(before))
            } else {
                forward.change
            }
        } else {
            let before = std::mem::replace(&mut self.base, model.clone());
            Change::Whole(Box::new(before))
        };
        self.push_undo(Step { what, change });
        self.drop_redo();
    }

    /// Puts `model` back to where the open edit began (a cancelled stroke: the origin, when
    /// the edit was re-gridded, or else the base where it changed since the last commit) and
    /// forgets the edit in progress. Returns what changed on the surface.
    pub fn revert(&mut self, model: &mut Model) -> Restored {
        self.open = None;
        if let Some(origin) = self.origin.take() {
            self.dirty = Dirty::default();
            self.base = *origin;
            *model = self.base.clone();
            return Restored::Everything;
        }
        self.rewind(model)
    }

    /// Puts `model` back to the base where it changed since the last commit (what a
    /// [`History::revert`] does when the edit stayed on the base's grid). Costs what the edit
    /// touched since. Returns what changed on the surface.
    fn rewind(&mut self, model: &mut Model) -> Restored {
        let dirty = std::mem::take(&mut self.dirty);
        model.regulation = self.base.regulation;
        if model.curves != self.base.curves {
            model.curves.clone_from(&self.base.curves);
        }
        if !same_shape(&self.base.surface, &model.surface) {
            *model = self.base.clone();
            return Restored::Everything;
        }
        let grid = &model.surface;
        let ids: Vec<usize> = if dirty.everything {
            (0..grid.nodes().len()).collect()
        } else {
            let m = grid.patches_u();
            let mut ids: Vec<usize> = dirty
                .patches
                .iter()
                .filter(|&&p| p < grid.patch_count())
                .flat_map(|&p| grid.patch_node_ids(p % m, p / m))
                .collect();
            ids.sort_unstable();
            ids.dedup();
            ids
        };
        let base = self.base.surface.nodes();
        let changes: Vec<(usize, DVec3)> = ids
            .into_iter()
            .filter(|&id| {
                grid.nodes()[id].to_array().map(f64::to_bits)
                    != base[id].to_array().map(f64::to_bits)
            })
            .map(|id| (id, base[id]))
            .collect();
        match model.surface.set_nodes(&changes) {
            Ok(patches) => Restored::Patches(patches),
            Err(_) => {
                *model = self.base.clone();
                Restored::Everything
            }
        }
    }

    /// Moves the open edit onto `model`, a finer grid of the surface the edit started from (an
    /// auto-refinement during a live stroke, the stroke's start put back first): from here on
    /// `model` is the base, while the step the edit commits still leads from the model it
    /// started from and a [`History::revert`] puts that one back. False (nothing done) when no
    /// edit is open.
    pub fn rebase_open(&mut self, model: &Model) -> bool {
        if self.open.is_none() {
            return false;
        }
        let before = std::mem::replace(&mut self.base, model.clone());
        if self.origin.is_none() {
            self.origin = Some(Box::new(before));
        }
        self.dirty = Dirty::default();
        true
    }

    /// Renames the open edit (a live stroke named after its final operation: a push that
    /// ended as a pull). False when no edit is open.
    pub fn rename_open(&mut self, what: impl Into<String>) -> bool {
        match &mut self.open {
            Some(name) => {
                *name = what.into();
                true
            }
            None => false,
        }
    }

    /// Undoes the last edit on `model` (committing the edit in progress first); `None` when
    /// there is nothing to undo.
    pub fn undo(&mut self, model: &mut Model) -> Option<Restored> {
        self.commit(model);
        let mut step = self.undo.pop_back()?;
        self.bytes -= step.bytes();
        let restored = self.swap_both(&mut step, model, true);
        self.bytes += step.bytes();
        self.redo.push(step);
        Some(restored)
    }

    /// Redoes the last undone edit on `model`; `None` when there is none.
    pub fn redo(&mut self, model: &mut Model) -> Option<Restored> {
        self.commit(model);
        let mut step = self.redo.pop()?;
        self.bytes -= step.bytes();
        let restored = self.swap_both(&mut step, model, false);
        self.push_undo(step);
        Some(restored)
    }

    /// Applies a step to the model and keeps the base equal to it.
    fn swap_both(&mut self, step: &mut Step, model: &mut Model, to_before: bool) -> Restored {
        match step.swap(model, to_before) {
            Ok(Restored::Everything) => {
                self.base = model.clone();
                Restored::Everything
            }
            Ok(restored) => {
                if step.swap(&mut self.base, to_before).is_err() {
                    self.base = model.clone();
                }
                restored
            }
            Err(_) => {
                // The model was as the step expects (the base), so this cannot happen; stay
                // consistent if it did.
                self.base = model.clone();
                Restored::Everything
            }
        }
    }

    fn push_undo(&mut self, step: Step) {
        self.bytes += step.bytes();
        self.undo.push_back(step);
        self.enforce_limit();
    }

    fn drop_redo(&mut self) {
        for step in self.redo.drain(..) {
            self.bytes -= step.bytes();
        }
    }

    fn enforce_limit(&mut self) {
        while self.bytes > self.limit_bytes && self.undo.len() + self.redo.len() > 1 {
            let dropped = if let Some(step) = self.undo.pop_front() {
                step
            } else {
                // Only redo steps hold the memory: drop the furthest one.
                self.redo.remove(0)
            };
            self.bytes -= dropped.bytes();
        }
    }

    /// The name of the edit undo would revert (the edit in progress, if one is begun).
    #[must_use]
    pub fn undo_name(&self) -> Option<&str> {
        self.open
            .as_deref()
            .or_else(|| self.undo.back().map(|s| s.what.as_str()))
    }

    /// The name of the edit redo would reapply.
    #[must_use]
    pub fn redo_name(&self) -> Option<&str> {
        if self.open.is_some() {
            return None;
        }
        self.redo.last().map(|s| s.what.as_str())
    }

    /// Forgets everything: `model` becomes the base (a new or opened model).
    pub fn clear(&mut self, model: &Model) {
        *self = Self {
            limit_bytes: self.limit_bytes,
            ..Self::new(model)
        };
    }

    /// Number of edits that can be undone (the edit in progress counts).
    #[must_use]
    pub fn undo_len(&self) -> usize {
        self.undo.len() + usize::from(self.open.is_some())
    }

    /// Number of edits that can be redone.
    #[must_use]
    pub fn redo_len(&self) -> usize {
        self.redo.len()
    }

    /// Bytes the undo and redo steps hold.
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.bytes
    }

    /// Bytes of the base model the steps apply to (one model, whatever the depth).
    #[must_use]
    pub fn base_bytes(&self) -> usize {
        model_bytes(&self.base)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Op, Primitive, PrimitiveParams, Sculptor};

    fn plane(n: usize) -> Model {
        let params = PrimitiveParams {
            patches: Some((n, n)),
            ..PrimitiveParams::default()
        };
        Model::new(Primitive::Plane.build(&params).expect("plane"))
    }

    fn push(model: &mut Model, history: &mut History, x: f64) {
        let op = Op::Push {
            at: DVec3::new(x, 0.25, 0.0),
            dir: -DVec3::Z,
            depth: 0.3,
            radius: 1.0,
        };
        history.begin("push", model);
        let touched = Sculptor::new()
            .apply(&mut model.surface, &op, model.regulation)
            .expect("push");
        history.touch_patches(&touched.patches);
        history.commit(model);
    }

    #[test]
    fn undo_then_redo_restores_each_state() {
        let mut now = plane(6);
        let mut h = History::new(&now);
        let a = now.clone();
        push(&mut now, &mut h, 0.0);
        let b = now.clone();
        push(&mut now, &mut h, 1.5);
        let c = now.clone();
        assert_ne!(a, b);
        assert!(h.undo(&mut now).is_some());
        assert_eq!(now, b);
        assert!(h.undo(&mut now).is_some());
        assert_eq!(now, a);
        assert!(h.undo(&mut now).is_none());
        assert!(h.redo(&mut now).is_some());
        assert_eq!(now, b);
        assert_eq!(h.redo_name(), Some("push"));
        assert!(h.redo(&mut now).is_some());
        assert_eq!(now, c);
        h.undo(&mut now);
        // A new edit drops what could have been redone.
        push(&mut now, &mut h, -1.0);
        assert!(h.redo(&mut now).is_none());
        assert_eq!(h.redo_len(), 0);
    }

    /// An open edit rewinds to its base as often as asked, keeps its name, and once moved
    /// onto a finer grid rewinds to that grid, commits one step from the original and
    /// reverts to the original, bit for bit.
    #[test]
    fn an_open_edit_rewinds_and_rebases_onto_a_refinement() {
        let op = |depth: f64| Op::Push {
            at: DVec3::new(0.1, 0.25, 0.0),
            dir: -DVec3::Z,
            depth,
            radius: 1.0,
        };
        let mut now = plane(6);
        let start = now.clone();
        let mut h = History::new(&now);
        h.begin("push", &now);
        let mut sculptor = Sculptor::new();
        for depth in [0.1, 0.2] {
            h.rewind(&mut now);
            let t = sculptor
                .apply(&mut now.surface, &op(depth), now.regulation)
                .expect("push");
            h.touch_patches(&t.patches);
            let mut back = now.clone();
            let restored = h.clone().rewind(&mut back);
            assert_eq!(back, start, "rewound bit for bit");
            assert_eq!(
                restored,
                Restored::Patches(t.patches.clone()),
                "the touched patches"
            );
        }
        assert_eq!(h.undo_name(), Some("push"), "the name stays");
        // Onto a finer grid of the same surface.
        h.rewind(&mut now);
        let finer = crate::surface::refine::Refinement::uniform(&now.surface, 2)
            .and_then(|r| r.apply(&now.surface))
            .expect("refined");
        now.surface = finer;
        let rebased = now.clone();
        assert!(h.rebase_open(&now));
        let t = sculptor
            .apply(&mut now.surface, &op(0.3), now.regulation)
            .expect("push");
        h.touch_patches(&t.patches);
        let mut back = now.clone();
        h.clone().rewind(&mut back);
        assert_eq!(back, rebased, "rewinds to the finer grid");
        let mut cancelled = now.clone();
        assert_eq!(h.clone().revert(&mut cancelled), Restored::Everything);
        assert_eq!(cancelled, start, "a revert puts the original grid back");
        assert!(h.rename_open("pull"));
        h.commit(&now);
        let end = now.clone();
        assert_eq!(h.undo_len(), 1);
        assert!(h.undo(&mut now).is_some());
        assert_eq!(now, start, "one step back to the original grid");
        assert!(h.redo(&mut now).is_some());
        assert_eq!(now, end);
        assert_eq!(h.undo_name(), Some("pull"));
    }

    /// A live stroke notes the patches of every frame; the list stays about the size of
    /// what was touched, not of the frames shown.
    #[test]
    fn touched_patches_noted_frame_after_frame_stay_few() {
        let now = plane(6);
        let mut h = History::new(&now);
        h.begin("push", &now);
        for frame in 0..10_000 {
            h.touch_patches(&[frame % 7, 3, 4, 5]);
        }
        assert!(
            h.dirty.patches.len() <= 2 * 256 + 4,
            "{}",
            h.dirty.patches.len()
        );
        let mut noted = h.dirty.patches.clone();
        noted.sort_unstable();
        noted.dedup();
        assert_eq!(noted, (0..7).collect::<Vec<_>>(), "no patch is lost");
    }

    #[test]
    fn a_change_of_shape_is_kept_whole() {
        let mut now = plane(2);
        let mut h = History::new(&now);
        h.begin("new plane", &now);
        now = plane(3);
        h.touch_everything();
        h.commit(&now);
        assert!(h.bytes() > model_bytes(&plane(2)));
        assert_eq!(h.undo(&mut now), Some(Restored::Everything));
        assert_eq!(now, plane(2));
        assert_eq!(h.redo(&mut now), Some(Restored::Everything));
        assert_eq!(now, plane(3));
    }

    #[test]
    fn the_oldest_steps_go_first_past_the_memory_limit() {
        let mut now = plane(8);
        let mut h = History::new(&now);
        push(&mut now, &mut h, 0.0);
        let one = h.bytes();
        assert!(one > 0);
        h.set_limit_bytes(3 * one + one / 2);
        for k in 0..6 {
            push(&mut now, &mut h, -2.0 + 0.7 * f64::from(k));
        }
        assert!(
            h.bytes() <= h.limit_bytes(),
            "{} > {}",
            h.bytes(),
            h.limit_bytes()
        );
        assert!(h.undo_len() >= 2 && h.undo_len() < 7, "{}", h.undo_len());
    }

    #[test]
    fn node_deltas_round_trip_every_bit_pattern() {
        let before = vec![
            DVec3::new(0.0, -0.0, 1.0),
            DVec3::new(1e-300, f64::MAX, -3.5),
            DVec3::new(2.0, 2.0, 2.0),
            DVec3::new(0.1, 0.2, 0.3),
        ];
        let after = vec![
            DVec3::new(-0.0, 0.0, 1.0),
            DVec3::new(-1e-300, f64::MIN_POSITIVE, -3.5000000000000004),
            DVec3::new(2.0, 2.0, 2.0),
            DVec3::new(0.1 + 1e-17, 7e5, 0.3),
        ];
        let d = NodeDelta::between(&before, &after, 0..4);
        assert_eq!(d.count, 3, "the unchanged node is not stored");
        for (id, x) in d.entries() {
            for k in 0..3 {
                assert_eq!(before[id][k].to_bits() ^ x[k], after[id][k].to_bits());
            }
        }
        let mut ids = Vec::new();
        for v in [0u64, 1, 127, 128, 300, u64::from(u32::MAX) + 5] {
            write_varint(&mut ids, v);
        }
        let mut r = ids.as_slice();
        for v in [0u64, 1, 127, 128, 300, u64::from(u32::MAX) + 5] {
            assert_eq!(read_varint(&mut r), v);
        }
    }
}
