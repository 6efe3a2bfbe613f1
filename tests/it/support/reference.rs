//! Independent references for the curve queries: dense sampling of the curve followed by a
//! golden-section polish of every sampled local minimum (`nendo_bench::reference`). Nothing
//! here uses Bezier clipping.

#![allow(dead_code)]

use nendo::curve::{Curve, Point};

pub use nendo_bench::reference::sampled_min;

/// Reference closest distance from `q` to the curve.
pub fn closest<P: Point>(c: &Curve<P>, q: P) -> (f64, f64) {
    let (lo, hi) = c.domain();
    let mut best = (f64::NAN, f64::INFINITY);
    for seg in c.segments().iter() {
        let f = |u: f64| (seg.bezier.eval(u) - q).length();
        let (u, d) = sampled_min(&f, 0.0, 1.0, 2000);
        if d < best.1 {
            best = (seg.to_global(u), d);
        }
    }
    let _ = (lo, hi);
    best
}

/// Distance from `x` to the ray `o + s d`, `s ≥ 0`.
pub fn point_ray_distance<P: Point>(x: P, o: P, d: P) -> f64 {
    let s = ((x - o).dot(d) / d.dot(d)).max(0.0);
    (x - (o + d * s)).length()
}

/// Reference ray distance.
pub fn ray<P: Point>(c: &Curve<P>, o: P, d: P) -> (f64, f64) {
    let mut best = (f64::NAN, f64::INFINITY);
    for seg in c.segments().iter() {
        let f = |u: f64| point_ray_distance(seg.bezier.eval(u), o, d);
        let (u, v) = sampled_min(&f, 0.0, 1.0, 2000);
        if v < best.1 {
            best = (seg.to_global(u), v);
        }
    }
    best
}

/// Reference sphere intervals: sign of `|C(u) − Q|² − R²` on a dense grid over the domain,
/// each sign change polished by bisection. Also returns the smallest `|e|` at the sampled
/// local extrema, to let callers skip near-tangent (ambiguous) cases.
pub fn sphere<P: Point>(c: &Curve<P>, q: P, r: f64, samples: usize) -> (Vec<(f64, f64)>, f64) {
    let (lo, hi) = c.domain();
    let e = |u: f64| (c.eval(u) - q).length_squared() - r * r;
    let us: Vec<f64> = (0..=samples)
        .map(|i| lo + (hi - lo) * i as f64 / samples as f64)
        .collect();
    let es: Vec<f64> = us.iter().map(|&u| e(u)).collect();
    let mut ambiguity = f64::INFINITY;
    for i in 1..samples {
        let ext = (es[i] <= es[i - 1] && es[i] <= es[i + 1])
            || (es[i] >= es[i - 1] && es[i] >= es[i + 1]);
        if ext {
            ambiguity = ambiguity.min(es[i].abs());
        }
    }
    ambiguity = ambiguity.min(es[0].abs()).min(es[samples].abs());
    let mut out: Vec<(f64, f64)> = Vec::new();
    let mut start = if es[0] <= 0.0 { Some(lo) } else { None };
    for i in 0..samples {
        let (a, b) = (es[i], es[i + 1]);
        if (a <= 0.0) != (b <= 0.0) {
            let (mut x0, mut x1) = (us[i], us[i + 1]);
            for _ in 0..200 {
                let m = 0.5 * (x0 + x1);
                if (e(m) <= 0.0) == (a <= 0.0) {
                    x0 = m;
                } else {
                    x1 = m;
                }
            }
            let root = 0.5 * (x0 + x1);
            if a <= 0.0 {
                out.push((start.take().unwrap_or(lo), root));
            } else {
                start = Some(root);
            }
        }
    }
    if let Some(s) = start {
        out.push((s, hi));
    }
    (out, ambiguity)
}
