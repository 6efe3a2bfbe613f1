//! Tests of [`super`].

use super::*;
use crate::surface::{Primitive, PrimitiveParams, Regulation, continuity, deform, regulate_all};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn build(p: Primitive, counts: (usize, usize)) -> Grid {
    p.build(&PrimitiveParams {
        patches: Some(counts),
        ..PrimitiveParams::default()
    })
    .unwrap()
}

/// The cubic at `t` by Bernstein sums (independent of de Casteljau).
fn bernstein(q: &[DVec3; 4], t: f64) -> DVec3 {
    let s = 1.0 - t;
    q[0] * (s * s * s) + q[1] * (3.0 * s * s * t) + q[2] * (3.0 * s * t * t) + q[3] * (t * t * t)
}

/// A factor far past the grid limit (up to `usize::MAX`) is refused before anything is
/// allocated.
#[test]
fn a_huge_uniform_factor_is_refused_without_allocating() {
    let g = build(Primitive::Sphere, (8, 4));
    for k in [usize::MAX, usize::MAX / 2, 1 << 40, 100_000] {
        assert!(
            matches!(
                Refinement::uniform(&g, k),
                Err(RefineError::TooLarge { .. })
            ),
            "k = {k}"
        );
    }
}

/// The finger rule works for every operation form: along the normal, a move and a smooth
/// refine where they reach, like a push there.
#[test]
fn every_operation_form_has_a_finger_rule() {
    let g = build(Primitive::Sphere, (8, 4));
    let top = DVec3::new(0.0, 0.0, 3.0);
    let ops = [
        Op::PushNormal {
            at: top,
            depth: 0.2,
            radius: 0.6,
        },
        Op::Groove {
            path: vec![top, DVec3::new(1.0, 0.0, 2.8)],
            dirs: crate::surface::Dirs::Normal,
            depth: 0.2,
            radius: 0.6,
        },
        Op::Move {
            at: top,
            to: top + DVec3::new(0.0, 0.0, 0.5),
            radius: 0.6,
        },
        Op::Smooth {
            at: top,
            radius: 0.6,
            strength: 0.5,
        },
    ];
    for op in &ops {
        let f = for_finger(&g, op).unwrap_or_else(|e| panic!("{op:?}: {e}"));
        assert!(!f.refinement.is_empty(), "{op:?} refines the coarse sphere");
        assert!((f.target - 0.3).abs() < 1e-15);
    }
}

