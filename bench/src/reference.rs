//! Slow, independent references for accuracy figures: dense sampling of a function of one
//! parameter, then a golden-section polish of every sampled local minimum. No clipping.

/// Golden-section search for a minimum of `f` on `[a, b]`; returns `(argmin, min)`.
pub fn golden(f: &impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> (f64, f64) {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let mut c = b - r * (b - a);
    let mut d = a + r * (b - a);
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..200 {
        if (b - a).abs() < 1e-15 {
            break;
        }
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - r * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + r * (b - a);
            fd = f(d);
        }
    }
    let u = 0.5 * (a + b);
    (u, f(u))
}

/// Minimum of `f` over `[lo, hi]`: `samples + 1` evenly spaced samples, then a golden-section
/// polish around every sampled local minimum (ends included). Returns `(argmin, min)`.
pub fn sampled_min(f: &impl Fn(f64) -> f64, lo: f64, hi: f64, samples: usize) -> (f64, f64) {
    let samples = samples.max(2);
    let us: Vec<f64> = (0..=samples)
        .map(|i| lo + (hi - lo) * i as f64 / samples as f64)
        .collect();
    let vs: Vec<f64> = us.iter().map(|&u| f(u)).collect();
    let mut best = (us[0], vs[0]);
    if vs[samples] < best.1 {
        best = (us[samples], vs[samples]);
    }
    for i in 0..=samples {
        let left = if i == 0 { f64::INFINITY } else { vs[i - 1] };
        let right = if i == samples {
            f64::INFINITY
        } else {
            vs[i + 1]
        };
        if vs[i] <= left && vs[i] <= right {
            let cand = golden(f, us[i.saturating_sub(1)], us[(i + 1).min(samples)]);
            if cand.1 < best.1 {
                best = cand;
            }
        }
    }
    best
}
