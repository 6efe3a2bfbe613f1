//! Tests of [`super`].

use super::*;
use crate::surface::{Primitive, PrimitiveParams, Sculptor};
use glam::DVec3;

/// The sphere of radius 3 with 16 × 8 patches.
fn sphere_16x8() -> Grid {
    Primitive::Sphere
        .build(&PrimitiveParams {
            patches: Some((16, 8)),
            ..PrimitiveParams::default()
        })
        .unwrap()
}

/// The engine's one rule, seen from both drivers: a mirrored hand contact of one
/// placement and the mirrored push it stands for give bit-identical grids — on the mirror
/// plane (where a flow and its mirror image tie), across it (where the finger and its
/// image overlap), and away from it — with every regulation method, on the plane, the
/// cylinder and the sphere.
#[test]
fn a_mirrored_contact_and_a_mirrored_push_give_the_same_grid() {
    use crate::surface::{Plane, Symmetry};
    let mut compared = 0;
    for primitive in [Primitive::Plane, Primitive::Cylinder, Primitive::Sphere] {
        let base = primitive.build(&PrimitiveParams::default()).unwrap();
        let symmetry = Symmetry::of(&base, Plane::X).unwrap();
        let b = base.bounds();
        for x in [0.0, 0.35, -0.8, 1.7] {
            // A point above the surface at `x`, the finger pressing towards the centre.
            let target = DVec3::new(x, 0.3 * (b.max.y - b.min.y) * 0.2, b.max.z);
            let near = crate::surface::nearest(&base, target).unwrap();
            let dir = -(near.point - (b.min + b.max) * 0.5).normalize();
            let dir = if primitive == Primitive::Plane {
                -DVec3::Z
            } else {
                dir
            };
            for reg in Regulation::ALL {
                let placement = [Placement {
                    tip: near.point + 0.3 * dir,
                    dir,
                    depth: 0.3,
                }];
                let mut contact = base.clone();
                let mut presser = Presser::default();
                presser.set_mirror(Some(symmetry.clone()));
                let pressed = presser.apply(&base, &mut contact, &placement, 0.9, 100.0, reg);
                let mut op = base.clone();
                let pushed = Sculptor::new().apply_mirrored(
                    &mut op,
                    &describe(&placement, 0.9)[0],
                    reg,
                    &symmetry,
                );
                assert_eq!(
                    pressed.is_ok(),
                    pushed.is_ok(),
                    "{primitive} x {x} {reg}: {pressed:?} vs {pushed:?}"
                );
                assert!(
                    contact != base || pressed.is_err(),
                    "{primitive} x {x}: no dent"
                );
                let same =
                    contact.nodes().iter().zip(op.nodes()).all(|(a, b)| {
                        a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits)
                    });
                if !same {
                    for (i, (a, b)) in contact.nodes().iter().zip(op.nodes()).enumerate() {
                        if a != b {
                            eprintln!("{i}: {a} vs {b} base {}", base.nodes()[i]);
                        }
                    }
                }
                assert!(
                    same,
                    "{primitive} x {x} {reg}: the contact and the push differ"
                );
                assert_eq!(contact, op, "{primitive} x {x} {reg}");
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 3 * 4 * Regulation::ALL.len());
}

#[test]
fn a_mirror_made_for_another_grid_is_refused_not_dropped() {
    use crate::surface::{Plane, Symmetry};
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let symmetry = Symmetry::of(&plane, Plane::X).unwrap();
    let finer = Primitive::Plane
        .build(&PrimitiveParams {
            patches: Some((12, 10)),
            ..PrimitiveParams::default()
        })
        .unwrap();
    let placement = [Placement {
        tip: DVec3::new(0.5, 0.0, -0.3),
        dir: -DVec3::Z,
        depth: 0.3,
    }];
    let mut presser = Presser::default();
    presser.set_mirror(Some(symmetry.clone()));
    let mut grid = finer.clone();
    let got = presser.apply(&finer, &mut grid, &placement, 1.0, 2.0, Regulation::Exact);
    assert!(matches!(got, Err(SurfaceError::BadOp(_))), "{got:?}");
    assert_eq!(grid, finer);
    let mut grid = finer.clone();
    let got = Sculptor::new().apply_mirrored(
        &mut grid,
        &describe(&placement, 1.0)[0],
        Regulation::Exact,
        &symmetry,
    );
    assert!(matches!(got, Err(SurfaceError::BadOp(_))), "{got:?}");
    assert_eq!(grid, finer);
}

#[test]
fn one_placement_is_exactly_a_push_and_a_straight_stroke_exactly_a_drag() {
    for reg in Regulation::ALL {
        let base = Primitive::Sphere
            .build(&PrimitiveParams::default())
            .unwrap();
        let at = DVec3::new(2.0, 1.0, 0.5).normalize() * 3.0;
        let dir = -at.normalize();
        let push = [Placement {
            tip: at + 0.4 * dir,
            dir,
            depth: 0.4,
        }];
        let mut got = base.clone();
        Presser::default()
            .apply(&base, &mut got, &push, 1.0, 2.0, reg)
            .unwrap();
        let mut want = base.clone();
        Sculptor::new()
            .apply(&mut want, &describe(&push, 1.0)[0], reg)
            .unwrap();
        assert_eq!(got.nodes(), want.nodes(), "push, {reg}");

        let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
        let d = -DVec3::Z;
        let stroke: Vec<Placement> = (0..5)
            .map(|k| Placement {
                tip: DVec3::new(-1.0 + 0.5 * k as f64, 0.2, -0.3),
                dir: d,
                depth: 0.3,
            })
            .collect();
        let mut got = plane.clone();
        Presser::default()
            .apply(&plane, &mut got, &stroke, 1.0, 2.0, reg)
            .unwrap();
        let mut want = plane.clone();
        let drag = Op::Drag {
            path: stroke.iter().map(|p| p.tip - 0.3 * d).collect(),
            dir: d,
            depth: 0.3,
            radius: 1.0,
        };
        Sculptor::new().apply(&mut want, &drag, reg).unwrap();
        for (a, b) in got.nodes().iter().zip(want.nodes()) {
            assert!((*a - *b).length() < 1e-12, "stroke, {reg}: {a} vs {b}");
        }
    }
}

#[test]
fn growing_a_stroke_frame_by_frame_equals_applying_it_at_once() {
    // Every regulation, g2 included: its contact projects the contact's exact net, never the
    // last frame's g2 result (`commit`'s `G2Contact`).
    for reg in Regulation::ALL {
        grow_a_stroke(reg);
    }
}

fn grow_a_stroke(reg: Regulation) {
    let sphere = sphere_16x8();
    let on = |lon: f64, r: f64| DVec3::new(lon.cos() * 0.9, lon.sin() * 0.9, 0.436) * r;
    let mut placements = Vec::new();
    let mut grid = sphere.clone();
    let mut presser = Presser::default();
    presser.begin(&sphere);
    for k in 0..40 {
        let lon = 0.05 * k as f64;
        let dir = -on(lon, 1.0).normalize();
        // The live placement deepens, then a new one starts; every few, the depth changes.
        let depth = 0.2 + 0.1 * ((k / 7) as f64);
        placements.push(Placement {
            tip: on(lon, 3.0) + depth * dir,
            dir,
            depth,
        });
        presser
            .apply(&sphere, &mut grid, &placements, 0.8, 2.0, reg)
            .unwrap();
        let last = placements.len() - 1;
        placements[last].depth += 0.05;
        placements[last].tip += 0.05 * dir;
        presser
            .apply(&sphere, &mut grid, &placements, 0.8, 2.0, reg)
            .unwrap();
    }
    let mut once = sphere.clone();
    Presser::default()
        .apply(&sphere, &mut once, &placements, 0.8, 2.0, reg)
        .unwrap();
    assert_eq!(grid.nodes(), once.nodes(), "{reg}");
    assert_eq!(grid, once, "{reg}");
}

#[test]
fn joining_and_splitting_coupled_sets_frame_by_frame_equals_applying_at_once() {
    // Two dents far apart (two sets of groups solved on their own), a broad third push
    // that joins them into one set, then the third taken away again (the sets split, and
    // the groups only the third touched go back to the reference): after every frame the
    // grid is exactly the contact applied at once.
    let plane = Primitive::Plane
        .build(&PrimitiveParams {
            patches: Some((10, 10)),
            ..PrimitiveParams::default()
        })
        .unwrap();
    let push = |x: f64, y: f64, depth: f64| {
        [Placement {
            tip: DVec3::new(x, y, -depth),
            dir: -DVec3::Z,
            depth,
        }]
    };
    let (a, b, c) = (
        push(-2.6, 0.3, 0.3),
        push(2.4, -0.2, 0.25),
        push(0.1, 0.2, 0.2),
    );
    let stroke = |placements, radius| Stroke {
        placements,
        radius,
        length: 2.0,
    };
    let (a, b, c) = (&a[..], &b[..], &c[..]);
    let frames = [
        vec![stroke(a, 1.0)],
        vec![stroke(a, 1.0), stroke(b, 1.0)],
        vec![stroke(a, 1.0), stroke(b, 1.0), stroke(c, 2.2)],
        vec![stroke(a, 1.0), stroke(b, 1.0)],
    ];
    let mut grid = plane.clone();
    let mut presser = Presser::default();
    presser.begin(&plane);
    for (f, strokes) in frames.iter().enumerate() {
        presser
            .apply_strokes(&plane, &mut grid, strokes, Regulation::default())
            .unwrap();
        let mut once = plane.clone();
        Presser::default()
            .apply_strokes(&plane, &mut once, strokes, Regulation::default())
            .unwrap();
        assert_eq!(grid, once, "frame {f}");
    }
}

#[test]
fn several_strokes_grown_frame_by_frame_equal_them_applied_at_once() {
    // Three fingers on the 16 × 8 sphere, near each other (shared patches and groups),
    // each growing its own stroke and deepening its live placement frame by frame, one of
    // them joining late; with and without a mirror. Every frame keeps the fingers that did
    // not change (and their flows): the result must be exactly that of a fresh presser
    // given the final strokes at once.
    let sphere = sphere_16x8();
    let on = |lon: f64, lat: f64| {
        DVec3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin()) * 3.0
    };
    for mirror in [None, Some(crate::surface::Plane::Y)] {
        let symmetry = mirror.map(|pl| Symmetry::of(&sphere, pl).unwrap());
        let mut presser = Presser::default();
        presser.set_mirror(symmetry.clone());
        presser.begin(&sphere);
        let mut grid = sphere.clone();
        let mut tracks: Vec<Vec<Placement>> = vec![Vec::new(), Vec::new(), Vec::new()];
        for k in 0..24 {
            for (f, t) in tracks.iter_mut().enumerate() {
                if f == 2 && k < 9 {
                    continue;
                }
                let (lon, lat) = (0.3 + 0.04 * k as f64, 0.2 + 0.35 * f as f64);
                let dir = -on(lon, lat).normalize();
                let depth = 0.15 + 0.02 * ((k + f) % 5) as f64;
                let next = Placement {
                    tip: on(lon, lat) + depth * dir,
                    dir,
                    depth,
                };
                // Every other frame the live placement deepens instead of a new one.
                if k % 2 == 1 && !t.is_empty() {
                    let last = t.len() - 1;
                    t[last].depth += 0.03;
                    let d = t[last].dir;
                    t[last].tip += 0.03 * d;
                } else {
                    // Every third frame the live placement also moves before the next
                    // one starts (as a merged straight run does): the new segment's start
                    // changed too.
                    if k % 3 == 2 && !t.is_empty() {
                        let last = t.len() - 1;
                        t[last].tip += 0.05 * DVec3::Z;
                    }
                    // Now and then an earlier placement moves alone: the segment after it
                    // changes with it though its own placement does not.
                    if k % 4 == 0 && t.len() >= 3 {
                        let mid = t.len() - 2;
                        t[mid].tip -= 0.04 * DVec3::Z;
                    }
                    t.push(next);
                }
            }
            let strokes: Vec<Stroke<'_>> = tracks
                .iter()
                .filter(|t| !t.is_empty())
                .enumerate()
                .map(|(f, t)| Stroke {
                    placements: t,
                    radius: 0.7 + 0.1 * f as f64,
                    length: 2.0,
                })
                .collect();
            presser
                .apply_strokes(&sphere, &mut grid, &strokes, Regulation::default())
                .unwrap();
        }
        let strokes: Vec<Stroke<'_>> = tracks
            .iter()
            .enumerate()
            .map(|(f, t)| Stroke {
                placements: t,
                radius: 0.7 + 0.1 * f as f64,
                length: 2.0,
            })
            .collect();
        let mut once = sphere.clone();
        let mut fresh = Presser::default();
        fresh.set_mirror(symmetry);
        fresh
            .apply_strokes(&sphere, &mut once, &strokes, Regulation::default())
            .unwrap();
        assert_eq!(grid.nodes(), once.nodes(), "mirror {mirror:?}");
    }
}

