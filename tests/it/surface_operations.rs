//! The sculpting operations of issue 12: lines that follow the clay (`"dir": "normal"`,
//! `"dirs"`), the exact grab-and-move, mirror symmetry, and smoothing — each on every topology
//! it concerns, against independent measures (brute-force nearest points, the continuity
//! report, the thin-plate energy), with fixed seeds.

use glam::DVec3;
use nendo::surface::{
    Dirs, Grid, Op, Plane, Primitive, PrimitiveParams, Regulation, Sculptor, SurfaceError,
    Symmetry, continuity, nearest, symmetry_error, thin_plate_energy,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::support::{run_with_input, temp_dir};

fn sphere(m: usize, n: usize) -> Grid {
    Primitive::Sphere
        .build(&PrimitiveParams {
            patches: Some((m, n)),
            radius: Some(3.0),
            ..PrimitiveParams::default()
        })
        .unwrap()
}

/// A point of the sphere of radius 3 at latitude / longitude (degrees).
fn on_sphere(lat: f64, lon: f64) -> DVec3 {
    let (lat, lon) = (lat.to_radians(), lon.to_radians());
    DVec3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin()) * 3.0
}

/// A great circle from the equator at longitude 0 up over the north pole and down to latitude
/// 45° at longitude 180°, a point every 3°.
fn pole_crossing_path() -> Vec<DVec3> {
    (0..=45)
        .map(|k| {
            let a = 3.0 * k as f64; // angle from the equator along the great circle
            if a <= 90.0 {
                on_sphere(a, 0.0)
            } else {
                on_sphere(180.0 - a, 180.0)
            }
        })
        .collect()
}

/// Depth of the surface below the radius-3 sphere along the radial line through `x`: where
/// the surface crosses the line (nearest points projected back onto it).
fn radial_depth(grid: &Grid, x: DVec3, guess: f64) -> f64 {
    let n = x.normalize();
    let mut t = 3.0 - guess;
    for _ in 0..30 {
        let s = nearest(grid, n * t).unwrap().point;
        t = s.dot(n);
    }
    3.0 - t
}

/// Path points at least `margin` from both ends, by arc length.
fn inner_points(path: &[DVec3], margin: f64) -> Vec<DVec3> {
    let mut along = vec![0.0];
    for w in path.windows(2) {
        along.push(along[along.len() - 1] + (w[1] - w[0]).length());
    }
    let total = along[along.len() - 1];
    path.iter()
        .zip(&along)
        .filter(|(_, s)| **s >= margin && **s <= total - margin)
        .map(|(p, _)| *p)
        .collect()
}

#[test]
fn a_groove_along_the_normals_keeps_its_depth_over_the_pole() {
    let path = pole_crossing_path();
    let (depth, radius) = (0.3, 1.2);
    let before = sphere(32, 16);
    let mut worst = 0.0f64;
    for op in [
        Op::Groove {
            path: path.clone(),
            dirs: Dirs::Normal,
            depth,
            radius,
        },
        Op::Groove {
            path: path.clone(),
            dirs: Dirs::Each(path.iter().map(|p| -*p).collect()),
            depth,
            radius,
        },
    ] {
        let mut grid = before.clone();
        Sculptor::new()
            .apply(&mut grid, &op, Regulation::Exact)
            .unwrap();
        let g1 = continuity::report(&grid, 9).g1_max_deg;
        assert!(g1 <= 0.01, "{g1}");
        for x in inner_points(&path, radius) {
            let d = radial_depth(&grid, x, depth);
            let err = (d - depth).abs() / depth;
            worst = worst.max(err);
            assert!(err <= 0.10, "{op:?} at {x}: depth {d} (want {depth})");
        }
    }
    eprintln!(
        "groove over the pole: worst depth error {:.2} %",
        100.0 * worst
    );
    // The old single direction cuts a sheared wall, not a groove: pressed along −z everywhere,
    // the depth along the normal near the equator is far from the finger's.
    let mut grid = before.clone();
    Sculptor::new()
        .apply(
            &mut grid,
            &Op::Drag {
                path: path.clone(),
                dir: -DVec3::Z,
                depth,
                radius,
            },
            Regulation::Exact,
        )
        .unwrap();
    let near_equator = on_sphere(12.0, 0.0);
    let d = radial_depth(&grid, near_equator, depth);
    assert!((d - depth).abs() / depth > 0.10, "{d}");
}

