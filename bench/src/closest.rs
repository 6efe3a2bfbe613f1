//! `nendo bench closest`: closest-point queries by Bezier clipping against a 1001-sample search
//! and Newton's method from 8 seeds (and any extra baselines a caller supplies — the criterion
//! bench `benches/closest.rs` adds kurbo's `CubicBez::nearest`), on the same random cases in
//! one run: median ns per query, worst distance and parameter errors against an independent
//! reference (dense sampling, golden section, Newton polish), the clipping-iteration
//! histogram, the probe-sphere and ray queries, and picking among 1 000 curves.
//!
//! Fairness: every method gets its inputs built before timing ([`Prepared`]; a baseline's
//! own curve type included) and answers them in a monomorphic loop; the methods of a case set
//! run interleaved, round after round ([`interleaved`]), and ratios are medians of per-round
//! ratios, so that load from other processes falls on both sides alike. The criterion bench
//! uses the same case sets ([`SEEDS`], [`case_count`]).
//!
//! Case sets (fixed seeds): control points uniform in `[−1,1]^d`; "spread" queries uniform in
//! `[−2,2]^d` (around the curve); "close" queries at `C(u) + δ N`, `|δ| ≤ 0.05` (near it).

use super::reference::sampled_min;
use super::rng::Seeded;
use super::{Table, median};
use glam::{DVec2, DVec3};
use nendo::curve::{
    Bezier, ClipStats, Curve, CurveSet, Point, closest_bezier, closest_bezier_with_stats,
    ray_closest_bezier, sphere_intervals_bezier,
};
use std::hint::black_box;
use std::time::Instant;

