//! `nendo bench closest`: closest-point queries by Bezier clipping against a 1001-sample search
//! and Newton's method from 8 seeds (and any extra baselines a caller supplies — the criterion
//! bench `benches/closest.rs` adds kurbo's `CubicBez::nearest`), on the same random cases in
//! one run: median ns per query, worst distance error against a dense-sampling reference, the
//! clipping-iteration histogram, and picking among 1 000 curves.
//!
//! Case sets (fixed seeds): control points uniform in `[−1,1]^d`; "spread" queries uniform in
//! `[−2,2]^d` (around the curve); "close" queries at `C(u) + δ N`, `|δ| ≤ 0.05` (near it).

use super::reference::sampled_min;
use super::{Stopwatch, Table};
use crate::curve::{Bezier, ClipStats, Curve, CurveSet, Point, closest_bezier_with_stats};
use glam::{DVec2, DVec3};
use std::hint::black_box;

/// A small deterministic generator (SplitMix64), so the library needs no `rand`.
#[derive(Debug, Clone)]
pub struct SplitMix(u64);

impl SplitMix {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
    }
    /// A point with coordinates uniform in `[−s, s)`.
    pub fn point<P: Point>(&mut self, s: f64) -> P {
        let c: Vec<f64> = (0..P::DIM).map(|_| self.range(-s, s)).collect();
        P::from_coords(&c).unwrap_or(P::ZERO)
    }
}

/// One query case with its reference distance.
#[derive(Debug, Clone)]
pub struct Case<P> {
    /// The curve.
    pub curve: Bezier<P>,
    /// The query point.
    pub q: P,
    /// Reference closest distance (dense sampling + golden-section polish).
    pub reference: f64,
}

/// Where the queries lie.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Spread {
    /// Uniform in `[−2,2]^d`, around the curve.
    Around,
    /// Within 0.05 of the curve.
    Close,
}

/// Random cases of the given degree and dimension.
pub fn cases<P: Point>(count: usize, degree: usize, spread: Spread, seed: u64) -> Vec<Case<P>> {
    let mut rng = SplitMix::new(seed);
    (0..count)
        .map(|_| {
            let curve: Bezier<P> = Bezier::new((0..=degree).map(|_| rng.point(1.0)).collect());
            let q: P = match spread {
                Spread::Around => rng.point(2.0),
                Spread::Close => {
                    let u = rng.range(0.0, 1.0);
                    let offset: P = rng.point(1.0);
                    let len = offset.length().max(1e-12);
                    curve.eval(u) + offset * (rng.range(-0.05, 0.05) / len)
                }
            };
            let f = |u: f64| (curve.eval(u) - q).length();
            let (_, reference) = sampled_min(&f, 0.0, 1.0, 2000);
            Case {
                curve,
                q,
                reference,
            }
        })
        .collect()
}

/// The closest distance by sampling `samples + 1` evenly spaced parameters (the paper's
/// "conventional method").
pub fn sampled_distance<P: Point>(c: &Bezier<P>, q: P, samples: usize) -> f64 {
    let mut best = f64::INFINITY;
    for i in 0..=samples {
        let d = (c.eval(i as f64 / samples as f64) - q).length_squared();
        if d < best {
            best = d;
        }
    }
    best.sqrt()
}

/// The closest distance by Newton's method on `g(u) = C'(u)·(C(u) − Q)` from 8 evenly spaced
/// seeds (clamped to `[0,1]`), keeping the best result and the end points.
pub fn newton_distance<P: Point>(c: &Bezier<P>, q: P) -> f64 {
    let d1 = c.hodograph();
    let d2 = d1.hodograph();
    let mut best = (c.eval(0.0) - q)
        .length_squared()
        .min((c.eval(1.0) - q).length_squared());
    for k in 0..8 {
        let mut u = (k as f64 + 0.5) / 8.0;
        for _ in 0..30 {
            let p = c.eval(u) - q;
            let t = d1.eval(u);
            let g = p.dot(t);
            let dg = t.dot(t) + p.dot(d2.eval(u));
            if dg == 0.0 {
                break;
            }
            let next = (u - g / dg).clamp(0.0, 1.0);
            let done = (next - u).abs() < 1e-14;
            u = next;
            if done {
                break;
            }
        }
        let d = (c.eval(u) - q).length_squared();
        if d < best {
            best = d;
        }
    }
    best.sqrt()
}