#[test]
fn split_pieces_trace_the_same_cubic() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..50 {
        let q: [DVec3; 4] =
            std::array::from_fn(|_| DVec3::new(rng.r#gen(), rng.r#gen(), rng.r#gen()));
        let t: f64 = rng.gen_range(0.05..0.95);
        let (l, r) = split(q, t);
        for k in 0..=10 {
            let s = k as f64 / 10.0;
            assert!((bernstein(&l, s) - bernstein(&q, s * t)).length() < 1e-14);
            assert!((bernstein(&r, s) - bernstein(&q, t + s * (1.0 - t))).length() < 1e-14);
        }
    }
}

#[test]
fn parameters_map_and_unmap() {
    let g = build(Primitive::Plane, (3, 2));
    let r = Refinement::new(&g, &[0.25, 0.5, 2.9], &[1.5]).unwrap();
    assert_eq!(r.counts(), (6, 3));
    assert_eq!(r.inserted_u(), vec![0.25, 0.5, 2.9]);
    // Column 0 is cut into [0, .25], [.25, .5], [.5, 1]: T = 0.75 is halfway along piece 2.
    assert!((r.map_u(0.75) - 2.5).abs() < 1e-15);
    assert!((r.map_u(1.5) - 3.5).abs() < 1e-15);
    assert!((r.map_u(3.0) - 6.0).abs() < 1e-15);
    assert!((r.map_v(1.75) - 2.5).abs() < 1e-15);
    for k in 0..=30 {
        let t = 3.0 * k as f64 / 30.0;
        assert!((r.unmap_u(r.map_u(t)) - t).abs() < 1e-14, "{t}");
    }
    let k3 = Refinement::uniform(&g, 3).unwrap();
    assert!((k3.map_u(1.3) - 3.9).abs() < 1e-14);
}

#[test]
fn bad_parameters_are_refused() {
    let g = build(Primitive::Cylinder, (8, 4));
    let e = |u: &[f64], v: &[f64]| Refinement::new(&g, u, v).unwrap_err();
    assert!(matches!(
        e(&[8.5, 1.5], &[]),
        RefineError::OutOfRange { .. }
    ));
    assert!(matches!(
        e(&[f64::NAN, 1.5], &[]),
        RefineError::OutOfRange { .. }
    ));
    assert!(matches!(
        e(&[2.0, 1.5], &[]),
        RefineError::OnGridLine { .. }
    ));
    assert!(matches!(e(&[1.5, 1.5], &[]), RefineError::TooClose { .. }));
    assert!(matches!(e(&[1.5], &[]), RefineError::OddClosed { .. }));
    assert!(Refinement::new(&g, &[1.5, 5.5], &[0.5]).is_ok());
    assert!(matches!(
        Refinement::uniform(&g, 0),
        Err(RefineError::Factor(0))
    ));
    let big = build(Primitive::Plane, (100, 100));
    assert!(matches!(
        uniform(&big, 3),
        Err(RefineError::TooLarge { to_u: 300, .. })
    ));
}

#[test]
fn a_split_keeps_the_surface_and_gives_the_ratio_formula() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for p in Primitive::ALL {
        let mut g = build(p, p.defaults().patches);
        regulate_all(&mut g, Regulation::Exact).unwrap();
        let (m, n) = (g.patches_u(), g.patches_v());
        let tu: f64 = rng.gen_range(0.1..0.9) + rng.gen_range(0..m) as f64;
        let tv: f64 = rng.gen_range(0.1..0.9) + rng.gen_range(0..n) as f64;
        let u = if g.topology().closed_u() {
            vec![tu, (tu + m as f64 / 2.0) % m as f64]
        } else {
            vec![tu]
        };
        let v = if g.topology().closed_v() {
            vec![tv, (tv + n as f64 / 2.0) % n as f64]
        } else {
            vec![tv]
        };
        let r = Refinement::new(&g, &u, &v).unwrap();
        let h = r.apply(&g).unwrap();
        assert_eq!((h.patches_u(), h.patches_v()), r.counts());
        let scale = g.bounds().max.abs().max(g.bounds().min.abs()).max_element();
        for _ in 0..200 {
            let a = rng.gen_range(0.0..m as f64);
            let b = rng.gen_range(0.0..n as f64);
            let old = eval_global(&g, a, b);
            let new = eval_global(&h, r.map_u(a), r.map_v(b));
            assert!((old - new).length() <= 1e-12 * scale, "{p}");
        }
        // The refined grid's rows all have its reference ratios: regulation is a no-op.
        let mut again = h.clone();
        regulate_all(&mut again, Regulation::Exact).unwrap();
        let moved = h
            .nodes()
            .iter()
            .zip(again.nodes())
            .map(|(a, b)| (*a - *b).length())
            .fold(0.0, f64::max);
        assert!(moved <= 1e-12 * scale, "{p}: {moved}");
        let rep = continuity::report(&h, 8);
        assert!(rep.g1_max_deg < 1e-6, "{p}: {}", rep.g1_max_deg);
    }
}

fn eval_global(g: &Grid, u: f64, v: f64) -> DVec3 {
    let iu = (u.floor() as usize).min(g.patches_u() - 1);
    let iv = (v.floor() as usize).min(g.patches_v() - 1);
    g.eval(iu, iv, u - iu as f64, v - iv as f64)
}

#[test]
fn a_small_finger_refines_where_it_reaches() {
    let g = build(Primitive::Plane, (10, 10));
    let op = Op::Push {
        at: DVec3::new(0.5, 0.5, 0.0),
        dir: DVec3::NEG_Z,
        depth: 0.1,
        radius: 0.3,
    };
    let f = for_finger(&g, &op).unwrap();
    assert!(!f.limited);
    let h = f.refinement.apply(&g).unwrap();
    let finger = op.finger().unwrap();
    let depth = finger.reach_depth(&h.bounds());
    let mut reached = Vec::new();
    h.patches_where(|b| finger.may_touch(b, depth), &mut reached);
    assert!(!reached.is_empty());
    for p in reached {
        let (lu, lv) = polygon_sizes(&h.patch_at(p));
        assert!(lu <= 0.15 + 1e-12 && lv <= 0.15 + 1e-12, "{lu} {lv}");
    }
    // Only the columns and rows around x, y = 0.5 were split.
    assert!(h.patches_u() < 20 && h.patches_v() < 20);
    // A second call finds nothing to do.
    assert!(for_finger(&h, &op).unwrap().refinement.is_empty());
    let mut s = h.clone();
    deform(&mut s, &op, Regulation::Exact).unwrap();
    assert!(continuity::report(&s, 8).g1_max_deg < 0.01);
}

#[test]
fn the_finger_rule_stops_at_the_grid_limit() {
    let g = build(Primitive::Sphere, (8, 4));
    let op = Op::Push {
        at: DVec3::new(0.0, 0.0, 3.0),
        dir: DVec3::NEG_Z,
        depth: 0.01,
        radius: 1e-4,
    };
    let f = for_finger(&g, &op).unwrap();
    assert!(f.limited);
    let (mu, nv) = f.refinement.counts();
    assert!(mu * nv <= MAX_PATCHES && mu % 2 == 0, "{mu} x {nv}");
    let h = f.refinement.apply(&g).unwrap();
    assert_eq!(h.patch_count(), mu * nv);
}

