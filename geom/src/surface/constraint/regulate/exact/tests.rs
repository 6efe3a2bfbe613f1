//! Tests of the exact regulation: the group projection, the coupled solve and its factor
//! cache, the pole.

use glam::DVec3;

use super::{regulate_group, regulate_pole};
use crate::surface::grid::Grid;
use crate::surface::group::Group;
use crate::surface::regulate::{GroupPoints, PolePoints};

fn noisy_group(seed: u64) -> GroupPoints {
    let mut u = crate::seeded::unit(seed);
    let mut r = move || u() - 0.5;
    let mut p = [[None; 3]; 3];
    for s in 0..3 {
        for t in 0..3 {
            let base = DVec3::new(s as f64 * 0.33, t as f64 * 0.33, 0.0);
            p[s][t] = Some(if (s, t) == (1, 1) {
                base
            } else {
                base + DVec3::new(r(), r(), r()) * 0.2
            });
        }
    }
    p
}

#[test]
fn rows_get_the_reference_ratio() {
    for seed in 0..30 {
        let (ru, rv) = (0.7 + 0.02 * seed as f64, 1.3 - 0.01 * seed as f64);
        let mut p = noisy_group(seed);
        assert!(regulate_group(&mut p, (ru, rv)));
        let g = |s: usize, t: usize| p[s][t].unwrap();
        for k in 0..3 {
            assert!((ru * g(0, k) - (1.0 + ru) * g(1, k) + g(2, k)).length() < 1e-14);
            assert!((rv * g(k, 0) - (1.0 + rv) * g(k, 1) + g(k, 2)).length() < 1e-14);
        }
    }
}

/// `∫|ΔS|²` over the four patches around the vertex, by dense quadrature of the patches
/// built from the group's nodes (the other nodes of each patch unchanged: zero change).
fn surface_change(a: &GroupPoints, b: &GroupPoints) -> f64 {
    let n = 48;
    let mut sum = 0.0;
    for (qs, qt) in [(0usize, 0usize), (2, 0), (0, 2), (2, 2)] {
        let d = |s: usize, t: usize| a[s][t].unwrap() - b[s][t].unwrap();
        let (d00, d10, d01, d11) = (d(1, 1), d(qs, 1), d(1, qt), d(qs, qt));
        for i in 0..n {
            for j in 0..n {
                let (u, v) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                let (b0u, b1u) = ((1.0 - u).powi(3), 3.0 * u * (1.0 - u).powi(2));
                let (b0v, b1v) = ((1.0 - v).powi(3), 3.0 * v * (1.0 - v).powi(2));
                let ds =
                    d00 * (b0u * b0v) + d10 * (b1u * b0v) + d01 * (b0u * b1v) + d11 * (b1u * b1v);
                sum += ds.length_squared();
            }
        }
    }
    sum / (n * n) as f64
}

#[test]
fn the_fit_is_nearest_in_the_surface_metric() {
    // Any other member of the family (vertex, a, b, c perturbed) changes the surface more.
    let (ru, rv) = (0.8, 1.2);
    let orig = noisy_group(4);
    let mut p = orig;
    regulate_group(&mut p, (ru, rv));
    let best = surface_change(&p, &orig);
    let su = [-1.0, 0.0, ru];
    let tv = [-1.0, 0.0, rv];
    let o = p[1][1].unwrap();
    let a = (p[2][1].unwrap() - o) / ru;
    let b = (p[1][2].unwrap() - o) / rv;
    let c = (p[2][2].unwrap() - o - a * ru - b * rv) / (ru * rv);
    for k in 0..8 {
        let e = DVec3::new(1e-3 * (k as f64).cos(), 1e-3 * (k as f64).sin(), -1e-3);
        let pick = |i: usize| if k % 4 == i { e } else { DVec3::ZERO };
        let mut q = p;
        for s in 0..3 {
            for t in 0..3 {
                q[s][t] = Some(
                    o + pick(0)
                        + (a + pick(1)) * su[s]
                        + (b + pick(2)) * tv[t]
                        + (c + pick(3)) * (su[s] * tv[t]),
                );
            }
        }
        assert!(surface_change(&q, &orig) > best, "{k}");
    }
}

/// `Σ_p ∫|S_a − S_b|²` over every patch, by midpoint quadrature (independent of the
/// Gram matrices the projection uses).
fn grid_change(a: &Grid, b: &Grid) -> f64 {
    let n = 24;
    let mut sum = 0.0;
    for p in 0..a.patch_count() {
        let (pa, pb) = (a.patch_struct(p), b.patch_struct(p));
        for i in 0..n {
            for j in 0..n {
                let (u, v) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                sum += (pa.eval(u, v) - pb.eval(u, v)).length_squared();
            }
        }
    }
    sum / (n * n) as f64
}

