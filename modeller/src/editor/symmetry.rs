//! The window's symmetry: the toggle (X), radial symmetry (Shift+X, `N` in the tool panel),
//! the lathe and the mirror planes (tool panel), whether the model allows them, and how a
//! mirrored stroke is refined.
//!
//! The symmetry asked for is a [`SymmetrySpec`] — any of the mirrors across x, y, z, and
//! `N`-fold radial symmetry about the z axis or the lathe (every stroke all the way round) —
//! made into one group ([`Symmetry::group`]) for the model; everything below said of the
//! mirror holds for every isometry of the group.
//!
//! **The lathe** asked for (Shift+X after radial symmetry, or the panel's checkbox) is the
//! lathe proper — `N` = the patch columns — when the model has every column's turn (a fresh
//! primitive); a model sculpted with radial symmetry has only its `N` turns (its dents, and the
//! columns auto-refine split unevenly round the axis), so the lathe keeps that `N`
//! ([`lathe_for`]): every stroke still goes all the way round (its field the envelope of its
//! turns every `2π / K`, [`crate::surface::SymmetrySpec::lathe`]) and the model stays `N`-fold.
//! (Asking for the lathe proper there was refused, the status line naming the turn the model
//! lacks, and the strokes after it stayed radial.)
//!
//! With symmetry on, every window stroke (Push, Pull, Draw a line, Move, Smooth, Inflate,
//! Flatten, Pinch, Crease) is applied
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

use crate::surface::{
    Dirs, Grid, MirrorError, Op, Plane, SculptBrush, Symmetry, SymmetrySpec, refine,
};

/// The mirror image of an operation across `plane`: every point and direction reflected.
#[must_use]
pub fn reflect_op(op: &Op, plane: Plane) -> Op {
    let r = |v| plane.reflect(v);
    match op {
        Op::Brushed { op, brush } => Op::Brushed {
            op: Box::new(reflect_op(op, plane)),
            brush: *brush,
        },
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
        Op::Sculpt(b) => Op::Sculpt(SculptBrush {
            path: b.path.iter().map(|p| r(*p)).collect(),
            ..b.clone()
        }),
    }
}

/// The symmetry asked for, made one the model has where a lathe is asked for: the lathe
/// proper (`N` = the patch columns, the model invariant under every column's turn) when the
/// grid allows it, else the lathe over `radial_n`-fold symmetry (the stroke still applied all
/// the way round, the model kept `radial_n`-fold: what a model sculpted with radial symmetry
/// has, and what the window's Shift+X cycle goes to from there). Any other request, or one
/// neither allows, is returned as asked (the refusal then names why).
#[must_use]
pub fn lathe_for(grid: &Grid, spec: SymmetrySpec, radial_n: u32) -> SymmetrySpec {
    if !spec.lathe || spec.radial > 1 || radial_n <= 1 || Symmetry::group(grid, &spec).is_ok() {
        return spec;
    }
    let turned = SymmetrySpec {
        radial: radial_n,
        ..spec.clone()
    };
    if Symmetry::group(grid, &turned).is_ok() {
        turned
    } else {
        spec
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
    let images = |params: Vec<f64>, along_v: bool| {
        let mut all: Vec<f64> = params
            .iter()
            .flat_map(|&t| mirror.parameter_images(grid, t, along_v))
            .collect();
        all.sort_by(f64::total_cmp);
        all.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
        all
    };
    let u = images(f.refinement.inserted_u(), false);
    let v = images(f.refinement.inserted_v(), true);
    let Ok(refined) = refine::Refinement::new(grid, &u, &v).and_then(|r| r.apply(grid)) else {
        return MirroredRefinement::Asymmetric;
    };
    match Symmetry::group(&refined, mirror.spec()) {
        Ok(s) => MirroredRefinement::Refined(Box::new((refined, s))),
        Err(_) => MirroredRefinement::Asymmetric,
    }
}

/// The symmetry toggle: what the user asked for, and whether the model allows it.
#[derive(Debug, Clone)]
pub struct MirrorToggle {
    /// The symmetry asked for: mirrors, radial `N`, lathe.
    spec: SymmetrySpec,
    /// `N` radial symmetry takes when turned on (Shift+X), kept while it is off.
    radial_n: u32,
    /// The user's choice (on by default, as in Blender's sculpt mode).
    wanted: bool,
    /// The symmetry group of the surface at a document revision, or why there is none.
    found: Option<(u64, Result<Symmetry, MirrorError>)>,
}

impl MirrorToggle {
    /// A toggle for the mirror across `plane`, on.
    #[must_use]
    pub fn new(plane: Plane) -> Self {
        Self {
            spec: SymmetrySpec::mirror(plane),
            radial_n: 4,
            wanted: true,
            found: None,
        }
    }

    /// The symmetry asked for.
    #[must_use]
    pub fn spec(&self) -> &SymmetrySpec {
        &self.spec
    }

    /// Asks for another symmetry (looked for again at the next [`MirrorToggle::update`]).
    pub fn set_spec(&mut self, spec: SymmetrySpec) {
        if spec.radial > 1 {
            self.radial_n = spec.radial;
        }
        if spec != self.spec {
            self.spec = spec;
            self.found = None;
        }
    }

    /// `N` radial symmetry takes when turned on.
    #[must_use]
    pub fn radial_n(&self) -> u32 {
        self.radial_n
    }

    /// The symmetry with radial symmetry turned on (with [`MirrorToggle::radial_n`]) or off
    /// (and the lathe off with it).
    #[must_use]
    pub fn with_radial(&self, on: bool) -> SymmetrySpec {
        let mut spec = self.spec.clone();
        spec.radial = if on { self.radial_n } else { 0 };
        spec.lathe = false;
        spec
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

    /// Looks for the symmetry group of `grid`, the surface at document revision `revision`
    /// (nothing to do when that revision was looked at already).
    pub fn update(&mut self, revision: u64, grid: &Grid) {
        if self.found.as_ref().is_some_and(|(r, _)| *r == revision) {
            return;
        }
        self.found = Some((revision, Symmetry::group(grid, &self.spec)));
    }

    /// Forgets what was found (another document: its revisions start again).
    pub fn invalidate(&mut self) {
        self.found = None;
    }

    /// True when the model allows the symmetry (as last looked at).
    #[must_use]
    pub fn available(&self) -> bool {
        matches!(self.found, Some((_, Ok(_))))
    }

    /// Why the model does not allow the symmetry (`None` when it does, or before a look).
    #[must_use]
    pub fn why_not(&self) -> Option<String> {
        match &self.found {
            Some((_, Err(e))) => Some(format!(
                "Symmetry ({}) is offered only for a model that has it: {e}",
                self.spec
            )),
            _ => None,
        }
    }

    /// The symmetry the strokes use on `grid`: wanted, available, and made for this grid.
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
