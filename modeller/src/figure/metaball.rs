//! Metaballs (3D) and the shape they make: P0 §4.3, the 3D counterpart of the metacircles
//! of [`super::metacircle`].
//!
//! Metaball `i` has a centre `C_i`, an effective radius `R_i` and a centre density `q_i`
//! (negative values carve). The shape's density at `X` is
//!
//! ```text
//! F(X) = Σ_i q_i f(|X − C_i|² / R_i²)
//! ```
//!
//! with Wyvill's sixth-degree falloff `f` ([`super::falloff`]), and the shape is the solid
//! `F ≥ T` whose boundary is the iso-surface `F = T` (threshold `T = 0.5` by default). A lone
//! metaball of density 1 has the sphere of radius `R/2` as its iso-surface. The gradient, which
//! gives the surface normals (`n = −∇F / |∇F|`, outward), is
//! `∇F(X) = Σ_i q_i f'(s_i) · 2 (X − C_i) / R_i²`, `s_i = |X − C_i|² / R_i²`.

use glam::DVec3;

use super::error::FigureError;
use super::falloff::{DEFAULT_THRESHOLD, density, density_and_ds};

/// One metaball.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metaball {
    /// Centre `C_i`.
    pub centre: DVec3,
    /// Effective radius `R_i ≥ 0`: the density is zero beyond it.
    pub radius: f64,
    /// Centre density `q_i` (negative allowed).
    pub density: f64,
}

impl Metaball {
    /// A metaball.
    #[must_use]
    pub fn new(centre: DVec3, radius: f64, density: f64) -> Self {
        Self {
            centre,
            radius,
            density,
        }
    }

    /// Its density `q f(|X − C|² / R²)` at `x`.
    #[inline]
    #[must_use]
    pub fn field(&self, x: DVec3) -> f64 {
        if self.radius <= 0.0 {
            return 0.0;
        }
        let s = (x - self.centre).length_squared() / (self.radius * self.radius);
        self.density * density(s)
    }

    /// Its density and gradient at `x`: `∇ = q f'(s) · 2 (X − C) / R²`.
    #[inline]
    #[must_use]
    pub fn field_and_gradient(&self, x: DVec3) -> (f64, DVec3) {
        if self.radius <= 0.0 {
            return (0.0, DVec3::ZERO);
        }
        let r2 = self.radius * self.radius;
        let d = x - self.centre;
        let (f, df) = density_and_ds(d.length_squared() / r2);
        (self.density * f, d * (self.density * df * 2.0 / r2))
    }