/// A baseline method supplied by the caller (e.g. kurbo, which the library does not depend on).
pub struct Baseline<'a> {
    /// Name printed in the table.
    pub name: &'a str,
    /// Returns the closest distance for a 2D cubic.
    pub distance: &'a dyn Fn(&Bezier<DVec2>, DVec2) -> f64,
}

/// One measured row.
#[derive(Debug, Clone)]
pub struct Row {
    /// Case set and method.
    pub label: String,
    /// Median ns per query.
    pub ns: f64,
    /// Worst `(d − d_ref)/max(d_ref, 1)` (positive: the method missed the reference minimum).
    pub max_error: f64,
}

fn measure<P: Point>(
    label: String,
    cases: &[Case<P>],
    batches: usize,
    f: &dyn Fn(&Bezier<P>, P) -> f64,
) -> Row {
    let mut max_error = 0.0f64;
    for c in cases {
        let d = f(&c.curve, c.q);
        max_error = max_error.max((d - c.reference) / c.reference.max(1.0));
    }
    let sw = Stopwatch {
        batches,
        calls_per_batch: cases.len(),
    };
    let ns = sw.median_ns(|k| {
        let c = &cases[k % cases.len()];
        black_box(f(black_box(&c.curve), black_box(c.q)));
    });
    Row {
        label,
        ns,
        max_error,
    }
}

fn clip_distance<P: Point>(c: &Bezier<P>, q: P) -> f64 {
    closest_bezier_with_stats(c, q, f64::INFINITY, &mut ClipStats::default())
        .map_or(f64::INFINITY, |n| n.distance)
}

fn histogram<P: Point>(cases: &[Case<P>]) -> (Vec<usize>, f64, f64) {
    let mut h = vec![0usize; 12];
    let mut total = ClipStats::default();
    for c in cases {
        let mut s = ClipStats::default();
        let _ = closest_bezier_with_stats(&c.curve, c.q, f64::INFINITY, &mut s);
        h[(s.clips as usize).min(11)] += 1;
        total.add(s);
    }
    let n = cases.len().max(1) as f64;
    (h, total.clips as f64 / n, total.newton as f64 / n)
}

