//! Curve-driven warping (P0 §4): the identity for unchanged curves, exact following on
//! curves, Beier and Neely's line-segment warp as the degree-1 reference, rigid motions, and
//! the 3D warp of a patch grid's control net by curves laid on it.

use crate::support::random;
use glam::{DMat2, DVec2, DVec3};
use nendo::curve::warp::{CurveWarp, WarpParams};
use nendo::curve::{BSpline, Bezier, Curve, Point};
use nendo::surface::{Grid, Primitive, PrimitiveParams};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn random_curve<P: Point>(rng: &mut ChaCha8Rng) -> Curve<P> {
    let degree = rng.gen_range(1..=5);
    let pts: Vec<P> = (0..=degree).map(|_| random::point(rng, 2.0)).collect();
    if rng.gen_bool(0.3) && degree >= 2 {
        let more: Vec<P> = pts
            .iter()
            .chain(std::iter::once(&random::point(rng, 2.0)))
            .copied()
            .collect();
        Curve::BSpline(BSpline::clamped_uniform(degree, more).expect("valid"))
    } else {
        Curve::Bezier(Bezier::new(pts))
    }
}

/// The curve with every control point moved by `f`.
fn mapped<P: Point>(c: &Curve<P>, f: impl Fn(P) -> P) -> Curve<P> {
    match c {
        Curve::Bezier(b) => Curve::Bezier(Bezier::new(b.points().iter().map(|&p| f(p)).collect())),
        Curve::BSpline(s) => Curve::BSpline(
            BSpline::try_new(
                s.degree(),
                s.knots().to_vec(),
                s.points().iter().map(|&p| f(p)).collect(),
            )
            .expect("same knots"),
        ),
    }
}

fn jiggled<P: Point>(rng: &mut ChaCha8Rng, c: &Curve<P>) -> Curve<P> {
    let moves: Vec<P> = (0..c.points().len())
        .map(|_| random::point(rng, 0.7))
        .collect();
    let mut i = 0;
    let pts: Vec<P> = c
        .points()
        .iter()
        .map(|&p| {
            i += 1;
            p + moves[i - 1]
        })
        .collect();
    match c {
        Curve::Bezier(_) => Curve::Bezier(Bezier::new(pts)),
        Curve::BSpline(s) => Curve::BSpline(
            BSpline::try_new(s.degree(), s.knots().to_vec(), pts).expect("same knots"),
        ),
    }
}

#[test]
fn unchanged_curves_warp_nothing() {
    let mut rng = ChaCha8Rng::seed_from_u64(7001);
    for _ in 0..50 {
        let curves: Vec<Curve<DVec2>> = (0..rng.gen_range(1..4))
            .map(|_| random_curve(&mut rng))
            .collect();
        let warp = CurveWarp::still(&curves, WarpParams::default()).expect("valid");
        for _ in 0..20 {
            let x: DVec2 = random::point(&mut rng, 4.0);
            assert_eq!(warp.warp_point(x), x);
        }
        // Also when the pairs are given explicitly (equal curves are recognised as still).
        let warp = CurveWarp::new(
            curves.iter().map(|c| (c.clone(), c.clone())).collect(),
            WarpParams::default(),
        )
        .expect("valid");
        let xs: Vec<DVec2> = (0..20).map(|_| random::point(&mut rng, 4.0)).collect();
        assert_eq!(warp.bind(&xs).apply(&warp).expect("same curves"), xs);
    }
}

#[test]
fn points_on_curves_follow_their_curve_exactly() {
    let mut rng = ChaCha8Rng::seed_from_u64(7002);
    let mut checked = 0;
    for _ in 0..60 {
        let originals: Vec<Curve<DVec2>> = (0..3).map(|_| random_curve(&mut rng)).collect();
        let mut warp = CurveWarp::still(&originals, WarpParams::default()).expect("valid");
        // Curve 0 moves, curve 1 is left still, curve 2 moves too.
        let moved0 = jiggled(&mut rng, &originals[0]);
        let moved2 = jiggled(&mut rng, &originals[2]);
        warp.set_deformed(0, moved0.clone()).expect("same domain");
        warp.set_deformed(2, moved2.clone()).expect("same domain");
        for _ in 0..10 {
            let k = rng.gen_range(0..3);
            let (a, b) = originals[k].domain();
            let u = a + rng.gen_range(0.0..1.0) * (b - a);
            let x = originals[k].eval(u);
            // Skip points where two curves cross (the point is on both).
            let on_others = (0..3)
                .filter(|&j| j != k)
                .any(|j| originals[j].closest(x, 1e-9).is_some());
            if on_others {
                continue;
            }
            let expected = match k {
                0 => moved0.eval(u),
                1 => x,
                _ => moved2.eval(u),
            };
            let got = warp.warp_point(x);
            // The closest point found may sit a rounding away from u: compare within 1e-9.
            assert!(
                (got - expected).length() < 1e-9,
                "curve {k}: {got} vs {expected}"
            );
            checked += 1;
        }
    }
    assert!(checked > 400);
}

