//! The boundary of a figure: the iso-curve `F = T` as polylines, by marching squares on a
//! lattice, each vertex then moved onto the curve by Newton steps along the gradient.
//!
//! Cells whose four corners lie on one side of `T` are skipped; a crossed cell edge gets one
//! vertex, interpolated linearly, and the segments of every cell are oriented so that the
//! inside is on the same side of each (a saddle cell — opposite corners inside — is resolved
//! by the density at its centre). Chained through their shared edge vertices, the segments form
//! closed loops (open polylines only where the figure leaves the lattice). Outer boundaries and
//! holes come out with opposite orientations.

use std::collections::HashMap;

use glam::DVec2;

use super::index::CircleGrid;
use super::metacircle::Figure;

/// A polyline of the iso-curve.
#[derive(Debug, Clone, PartialEq)]
pub struct IsoLine {
    /// Its vertices.
    pub points: Vec<DVec2>,
    /// Whether the last vertex joins the first.
    pub closed: bool,
}

impl IsoLine {
    /// Signed area (shoelace) of a closed line; 0 for an open one.
    #[must_use]
    pub fn signed_area(&self) -> f64 {
        if !self.closed {
            return 0.0;
        }
        let n = self.points.len();
        0.5 * (0..n)
            .map(|i| self.points[i].perp_dot(self.points[(i + 1) % n]))
            .sum::<f64>()
    }
}

/// The lattice the iso-curve is traced on: `cells.0 × cells.1` square cells of side `step`
/// from `origin`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lattice {
    /// Lower corner.
    pub origin: DVec2,
    /// Cell side.
    pub step: f64,
    /// Cells along x and y.
    pub cells: (usize, usize),
}

impl Lattice {
    /// A lattice of cells of side `step` covering the figure's bounds with one cell to spare;
    /// `None` for a figure without a metacircle of positive density, or a bad step.
    #[must_use]
    pub fn around(figure: &Figure, step: f64) -> Option<Self> {
        let (lo, hi) = figure.bounds()?;
        if !(step.is_finite() && step > 0.0) {
            return None;
        }
        let origin = lo - DVec2::splat(step);
        let n = ((hi - lo) / step).ceil() + 2.0;
        if n.x * n.y > 1e8 {
            return None;
        }
        Some(Self {
            origin,
            step,
            cells: (n.x as usize, n.y as usize),
        })
    }
}

/// Traces the iso-curve `F = T` of a figure on a lattice, refining each vertex onto the curve
/// with up to `newton` steps (0 for the plain linear interpolation).
#[must_use]
pub fn iso_lines(figure: &Figure, lattice: &Lattice, newton: usize) -> Vec<IsoLine> {
    let (nx, ny) = lattice.cells;
    let cw = nx + 1;
    let step = lattice.step;
    let hi = lattice.origin + DVec2::new(nx as f64, ny as f64) * step;
    let grid = CircleGrid::new(
        &figure.metacircles,
        lattice.origin,
        hi,
        (8.0 * step).max(1e-300),
    );
    let t = figure.threshold;
    let corner = |i: usize, j: usize| lattice.origin + DVec2::new(i as f64, j as f64) * step;
    let values: Vec<f64> = (0..=ny)
        .flat_map(|j| (0..=nx).map(move |i| (i, j)))
        .map(|(i, j)| grid.field(corner(i, j)))
        .collect();
    let v = |i: usize, j: usize| values[j * cw + i];
    // Edge keys: horizontal edge (i,j)-(i+1,j) → 2 (j cw + i); vertical (i,j)-(i,j+1) → 2 (j cw + i) + 1.
    let mut vertex: HashMap<usize, DVec2> = HashMap::new();
    let mut next: HashMap<usize, usize> = HashMap::new();
    let mut edge_point = |key: usize, a: DVec2, fa: f64, b: DVec2, fb: f64| {
        vertex.entry(key).or_insert_with(|| {
            let s = ((t - fa) / (fb - fa)).clamp(0.0, 1.0);
            a.lerp(b, s)
        });
    };
    for j in 0..ny {
        for i in 0..nx {
            // Corners around the cell: c0 (i,j), c1 (i+1,j), c2 (i+1,j+1), c3 (i,j+1).
            let c = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let f = c.map(|(a, b)| v(a, b));
            let inside = f.map(|x| x >= t);
            if inside.iter().all(|&x| x) || inside.iter().all(|&x| !x) {
                continue;
            }
            let keys = [
                2 * (j * cw + i),
                2 * (j * cw + i + 1) + 1,
                2 * ((j + 1) * cw + i),
                2 * (j * cw + i) + 1,
            ];
            // Crossings in walking order: edge k from corner k to corner k+1; leaving = in → out.
            let mut leaving = Vec::with_capacity(2);
            let mut entering = Vec::with_capacity(2);
            for k in 0..4 {
                let k1 = (k + 1) % 4;
                if inside[k] != inside[k1] {
                    edge_point(
                        keys[k],
                        corner(c[k].0, c[k].1),
                        f[k],
                        corner(c[k1].0, c[k1].1),
                        f[k1],
                    );
                    if inside[k] {
                        leaving.push(k)
                    } else {
                        entering.push(k)
                    }
                }
            }
            if leaving.len() == 1 {
                next.insert(keys[leaving[0]], keys[entering[0]]);
            } else {
                // Saddle: with the centre inside, each leaving crossing joins the next entering
                // one around the cell (cutting off the outside corners); else the previous one.
                let centre_inside = grid.field(corner(i, j) + DVec2::splat(0.5 * step)) >= t;
                for &l in &leaving {
                    let e = if centre_inside {
                        (l + 1) % 4
                    } else {
                        (l + 3) % 4
                    };
                    next.insert(keys[l], keys[e]);
                }
            }
        }
    }
    let refine = |p: DVec2| {
        let mut q = p;
        for _ in 0..newton {
            let (fv, g) = grid.field_and_gradient(q);
            let g2 = g.length_squared();
            if g2 <= 1e-300 {
                return p;
            }
            let s = g * ((fv - t) / g2);
            if s.length() > step {
                return p; // not converging nearby: keep the lattice estimate
            }
            q -= s;
        }
        q
    };
    // Chains: first the open ones (starting at a key nobody points to), then the loops.
    let targets: std::collections::HashSet<usize> = next.values().copied().collect();
    let mut starts: Vec<usize> = next
        .keys()
        .copied()
        .filter(|k| !targets.contains(k))
        .collect();
    starts.sort_unstable();
    let mut loop_starts: Vec<usize> = next.keys().copied().collect();
    loop_starts.sort_unstable();
    let mut lines = Vec::new();
    let mut used: std::collections::HashSet<usize> = std::collections::HashSet::new();
    for (open, &s) in starts
        .iter()
        .map(|s| (true, s))
        .chain(loop_starts.iter().map(|s| (false, s)))
    {
        if used.contains(&s) {
            continue;
        }
        let mut points = Vec::new();
        let mut k = s;
        let mut closed = false;
        loop {
            used.insert(k);
            points.push(refine(vertex[&k]));
            match next.get(&k) {
                Some(&n) if n == s => {
                    closed = true;
                    break;
                }
                Some(&n) if !used.contains(&n) => k = n,
                Some(&n) => {
                    // Ran into an already traced chain (cannot happen for a consistent field).
                    points.push(refine(vertex[&n]));
                    break;
                }
                None => break,
            }
        }
        debug_assert!(open || closed || points.len() > 1);
        lines.push(IsoLine { points, closed });
    }
    lines
}

