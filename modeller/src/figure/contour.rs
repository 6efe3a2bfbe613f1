//! Closed contours (simple polygons): the outlines figures are fitted to, the polygons a warp
//! carries, and the sections of a metaball shape.

use glam::DVec2;

use super::error::FigureError;

/// A closed polygon, its last vertex joined to its first (the closing vertex is not repeated).
#[derive(Debug, Clone, PartialEq)]
pub struct Contour {
    points: Vec<DVec2>,
}

impl Contour {
    /// The largest coordinate magnitude a contour may have. Far beyond any drawing, and small
    /// enough that the contour's extent, its area and the sampling grids laid over its bounds
    /// stay finite (a vertex at 1.8e308 made the extent overflow and the sampling never end).
    pub const MAX_COORDINATE: f64 = 1e12;

    /// A contour through `points`. Repeated consecutive vertices (and a last vertex equal to the
    /// first) are dropped.
    ///
    /// # Errors
    /// [`FigureError::NotFinite`] for a NaN or infinite coordinate, [`FigureError::Contour`]
    /// for a coordinate beyond ±[`Contour::MAX_COORDINATE`], with fewer than three distinct
    /// vertices or a zero area; `what` names the contour.
    pub fn new(points: Vec<DVec2>, what: &str) -> Result<Self, FigureError> {
        if let Some(i) = points.iter().position(|p| !p.is_finite()) {
            return Err(FigureError::NotFinite {
                what: format!("{what} vertex {i}"),
            });
        }
        if let Some(i) = points
            .iter()
            .position(|p| p.abs().max_element() > Self::MAX_COORDINATE)
        {
            return Err(FigureError::Contour {
                what: what.to_string(),
                reason: format!(
                    "vertex {i} lies beyond ±{:e}, where sizes and areas are no longer representable",
                    Self::MAX_COORDINATE
                ),
            });
        }
        let mut clean: Vec<DVec2> = Vec::with_capacity(points.len());
        for p in points {
            if clean.last() != Some(&p) {
                clean.push(p);
            }
        }
        while clean.len() > 1 && clean.first() == clean.last() {
            clean.pop();
        }
        if clean.len() < 3 {
            return Err(FigureError::Contour {
                what: what.to_string(),
                reason: format!("needs at least 3 distinct vertices, has {}", clean.len()),
            });
        }
        let c = Self { points: clean };
        let (lo, hi) = c.bounds();
        let size = (hi - lo).max_element();
        if c.signed_area().abs() <= 1e-12 * size * size {
            return Err(FigureError::Contour {
                what: what.to_string(),
                reason: "has no area".into(),
            });
        }
        Ok(c)
    }

    /// The vertices.
    #[must_use]
    pub fn points(&self) -> &[DVec2] {
        &self.points
    }

