//! The patch grid: topologies, counts, layout, shared control points, primitives.

use glam::DVec3;
use nendo::surface::{
    Grid, Ideal, Primitive, PrimitiveParams, PrimitiveSize, SurfaceError, Topology,
};

fn params(m: usize, n: usize) -> PrimitiveParams {
    PrimitiveParams {
        patches: Some((m, n)),
        ..PrimitiveParams::default()
    }
}

#[test]
fn odd_counts_around_closed_directions_are_rejected() {
    for p in [
        Primitive::Cylinder,
        Primitive::Hemisphere,
        Primitive::Sphere,
        Primitive::Torus,
        Primitive::Tube,
    ] {
        let err = p.build(&params(7, 4)).unwrap_err();
        assert!(
            matches!(
                err,
                SurfaceError::OddClosedCount {
                    direction: "u",
                    got: 7,
                    ..
                }
            ),
            "{p}: {err}"
        );
        assert!(err.to_string().contains("even"), "{err}");
    }
    let err = Primitive::Torus.build(&params(8, 5)).unwrap_err();
    assert!(
        matches!(
            err,
            SurfaceError::OddClosedCount {
                direction: "v",
                got: 5,
                ..
            }
        ),
        "{err}"
    );
    // Open directions take any count.
    assert!(Primitive::Plane.build(&params(7, 3)).is_ok());
    assert!(Primitive::Cylinder.build(&params(8, 3)).is_ok());
}

#[test]
fn too_few_patches_are_rejected() {
    assert!(matches!(
        Primitive::Plane.build(&params(0, 3)),
        Err(SurfaceError::TooFewPatches { .. })
    ));
    // A pole needs 2n ≥ 6 patches around it.
    assert!(matches!(
        Primitive::Sphere.build(&params(4, 4)),
        Err(SurfaceError::TooFewPatches {
            direction: "u",
            min: 6,
            ..
        })
    ));
    assert!(Primitive::Sphere.build(&params(6, 2)).is_ok());
    assert!(matches!(
        Primitive::Sphere.build(&params(8, 1)),
        Err(SurfaceError::TooFewPatches { .. })
    ));
}

#[test]
fn bad_sizes_are_rejected() {
    let p = PrimitiveParams {
        radius: Some(-1.0),
        ..PrimitiveParams::default()
    };
    assert!(matches!(
        Primitive::Sphere.build(&p),
        Err(SurfaceError::BadParameter { .. })
    ));
    let p = PrimitiveParams {
        radius: Some(f64::NAN),
        ..PrimitiveParams::default()
    };
    assert!(matches!(
        Primitive::Cylinder.build(&p),
        Err(SurfaceError::BadParameter { .. })
    ));
    let p = PrimitiveParams {
        radius: Some(1.0),
        minor_radius: Some(2.0),
        ..PrimitiveParams::default()
    };
    assert!(matches!(
        Primitive::Torus.build(&p),
        Err(SurfaceError::BadParameter { .. })
    ));
}

#[test]
fn plane_patches_are_unit_squares_in_the_documented_layout() {
    let g = Primitive::Plane.build(&params(10, 6)).unwrap();
    assert_eq!((g.patches_u(), g.patches_v(), g.patch_count()), (10, 6, 60));
    for iv in 0..6 {
        for iu in 0..10 {
            let p = g.patch(iu, iv);
            assert_eq!(p, g.patch_at(iv * 10 + iu));
            for i in 0..4 {
                for j in 0..4 {
                    let want = DVec3::new(
                        iu as f64 + i as f64 / 3.0 - 5.0,
                        iv as f64 + j as f64 / 3.0 - 3.0,
                        0.0,
                    );
                    assert!((p[4 * i + j] - want).length() < 1e-14);
                }
            }
            assert_eq!(g.normal(iu, iv, 0.3, 0.6), Some(DVec3::Z));
        }
    }
    let b = g.bounds();
    assert_eq!(
        (b.min, b.max),
        (DVec3::new(-5.0, -3.0, 0.0), DVec3::new(5.0, 3.0, 0.0))
    );
}

/// Patch `(iu, iv)`'s neighbour along +u / +v, if the topology has one.
fn neighbour(g: &Grid, iu: usize, iv: usize, along_u: bool) -> Option<(usize, usize)> {
    let (m, n) = (g.patches_u(), g.patches_v());
    if along_u {
        if iu + 1 < m {
            Some((iu + 1, iv))
        } else if g.topology().closed_u() {
            Some((0, iv))
        } else {
            None
        }
    } else if iv + 1 < n {
        Some((iu, iv + 1))
    } else if g.topology().closed_v() {
        Some((iu, 0))
    } else {
        None
    }
}