/// One query case with its reference distance.
#[derive(Debug, Clone)]
pub struct ClosestCase<P> {
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
pub fn cases<P: Point>(
    count: usize,
    degree: usize,
    spread: Spread,
    seed: u64,
) -> Vec<ClosestCase<P>> {
    let mut rng = Seeded::new(seed);
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
            ClosestCase {
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

/// One batch of prepared queries: every call answers all its cases once. The loop over the
/// cases is monomorphic (no per-query indirection); only the batch is called through `dyn`.
pub trait Batch {
    /// Answers every case once (results through `black_box`); returns the number of queries.
    fn run(&self) -> usize;
    /// `(u, distance)` for every case, for the accuracy columns (not timed).
    fn answers(&self) -> Vec<(f64, f64)>;
}

/// Queries whose inputs were built before any timing, answered by `query`.
pub struct Prepared<T, F> {
    inputs: Vec<T>,
    query: F,
}

impl<T, F: Fn(&T) -> (f64, f64)> Prepared<T, F> {
    /// The prepared inputs and the query that answers one of them with `(u, distance)`.
    pub fn new(inputs: Vec<T>, query: F) -> Self {
        Self { inputs, query }
    }
}

impl<T, F: Fn(&T) -> (f64, f64)> Batch for Prepared<T, F> {
    #[inline(never)]
    fn run(&self) -> usize {
        for x in &self.inputs {
            black_box((self.query)(black_box(x)));
        }
        self.inputs.len()
    }
    fn answers(&self) -> Vec<(f64, f64)> {
        self.inputs.iter().map(&self.query).collect()
    }
}

/// A method compared with clipping on the 2D cubic cases, supplied by the caller (e.g. kurbo,
/// which the library does not depend on). It builds its own inputs for the cases outside the
/// timed loop, exactly as the clipping side gets its curves and queries ready-made.
pub trait Baseline {
    /// Name printed in the table.
    fn name(&self) -> &str;
    /// The prepared batch for these cases.
    fn prepare<'a>(&'a self, cases: &[ClosestCase<DVec2>]) -> Box<dyn Batch + 'a>;
}

/// The clipping query on prepared cases: `closest_bezier(curve, q, ∞)`, as in the criterion
/// bench.
pub fn clipping_batch<P: Point>(cases: &[ClosestCase<P>]) -> Box<dyn Batch> {
    let inputs: Vec<(Bezier<P>, P)> = cases.iter().map(|c| (c.curve.clone(), c.q)).collect();
    Box::new(Prepared::new(inputs, |(c, q): &(Bezier<P>, P)| {
        closest_bezier(c, *q, f64::INFINITY)
            .map_or((f64::NAN, f64::INFINITY), |n| (n.u, n.distance))
    }))
}

/// Rounds of interleaved timing: in every round each batch runs once (the order rotating from
/// round to round), so that load on a shared machine falls on all of them alike. Times are the
/// measuring thread's CPU time where Linux reports it (time spent descheduled by other
/// processes is not counted), else wall time. Returns, per batch, the ns per query of every
/// round (one warm-up round is discarded).
pub fn interleaved(batches: &[&dyn Batch], rounds: usize) -> Vec<Vec<f64>> {
    let k = batches.len();
    let mut out = vec![Vec::with_capacity(rounds); k];
    let cpu = super::sculpt::thread_cpu_ns().is_some();
    for round in 0..=rounds {
        for j in 0..k {
            let i = (j + round) % k;
            let start = Instant::now();
            let cpu0 = super::sculpt::thread_cpu_ns().unwrap_or(0);
            let n = batches[i].run();
            let elapsed = if cpu {
                super::sculpt::thread_cpu_ns()
                    .unwrap_or(0)
                    .saturating_sub(cpu0) as f64
            } else {
                start.elapsed().as_nanos() as f64
            };
            let ns = elapsed / n.max(1) as f64;
            if round > 0 {
                out[i].push(ns);
            }
        }
    }
    out
}

/// One measured row.
#[derive(Debug, Clone)]
pub struct Row {
    /// Case set and method.
    pub label: String,
    /// Median ns per query over the rounds.
    pub ns: f64,
    /// Lowest and highest round.
    pub range: (f64, f64),
    /// Worst `(d − d_ref)/max(d_ref, 1)` (positive: the method missed the reference minimum).
    pub max_error: f64,
    /// Worst `|u − u_ref|` over the cases whose reference minimum is unique (no other local
    /// minimum within 1e-6 of its distance), or NaN when the method reports no parameter.
    pub max_u_error: f64,
}

/// The local minima of `|C(u) − Q|` on `[0,1]`, independent of clipping: 2 001 samples, a
/// golden-section polish of every sampled local minimum, then Newton steps on
/// `g = C'·(C − Q)` (derivatives by de Casteljau on the hodographs) to bring each parameter to
/// rounding. Sorted by distance, best first.
pub fn reference_minima<P: Point>(c: &Bezier<P>, q: P) -> Vec<(f64, f64)> {
    let f = |u: f64| (c.eval(u) - q).length();
    let samples = 2000;
    let vs: Vec<f64> = (0..=samples)
        .map(|i| f(i as f64 / samples as f64))
        .collect();
    let d1 = c.hodograph();
    let d2 = d1.hodograph();
    let mut out: Vec<(f64, f64)> = Vec::new();
    for i in 0..=samples {
        let left = if i == 0 { f64::INFINITY } else { vs[i - 1] };
        let right = if i == samples {
            f64::INFINITY
        } else {
            vs[i + 1]
        };
        if !(vs[i] <= left && vs[i] <= right) {
            continue;
        }
        let lo = i.saturating_sub(1) as f64 / samples as f64;
        let hi = (i + 1).min(samples) as f64 / samples as f64;
        let (mut u, _) = super::reference::golden(&f, lo, hi);
        for _ in 0..8 {
            let p = c.eval(u) - q;
            let t = d1.eval(u);
            let dg = t.dot(t) + p.dot(d2.eval(u));
            if dg <= 0.0 {
                break;
            }
            let next = u - p.dot(t) / dg;
            if !(lo..=hi).contains(&next) {
                break;
            }
            u = next;
        }
        let d = f(u);
        let (u, d) = if f(0.0) <= d && i == 0 {
            (0.0, f(0.0))
        } else if f(1.0) <= d && i == samples {
            (1.0, f(1.0))
        } else {
            (u, d)
        };
        out.push((u, d));
    }
    out.sort_by(|a, b| a.1.total_cmp(&b.1));
    out
}

fn accuracy<P: Point>(
    cases: &[ClosestCase<P>],
    minima: &[Vec<(f64, f64)>],
    answers: &[(f64, f64)],
) -> (f64, f64) {
    let mut max_error = 0.0f64;
    let mut max_u = 0.0f64;
    for ((c, m), &(u, d)) in cases.iter().zip(minima).zip(answers) {
        max_error = max_error.max((d - c.reference) / c.reference.max(1.0));
        let unique = m.len() < 2 || m[1].1 - m[0].1 > 1e-6 * m[0].1.max(1.0);
        if unique && !m.is_empty() {
            max_u = max_u.max((u - m[0].0).abs());
        }
    }
    (max_error, max_u)
}

/// Times the batches interleaved and turns them into rows (accuracy against `cases`).
fn rows_for<P: Point>(
    cases: &[ClosestCase<P>],
    minima: &[Vec<(f64, f64)>],
    named: &[(String, &dyn Batch, bool)],
    rounds: usize,
) -> (Vec<Row>, Vec<Vec<f64>>) {
    let batches: Vec<&dyn Batch> = named.iter().map(|(_, b, _)| *b).collect();
    let times = interleaved(&batches, rounds);
    let rows = named
        .iter()
        .zip(&times)
        .map(|((label, b, has_u), t)| {
            let (max_error, max_u) = accuracy(cases, minima, &b.answers());
            let mut sorted = t.clone();
            let ns = median(&mut sorted);
            Row {
                label: label.clone(),
                ns,
                range: (sorted[0], sorted[sorted.len() - 1]),
                max_error,
                max_u_error: if *has_u { max_u } else { f64::NAN },
            }
        })
        .collect();
    (rows, times)
}

/// Median over rounds of the per-round ratio `a/b` (both measured in the same round).
fn round_ratio(a: &[f64], b: &[f64]) -> f64 {
    let mut r: Vec<f64> = a.iter().zip(b).map(|(x, y)| x / y).collect();
    median(&mut r)
}

fn sampled_batch<P: Point>(cases: &[ClosestCase<P>]) -> Box<dyn Batch> {
    let inputs: Vec<(Bezier<P>, P)> = cases.iter().map(|c| (c.curve.clone(), c.q)).collect();
    Box::new(Prepared::new(inputs, |(c, q): &(Bezier<P>, P)| {
        (f64::NAN, sampled_distance(c, *q, 1000))
    }))
}

fn newton_batch<P: Point>(cases: &[ClosestCase<P>]) -> Box<dyn Batch> {
    let inputs: Vec<(Bezier<P>, P)> = cases.iter().map(|c| (c.curve.clone(), c.q)).collect();
    Box::new(Prepared::new(inputs, |(c, q): &(Bezier<P>, P)| {
        (f64::NAN, newton_distance(c, *q))
    }))
}

fn histogram<P: Point>(cases: &[ClosestCase<P>]) -> (Vec<usize>, f64, f64, f64) {
    let mut h = vec![0usize; 12];
    let mut total = ClipStats::default();
    for c in cases {
        let mut s = ClipStats::default();
        let _ = closest_bezier_with_stats(&c.curve, c.q, f64::INFINITY, &mut s);
        h[(s.clips as usize).min(11)] += 1;
        total.add(s);
    }
    let n = cases.len().max(1) as f64;
    (
        h,
        total.clips as f64 / n,
        total.newton as f64 / n,
        total.splits as f64 / n,
    )
}

/// The seeds of the case sets, shared with the criterion bench so that both measure the same
/// queries: 2D cubic spread, 2D cubic close, 3D cubic spread, 2D degree 9, 3D degree 9.
pub const SEEDS: [u64; 5] = [1, 2, 3, 4, 5];

/// Number of cases per set at `scale` (1.0: 2 000).
#[must_use]
pub fn case_count(scale: f64) -> usize {
    ((2000.0 * scale) as usize).max(50)
}

/// Picking set-up shared with the criterion bench: 1 000 cubics scattered over a 40 × 40
/// square and `count` queries over it.
#[must_use]
pub fn pick_setup(count: usize) -> (Vec<Curve<DVec2>>, Vec<DVec2>) {
    let mut rng = Seeded::new(6);
    let curves: Vec<Curve<DVec2>> = (0..1000)
        .map(|_| {
            let centre = DVec2::new(rng.range(0.0, 40.0), rng.range(0.0, 40.0));
            Curve::Bezier(Bezier::new(
                (0..4).map(|_| centre + rng.point::<DVec2>(1.0)).collect(),
            ))
        })
        .collect();
    let queries = (0..count)
        .map(|_| DVec2::new(rng.range(0.0, 40.0), rng.range(0.0, 40.0)))
        .collect();
    (curves, queries)
}

/// Probe-sphere and ray set-up shared with the criterion bench, on the 3D cubic spread cases:
/// the sphere's radius is 1.2 times the reference closest distance (so it meets the curve),
/// and the ray runs from the query along a direction drawn from seed 7.
#[must_use]
pub fn probe_setup(cases: &[ClosestCase<DVec3>]) -> (Vec<f64>, Vec<DVec3>) {
    let mut rng = Seeded::new(7);
    let radii = cases.iter().map(|c| 1.2 * c.reference).collect();
    let dirs = cases
        .iter()
        .map(|_| {
            let d: DVec3 = rng.point(1.0);
            if d.length() < 1e-3 { DVec3::X } else { d }
        })
        .collect();
    (radii, dirs)
}

fn fmt_row(t: &mut Table, r: &Row) {
    t.row(vec![
        r.label.clone(),
        format!("{:.0}", r.ns),
        format!("{:.0}–{:.0}", r.range.0, r.range.1),
        format!("{:.1e}", r.max_error),
        if r.max_u_error.is_nan() {
            "-".into()
        } else {
            format!("{:.1e}", r.max_u_error)
        },
    ]);
}

/// Runs the suite and returns the report. `scale` multiplies the case counts (1.0: 2 000 cases
/// per set). Every set's methods are timed interleaved, `ROUNDS` rounds of thread CPU time,
/// medians reported.
pub fn report(scale: f64, baselines: &[&dyn Baseline]) -> String {
    const ROUNDS: usize = 21;
    let count = case_count(scale);
    let spread2: Vec<ClosestCase<DVec2>> = cases(count, 3, Spread::Around, SEEDS[0]);
    let close2: Vec<ClosestCase<DVec2>> = cases(count, 3, Spread::Close, SEEDS[1]);
    let spread3: Vec<ClosestCase<DVec3>> = cases(count, 3, Spread::Around, SEEDS[2]);
    let nonic: Vec<ClosestCase<DVec2>> = cases(count, 9, Spread::Around, SEEDS[3]);
    let nonic3: Vec<ClosestCase<DVec3>> = cases(count, 9, Spread::Around, SEEDS[4]);
    let minima = |set: &[ClosestCase<DVec2>]| -> Vec<Vec<(f64, f64)>> {
        set.iter()
            .map(|c| reference_minima(&c.curve, c.q))
            .collect()
    };
    let minima3 = |set: &[ClosestCase<DVec3>]| -> Vec<Vec<(f64, f64)>> {
        set.iter()
            .map(|c| reference_minima(&c.curve, c.q))
            .collect()
    };

    let mut rows: Vec<Row> = Vec::new();
    let mut ratios: Vec<String> = Vec::new();
    let mut clip_spread_ns = f64::NAN;
    let mut s1001_ns = f64::NAN;
    for (set_name, set, slow, target) in [
        ("2D cubic, spread", &spread2, true, 0.5),
        ("2D cubic, close", &close2, false, 0.7),
    ] {
        let m = minima(set);
        let clip = clipping_batch(set);
        let base: Vec<Box<dyn Batch + '_>> = baselines.iter().map(|b| b.prepare(set)).collect();
        let sampled = sampled_batch(set);
        let newton = newton_batch(set);
        let mut named: Vec<(String, &dyn Batch, bool)> =
            vec![(format!("{set_name}: Bezier clipping"), clip.as_ref(), true)];
        for (b, batch) in baselines.iter().zip(&base) {
            named.push((format!("{set_name}: {}", b.name()), batch.as_ref(), true));
        }
        if slow {
            named.push((
                format!("{set_name}: 1001-sample search"),
                sampled.as_ref(),
                false,
            ));
            named.push((
                format!("{set_name}: Newton from 8 seeds"),
                newton.as_ref(),
                false,
            ));
        }
        let (r, times) = rows_for(set, &m, &named, ROUNDS);
        for (i, b) in baselines.iter().enumerate() {
            ratios.push(format!(
                "{set_name}: clipping / {} = {:.2} (median of per-round ratios; target ≤ {target})",
                b.name(),
                round_ratio(&times[0], &times[1 + i])
            ));
        }
        if slow {
            clip_spread_ns = r[0].ns;
            s1001_ns = r[1 + baselines.len()].ns;
        }
        rows.extend(r);
    }

    // 3D cubic: the closest point, the probe sphere and the ray, interleaved.
    let m3 = minima3(&spread3);
    let clip3 = clipping_batch(&spread3);
    let (radii, dirs) = probe_setup(&spread3);
    let sphere_inputs: Vec<(Bezier<DVec3>, DVec3, f64)> = spread3
        .iter()
        .zip(&radii)
        .map(|(c, &r)| (c.curve.clone(), c.q, r))
        .collect();
    let sphere = Prepared::new(sphere_inputs, |(c, q, r): &(Bezier<DVec3>, DVec3, f64)| {
        // The worst residual ||C(u)| − r| over the interval ends inside (0,1), as the "distance".
        let iv = sphere_intervals_bezier(c, *q, *r);
        let mut worst = 0.0f64;
        for &(a, b) in &iv {
            for u in [a, b] {
                if u > 0.0 && u < 1.0 {
                    worst = worst.max(((c.eval(u) - *q).length() - r).abs());
                }
            }
        }
        (iv.len() as f64, worst)
    });
    let ray_inputs: Vec<(Bezier<DVec3>, DVec3, DVec3)> = spread3
        .iter()
        .zip(&dirs)
        .map(|(c, &d)| (c.curve.clone(), c.q, d))
        .collect();
    let ray = Prepared::new(ray_inputs, |(c, o, d): &(Bezier<DVec3>, DVec3, DVec3)| {
        ray_closest_bezier(c, *o, *d).map_or((f64::NAN, f64::INFINITY), |r| (r.u, r.distance))
    });
    let sampled3 = sampled_batch(&spread3);
    let newton3 = newton_batch(&spread3);
    let named3: Vec<(String, &dyn Batch, bool)> = vec![
        (
            "3D cubic, spread: Bezier clipping".into(),
            clip3.as_ref(),
            true,
        ),
        (
            "3D cubic, spread: 1001-sample search".into(),
            sampled3.as_ref(),
            false,
        ),
        (
            "3D cubic, spread: Newton from 8 seeds".into(),
            newton3.as_ref(),
            false,
        ),
        ("3D cubic: probe sphere (r = 1.2 d)".into(), &sphere, false),
        ("3D cubic: ray".into(), &ray, false),
    ];
    let (mut r3, _) = rows_for(&spread3, &m3, &named3, ROUNDS);
    let clip3_ns = r3[0].ns;
    // The sphere's and the ray's own accuracy: the interval ends' residual, and the ray
    // distance against dense sampling of the point–ray distance.
    r3[3].max_error = sphere.answers().iter().map(|a| a.1).fold(0.0, f64::max);
    r3[4].max_error = ray
        .answers()
        .iter()
        .zip(spread3.iter().zip(&dirs))
        .map(|(&(_, d), (c, &dir))| {
            let f = |u: f64| point_ray_distance(c.curve.eval(u), c.q, dir);
            let (_, d_ref) = sampled_min(&f, 0.0, 1.0, 2000);
            (d - d_ref) / d_ref.max(1.0)
        })
        .fold(0.0, f64::max);
    rows.extend(r3);

    let m9 = minima(&nonic);
    let clip9 = clipping_batch(&nonic);
    let sampled9 = sampled_batch(&nonic);
    let newton9 = newton_batch(&nonic);
    let (r9, _) = rows_for(
        &nonic,
        &m9,
        &[
            (
                "2D degree 9, spread: Bezier clipping".into(),
                clip9.as_ref(),
                true,
            ),
            (
                "2D degree 9, spread: 1001-sample search".into(),
                sampled9.as_ref(),
                false,
            ),
            (
                "2D degree 9, spread: Newton from 8 seeds".into(),
                newton9.as_ref(),
                false,
            ),
        ],
        ROUNDS,
    );
    let (clip9_ns, s9_ns) = (r9[0].ns, r9[1].ns);
    rows.extend(r9);
    let m93 = minima3(&nonic3);
    let clip93 = clipping_batch(&nonic3);
    let (r93, _) = rows_for(
        &nonic3,
        &m93,
        &[(
            "3D degree 9, spread: Bezier clipping".into(),
            clip93.as_ref(),
            true,
        )],
        ROUNDS,
    );
    rows.extend(r93);

    // Picking among 1 000 curves, interleaved with the single 2D query it is compared to.
    let (curves, queries) = pick_setup(count);
    let set = CurveSet::new(&curves);
    let pick = Prepared::new(queries, |&q: &DVec2| {
        set.pick(q, f64::INFINITY)
            .map_or((f64::NAN, f64::INFINITY), |p| {
                (p.nearest.u, p.nearest.distance)
            })
    });
    let clip_again = clipping_batch(&spread2);
    let times = interleaved(&[&pick, clip_again.as_ref()], ROUNDS);
    let pick_ns = median(&mut times[0].clone());
    let pick_ratio = round_ratio(&times[0], &times[1]);

    let mut t = Table::new(&[
        "case: method",
        "ns/query (median)",
        "rounds min–max",
        "max distance error",
        "max |u − u_ref|",
    ]);
    for r in &rows {
        fmt_row(&mut t, r);
    }
    let mut pick_sorted = times[0].clone();
    pick_sorted.sort_by(f64::total_cmp);
    t.row(vec![
        "pick among 1 000 2D cubics (CurveSet)".into(),
        format!("{pick_ns:.0}"),
        format!(
            "{:.0}–{:.0}",
            pick_sorted[0],
            pick_sorted[pick_sorted.len() - 1]
        ),
        "-".into(),
        "-".into(),
    ]);
    let mut out = format!(
        "nendo bench closest — {count} random cases per set; every set's methods timed \
         interleaved (thread CPU time), medians of {ROUNDS} rounds\n\
         (distance error: (d − d_ref)/max(d_ref, 1) against dense sampling + golden section; \
         probe sphere: worst |dist(C(u_end)) − r|; u error where the reference minimum is unique)\n\n"
    );
    out.push_str(&t.render());
    out.push('\n');
    for r in ratios {
        out.push_str(&r);
        out.push('\n');
    }
    out.push_str(&format!(
        "3D cubic clipping: {clip3_ns:.0} ns/query (target ≤ 200)\n"
    ));
    out.push_str(&format!(
        "pick among 1 000 / one 2D query = {pick_ratio:.1} (median of per-round ratios; target ≤ 20)\n"
    ));
    out.push_str(&format!(
        "speed-up over the 1001-sample search (parameter precision 1e-3; clipping runs to ~1e-12): cubic {:.0}×, degree 9 {:.0}× (paper: ~100× at 1e-3)\n",
        s1001_ns / clip_spread_ns,
        s9_ns / clip9_ns
    ));
    for (name, set) in [("2D cubic, spread", &spread2), ("2D cubic, close", &close2)] {
        let (h, clips, newton, splits) = histogram(set);
        out.push_str(&format!(
            "clipping iterations, {name}: mean {clips:.2} (+ {newton:.2} Newton steps, {splits:.2} splits); histogram 1..11+: {:?}\n",
            &h[1..]
        ));
    }
    let (h, clips, newton, splits) = histogram(&spread3);
    out.push_str(&format!(
        "clipping iterations, 3D cubic: mean {clips:.2} (+ {newton:.2} Newton steps, {splits:.2} splits); histogram 1..11+: {:?}\n",
        &h[1..]
    ));
    let (h, clips, newton, splits) = histogram(&nonic);
    out.push_str(&format!(
        "clipping iterations, degree 9: mean {clips:.2} (+ {newton:.2} Newton steps, {splits:.2} splits); histogram 1..11+: {:?}\n",
        &h[1..]
    ));
    out
}

/// Distance from `x` to the ray `o + s d`, `s ≥ 0`.
fn point_ray_distance(x: DVec3, o: DVec3, d: DVec3) -> f64 {
    let s = ((x - o).dot(d) / d.dot(d)).max(0.0);
    (x - (o + d * s)).length()
}