    /// Number of vertices (and of edges).
    #[must_use]
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Always false: a contour has at least three vertices.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The edges `(a, b)`, the last one closing the polygon.
    pub fn edges(&self) -> impl Iterator<Item = (DVec2, DVec2)> + '_ {
        let n = self.points.len();
        (0..n).map(move |i| (self.points[i], self.points[(i + 1) % n]))
    }

    /// Signed area by the shoelace formula (positive when the vertices turn from +x to +y).
    #[must_use]
    pub fn signed_area(&self) -> f64 {
        0.5 * self.edges().map(|(a, b)| a.perp_dot(b)).sum::<f64>()
    }

    /// Length of the boundary.
    #[must_use]
    pub fn perimeter(&self) -> f64 {
        self.edges().map(|(a, b)| a.distance(b)).sum()
    }

    /// Axis-aligned bounds.
    #[must_use]
    pub fn bounds(&self) -> (DVec2, DVec2) {
        self.points
            .iter()
            .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), &p| {
                (lo.min(p), hi.max(p))
            })
    }

    /// Whether `p` is inside (even–odd rule; points on the boundary may go either way).
    #[must_use]
    pub fn contains(&self, p: DVec2) -> bool {
        let mut inside = false;
        for (a, b) in self.edges() {
            if (a.y > p.y) != (b.y > p.y) {
                let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if p.x < x {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// Distance from `p` to the boundary.
    #[must_use]
    pub fn distance(&self, p: DVec2) -> f64 {
        self.edges()
            .map(|(a, b)| segment_distance_squared(p, a, b))
            .fold(f64::INFINITY, f64::min)
            .sqrt()
    }

    /// The point of the boundary nearest to `p`.
    #[must_use]
    pub fn closest_point(&self, p: DVec2) -> DVec2 {
        let mut best = (f64::INFINITY, self.points[0]);
        for (a, b) in self.edges() {
            let ab = b - a;
            let l2 = ab.length_squared();
            let t = if l2 > 0.0 {
                ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let q = a + ab * t;
            let d2 = q.distance_squared(p);
            if d2 < best.0 {
                best = (d2, q);
            }
        }
        best.1
    }

    /// `n ≥ 1` points evenly spaced by arc length along the boundary, starting at vertex 0.
    #[must_use]
    pub fn resample(&self, n: usize) -> Vec<DVec2> {
        let total = self.perimeter();
        let step = total / n.max(1) as f64;
        let mut out = Vec::with_capacity(n);
        let mut next = 0.0;
        let mut walked = 0.0;
        for (a, b) in self.edges() {
            let len = a.distance(b);
            while next < walked + len && out.len() < n {
                out.push(a.lerp(b, (next - walked) / len));
                next += step;
            }
            walked += len;
        }
        while out.len() < n {
            out.push(self.points[0]);
        }
        out
    }

    /// The same polygon with vertices inserted so that no edge is longer than `max_edge`
    /// (so that a warp bends its edges, not only moves its corners).
    #[must_use]
    pub fn subdivided(&self, max_edge: f64) -> Self {
        if !(max_edge.is_finite() && max_edge > 0.0) {
            return self.clone();
        }
        let mut points = Vec::new();
        for (a, b) in self.edges() {
            let k = ((a.distance(b) / max_edge).ceil() as usize).clamp(1, 1 << 16);
            points.extend((0..k).map(|i| a.lerp(b, i as f64 / k as f64)));
        }
        Self { points }
    }

    /// The contour with every vertex moved by `map`.
    ///
    /// # Errors
    /// As [`Contour::new`], when the moved polygon degenerates.
    pub fn mapped(&self, map: impl FnMut(DVec2) -> DVec2, what: &str) -> Result<Self, FigureError> {
        Self::new(self.points.iter().copied().map(map).collect(), what)
    }
}

/// Squared distance from `p` to the segment `[a, b]`.
#[must_use]
pub fn segment_distance_squared(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).length_squared()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Contour {
        Contour::new(
            vec![
                DVec2::ZERO,
                DVec2::new(2.0, 0.0),
                DVec2::new(2.0, 2.0),
                DVec2::new(0.0, 2.0),
                DVec2::ZERO,
            ],
            "sq",
        )
        .unwrap()
    }

    #[test]
    fn square_measures() {
        let s = square();
        assert_eq!(s.len(), 4);
        assert!((s.signed_area() - 4.0).abs() < 1e-15);
        assert!((s.perimeter() - 8.0).abs() < 1e-15);
        assert!(s.contains(DVec2::new(1.0, 1.5)));
        assert!(!s.contains(DVec2::new(2.5, 1.0)));
        assert!((s.distance(DVec2::new(1.0, 1.5)) - 0.5).abs() < 1e-15);
        assert!((s.distance(DVec2::new(3.0, 3.0)) - 2f64.sqrt()).abs() < 1e-15);
        assert_eq!(s.closest_point(DVec2::new(3.0, 1.0)), DVec2::new(2.0, 1.0));
        let r = s.resample(16);
        assert_eq!(r.len(), 16);
        assert!(r.iter().all(|&p| s.distance(p) < 1e-12));
        assert!((r[1] - DVec2::new(0.5, 0.0)).length() < 1e-12);
        assert_eq!(s.subdivided(0.5).len(), 16);
    }

    #[test]
    fn rejects_degenerate_polygons() {
        assert!(Contour::new(vec![DVec2::ZERO, DVec2::X, DVec2::ZERO], "a").is_err());
        assert!(Contour::new(vec![DVec2::ZERO, DVec2::X, DVec2::new(2.0, 0.0)], "b").is_err());
        let e =
            Contour::new(vec![DVec2::ZERO, DVec2::X, DVec2::new(f64::NAN, 1.0)], "c").unwrap_err();
        assert!(e.to_string().contains("c vertex 2"));
    }

    #[test]
    fn rejects_vertices_too_far_for_its_extent_to_be_finite() {
        let far = vec![
            DVec2::new(10.0, 50.0),
            DVec2::new(40.0, 20.0),
            DVec2::new(-1.797_693_134_862_315_7e308, 50.0),
            DVec2::new(40.0, 80.0),
        ];
        let e = Contour::new(far, "d").unwrap_err();
        assert!(e.to_string().contains("vertex 2"), "{e}");
        let edge = Contour::MAX_COORDINATE;
        let ok = vec![DVec2::ZERO, DVec2::new(edge, 0.0), DVec2::new(0.0, -edge)];
        assert!(Contour::new(ok, "e").is_ok());
    }
}
