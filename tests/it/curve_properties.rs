//! Property tests (proptest) for the Bernstein and curve identities the queries rely on:
//! subdivision and restriction reproduce the curve, degree elevation keeps it, derivatives match
//! finite differences, the product formula multiplies, B-spline segments and knot insertion
//! keep the curve.

use glam::{DVec2, DVec3};
use nendo::curve::bernstein::{self, derivative, elevate, eval, product, restrict, subdivide};
use nendo::curve::{BSpline, Bezier};
use proptest::prelude::*;

fn coords() -> impl Strategy<Value = f64> {
    -10.0..10.0f64
}

fn points3(max: usize) -> impl Strategy<Value = Vec<DVec3>> {
    prop::collection::vec(
        (coords(), coords(), coords()).prop_map(|(x, y, z)| DVec3::new(x, y, z)),
        1..=max,
    )
}

fn scale(p: &[DVec3]) -> f64 {
    p.iter().fold(1.0, |m, q| m.max(q.abs().max_element()))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn subdivision_reproduces_both_halves(p in points3(10), t in 0.0..1.0f64, s in 0.0..1.0f64) {
        let (l, r) = subdivide(&p, t);
        let tol = 1e-12 * scale(&p);
        prop_assert!((eval(&l, s) - eval(&p, s * t)).length() <= tol);
        prop_assert!((eval(&r, s) - eval(&p, t + s * (1.0 - t))).length() <= tol);
        // The halves meet at C(t).
        prop_assert!((l[l.len() - 1] - r[0]).length() <= tol);
    }

    #[test]
    fn restriction_is_reparameterisation(p in points3(10), a in 0.0..1.0f64, w in 0.0..1.0f64, s in 0.0..1.0f64) {
        let b = a + (1.0 - a) * w;
        let r = restrict(&p, a, b);
        prop_assert!((eval(&r, s) - eval(&p, a + s * (b - a))).length() <= 1e-11 * scale(&p));
    }

    #[test]
    fn elevation_keeps_the_curve(p in points3(10), s in 0.0..1.0f64) {
        let e = elevate(&p);
        prop_assert_eq!(e.len(), p.len() + 1);
        prop_assert!((eval(&e, s) - eval(&p, s)).length() <= 1e-12 * scale(&p));
    }

    #[test]
    fn derivative_matches_finite_differences(p in points3(10), s in 0.01..0.99f64) {
        let h = 1e-6;
        let d = eval(&derivative(&p), s);
        let fd = (eval(&p, s + h) - eval(&p, s - h)) / (2.0 * h);
        // Central differences: error O(h²·C''') plus rounding O(eps·|C|/h).
        let n = p.len() as f64;
        prop_assert!((d - fd).length() <= 1e-6 * scale(&p) * n * n * n, "{d:?} vs {fd:?}");
        // Second derivative too.
        let d2 = eval(&bernstein::derivative_k(&p, 2), s);
        let fd2 = (eval(&derivative(&p), s + h) - eval(&derivative(&p), s - h)) / (2.0 * h);
        prop_assert!((d2 - fd2).length() <= 1e-5 * scale(&p) * n * n * n * n);
    }

    #[test]
    fn product_formula_multiplies(a in prop::collection::vec(coords(), 1..8), b in prop::collection::vec(coords(), 1..8), s in 0.0..1.0f64) {
        let h = product(&a, &b, |x, y| x * y);
        let want = eval(&a, s) * eval(&b, s);
        prop_assert!((eval(&h, s) - want).abs() <= 1e-11 * 100.0);
    }

    #[test]
    fn fast_scalar_evaluation_agrees(c in prop::collection::vec(coords(), 1..20), s in 0.0..1.0f64) {
        prop_assert!((bernstein::eval_scalar_fast(&c, s) - eval(&c, s)).abs() <= 1e-11 * 10.0);
    }

    #[test]
    fn bezier_split_matches(p in points3(10), t in 0.0..1.0f64) {
        let c = Bezier::new(p.clone());
        let (l, r) = c.split(t);
        prop_assert!((l.eval(1.0) - c.eval(t)).length() <= 1e-12 * scale(&p));
        prop_assert!((r.eval(0.0) - c.eval(t)).length() <= 1e-12 * scale(&p));
    }

    #[test]
    fn bspline_segments_and_knot_insertion_keep_the_curve(
        degree in 1usize..=5,
        extra in 0usize..6,
        seed_knots in prop::collection::vec(0.0..1.0f64, 20),
        pts in prop::collection::vec((coords(), coords()).prop_map(|(x, y)| DVec2::new(x, y)), 12),
        at in 0.0..1.0f64,
        s in 0.0..1.0f64,
    ) {
        let n = degree + 1 + extra;
        let mut knots: Vec<f64> = seed_knots[..n + degree + 1].to_vec();
        knots.sort_by(f64::total_cmp);
        let Ok(spline) = BSpline::try_new(degree, knots, pts[..n].to_vec()) else { return Ok(()) };
        let (a, b) = spline.domain();
        let u = a + s * (b - a);
        let tol = 1e-9 * 10.0;
        // Segments.
        for seg in spline.to_bezier_segments() {
            let v = seg.to_global(s);
            prop_assert!((seg.bezier.eval(s) - spline.eval(v)).length() <= tol);
        }
        // Knot insertion.
        let t = a + at * (b - a);
        if let Ok(ins) = spline.insert_knot(t) {
            prop_assert!((ins.eval(u) - spline.eval(u)).length() <= tol);
        }
        // Split.
        if t > a && t < b {
            let (l, r) = spline.split(t).expect("inside the domain");
            let probe = if u <= t { l.eval(u) } else { r.eval(u) };
            prop_assert!((probe - spline.eval(u)).length() <= tol);
        }
    }
}