#[test]
fn strokes_far_apart_are_each_their_own_push_and_one_stroke_is_apply() {
    // Two fingers pressing the 16 × 8 sphere far apart (opposite sides, no shared group):
    // together, one application, exactly each push applied on its own, one after the other;
    // a palm-sized radius for the second.
    let sphere = sphere_16x8();
    let on = |d: DVec3| 3.0 * d.normalize();
    let a = DVec3::new(1.0, 0.3, 0.2);
    let b = DVec3::new(-1.0, -0.2, -0.1);
    let pa = [Placement {
        tip: on(a) - 0.3 * a.normalize(),
        dir: -a.normalize(),
        depth: 0.3,
    }];
    let pb = [Placement {
        tip: on(b) - 0.2 * b.normalize(),
        dir: -b.normalize(),
        depth: 0.2,
    }];
    for reg in Regulation::ALL {
        let strokes = [
            Stroke {
                placements: &pa,
                radius: 0.8,
                length: 2.0,
            },
            Stroke {
                placements: &pb,
                radius: 1.2,
                length: 2.0,
            },
        ];
        let mut together = sphere.clone();
        Presser::default()
            .apply_strokes(&sphere, &mut together, &strokes, reg)
            .unwrap();
        let mut apart = sphere.clone();
        Sculptor::new()
            .apply(&mut apart, &describe(&pa, 0.8)[0], reg)
            .unwrap();
        Sculptor::new()
            .apply(&mut apart, &describe(&pb, 1.2)[0], reg)
            .unwrap();
        // Under g2 a stroke's window reaches two patches past what it moves (on this 8 × 4
        // sphere, the whole grid), so strokes far apart are not independent there.
        if reg != Regulation::G2 {
            for (x, y) in together.nodes().iter().zip(apart.nodes()) {
                assert!((*x - *y).length() < 1e-12, "{reg}: {x} vs {y}");
            }
        }
        let mut one = sphere.clone();
        Presser::default()
            .apply_strokes(&sphere, &mut one, &strokes[..1], reg)
            .unwrap();
        let mut plain = sphere.clone();
        Presser::default()
            .apply(&sphere, &mut plain, &pa, 0.8, 2.0, reg)
            .unwrap();
        assert_eq!(one, plain, "{reg}");
    }
}

