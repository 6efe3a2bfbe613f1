//! Similarity-preserving refinement (P3): similar copies when the constraints admit one
//! (both modes; Bezier degrees 2–9, B-splines, piecewise curves with C1/C2 joins), constraints
//! already met leave the curve alone, optimality of the weak terms against other feasible
//! curves, iterated refinement, and the paper's straightening and mirroring (its Fig. 5).

use glam::{DMat2, DVec2};
use nendo::curve::refine::{
    Constraint, Similarity, refine, refine_piecewise, similarity_variables,
};
use nendo::curve::{BSpline, Bezier, Curve, CurveError};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn rp(rng: &mut ChaCha8Rng) -> DVec2 {
    DVec2::new(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0))
}

/// A curve with some bend: control points along a wavy line with noise.
fn random_points(rng: &mut ChaCha8Rng, count: usize) -> Vec<DVec2> {
    let amp = rng.gen_range(0.3..1.0);
    (0..count)
        .map(|i| {
            let t = i as f64 / (count - 1) as f64;
            DVec2::new(2.0 * t - 1.0, amp * (3.0 * t).sin()) + rp(rng) * 0.3
        })
        .collect()
}

fn random_bezier(rng: &mut ChaCha8Rng, degree: usize) -> Curve<DVec2> {
    Curve::Bezier(Bezier::new(random_points(rng, degree + 1)))
}

fn random_bspline(rng: &mut ChaCha8Rng, degree: usize) -> Curve<DVec2> {
    let count = degree + 1 + rng.gen_range(1..4);
    Curve::BSpline(BSpline::clamped_uniform(degree, random_points(rng, count)).expect("valid"))
}

/// A C2 piecewise cubic: the Bezier segments of a clamped cubic B-spline.
fn random_piecewise(rng: &mut ChaCha8Rng, segments: usize) -> Vec<Bezier<DVec2>> {
    match random_bspline_with(rng, 3, segments + 3) {
        Curve::BSpline(s) => s
            .to_bezier_segments()
            .into_iter()
            .map(|s| s.bezier)
            .collect(),
        Curve::Bezier(b) => vec![b],
    }
}

fn random_bspline_with(rng: &mut ChaCha8Rng, degree: usize, count: usize) -> Curve<DVec2> {
    Curve::BSpline(BSpline::clamped_uniform(degree, random_points(rng, count)).expect("valid"))
}

fn map_curve(c: &Curve<DVec2>, f: impl Fn(DVec2) -> DVec2) -> Curve<DVec2> {
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

fn max_point_gap(a: &[DVec2], b: &[DVec2]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).length())
        .fold(0.0, f64::max)
}

/// A random similarity about `centre`: rotation in (−π, π), scale in (0.5, 2).
fn random_similarity(rng: &mut ChaCha8Rng, centre: DVec2) -> impl Fn(DVec2) -> DVec2 + Clone {
    let m = DMat2::from_angle(rng.gen_range(-3.1..3.1)) * rng.gen_range(0.5..2.0);
    move |p| centre + m * (p - centre)
}

/// Constraints admitting the similar copy `sim(C)`: the start stays, the end moves by `sim`; in
/// variation mode also the end tangents turned by `sim`.
fn copy_constraints(
    mode: Similarity,
    domain: (f64, f64),
    start: DVec2,
    end: DVec2,
    tangents: (DVec2, DVec2),
    sim: &impl Fn(DVec2) -> DVec2,
) -> Vec<Constraint> {
    let (a, b) = domain;
    let turn = |v: DVec2| sim(v) - sim(DVec2::ZERO);
    let mut c = vec![
        Constraint::Point { u: a, point: start },
        Constraint::Point {
            u: b,
            point: sim(end),
        },
    ];
    if mode == Similarity::Variation {
        c.push(Constraint::Tangent {
            u: a,
            direction: turn(tangents.0),
        });
        c.push(Constraint::Tangent {
            u: b,
            direction: turn(tangents.1),
        });
    }
    c
}

fn end_tangents(c: &Curve<DVec2>) -> (DVec2, DVec2) {
    let (a, b) = c.domain();
    (
        nendo::curve::edit::derivative(c, a, 1).expect("inside"),
        nendo::curve::edit::derivative(c, b, 1).expect("inside"),
    )
}

