//! Metacircles (2D metaballs) and the figure they make: P0 §4.2 1), eqs. (8) and (9).
//!
//! Metacircle `i` has a centre `P_i`, an effective radius `R_i`, a centre density `q_i`
//! (negative values carve) and a colour. The figure's density at `p` is
//!
//! ```text
//! F(p) = Σ_i q_i f(|p − P_i|² / R_i²)
//! ```
//!
//! with Wyvill's falloff `f` ([`super::falloff`]), and the figure is the region `F ≥ T` whose
//! boundary is the iso-curve `F = T` (threshold `T = 0.5` by default). A metacircle of radius 0
//! contributes nothing (the dummies of morphing).

use glam::DVec2;

use super::error::FigureError;
use super::falloff::{DEFAULT_THRESHOLD, density, density_and_ds};

/// An 8-bit sRGB colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Rgb(pub [u8; 3]);

impl Rgb {
    /// Black.
    pub const BLACK: Rgb = Rgb([0, 0, 0]);
    /// White.
    pub const WHITE: Rgb = Rgb([255, 255, 255]);
    /// The colour metacircles get when none is given: a clay brown.
    pub const CLAY: Rgb = Rgb([0x8a, 0x5a, 0x3c]);

    /// Parses `#rrggbb` (or `rrggbb`).
    ///
    /// ```
    /// use nendo::figure::Rgb;
    /// assert_eq!(Rgb::parse_hex("#ff8000"), Some(Rgb([255, 128, 0])));
    /// assert_eq!(Rgb::parse_hex("#ff80"), None);
    /// ```
    #[must_use]
    pub fn parse_hex(s: &str) -> Option<Rgb> {
        let h = s.strip_prefix('#').unwrap_or(s);
        if h.len() != 6 || !h.is_ascii() {
            return None;
        }
        let byte = |i: usize| u8::from_str_radix(&h[i..i + 2], 16).ok();
        Some(Rgb([byte(0)?, byte(2)?, byte(4)?]))
    }

    /// `#rrggbb`.
    #[must_use]
    pub fn to_hex(self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.0[0], self.0[1], self.0[2])
    }
}

/// One metacircle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metacircle {
    /// Centre `P_i`.
    pub centre: DVec2,
    /// Effective radius `R_i ≥ 0`: the density is zero beyond it.
    pub radius: f64,
    /// Centre density `q_i` (negative allowed).
    pub density: f64,
    /// Colour.
    pub colour: Rgb,
}

impl Metacircle {
    /// A metacircle of the default colour.
    #[must_use]
    pub fn new(centre: DVec2, radius: f64, density: f64) -> Self {
        Self {
            centre,
            radius,
            density,
            colour: Rgb::CLAY,
        }
    }

    /// Its density `q f(|p − P|² / R²)` at `p`.
    #[inline]
    #[must_use]
    pub fn field(&self, p: DVec2) -> f64 {
        if self.radius <= 0.0 {
            return 0.0;
        }
        let s = (p - self.centre).length_squared() / (self.radius * self.radius);
        self.density * density(s)
    }

    /// Its density and the density's gradient at `p`:
    /// `∇ = q f'(s) · 2 (p − P) / R²`.
    #[inline]
    #[must_use]
    pub fn field_and_gradient(&self, p: DVec2) -> (f64, DVec2) {
        if self.radius <= 0.0 {
            return (0.0, DVec2::ZERO);
        }
        let r2 = self.radius * self.radius;
        let d = p - self.centre;
        let (f, df) = density_and_ds(d.length_squared() / r2);
        (self.density * f, d * (self.density * df * 2.0 / r2))
    }

    /// Checks that every number is finite and the radius is not negative; `what` names it.
    ///
    /// # Errors
    /// [`FigureError::NotFinite`] or [`FigureError::NegativeRadius`].
    pub fn validate(&self, what: &str) -> Result<(), FigureError> {
        if !self.centre.is_finite() {
            return Err(FigureError::NotFinite {
                what: format!("{what} centre"),
            });
        }
        if !self.radius.is_finite() {
            return Err(FigureError::NotFinite {
                what: format!("{what} radius"),
            });
        }
        if !self.density.is_finite() {
            return Err(FigureError::NotFinite {
                what: format!("{what} density"),
            });
        }
        if self.radius < 0.0 {
            return Err(FigureError::NegativeRadius {
                what: what.to_string(),
                radius: self.radius,
            });
        }
        Ok(())
    }
}

/// A figure: metacircles and the threshold of its iso-curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// The metacircles.
    pub metacircles: Vec<Metacircle>,
    /// The threshold `T > 0`: the figure is `F ≥ T`.
    pub threshold: f64,
}

impl Default for Figure {
    fn default() -> Self {
        Self {
            metacircles: Vec::new(),
            threshold: DEFAULT_THRESHOLD,
        }
    }
}

impl Figure {
    /// A figure with the default threshold 0.5.
    #[must_use]
    pub fn new(metacircles: Vec<Metacircle>) -> Self {
        Self {
            metacircles,
            threshold: DEFAULT_THRESHOLD,
        }
    }