#[test]
fn one_direction_for_every_point_is_exactly_the_drag() {
    let path = vec![
        DVec3::new(-1.0, 0.2, 0.0),
        DVec3::new(0.0, 0.5, 0.0),
        DVec3::new(1.5, 0.1, 0.0),
    ];
    let dir = DVec3::new(0.1, 0.0, -1.0);
    let plane = Primitive::Plane.build(&PrimitiveParams::default()).unwrap();
    let (mut a, mut b) = (plane.clone(), plane.clone());
    let drag = Op::Drag {
        path: path.clone(),
        dir,
        depth: 0.3,
        radius: 1.0,
    };
    let groove = Op::Groove {
        path: path.clone(),
        dirs: Dirs::Each(vec![dir * 2.0; 3]),
        depth: 0.3,
        radius: 1.0,
    };
    Sculptor::new()
        .apply(&mut a, &drag, Regulation::Exact)
        .unwrap();
    Sculptor::new()
        .apply(&mut b, &groove, Regulation::Exact)
        .unwrap();
    assert_eq!(a, b);
    // And a push along the normal of the plane is the push along −normal.
    let (mut a, mut b) = (plane.clone(), plane.clone());
    let n = plane.normal(5, 5, 0.5, 0.5).unwrap();
    let at = DVec3::new(0.5, 0.5, 0.0);
    Sculptor::new()
        .apply(
            &mut a,
            &Op::PushNormal {
                at,
                depth: 0.4,
                radius: 1.0,
            },
            Regulation::Exact,
        )
        .unwrap();
    Sculptor::new()
        .apply(
            &mut b,
            &Op::Push {
                at,
                dir: -n,
                depth: 0.4,
                radius: 1.0,
            },
            Regulation::Exact,
        )
        .unwrap();
    for (x, y) in a.nodes().iter().zip(b.nodes()) {
        assert!((*x - *y).length() < 1e-12);
    }
}

/// Every primitive at its default size.
fn primitives() -> Vec<(Primitive, Grid)> {
    Primitive::ALL
        .into_iter()
        .map(|p| (p, p.build(&PrimitiveParams::default()).unwrap()))
        .collect()
}

/// The patches sharing a grid vertex with a patch in `reach` (and the whole pole row when
/// one of them touches a pole): what the regulation may adjust next to the reach.
fn reach_and_ring(grid: &Grid, reach: &[usize]) -> Vec<bool> {
    let (m, n) = (grid.patches_u() as isize, grid.patches_v() as isize);
    let t = grid.topology();
    let mut out = vec![false; grid.patch_count()];
    for &p in reach {
        let (iu, iv) = (p as isize % m, p as isize / m);
        for du in -1..=1 {
            for dv in -1..=1 {
                let (mut u, mut v) = (iu + du, iv + dv);
                if t.closed_u() {
                    u = u.rem_euclid(m);
                }
                if t.closed_v() {
                    v = v.rem_euclid(n);
                }
                if (0..m).contains(&u) && (0..n).contains(&v) {
                    out[(v * m + u) as usize] = true;
                }
            }
        }
        let pole_row = (iv == 0 && t.pole_at_start()) || (iv == n - 1 && t.pole_at_end());
        if pole_row {
            for u in 0..m {
                out[(iv * m + u) as usize] = true;
            }
            // The pole's ring reaches one row further only through its own patches.
        }
    }
    out
}

/// The patches whose control-point boxes come within `r` of one of `centres`.
fn in_reach(grid: &Grid, centres: &[DVec3], r: f64) -> Vec<usize> {
    (0..grid.patch_count())
        .filter(|&p| {
            let b = grid.patch_bounds(p);
            centres.iter().any(|c| {
                let d = (b.min - *c).max(*c - b.max).max(DVec3::ZERO);
                d.length() <= r
            })
        })
        .collect()
}