/// Beier and Neely's warp by line segments (their eqs. 1–5 with the weight of eq. 6), written
/// independently: `u` along `PQ` as a fraction, `v` the signed perpendicular distance.
fn beier_neely(lines: &[(DVec2, DVec2, DVec2, DVec2)], x: DVec2, params: WarpParams) -> DVec2 {
    let mut sum = DVec2::ZERO;
    let mut wsum = 0.0;
    for &(p, q, pd, qd) in lines {
        let pq = q - p;
        let u = (x - p).dot(pq) / pq.length_squared();
        let v = (x - p).dot(pq.perp()) / pq.length();
        let xd = pd + (qd - pd) * u + (qd - pd).perp() * (v / (qd - pd).length());
        let dist = if u < 0.0 {
            (x - p).length()
        } else if u > 1.0 {
            (x - q).length()
        } else {
            v.abs()
        };
        let w = (pq.length().powf(params.p) / (params.a + dist)).powf(params.b);
        sum += (xd - x) * w;
        wsum += w;
    }
    x + sum / wsum
}

#[test]
fn degree_one_curves_are_beier_neely_line_warping() {
    let mut rng = ChaCha8Rng::seed_from_u64(7003);
    let params = WarpParams {
        a: 0.01,
        b: 1.5,
        p: 0.5,
        reach: f64::INFINITY,
    };
    let mut checked = 0;
    for _ in 0..40 {
        let lines: Vec<(DVec2, DVec2, DVec2, DVec2)> = (0..3)
            .map(|_| {
                let p: DVec2 = random::point(&mut rng, 2.0);
                let q: DVec2 = random::point(&mut rng, 2.0);
                (
                    p,
                    q,
                    p + random::point::<DVec2>(&mut rng, 0.5),
                    q + random::point::<DVec2>(&mut rng, 0.5),
                )
            })
            .collect();
        let pairs = lines
            .iter()
            .map(|&(p, q, pd, qd)| {
                (
                    Curve::Bezier(Bezier::new(vec![p, q])),
                    Curve::Bezier(Bezier::new(vec![pd, qd])),
                )
            })
            .collect();
        let warp = CurveWarp::new(pairs, params).expect("valid");
        for _ in 0..50 {
            let x: DVec2 = random::point(&mut rng, 3.0);
            // Within every line's perpendicular strip the two constructions agree (beyond an
            // end Beier and Neely extrapolate the line, nendo carries the end's frame).
            let inside = lines.iter().all(|&(p, q, _, _)| {
                let u = (x - p).dot(q - p) / (q - p).length_squared();
                (0.0..=1.0).contains(&u)
            });
            if !inside {
                continue;
            }
            let got = warp.warp_point(x);
            let want = beier_neely(&lines, x, params);
            assert!((got - want).length() < 1e-9, "{got} vs {want}");
            checked += 1;
        }
    }
    assert!(checked > 50, "{checked}");
}

#[test]
fn a_rigid_motion_of_all_curves_moves_every_point_by_it() {
    let mut rng = ChaCha8Rng::seed_from_u64(7004);
    for _ in 0..30 {
        let originals: Vec<Curve<DVec2>> = (0..3).map(|_| random_curve(&mut rng)).collect();
        let rot = DMat2::from_angle(rng.gen_range(-3.0..3.0));
        let shift: DVec2 = random::point(&mut rng, 2.0);
        let motion = |p: DVec2| rot * p + shift;
        let pairs = originals
            .iter()
            .map(|c| (c.clone(), mapped(c, motion)))
            .collect();
        let warp = CurveWarp::new(pairs, WarpParams::default()).expect("valid");
        let xs: Vec<DVec2> = (0..30).map(|_| random::point(&mut rng, 4.0)).collect();
        let bound = warp.bind(&xs).apply(&warp).expect("same curves");
        for (x, b) in xs.iter().zip(&bound) {
            let direct = warp.warp_point(*x);
            assert!(
                (direct - motion(*x)).length() < 1e-9,
                "{direct} vs {}",
                motion(*x)
            );
            assert!((*b - direct).length() < 1e-12);
        }
    }
}