/// The slack: a grid split for one finger is not split again for a slightly smaller one
/// (the patches are within `σ·r_f/2` of it), only for a finger clearly smaller.
#[test]
fn a_slightly_smaller_finger_does_not_split_again() {
    let g = build(Primitive::Plane, (10, 10));
    let push = |radius: f64| Op::Push {
        at: DVec3::new(0.5, 0.5, 0.0),
        dir: DVec3::NEG_Z,
        depth: 0.1,
        radius,
    };
    let f = for_finger(&g, &push(0.72)).unwrap();
    let h = f.refinement.apply(&g).unwrap();
    // Unit patches split into ⌈1 / 0.36⌉ = 3 pieces of 1/3 where the finger reaches.
    assert!(h.patches_u() > 10 && h.patches_v() > 10);
    // A finger of 0.6 (h = 0.3 < 1/3 ≤ σ·h = 0.45) leaves them; without the slack it
    // would halve every one of those columns and rows.
    assert!(for_finger(&h, &push(0.6)).unwrap().refinement.is_empty());
    // A finger of 0.4 (σ·h = 0.3 < 1/3) splits them again, into pieces of at most 0.2.
    let f = for_finger(&h, &push(0.4)).unwrap();
    assert!(!f.refinement.is_empty());
    let k = f.refinement.apply(&h).unwrap();
    let finger = push(0.4).finger().unwrap();
    let depth = finger.reach_depth(&k.bounds());
    let mut reached = Vec::new();
    k.patches_where(|b| finger.may_touch(b, depth), &mut reached);
    for p in reached {
        let (lu, lv) = polygon_sizes(&k.patch_at(p));
        assert!(lu <= 0.3 + 1e-12 && lv <= 0.3 + 1e-12, "{lu} {lv}");
    }
}

/// Refinement marks the lines it inserts and keeps the marks of the old ones, through
/// refinements one after another: checked against where the primitive's own lines are (the
/// plane's x and y of its 3 × 2 lines, the sphere's meridian angles of its 8 columns), not
/// against the bookkeeping.
#[test]
fn refined_lines_are_marked_and_the_primitive_lines_kept() {
    let plane = build(Primitive::Plane, (3, 2));
    assert!(
        plane
            .refined_u()
            .iter()
            .chain(plane.refined_v())
            .all(|r| !r)
    );
    let once = Refinement::new(&plane, &[0.5, 2.25, 2.75], &[1.5])
        .unwrap()
        .apply(&plane)
        .unwrap();
    let twice = uniform(&once, 2).unwrap();
    // The fraction of the way from `a` to `b` at which `p` lies, times `count`: a whole
    // number on the primitive's own lines.
    let on_line = |a: DVec3, b: DVec3, p: DVec3, count: f64| {
        let s = (p - a).dot(b - a) / (b - a).length_squared() * count;
        (s - s.round()).abs() < 1e-9
    };
    let node = |g: &Grid, a: usize, b: usize| g.nodes()[g.node_id(a as isize, b as isize).unwrap()];
    let (a0, a1) = (node(&plane, 0, 0), node(&plane, 9, 0));
    let (b0, b1) = (node(&plane, 0, 0), node(&plane, 0, 6));
    let (la, lb) = twice.lattice_size();
    assert_eq!(twice.refined_u().len(), twice.vertices_u());
    for (k, &refined) in twice.refined_u().iter().enumerate() {
        let original = on_line(a0, a1, node(&twice, 3 * k, 0), 3.0);
        assert_eq!(refined, !original, "u line {k}");
    }
    for (q, &refined) in twice.refined_v().iter().enumerate() {
        let original = on_line(b0, b1, node(&twice, 0, 3 * q), 2.0);
        assert_eq!(refined, !original, "v line {q}");
    }
    assert_eq!(twice.refined_u().iter().filter(|r| !**r).count(), 4);
    assert_eq!(twice.refined_v().iter().filter(|r| !**r).count(), 3);
    assert!(la > 0 && lb > 0);

    // Closed: the sphere's 8 meridians stay marked original after an insertion and its
    // opposite, whatever their angles become in the list.
    let sphere = build(Primitive::Sphere, (8, 4));
    let refined = Refinement::new(&sphere, &[0.5, 4.5], &[1.25])
        .unwrap()
        .apply(&sphere)
        .unwrap();
    assert_eq!(refined.refined_u().len(), 10);
    let first = node(&sphere, 0, 6);
    let base = first.y.atan2(first.x);
    for (k, &marked) in refined.refined_u().iter().enumerate() {
        let p = node(&refined, 3 * k, 6);
        let turns = (p.y.atan2(p.x) - base) / std::f64::consts::FRAC_PI_4;
        let on_a_meridian = (turns - turns.round()).abs() < 1e-6;
        assert_eq!(marked, !on_a_meridian, "meridian {k} at {turns} eighths");
    }
    assert_eq!(refined.refined_v().iter().filter(|r| **r).count(), 1);
}
