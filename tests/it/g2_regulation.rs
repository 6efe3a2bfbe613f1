//! The `g2` regulation (issue 29): curvature continuity across every regular seam after a
//! stroke, on the plane of the paper's experiment, the sphere and the torus; G1 kept; what
//! is refused rolled back; and its fidelity against `exact`.

use glam::DVec3;
use nendo::surface::continuity::report;
use nendo::surface::curvature::g2_report;
use nendo::surface::deviation::{ideal_samples, samples};
use nendo::surface::{Grid, Op, Primitive, PrimitiveParams, Regulation, deform};

fn primitive(p: Primitive, patches: Option<(usize, usize)>) -> Grid {
    p.build(&PrimitiveParams {
        patches,
        ..PrimitiveParams::default()
    })
    .expect("primitive builds")
}

/// The paper's push (P2 §6): the 10 × 10 plane at (0.5, 0.5, 0), finger radius 1.25 side.
fn paper_push(depth: f64) -> Op {
    Op::Push {
        at: DVec3::new(0.5, 0.5, 0.0),
        dir: -DVec3::Z,
        depth,
        radius: 1.25,
    }
}

fn mean_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (*x - *y).length())
        .sum::<f64>()
        / a.len() as f64
}

#[test]
fn explore() {
    for depth in [0.25, 0.5, 1.0] {
        let base = primitive(Primitive::Plane, Some((10, 10)));
        let op = paper_push(depth);
        let finger = op.finger().unwrap();
        let ideal = ideal_samples(&base, &finger, 20);
        for reg in [Regulation::Exact, Regulation::G2] {
            let mut g = base.clone();
            let t = deform(&mut g, &op, reg).unwrap();
            let g2 = g2_report(&g, 9);
            let c = report(&g, 33);
            println!(
                "plane depth {depth} {reg}: patches {} g2 max rel {:.3e} abs {:.3e} mean {:.3e} g1 {:.3e} dev mean {:.4}",
                t.patches.len(),
                g2.max_relative,
                g2.max_absolute,
                g2.mean_relative,
                c.g1_max_deg,
                mean_distance(&samples(&g, 20), &ideal)
            );
        }
    }
    for p in [Primitive::Sphere, Primitive::Torus] {
        let base = primitive(p, None);
        let g0 = g2_report(&base, 9);
        println!("{p:?} primitive g2 {:.3e}", g0.max_relative);
        let c = base.eval(1, 1, 0.5, 0.5);
        let n = base.normal(1, 1, 0.5, 0.5).unwrap();
        let op = Op::Push {
            at: c,
            dir: -n,
            depth: 0.4,
            radius: 1.0,
        };
        for reg in [Regulation::Exact, Regulation::G2] {
            let mut g = base.clone();
            let r = deform(&mut g, &op, reg);
            let g2 = g2_report(&g, 9);
            println!(
                "{p:?} {reg}: {:?} g2 max rel {:.3e} poles {:?} g1 {:.3e}",
                r.map(|t| t.patches.len()),
                g2.max_relative,
                g2.poles.iter().map(|p| p.relative).collect::<Vec<_>>(),
                report(&g, 33).g1_max_deg
            );
        }
    }
}
