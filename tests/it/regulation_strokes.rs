//! The default regulation after 10 000 random strokes on each topology: G1 to within 0.01°
//! on every shared edge and at every pole, no NaN, poles still single points, seams closed.
//! (About a second per topology in release mode; the same figures for every method are in
//! `nendo bench regulation`.)

use nendo::surface::{Primitive, Regulation};
use nendo_bench::regulation::random_strokes;

#[test]
fn ten_thousand_random_strokes_keep_the_default_method_g1_on_every_topology() {
    let strokes = if cfg!(debug_assertions) {
        1_000
    } else {
        10_000
    };
    for p in [
        Primitive::Plane,
        Primitive::Cylinder,
        Primitive::Hemisphere,
        Primitive::Sphere,
        Primitive::Torus,
    ] {
        let r = random_strokes(p, Regulation::Exact, strokes, 2024);
        println!(
            "{p:>10}: {strokes} strokes, {:.1} µs/stroke, G0 {:.1e}, G1 max {:.3e}°, mean {:.3e}°, no normal at {}, pole spread {:.3e}°",
            r.mean_us,
            r.g0_gap,
            r.g1_max_deg,
            r.g1_mean_deg,
            r.undefined_normals,
            r.pole_spread_deg
        );
        assert!(r.finite, "{p}: NaN or infinity");
        assert!(r.poles_degenerate, "{p}: a pole came apart");
        assert_eq!(r.g0_gap, 0.0, "{p}: a seam opened");
        assert!(r.g1_max_deg <= 0.01, "{p}: G1 max {}", r.g1_max_deg);
        assert!(
            r.pole_spread_deg <= 0.01,
            "{p}: pole spread {}",
            r.pole_spread_deg
        );
    }
}