#[test]
fn similar_copies_are_found_when_the_constraints_admit_them() {
    let mut rng = ChaCha8Rng::seed_from_u64(9001);
    let mut worst: f64 = 0.0;
    let mut cases = 0;
    for mode in [Similarity::Curvature, Similarity::Variation] {
        let low = if mode == Similarity::Curvature { 2 } else { 3 };
        for degree in low..=9 {
            for trial in 0..12 {
                let c = if trial % 3 == 2 && degree <= 6 {
                    random_bspline(&mut rng, degree)
                } else {
                    random_bezier(&mut rng, degree)
                };
                let (a, b) = c.domain();
                let start = c.eval(a);
                let sim = random_similarity(&mut rng, start);
                let cons = copy_constraints(mode, (a, b), start, c.eval(b), end_tangents(&c), &sim);
                let r = refine(&c, mode, &cons).expect("refined");
                let copy = map_curve(&c, &sim);
                let gap = max_point_gap(r.curve.points(), copy.points());
                assert!(gap < 1e-9, "{mode:?} degree {degree}: {gap:e}");
                assert!(r.similarity_rms < 1e-9 && r.constraint_residual < 1e-9);
                worst = worst.max(gap);
                cases += 1;
            }
        }
    }
    assert!(cases > 150);
    eprintln!("similar copy: worst control-point error {worst:e} over {cases} curves");
}

#[test]
fn piecewise_curves_keep_their_joins_and_find_similar_copies() {
    let mut rng = ChaCha8Rng::seed_from_u64(9002);
    for mode in [Similarity::Curvature, Similarity::Variation] {
        for segments in 2..=4 {
            for _ in 0..10 {
                let segs = random_piecewise(&mut rng, segments);
                let n = segs.len() as f64;
                let start = segs[0].eval(0.0);
                let end = segs[segs.len() - 1].eval(1.0);
                let sim = random_similarity(&mut rng, start);
                let t0 = segs[0].eval_derivative(0.0, 1);
                let t1 = segs[segs.len() - 1].eval_derivative(1.0, 1);
                let cons = copy_constraints(mode, (0.0, n), start, end, (t0, t1), &sim);
                let r = refine_piecewise(&segs, mode, &cons).expect("refined");
                for (got, orig) in r.curve.iter().zip(&segs) {
                    let want: Vec<DVec2> = orig.points().iter().map(|&p| sim(p)).collect();
                    assert!(max_point_gap(got.points(), &want) < 1e-9, "{mode:?}");
                }
            }
        }
    }
    // A move that is no similarity: the joins (C2 in the original) stay C2.
    let segs = random_piecewise(&mut rng, 3);
    let pulled = segs[1].eval(0.5) + DVec2::new(0.2, 0.3);
    let cons = [
        Constraint::Point {
            u: 0.0,
            point: segs[0].eval(0.0),
        },
        Constraint::Point {
            u: 1.5,
            point: segs[1].eval(0.5) + DVec2::new(0.2, 0.3),
        },
        Constraint::Point {
            u: 3.0,
            point: segs[2].eval(1.0),
        },
    ];
    let r = refine_piecewise(&segs, Similarity::Curvature, &cons).expect("refined");
    assert!(r.constraint_residual < 1e-9);
    assert!((r.curve[1].eval(0.5) - pulled).length() < 1e-9);
    for i in 0..2 {
        for k in 0..=2 {
            let (l, rr) = (
                r.curve[i].eval_derivative(1.0, k),
                r.curve[i + 1].eval_derivative(0.0, k),
            );
            assert!(
                (l - rr).length() < 1e-9 * l.length().max(1.0),
                "joint {i}, order {k}"
            );
        }
    }
}