#[test]
fn the_coupled_projection_is_g1_local_and_nearest_in_the_surface_metric() {
    use crate::surface::{Op, Primitive, PrimitiveParams, Regulation, Sculptor};
    for (prim, at, dir) in [
        (Primitive::Plane, DVec3::new(0.3, 0.6, 0.0), -DVec3::Z),
        (
            Primitive::Sphere,
            DVec3::new(2.0, 1.0, 1.5),
            DVec3::new(-2.0, -1.0, -1.5),
        ),
        (Primitive::Torus, DVec3::new(4.0, 0.0, 0.0), -DVec3::X),
    ] {
        let base = prim.build(&PrimitiveParams::default()).unwrap();
        let op = Op::Push {
            at,
            dir,
            depth: 0.4,
            radius: 1.1,
        };
        let mut unreg = base.clone();
        let touched = Sculptor::new()
            .apply(&mut unreg, &op, Regulation::None)
            .unwrap();
        let mut got = base.clone();
        let t = Sculptor::new()
            .apply(&mut got, &op, Regulation::Exact)
            .unwrap();
        assert!(t.deformed == touched.deformed && t.deformed > 0, "{prim}");
        assert!(
            crate::surface::continuity::report(&got, 33).g1_max_deg < 1e-9,
            "{prim}"
        );
        // Nothing beyond the patches listed moved.
        for p in 0..base.patch_count() {
            if !t.patches.contains(&p) {
                assert_eq!(got.patch_at(p), base.patch_at(p), "{prim} {p}");
            }
        }
        // Nearest: moving any regulated group along its family changes the surface more.
        let best = grid_change(&got, &unreg);
        let groups: Vec<Group> = got
            .groups()
            .into_iter()
            .filter(|g| {
                g.patch_count() >= 2
                    && g.nodes
                        .iter()
                        .flatten()
                        .flatten()
                        .any(|&id| got.nodes()[id] != unreg.nodes()[id])
            })
            .collect();
        assert!(!groups.is_empty(), "{prim}");
        for (gi, g) in groups.iter().enumerate().step_by(3) {
            let su = [-1.0, 0.0, g.ratios.0];
            let tv = [-1.0, 0.0, g.ratios.1];
            let which = gi % 4;
            let e = DVec3::new(1e-3, -2e-3, 1.5e-3);
            let mut q = got.clone();
            let nodes = q.nodes_mut();
            for s in 0..3 {
                for t in 0..3 {
                    if let Some(id) = g.nodes[s][t] {
                        let f = [1.0, su[s], tv[t], su[s] * tv[t]][which];
                        nodes[id] += e * f;
                    }
                }
            }
            let worse = grid_change(&q, &unreg);
            assert!(
                worse > best,
                "{prim} group {:?}: {worse} vs {best}",
                g.vertex
            );
        }
    }
}

#[test]
fn a_reused_factor_gives_the_fresh_solve() {
    // The same push shifted by whole patches has the same normal matrix: the second
    // solve reuses the first's factor and must agree with a fresh sculptor's.
    use crate::surface::{Op, Primitive, PrimitiveParams, Regulation, Sculptor};
    let base = Primitive::Plane
        .build(&PrimitiveParams {
            patches: Some((10, 10)),
            ..PrimitiveParams::default()
        })
        .unwrap();
    let push = |x: f64, y: f64, depth: f64| Op::Push {
        at: DVec3::new(x, y, 0.0),
        dir: DVec3::new(0.1, -0.05, -1.0),
        depth,
        radius: 1.1,
    };
    let mut warm = Sculptor::new();
    let mut scratch = base.clone();
    warm.apply(&mut scratch, &push(-1.7, 0.4, 0.3), Regulation::Exact)
        .unwrap();
    for (x, y, depth) in [(0.3, 0.4, 0.5), (1.3, -1.6, -0.2), (-1.7, 0.4, 0.7)] {
        let op = push(x, y, depth);
        let mut reused = base.clone();
        warm.apply(&mut reused, &op, Regulation::Exact).unwrap();
        let mut fresh = base.clone();
        Sculptor::new()
            .apply(&mut fresh, &op, Regulation::Exact)
            .unwrap();
        for (a, b) in reused.nodes().iter().zip(fresh.nodes()) {
            assert!((*a - *b).length() < 1e-13, "{x} {y}: {a} vs {b}");
        }
    }
}

#[test]
fn a_regulated_pole_has_a_tangent_plane() {
    let len = 24;
    let mut u = crate::seeded::unit(9u64);
    let mut r = move || u() - 0.5;
    let ring: Vec<DVec3> = (0..len)
        .map(|a| {
            let phi = std::f64::consts::TAU * a as f64 / len as f64;
            DVec3::new(phi.cos(), phi.sin(), 0.4 * phi.cos() + 0.1)
                + DVec3::new(r(), r(), r()) * 0.1
        })
        .collect();
    let mut p = PolePoints {
        pole: DVec3::new(0.0, 0.0, 0.05),
        ring,
    };
    let ratios = vec![1.0; len / 3];
    assert!(regulate_pole(&mut p, &ratios));
    let n = crate::surface::plane_fit::plane_normal(p.ring.iter().map(|x| *x - p.pole)).unwrap();
    for x in &p.ring {
        assert!(n.dot(*x - p.pole).abs() < 1e-14);
    }
    for k in 0..len / 3 {
        let a = 3 * k as isize;
        let at = |i: isize| p.ring[i.rem_euclid(len as isize) as usize];
        assert!((at(a - 1) - 2.0 * at(a) + at(a + 1)).length() < 1e-14);
    }
}
