//! The curve queries against independent references (tests/support/reference.rs: dense sampling
//! and golden-section polish, no clipping), on more than 10 000 random cases with fixed seeds,
//! and the hard cases by name.

use crate::support::random;
use crate::support::reference;
use glam::{DVec2, DVec3};
use nendo::curve::{BSpline, Bezier, Curve, CurveSet, Point, pick};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Relative distance tolerance of the issue: 1e-9 of the distance (or of the curve's unit scale
/// where the distance is below one).
fn tol(d: f64) -> f64 {
    1e-9 * d.max(1.0)
}

fn check_closest<P: Point>(rng: &mut ChaCha8Rng, cases: usize) -> usize {
    let mut checked = 0;
    for case in 0..cases {
        let degree = 1 + case % 9;
        let c: Curve<P> = random::curve(rng, degree);
        let spread = if rng.gen_bool(0.2) { 5.0 } else { 1.5 };
        let q: P = random::point(rng, spread);
        let (u_ref, d_ref) = reference::closest(&c, q);
        let rmax = if rng.gen_bool(0.4) {
            rng.gen_range(0.0..2.0)
        } else {
            f64::INFINITY
        };
        let got = c.closest(q, rmax);
        if d_ref > rmax * (1.0 + 1e-9) + 1e-12 {
            assert!(
                got.is_none() || got.is_some_and(|n| n.distance <= rmax),
                "case {case}: beyond rmax"
            );
            continue;
        }
        if (d_ref - rmax).abs() < 1e-9 {
            continue; // on the boundary: either answer is right
        }
        let n = got.unwrap_or_else(|| {
            panic!("case {case}: deg {degree} q {q:?} expected {d_ref} (u {u_ref}), got none")
        });
        assert!(
            n.distance <= d_ref + tol(d_ref),
            "case {case}: deg {degree} {c:?} q {q:?}: got {} at u {}, reference {d_ref} at u {u_ref}",
            n.distance,
            n.u
        );
        // Our answer is a point of the curve, so it cannot be much below the true minimum.
        assert!(
            n.distance >= d_ref - 1e-6 * d_ref.max(1.0),
            "case {case}: reference missed a minimum"
        );
        assert!(
            (c.eval(n.u) - n.point).length() < 1e-12,
            "case {case}: {c:?} u {} point {:?} eval {:?}",
            n.u,
            n.point,
            c.eval(n.u)
        );
        assert!(((n.point - q).length() - n.distance).abs() < 1e-12);
        checked += 1;
    }
    checked
}

#[test]
fn closest_matches_reference_2d_and_3d() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0001);
    let a = check_closest::<DVec2>(&mut rng, 3000);
    let b = check_closest::<DVec3>(&mut rng, 3000);
    assert!(a + b > 4500, "too few cases were comparable: {a} + {b}");
}

#[test]
fn pick_matches_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0002);
    for case in 0..700 {
        let k = rng.gen_range(2..=50);
        let curves: Vec<Curve<DVec2>> = (0..k)
            .map(|_| {
                let deg = rng.gen_range(1..=9);
                let mut c = random::curve::<DVec2>(&mut rng, deg);
                let shift = random::point::<DVec2>(&mut rng, 6.0);
                c = match c {
                    Curve::Bezier(b) => {
                        Curve::Bezier(Bezier::new(b.points().iter().map(|&p| p + shift).collect()))
                    }
                    Curve::BSpline(s) => Curve::BSpline(
                        BSpline::try_new(
                            s.degree(),
                            s.knots().to_vec(),
                            s.points().iter().map(|&p| p + shift).collect(),
                        )
                        .expect("shifted spline is valid"),
                    ),
                };
                c
            })
            .collect();
        let q: DVec2 = random::point(&mut rng, 7.0);
        let refs: Vec<f64> = curves.iter().map(|c| reference::closest(c, q).1).collect();
        let best = refs.iter().copied().fold(f64::INFINITY, f64::min);
        let rmax = if case % 3 == 0 {
            rng.gen_range(0.0..3.0)
        } else {
            f64::INFINITY
        };
        let set = CurveSet::new(&curves);
        for got in [pick(&curves, q, rmax), set.pick(q, rmax)] {
            if best > rmax + 1e-9 {
                assert!(got.is_none(), "case {case}: expected none");
                continue;
            }
            if (best - rmax).abs() < 1e-9 {
                continue;
            }
            let p = got.unwrap_or_else(|| panic!("case {case}: expected a pick at {best}"));
            assert!(
                p.nearest.distance <= best + tol(best),
                "case {case}: {} vs {best}",
                p.nearest.distance
            );
            assert!((refs[p.index] - p.nearest.distance).abs() <= 1e-6 * best.max(1.0));
        }
    }
}