/// The largest distance from the vertices of `a` to the polylines of `b` (a one-sided
/// Hausdorff distance between traced boundaries); `∞` when `b` is empty and `a` is not.
#[must_use]
pub fn polyline_distance(a: &[IsoLine], b: &[IsoLine]) -> f64 {
    let segs: Vec<(DVec2, DVec2)> = b
        .iter()
        .flat_map(|l| {
            let n = l.points.len();
            let m = if l.closed { n } else { n.saturating_sub(1) };
            (0..m).map(move |i| (l.points[i], l.points[(i + 1) % n]))
        })
        .collect();
    let mut worst = 0.0f64;
    for p in a.iter().flat_map(|l| l.points.iter()) {
        let d2 = segs
            .iter()
            .map(|&(s, e)| super::contour::segment_distance_squared(*p, s, e))
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(d2.sqrt());
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figure::Metacircle;

    #[test]
    fn lone_circle_traces_one_loop_on_the_circle() {
        let fig = Figure::new(vec![Metacircle::new(DVec2::new(3.0, -2.0), 10.0, 1.0)]);
        let lat = Lattice::around(&fig, 0.5).unwrap();
        let lines = iso_lines(&fig, &lat, 4);
        assert_eq!(lines.len(), 1);
        assert!(lines[0].closed);
        for p in &lines[0].points {
            assert!(((*p - DVec2::new(3.0, -2.0)).length() - 5.0).abs() < 1e-9);
        }
        let area = lines[0].signed_area().abs();
        assert!((area - std::f64::consts::PI * 25.0).abs() < 0.2, "{area}");
    }

    #[test]
    fn a_hole_has_the_opposite_orientation() {
        let fig = Figure::new(vec![
            Metacircle::new(DVec2::ZERO, 20.0, 1.0),
            Metacircle::new(DVec2::ZERO, 6.0, -1.0),
        ]);
        let lat = Lattice::around(&fig, 0.4).unwrap();
        let lines = iso_lines(&fig, &lat, 3);
        assert_eq!(lines.len(), 2);
        assert!(lines.iter().all(|l| l.closed));
        assert!(lines[0].signed_area() * lines[1].signed_area() < 0.0);
    }

    #[test]
    fn separate_blobs_trace_separate_loops() {
        let fig = Figure::new(vec![
            Metacircle::new(DVec2::ZERO, 4.0, 1.0),
            Metacircle::new(DVec2::new(10.0, 0.0), 4.0, 1.0),
            Metacircle::new(DVec2::new(0.0, 10.0), 4.0, 1.0),
        ]);
        let lat = Lattice::around(&fig, 0.25).unwrap();
        let lines = iso_lines(&fig, &lat, 3);
        assert_eq!(lines.len(), 3);
        let areas: Vec<f64> = lines.iter().map(IsoLine::signed_area).collect();
        assert!(areas.iter().all(|a| a.signum() == areas[0].signum()));
        assert!(polyline_distance(&lines, &lines) < 1e-12);
    }
}