#[test]
fn explicit_joins_override_the_original_continuity() {
    // Two cubics meeting at a corner (C0 only).
    let segs = vec![
        Bezier::new(vec![
            DVec2::ZERO,
            DVec2::new(0.3, 0.5),
            DVec2::new(0.7, 0.6),
            DVec2::new(1.0, 0.0),
        ]),
        Bezier::new(vec![
            DVec2::new(1.0, 0.0),
            DVec2::new(1.4, 0.5),
            DVec2::new(1.7, -0.4),
            DVec2::new(2.0, 0.1),
        ]),
    ];
    let ends = [
        Constraint::Point {
            u: 0.0,
            point: DVec2::ZERO,
        },
        Constraint::Point {
            u: 2.0,
            point: DVec2::new(2.0, 0.1),
        },
    ];
    // Kept as it is: the corner stays a corner (constraints met: nothing changes).
    let kept = refine_piecewise(&segs, Similarity::Curvature, &ends).expect("refined");
    assert!(max_point_gap(kept.curve[0].points(), segs[0].points()) < 1e-12);
    // Asked for C1: the derivatives now agree.
    let mut cons = ends.to_vec();
    cons.push(Constraint::Join { at: 0, order: 1 });
    let smooth = refine_piecewise(&segs, Similarity::Curvature, &cons).expect("refined");
    let (l, r) = (
        smooth.curve[0].eval_derivative(1.0, 1),
        smooth.curve[1].eval_derivative(0.0, 1),
    );
    assert!((l - r).length() < 1e-9);
    assert!((smooth.curve[0].eval(1.0) - smooth.curve[1].eval(0.0)).length() < 1e-12);
    // Bad joins.
    cons.push(Constraint::Join { at: 1, order: 1 });
    assert!(matches!(
        refine_piecewise(&segs, Similarity::Curvature, &cons),
        Err(CurveError::Refine(_))
    ));
    let bad_order = [Constraint::Join { at: 0, order: 3 }];
    assert!(refine_piecewise(&segs, Similarity::Curvature, &bad_order).is_err());
}

#[test]
fn constraints_already_met_leave_the_curve_unchanged() {
    let mut rng = ChaCha8Rng::seed_from_u64(9003);
    for _ in 0..60 {
        let degree = rng.gen_range(3..=7);
        let c = if rng.gen_bool(0.5) {
            random_bezier(&mut rng, degree)
        } else {
            random_bspline(&mut rng, 3)
        };
        let (a, b) = c.domain();
        let mut cons = Vec::new();
        for _ in 0..rng.gen_range(1..4) {
            let u = a + rng.gen_range(0.0..1.0) * (b - a);
            cons.push(Constraint::Point {
                u,
                point: c.eval(u),
            });
        }
        let u = a + rng.gen_range(0.0..1.0) * (b - a);
        cons.push(Constraint::Tangent {
            u,
            direction: nendo::curve::edit::derivative(&c, u, 1).expect("inside"),
        });
        for mode in [Similarity::Curvature, Similarity::Variation] {
            let r = refine(&c, mode, &cons).expect("refined");
            assert!(max_point_gap(r.curve.points(), c.points()) < 1e-12);
        }
    }
}

#[test]
fn no_feasible_curve_is_more_similar_than_the_refined_one() {
    let mut rng = ChaCha8Rng::seed_from_u64(9004);
    for _ in 0..80 {
        let degree = rng.gen_range(3..=6);
        let c = random_bezier(&mut rng, degree);
        let u1 = rng.gen_range(0.1..0.9);
        let target = c.eval(u1) + rp(&mut rng) * 0.5;
        let cons = [
            Constraint::Point {
                u: 0.0,
                point: c.eval(0.0),
            },
            Constraint::Point {
                u: u1,
                point: target,
            },
        ];
        for mode in [Similarity::Curvature, Similarity::Variation] {
            let r = refine(&c, mode, &cons).expect("refined");
            assert!((r.curve.eval(u1) - target).length() < 1e-9);
            let s_of = |x: &Curve<DVec2>| -> f64 {
                similarity_variables(&c, x, mode)
                    .expect("same kind")
                    .iter()
                    .map(|s| s.d * s.d + s.c * s.c)
                    .sum()
            };
            let best = s_of(&r.curve);
            assert!(((best / r.samples as f64).sqrt() - r.similarity_rms).abs() < 1e-9);
            // Other curves through the same two points: the refined one plus a random move of the
            // control points that keeps C(0) and C(u1).
            let w0 = nendo::curve::edit::control_weights(&c, 0.0, 0).expect("inside");
            let w1 = nendo::curve::edit::control_weights(&c, u1, 0).expect("inside");
            for _ in 0..5 {
                let mut e: Vec<DVec2> = (0..=degree).map(|_| rp(&mut rng) * 0.2).collect();
                // Project e onto {Σ w0 e = 0, Σ w1 e = 0} (Gram–Schmidt on the two weight vectors).
                let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
                let n0 = dot(&w0, &w0);
                let w1p: Vec<f64> = w1
                    .iter()
                    .zip(&w0)
                    .map(|(x, y)| x - y * dot(&w1, &w0) / n0)
                    .collect();
                let n1 = dot(&w1p, &w1p);
                for (basis, norm) in [(&w0, n0), (&w1p, n1)] {
                    let proj = e
                        .iter()
                        .zip(basis.iter())
                        .fold(DVec2::ZERO, |acc, (v, w)| acc + *v * *w)
                        / norm;
                    for (v, w) in e.iter_mut().zip(basis.iter()) {
                        *v -= proj * *w;
                    }
                }
                let other_pts: Vec<DVec2> = r
                    .curve
                    .points()
                    .iter()
                    .zip(&e)
                    .map(|(p, d)| *p + *d)
                    .collect();
                let other = Curve::Bezier(Bezier::new(other_pts));
                assert!((other.eval(u1) - target).length() < 1e-9);
                assert!(
                    s_of(&other) >= best - 1e-12,
                    "{mode:?}: {} < {best}",
                    s_of(&other)
                );
            }
        }
    }
}

