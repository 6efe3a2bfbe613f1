//! Curve editing (P0 §3, P4 §3(2)): derivative weights against independent derivatives,
//! grabs that carry the grabbed point exactly (every method, Bezier and B-spline, 2D and 3D,
//! degrees 1–9), the least-change grab's optimality, split, tangent edit, insertion.

use crate::support::random;
use glam::{DVec2, DVec3};
use nendo::curve::edit::{
    Follow, Grab, GrabMethod, GrabOptions, JointSide, control_weights, derivative, grab,
    insert_control_point, joint, move_joint, split, tangent_edit,
};
use nendo::curve::{Bezier, Curve, CurveError, Point};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn random_curve<P: Point>(rng: &mut ChaCha8Rng) -> Curve<P> {
    if rng.gen_bool(0.5) {
        let d = rng.gen_range(1..=9);
        random::bezier(rng, d)
    } else {
        let d = rng.gen_range(1..=5);
        random::bspline(rng, d)
    }
}

fn random_u<P: Point>(rng: &mut ChaCha8Rng, c: &Curve<P>) -> f64 {
    let (a, b) = c.domain();
    a + rng.gen_range(0.0..=1.0) * (b - a)
}

/// `C^{(k)}(u)` from the Bezier segment holding `u`, by the curve core's hodographs, rescaled to
/// the B-spline's parameter: an independent reference for [`derivative`].
fn reference_derivative<P: Point>(c: &Curve<P>, u: f64, k: usize) -> P {
    let segs = c.segments();
    let seg = segs
        .iter()
        .find(|s| u <= s.end)
        .unwrap_or(&segs[segs.len() - 1]);
    let h = seg.end - seg.start;
    seg.bezier.eval_derivative((u - seg.start) / h, k) * (1.0 / h.powi(k as i32))
}

#[test]
fn derivative_weights_match_the_hodographs() {
    let mut rng = ChaCha8Rng::seed_from_u64(8001);
    for _ in 0..400 {
        let c: Curve<DVec3> = random_curve(&mut rng);
        let u = random_u(&mut rng, &c);
        let w = control_weights(&c, u, 0).expect("inside");
        assert!(
            (w.iter().sum::<f64>() - 1.0).abs() < 1e-12,
            "partition of unity"
        );
        assert!((derivative(&c, u, 0).expect("inside") - c.eval(u)).length() < 1e-12);
        for k in 1..=3 {
            let got = derivative(&c, u, k).expect("inside");
            let want = reference_derivative(&c, u, k);
            assert!(
                (got - want).length() <= 1e-9 * want.length().max(1.0),
                "k={k}: {got} vs {want}"
            );
        }
    }
    let c: Curve<DVec2> = random::bezier(&mut rng, 3);
    assert!(matches!(
        control_weights(&c, 1.5, 0),
        Err(CurveError::OutOfDomain { .. })
    ));
    assert!(control_weights(&c, f64::NAN, 0).is_err());
}

fn grab_case<P: Point>(rng: &mut ChaCha8Rng) -> usize {
    let c: Curve<P> = random_curve(rng);
    let u = random_u(rng, &c);
    let delta: P = random::point(rng, 0.5);
    let mut done = 0;
    for method in [
        GrabMethod::LargestWeight,
        GrabMethod::NearestParameter,
        GrabMethod::LeastChange,
    ] {
        for keep_ends in [false, true] {
            let options = GrabOptions { method, keep_ends };
            let g = match Grab::new(&c, u, options) {
                Ok(g) => g,
                Err(e) => {
                    // Refused only when no movable point carries C(u).
                    assert!(keep_ends && matches!(e, CurveError::Edit(_)), "{e}");
                    continue;
                }
            };
            let moved = g.moved_by(delta).expect("finite");
            let want = c.eval(u) + delta;
            let gain = g.factors().iter().map(|f| f.1.abs()).fold(1.0, f64::max);
            assert!(
                (moved.eval(u) - want).length() <= 1e-12 * gain.max(1.0),
                "{method:?}: {}",
                (moved.eval(u) - want).length()
            );
            let changed: Vec<usize> = (0..c.points().len())
                .filter(|&k| moved.points()[k] != c.points()[k])
                .collect();
            let w = control_weights(&c, u, 0).expect("inside");
            let last = w.len() - 1;
            if keep_ends {
                assert!(!changed.contains(&0) && !changed.contains(&last));
            }
            match method {
                GrabMethod::LargestWeight => {
                    assert_eq!(changed.len(), 1);
                    let k = changed[0];
                    let best = (0..w.len())
                        .filter(|&j| !keep_ends || (j != 0 && j != last))
                        .map(|j| w[j])
                        .fold(0.0, f64::max);
                    assert_eq!(w[k], best);
                }
                GrabMethod::NearestParameter => assert_eq!(changed.len(), 1),
                GrabMethod::LeastChange => {
                    // The moves are proportional to the weights: ΔP_k = B_k ΔP / Σ B_j².
                    let sum: f64 = (0..w.len())
                        .filter(|&j| !keep_ends || (j != 0 && j != last))
                        .map(|j| w[j] * w[j])
                        .sum();
                    for (k, wk) in w.iter().enumerate() {
                        let d = moved.points()[k] - c.points()[k];
                        let movable = !keep_ends || (k != 0 && k != last);
                        let want = if movable { delta * (wk / sum) } else { P::ZERO };
                        assert!((d - want).length() < 1e-12 * (1.0 / sum).max(1.0));
                    }
                }
            }
            done += 1;
        }
    }
    done
}