#[test]
fn polygons_are_refined_then_warped() {
    let c: Curve<DVec2> = Bezier::new(vec![
        DVec2::new(-2.0, 0.0),
        DVec2::new(0.0, 0.0),
        DVec2::new(2.0, 0.0),
    ])
    .into();
    let bent: Curve<DVec2> = Bezier::new(vec![
        DVec2::new(-2.0, 0.0),
        DVec2::new(0.0, 2.0),
        DVec2::new(2.0, 0.0),
    ])
    .into();
    let warp = CurveWarp::new(vec![(c, bent.clone())], WarpParams::default()).expect("valid");
    let square = [
        DVec2::new(-1.0, -0.5),
        DVec2::new(1.0, -0.5),
        DVec2::new(1.0, 0.5),
        DVec2::new(-1.0, 0.5),
    ];
    let coarse = warp.warp_polygon(&square, f64::INFINITY).expect("positive");
    assert_eq!(coarse.len(), 4);
    let fine = warp.warp_polygon(&square, 0.1).expect("positive");
    assert_eq!(fine.len(), 2 * (20 + 10));
    // A lone curve carries its whole neighbourhood: every point keeps its offset from the
    // curve along the normal, so the refined bottom edge bends like the curve.
    let mid_bottom = fine[10];
    assert!(
        (mid_bottom - DVec2::new(0.0, 0.5)).length() < 1e-9,
        "{mid_bottom}"
    );
    assert!(warp.warp_polygon(&square, 0.0).is_err());
}

#[test]
fn a_still_background_limits_the_reach_of_a_moved_curve() {
    let c: Curve<DVec2> = Bezier::new(vec![DVec2::new(-1.0, 0.0), DVec2::new(1.0, 0.0)]).into();
    let up = mapped(&c, |p| p + DVec2::Y);
    let params = WarpParams {
        reach: 2.0,
        b: 1.0,
        ..WarpParams::default()
    };
    let warp = CurveWarp::new(vec![(c, up)], params).expect("valid");
    // At distance `reach` the point moves half as far as the curve.
    let x = DVec2::new(0.0, -2.0);
    assert!((warp.warp_point(x) - (x + DVec2::Y * 0.5)).length() < 1e-12);
    // Far away it hardly moves; on the curve it follows.
    assert!((warp.warp_point(DVec2::new(0.0, -200.0)).y + 200.0).abs() < 0.02);
    assert!((warp.warp_point(DVec2::new(0.3, 0.0)) - DVec2::new(0.3, 1.0)).length() < 1e-12);
}

#[test]
fn deformed_curves_must_keep_the_domain() {
    let s: Curve<DVec2> = BSpline::clamped_uniform(
        2,
        vec![
            DVec2::ZERO,
            DVec2::X,
            DVec2::new(2.0, 1.0),
            DVec2::new(3.0, 0.0),
        ],
    )
    .expect("valid")
    .into();
    let other: Curve<DVec2> = BSpline::try_new(
        2,
        vec![0.0, 0.0, 0.0, 0.5, 2.0, 2.0, 2.0],
        vec![
            DVec2::ZERO,
            DVec2::X,
            DVec2::new(2.0, 1.0),
            DVec2::new(3.0, 0.0),
        ],
    )
    .expect("valid")
    .into();
    assert!(CurveWarp::new(vec![(s.clone(), other.clone())], WarpParams::default()).is_err());
    let mut warp = CurveWarp::still(&[s], WarpParams::default()).expect("valid");
    assert!(warp.set_deformed(0, other).is_err());
    assert!(
        warp.set_deformed(3, Bezier::new(vec![DVec2::ZERO]).into())
            .is_err()
    );
}

// ---- 3D: a patch grid's control net carried by curves laid on it ----

fn plane(m: usize, n: usize) -> Grid {
    Primitive::Plane
        .build(&PrimitiveParams {
            patches: Some((m, n)),
            ..PrimitiveParams::default()
        })
        .expect("plane")
}

/// A cubic along the lattice row `y = y0` of the plane (`z = 0`), from `x0` to `x1`.
fn row_curve(x0: f64, x1: f64, y0: f64) -> Curve<DVec3> {
    Bezier::new(
        (0..4)
            .map(|i| DVec3::new(x0 + (x1 - x0) * i as f64 / 3.0, y0, 0.0))
            .collect(),
    )
    .into()
}

