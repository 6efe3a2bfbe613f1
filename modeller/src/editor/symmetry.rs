//! The window's symmetry: the toggle (X), whether the model allows it, and how a mirrored
//! stroke is refined.
//!
//! With symmetry on, every window stroke (Push, Pull, Draw a line, Move, Smooth) is applied
//! together with its mirror image across the plane `x = 0` as one operation
//! ([`crate::surface::Sculptor::apply_mirrored`], as `nendo sculpt --mirror x`), and so is every
//! contact of the Hand tool (the hand loop's envelope with the mirrored fingers, see
//! [`super::hand_input`]). The toggle is offered only when the model is symmetric about
//! the plane ([`Symmetry::of`]: every control point's mirror image is a control point, to
//! [`crate::surface::SYMMETRY_TOLERANCE`], and the grid spacing mirrors); it is on by
//! default then, and otherwise disabled with the reason ([`MirrorError`]).
//!
//! **Auto-refine with a mirror.** The CLI refuses `--auto-refine` with `--mirror`: a refinement
//! for one finger splits columns on one side only, and the grid is no longer symmetric. The
//! window refines where the operation's finger reaches ([`refine::for_finger`]) *and* at the
//! mirror images of those grid parameters, in one refinement ([`refine_mirrored`]): the mirror
//! map takes a global grid parameter `T` to `T` or to `s − T` (mod `M` around a closed
//! direction), read from the partners of the grid vertices. (Refining for the operation and
//! then for its mirror image, [`reflect_op`], is not enough: the finger rule compares patch
//! sizes with `σ·r_f / 2`, and a piece exactly that wide is split on one side and not on the
//! other by rounding.) The result is kept only when the refined grid is still symmetric (a new
//! [`Symmetry`] is found for it); otherwise (an odd number of insertions around a closed
//! direction, the grid limit) the stroke goes on unrefined and the status line says so.

use crate::surface::{Dirs, Grid, MirrorError, Op, Plane, Symmetry, refine};

/// The mirror image of an operation across `plane`: every point and direction reflected.
#[must_use]
pub fn reflect_op(op: &Op, plane: Plane) -> Op {
    let r = |v| plane.reflect(v);
    match op {
        Op::Push {
            at,
            dir,
            depth,
            radius,
        } => Op::Push {
            at: r(*at),
            dir: r(*dir),
            depth: *depth,
            radius: *radius,
        },
        Op::Drag {
            path,
            dir,
            depth,
            radius,
        } => Op::Drag {
            path: path.iter().map(|p| r(*p)).collect(),
            dir: r(*dir),
            depth: *depth,
            radius: *radius,
        },
        Op::PushNormal { at, depth, radius } => Op::PushNormal {
            at: r(*at),
            depth: *depth,
            radius: *radius,
        },
        Op::Groove {
            path,
            dirs,
            depth,
            radius,
        } => Op::Groove {
            path: path.iter().map(|p| r(*p)).collect(),
            dirs: match dirs {
                Dirs::Normal => Dirs::Normal,
                Dirs::Each(d) => Dirs::Each(d.iter().map(|v| r(*v)).collect()),
            },
            depth: *depth,
            radius: *radius,
        },
        Op::Move { at, to, radius } => Op::Move {
            at: r(*at),
            to: r(*to),
            radius: *radius,
        },
        Op::Smooth {
            at,
            radius,
            strength,
        } => Op::Smooth {
            at: r(*at),
            radius: *radius,
            strength: *strength,
        },
    }
}

/// What auto-refine does for a mirrored operation.
#[derive(Debug, Clone)]
pub enum MirroredRefinement {
    /// Nothing to refine (or the operation is invalid: the operation itself says why).
    Unchanged,
    /// The grid refined for the operation and its mirror image, still symmetric: the
    /// refined grid and its mirror map.
    Refined(Box<(Grid, Symmetry)>),
    /// The refinement would break the grid's symmetry: not refined.
    Asymmetric,
}