#[test]
fn sphere_intervals_match_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0003);
    let mut compared = 0;
    for case in 0..2000 {
        let degree = 1 + case % 9;
        let (ok, amb) = if case % 2 == 0 {
            let c: Curve<DVec2> = random::curve(&mut rng, degree);
            let q: DVec2 = random::point(&mut rng, 1.0);
            let r = rng.gen_range(0.05..1.5);
            compare_sphere(&c, q, r)
        } else {
            let c: Curve<DVec3> = random::curve(&mut rng, degree);
            let q: DVec3 = random::point(&mut rng, 1.0);
            let r = rng.gen_range(0.05..1.5);
            compare_sphere(&c, q, r)
        };
        if amb {
            continue;
        }
        assert!(ok.is_ok(), "case {case}: {}", ok.err().unwrap_or_default());
        compared += 1;
    }
    assert!(compared > 1800, "only {compared} unambiguous cases");
}

fn compare_sphere<P: Point>(c: &Curve<P>, q: P, r: f64) -> (Result<(), String>, bool) {
    let (want, ambiguity) = reference::sphere(c, q, r, 4000);
    // Skip cases where the curve grazes the sphere: the interval count depends on rounding.
    if ambiguity < 1e-4 {
        return (Ok(()), true);
    }
    let got = c.sphere_intervals(q, r);
    if got.len() != want.len() {
        return (
            Err(format!("{c:?} q {q:?} r {r}: got {got:?}, want {want:?}")),
            false,
        );
    }
    for (g, w) in got.iter().zip(&want) {
        if (g.0 - w.0).abs() > 1e-9 || (g.1 - w.1).abs() > 1e-9 {
            return (
                Err(format!("{c:?} q {q:?} r {r}: got {got:?}, want {want:?}")),
                false,
            );
        }
    }
    (Ok(()), false)
}

#[test]
fn ray_matches_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0004);
    for case in 0..1500 {
        let degree = 1 + case % 9;
        let c: Curve<DVec3> = random::curve(&mut rng, degree);
        let o: DVec3 = random::point(&mut rng, 3.0);
        let d: DVec3 = random::point(&mut rng, 1.0);
        if d.length() < 1e-3 {
            continue;
        }
        let (_, d_ref) = reference::ray(&c, o, d);
        let r = c.ray_closest(o, d).expect("finite ray");
        assert!(
            r.distance <= d_ref + tol(d_ref),
            "case {case}: {} vs {d_ref}",
            r.distance
        );
        assert!(
            r.distance >= d_ref - 1e-6 * d_ref.max(1.0),
            "case {case}: reference missed"
        );
        assert!(r.ray_t >= 0.0);
        let on_ray = o + d * r.ray_t;
        assert!(((r.point - on_ray).length() - r.distance).abs() < 1e-9);
    }
}

// ---- Hard cases, by name ------------------------------------------------------------------

fn cubic2(p: [[f64; 2]; 4]) -> Bezier<DVec2> {
    Bezier::new(p.iter().map(|&[x, y]| DVec2::new(x, y)).collect())
}