#[test]
fn iterated_refinement_stays_near_the_previous_step() {
    let mut rng = ChaCha8Rng::seed_from_u64(9005);
    for _ in 0..20 {
        // The paper's Fig. 8: a two-segment curve refined again and again from the last result.
        let segs = random_piecewise(&mut rng, 2);
        let start = segs[0].eval(0.0);
        let mut current = segs.clone();
        let mut total = segs.clone();
        let step_angle = rng.gen_range(-0.2..0.2);
        let step_scale = rng.gen_range(0.95..1.05);
        let step = DMat2::from_angle(step_angle) * step_scale;
        let mut end_target = segs[1].eval(1.0);
        for k in 1..=8 {
            let previous = current.clone();
            let new_end = start + step * (end_target - start);
            let cons = [
                Constraint::Point {
                    u: 0.0,
                    point: start,
                },
                Constraint::Point {
                    u: 2.0,
                    point: new_end,
                },
            ];
            let moved = (new_end - end_target).length();
            end_target = new_end;
            current = refine_piecewise(&current, Similarity::Curvature, &cons)
                .expect("refined")
                .curve;
            // Each step is a similar copy of the previous one: it stays near it, by at most the
            // move of the constraint times the curve's extent over the end's lever.
            let lever = (previous[1].eval(1.0) - start).length();
            let reach = previous
                .iter()
                .flat_map(|s| s.points())
                .map(|p| (*p - start).length())
                .fold(0.0, f64::max);
            for (a, b) in current.iter().zip(&previous) {
                assert!(
                    max_point_gap(a.points(), b.points())
                        <= moved * reach / lever * (1.0 + 1e-9) + 1e-12
                );
            }
            // And k small steps equal one step by the composed similarity.
            let composed = DMat2::from_angle(step_angle * k as f64) * step_scale.powi(k);
            total = segs
                .iter()
                .map(|s| {
                    Bezier::new(
                        s.points()
                            .iter()
                            .map(|&p| start + composed * (p - start))
                            .collect(),
                    )
                })
                .collect();
            for (a, b) in current.iter().zip(&total) {
                assert!(max_point_gap(a.points(), b.points()) < 1e-9);
            }
        }
        assert_eq!(total.len(), 2);
    }
}

/// The paper's Fig. 5 set-up: a two-segment C2 arch whose x is linear in the parameter.
fn arch() -> Vec<Bezier<DVec2>> {
    // A clamped uniform cubic B-spline on [0, 1] with two spans; x at the Greville abscissae
    // makes x(u) linear (linear precision), so the arch is x = 2u, y = bump(u).
    let greville = [0.0, 1.0 / 6.0, 0.5, 5.0 / 6.0, 1.0];
    let ys = [0.0, 0.6, 1.0, 0.7, 0.0];
    let pts = greville
        .iter()
        .zip(ys)
        .map(|(&g, y)| DVec2::new(2.0 * g, y))
        .collect();
    let s = BSpline::clamped_uniform(3, pts).expect("valid");
    s.to_bezier_segments()
        .into_iter()
        .map(|s| s.bezier)
        .collect()
}

