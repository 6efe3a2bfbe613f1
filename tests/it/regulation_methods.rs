//! Regulation methods (docs/design.md §12): the properties each method promises, on the grid.

use glam::DVec3;
use nendo::surface::continuity::report;
use nendo::surface::{
    Grid, Op, Primitive, PrimitiveParams, Regulation, Sculptor, deform, regulate_all,
};
use nendo_bench::regulation::{Strokes, experiment, experiment_cases};
use proptest::prelude::*;

fn sine_of_kink(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (d1, d2) = (b - a, c - b);
    d1.cross(d2).length() / (d1.length() * d2.length())
}

/// The worst kink of the three-point rows crossing shared grid lines, over every group.
fn worst_row_kink(g: &Grid) -> f64 {
    let mut worst = 0.0f64;
    for grp in g.groups() {
        let at = |s: isize, t: isize| grp.node(s, t).map(|id| g.nodes()[id]);
        for k in -1..=1 {
            if let (Some(a), Some(b), Some(c)) = (at(-1, k), at(0, k), at(1, k)) {
                worst = worst.max(sine_of_kink(a, b, c));
            }
            if let (Some(a), Some(b), Some(c)) = (at(k, -1), at(k, 0), at(k, 1)) {
                worst = worst.max(sine_of_kink(a, b, c));
            }
        }
    }
    worst
}

/// The worst kink of `ring[3k + l − 1]`, pole, `ring[3(k + n) + l − 1]` over opposite pairs.
fn worst_pole_pair_kink(g: &Grid) -> f64 {
    let mut worst = 0.0f64;
    for pole in g.poles() {
        let o = g.nodes()[pole.node];
        let len = pole.ring.len() as isize;
        let at = |a: isize| g.nodes()[pole.ring[a.rem_euclid(len) as usize]];
        let n = len / 6;
        for k in 0..n {
            for l in -1..=1 {
                worst = worst.max(sine_of_kink(at(3 * k + l), o, at(3 * (k + n) + l)));
            }
        }
    }
    worst
}

fn plane() -> Grid {
    Primitive::Plane
        .build(&PrimitiveParams {
            patches: Some((10, 10)),
            ..PrimitiveParams::default()
        })
        .unwrap()
}

fn sphere() -> Grid {
    Primitive::Sphere
        .build(&PrimitiveParams::default())
        .unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn g1_makes_every_row_of_every_group_collinear(x in -3.0..3.0f64, y in -3.0..3.0f64, depth in -1.2..1.2f64, r in 0.4..2.0f64) {
        let mut g = plane();
        deform(&mut g, &Op::Push { at: DVec3::new(x, y, 0.0), dir: DVec3::new(0.1, -0.2, -1.0), depth, radius: r }, Regulation::G1).unwrap();
        prop_assert!(worst_row_kink(&g) < 1e-10, "{}", worst_row_kink(&g));
    }

    #[test]
    fn g1_and_c1_make_opposite_pairs_collinear_through_the_pole(lat in 1.0..1.5f64, lon in 0.0..std::f64::consts::TAU, depth in -0.8..0.8f64) {
        for method in [Regulation::G1, Regulation::C1] {
            let mut g = sphere();
            let at = DVec3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin()) * 3.0;
            deform(&mut g, &Op::Push { at, dir: -at, depth, radius: 1.5 }, method).unwrap();
            prop_assert!(worst_pole_pair_kink(&g) < 1e-10, "{method}: {}", worst_pole_pair_kink(&g));
            prop_assert!(worst_row_kink(&g) < 1e-10, "{method}: {}", worst_row_kink(&g));
        }
    }

    #[test]
    fn c1_rows_are_equally_spaced(x in -3.0..3.0f64, y in -3.0..3.0f64, depth in -1.0..1.0f64) {
        let mut g = plane();
        deform(&mut g, &Op::Push { at: DVec3::new(x, y, 0.0), dir: -DVec3::Z, depth, radius: 1.25 }, Regulation::C1).unwrap();
        for grp in g.groups() {
            let at = |s: isize, t: isize| grp.node(s, t).map(|id| g.nodes()[id]);
            for k in -1..=1 {
                if let (Some(a), Some(b), Some(c)) = (at(-1, k), at(0, k), at(1, k)) {
                    prop_assert!(((c - b) - (b - a)).length() < 1e-12);
                }
            }
        }
    }

    #[test]
    fn exact_is_g1_to_rounding_after_random_strokes(seed in 0u64..1000, which in 0usize..5) {
        let p = [Primitive::Plane, Primitive::Cylinder, Primitive::Hemisphere, Primitive::Sphere, Primitive::Torus][which];
        let mut g = p.build(&PrimitiveParams::default()).unwrap();
        let mut strokes = Strokes::new(seed);
        let mut s = Sculptor::new();
        for _ in 0..40 {
            let op = strokes.next_op(&g);
            s.apply(&mut g, &op, Regulation::Exact).unwrap();
        }
        let r = report(&g, 33);
        prop_assert!(r.g1_max_deg < 1e-8, "{p}: {}", r.g1_max_deg);
        for pole in &r.poles {
            prop_assert!(pole.spread_deg < 1e-8, "{p}: {}", pole.spread_deg);
        }
    }
}

