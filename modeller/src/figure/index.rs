//! A uniform grid of cells over a rectangle, each listing the metacircles whose support disc
//! touches it, so that the density at a point sums only the few metacircles that reach it.

use glam::DVec2;

use super::metacircle::Metacircle;

/// Metacircles binned into the cells of a grid over `[min, max]`.
#[derive(Debug, Clone)]
pub struct CircleGrid<'a> {
    circles: &'a [Metacircle],
    origin: DVec2,
    cell: f64,
    nx: usize,
    ny: usize,
    /// `items[starts[c]..starts[c + 1]]` are the circles of cell `c = iy * nx + ix`.
    starts: Vec<u32>,
    items: Vec<u32>,
}

impl<'a> CircleGrid<'a> {
    /// Bins `circles` into square cells of side `cell` covering `[min, max]` (at least one
    /// cell). Metacircles of zero radius or zero density are left out: they add nothing.
    ///
    /// # Panics
    /// If `cell` is not positive and finite or the rectangle is not finite (programming errors;
    /// callers derive both from validated figures).
    #[must_use]
    pub fn new(circles: &'a [Metacircle], min: DVec2, max: DVec2, cell: f64) -> Self {
        assert!(cell.is_finite() && cell > 0.0, "cell size must be positive");
        assert!(
            min.is_finite() && max.is_finite(),
            "grid bounds must be finite"
        );
        let size = (max - min).max(DVec2::ZERO);
        let nx = ((size.x / cell).ceil() as usize).max(1);
        let ny = ((size.y / cell).ceil() as usize).max(1);
        let mut counts = vec![0u32; nx * ny + 1];
        let range = |m: &Metacircle| -> Option<(usize, usize, usize, usize)> {
            if m.radius <= 0.0 || m.density == 0.0 {
                return None;
            }
            let lo = (m.centre - DVec2::splat(m.radius) - min) / cell;
            let hi = (m.centre + DVec2::splat(m.radius) - min) / cell;
            if hi.x < 0.0 || hi.y < 0.0 || lo.x >= nx as f64 || lo.y >= ny as f64 {
                return None;
            }
            let x0 = lo.x.max(0.0) as usize;
            let y0 = lo.y.max(0.0) as usize;
            let x1 = (hi.x as usize).min(nx - 1);
            let y1 = (hi.y as usize).min(ny - 1);
            Some((x0, x1, y0, y1))
        };
        let touches = |m: &Metacircle, ix: usize, iy: usize| {
            let lo = min + DVec2::new(ix as f64, iy as f64) * cell;
            let d = (lo - m.centre)
                .max(m.centre - (lo + DVec2::splat(cell)))
                .max(DVec2::ZERO);
            d.length_squared() <= m.radius * m.radius
        };
        for m in circles {
            if let Some((x0, x1, y0, y1)) = range(m) {
                for iy in y0..=y1 {
                    for ix in x0..=x1 {
                        if touches(m, ix, iy) {
                            counts[iy * nx + ix + 1] += 1;
                        }
                    }
                }
            }
        }
        for c in 1..counts.len() {
            counts[c] += counts[c - 1];
        }
        let starts = counts;
        let mut fill = starts.clone();
        let mut items = vec![0u32; starts[nx * ny] as usize];
        for (i, m) in circles.iter().enumerate() {
            if let Some((x0, x1, y0, y1)) = range(m) {
                for iy in y0..=y1 {
                    for ix in x0..=x1 {
                        if touches(m, ix, iy) {
                            let c = iy * nx + ix;
                            items[fill[c] as usize] = i as u32;
                            fill[c] += 1;
                        }
                    }
                }
            }
        }
        Self {
            circles,
            origin: min,
            cell,
            nx,
            ny,
            starts,
            items,
        }
    }

    /// Number of cells along x and y.
    #[must_use]
    pub fn cells(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// The metacircles of cell `(ix, iy)` (empty outside the grid).
    pub fn cell_circles(&self, ix: usize, iy: usize) -> impl Iterator<Item = &'a Metacircle> + '_ {
        let (a, b) = if ix < self.nx && iy < self.ny {
            let c = iy * self.nx + ix;
            (self.starts[c] as usize, self.starts[c + 1] as usize)
        } else {
            (0, 0)
        };
        let circles = self.circles;
        self.items[a..b].iter().map(move |&i| &circles[i as usize])
    }

    /// The cell holding `p`, `None` outside the grid (points on the far edges belong to the
    /// last cells).
    #[must_use]
    pub fn cell_of(&self, p: DVec2) -> Option<(usize, usize)> {
        let g = (p - self.origin) / self.cell;
        if !(g.x >= 0.0 && g.y >= 0.0 && g.x <= self.nx as f64 && g.y <= self.ny as f64) {
            return None;
        }
        Some((
            (g.x as usize).min(self.nx - 1),
            (g.y as usize).min(self.ny - 1),
        ))
    }

    /// The density at `p`: through its cell inside the grid, over every metacircle outside.
    #[must_use]
    pub fn field(&self, p: DVec2) -> f64 {
        match self.cell_of(p) {
            Some((ix, iy)) => self.cell_circles(ix, iy).map(|m| m.field(p)).sum(),
            None => self.circles.iter().map(|m| m.field(p)).sum(),
        }
    }

    /// The density and its gradient at `p`.
    #[must_use]
    pub fn field_and_gradient(&self, p: DVec2) -> (f64, DVec2) {
        let add = |(f, g): (f64, DVec2), m: &Metacircle| {
            let (fi, gi) = m.field_and_gradient(p);
            (f + fi, g + gi)
        };
        match self.cell_of(p) {
            Some((ix, iy)) => self.cell_circles(ix, iy).fold((0.0, DVec2::ZERO), add),
            None => self.circles.iter().fold((0.0, DVec2::ZERO), add),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figure::Figure;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn grid_field_equals_brute_force() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let circles: Vec<Metacircle> = (0..200)
            .map(|_| {
                Metacircle::new(
                    DVec2::new(rng.gen_range(-10.0..110.0), rng.gen_range(-10.0..110.0)),
                    rng.gen_range(0.0..15.0),
                    rng.gen_range(-1.0..2.0),
                )
            })
            .collect();
        let fig = Figure::new(circles);
        let grid = CircleGrid::new(&fig.metacircles, DVec2::ZERO, DVec2::splat(100.0), 7.0);
        for _ in 0..5000 {
            let p = DVec2::new(rng.gen_range(-20.0..120.0), rng.gen_range(-20.0..120.0));
            assert!((grid.field(p) - fig.field(p)).abs() < 1e-12);
            let (f, g) = grid.field_and_gradient(p);
            let (fb, gb) = fig.field_and_gradient(p);
            assert!((f - fb).abs() < 1e-12 && (g - gb).length() < 1e-12);
        }
    }
}
