//! Random curves for property tests, from a seeded ChaCha generator: the same seed gives the
//! same cases on every machine.

use nendo::curve::{BSpline, Bezier, Curve, Point};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// A point with every coordinate uniform in `(-scale, scale)`.
pub fn point<P: Point>(rng: &mut ChaCha8Rng, scale: f64) -> P {
    let c: Vec<f64> = (0..P::DIM).map(|_| rng.gen_range(-scale..scale)).collect();
    P::from_coords(&c).expect("DIM coordinates")
}

/// A Bezier curve of `degree` with control points in the unit box.
pub fn bezier<P: Point>(rng: &mut ChaCha8Rng, degree: usize) -> Curve<P> {
    Curve::Bezier(Bezier::new((0..=degree).map(|_| point(rng, 1.0)).collect()))
}

/// A clamped or unclamped B-spline of `degree` with random knots in `[0, 1]` (sometimes a
/// repeated interior knot) and control points in the unit box.
pub fn bspline<P: Point>(rng: &mut ChaCha8Rng, degree: usize) -> Curve<P> {
    loop {
        let n = degree + 1 + rng.gen_range(0..5);
        let mut knots: Vec<f64> = (0..n + degree + 1)
            .map(|_| rng.gen_range(0.0..1.0))
            .collect();
        knots.sort_by(f64::total_cmp);
        if rng.gen_bool(0.5) {
            for k in knots.iter_mut().take(degree + 1) {
                *k = 0.0;
            }
            for k in knots.iter_mut().skip(n) {
                *k = 1.0;
            }
        }
        if rng.gen_bool(0.3) && n > degree + 1 {
            knots[degree + 2] = knots[degree + 1];
        }
        let pts = (0..n).map(|_| point(rng, 1.0)).collect();
        if let Ok(s) = BSpline::try_new(degree, knots, pts) {
            return Curve::BSpline(s);
        }
    }
}

/// A Bezier curve (70 %) or a B-spline of degree `min(degree, 6)` (30 %).
pub fn curve<P: Point>(rng: &mut ChaCha8Rng, degree: usize) -> Curve<P> {
    if rng.gen_bool(0.3) {
        bspline(rng, degree.min(6))
    } else {
        bezier(rng, degree)
    }
}