#[test]
fn query_on_the_curve() {
    let c = cubic2([[0.0, 0.0], [1.0, 2.0], [2.0, -1.0], [3.0, 1.0]]);
    for k in 1..20 {
        let u = k as f64 / 20.0;
        let q = c.eval(u);
        let n = nendo::curve::closest_bezier(&c, q, f64::INFINITY).expect("unbounded");
        assert!(n.distance < 1e-12, "u {u}: {}", n.distance);
        assert!((n.u - u).abs() < 1e-7, "u {u}: {}", n.u);
    }
}

#[test]
fn query_at_an_end_point() {
    let c = cubic2([[0.0, 0.0], [1.0, 2.0], [2.0, -1.0], [3.0, 1.0]]);
    let n =
        nendo::curve::closest_bezier(&c, DVec2::new(0.0, 0.0), f64::INFINITY).expect("unbounded");
    assert_eq!((n.u, n.distance), (0.0, 0.0));
    // Beyond the end, the end point is the closest.
    let n =
        nendo::curve::closest_bezier(&c, DVec2::new(4.0, 2.0), f64::INFINITY).expect("unbounded");
    assert_eq!(n.u, 1.0);
    assert!((n.distance - 2f64.sqrt()).abs() < 1e-12);
}

#[test]
fn query_at_a_cusp() {
    // P1 − P0 and P3 − P2 crossed symmetrically gives a cusp at u = 1/2.
    let c = cubic2([[0.0, 0.0], [2.0, 1.0], [0.0, 1.0], [2.0, 0.0]]);
    let cusp = c.eval(0.5);
    assert!(
        c.eval_derivative(0.5, 1).length() < 1e-12,
        "the test curve has a cusp"
    );
    let n = nendo::curve::closest_bezier(&c, cusp, f64::INFINITY).expect("unbounded");
    assert!(n.distance < 1e-9 && (n.u - 0.5).abs() < 1e-4);
    let q = cusp + DVec2::new(0.0, 0.3);
    let (_, d_ref) = reference::closest(&Curve::Bezier(c.clone()), q);
    let n = nendo::curve::closest_bezier(&c, q, f64::INFINITY).expect("unbounded");
    assert!((n.distance - d_ref).abs() < 1e-9);
}

#[test]
fn query_on_the_axis_of_a_symmetric_curve_has_two_equal_minima() {
    // A symmetric arch; a point above its middle but below the centre of curvature has two
    // symmetric closest points. Either is right; the answer is deterministic.
    let c = cubic2([[-2.0, 0.0], [-1.0, 3.0], [1.0, 3.0], [2.0, 0.0]]);
    let q = DVec2::new(0.0, 0.0);
    let (_, d_ref) = reference::closest(&Curve::Bezier(c.clone()), q);
    let a = nendo::curve::closest_bezier(&c, q, f64::INFINITY).expect("unbounded");
    let b = nendo::curve::closest_bezier(&c, q, f64::INFINITY).expect("unbounded");
    assert_eq!(a, b);
    assert!((a.distance - d_ref).abs() < 1e-9);
    let mirror = nendo::curve::closest_bezier(&c, q, f64::INFINITY)
        .map(|n| 1.0 - n.u)
        .expect("unbounded");
    assert!((c.eval(mirror) - q).length() - a.distance < 1e-9);
}

