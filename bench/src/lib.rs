#![forbid(unsafe_code)]
//! # nendo-bench
//!
//! The measurement suites behind `nendo bench <suite>`: measurements printed as tables, on the
//! same cases in one run, so that ratios against a baseline are meaningful on a noisy machine.
//! Criterion benches under `benches/` (in the root package) measure the same code paths and
//! share their cases from here; these suites add accuracy figures, counts and the comparisons
//! each issue asks for.
//!
//! The suites measure the library ([`nendo`], package `nendo-modeller`): its editor, renderer,
//! figures and hand loop, so this crate depends on it and not the other way round; only the
//! binary (which adds [`cli`] as `nendo bench`), the criterion benches and the integration
//! tests use it. Feature `gui` (on by default) adds the `live` suite and the GPU frames of the
//! `render` suite.
//!
//! One module per suite, [`cli`] for the subcommand, [`rng`] for the suites' one seeded
//! generator and [`reference`] for slow independent references. Timing is by medians of
//! repeated batches ([`Stopwatch`]).
#![warn(missing_docs)]

use std::time::Instant;

pub mod cli;
pub mod closest;
pub mod curves;
pub mod figures;
pub mod input;
#[cfg(feature = "gui")]
pub mod live;
pub mod reference;
pub mod regulation;
pub mod render;
pub mod rng;
pub mod sculpt;

/// Repeated timing of a closure, reporting the median of per-batch means.
#[derive(Debug, Clone, Copy)]
pub struct Stopwatch {
    /// Number of batches whose per-call mean is recorded.
    pub batches: usize,
    /// Calls per batch.
    pub calls_per_batch: usize,
}

impl Default for Stopwatch {
    fn default() -> Self {
        Self {
            batches: 15,
            calls_per_batch: 1,
        }
    }
}

impl Stopwatch {
    /// Median over batches of the mean time per call, in nanoseconds. `f` receives the call
    /// index so that it can walk through a set of cases.
    pub fn median_ns(&self, mut f: impl FnMut(usize)) -> f64 {
        let mut per_call = Vec::with_capacity(self.batches);
        let mut k = 0usize;
        // One warm-up batch.
        for _ in 0..self.calls_per_batch {
            f(k);
            k += 1;
        }
        for _ in 0..self.batches.max(1) {
            let start = Instant::now();
            for _ in 0..self.calls_per_batch {
                f(k);
                k += 1;
            }
            per_call.push(start.elapsed().as_nanos() as f64 / self.calls_per_batch.max(1) as f64);
        }
        median(&mut per_call)
    }
}

/// Median over `batches` of the mean time per call of `f` (which receives the call index), in
/// nanoseconds of the measuring thread's CPU time where Linux reports it (other processes on a
/// shared machine then do not inflate it), else in wall time through [`Stopwatch`]. One
/// warm-up batch first.
pub fn cpu_median_ns(batches: usize, calls_per_batch: usize, mut f: impl FnMut(usize)) -> f64 {
    if sculpt::thread_cpu_ns().is_none() {
        return Stopwatch {
            batches,
            calls_per_batch,
        }
        .median_ns(f);
    }
    let mut k = 0usize;
    for _ in 0..calls_per_batch {
        f(k);
        k += 1;
    }
    let mut per_call = Vec::with_capacity(batches);
    for _ in 0..batches.max(1) {
        let t0 = sculpt::thread_cpu_ns().unwrap_or(0);
        for _ in 0..calls_per_batch {
            f(k);
            k += 1;
        }
        let t1 = sculpt::thread_cpu_ns().unwrap_or(0);
        per_call.push(t1.saturating_sub(t0) as f64 / calls_per_batch.max(1) as f64);
    }
    median(&mut per_call)
}

/// A duration in nanoseconds as `12.34 ms`, `5.67 µs` or `890 ns`.
#[must_use]
pub fn format_ns(ns: f64) -> String {
    if ns >= 1e6 {
        format!("{:.2} ms", ns / 1e6)
    } else if ns >= 1e3 {
        format!("{:.2} µs", ns / 1e3)
    } else {
        format!("{ns:.0} ns")
    }
}

/// Median of a sample (sorts it in place); NaN for an empty sample.
pub fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// A plain text table with right-aligned columns.
#[derive(Debug, Default)]
pub struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with the given column titles.
    pub fn new(header: &[&str]) -> Self {
        Self {
            header: header.iter().map(|s| s.to_string()).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row (cells beyond the header are kept; missing cells print empty).
    pub fn row(&mut self, cells: Vec<String>) {
        self.rows.push(cells);
    }

    /// Renders the table as text.
    pub fn render(&self) -> String {
        let cols = self
            .rows
            .iter()
            .map(Vec::len)
            .chain([self.header.len()])
            .max()
            .unwrap_or(0);
        let mut width = vec![0usize; cols];
        for r in std::iter::once(&self.header).chain(&self.rows) {
            for (i, c) in r.iter().enumerate() {
                width[i] = width[i].max(c.chars().count());
            }
        }
        let line = |r: &Vec<String>| {
            let mut s = String::new();
            for (i, w) in width.iter().enumerate() {
                let c = r.get(i).map(String::as_str).unwrap_or("");
                let pad = w - c.chars().count();
                if i == 0 {
                    s.push_str(c);
                    s.push_str(&" ".repeat(pad));
                } else {
                    s.push_str("  ");
                    s.push_str(&" ".repeat(pad));
                    s.push_str(c);
                }
            }
            s.trim_end().to_string()
        };
        let mut out = line(&self.header);
        out.push('\n');
        out.push_str(&"-".repeat(width.iter().sum::<usize>() + 2 * cols.saturating_sub(1)));
        out.push('\n');
        for r in &self.rows {
            out.push_str(&line(r));
            out.push('\n');
        }
        out
    }
}