#[test]
fn reapplying_restores_what_the_last_application_moved() {
    for reg in Regulation::ALL {
        reapply(reg);
    }
}

fn reapply(reg: Regulation) {
    let base = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let mut grid = base.clone();
    let mut presser = Presser::default();
    presser.begin(&base);
    let deep = [Placement {
        tip: DVec3::new(2.0, 2.0, -0.5),
        dir: -DVec3::Z,
        depth: 0.5,
    }];
    let shallow = [Placement {
        tip: DVec3::new(-2.0, -2.0, -0.2),
        dir: -DVec3::Z,
        depth: 0.2,
    }];
    presser
        .apply(&base, &mut grid, &deep, 1.0, 2.0, reg)
        .unwrap();
    presser
        .apply(&base, &mut grid, &shallow, 1.0, 2.0, reg)
        .unwrap();
    let mut once = base.clone();
    Presser::default()
        .apply(&base, &mut once, &shallow, 1.0, 2.0, reg)
        .unwrap();
    assert_eq!(grid, once, "{reg}");
}

/// A finger held in the clay under every regulation, its tip jittering by a micrometre
/// frame after frame (a resting hand on a tracker): the surface stays where the first frame
/// put it — every frame whose placement is the first's gives that frame's grid, bit for bit.
/// (Under g2 each frame once re-projected the last frame's result, and a held contact drifted
/// ≈ 3e-3 side per frame.)
#[test]
fn a_held_jittering_contact_does_not_drift() {
    let sphere = sphere_16x8();
    let at = DVec3::new(0.9, 0.2, 0.4).normalize();
    let held = |jitter: f64| {
        [Placement {
            tip: 3.0 * at - (0.3 + jitter) * at,
            dir: -at,
            depth: 0.3 + jitter,
        }]
    };
    for reg in Regulation::ALL {
        let mut grid = sphere.clone();
        let mut presser = Presser::default();
        presser.begin(&sphere);
        presser
            .apply(&sphere, &mut grid, &held(0.0), 0.8, 2.0, reg)
            .unwrap();
        let first = grid.clone();
        for k in 0..30 {
            let jitter = 1e-6 * f64::from(k % 5) - 2e-6;
            presser
                .apply(&sphere, &mut grid, &held(jitter), 0.8, 2.0, reg)
                .unwrap();
            presser
                .apply(&sphere, &mut grid, &held(0.0), 0.8, 2.0, reg)
                .unwrap();
            assert_eq!(grid, first, "{reg}, frame {k}");
        }
    }
}