#[test]
fn grabs_carry_the_grabbed_point_exactly() {
    let mut rng = ChaCha8Rng::seed_from_u64(8002);
    let mut done = 0;
    for _ in 0..300 {
        done += grab_case::<DVec2>(&mut rng);
        done += grab_case::<DVec3>(&mut rng);
    }
    assert!(done > 3000, "{done}");
}

#[test]
fn least_change_beats_every_other_exact_move() {
    let mut rng = ChaCha8Rng::seed_from_u64(8003);
    for _ in 0..200 {
        let c: Curve<DVec3> = random_curve(&mut rng);
        let u = random_u(&mut rng, &c);
        let delta: DVec3 = random::point(&mut rng, 1.0);
        let opts = |method| GrabOptions {
            method,
            keep_ends: false,
        };
        let least = grab(&c, u, delta, opts(GrabMethod::LeastChange)).expect("movable");
        let change = |m: &Curve<DVec3>| -> f64 {
            m.points()
                .iter()
                .zip(c.points())
                .map(|(a, b)| (*a - *b).length_squared())
                .sum()
        };
        let single = grab(&c, u, delta, opts(GrabMethod::LargestWeight)).expect("movable");
        assert!(change(&least) <= change(&single) * (1.0 + 1e-12));
        // Any other exact move: the least one plus a move of the control points that keeps C(u).
        let w = control_weights(&c, u, 0).expect("inside");
        let extra: Vec<DVec3> = (0..w.len()).map(|_| random::point(&mut rng, 0.3)).collect();
        let carried = extra
            .iter()
            .zip(&w)
            .fold(DVec3::ZERO, |a, (e, w)| a + *e * *w);
        let wsum: f64 = w.iter().map(|x| x * x).sum();
        let pts: Vec<DVec3> = least
            .points()
            .iter()
            .zip(&extra)
            .zip(&w)
            .map(|((p, e), wk)| *p + *e - carried * (wk / wsum))
            .collect();
        let other = nendo::curve::edit::with_points(&c, pts).expect("same kind");
        assert!((other.eval(u) - least.eval(u)).length() < 1e-9);
        assert!(change(&least) <= change(&other) + 1e-12);
    }
}

#[test]
fn seed_000_picks_the_control_point_of_the_nearest_parameter() {
    // "For a cubic grabbed at u = 0.25, P1 (u = 0.33) is chosen."
    let c: Curve<DVec2> = Bezier::new(vec![DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::ONE]).into();
    let g = Grab::new(
        &c,
        0.25,
        GrabOptions {
            method: GrabMethod::NearestParameter,
            keep_ends: false,
        },
    )
    .expect("ok");
    assert_eq!(g.factors()[0].0, 1);
    let g = Grab::new(
        &c,
        0.1,
        GrabOptions {
            method: GrabMethod::NearestParameter,
            keep_ends: false,
        },
    )
    .expect("ok");
    assert_eq!(g.factors()[0].0, 0);
    let g = Grab::new(
        &c,
        0.1,
        GrabOptions {
            method: GrabMethod::NearestParameter,
            keep_ends: true,
        },
    )
    .expect("ok");
    assert_eq!(g.factors()[0].0, 1);
    // At an end with the ends kept, nothing can move the point.
    assert!(matches!(
        Grab::new(
            &c,
            0.0,
            GrabOptions {
                keep_ends: true,
                ..GrabOptions::default()
            }
        ),
        Err(CurveError::Edit(_))
    ));
    let line: Curve<DVec2> = Bezier::new(vec![DVec2::ZERO, DVec2::X]).into();
    assert!(
        Grab::new(
            &line,
            0.5,
            GrabOptions {
                keep_ends: true,
                ..GrabOptions::default()
            }
        )
        .is_err()
    );
}