#[test]
fn a_dragged_curve_reshapes_the_net_and_still_curves_hold_theirs() {
    let grid = plane(10, 10);
    let nodes = grid.nodes().to_vec();
    // Lattice rows are at y = k/3 − 5; the curves lie on rows y = −2 and y = 2.
    let dragged = row_curve(-3.0, 3.0, -2.0);
    let still = row_curve(-3.0, 3.0, 2.0);
    let mut warp =
        CurveWarp::still(&[dragged.clone(), still.clone()], WarpParams::default()).expect("valid");
    let bound = warp.bind(&nodes);
    // Unchanged: the identity, exactly.
    assert_eq!(bound.apply(&warp).expect("same"), nodes);
    // Lift the first curve into an arch.
    let arch: Curve<DVec3> = Bezier::new(vec![
        DVec3::new(-3.0, -2.0, 0.0),
        DVec3::new(-1.0, -2.0, 1.5),
        DVec3::new(1.0, -2.0, 1.5),
        DVec3::new(3.0, -2.0, 0.0),
    ])
    .into();
    warp.set_deformed(0, arch.clone()).expect("same domain");
    let moved = bound.apply(&warp).expect("same");
    let mut on_dragged = 0;
    let mut on_still = 0;
    for (x, y) in nodes.iter().zip(&moved) {
        if (x.y + 2.0).abs() < 1e-12 && x.x.abs() <= 3.0 + 1e-12 {
            // On the dragged curve (a straight cubic with evenly spaced points: C(u) = x at
            // u = (x + 3)/6): the node follows the arch exactly.
            let u = (x.x + 3.0) / 6.0;
            assert!((*y - arch.eval(u)).length() < 1e-9, "{x} → {y}");
            on_dragged += 1;
        }
        if (x.y - 2.0).abs() < 1e-12 && x.x.abs() <= 3.0 + 1e-12 {
            assert!(
                (*y - *x).length() < 1e-12,
                "a node on the still curve moved: {x} → {y}"
            );
            on_still += 1;
        }
    }
    assert_eq!((on_dragged, on_still), (19, 19));
    // Between the curves the clay rises less the nearer it is to the still curve.
    let lift = |x: f64, y: f64| {
        let i = nodes
            .iter()
            .position(|p| (p.x - x).abs() < 1e-9 && (p.y - y).abs() < 1e-9)
            .expect("node");
        moved[i].z
    };
    assert!(
        lift(0.0, -1.0) > lift(0.0, 0.0) && lift(0.0, 0.0) > lift(0.0, 1.0) && lift(0.0, 1.0) > 0.0
    );
    // The warped net is a valid grid again (the regulation's reference ratios kept).
    let mut regrid = Grid::from_net(grid.topology(), 10, 10, moved).expect("finite net");
    regrid
        .set_ratios(grid.ratios_u(), grid.ratios_v())
        .expect("same counts");
}

#[test]
fn space_curves_carry_points_by_rotation_minimising_frames() {
    let mut rng = ChaCha8Rng::seed_from_u64(7005);
    for _ in 0..30 {
        let originals: Vec<Curve<DVec3>> = (0..2).map(|_| random_curve(&mut rng)).collect();
        let moved0 = jiggled(&mut rng, &originals[0]);
        let mut warp = CurveWarp::still(&originals, WarpParams::default()).expect("valid");
        let xs: Vec<DVec3> = (0..40).map(|_| random::point(&mut rng, 3.0)).collect();
        let bound = warp.bind(&xs);
        assert_eq!(bound.apply(&warp).expect("same"), xs);
        warp.set_deformed(0, moved0.clone()).expect("same domain");
        let out = bound.apply(&warp).expect("same");
        for (x, y) in xs.iter().zip(&out) {
            assert!((warp.warp_point(*x) - *y).length() < 1e-12);
        }
        // Points on either curve: followed exactly / held exactly.
        for k in 0..2 {
            let (a, b) = originals[k].domain();
            let u = a + rng.gen_range(0.05..0.95) * (b - a);
            let x = originals[k].eval(u);
            if originals[1 - k].closest(x, 1e-9).is_some() {
                continue;
            }
            let want = if k == 0 { moved0.eval(u) } else { x };
            assert!((warp.warp_point(x) - want).length() < 1e-9);
        }
        // Translating every curve translates every point.
        let shift: DVec3 = random::point(&mut rng, 2.0);
        let pairs = originals
            .iter()
            .map(|c| (c.clone(), mapped(c, |p| p + shift)))
            .collect();
        let shifted = CurveWarp::new(pairs, WarpParams::default()).expect("valid");
        for x in &xs {
            assert!((shifted.warp_point(*x) - (*x + shift)).length() < 1e-9);
        }
    }
}
