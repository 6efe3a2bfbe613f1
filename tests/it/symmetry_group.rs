//! Symmetry groups (issue 27): radial symmetry about the z axis, the lathe, and mirrors across
//! x, y and z combined — invariance after 200 random operations of every kind on every
//! rotational primitive, G1 kept, undo bit-identical, and the refusals (`N` not dividing the
//! patch columns, a model without the symmetry), all with fixed seeds.

use glam::DVec3;
use nendo::editor::document::Document;
use nendo::editor::stroke::LiveStroke;
use nendo::model::Model;
use nendo::surface::brush::{Brush, Falloff};
use nendo::surface::{
    Dirs, Grid, Isometry, MirrorError, Op, Plane, Primitive, PrimitiveParams, Regulation,
    SculptBrush, SculptKind, Sculptor, SurfaceError, Symmetry, SymmetrySpec, continuity,
    group_error, is_symmetric, nearest,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::support::{run, temp_dir};

/// The primitives that turn about the z axis.
const ROTATIONAL: [Primitive; 5] = [
    Primitive::Cylinder,
    Primitive::Tube,
    Primitive::Hemisphere,
    Primitive::Sphere,
    Primitive::Torus,
];

fn build(p: Primitive) -> Grid {
    p.build(&PrimitiveParams::default()).expect("primitive")
}

fn random_surface_point(rng: &mut ChaCha8Rng, grid: &Grid) -> (DVec3, DVec3) {
    let m = grid.patches_u();
    let p = rng.gen_range(0..grid.patch_count());
    let (u, v) = (rng.gen_range(0.05..0.95), rng.gen_range(0.05..0.95));
    let x = grid.eval(p % m, p / m, u, v);
    let n = grid.normal(p % m, p / m, u, v).unwrap_or(DVec3::Z);
    (x, n)
}

/// One of every kind of operation `nendo sculpt` accepts, at a random surface point.
fn random_op(rng: &mut ChaCha8Rng, grid: &Grid) -> Op {
    let (at, n) = random_surface_point(rng, grid);
    let radius = rng.gen_range(0.4..1.0);
    let depth = rng.gen_range(-0.1..0.1);
    match rng.gen_range(0..6 + SculptKind::ALL.len()) {
        0 => Op::Push {
            at,
            dir: -n,
            depth,
            radius,
        },
        1 => Op::PushNormal { at, depth, radius },
        2 => {
            let (b, _) = random_surface_point(rng, grid);
            Op::Drag {
                path: vec![at, at + (b - at).clamp_length_max(1.0)],
                dir: -n,
                depth,
                radius,
            }
        }
        3 => {
            let (b, _) = random_surface_point(rng, grid);
            let end = at + (b - at).clamp_length_max(1.0);
            Op::Groove {
                path: vec![at, at.lerp(end, 0.5), end],
                dirs: Dirs::Normal,
                depth,
                radius,
            }
        }
        4 => Op::Move {
            at,
            to: at + (DVec3::new(rng.r#gen(), rng.r#gen(), rng.r#gen()) - 0.5) * 0.15,
            radius,
        },
        5 => Op::Smooth {
            at,
            radius,
            strength: rng.gen_range(0.1..1.0),
        },
        k => {
            // The surface brushes: inflate and flatten as dabs, pinch and crease as strokes.
            let kind = SculptKind::ALL[k - 6];
            let (b, _) = random_surface_point(rng, grid);
            let path = match kind {
                SculptKind::Inflate | SculptKind::Flatten => vec![at],
                SculptKind::Pinch | SculptKind::Crease => {
                    vec![at, at + (b - at).clamp_length_max(1.0)]
                }
            };
            let depth = match kind {
                SculptKind::Inflate | SculptKind::Crease => depth,
                SculptKind::Flatten | SculptKind::Pinch => 0.0,
            };
            let brush = Brush {
                falloff: Falloff::ALL[rng.gen_range(0..Falloff::ALL.len())],
                strength: rng.gen_range(0.1..1.0),
            };
            Op::Sculpt(SculptBrush::try_new(kind, path, radius, depth, brush).expect("valid brush"))
        }
    }
}

/// 200 random operations with `spec` on `p`: the model invariant under the whole group to
/// 1e-12 of its size after every operation, refusals leaving it bit for bit, G1 kept.
fn sculpt_with(p: Primitive, spec: &SymmetrySpec, seed: u64) {
    let mut grid = build(p);
    let symmetry = Symmetry::group(&grid, spec).unwrap_or_else(|e| panic!("{p} {spec}: {e}"));
    symmetry.enforce_all(&mut grid, true).expect("fits");
    let start = grid.clone();
    let g1_start = continuity::report(&grid, 9).g1_max_deg;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut sculptor = Sculptor::new();
    let (mut refused, mut worst, mut drift) = (0, 0.0f64, 0.0f64);
    for k in 0..200 {
        let op = random_op(&mut rng, &grid);
        let before = grid.clone();
        match sculptor.apply_mirrored(&mut grid, &op, Regulation::Exact, &symmetry) {
            Ok(_) => drift = drift.max(sculptor.last_asymmetry()),
            Err(SurfaceError::NotG1 { .. } | SurfaceError::OutOfRange { .. }) => {
                assert_eq!(
                    grid, before,
                    "{p} {spec} op {k}: a refusal changed the model"
                );
                refused += 1;
            }
            Err(e) => panic!("{p} {spec} op {k}: {op:?}: {e}"),
        }
        let e = group_error(&grid, &symmetry);
        worst = worst.max(e);
        assert!(e <= 1e-12, "{p} {spec} op {k}: {op:?}: asymmetry {e:.2e}");
    }
    let g1 = continuity::report(&grid, 9).g1_max_deg;
    eprintln!(
        "{p} {spec} (order {}): worst asymmetry {worst:.1e} over 200 ops ({refused} refused), \
         largest before enforcing {drift:.1e}, G1 {g1_start:.2e}° -> {g1:.2e}°",
        symmetry.order()
    );
    assert!(g1 <= 0.01, "{p} {spec}: G1 {g1}°");
    assert!(refused < 40, "{p} {spec}: {refused} refused");
    assert!(grid != start, "{p} {spec}: nothing happened");
}

fn radial(n: u32) -> SymmetrySpec {
    SymmetrySpec {
        radial: n,
        ..SymmetrySpec::default()
    }
}

/// `N` = half the patch columns (4 on the default 8, 8 on the tube's 16).
#[test]
fn radial_symmetry_stays_exact_on_every_rotational_primitive() {
    for (i, p) in ROTATIONAL.into_iter().enumerate() {
        let n = (build(p).patches_u() / 2) as u32;
        sculpt_with(p, &radial(n), 100 + i as u64);
    }
}

#[test]
fn lathe_stays_exact_on_every_rotational_primitive() {
    let spec = SymmetrySpec {
        lathe: true,
        ..SymmetrySpec::default()
    };
    for (i, p) in ROTATIONAL.into_iter().enumerate() {
        sculpt_with(p, &spec, 200 + i as u64);
    }
}

/// Every mirror the primitive has, combined (x and y on all; z too on the sphere and the
/// torus), and a mirror with radial symmetry (dihedral).
#[test]
fn combined_mirrors_stay_exact_on_every_rotational_primitive() {
    for (i, p) in ROTATIONAL.into_iter().enumerate() {
        let grid = build(p);
        let mut spec = SymmetrySpec::default();
        for plane in Plane::ALL {
            if is_symmetric(&grid, plane) {
                spec.add_plane(plane);
            }
        }
        assert!(spec.planes.len() >= 2, "{p}: {spec}");
        sculpt_with(p, &spec, 300 + i as u64);
        let mut dihedral = radial((grid.patches_u() / 4) as u32);
        dihedral.add_plane(Plane::X);
        sculpt_with(p, &dihedral, 400 + i as u64);
    }
}

/// Whether two isometries are the same map (on the basis, to rounding).
fn same_map(a: &Isometry, b: &Isometry) -> bool {
    [DVec3::X, DVec3::Y, DVec3::Z]
        .iter()
        .all(|&e| (a.apply(e) - b.apply(e)).length() < 1e-9)
}

/// Every group the 24-column tube (and the 8 × 4 sphere, mirrors across z too) can be given —
/// every set of mirrors with every radial `N` dividing the columns — is a group: each map
/// listed once, the identity left out, every product of two elements the identity or an
/// element, of the order its mirrors and turns make (`N` turns; twice as many maps with a
/// vertical mirror; twice again with z). Mirrors across x and y with an odd `N` make the
/// `2N`-fold turn. A map listed twice under two names (the mirror across y and the mirror
/// across x after a half turn) once made `--mirror x,y --radial 4` refuse 580 of the
/// `tube-pot` trace's 3 232 frames (creases up to 0.07°).
#[test]
fn every_symmetry_spec_makes_a_closed_group_of_distinct_maps() {
    let tube = Primitive::Tube
        .build(&PrimitiveParams {
            patches: Some((24, 8)),
            ..PrimitiveParams::default()
        })
        .expect("tube");
    let sphere = build(Primitive::Sphere);
    let mut checked = 0;
    for (grid, planes) in [
        (&tube, &[Plane::X, Plane::Y][..]),
        (&sphere, &[Plane::X, Plane::Y, Plane::Z][..]),
    ] {
        for mask in 0..(1u32 << planes.len()) {
            for n in [1, 2, 3, 4, 6, 8, 12] {
                let mut spec = radial(n);
                for (i, &p) in planes.iter().enumerate() {
                    if mask & (1 << i) != 0 {
                        spec.add_plane(p);
                    }
                }
                let Ok(g) = Symmetry::group(grid, &spec) else {
                    assert!(
                        grid.patches_u() % (n as usize) != 0
                            || (n % 2 == 1
                                && mask & 3 == 3
                                && grid.patches_u() % (2 * n as usize) != 0),
                        "{spec} refused on {} columns",
                        grid.patches_u()
                    );
                    continue;
                };
                let elements: Vec<Isometry> = g.isometries().copied().collect();
                let vertical = usize::from(mask & 3 != 0);
                let z = usize::from(mask & 4 != 0);
                let both = mask & 3 == 3;
                if n > 1 {
                    let turns = if both && n % 2 == 1 { 2 * n } else { n };
                    assert_eq!(g.turns(), turns, "{spec}");
                }
                // The rotations in the group: the `N` turns, with the half turn when both
                // vertical mirrors are in it.
                let rotations = if both && n % 2 == 1 { 2 * n } else { n };
                assert_eq!(
                    g.order(),
                    (rotations as usize) << (vertical + z),
                    "{spec}: {elements:?}"
                );
                for (i, a) in elements.iter().enumerate() {
                    assert!(!same_map(a, &Isometry::IDENTITY), "{spec}: {a:?}");
                    for b in &elements[i + 1..] {
                        assert!(!same_map(a, b), "{spec}: {a:?} and {b:?} are one map");
                    }
                    for b in &elements {
                        let ab = a.then_after(b);
                        assert!(
                            same_map(&ab, &Isometry::IDENTITY)
                                || elements.iter().any(|c| same_map(c, &ab)),
                            "{spec}: {a:?} after {b:?} is not in the group"
                        );
                    }
                }
                checked += 1;
            }
        }
    }
    assert!(checked >= 30, "{checked} groups checked");
}

/// Mirrors across x and y with the 4-fold turn: the same group as the mirror across x with it,
/// sculpted the same way (200 random operations, exact, G1).
#[test]
fn mirrors_across_x_and_y_with_a_radial_turn_stay_exact() {
    let mut spec = radial(4);
    spec.add_plane(Plane::X);
    spec.add_plane(Plane::Y);
    sculpt_with(Primitive::Tube, &spec, 500);
}

/// A lathe push at one point dents the tube all the way round: at every angle the wall is
/// pushed in by the same depth (to the rounding of the group's turns), between the copies of
/// the group as much as on them.
#[test]
fn a_lathe_push_goes_all_the_way_round() {
    let mut grid = build(Primitive::Tube);
    let spec = SymmetrySpec {
        lathe: true,
        ..SymmetrySpec::default()
    };
    let symmetry = Symmetry::group(&grid, &spec).expect("the tube turns");
    assert_eq!(symmetry.turns() as usize, grid.patches_u());
    let z = 2.5;
    let radius_at = |grid: &Grid, angle: f64| {
        let dir = DVec3::new(angle.cos(), angle.sin(), 0.0);
        // Where the wall crosses the ray from the axis at height z.
        let mut r = 2.0;
        for _ in 0..40 {
            let s = nearest(grid, DVec3::new(0.0, 0.0, z) + dir * r)
                .expect("near")
                .point;
            r = (s - DVec3::new(0.0, 0.0, z)).dot(dir);
        }
        r
    };
    let before: Vec<f64> = (0..36)
        .map(|k| radius_at(&grid, k as f64 * 0.1745))
        .collect();
    let at = DVec3::new(2.0 * 0.3f64.cos(), 2.0 * 0.3f64.sin(), z);
    Sculptor::new()
        .apply_mirrored(
            &mut grid,
            &Op::PushNormal {
                at,
                depth: 0.3,
                radius: 0.8,
            },
            Regulation::Exact,
            &symmetry,
        )
        .expect("pushed");
    let dents: Vec<f64> = (0..36)
        .map(|k| before[k] - radius_at(&grid, k as f64 * 0.1745))
        .collect();
    let (lo, hi) = dents.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &d| {
        (lo.min(d), hi.max(d))
    });
    eprintln!("lathe push 0.3 on the tube: dent {lo:.4} .. {hi:.4} at 36 angles");
    assert!(lo > 0.2, "dented all round: {dents:?}");
    assert!(hi - lo < 0.02 * hi, "evenly: {lo} .. {hi}");
}

/// Radial symmetry whose N does not divide the patch columns is refused with the reason (not
/// refined); so is radial symmetry on the plane, and a model that lost the symmetry.
#[test]
fn radial_symmetry_is_refused_where_the_model_does_not_have_it() {
    let tube = build(Primitive::Tube);
    let e = Symmetry::group(&tube, &radial(3)).unwrap_err();
    assert_eq!(e, MirrorError::Columns { n: 3, columns: 16 });
    assert!(e.to_string().contains("divisible by 3"), "{e}");
    let plane = build(Primitive::Plane);
    assert_eq!(
        Symmetry::group(&plane, &radial(2)).unwrap_err(),
        MirrorError::NotRotational
    );
    let mut pushed = tube.clone();
    Sculptor::new()
        .apply(
            &mut pushed,
            &Op::PushNormal {
                at: DVec3::new(2.0, 0.0, 2.0),
                depth: 0.3,
                radius: 0.8,
            },
            Regulation::Exact,
        )
        .expect("pushed");
    let e = Symmetry::group(&pushed, &radial(4)).unwrap_err();
    assert!(matches!(e, MirrorError::NotRadial { n: 4, .. }), "{e}");
    // Still mirror symmetric about y = 0 (the push was on the x axis), not about x = 0.
    let mut spec = radial(1);
    spec.add_plane(Plane::Y);
    assert!(Symmetry::group(&pushed, &spec).is_ok());
    spec.add_plane(Plane::X);
    assert!(matches!(
        Symmetry::group(&pushed, &spec),
        Err(MirrorError::NotSymmetric(a)) if a.plane == Plane::X
    ));

    // The command line says the same and writes nothing.
    let dir = temp_dir("symmetry_group_refusal");
    let out = dir.join("m.json");
    let o = run(&[
        "sculpt",
        "--primitive",
        "tube",
        "--radial",
        "3",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--radial 3") && err.contains("divisible by 3"),
        "{err}"
    );
    assert!(!out.exists());
}

/// Through the window's document: a lathe stroke and a combined-mirror stroke are each one
/// undo step, and undo gives the model back bit for bit.
#[test]
fn undo_of_a_group_stroke_is_bit_identical() {
    for (p, spec) in [
        (
            Primitive::Tube,
            SymmetrySpec {
                lathe: true,
                ..SymmetrySpec::default()
            },
        ),
        (Primitive::Sphere, {
            let mut s = radial(4);
            s.add_plane(Plane::X);
            s.add_plane(Plane::Z);
            s
        }),
    ] {
        let mut doc = Document::new(Model::new(build(p)));
        let symmetry = Symmetry::group(&doc.model().surface, &spec).expect("symmetric");
        let bits = |g: &Grid| -> Vec<[u64; 3]> {
            g.nodes()
                .iter()
                .map(|x| x.to_array().map(f64::to_bits))
                .collect()
        };
        let before = bits(&doc.model().surface);
        let mut rng = ChaCha8Rng::seed_from_u64(27);
        let op = random_op(&mut rng, &doc.model().surface);
        let op = match op {
            Op::Smooth { .. } | Op::Move { .. } => Op::PushNormal {
                at: random_surface_point(&mut rng, &doc.model().surface).0,
                depth: 0.2,
                radius: 0.7,
            },
            other => other,
        };
        let mut stroke = LiveStroke::begin(&doc, &[], &nendo::mesh::TriMesh::default(), false)
            .with_mirror(Some(symmetry.clone()));
        stroke.show(&mut doc, Some(&op));
        assert!(stroke.commit(&mut doc, Some(&op)).is_none(), "{p} {spec}");
        assert_ne!(bits(&doc.model().surface), before, "{p} {spec}: changed");
        assert!(group_error(&doc.model().surface, &symmetry) <= 1e-12);
        assert!(doc.undo());
        assert_eq!(bits(&doc.model().surface), before, "{p} {spec}: undo");
    }
}