/// Runs the suite and returns the report. `scale` multiplies the case counts (1.0: 2 000 cases
/// per set).
pub fn report(scale: f64, baselines: &[Baseline<'_>]) -> String {
    let count = ((2000.0 * scale) as usize).max(50);
    let batches = 11;
    let spread2: Vec<Case<DVec2>> = cases(count, 3, Spread::Around, 1);
    let close2: Vec<Case<DVec2>> = cases(count, 3, Spread::Close, 2);
    let spread3: Vec<Case<DVec3>> = cases(count, 3, Spread::Around, 3);
    let nonic: Vec<Case<DVec2>> = cases(count, 9, Spread::Around, 4);
    let nonic3: Vec<Case<DVec3>> = cases(count, 9, Spread::Around, 5);

    let mut rows: Vec<Row> = Vec::new();
    let clip2 = measure(
        "2D cubic, spread: Bezier clipping".into(),
        &spread2,
        batches,
        &clip_distance,
    );
    let clip2c = measure(
        "2D cubic, close:  Bezier clipping".into(),
        &close2,
        batches,
        &clip_distance,
    );
    rows.push(clip2.clone());
    let mut ratios = Vec::new();
    for b in baselines {
        let r = measure(
            format!("2D cubic, spread: {}", b.name),
            &spread2,
            batches,
            b.distance,
        );
        ratios.push(format!(
            "2D cubic spread: clipping / {} = {:.2} (target ≤ 0.5)",
            b.name,
            clip2.ns / r.ns
        ));
        rows.push(r);
    }
    let s1001 = measure(
        "2D cubic, spread: 1001-sample search".into(),
        &spread2,
        batches,
        &|c, q| sampled_distance(c, q, 1000),
    );
    let newton = measure(
        "2D cubic, spread: Newton from 8 seeds".into(),
        &spread2,
        batches,
        &|c, q| newton_distance(c, q),
    );
    rows.push(s1001.clone());
    rows.push(newton);
    rows.push(clip2c.clone());
    for b in baselines {
        let r = measure(
            format!("2D cubic, close:  {}", b.name),
            &close2,
            batches,
            b.distance,
        );
        ratios.push(format!(
            "2D cubic close: clipping / {} = {:.2} (target ≤ 0.7)",
            b.name,
            clip2c.ns / r.ns
        ));
        rows.push(r);
    }
    rows.push(measure(
        "2D cubic, close:  1001-sample search".into(),
        &close2,
        batches,
        &|c, q| sampled_distance(c, q, 1000),
    ));
    let clip3 = measure(
        "3D cubic, spread: Bezier clipping".into(),
        &spread3,
        batches,
        &clip_distance,
    );
    rows.push(clip3.clone());
    rows.push(measure(
        "3D cubic, spread: 1001-sample search".into(),
        &spread3,
        batches,
        &|c, q| sampled_distance(c, q, 1000),
    ));
    rows.push(measure(
        "3D cubic, spread: Newton from 8 seeds".into(),
        &spread3,
        batches,
        &|c, q| newton_distance(c, q),
    ));
    let clip9 = measure(
        "2D degree 9, spread: Bezier clipping".into(),
        &nonic,
        batches,
        &clip_distance,
    );
    rows.push(clip9.clone());
    let s9 = measure(
        "2D degree 9, spread: 1001-sample search".into(),
        &nonic,
        batches,
        &|c, q| sampled_distance(c, q, 1000),
    );
    rows.push(s9.clone());
    rows.push(measure(
        "2D degree 9, spread: Newton from 8 seeds".into(),
        &nonic,
        batches,
        &|c, q| newton_distance(c, q),
    ));
    rows.push(measure(
        "3D degree 9, spread: Bezier clipping".into(),
        &nonic3,
        batches,
        &clip_distance,
    ));

    // Picking among 1 000 curves scattered over a 40 × 40 square.
    let mut rng = SplitMix::new(6);
    let curves: Vec<Curve<DVec2>> = (0..1000)
        .map(|_| {
            let centre = DVec2::new(rng.range(0.0, 40.0), rng.range(0.0, 40.0));
            Curve::Bezier(Bezier::new(
                (0..4).map(|_| centre + rng.point::<DVec2>(1.0)).collect(),
            ))
        })
        .collect();
    let set = CurveSet::new(&curves);
    let queries: Vec<DVec2> = (0..count)
        .map(|_| DVec2::new(rng.range(0.0, 40.0), rng.range(0.0, 40.0)))
        .collect();
    let pick_ns = Stopwatch {
        batches,
        calls_per_batch: queries.len(),
    }
    .median_ns(|k| {
        black_box(set.pick(black_box(queries[k % queries.len()]), f64::INFINITY));
    });

    let mut t = Table::new(&[
        "case: method",
        "ns/query (median)",
        "max error vs reference",
    ]);
    for r in &rows {
        t.row(vec![
            r.label.clone(),
            format!("{:.0}", r.ns),
            format!("{:.1e}", r.max_error),
        ]);
    }
    t.row(vec![
        "pick among 1 000 2D cubics (CurveSet)".into(),
        format!("{pick_ns:.0}"),
        "-".into(),
    ]);
    let mut out = format!(
        "nendo bench closest — {count} random cases per set, medians of {batches} batches\n\n"
    );
    out.push_str(&t.render());
    out.push('\n');
    for r in ratios {
        out.push_str(&r);
        out.push('\n');
    }
    out.push_str(&format!(
        "3D cubic clipping: {:.0} ns/query (target ≤ 200)\n",
        clip3.ns
    ));
    out.push_str(&format!(
        "pick among 1 000 / one 2D query = {:.1} (target ≤ 20)\n",
        pick_ns / clip2.ns
    ));
    out.push_str(&format!(
        "speed-up over the 1001-sample search (parameter precision 1e-3; clipping runs to ~1e-12): cubic {:.0}×, degree 9 {:.0}× (paper: ~100× at 1e-3)\n",
        s1001.ns / clip2.ns,
        s9.ns / clip9.ns
    ));
    for (name, set) in [("2D cubic, spread", &spread2), ("2D cubic, close", &close2)] {
        let (h, mean_clips, mean_newton) = histogram(set);
        out.push_str(&format!(
            "clipping iterations, {name}: mean {mean_clips:.2} (+ {mean_newton:.2} Newton steps); histogram 1..11+: {:?}\n",
            &h[1..]
        ));
    }
    let (h, mean_clips, _) = histogram(&nonic);
    out.push_str(&format!(
        "clipping iterations, degree 9: mean {mean_clips:.2}; histogram 1..11+: {:?}\n",
        &h[1..]
    ));
    out
}