/// Asserts that only patches in `allowed` changed.
fn assert_local(before: &Grid, after: &Grid, allowed: &[bool], what: &str) {
    let m = before.patches_u();
    for (p, &ok) in allowed.iter().enumerate() {
        if before.patch(p % m, p / m) != after.patch(p % m, p / m) {
            assert!(ok, "{what}: patch {p} moved out of reach and ring");
        }
    }
}

#[test]
fn a_move_lands_on_its_target_on_every_topology_poles_and_seams_included() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let mut worst = 0.0f64;
    for (prim, base) in primitives() {
        let m = base.patches_u();
        let t = base.topology();
        // Grabbed parameters: random ones, a closed seam (u = 0 of patch 0), a grid vertex,
        // and the poles.
        let mut grabs: Vec<(usize, f64, f64)> = (0..6)
            .map(|_| {
                (
                    rng.gen_range(0..base.patch_count()),
                    rng.r#gen::<f64>(),
                    rng.r#gen::<f64>(),
                )
            })
            .collect();
        grabs.push((m + 1, 0.0, 0.37));
        grabs.push((m + 1, 1.0, 1.0));
        if t.pole_at_start() {
            grabs.push((0, 0.3, 0.0));
        }
        if t.pole_at_end() {
            grabs.push((base.patch_count() - 1, 0.6, 1.0));
        }
        for (k, &(p, u, v)) in grabs.iter().enumerate() {
            let mut grid = base.clone();
            let at = base.eval(p % m, p / m, u, v);
            let step = DVec3::new(rng.r#gen(), rng.r#gen(), rng.r#gen()) - 0.5;
            let to = at + step * 0.6;
            let radius = rng.gen_range(0.3..1.5);
            let grabbed = nearest(&base, at).unwrap();
            let touched = Sculptor::new()
                .apply(&mut grid, &Op::Move { at, to, radius }, Regulation::Exact)
                .unwrap_or_else(|e| panic!("{prim} grab {k}: {e}"));
            let got = grid.eval(grabbed.patch % m, grabbed.patch / m, grabbed.u, grabbed.v);
            let residual = (got - to).length() / to.length().max(1.0);
            worst = worst.max(residual);
            assert!(residual <= 1e-9, "{prim} grab {k}: {got} vs {to}");
            let g1 = continuity::report(&grid, 9).g1_max_deg;
            assert!(g1 <= 0.01, "{prim} grab {k}: G1 {g1}°");
            let mut reach = in_reach(&base, &[grabbed.point], radius);
            reach.push(grabbed.patch);
            let allowed = reach_and_ring(&base, &reach);
            assert_local(&base, &grid, &allowed, &format!("{prim} grab {k}"));
            for p in 0..grid.patch_count() {
                if base.patch(p % m, p / m) != grid.patch(p % m, p / m) {
                    assert!(
                        touched.patches.contains(&p),
                        "{prim} grab {k}: {p} unreported"
                    );
                }
            }
        }
    }
    eprintln!("move: worst relative residual {worst:.2e}");
}

#[test]
fn a_live_move_keeps_the_grabbed_point_under_the_cursor() {
    // Frame by frame from the stroke's start: one call per frame, the grabbed point on the
    // cursor's target every time.
    let base = sphere(16, 8);
    let at = on_sphere(20.0, 30.0);
    let grabbed = nearest(&base, at).unwrap();
    let m = base.patches_u();
    let mut sculptor = Sculptor::new();
    for k in 1..=20 {
        let to = at + DVec3::new(0.02, -0.01, 0.03) * k as f64;
        let mut grid = base.clone();
        sculptor
            .apply(
                &mut grid,
                &Op::Move {
                    at,
                    to,
                    radius: 1.0,
                },
                Regulation::Exact,
            )
            .unwrap();
        let got = grid.eval(grabbed.patch % m, grabbed.patch / m, grabbed.u, grabbed.v);
        assert!(
            (got - to).length() <= 1e-9 * to.length(),
            "{k}: {got} vs {to}"
        );
    }
}