#[test]
fn straight_line_with_collinear_control_points() {
    // Control points out of order along one line: the curve doubles back on itself.
    let c = Bezier::new(vec![
        DVec3::ZERO,
        DVec3::new(3.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(2.0, 0.0, 0.0),
    ]);
    for &x in &[-1.0, 0.5, 1.2, 1.9, 2.5, 4.0] {
        let q = DVec3::new(x, 1.0, 0.0);
        let (_, d_ref) = reference::closest(&Curve::Bezier(c.clone()), q);
        let n = nendo::curve::closest_bezier(&c, q, f64::INFINITY).expect("unbounded");
        assert!(
            (n.distance - d_ref).abs() < 1e-9,
            "x {x}: {} vs {d_ref}",
            n.distance
        );
    }
}

#[test]
fn curve_whose_points_all_coincide() {
    let p = DVec2::new(1.0, 1.0);
    let c = Bezier::new(vec![p; 5]);
    let n = nendo::curve::closest_bezier(&c, DVec2::ZERO, f64::INFINITY).expect("unbounded");
    assert_eq!(n.point, p);
    assert!((n.distance - 2f64.sqrt()).abs() < 1e-15);
    assert!(c.eval(n.u) == p);
}

#[test]
fn query_far_outside_rmax() {
    let c = cubic2([[0.0, 0.0], [1.0, 2.0], [2.0, -1.0], [3.0, 1.0]]);
    assert!(nendo::curve::closest_bezier(&c, DVec2::new(100.0, 100.0), 5.0).is_none());
    let curves = vec![Curve::Bezier(c)];
    assert!(pick(&curves, DVec2::new(100.0, 100.0), 5.0).is_none());
    assert!(
        CurveSet::new(&curves)
            .pick(DVec2::new(100.0, 100.0), 5.0)
            .is_none()
    );
}

#[test]
fn tangential_sphere() {
    // A parabola-like arch touching the circle of radius 1 at its apex from outside.
    let c = Curve::Bezier(Bezier::new(vec![
        DVec2::new(-1.0, 3.0),
        DVec2::new(0.0, -1.0),
        DVec2::new(1.0, 3.0),
    ]));
    let iv = c.sphere_intervals(DVec2::ZERO, 1.0);
    assert_eq!(iv.len(), 1, "{iv:?}");
    assert!((iv[0].0 - 0.5).abs() < 1e-6 && (iv[0].1 - 0.5).abs() < 1e-6);
    // Slightly larger: a real interval around the apex; slightly smaller: nothing.
    let iv = c.sphere_intervals(DVec2::ZERO, 1.01);
    assert!(iv.len() == 1 && iv[0].0 < 0.5 && iv[0].1 > 0.5);
    assert!(c.sphere_intervals(DVec2::ZERO, 0.99).is_empty());
}

#[test]
fn bspline_parameters_are_reported_in_the_bspline_domain() {
    let pts: Vec<DVec2> = (0..7)
        .map(|i| DVec2::new(i as f64, if i % 2 == 0 { 0.0 } else { 1.0 }))
        .collect();
    let s = BSpline::try_new(
        3,
        vec![2.0, 2.0, 2.0, 2.0, 3.0, 4.0, 5.0, 6.0, 6.0, 6.0, 6.0],
        pts,
    )
    .expect("valid");
    let c = Curve::BSpline(s.clone());
    let q = s.eval(4.6) + DVec2::new(0.0, 0.0);
    let n = c.closest(q, f64::INFINITY).expect("unbounded");
    assert!((n.u - 4.6).abs() < 1e-7 && n.distance < 1e-12);
}

#[test]
fn rmax_is_inclusive_in_the_interior_as_at_the_ends() {
    // A line at distance exactly 1 below the query: found with R = 1.
    let line: Curve<DVec2> = Bezier::new(vec![DVec2::ZERO, DVec2::new(2.0, 0.0)]).into();
    let n = line
        .closest(DVec2::new(1.0, 1.0), 1.0)
        .expect("at distance exactly R");
    assert!((n.u - 0.5).abs() < 1e-12 && (n.distance - 1.0).abs() < 1e-15);
    // A query exactly on the curve, R = 0.
    let arch: Curve<DVec2> = Bezier::new(vec![
        DVec2::ZERO,
        DVec2::new(1.0, 2.0),
        DVec2::new(2.0, 0.0),
    ])
    .into();
    let n = arch
        .closest(DVec2::new(1.0, 1.0), 0.0)
        .expect("on the curve");
    assert!((n.u - 0.5).abs() < 1e-9 && n.distance < 1e-15);
    // Pick, likewise.
    let other: Curve<DVec2> = Bezier::new(vec![DVec2::new(0.0, 5.0), DVec2::new(2.0, 5.0)]).into();
    let p = pick(&[line, other], DVec2::new(1.0, 1.0), 1.0).expect("at distance exactly R");
    assert_eq!(p.index, 0);
    // Just beyond R is still nothing.
    let line: Curve<DVec2> = Bezier::new(vec![DVec2::ZERO, DVec2::new(2.0, 0.0)]).into();
    assert!(line.closest(DVec2::new(1.0, 1.0 + 1e-9), 1.0).is_none());
}

#[test]
fn bspline_pieces_meet_exactly_at_their_knots() {
    let c: Curve<DVec2> = BSpline::try_new(
        1,
        vec![0.317, 0.317, 0.896, 1.5, 1.5],
        vec![DVec2::new(-1.0, 0.0), DVec2::ZERO, DVec2::new(1.0, 0.0)],
    )
    .unwrap()
    .into();
    let iv = c.sphere_intervals(DVec2::ZERO, 0.5);
    assert_eq!(iv.len(), 1, "one maximal interval across the knot: {iv:?}");
    let n = c.closest(DVec2::new(0.0, 0.3), f64::INFINITY).unwrap();
    assert_eq!(n.u, 0.896, "the knot itself, not an ulp beside it");
    // u never leaves the domain.
    let knots = vec![
        -2.4923951223606045,
        -2.4923951223606045,
        -1.7823977102797848,
        -1.6941254204731018,
        5.556019349283365,
        5.556019349283365,
    ];
    let pts = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(2.0, -1.0),
        DVec2::new(3.0, 0.5),
    ];
    let c: Curve<DVec2> = BSpline::try_new(1, knots, pts).unwrap().into();
    let (a, b) = c.domain();
    for q in [
        DVec2::new(9.0, 0.5),
        DVec2::new(-9.0, 0.0),
        DVec2::new(1.5, 3.0),
    ] {
        let n = c.closest(q, f64::INFINITY).unwrap();
        assert!(n.u >= a && n.u <= b, "{} outside [{a}, {b}]", n.u);
    }
}