#[test]
fn curvature_variation_similarity_straightens_and_mirrors_an_arch() {
    let segs = arch();
    assert_eq!(segs.len(), 2);
    let (a, mid, c) = (segs[0].eval(0.0), segs[0].eval(1.0), segs[1].eval(1.0));
    let chord = c - a;
    // Straighten: the joint onto the chord, the end tangents along it.
    let on_chord = a + chord * ((mid - a).dot(chord) / chord.length_squared());
    let straight = [
        Constraint::Point { u: 0.0, point: a },
        Constraint::Point {
            u: 1.0,
            point: on_chord,
        },
        Constraint::Point { u: 2.0, point: c },
        Constraint::Tangent {
            u: 0.0,
            direction: chord,
        },
        Constraint::Tangent {
            u: 2.0,
            direction: chord,
        },
        Constraint::Join { at: 0, order: 2 },
    ];
    let r = refine_piecewise(&segs, Similarity::Variation, &straight).expect("refined");
    for s in &r.curve {
        for p in s.points() {
            assert!(
                (*p - a).perp_dot(chord).abs() / chord.length() < 1e-9,
                "{p} is off the chord"
            );
        }
    }
    assert!(r.similarity_rms < 1e-9);
    // Curvature similarity cannot straighten it: the first derivative is held too.
    let rc = refine_piecewise(&segs, Similarity::Curvature, &straight).expect("refined");
    assert!(rc.similarity_rms > 1e-3, "{}", rc.similarity_rms);
    // Mirror (Fig. 5(c)): the joint to the other side of the chord, the tangents mirrored.
    let mirror = |p: DVec2| DVec2::new(p.x, -p.y);
    let t0 = segs[0].eval_derivative(0.0, 1);
    let t1 = segs[1].eval_derivative(1.0, 1);
    let flipped = [
        Constraint::Point { u: 0.0, point: a },
        Constraint::Point {
            u: 1.0,
            point: mirror(mid),
        },
        Constraint::Point { u: 2.0, point: c },
        Constraint::Tangent {
            u: 0.0,
            direction: mirror(t0),
        },
        Constraint::Tangent {
            u: 2.0,
            direction: mirror(t1),
        },
    ];
    let r = refine_piecewise(&segs, Similarity::Variation, &flipped).expect("refined");
    for (got, orig) in r.curve.iter().zip(&segs) {
        let want: Vec<DVec2> = orig.points().iter().map(|&p| mirror(p)).collect();
        assert!(max_point_gap(got.points(), &want) < 1e-9);
    }
}

#[test]
fn bad_refinements_are_refused() {
    let c: Curve<DVec2> = Bezier::new(vec![
        DVec2::ZERO,
        DVec2::new(1.0, 1.0),
        DVec2::new(2.0, 0.0),
    ])
    .into();
    let ok = [Constraint::Point {
        u: 1.0,
        point: DVec2::new(2.0, 1.0),
    }];
    assert!(refine(&c, Similarity::Curvature, &ok).is_ok());
    // Degree 2 has no third derivative to compare.
    assert!(matches!(
        refine(&c, Similarity::Variation, &ok),
        Err(CurveError::Refine(_))
    ));
    let outside = [Constraint::Point {
        u: 1.5,
        point: DVec2::ZERO,
    }];
    assert!(matches!(
        refine(&c, Similarity::Curvature, &outside),
        Err(CurveError::Refine(_))
    ));
    let zero = [Constraint::Tangent {
        u: 0.5,
        direction: DVec2::ZERO,
    }];
    assert!(refine(&c, Similarity::Curvature, &zero).is_err());
    let nan = [Constraint::Point {
        u: 0.5,
        point: DVec2::new(f64::NAN, 0.0),
    }];
    assert!(matches!(
        refine(&c, Similarity::Curvature, &nan),
        Err(CurveError::NotFinite { .. })
    ));
    let join = [Constraint::Join { at: 0, order: 1 }];
    assert!(refine(&c, Similarity::Curvature, &join).is_err());
    // An evenly parameterised straight line has no curvature to keep.
    let line: Curve<DVec2> = Bezier::new(vec![
        DVec2::ZERO,
        DVec2::X,
        DVec2::new(2.0, 0.0),
        DVec2::new(3.0, 0.0),
    ])
    .into();
    assert!(matches!(
        refine(&line, Similarity::Curvature, &ok),
        Err(CurveError::Refine(_))
    ));
    assert!(refine_piecewise(&[], Similarity::Curvature, &ok).is_err());
    let spline: Curve<DVec2> =
        BSpline::clamped_uniform(3, vec![DVec2::ZERO, DVec2::X, DVec2::ONE, DVec2::Y])
            .expect("valid")
            .into();
    assert!(similarity_variables(&c, &spline, Similarity::Curvature).is_err());
}

