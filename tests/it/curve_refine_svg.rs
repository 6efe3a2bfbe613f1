//! SVG import and export of planar curves (the paper's working format, P3 §3.1): exact
//! round trips, the path grammar (relative commands, reflections, implicit repeats, closing),
//! refusals, and the paper's workflow — read a curve from SVG, refine it, write it back.

use glam::DVec2;
use nendo::curve::refine::{Constraint, Similarity, refine_piecewise};
use nendo::curve::svg::{SvgError, SvgOptions, parse_path_data, path_data, read_svg, write_svg};
use nendo::curve::{BSpline, Bezier, Curve};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn rp(rng: &mut ChaCha8Rng) -> DVec2 {
    DVec2::new(rng.gen_range(-1e3..1e3), rng.gen_range(-1e3..1e3)) * rng.gen_range(1e-6..1.0)
}

#[test]
fn written_curves_read_back_bit_for_bit() {
    let mut rng = ChaCha8Rng::seed_from_u64(9101);
    for _ in 0..200 {
        let mut curves: Vec<Curve<DVec2>> = Vec::new();
        for _ in 0..rng.gen_range(1..4) {
            if rng.gen_bool(0.3) {
                let pts = (0..rng.gen_range(4..8)).map(|_| rp(&mut rng)).collect();
                curves.push(BSpline::clamped_uniform(3, pts).expect("valid").into());
            } else {
                let degree = rng.gen_range(1..=3);
                curves.push(Bezier::new((0..=degree).map(|_| rp(&mut rng)).collect()).into());
            }
        }
        let flip = rng.gen_bool(0.5);
        let text = write_svg(
            &curves,
            SvgOptions {
                flip_y: flip,
                ..SvgOptions::default()
            },
        )
        .expect("degrees ≤ 3");
        let paths = read_svg(&text).expect("readable");
        assert_eq!(paths.len(), curves.len());
        for (p, c) in paths.iter().zip(&curves) {
            let want: Vec<Bezier<DVec2>> = c.segments().iter().map(|s| s.bezier.clone()).collect();
            assert_eq!(p.segments.len(), want.len());
            for (a, b) in p.segments.iter().zip(&want) {
                let b: Vec<DVec2> = b
                    .points()
                    .iter()
                    .map(|q| if flip { DVec2::new(q.x, -q.y) } else { *q })
                    .collect();
                if matches!(c, Curve::Bezier(_)) {
                    assert_eq!(a.points(), &b[..]);
                } else {
                    // A B-spline's segments are joined exactly on the way out (their shared
                    // points can differ by a rounding).
                    for (x, y) in a.points().iter().zip(&b) {
                        assert!((*x - *y).length() <= 1e-12 * y.length().max(1.0));
                    }
                }
            }
        }
    }
}

#[test]
fn the_path_grammar() {
    // Relative moves and lines, H/V, implicit repeats after M, numbers run together.
    let p = parse_path_data("m1,1 2,0 h-1 v2.5e0 l-.5-.5 z").expect("valid");
    assert_eq!(p.len(), 1);
    assert!(p[0].closed);
    let ends: Vec<DVec2> = p[0]
        .segments
        .iter()
        .map(|s| s.points()[s.degree()])
        .collect();
    assert_eq!(
        ends,
        vec![
            DVec2::new(3.0, 1.0),
            DVec2::new(2.0, 1.0),
            DVec2::new(2.0, 3.5),
            DVec2::new(1.5, 3.0),
            DVec2::new(1.0, 1.0)
        ]
    );
    // Quadratic smooth continuation reflects the control point.
    let q = parse_path_data("M0 0 Q1 1 2 0 T4 0").expect("valid");
    assert_eq!(
        q[0].segments[1].points(),
        &[
            DVec2::new(2.0, 0.0),
            DVec2::new(3.0, -1.0),
            DVec2::new(4.0, 0.0)
        ]
    );
    // S after a non-cubic uses the current point as first control point.
    let s = parse_path_data("M0 0 L1 0 S2 1 3 0").expect("valid");
    assert_eq!(s[0].segments[1].points()[1], DVec2::new(1.0, 0.0));
    // Two subpaths; a drawing command after Z starts a new one at the closing point.
    let two = parse_path_data("M0 0 L1 0 L1 1 Z L5 5 M9 9 c1 0 1 1 0 1").expect("valid");
    assert_eq!(two.len(), 3);
    assert_eq!(
        two[1].segments[0].points(),
        &[DVec2::ZERO, DVec2::new(5.0, 5.0)]
    );
    assert_eq!(two[2].segments[0].points()[3], DVec2::new(9.0, 10.0));
    // A document with comments, other elements and single quotes.
    let doc = "<svg><!-- <path d='M 9 9 L 0 0'/> --><rect x='0'/><path id='a' d='M0 0 C0 1 1 1 1 0'/><g><path\n d=\"M 2 2 L 3 3\"/></g></svg>";
    let paths = read_svg(doc).expect("valid");
    assert_eq!(paths.len(), 2);
    assert_eq!(paths[0].segments[0].degree(), 3);
}

#[test]
fn what_svg_cannot_hold_is_refused() {
    for bad in [
        "L 1 1",
        "M 0 0 A 1 1 0 0 1 2 2",
        "M 0 0 L 1",
        "M 0 0 X 1 1",
        "M 0 0 L 1 1e999",
    ] {
        let e = parse_path_data(bad).expect_err(bad);
        assert!(
            matches!(
                e,
                SvgError::Data(_) | SvgError::Arc | SvgError::NoMove | SvgError::NotFinite { .. }
            ),
            "{bad}: {e}"
        );
    }
    assert!(read_svg("<path id='x'/>").is_err());
    let quartic = Bezier::new(vec![
        DVec2::ZERO,
        DVec2::X,
        DVec2::ONE,
        DVec2::Y,
        DVec2::ZERO,
    ]);
    assert!(matches!(
        path_data(std::slice::from_ref(&quartic), false),
        Err(SvgError::Degree {
            index: 0,
            degree: 4
        })
    ));
    assert!(write_svg(&[quartic.into()], SvgOptions::default()).is_err());
    assert_eq!(read_svg("<svg></svg>").expect("no paths"), vec![]);
}

#[test]
fn refine_a_curve_read_from_svg_and_write_it_back() {
    // The paper's loop: a two-segment C1 cubic from a drawing tool, its end pulled up.
    let doc = r#"<svg xmlns="http://www.w3.org/2000/svg"><path d="M 0 0 C 10 40 40 50 50 50 S 90 40 100 0"/></svg>"#;
    let paths = read_svg(doc).expect("valid");
    let segs = &paths[0].segments;
    assert_eq!(segs.len(), 2);
    let start = segs[0].points()[0];
    let end = DVec2::new(90.0, 30.0);
    let cons = [
        Constraint::Point {
            u: 0.0,
            point: start,
        },
        Constraint::Point { u: 2.0, point: end },
    ];
    let r = refine_piecewise(segs, Similarity::Curvature, &cons).expect("refined");
    assert!(
        r.similarity_rms < 1e-9,
        "a similar copy exists: {}",
        r.similarity_rms
    );
    let out = path_data(&r.curve, false).expect("cubic");
    let back = parse_path_data(&out).expect("valid");
    assert_eq!(back[0].segments, r.curve);
    assert!((back[0].segments[1].points()[3] - end).length() < 1e-9);
}