#[test]
fn shared_boundaries_seams_and_poles_are_the_same_points() {
    for p in Primitive::ALL {
        let g = p.build(&PrimitiveParams::default()).unwrap();
        for iv in 0..g.patches_v() {
            for iu in 0..g.patches_u() {
                let a = g.patch(iu, iv);
                if let Some((ju, jv)) = neighbour(&g, iu, iv, true) {
                    let b = g.patch(ju, jv);
                    for j in 0..4 {
                        assert_eq!(a[12 + j], b[j], "{p}: u-edge of ({iu},{iv})");
                    }
                }
                if let Some((ju, jv)) = neighbour(&g, iu, iv, false) {
                    let b = g.patch(ju, jv);
                    for i in 0..4 {
                        assert_eq!(a[4 * i + 3], b[4 * i], "{p}: v-edge of ({iu},{iv})");
                    }
                }
                if g.topology().pole_at_start() && iv == 0 {
                    let pole = g.nodes()[g.pole(nendo::surface::PoleEnd::Start).unwrap().node];
                    for i in 0..4 {
                        assert_eq!(a[4 * i], pole);
                    }
                }
                if g.topology().pole_at_end() && iv + 1 == g.patches_v() {
                    let pole = g.nodes()[g.pole(nendo::surface::PoleEnd::End).unwrap().node];
                    for i in 0..4 {
                        assert_eq!(a[4 * i + 3], pole);
                    }
                }
            }
        }
    }
}

#[test]
fn primitives_are_close_to_their_ideal_shapes() {
    // Measured on 40 × 40 samples per patch; the bounds are a little above the measured
    // values (printed with --nocapture).
    let cases: [(Primitive, f64); 6] = [
        (Primitive::Plane, 0.0),
        (Primitive::Cylinder, 2e-5),
        (Primitive::Hemisphere, 3e-5),
        (Primitive::Sphere, 3e-5),
        (Primitive::Torus, 3e-4),
        (Primitive::Tube, 2e-4),
    ];
    for (p, bound) in cases {
        let d = PrimitiveParams::default();
        let g = p.build(&d).unwrap();
        let ideal = p.ideal(&d).unwrap();
        let err = ideal.max_distance(&g, 40);
        let r = p.resolve(&d).unwrap();
        println!(
            "{p:>10} {:>2} x {:<2} R {}: max distance from the ideal {err:.3e} side",
            r.patches.0, r.patches.1, r.radius
        );
        assert!(err <= bound, "{p}: {err}");
    }
    // Finer grids approach the ideal: the sphere with 32 × 16 patches.
    let g = Primitive::Sphere.build(&params(32, 16)).unwrap();
    let err = Ideal::Sphere {
        center: DVec3::ZERO,
        radius: 3.0,
    }
    .max_distance(&g, 20);
    println!("    sphere 32 x 16 R 3: {err:.3e} side");
    assert!(err < 1e-6);
}

#[test]
fn normals_point_outward() {
    for p in Primitive::ALL {
        let d = PrimitiveParams::default();
        let g = p.build(&d).unwrap();
        let r = p.resolve(&d).unwrap();
        for iv in 0..g.patches_v() {
            for iu in 0..g.patches_u() {
                for &(u, v) in &[(0.5, 0.5), (0.0, 0.0), (1.0, 1.0), (0.2, 0.9)] {
                    let x = g.eval(iu, iv, u, v);
                    let n = g
                        .normal(iu, iv, u, v)
                        .unwrap_or_else(|| panic!("{p}: no normal at ({iu},{iv},{u},{v})"));
                    let out = match p {
                        Primitive::Plane => DVec3::Z,
                        Primitive::Cylinder => x.with_z(0.0),
                        Primitive::Hemisphere | Primitive::Sphere => x,
                        Primitive::Torus => x - (x.with_z(0.0).normalize() * r.radius),
                        Primitive::Tube => {
                            if x.z >= r.radius {
                                x.with_z(0.0)
                            } else {
                                x - DVec3::new(0.0, 0.0, r.radius)
                            }
                        }
                    };
                    let cos = n.dot(out.normalize());
                    assert!(
                        cos > 0.99,
                        "{p}: patch ({iu},{iv}) at ({u},{v}): normal {n} vs outward {out}"
                    );
                }
            }
        }
    }
}