    /// The density `F(p) = Σ q_i f_i(p)`, summed over every metacircle (see
    /// [`super::CircleGrid`] for many queries).
    ///
    /// ```
    /// use glam::DVec2;
    /// use nendo::figure::{Figure, Metacircle};
    /// let fig = Figure::new(vec![Metacircle::new(DVec2::ZERO, 2.0, 1.0)]);
    /// // A lone metacircle's boundary is the circle of radius R/2.
    /// assert!((fig.field(DVec2::new(1.0, 0.0)) - fig.threshold).abs() < 1e-15);
    /// ```
    #[must_use]
    pub fn field(&self, p: DVec2) -> f64 {
        self.metacircles.iter().map(|m| m.field(p)).sum()
    }

    /// The density and its gradient.
    #[must_use]
    pub fn field_and_gradient(&self, p: DVec2) -> (f64, DVec2) {
        self.metacircles
            .iter()
            .fold((0.0, DVec2::ZERO), |(f, g), m| {
                let (fi, gi) = m.field_and_gradient(p);
                (f + fi, g + gi)
            })
    }

    /// Whether `p` is inside the figure (`F(p) ≥ T`).
    #[must_use]
    pub fn contains(&self, p: DVec2) -> bool {
        self.field(p) >= self.threshold
    }

    /// Bounds of the supports of the metacircles of positive density and radius (the figure
    /// lies inside them); `None` when there is none.
    #[must_use]
    pub fn bounds(&self) -> Option<(DVec2, DVec2)> {
        self.metacircles
            .iter()
            .filter(|m| m.density > 0.0 && m.radius > 0.0)
            .fold(None, |acc, m| {
                let r = DVec2::splat(m.radius);
                let (lo, hi) = (m.centre - r, m.centre + r);
                Some(match acc {
                    None => (lo, hi),
                    Some((a, b)) => (a.min(lo), b.max(hi)),
                })
            })
    }

    /// Checks every metacircle and the threshold.
    ///
    /// # Errors
    /// The first problem found, naming the metacircle.
    pub fn validate(&self) -> Result<(), FigureError> {
        if !(self.threshold.is_finite() && self.threshold > 0.0) {
            return Err(FigureError::Threshold(self.threshold));
        }
        for (i, m) in self.metacircles.iter().enumerate() {
            m.validate(&format!("metacircle {i}"))?;
        }
        Ok(())
    }

    /// Applies `map` to every centre (the warp of a figure moves its metacircles' centres).
    pub fn map_centres(&mut self, mut map: impl FnMut(DVec2) -> DVec2) {
        for m in &mut self.metacircles {
            m.centre = map(m.centre);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradient_matches_finite_differences() {
        let fig = Figure::new(vec![
            Metacircle::new(DVec2::new(0.0, 0.0), 2.0, 1.0),
            Metacircle::new(DVec2::new(1.0, 0.5), 1.5, -0.7),
            Metacircle::new(DVec2::new(-0.5, 1.0), 3.0, 0.4),
        ]);
        for k in 0..50 {
            let t = k as f64 * 0.37;
            let p = DVec2::new(t.sin() * 1.3, (1.7 * t).cos() * 1.1);
            let (f, g) = fig.field_and_gradient(p);
            assert!((f - fig.field(p)).abs() < 1e-14);
            let h = 1e-6;
            let gx = (fig.field(p + DVec2::X * h) - fig.field(p - DVec2::X * h)) / (2.0 * h);
            let gy = (fig.field(p + DVec2::Y * h) - fig.field(p - DVec2::Y * h)) / (2.0 * h);
            assert!((g - DVec2::new(gx, gy)).length() < 1e-7, "{g} vs {gx} {gy}");
        }
    }

    #[test]
    fn zero_radius_contributes_nothing() {
        let m = Metacircle::new(DVec2::ZERO, 0.0, 5.0);
        assert_eq!(m.field(DVec2::ZERO), 0.0);
        assert_eq!(m.field_and_gradient(DVec2::ZERO), (0.0, DVec2::ZERO));
    }

    #[test]
    fn two_metacircles_fuse() {
        // Two circles whose lone iso-circles (radius 1) are 0.4 apart fuse: the midpoint is inside.
        let fig = Figure::new(vec![
            Metacircle::new(DVec2::new(-1.2, 0.0), 2.0, 1.0),
            Metacircle::new(DVec2::new(1.2, 0.0), 2.0, 1.0),
        ]);
        assert!(fig.contains(DVec2::ZERO));
    }

    #[test]
    fn validation_names_the_culprit() {
        let mut fig = Figure::new(vec![Metacircle::new(DVec2::ZERO, 1.0, 1.0); 3]);
        assert!(fig.validate().is_ok());
        fig.metacircles[2].radius = -1.0;
        assert!(
            fig.validate()
                .unwrap_err()
                .to_string()
                .contains("metacircle 2")
        );
        fig.metacircles[2].radius = f64::NAN;
        assert!(matches!(fig.validate(), Err(FigureError::NotFinite { .. })));
        fig.metacircles[2].radius = 1.0;
        fig.threshold = 0.0;
        assert!(matches!(fig.validate(), Err(FigureError::Threshold(_))));
    }
}