#[test]
fn grabbing_at_a_point_uses_the_closest_point() {
    let c: Curve<DVec2> = Bezier::new(vec![
        DVec2::ZERO,
        DVec2::new(1.0, 2.0),
        DVec2::new(2.0, 0.0),
    ])
    .into();
    let from = DVec2::new(1.0, 1.3);
    let g = Grab::at_point(&c, from, 1.0, GrabOptions::default())
        .expect("ok")
        .expect("near");
    let moved = g
        .moved_to(g.start() + DVec2::new(0.2, 0.4))
        .expect("finite");
    assert!((moved.eval(g.u()) - g.start() - DVec2::new(0.2, 0.4)).length() < 1e-12);
    assert!(
        Grab::at_point(&c, DVec2::new(10.0, 10.0), 1.0, GrabOptions::default())
            .expect("ok")
            .is_none()
    );
}

#[test]
fn split_halves_trace_the_curve() {
    let mut rng = ChaCha8Rng::seed_from_u64(8004);
    for _ in 0..200 {
        let c: Curve<DVec3> = random_curve(&mut rng);
        let (a, b) = c.domain();
        let u = a + rng.gen_range(0.05..0.95) * (b - a);
        let (l, r) = split(&c, u).expect("inside");
        assert_eq!(l.points()[l.points().len() - 1], r.points()[0]);
        assert!((l.eval(l.domain().1) - c.eval(u)).length() < 1e-12);
        for i in 0..=10 {
            let s = i as f64 / 10.0;
            let (la, lb) = l.domain();
            let (ra, rb) = r.domain();
            // Bezier halves are reparameterised to [0,1]; B-spline halves keep the parameter.
            let (lu, cu_l) = match c {
                Curve::Bezier(_) => (s, s * u),
                Curve::BSpline(_) => (la + s * (lb - la), la + s * (lb - la)),
            };
            let (ru, cu_r) = match c {
                Curve::Bezier(_) => (s, u + s * (1.0 - u)),
                Curve::BSpline(_) => (ra + s * (rb - ra), ra + s * (rb - ra)),
            };
            assert!((l.eval(lu) - c.eval(cu_l)).length() < 1e-12);
            assert!((r.eval(ru) - c.eval(cu_r)).length() < 1e-12);
        }
        assert!(split(&c, a).is_err() && split(&c, b).is_err());
    }
}

#[test]
fn tangent_edit_keeps_the_joint_collinear() {
    let mut rng = ChaCha8Rng::seed_from_u64(8005);
    for _ in 0..200 {
        let c: Curve<DVec3> = {
            let d = rng.gen_range(2..=9);
            random::bezier(&mut rng, d)
        };
        let t = rng.gen_range(0.1..0.9);
        let (l, r) = split(&c, t).expect("inside");
        let (ql, q, qr) = joint(&l, &r).expect("a joint");
        for side in [JointSide::Left, JointSide::Right] {
            for follow in [Follow::KeepLength, Follow::KeepRatio] {
                let target = q + random::point::<DVec3>(&mut rng, 1.0);
                let (nl, nr) = tangent_edit(&l, &r, side, target, follow).expect("edit");
                let (nql, nq, nqr) = joint(&nl, &nr).expect("still a joint");
                assert_eq!(nq, q);
                assert_eq!(if side == JointSide::Left { nql } else { nqr }, target);
                // Collinear, on opposite sides of Q.
                let (a, b) = (nq - nql, nqr - nq);
                assert!(a.cross(b).length() <= 1e-12 * a.length() * b.length());
                assert!(a.dot(b) > 0.0);
                match follow {
                    Follow::KeepLength => {
                        let (other_new, other_old) = if side == JointSide::Left {
                            (b, qr - q)
                        } else {
                            (a, q - ql)
                        };
                        assert!((other_new.length() - other_old.length()).abs() < 1e-12);
                    }
                    Follow::KeepRatio => {
                        // The split of a curve at t is C1 in the original parameter:
                        // (Q − Q_L)/t = (Q_R − Q)/(1 − t), and stays so.
                        assert!(
                            (a / t - b / (1.0 - t)).length() < 1e-9 * (a / t).length().max(1.0)
                        );
                    }
                }
                // Only the two neighbours moved.
                assert_eq!(
                    &nl.points()[..nl.points().len() - 2],
                    &l.points()[..l.points().len() - 2]
                );
                assert_eq!(&nr.points()[2..], &r.points()[2..]);
            }
        }
        assert!(tangent_edit(&l, &r, JointSide::Left, q, Follow::KeepLength).is_err());
        assert!(matches!(joint(&r, &l), Err(CurveError::Edit(_))));
        let moved = q + DVec3::new(0.1, -0.2, 0.3);
        let (ml, mr) = move_joint(&l, &r, moved).expect("joint");
        let (a, m, b) = joint(&ml, &mr).expect("joint");
        assert_eq!(m, moved);
        assert!(
            (a - (ql + (moved - q))).length() < 1e-12 && (b - (qr + (moved - q))).length() < 1e-12
        );
    }
}