/// Refines `grid` where `op`'s finger reaches ([`refine::for_finger`]) and at the mirror
/// images of those parameters, in one refinement, keeping the result only when it is still
/// symmetric about `mirror`'s plane (see the module docs).
#[must_use]
pub fn refine_mirrored(grid: &Grid, op: &Op, mirror: &Symmetry) -> MirroredRefinement {
    let Ok(f) = refine::for_finger(grid, op) else {
        return MirroredRefinement::Unchanged;
    };
    if f.refinement.is_empty() {
        return MirroredRefinement::Unchanged;
    }
    let t = grid.topology();
    let map_u = ParameterMap::of(grid.patches_u(), t.closed_u(), grid.vertices_u(), |k| {
        mirror.vertex_partner(grid, k, 0).0
    });
    let map_v = ParameterMap::of(grid.patches_v(), t.closed_v(), grid.vertices_v(), |q| {
        mirror.vertex_partner(grid, 0, q).1
    });
    let u = map_u.with_images(f.refinement.inserted_u());
    let v = map_v.with_images(f.refinement.inserted_v());
    let Ok(refined) = refine::Refinement::new(grid, &u, &v).and_then(|r| r.apply(grid)) else {
        return MirroredRefinement::Asymmetric;
    };
    match Symmetry::of(&refined, mirror.plane()) {
        Ok(s) => MirroredRefinement::Refined(Box::new((refined, s))),
        Err(_) => MirroredRefinement::Asymmetric,
    }
}

/// The mirror map on a direction's global grid parameters: `T ↦ T`, or `T ↦ s − T` (taken
/// mod `M` on a closed direction), read from the partners of the grid vertices.
#[derive(Debug, Clone, Copy, PartialEq)]
enum ParameterMap {
    Identity,
    Reflect { s: f64, count: usize, closed: bool },
}

impl ParameterMap {
    fn of(count: usize, closed: bool, vertices: usize, partner: impl Fn(usize) -> usize) -> Self {
        let (p0, p1) = (partner(0), partner(1 % vertices.max(1)));
        if p0 == 0 && (vertices < 2 || p1 == 1) {
            ParameterMap::Identity
        } else {
            ParameterMap::Reflect {
                s: p0 as f64,
                count,
                closed,
            }
        }
    }

    fn apply(self, t: f64) -> f64 {
        match self {
            ParameterMap::Identity => t,
            ParameterMap::Reflect { s, count, closed } => {
                let r = s - t;
                if closed {
                    r.rem_euclid(count as f64)
                } else {
                    r
                }
            }
        }
    }

    /// `params` and their images, sorted, without repeats (within 1e-12).
    fn with_images(self, params: Vec<f64>) -> Vec<f64> {
        let mut all: Vec<f64> = params.iter().map(|&t| self.apply(t)).collect();
        all.extend(params);
        all.sort_by(f64::total_cmp);
        all.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
        all
    }
}

/// The symmetry toggle: what the user asked for, and whether the model allows it.
#[derive(Debug, Clone)]
pub struct MirrorToggle {
    plane: Plane,
    /// The user's choice (on by default, as in Blender's sculpt mode).
    wanted: bool,
    /// The mirror map of the surface at a document revision, or why there is none.
    found: Option<(u64, Result<Symmetry, MirrorError>)>,
}

impl MirrorToggle {
    /// A toggle for `plane`, on.
    #[must_use]
    pub fn new(plane: Plane) -> Self {
        Self {
            plane,
            wanted: true,
            found: None,
        }
    }

    /// The mirror plane.
    #[must_use]
    pub fn plane(&self) -> Plane {
        self.plane
    }

    /// The user's choice.
    #[must_use]
    pub fn wanted(&self) -> bool {
        self.wanted
    }

    /// Sets the user's choice.
    pub fn set_wanted(&mut self, on: bool) {
        self.wanted = on;
    }

    /// Looks for the mirror map of `grid`, the surface at document revision `revision`
    /// (nothing to do when that revision was looked at already).
    pub fn update(&mut self, revision: u64, grid: &Grid) {
        if self.found.as_ref().is_some_and(|(r, _)| *r == revision) {
            return;
        }
        self.found = Some((revision, Symmetry::of(grid, self.plane)));
    }

    /// Forgets what was found (another document: its revisions start again).
    pub fn invalidate(&mut self) {
        self.found = None;
    }

    /// True when the model allows the mirror (as last looked at).
    #[must_use]
    pub fn available(&self) -> bool {
        matches!(self.found, Some((_, Ok(_))))
    }

    /// Why the model does not allow the mirror (`None` when it does, or before a look).
    #[must_use]
    pub fn why_not(&self) -> Option<String> {
        match &self.found {
            Some((_, Err(e))) => Some(format!(
                "Symmetry is offered only for a model symmetric about {}: {e}",
                self.plane
            )),
            _ => None,
        }
    }

