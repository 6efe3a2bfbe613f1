//! Deformation by shape functions through the Bernstein inverse (docs/design.md §11): the dent, pull,
//! the groove, locality, determinism, C0 under random strokes, seams and poles.

use glam::DVec3;
use nendo::surface::{
    Grid, Op, Primitive, PrimitiveParams, Regulation, Sculptor, SurfaceError, deform,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn plane(m: usize) -> Grid {
    Primitive::Plane
        .build(&PrimitiveParams {
            patches: Some((m, m)),
            ..PrimitiveParams::default()
        })
        .unwrap()
}

fn paper_push(depth: f64) -> Op {
    Op::Push {
        at: DVec3::new(0.5, 0.5, 0.0),
        dir: -DVec3::Z,
        depth,
        radius: 1.25,
    }
}

/// Patch `(iu, iv)` of the 10 × 10 plane starts at `(iu − 5, iv − 5)`.
fn plane_point(iu: usize, iv: usize, u: f64, v: f64) -> DVec3 {
    DVec3::new(iu as f64 - 5.0 + u, iv as f64 - 5.0 + v, 0.0)
}

#[test]
fn a_patch_inside_the_finger_reproduces_the_paraboloid_exactly() {
    let mut g = plane(10);
    let op = paper_push(0.6);
    let finger = op.finger().unwrap();
    deform(&mut g, &op, Regulation::None).unwrap();
    // Patch (5, 5) = [0,1]², entirely within r_f = 1.25 of (0.5, 0.5).
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for _ in 0..200 {
        let (u, v) = (rng.r#gen::<f64>(), rng.r#gen::<f64>());
        let want = finger.ideal(plane_point(5, 5, u, v));
        let got = g.eval(5, 5, u, v);
        assert!((got - want).length() < 1e-13, "({u}, {v}): {got} vs {want}");
    }
    // The point on the finger axis moves by exactly |M|.
    let centre = g.eval(5, 5, 0.5, 0.5);
    assert!(
        (centre - DVec3::new(0.5, 0.5, -0.6)).length() < 1e-14,
        "{centre}"
    );
}

#[test]
fn only_reachable_patches_move_and_the_rest_stay_bit_identical() {
    for m in [10, 40] {
        let mut g = plane(m);
        let before = g.clone();
        let op = paper_push(0.5);
        let finger = op.finger().unwrap();
        let touched = deform(&mut g, &op, Regulation::None).unwrap();
        // Brute force: the patches with a sample within reach.
        let mut want = Vec::new();
        for p in 0..g.patch_count() {
            let pts = before.patch_at(p);
            let r = nendo::surface::inverse::samples(&pts);
            if r.iter().any(|&x| finger.flow(x) != DVec3::ZERO) {
                want.push(p);
            }
        }
        assert_eq!(touched.patches, want, "{m} x {m}");
        assert_eq!(touched.deformed, 9);
        for p in 0..g.patch_count() {
            if !want.contains(&p) {
                assert_eq!(
                    g.patch_at(p),
                    before.patch_at(p),
                    "patch {p} beyond reach changed"
                );
            }
        }
    }
}

#[test]
fn pull_mirrors_push() {
    let base = plane(10);
    let (mut pushed, mut pulled) = (base.clone(), base.clone());
    deform(&mut pushed, &paper_push(0.8), Regulation::None).unwrap();
    deform(&mut pulled, &paper_push(-0.8), Regulation::None).unwrap();
    for ((a, b), o) in pushed.nodes().iter().zip(pulled.nodes()).zip(base.nodes()) {
        let (da, db) = (*a - *o, *b - *o);
        assert!((da + db).length() < 1e-15, "{da} vs {db}");
    }
    // A bump of height |M| on the axis.
    assert!((pulled.eval(5, 5, 0.5, 0.5) - DVec3::new(0.5, 0.5, 0.8)).length() < 1e-14);
}

#[test]
fn a_drag_leaves_a_groove_of_depth_lf_along_the_stroke() {
    let mut g = plane(10);
    let op = Op::Drag {
        path: vec![
            DVec3::new(-2.5, 0.3, 0.0),
            DVec3::new(0.0, 0.3, 0.0),
            DVec3::new(2.5, 0.3, 0.0),
        ],
        dir: -DVec3::Z,
        depth: 0.4,
        radius: 1.0,
    };
    let finger = op.finger().unwrap();
    deform(&mut g, &op, Regulation::None).unwrap();
    // Patches with x ∈ [−2, 2], y ∈ [0, 1] lie wholly inside the groove (|y − 0.3| ≤ 0.7 < r_f,
    // away from the rounded ends): the groove there is quadratic across, constant along, and
    // reproduced exactly.
    for iu in 3..7 {
        for k in 0..=20 {
            let u = k as f64 / 20.0;
            let p = g.eval(iu, 5, u, 0.3);
            assert!((p.z + 0.4).abs() < 1e-14, "({iu}, {u}): {p}");
            let q = g.eval(iu, 5, u, 0.9);
            let want = finger.ideal(plane_point(iu, 5, u, 0.9));
            assert!((q - want).length() < 1e-14);
        }
    }
    // The joint at x = 0 is not pressed twice.
    assert!((g.eval(5, 5, 0.0, 0.3).z + 0.4).abs() < 1e-14);
}

/// Independent of the sculptor's code: every patch's 16 samples after an operation (without
/// regulation) are its samples before it moved by the finger's flow there, evaluated directly
/// (`Finger::flow`, the shape function) — the Bernstein inverse reproduces the flows at the
/// samples — and doing it again from the same surface gives the same bits.
#[test]
fn every_sample_moves_by_the_flow_and_a_repeat_gives_identical_bits() {
    use nendo::surface::inverse::samples;
    for p in [Primitive::Plane, Primitive::Sphere, Primitive::Torus] {
        let base = p.build(&PrimitiveParams::default()).unwrap();
        let at = base.eval(1, 1, 0.4, 0.7);
        let n = base.normal(1, 1, 0.4, 0.7).unwrap();
        let ops = [
            Op::Push {
                at,
                dir: -n,
                depth: 0.3,
                radius: 1.1,
            },
            Op::Drag {
                path: vec![at, at + DVec3::new(0.5, 0.3, 0.1), at + DVec3::X],
                dir: -n,
                depth: -0.2,
                radius: 0.9,
            },
        ];
        let mut g = base.clone();
        let mut s = Sculptor::new();
        for op in &ops {
            let before = g.clone();
            let finger = op.finger().unwrap();
            let touched = s.apply(&mut g, op, Regulation::None).unwrap();
            let mut moved = 0;
            for k in 0..g.patch_count() {
                let old = samples(&before.patch_at(k));
                let new = samples(&g.patch_at(k));
                for (x, y) in old.iter().zip(&new) {
                    let want = *x + finger.flow(*x);
                    assert!(
                        (*y - want).length() < 1e-12,
                        "{p}, {op:?}, patch {k}: {y} vs {want}"
                    );
                }
                if old != new {
                    moved += 1;
                    assert!(touched.patches.contains(&k), "{p}: patch {k} moved untold");
                }
            }
            assert!(moved > 0, "{p}: the operation moved nothing");
            // The same operation on the same surface, with a fresh sculptor: the same bits.
            let mut again = before.clone();
            assert_eq!(deform(&mut again, op, Regulation::None).unwrap(), touched);
            assert!(
                again
                    .nodes()
                    .iter()
                    .zip(g.nodes())
                    .all(|(x, y)| x.to_array().map(f64::to_bits) == y.to_array().map(f64::to_bits)),
                "{p}"
            );
        }
    }
}

#[test]
fn a_bad_operation_is_rejected_and_changes_nothing() {
    let mut g = plane(4);
    let before = g.clone();
    let op = Op::Push {
        at: DVec3::ZERO,
        dir: DVec3::ZERO,
        depth: 0.1,
        radius: 1.0,
    };
    assert!(matches!(
        deform(&mut g, &op, Regulation::None),
        Err(SurfaceError::BadOp(_))
    ));
    assert_eq!(g, before);
}

/// A random push or drag aimed at the surface.
fn random_op(g: &Grid, rng: &mut ChaCha8Rng) -> Op {
    let (iu, iv) = (
        rng.gen_range(0..g.patches_u()),
        rng.gen_range(0..g.patches_v()),
    );
    let (u, v) = (rng.r#gen::<f64>(), rng.r#gen::<f64>());
    let at = g.eval(iu, iv, u, v);
    let n = g.normal(iu, iv, u, v).unwrap_or(DVec3::Z);
    let wobble = DVec3::new(
        rng.gen_range(-0.3..0.3),
        rng.gen_range(-0.3..0.3),
        rng.gen_range(-0.3..0.3),
    );
    let dir = -n + wobble;
    let depth = rng.gen_range(-0.25..0.25);
    let radius = rng.gen_range(0.3..1.5);
    if rng.gen_bool(0.5) {
        Op::Push {
            at,
            dir,
            depth,
            radius,
        }
    } else {
        let mut path = vec![at];
        for _ in 0..rng.gen_range(1..4) {
            let last = path[path.len() - 1];
            path.push(
                last + DVec3::new(
                    rng.gen_range(-0.8..0.8),
                    rng.gen_range(-0.8..0.8),
                    rng.gen_range(-0.8..0.8),
                ),
            );
        }
        Op::Drag {
            path,
            dir,
            depth,
            radius,
        }
    }
}

/// Every shared boundary, seam and pole, compared on the patches and on their evaluations.
fn assert_c0(g: &Grid, what: &str) {
    let (m, n) = (g.patches_u(), g.patches_v());
    let t = g.topology();
    for iv in 0..n {
        for iu in 0..m {
            let a = g.patch(iu, iv);
            let right = if iu + 1 < m {
                Some(iu + 1)
            } else if t.closed_u() {
                Some(0)
            } else {
                None
            };
            if let Some(ju) = right {
                let b = g.patch(ju, iv);
                for j in 0..4 {
                    assert_eq!(a[12 + j], b[j], "{what}: u-edge ({iu},{iv})");
                }
                for k in 0..=8 {
                    let s = k as f64 / 8.0;
                    assert_eq!(
                        g.eval(iu, iv, 1.0, s),
                        g.eval(ju, iv, 0.0, s),
                        "{what}: u-edge ({iu},{iv}) at {s}"
                    );
                }
            }
            let up = if iv + 1 < n {
                Some(iv + 1)
            } else if t.closed_v() {
                Some(0)
            } else {
                None
            };
            if let Some(jv) = up {
                let b = g.patch(iu, jv);
                for i in 0..4 {
                    assert_eq!(a[4 * i + 3], b[4 * i], "{what}: v-edge ({iu},{iv})");
                }
                for k in 0..=8 {
                    let s = k as f64 / 8.0;
                    assert_eq!(
                        g.eval(iu, iv, s, 1.0),
                        g.eval(iu, jv, s, 0.0),
                        "{what}: v-edge ({iu},{iv}) at {s}"
                    );
                }
            }
        }
    }
    for pole in g.poles() {
        let o = g.nodes()[pole.node];
        let iv = if pole.end == nendo::surface::PoleEnd::Start {
            0
        } else {
            n - 1
        };
        let j = if iv == 0 && t.pole_at_start() { 0 } else { 3 };
        for iu in 0..m {
            let p = g.patch(iu, iv);
            for i in 0..4 {
                assert_eq!(p[4 * i + j], o, "{what}: pole row of patch ({iu},{iv})");
            }
            for k in 0..=4 {
                assert_eq!(
                    g.eval(iu, iv, k as f64 / 4.0, j as f64 / 3.0),
                    o,
                    "{what}: pole not degenerate"
                );
            }
        }
    }
}

#[test]
fn c0_holds_exactly_after_1000_random_pushes_and_drags_on_every_topology() {
    for p in [
        Primitive::Plane,
        Primitive::Cylinder,
        Primitive::Hemisphere,
        Primitive::Sphere,
        Primitive::Torus,
    ] {
        let mut g = p.build(&PrimitiveParams::default()).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut s = Sculptor::new();
        let mut moved = 0;
        for _ in 0..1000 {
            let op = random_op(&g, &mut rng);
            moved += s.apply(&mut g, &op, Regulation::None).unwrap().deformed;
        }
        assert!(
            moved > 1000,
            "{p}: the strokes must reach the surface ({moved})"
        );
        assert!(g.nodes().iter().all(|x| x.is_finite()));
        assert_c0(&g, p.name());
    }
}

#[test]
fn strokes_across_seams_and_poles_keep_them_closed_and_degenerate() {
    // The cylinder's seam is at u = 0 (x > 0, y = 0); the sphere's poles are on ±z.
    let mut cyl = Primitive::Cylinder
        .build(&PrimitiveParams::default())
        .unwrap();
    let op = Op::Drag {
        path: vec![DVec3::new(3.0, -1.5, 2.0), DVec3::new(3.0, 1.5, 2.2)],
        dir: -DVec3::X,
        depth: 0.5,
        radius: 0.8,
    };
    let t = deform(&mut cyl, &op, Regulation::None).unwrap();
    assert!(
        t.patches.iter().any(|&p| p % 8 == 0) && t.patches.iter().any(|&p| p % 8 == 7),
        "{t:?}"
    );
    assert_c0(&cyl, "cylinder seam");

    let mut sphere = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .unwrap();
    for op in [
        Op::Drag {
            path: vec![
                DVec3::new(-1.5, 0.2, 2.6),
                DVec3::new(0.0, 0.0, 3.0),
                DVec3::new(1.5, -0.3, 2.6),
            ],
            dir: -DVec3::Z,
            depth: 0.4,
            radius: 1.0,
        },
        Op::Push {
            at: DVec3::new(0.4, 0.3, -3.0),
            dir: DVec3::new(0.2, 0.1, 1.0),
            depth: -0.6,
            radius: 1.3,
        },
    ] {
        deform(&mut sphere, &op, Regulation::None).unwrap();
        assert_c0(&sphere, "sphere poles");
    }
}

#[test]
fn the_papers_sphere_pushed_at_a_pole_and_at_a_vertex() {
    let base = Primitive::Sphere
        .build(&PrimitiveParams::default())
        .unwrap();
    assert_eq!((base.patches_u(), base.patches_v()), (8, 4));
    // At the north pole: the pole sample is on the finger axis and moves by |M|.
    let mut g = base.clone();
    let t = deform(
        &mut g,
        &Op::Push {
            at: DVec3::new(0.0, 0.0, 3.0),
            dir: -DVec3::Z,
            depth: 0.5,
            radius: 1.25,
        },
        Regulation::None,
    )
    .unwrap();
    let pole = g.pole(nendo::surface::PoleEnd::End).unwrap();
    assert!((g.nodes()[pole.node] - DVec3::new(0.0, 0.0, 2.5)).length() < 1e-15);
    assert_eq!(t.deformed, 8, "the pole row of patches");
    assert_c0(&g, "pole push");
    // At the grid vertex on the equator at azimuth 0 (u-line 0, v-line 2).
    let mut g = base.clone();
    let vertex = base.nodes()[base.node_id(0, 6).unwrap()];
    assert!((vertex - DVec3::new(3.0, 0.0, 0.0)).length() < 1e-15);
    let t = deform(
        &mut g,
        &Op::Push {
            at: vertex,
            dir: -DVec3::X,
            depth: 0.5,
            radius: 1.25,
        },
        Regulation::None,
    )
    .unwrap();
    assert_eq!(
        g.nodes()[g.node_id(0, 6).unwrap()],
        vertex - DVec3::new(0.5, 0.0, 0.0)
    );
    assert!(t.deformed >= 4);
    assert_c0(&g, "vertex push");
}
