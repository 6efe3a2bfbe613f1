//! The closest-point query's fast paths (the seed neighbourhood examined first, the bracketed
//! Newton finish, pruning by the bound and by Descartes' rule) against the independent
//! reference of `support::reference` (dense sampling and golden section, no clipping), on
//! random cases with fixed seeds: queries close to the curve, queries near a centre of
//! curvature (a near-double root of the distance's derivative), minima at the edges of the
//! seed's neighbourhood, and ties between two equally close points.

use crate::support::random;
use crate::support::reference;
use glam::{DVec2, DVec3};
use nendo::curve::{Bezier, Curve, Point, closest_bezier};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// 1e-9 of the distance, or of the curve's unit scale where the distance is below one.
fn tol(d: f64) -> f64 {
    1e-9 * d.max(1.0)
}

fn random_bezier<P: Point>(rng: &mut ChaCha8Rng, degree: usize) -> Bezier<P> {
    Bezier::new((0..=degree).map(|_| random::point::<P>(rng, 1.0)).collect())
}

/// Checks one query against the reference: the distance within `tol` of the reference
/// minimum (never above it by more), the point on the curve at the reported parameter.
fn check<P: Point>(c: &Bezier<P>, q: P, what: &str) {
    let curve = Curve::Bezier(c.clone());
    let (u_ref, d_ref) = reference::closest(&curve, q);
    let n = closest_bezier(c, q, f64::INFINITY)
        .unwrap_or_else(|| panic!("{what}: no answer for {c:?} q {q:?}"));
    assert!(
        n.distance <= d_ref + tol(d_ref),
        "{what}: {c:?} q {q:?}: got {} at u {}, reference {d_ref} at u {u_ref}",
        n.distance,
        n.u
    );
    assert!(
        n.distance >= d_ref - 1e-6 * d_ref.max(1.0),
        "{what}: reference missed a minimum"
    );
    assert!(
        (c.eval(n.u) - n.point).length() < 1e-12,
        "{what}: point off the curve"
    );
    assert!(((n.point - q).length() - n.distance).abs() < 1e-12);
    // Deterministic: the same query gives the same answer.
    assert_eq!(closest_bezier(c, q, f64::INFINITY), Some(n));
}

/// The centre of curvature at `u` (2D): `C + N/κ`, `N` the left unit normal, `κ` signed.
fn curvature_centre_2d(c: &Bezier<DVec2>, u: f64) -> Option<DVec2> {
    let d1 = c.eval_derivative(u, 1);
    let d2 = c.eval_derivative(u, 2);
    let cross = d1.x * d2.y - d1.y * d2.x;
    let speed = d1.length();
    if speed < 1e-3 || cross.abs() < 1e-9 {
        return None;
    }
    let kappa = cross / speed.powi(3);
    let normal = DVec2::new(-d1.y, d1.x) / speed;
    Some(c.eval(u) + normal / kappa)
}

/// The centre of curvature at `u` (3D): `C + N/κ` with `N` the part of `C''` normal to `C'`.
fn curvature_centre_3d(c: &Bezier<DVec3>, u: f64) -> Option<DVec3> {
    let d1 = c.eval_derivative(u, 1);
    let d2 = c.eval_derivative(u, 2);
    let speed = d1.length();
    if speed < 1e-3 {
        return None;
    }
    let kappa = d1.cross(d2).length() / speed.powi(3);
    let t = d1 / speed;
    let normal = d2 - t * d2.dot(t);
    if kappa < 1e-9 || normal.length() < 1e-12 {
        return None;
    }
    Some(c.eval(u) + normal.normalize() / kappa)
}

#[test]
fn close_queries_match_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0f15);
    for case in 0..1500 {
        let degree = 2 + case % 8;
        let u = rng.gen_range(0.0..1.0);
        let delta = rng.gen_range(-0.05..0.05) * 10f64.powi(-(case as i32 % 4));
        if case % 2 == 0 {
            let c: Bezier<DVec2> = random_bezier(&mut rng, degree);
            let off: DVec2 = random::point(&mut rng, 1.0);
            let q = c.eval(u) + off.normalize_or_zero() * delta;
            check(&c, q, &format!("2D close case {case}"));
        } else {
            let c: Bezier<DVec3> = random_bezier(&mut rng, degree);
            let off: DVec3 = random::point(&mut rng, 1.0);
            let q = c.eval(u) + off.normalize_or_zero() * delta;
            check(&c, q, &format!("3D close case {case}"));
        }
    }
}

#[test]
fn queries_near_a_centre_of_curvature_match_reference() {
    // At the centre of curvature the distance's derivative has a double root: the hardest
    // case for root isolation, and for the Newton finish.
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0f16);
    let mut checked = 0;
    for case in 0..1500 {
        let degree = 2 + case % 8;
        let u = rng.gen_range(0.02..0.98);
        let eps = rng.gen_range(-1e-3..1e-3) * 10f64.powi(-(case as i32 % 5));
        if case % 2 == 0 {
            let c: Bezier<DVec2> = random_bezier(&mut rng, degree);
            if let Some(centre) = curvature_centre_2d(&c, u) {
                let q = c.eval(u) + (centre - c.eval(u)) * (1.0 + eps);
                check(&c, q, &format!("2D curvature case {case}"));
                checked += 1;
            }
        } else {
            let c: Bezier<DVec3> = random_bezier(&mut rng, degree);
            if let Some(centre) = curvature_centre_3d(&c, u) {
                let q = c.eval(u) + (centre - c.eval(u)) * (1.0 + eps);
                check(&c, q, &format!("3D curvature case {case}"));
                checked += 1;
            }
        }
    }
    assert!(
        checked > 1400,
        "only {checked} cases had a centre of curvature"
    );
}

#[test]
fn spread_queries_of_every_degree_match_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0f17);
    for case in 0..2000 {
        let degree = 1 + case % 12;
        let spread = [0.5, 2.0, 10.0][case % 3];
        if case % 2 == 0 {
            let c: Bezier<DVec2> = random_bezier(&mut rng, degree);
            let q: DVec2 = random::point(&mut rng, spread);
            check(&c, q, &format!("2D spread case {case}"));
        } else {
            let c: Bezier<DVec3> = random_bezier(&mut rng, degree);
            let q: DVec3 = random::point(&mut rng, spread);
            check(&c, q, &format!("3D spread case {case}"));
        }
    }
}

#[test]
fn ties_between_two_equally_close_points() {
    // Curves symmetric about the y axis, queries on the axis: the two halves' minima are
    // equally close (up to rounding), and either is a right answer.
    let mut rng = ChaCha8Rng::seed_from_u64(0x5eed_0f18);
    for case in 0..800 {
        let half = 1 + case % 4;
        let mut pts: Vec<DVec2> = (0..=half)
            .map(|i| {
                let x = -1.0 + i as f64 / (half as f64 + 0.5) + rng.gen_range(-0.2..0.2);
                DVec2::new(x.min(-0.05), rng.gen_range(-1.0..1.0))
            })
            .collect();
        let mirror: Vec<DVec2> = pts.iter().rev().map(|p| DVec2::new(-p.x, p.y)).collect();
        if case % 2 == 0 {
            // Odd degree: the mirrored halves meet.
            pts.extend(mirror);
        } else {
            // Even degree: a middle point on the axis.
            pts.push(DVec2::new(0.0, rng.gen_range(-1.0..1.0)));
            pts.extend(mirror);
        }
        let c = Bezier::new(pts);
        let q = DVec2::new(0.0, rng.gen_range(-2.0..2.0));
        check(&c, q, &format!("tie case {case}"));
    }
}