    /// The mirror the strokes use on `grid`: wanted, available, and made for this grid.
    #[must_use]
    pub fn active(&self, grid: &Grid) -> Option<&Symmetry> {
        match &self.found {
            Some((_, Ok(s))) if self.wanted && s.fits(grid) => Some(s),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Primitive, PrimitiveParams, Regulation, Sculptor};
    use glam::DVec3;

    /// Every primitive is symmetric about x = 0: the toggle is offered (and on); after an
    /// unmirrored push off the plane it is not, and says why.
    #[test]
    fn the_toggle_is_offered_only_for_a_symmetric_model() {
        for primitive in Primitive::ALL {
            let grid = primitive
                .build(&PrimitiveParams::default())
                .expect("primitive");
            let mut toggle = MirrorToggle::new(Plane::X);
            toggle.update(0, &grid);
            assert!(toggle.available(), "{}", primitive.name());
            assert!(toggle.active(&grid).is_some());
            assert!(toggle.why_not().is_none());
            toggle.set_wanted(false);
            assert!(toggle.active(&grid).is_none(), "off when the user says so");
        }
        let mut grid = Primitive::Plane
            .build(&PrimitiveParams::default())
            .expect("plane");
        Sculptor::new()
            .apply(
                &mut grid,
                &Op::Push {
                    at: DVec3::new(1.5, 0.5, 0.0),
                    dir: -DVec3::Z,
                    depth: 0.3,
                    radius: 1.0,
                },
                Regulation::Exact,
            )
            .expect("push");
        let mut toggle = MirrorToggle::new(Plane::X);
        toggle.update(1, &grid);
        assert!(!toggle.available());
        assert!(toggle.active(&grid).is_none());
        let why = toggle.why_not().expect("a reason");
        assert!(
            why.contains("x = 0") && why.contains("not symmetric"),
            "{why}"
        );
    }

    /// The mirror image of every operation form reflects its points and directions exactly;
    /// reflecting twice gives the operation back.
    #[test]
    fn reflecting_an_operation_twice_gives_it_back() {
        let a = DVec3::new(0.3, -0.7, 0.2);
        let b = DVec3::new(-1.1, 0.4, 0.9);
        let ops = [
            Op::Push {
                at: a,
                dir: b,
                depth: 0.2,
                radius: 1.0,
            },
            Op::Drag {
                path: vec![a, b],
                dir: b,
                depth: -0.1,
                radius: 0.5,
            },
            Op::PushNormal {
                at: a,
                depth: 0.3,
                radius: 0.4,
            },
            Op::Groove {
                path: vec![a, b],
                dirs: Dirs::Each(vec![b, a]),
                depth: 0.1,
                radius: 0.6,
            },
            Op::Move {
                at: a,
                to: b,
                radius: 0.7,
            },
            Op::Smooth {
                at: b,
                radius: 0.8,
                strength: 0.5,
            },
        ];
        for op in &ops {
            let m = reflect_op(op, Plane::X);
            assert_ne!(&m, op);
            assert_eq!(&reflect_op(&m, Plane::X), op);
        }
        let Op::Move { at, to, .. } = reflect_op(&ops[4], Plane::X) else {
            panic!("a move")
        };
        assert_eq!(
            (at, to),
            (DVec3::new(-0.3, -0.7, 0.2), DVec3::new(1.1, 0.4, 0.9))
        );
    }

    /// A push off the plane x = 0 on every primitive: the refinement for it and the mirror
    /// images of its parameters keeps the grid symmetric, with more patches than before.
    #[test]
    fn a_mirrored_refinement_stays_symmetric() {
        for primitive in Primitive::ALL {
            let grid = primitive
                .build(&PrimitiveParams::default())
                .expect("primitive");
            let mirror = Symmetry::of(&grid, Plane::X).expect("symmetric");
            // A control point well off the plane, on the surface's side of x > 0.
            let at = grid
                .patches()
                .iter()
                .flatten()
                .copied()
                .filter(|p| p.x > 0.8)
                .min_by(|a, b| (a.x - 1.3).abs().total_cmp(&(b.x - 1.3).abs()))
                .expect("a point");
            let near = crate::surface::nearest(&grid, at).expect("near").point;
            let op = Op::PushNormal {
                at: near,
                depth: 0.2,
                radius: 0.45,
            };
            match refine_mirrored(&grid, &op, &mirror) {
                MirroredRefinement::Refined(found) => {
                    let (refined, s) = *found;
                    assert!(refined.patch_count() > grid.patch_count());
                    assert!(s.fits(&refined));
                }
                other => panic!("{}: refined expected: {other:?}", primitive.name()),
            }
        }
    }
}