#[test]
fn groups_and_poles_partition_the_net() {
    for t in Topology::ALL {
        let p = match t {
            Topology::Plane => Primitive::Plane,
            Topology::Cylinder => Primitive::Cylinder,
            Topology::Hemisphere => Primitive::Hemisphere,
            Topology::Sphere => Primitive::Sphere,
            Topology::Torus => Primitive::Torus,
        };
        let g = p.build(&PrimitiveParams::default()).unwrap();
        let mut seen = vec![0usize; g.nodes().len()];
        for grp in g.groups() {
            for row in grp.nodes {
                for id in row.into_iter().flatten() {
                    seen[id] += 1;
                }
            }
        }
        for pole in g.poles() {
            seen[pole.node] += 1;
            assert_eq!(pole.ring.len(), 3 * g.patches_u());
            for &id in &pole.ring {
                seen[id] += 1;
            }
        }
        assert!(seen.iter().all(|&c| c == 1), "{t}: {seen:?}");
        assert_eq!(g.poles().len(), t.pole_count());
    }
}

#[test]
fn from_patches_merges_shared_points_and_reports_disagreement() {
    let g = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .unwrap();
    let patches = g.patches();
    let (back, gap) = Grid::from_patches(Topology::Sphere, 8, 4, &patches, 1e-9).unwrap();
    assert_eq!(back, g);
    assert_eq!(gap, 0.0);
    // Move one copy of a seam point.
    let mut bad = patches.clone();
    bad[7][12 + 1] += DVec3::new(0.0, 1e-3, 0.0);
    let err = Grid::from_patches(Topology::Sphere, 8, 4, &bad, 1e-9).unwrap_err();
    assert!(
        matches!(
            err,
            SurfaceError::NotCoincident {
                patch: 7,
                point: 13,
                what: "closed seam",
                ..
            }
        ),
        "{err}"
    );
    // Break the pole.
    let mut bad = patches.clone();
    bad[3][4] += DVec3::new(1e-3, 0.0, 0.0);
    let err = Grid::from_patches(Topology::Sphere, 8, 4, &bad, 1e-9).unwrap_err();
    assert!(
        matches!(err, SurfaceError::NotCoincident { what: "pole", .. }),
        "{err}"
    );
    // Wrong count, non-finite.
    assert!(matches!(
        Grid::from_patches(Topology::Sphere, 8, 4, &patches[1..], 1e-9),
        Err(SurfaceError::WrongCount { .. })
    ));
    let mut bad = patches;
    bad[5][9].x = f64::NAN;
    assert!(matches!(
        Grid::from_patches(Topology::Sphere, 8, 4, &bad, 1e-9),
        Err(SurfaceError::NotFinite { patch: 5, point: 9 })
    ));
}

#[test]
fn tube_has_the_papers_128_patches_and_a_smooth_pole() {
    let g = Primitive::Tube.build(&PrimitiveParams::default()).unwrap();
    assert_eq!(g.patch_count(), 128);
    let pole = &g.poles()[0];
    let o = g.nodes()[pole.node];
    assert_eq!(o, DVec3::ZERO);
    for &id in &pole.ring {
        assert!(
            (g.nodes()[id].z - o.z).abs() < 1e-15,
            "first ring lies in the pole's tangent plane"
        );
    }
}

/// `Primitive::uses` says which size parameters shape each primitive: changing a used one
/// moves control points, changing an unused one leaves the built grid identical.
#[test]
fn uses_names_exactly_the_sizes_that_change_the_built_primitive() {
    for p in Primitive::ALL {
        let base = p
            .build(&PrimitiveParams::default())
            .expect("defaults build");
        let d = p.defaults();
        for size in PrimitiveSize::ALL {
            let mut changed = PrimitiveParams::default();
            match size {
                PrimitiveSize::Radius => changed.radius = Some(d.radius * 1.25),
                PrimitiveSize::Height => changed.height = Some(d.height * 1.25),
                PrimitiveSize::MinorRadius => changed.minor_radius = Some(d.minor_radius * 0.75),
            }
            let other = p.build(&changed).expect("changed sizes build");
            assert_eq!(
                other.nodes() != base.nodes(),
                p.uses(size),
                "{p} {size:?}: uses says {}",
                p.uses(size)
            );
        }
    }
}