#[test]
fn split_bsplines_have_joints_too() {
    let mut rng = ChaCha8Rng::seed_from_u64(8006);
    let c = loop {
        let c: Curve<DVec2> = random::bspline(&mut rng, 3);
        if let Curve::BSpline(s) = &c
            && s.knots()[0] == s.knots()[3]
            && s.points().len() > 4
        {
            break c;
        }
    };
    let (a, b) = c.domain();
    let (l, r) = split(&c, 0.5 * (a + b)).expect("inside");
    let (_, q, _) = joint(&l, &r).expect("clamped halves meet at a control point");
    let (nl, nr) = tangent_edit(
        &l,
        &r,
        JointSide::Right,
        q + DVec2::new(0.3, 0.1),
        Follow::KeepLength,
    )
    .expect("edit");
    assert!((nl.eval(nl.domain().1) - nr.eval(nr.domain().0)).length() < 1e-12);
}

#[test]
fn inserting_a_control_point_keeps_the_curve() {
    let mut rng = ChaCha8Rng::seed_from_u64(8007);
    for _ in 0..100 {
        let c: Curve<DVec2> = if rng.gen_bool(0.5) {
            {
                let d = rng.gen_range(1..=8);
                random::bezier(&mut rng, d)
            }
        } else {
            random::bspline(&mut rng, 3)
        };
        let u = random_u(&mut rng, &c);
        let (new, k) = match insert_control_point(&c, u) {
            Ok(x) => x,
            Err(e) => {
                assert!(matches!(e, CurveError::KnotMultiplicity { .. }), "{e}");
                continue;
            }
        };
        assert_eq!(new.points().len(), c.points().len() + 1);
        let w = control_weights(&new, u, 0).expect("inside");
        assert!(w.iter().all(|&x| x <= w[k]));
        let (a, b) = c.domain();
        for i in 0..=20 {
            let s = a + (b - a) * i as f64 / 20.0;
            assert!((new.eval(s) - c.eval(s)).length() < 1e-12);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    /// A grab carries the grabbed point exactly, whatever the cubic and the move.
    #[test]
    fn grabbed_point_follows(
        pts in prop::collection::vec((-10.0f64..10.0, -10.0f64..10.0, -10.0f64..10.0), 4),
        u in 0.0f64..=1.0,
        d in (-5.0f64..5.0, -5.0f64..5.0, -5.0f64..5.0),
        least in any::<bool>(),
    ) {
        let c: Curve<DVec3> = Bezier::new(pts.iter().map(|&(x, y, z)| DVec3::new(x, y, z)).collect()).into();
        let method = if least { GrabMethod::LeastChange } else { GrabMethod::LargestWeight };
        let delta = DVec3::new(d.0, d.1, d.2);
        let moved = grab(&c, u, delta, GrabOptions { method, keep_ends: false }).expect("movable");
        prop_assert!((moved.eval(u) - (c.eval(u) + delta)).length() < 1e-11);
    }
}

#[test]
fn edited_curves_round_trip_through_the_model_file() {
    use nendo::curve::json::DynCurve;
    use nendo::model::Model;
    use nendo::surface::{Primitive, PrimitiveParams};
    let mut rng = ChaCha8Rng::seed_from_u64(8008);
    let grid = Primitive::Plane
        .build(&PrimitiveParams {
            patches: Some((2, 2)),
            ..PrimitiveParams::default()
        })
        .expect("plane");
    let mut model = Model::new(grid);
    for _ in 0..20 {
        let c3: Curve<DVec3> = random_curve(&mut rng);
        let u = random_u(&mut rng, &c3);
        let delta: DVec3 = random::point(&mut rng, 0.5);
        let options = GrabOptions {
            method: GrabMethod::LeastChange,
            keep_ends: false,
        };
        model
            .curves
            .push(DynCurve::D3(grab(&c3, u, delta, options).expect("movable")));
        let c2: Curve<DVec2> = random_curve(&mut rng);
        let (a, b) = c2.domain();
        let (l, r) = split(&c2, 0.5 * (a + b)).expect("inside");
        model.curves.push(DynCurve::D2(l));
        model.curves.push(DynCurve::D2(r));
    }
    let text = model.to_json_string();
    let back = Model::from_json_str(&text).expect("readable").model;
    assert_eq!(back.curves, model.curves);
}