#[test]
fn derivative_constraints_and_contradictions() {
    let c: Curve<DVec2> = Bezier::new(vec![
        DVec2::ZERO,
        DVec2::new(0.5, 1.0),
        DVec2::new(1.5, 1.2),
        DVec2::new(2.0, 0.2),
    ])
    .into();
    let d = DVec2::new(1.0, 2.5);
    let r = refine(
        &c,
        Similarity::Curvature,
        &[Constraint::Derivative { u: 0.3, vector: d }],
    )
    .expect("refined");
    assert!(
        (nendo::curve::edit::derivative(&r.curve, 0.3, 1).expect("inside") - d).length() < 1e-9
    );
    // Two different points at one parameter: met in the least-squares sense, and reported.
    let clash = [
        Constraint::Point {
            u: 0.5,
            point: DVec2::new(1.0, 1.0),
        },
        Constraint::Point {
            u: 0.5,
            point: DVec2::new(1.0, 2.0),
        },
    ];
    let r = refine(&c, Similarity::Curvature, &clash).expect("refined");
    assert!((r.curve.eval(0.5) - DVec2::new(1.0, 1.5)).length() < 1e-9);
    assert!((r.constraint_residual - 0.5f64.sqrt()).abs() < 1e-9);
}

/// The constraint sets documented in `nendo::curve::refine` ("Which constraints give the similar
/// copy"): in variation mode the two end points alone leave a linear term free and do not give
/// the copy; adding a derivative, both end tangents, or a third point does; in curvature mode a
/// point and a derivative suffice.
#[test]
fn which_constraints_give_the_similar_copy() {
    let mut rng = ChaCha8Rng::seed_from_u64(4242);
    let mut ends_only_missed = 0;
    let mut trials = 0;
    for degree in 3..=7 {
        for _ in 0..6 {
            let c = random_bezier(&mut rng, degree);
            let (a, b) = c.domain();
            let start = c.eval(a);
            let sim = random_similarity(&mut rng, start);
            let turn = |v: DVec2| sim(v) - sim(DVec2::ZERO);
            let copy = map_curve(&c, &sim);
            let (t0, t1) = end_tangents(&c);
            let ends = vec![
                Constraint::Point { u: a, point: start },
                Constraint::Point {
                    u: b,
                    point: sim(c.eval(b)),
                },
            ];
            let gap = |mode, cons: &[Constraint]| {
                let r = refine(&c, mode, cons).expect("refined");
                assert!(r.similarity_rms < 1e-8, "{mode:?} {}", r.similarity_rms);
                max_point_gap(r.curve.points(), copy.points())
            };
            // Variation, end points only: similarity 0, but generally not the copy.
            if gap(Similarity::Variation, &ends) > 1e-6 {
                ends_only_missed += 1;
            }
            // Variation, end points and one derivative.
            let mut with_derivative = ends.clone();
            with_derivative.push(Constraint::Derivative {
                u: a,
                vector: turn(t0),
            });
            assert!(gap(Similarity::Variation, &with_derivative) < 1e-9);
            // Variation, end points and both end tangents.
            let mut with_tangents = ends.clone();
            with_tangents.push(Constraint::Tangent {
                u: a,
                direction: turn(t0),
            });
            with_tangents.push(Constraint::Tangent {
                u: b,
                direction: turn(t1),
            });
            assert!(gap(Similarity::Variation, &with_tangents) < 1e-9);
            // Variation, three points (a random curve is not in uniform motion along a line).
            let mid = 0.5 * (a + b);
            let mut three = ends.clone();
            three.push(Constraint::Point {
                u: mid,
                point: sim(c.eval(mid)),
            });
            assert!(gap(Similarity::Variation, &three) < 1e-8);
            // Curvature: the end points; or one point and one derivative.
            assert!(gap(Similarity::Curvature, &ends) < 1e-9);
            let point_and_derivative = [
                Constraint::Point {
                    u: mid,
                    point: sim(c.eval(mid)),
                },
                Constraint::Derivative {
                    u: b,
                    vector: turn(t1),
                },
            ];
            assert!(gap(Similarity::Curvature, &point_and_derivative) < 1e-9);
            trials += 1;
        }
    }
    // The end points alone miss the copy in (nearly) every random case.
    assert!(
        ends_only_missed * 10 >= trials * 9,
        "{ends_only_missed} of {trials}"
    );
}