#[test]
fn extreme_magnitudes_give_the_unit_scale_answers_scaled() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5ca1e);
    for &scale in &[1e-250, 1e-160, 1e160, 1e250, 1e300] {
        for _ in 0..100 {
            let c: Bezier<DVec2> = Bezier::new(
                (0..4)
                    .map(|_| random::point::<DVec2>(&mut rng, 1.0))
                    .collect(),
            );
            let q: DVec2 = random::point(&mut rng, 1.5);
            let unit = Curve::from(c.clone()).closest(q, f64::INFINITY).unwrap();
            let big = Bezier::new(c.points().iter().map(|&p| p * scale).collect());
            let n = Curve::from(big.clone())
                .closest(q * scale, f64::INFINITY)
                .unwrap();
            assert!(n.distance.is_finite(), "scale {scale}");
            assert!(
                (n.distance / scale - unit.distance).abs() <= 1e-9 * unit.distance.max(1e-300),
                "scale {scale}: {} vs {}",
                n.distance / scale,
                unit.distance
            );
            let iv = Curve::from(big).sphere_intervals(q * scale, unit.distance * 1.5 * scale);
            assert!(
                !iv.is_empty(),
                "scale {scale}: the sphere holds the closest point"
            );
        }
    }
    // A ray whose direction is tiny still has a direction.
    let line: Curve<DVec3> =
        Bezier::new(vec![DVec3::new(-1.0, 0.0, 0.0), DVec3::new(1.0, 0.0, 0.0)]).into();
    for d in [1e-300, 1e300] {
        let r = line
            .ray_closest(DVec3::new(0.0, -3.0, 0.0), DVec3::new(0.0, d, 0.0))
            .expect("a ray");
        assert!(r.distance < 1e-12, "dir {d}: {}", r.distance);
        assert!(
            (r.ray_t * d - 3.0).abs() < 1e-9,
            "dir {d}: ray_t {}",
            r.ray_t
        );
    }
}