#[test]
fn a_push_exactly_at_a_pole_keeps_it_smooth_with_every_method() {
    for method in [Regulation::C1, Regulation::G1, Regulation::Exact] {
        for depth in [0.3, 0.9, -0.6] {
            let mut g = sphere();
            deform(
                &mut g,
                &Op::Push {
                    at: DVec3::new(0.0, 0.0, 3.0),
                    dir: -DVec3::Z,
                    depth,
                    radius: 1.25,
                },
                method,
            )
            .unwrap();
            let r = report(&g, 33);
            let north = r.poles.iter().find(|p| p.position.z > 0.0).unwrap();
            assert!(
                north.spread_deg < 1e-9,
                "{method} {depth}: spread {}",
                north.spread_deg
            );
            assert!(
                (north.position - DVec3::new(0.0, 0.0, 3.0 - depth)).length() < 1e-12,
                "{method}: the pole is the axis sample"
            );
            assert!(
                r.g1_max_deg < 1e-8 || method == Regulation::G1,
                "{method}: {}",
                r.g1_max_deg
            );
        }
    }
}

#[test]
fn the_paper_method_is_g1_only_where_the_end_ratios_agree() {
    // An off-centre push gives the groups at the two ends of an edge different ratios: the
    // paper's construction leaves a seam angle that grows with the depth; exact does not.
    let mut worst = Vec::new();
    for depth in [0.25, 1.0] {
        let mut g = plane();
        deform(
            &mut g,
            &Op::Push {
                at: DVec3::new(0.5, 0.5, 0.0),
                dir: -DVec3::Z,
                depth,
                radius: 1.25,
            },
            Regulation::G1,
        )
        .unwrap();
        worst.push(report(&g, 33).g1_max_deg);
        let mut e = plane();
        deform(
            &mut e,
            &Op::Push {
                at: DVec3::new(0.5, 0.5, 0.0),
                dir: -DVec3::Z,
                depth,
                radius: 1.25,
            },
            Regulation::Exact,
        )
        .unwrap();
        assert!(report(&e, 33).g1_max_deg < 1e-9);
    }
    assert!(worst[0] > 1e-3 && worst[1] > worst[0], "{worst:?}");
}

#[test]
fn regulation_stays_local_and_deterministic() {
    for method in Regulation::ALL {
        for base in [plane(), sphere()] {
            let op = Op::Push {
                at: base.eval(2, 2, 0.3, 0.6),
                dir: -base.normal(2, 2, 0.3, 0.6).unwrap(),
                depth: 0.4,
                radius: 1.0,
            };
            let (mut a, mut b) = (base.clone(), base.clone());
            let ta = deform(&mut a, &op, method).unwrap();
            let tb = deform(&mut b, &op, method).unwrap();
            assert_eq!(ta, tb);
            assert!(
                a.nodes()
                    .iter()
                    .zip(b.nodes())
                    .all(|(x, y)| x.to_array().map(f64::to_bits) == y.to_array().map(f64::to_bits))
            );
            for p in 0..base.patch_count() {
                if !ta.patches.contains(&p) {
                    assert_eq!(
                        a.patch_at(p),
                        base.patch_at(p),
                        "{method}: patch {p} outside the touched set changed"
                    );
                }
            }
            assert!(
                ta.patches.len() < base.patch_count() || base.patch_count() <= 32,
                "{method}: {}",
                ta.patches.len()
            );
        }
    }
}

#[test]
fn regulating_a_whole_unregulated_model_makes_it_g1() {
    let mut g = sphere();
    let mut strokes = Strokes::new(77);
    let mut s = Sculptor::new();
    for _ in 0..100 {
        let op = strokes.next_op(&g);
        s.apply(&mut g, &op, Regulation::None).unwrap();
    }
    assert!(report(&g, 33).g1_max_deg > 1.0);
    regulate_all(&mut g, Regulation::Exact).expect("exact regulates");
    let r = report(&g, 33);
    assert!(r.g1_max_deg < 1e-8, "{}", r.g1_max_deg);
    assert!(r.poles.iter().all(|p| p.spread_deg < 1e-8));
}

#[test]
fn the_default_method_meets_the_deviation_target_on_the_papers_experiment() {
    let row = experiment(Regulation::Exact, &experiment_cases());
    assert!(
        row.from_ideal.mean <= 0.03,
        "mean deviation from the ideal {}",
        row.from_ideal.mean
    );
    assert!(row.g1_max_deg < 1e-9, "{}", row.g1_max_deg);
    let paper = experiment(Regulation::G1, &experiment_cases());
    assert!(
        row.from_ideal.mean < paper.from_ideal.mean,
        "{} vs {}",
        row.from_ideal.mean,
        paper.from_ideal.mean
    );
}