    /// Checks that every number is finite and the radius is not negative; `what` names it.
    ///
    /// # Errors
    /// [`FigureError::NotFinite`] or [`FigureError::NegativeRadius`].
    pub fn validate(&self, what: &str) -> Result<(), FigureError> {
        for (name, ok) in [
            ("centre", self.centre.is_finite()),
            ("radius", self.radius.is_finite()),
            ("density", self.density.is_finite()),
        ] {
            if !ok {
                return Err(FigureError::NotFinite {
                    what: format!("{what} {name}"),
                });
            }
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

/// A shape: metaballs and the threshold of its iso-surface.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// The metaballs.
    pub balls: Vec<Metaball>,
    /// The threshold `T > 0`: the shape is `F ≥ T`.
    pub threshold: f64,
}

impl Default for Shape {
    fn default() -> Self {
        Self {
            balls: Vec::new(),
            threshold: DEFAULT_THRESHOLD,
        }
    }
}

impl Shape {
    /// A shape with the default threshold 0.5.
    #[must_use]
    pub fn new(balls: Vec<Metaball>) -> Self {
        Self {
            balls,
            threshold: DEFAULT_THRESHOLD,
        }
    }

    /// The density `F(X) = Σ q_i f_i(X)`.
    ///
    /// ```
    /// use glam::DVec3;
    /// use nendo::figure::{Metaball, Shape};
    /// let shape = Shape::new(vec![Metaball::new(DVec3::ZERO, 2.0, 1.0)]);
    /// // A lone metaball's boundary is the sphere of radius R/2.
    /// assert!((shape.field(DVec3::new(0.6, 0.0, 0.8)) - shape.threshold).abs() < 1e-15);
    /// ```
    #[must_use]
    pub fn field(&self, x: DVec3) -> f64 {
        self.balls.iter().map(|b| b.field(x)).sum()
    }

    /// The density and its gradient.
    #[must_use]
    pub fn field_and_gradient(&self, x: DVec3) -> (f64, DVec3) {
        self.balls.iter().fold((0.0, DVec3::ZERO), |(f, g), b| {
            let (fi, gi) = b.field_and_gradient(x);
            (f + fi, g + gi)
        })
    }

    /// Whether `x` is inside (`F(x) ≥ T`).
    #[must_use]
    pub fn contains(&self, x: DVec3) -> bool {
        self.field(x) >= self.threshold
    }

    /// Bounds of the supports of the metaballs of positive density and radius (the solid lies
    /// inside them); `None` when there is none.
    #[must_use]
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        self.balls
            .iter()
            .filter(|b| b.density > 0.0 && b.radius > 0.0)
            .fold(None, |acc, b| {
                let r = DVec3::splat(b.radius);
                let (lo, hi) = (b.centre - r, b.centre + r);
                Some(match acc {
                    None => (lo, hi),
                    Some((a, c)) => (a.min(lo), c.max(hi)),
                })
            })
    }

    /// Checks every metaball and the threshold.
    ///
    /// # Errors
    /// The first problem found, naming the metaball.
    pub fn validate(&self) -> Result<(), FigureError> {
        if !(self.threshold.is_finite() && self.threshold > 0.0) {
            return Err(FigureError::Threshold(self.threshold));
        }
        for (i, b) in self.balls.iter().enumerate() {
            b.validate(&format!("metaball {i}"))?;
        }
        Ok(())
    }

    /// Distance from `x` to the iso-surface `F = T` by Newton steps along the gradient
    /// (`X ← X − (F − T) ∇F / |∇F|²`, each step at most `size / 20`); `None` when the iteration
    /// does not settle on the surface (no density gradient near `x`).
    #[must_use]
    pub fn distance_to_surface(&self, x: DVec3, size: f64) -> Option<f64> {
        super::falloff::distance_to_level(|q| self.field_and_gradient(q), self.threshold, x, size)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradient_matches_finite_differences() {
        let shape = Shape::new(vec![
            Metaball::new(DVec3::new(0.0, 0.0, 0.0), 2.0, 1.0),
            Metaball::new(DVec3::new(1.0, 0.5, -0.3), 1.5, -0.7),
            Metaball::new(DVec3::new(-0.5, 1.0, 0.4), 3.0, 0.4),
        ]);
        for k in 0..50 {
            let t = k as f64 * 0.37;
            let x = DVec3::new(t.sin() * 1.3, (1.7 * t).cos() * 1.1, (0.6 * t).sin());
            let (f, g) = shape.field_and_gradient(x);
            assert!((f - shape.field(x)).abs() < 1e-14);
            let h = 1e-6;
            let fd = DVec3::new(
                shape.field(x + DVec3::X * h) - shape.field(x - DVec3::X * h),
                shape.field(x + DVec3::Y * h) - shape.field(x - DVec3::Y * h),
                shape.field(x + DVec3::Z * h) - shape.field(x - DVec3::Z * h),
            ) / (2.0 * h);
            assert!((g - fd).length() < 1e-7, "{g} vs {fd}");
        }
    }

    #[test]
    fn a_lone_ball_is_a_sphere_of_half_its_radius() {
        let shape = Shape::new(vec![Metaball::new(DVec3::new(1.0, 2.0, 3.0), 4.0, 1.0)]);
        for k in 0..20 {
            let dir = DVec3::new((k as f64).sin(), (k as f64 * 0.7).cos(), 0.3).normalize();
            let on = DVec3::new(1.0, 2.0, 3.0) + dir * 2.0;
            assert!((shape.field(on) - 0.5).abs() < 1e-14);
            let out = on + dir * 0.25;
            let d = shape.distance_to_surface(out, 8.0).unwrap();
            assert!((d - 0.25).abs() < 1e-9, "{d}");
        }
        assert!(shape.contains(DVec3::new(1.0, 2.0, 3.0)));
        assert_eq!(
            shape.bounds(),
            Some((DVec3::new(-3.0, -2.0, -1.0), DVec3::new(5.0, 6.0, 7.0)))
        );
    }

    #[test]
    fn validation_names_the_culprit() {
        let mut shape = Shape::new(vec![Metaball::new(DVec3::ZERO, 1.0, 1.0); 3]);
        assert!(shape.validate().is_ok());
        shape.balls[1].radius = -1.0;
        assert!(
            shape
                .validate()
                .unwrap_err()
                .to_string()
                .contains("metaball 1")
        );
        shape.balls[1].radius = 1.0;
        shape.balls[2].centre.z = f64::INFINITY;
        assert!(matches!(
            shape.validate(),
            Err(FigureError::NotFinite { .. })
        ));
    }
}