fn random_surface_point(rng: &mut ChaCha8Rng, grid: &Grid) -> (DVec3, DVec3) {
    let m = grid.patches_u();
    let p = rng.gen_range(0..grid.patch_count());
    let (u, v) = (rng.gen_range(0.05..0.95), rng.gen_range(0.05..0.95));
    let x = grid.eval(p % m, p / m, u, v);
    let n = grid.normal(p % m, p / m, u, v).unwrap_or(DVec3::Z);
    (x, n)
}

fn random_op(rng: &mut ChaCha8Rng, grid: &Grid) -> Op {
    let (at, n) = random_surface_point(rng, grid);
    let radius = rng.gen_range(0.4..1.2);
    let depth = rng.gen_range(-0.12..0.12);
    match rng.gen_range(0..6) {
        0 => Op::Push {
            at,
            dir: -n,
            depth,
            radius,
        },
        1 => Op::PushNormal { at, depth, radius },
        2 => {
            let (b, _) = random_surface_point(rng, grid);
            let end = at + (b - at).clamp_length_max(1.0);
            Op::Drag {
                path: vec![at, end],
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
            to: at + (DVec3::new(rng.r#gen(), rng.r#gen(), rng.r#gen()) - 0.5) * 0.2,
            radius,
        },
        _ => Op::Smooth {
            at,
            radius,
            strength: rng.gen_range(0.1..1.0),
        },
    }
}

#[test]
fn mirrored_sculpting_stays_symmetric_on_every_primitive() {
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    for (prim, base) in primitives() {
        for plane in [Plane::X, Plane::Y] {
            let mut grid = base.clone();
            let symmetry = Symmetry::of(&grid, plane).unwrap();
            symmetry.enforce_all(&mut grid, true).unwrap();
            let mut sculptor = Sculptor::new();
            let (mut refused, mut drift) = (0, 0.0f64);
            for k in 0..200 {
                let op = random_op(&mut rng, &grid);
                let before = grid.clone();
                match sculptor.apply_mirrored(&mut grid, &op, Regulation::Exact, &symmetry) {
                    Ok(_) => drift = drift.max(sculptor.last_asymmetry()),
                    Err(SurfaceError::NotG1 { .. } | SurfaceError::OutOfRange { .. }) => {
                        assert_eq!(grid, before, "{prim} {plane} op {k}");
                        refused += 1;
                    }
                    Err(e) => panic!("{prim} {plane} op {k}: {op:?}: {e}"),
                }
            }
            let a = symmetry_error(&grid, plane);
            eprintln!(
                "{prim} mirror {plane}: asymmetry {:.1e} after 200 ops ({refused} refused), \
                 largest before enforcing {drift:.1e}",
                a.relative
            );
            assert!(a.relative <= 1e-12, "{prim} {plane}: {a:?}");
            assert!(refused < 20, "{prim} {plane}: {refused} refused");
            assert!(drift < 1e-9, "{prim} {plane}: drift {drift}");
            let g1 = continuity::report(&grid, 9).g1_max_deg;
            assert!(g1 <= 0.01, "{prim} {plane}: G1 {g1}°");
            assert!(grid != base, "{prim} {plane}: nothing happened");
        }
    }
}

#[test]
fn a_mirrored_push_dents_both_sides() {
    let base = sphere(16, 8);
    let symmetry = Symmetry::of(&base, Plane::X).unwrap();
    let mut grid = base.clone();
    let at = on_sphere(10.0, 30.0);
    Sculptor::new()
        .apply_mirrored(
            &mut grid,
            &Op::PushNormal {
                at,
                depth: 0.3,
                radius: 1.0,
            },
            Regulation::Exact,
            &symmetry,
        )
        .unwrap();
    for x in [at, Plane::X.reflect(at)] {
        let d = radial_depth(&grid, x, 0.3);
        assert!((d - 0.3).abs() < 0.05, "{x}: {d}");
    }
}

/// A 32 × 16 sphere of radius 3 dented by six small pushes around latitude 34°, longitude 35°.
fn dented_sphere(regulation: Regulation) -> Grid {
    let mut grid = sphere(32, 16);
    let mut sculptor = Sculptor::new();
    for k in 0..6 {
        let at = on_sphere(30.0 + 8.0 * (k % 2) as f64, 20.0 + 6.0 * k as f64);
        sculptor
            .apply(
                &mut grid,
                &Op::Push {
                    at,
                    dir: -at,
                    depth: 0.5,
                    radius: 0.8,
                },
                regulation,
            )
            .unwrap();
    }
    grid
}

#[test]
fn smoothing_lowers_the_thin_plate_energy_locally_and_keeps_g1() {
    let base = dented_sphere(Regulation::Exact);
    let at = on_sphere(34.0, 35.0);
    let radius = 1.25;
    let mut grid = base.clone();
    let mut sculptor = Sculptor::new();
    let mut energy = thin_plate_energy(&grid);
    for stroke in 0..5 {
        let op = Op::Smooth {
            at,
            radius,
            strength: 1.0,
        };
        let touched = sculptor.apply(&mut grid, &op, Regulation::Exact).unwrap();
        assert!(!touched.patches.is_empty(), "stroke {stroke}");
        let e = thin_plate_energy(&grid);
        let drop = sculptor.last_energy().unwrap();
        eprintln!(
            "smooth stroke {stroke}: energy {energy:.4} -> {e:.4} ({:.2} % of the touched patches', {} halvings)",
            100.0 * drop.relative(),
            drop.halvings
        );
        assert!(e < energy, "stroke {stroke}: {energy} -> {e}");
        // The whole grid's change is the touched patches' change.
        assert!(((energy - e) - (drop.before - drop.after)).abs() < 1e-9 * energy);
        energy = e;
        let g1 = continuity::report(&grid, 9).g1_max_deg;
        assert!(g1 <= 0.01, "stroke {stroke}: G1 {g1}°");
    }
    let allowed = reach_and_ring(&base, &in_reach(&base, &[at], radius));
    assert_local(&base, &grid, &allowed, "smooth");
}

#[test]
fn the_smoothing_step_alone_lowers_the_energy_for_every_strength() {
    // Without regulation the step is the bounded descent step itself: no halving needed.
    let base = dented_sphere(Regulation::None);
    let at = on_sphere(34.0, 35.0);
    for s in [1e-6, 0.01, 0.3, 0.7, 1.0] {
        let mut grid = base.clone();
        let mut sculptor = Sculptor::new();
        sculptor
            .apply(
                &mut grid,
                &Op::Smooth {
                    at,
                    radius: 1.25,
                    strength: s,
                },
                Regulation::None,
            )
            .unwrap();
        let drop = sculptor.last_energy().unwrap();
        assert_eq!(drop.halvings, 0, "{s}");
        assert!(thin_plate_energy(&grid) < thin_plate_energy(&base), "{s}");
    }
}

#[test]
fn a_vanishing_strength_moves_nothing() {
    let base = dented_sphere(Regulation::Exact);
    let at = on_sphere(34.0, 35.0);
    let moved = |s: f64| {
        let mut grid = base.clone();
        Sculptor::new()
            .apply(
                &mut grid,
                &Op::Smooth {
                    at,
                    radius: 1.25,
                    strength: s,
                },
                Regulation::Exact,
            )
            .unwrap();
        grid.nodes()
            .iter()
            .zip(base.nodes())
            .map(|(a, b)| (*a - *b).length())
            .fold(0.0f64, f64::max)
    };
    let full = moved(1.0);
    assert!(full > 1e-3, "{full}");
    // The implicit fairing step saturates at full strength (it moves less than linearly in
    // s), so the vanishing moves are compared with the slope at a small strength: each is
    // at most twice that slope times its strength.
    let slope = moved(1e-2) / 1e-2;
    assert!(slope * 1e-2 <= full, "{slope}");
    for s in [1e-3, 1e-6, 1e-9] {
        let d = moved(s);
        assert!(d <= 2.0 * s * slope + 1e-13, "{s}: {d} (slope {slope})");
    }
}

#[test]
fn sculpt_mirror_keeps_the_model_symmetric_and_refuses_an_asymmetric_one() {
    let dir = temp_dir("sculpt-mirror");
    let sym = dir.join("sym.json");
    let ops = "{\"op\":\"push\",\"at\":[1.5,1.0,2.4],\"dir\":\"normal\",\"depth\":0.3,\"radius\":1}\n\
               {\"op\":\"move\",\"at\":[2.0,-1.0,1.9],\"to\":[2.3,-1.2,2.0],\"radius\":0.8}\n\
               {\"op\":\"smooth\",\"at\":[1.5,1.0,2.4],\"radius\":1,\"strength\":0.5}\n\
               {\"op\":\"drag\",\"path\":[[2.9,0,0.5],[2.5,1.5,0.5]],\"dir\":\"normal\",\"depth\":0.2,\"radius\":0.7}\n";
    let out = run_with_input(
        &[
            "sculpt",
            "--primitive",
            "sphere",
            "--mirror",
            "x",
            "--ops",
            "-",
            "--out",
            sym.to_str().unwrap(),
        ],
        ops,
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let model = nendo::model::Model::read(&sym).unwrap().model;
    assert!(symmetry_error(&model.surface, Plane::X).relative <= 1e-12);
    // Without the mirror the same operations break the symmetry, and --mirror refuses it.
    let lop = dir.join("lop.json");
    let out = run_with_input(
        &[
            "sculpt",
            "--primitive",
            "sphere",
            "--ops",
            "-",
            "--out",
            lop.to_str().unwrap(),
        ],
        ops,
    );
    assert!(out.status.success());
    let again = dir.join("again.json");
    let out = run_with_input(
        &[
            "sculpt",
            "--model",
            lop.to_str().unwrap(),
            "--mirror",
            "x",
            "--ops",
            "-",
            "--out",
            again.to_str().unwrap(),
        ],
        ops,
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("not symmetric about the plane x = 0"), "{err}");
    assert!(err.contains("of the model's size"), "{err}");
    assert!(!again.exists());
    // A bad plane name.
    let out = run_with_input(
        &[
            "sculpt",
            "--primitive",
            "sphere",
            "--mirror",
            "w",
            "--out",
            again.to_str().unwrap(),
        ],
        "",
    );
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn replay_mirror_presses_both_sides_and_stays_symmetric() {
    let dir = temp_dir("replay-mirror");
    let trace = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("devices/traces/sphere-push-pull.trace")
        .display()
        .to_string();
    let (plain, mirrored) = (dir.join("plain.json"), dir.join("mirrored.json"));
    for (out, mirror) in [(&plain, None), (&mirrored, Some("y"))] {
        let mut args = vec![
            "replay",
            trace.as_str(),
            "--primitive",
            "sphere",
            "--out",
            out.to_str().unwrap(),
        ];
        if let Some(m) = mirror {
            args.extend_from_slice(&["--mirror", m]);
        }
        let o = crate::support::run(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let plain = nendo::model::Model::read(&plain).unwrap().model.surface;
    let mirrored = nendo::model::Model::read(&mirrored).unwrap().model.surface;
    let base = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .unwrap();
    assert!(symmetry_error(&mirrored, Plane::Y).relative <= 1e-12);
    // The trace alone is not symmetric about y = 0; mirrored, the control points it moved
    // and their partners moved.
    assert!(symmetry_error(&plain, Plane::Y).relative > 1e-6);
    let sym = Symmetry::of(&base, Plane::Y).unwrap();
    let mut checked = 0;
    for id in 0..base.nodes().len() {
        if (plain.nodes()[id] - base.nodes()[id]).length() > 1e-3 {
            let q = sym.node_partner(id);
            assert!(
                (mirrored.nodes()[q] - base.nodes()[q]).length() > 1e-4,
                "{id} -> {q}"
            );
            checked += 1;
        }
    }
    assert!(checked > 0);
    assert!(continuity::report(&mirrored, 9).g1_max_deg <= 0.01);
}
