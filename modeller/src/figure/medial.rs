//! Seeding metacircles inside a contour from an approximation of its medial axis (P0
//! §4.2 1): "medial axes … to compute the circles inside the figure's region").
//!
//! The region is sampled on a square grid; every inside cell centre gets its distance `d` to
//! the boundary, the radius of the largest disc centred there inside the region. The medial
//! axis is the locus of centres of maximal discs — discs contained in no other. Taking cells
//! by decreasing `d`, a cell becomes a seed unless its disc lies within an already chosen disc
//! (up to a small slack: the cell is off the axis) or its centre is closer than `spacing · d`
//! to a chosen centre (the axis is already sampled there). The chosen discs approximate the
//! medial-axis transform, from the widest part of the figure down to `min_radius`.

use glam::DVec2;

use super::contour::Contour;

/// How seeds are picked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeedOptions {
    /// Grid cells along the longer side of the contour's bounds.
    pub resolution: usize,
    /// Most seeds returned.
    pub max_seeds: usize,
    /// Smallest disc radius kept, in grid cells.
    pub min_radius_cells: f64,
    /// Seeds along the axis are at least `spacing · d` apart (`d` the smaller disc radius).
    pub spacing: f64,
    /// A disc within `slack · r` of containment in a chosen disc of radius `r` is off the axis.
    pub slack: f64,
}

impl Default for SeedOptions {
    fn default() -> Self {
        Self {
            resolution: 128,
            max_seeds: 200,
            min_radius_cells: 1.5,
            spacing: 0.6,
            slack: 0.12,
        }
    }
}

/// A maximal inscribed disc found on the grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Disc {
    /// Centre.
    pub centre: DVec2,
    /// Radius: the centre's distance to the boundary.
    pub radius: f64,
}

/// The inside cell centres of a grid over the contour, with their distance to the boundary.
#[must_use]
pub fn distance_samples(contour: &Contour, resolution: usize) -> (f64, Vec<Disc>) {
    let (lo, hi) = contour.bounds();
    let cell = (hi - lo).max_element() / resolution.max(2) as f64;
    let nx = ((hi.x - lo.x) / cell).ceil() as usize + 1;
    let ny = ((hi.y - lo.y) / cell).ceil() as usize + 1;
    let mut out = Vec::new();
    let mut xs: Vec<f64> = Vec::new();
    for j in 0..ny {
        // Scanline: the crossings of the row with the edges, sorted; inside between pairs.
        let y = lo.y + (j as f64 + 0.5) * cell;
        xs.clear();
        for (a, b) in contour.edges() {
            if (a.y > y) != (b.y > y) {
                xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
            }
        }
        xs.sort_by(f64::total_cmp);
        for pair in xs.chunks_exact(2) {
            let i0 = ((pair[0] - lo.x) / cell - 0.5).ceil().max(0.0) as usize;
            let i1 = (((pair[1] - lo.x) / cell - 0.5).floor().max(-1.0) + 1.0) as usize;
            for i in i0..i1.min(nx) {
                let p = DVec2::new(lo.x + (i as f64 + 0.5) * cell, y);
                out.push(Disc {
                    centre: p,
                    radius: contour.distance(p),
                });
            }
        }
    }
    (cell, out)
}

/// Seeds on the approximate medial axis, widest first.
#[must_use]
pub fn medial_discs(contour: &Contour, options: &SeedOptions) -> Vec<Disc> {
    let (cell, mut cells) = distance_samples(contour, options.resolution);
    cells.sort_by(|a, b| b.radius.total_cmp(&a.radius));
    let min_radius = options.min_radius_cells * cell;
    let mut chosen: Vec<Disc> = Vec::new();
    for c in cells {
        if c.radius < min_radius || chosen.len() >= options.max_seeds {
            break;
        }
        let redundant = chosen.iter().any(|s| {
            let d = s.centre.distance(c.centre);
            d + c.radius <= s.radius * (1.0 + options.slack)
                || d < options.spacing * c.radius.min(s.radius)
        });
        if !redundant {
            chosen.push(c);
        }
    }
    if chosen.is_empty() {
        // A contour thinner than the grid: fall back to its widest cell, or its centroid.
        let (lo, hi) = contour.bounds();
        let centre = 0.5 * (lo + hi);
        chosen.push(Disc {
            centre,
            radius: contour.distance(centre).max(cell),
        });
    }
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_disc_has_one_seed_at_its_centre() {
        let pts: Vec<DVec2> = (0..128)
            .map(|k| {
                DVec2::from_angle(k as f64 * std::f64::consts::TAU / 128.0) * 50.0
                    + DVec2::new(10.0, 20.0)
            })
            .collect();
        let c = Contour::new(pts, "disc").unwrap();
        let seeds = medial_discs(&c, &SeedOptions::default());
        assert!((seeds[0].centre - DVec2::new(10.0, 20.0)).length() < 1.0);
        assert!((seeds[0].radius - 50.0).abs() < 1.0);
        // Smaller discs near the rim are off the axis (inside the big one).
        assert!(seeds.len() <= 3, "{}", seeds.len());
    }

    #[test]
    fn a_long_rectangle_is_seeded_along_its_axis() {
        let c = Contour::new(
            vec![
                DVec2::new(0.0, 0.0),
                DVec2::new(200.0, 0.0),
                DVec2::new(200.0, 20.0),
                DVec2::new(0.0, 20.0),
            ],
            "bar",
        )
        .unwrap();
        let seeds = medial_discs(&c, &SeedOptions::default());
        let on_axis = seeds
            .iter()
            .filter(|s| (s.centre.y - 10.0).abs() < 2.0)
            .count();
        assert!(on_axis >= 10, "{on_axis} of {}", seeds.len());
        let spread = seeds
            .iter()
            .map(|s| s.centre.x)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
        assert!(spread.0 < 20.0 && spread.1 > 180.0);
        for s in &seeds {
            assert!(c.contains(s.centre));
            assert!((s.radius - c.distance(s.centre)).abs() < 1e-12);
        }
    }
}
