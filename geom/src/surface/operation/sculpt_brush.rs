//! Sculpt brushes that follow the surface: **inflate**, **flatten**, **pinch** and **crease**
//! (Blender's I, Shift+T, P, Shift+C). Each is a displacement field the one engine
//! ([`crate::surface::engine`]) runs like any finger: envelope, Bernstein inverse, regulation,
//! symmetry, verification or rollback.
//!
//! A brush has a stroke `P` (one point: a dab at that point; more: the polyline through them),
//! a radius `R`, a brush ([`super::brush`]: falloff `w`, strength `s`, `0 < s ≤ 1`) and, for
//! inflate and crease, a depth `h`. For a surface sample `x` with unit normal
//! `n = unit(S_u × S_v)` (the surface's own orientation: outward on the closed primitives,
//! `+z` on the plane):
//!
//! ```text
//! c(x) = the point of P nearest x,   t = |x − c(x)|² / R²,   T = I − n nᵀ (the tangent plane)
//!
//! inflate   F = s · w(t) · h · n                     h > 0 outward (inflate), h < 0 inward
//! flatten   F = s · w(t) · ((q − x) · m) m           toward the plane (q, m) under the brush
//! pinch     F = ½ · s · w(t) · T (c(x) − x)          toward the stroke, along the surface
//! crease    F = ½ · s · w(t) · T (c(x) − x) − s · w(t) · h · n
//!                                                     a pinch and a push (h > 0: a valley)
//! ```
//!
//! The flatten plane is the weighted least-squares plane of the surface under the brush, as
//! the surface is before the stroke: `q = Σ ωₖ xₖ / Σ ωₖ`, `m` the unit eigenvector of the
//! smallest eigenvalue of `C = Σ ωₖ (xₖ − q)(xₖ − q)ᵀ` ([`crate::surface::plane_fit`]), over the midpoints `xₖ` of an 8 × 8
//! parameter grid on every patch within reach, `ωₖ = w(tₖ) · |S_u × S_v|(xₖ) / 64` (falloff
//! times area: a midpoint-rule quadrature of `∫ w dA`).
//!
//! The pinch moves a sample at most half way to the stroke: along a line through a dab the
//! distance `ρ` from the centre becomes `ρ (1 − ½ s w)`, whose derivative
//! `1 − ½ s w − ½ s ρ w′(ρ) ≥ ½` for every non-increasing falloff, so the map never folds.
//! A sample where the surface has no tangent plane does not move (`F = 0`).
//!
//! Limits of the rule: at a sharp corner of a stroke, points on its inner side equidistant
//! from two pieces are pulled toward the nearer, so the pinch's field jumps there and the
//! bicubic surface follows it only in the mean (the window's strokes, resampled every fifth
//! of the radius, turn gently); at a stroke's end caps the pull turns toward the end point
//! and the field's slope jumps (the plane test measures 12 % of the largest displacement
//! there, 2.5 % for a dab). Where a brush overlaps its own images under a symmetry, the
//! engine's envelope picks the stronger of two tangential pulls, and the commit makes the
//! result exactly symmetric.

use glam::DVec3;

use super::brush::Brush;
use crate::surface::bounds::Aabb;
use crate::surface::error::SurfaceError;
use crate::surface::grid::Grid;
use crate::surface::limits::COORDINATE_LIMIT;
use crate::surface::patch::Patch;
use crate::surface::plane_fit::symmetric_eigen;

/// Which surface-following brush.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SculptKind {
    /// Along each point's own normal by `s · w · h`.
    Inflate,
    /// Toward the average plane under the brush.
    Flatten,
    /// Toward the stroke along the surface.
    Pinch,
    /// A pinch and a push along the normal.
    Crease,
}

impl SculptKind {
    /// Every kind, in panel order.
    pub const ALL: [SculptKind; 4] = [
        SculptKind::Inflate,
        SculptKind::Flatten,
        SculptKind::Pinch,
        SculptKind::Crease,
    ];

    /// The `op` name in operation files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            SculptKind::Inflate => "inflate",
            SculptKind::Flatten => "flatten",
            SculptKind::Pinch => "pinch",
            SculptKind::Crease => "crease",
        }
    }

    /// The kind called `name` (see [`SculptKind::name`]).
    #[must_use]
    pub fn from_name(name: &str) -> Option<SculptKind> {
        SculptKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Whether the brush presses a depth `h` (inflate, crease).
    #[must_use]
    pub fn has_depth(self) -> bool {
        matches!(self, SculptKind::Inflate | SculptKind::Crease)
    }
}

/// One inflate, flatten, pinch or crease stroke (see the module docs for the formulas).
#[derive(Debug, Clone, PartialEq)]
pub struct SculptBrush {
    /// Which brush.
    pub kind: SculptKind,
    /// The stroke: one point (a dab) or a polyline.
    pub path: Vec<DVec3>,
    /// The brush radius `R`.
    pub radius: f64,
    /// The depth `h` (inflate: outward; crease: inward); zero for flatten and pinch.
    pub depth: f64,
    /// The falloff and strength.
    pub brush: Brush,
}

impl SculptBrush {
    /// A validated brush stroke.
    ///
    /// # Errors
    /// As [`SculptBrush::validate`].
    pub fn try_new(
        kind: SculptKind,
        path: Vec<DVec3>,
        radius: f64,
        depth: f64,
        brush: Brush,
    ) -> Result<SculptBrush, SurfaceError> {
        let b = SculptBrush {
            kind,
            path,
            radius,
            depth,
            brush,
        };
        b.validate()?;
        Ok(b)
    }

    /// Checks the stroke: at least one point, every coordinate finite and within
    /// [`COORDINATE_LIMIT`], `0 < R ≤ COORDINATE_LIMIT`, `|h| ≤ COORDINATE_LIMIT` (zero for
    /// flatten and pinch), and the brush's `0 < s ≤ 1`.
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] saying what is wrong.
    pub fn validate(&self) -> Result<(), SurfaceError> {
        let bad = |s: String| Err(SurfaceError::BadOp(s));
        let name = self.kind.name();
        let within = |x: f64| x.is_finite() && x.abs() <= COORDINATE_LIMIT;
        if self.path.is_empty() {
            return bad(format!("{name} needs at least one point"));
        }
        if self
            .path
            .iter()
            .any(|p| !(within(p.x) && within(p.y) && within(p.z)))
        {
            return bad(format!(
                "every point of {name} must be finite and within {COORDINATE_LIMIT:e}"
            ));
        }
        if !(within(self.radius) && self.radius > 0.0) {
            return bad(format!(
                "{name} radius must be a positive finite number up to {COORDINATE_LIMIT:e} (got {})",
                self.radius
            ));
        }
        if !within(self.depth) {
            return bad(format!(
                "{name} depth must be a finite number up to {COORDINATE_LIMIT:e} in size (got {})",
                self.depth
            ));
        }
        if !self.kind.has_depth() && self.depth != 0.0 {
            return bad(format!("{name} takes no depth"));
        }
        self.brush.validate()
    }

    /// The point of the stroke nearest `x` and its squared distance.
    #[must_use]
    pub fn nearest_on_stroke(&self, x: DVec3) -> (DVec3, f64) {
        let mut best = (self.path[0], (x - self.path[0]).length_squared());
        for w in self.path.windows(2) {
            let e = w[1] - w[0];
            let len2 = e.length_squared();
            let t = if len2 > 0.0 {
                ((x - w[0]).dot(e) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let c = w[0] + e * t;
            let d2 = (x - c).length_squared();
            if d2 < best.1 {
                best = (c, d2);
            }
        }
        best
    }

    /// The weight `w(t)`, `t = |x − c(x)|²/R²`, and `c(x)`.
    #[must_use]
    pub fn weight(&self, x: DVec3) -> (f64, DVec3) {
        let (c, d2) = self.nearest_on_stroke(x);
        (
            self.brush.falloff.weight(d2 / (self.radius * self.radius)),
            c,
        )
    }

    /// True when some point of the box may lie within `R` of the stroke (conservative).
    #[must_use]
    pub fn may_touch(&self, b: &Aabb) -> bool {
        let bb = b.inflated(self.radius);
        let seg_box = |p: DVec3, q: DVec3| {
            let (lo, hi) = (p.min(q), p.max(q));
            lo.cmple(bb.max).all() && bb.min.cmple(hi).all()
        };
        if self.path.len() == 1 {
            return seg_box(self.path[0], self.path[0]);
        }
        self.path.windows(2).any(|w| seg_box(w[0], w[1]))
    }

    /// The flow at a sample `x` whose unit normal is `n` (`None`: no tangent plane), with the
    /// flatten plane `(q, m)` (see the module docs).
    #[must_use]
    pub fn flow(&self, x: DVec3, n: Option<DVec3>, plane: Option<(DVec3, DVec3)>) -> DVec3 {
        let (w, c) = self.weight(x);
        if w == 0.0 {
            return DVec3::ZERO;
        }
        let sw = self.brush.strength * w;
        match self.kind {
            SculptKind::Flatten => match plane {
                Some((q, m)) => m * (sw * (q - x).dot(m)),
                None => DVec3::ZERO,
            },
            SculptKind::Inflate => n.map_or(DVec3::ZERO, |n| n * (sw * self.depth)),
            SculptKind::Pinch | SculptKind::Crease => {
                let Some(n) = n else {
                    return DVec3::ZERO;
                };
                let to = c - x;
                let tangential = (to - n * to.dot(n)) * (0.5 * sw);
                if self.kind == SculptKind::Crease {
                    tangential - n * (sw * self.depth)
                } else {
                    tangential
                }
            }
        }
    }

    /// The flatten plane `(q, m)` of the surface under the brush (see the module docs).
    ///
    /// # Errors
    /// [`SurfaceError::BadOp`] when no surface lies under the brush, or its samples span no
    /// plane (a degenerate covariance).
    pub fn average_plane(&self, grid: &Grid) -> Result<(DVec3, DVec3), SurfaceError> {
        const K: usize = 8;
        let mut patches = Vec::new();
        grid.hierarchy().query(&|b| self.may_touch(b), &mut patches);
        let m = grid.patches_u();
        let mut samples = Vec::new();
        for &p in &patches {
            let patch = Patch::new(grid.patch(p % m, p / m));
            for a in 0..K {
                for b in 0..K {
                    let (u, v) = ((a as f64 + 0.5) / K as f64, (b as f64 + 0.5) / K as f64);
                    let f = patch.frame(u, v);
                    let (w, _) = self.weight(f.point);
                    let omega = w * f.du.cross(f.dv).length() / (K * K) as f64;
                    if omega > 0.0 && omega.is_finite() {
                        samples.push((f.point, omega));
                    }
                }
            }
        }
        weighted_plane(&samples).ok_or_else(|| {
            SurfaceError::BadOp(
                "flatten: no surface under the brush to fit a plane to (press on the surface)"
                    .to_string(),
            )
        })
    }
}

/// The weighted least-squares plane `(q, m)` of the points (see the module docs); `None` for
/// no weight or no defined smallest direction.
#[must_use]
pub fn weighted_plane(samples: &[(DVec3, f64)]) -> Option<(DVec3, DVec3)> {
    let total: f64 = samples.iter().map(|s| s.1).sum();
    if !(total > 0.0 && total.is_finite()) {
        return None;
    }
    let q = samples.iter().map(|(x, w)| *x * *w).sum::<DVec3>() / total;
    let mut c = [[0.0f64; 3]; 3];
    for (x, w) in samples {
        let d = (*x - q).to_array();
        for (i, row) in c.iter_mut().enumerate() {
            for (j, cij) in row.iter_mut().enumerate().skip(i) {
                *cij += w * d[i] * d[j];
            }
        }
    }
    let (_, vectors) = symmetric_eigen(c);
    let m = vectors[0].try_normalize()?;
    m.is_finite().then_some((q, m))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::brush::Falloff;

    fn dab(kind: SculptKind, depth: f64) -> SculptBrush {
        SculptBrush::try_new(
            kind,
            vec![DVec3::ZERO],
            2.0,
            depth,
            Brush {
                falloff: Falloff::Soft,
                strength: 0.8,
            },
        )
        .unwrap()
    }

    #[test]
    fn the_flows_follow_their_formulas() {
        let x = DVec3::new(0.6, -0.8, 0.0);
        let n = DVec3::Z;
        let w = 0.8 * (1.0f64 - 1.0 / 4.0).powi(3);
        let f = dab(SculptKind::Inflate, 0.5).flow(x, Some(n), None);
        assert!((f - n * (w * 0.5)).length() < 1e-15);
        let f = dab(SculptKind::Pinch, 0.0).flow(x, Some(n), None);
        assert!((f - (-x) * (0.5 * w)).length() < 1e-15);
        let f = dab(SculptKind::Crease, 0.3).flow(x, Some(n), None);
        assert!((f - ((-x) * (0.5 * w) - n * (w * 0.3))).length() < 1e-15);
        let plane = (DVec3::new(0.0, 0.0, 0.2), DVec3::Z);
        let f = dab(SculptKind::Flatten, 0.0).flow(x, Some(n), Some(plane));
        assert!((f - DVec3::Z * (w * 0.2)).length() < 1e-15);
        assert_eq!(
            dab(SculptKind::Inflate, 0.5).flow(DVec3::new(2.0, 0.0, 0.0), Some(n), None),
            DVec3::ZERO
        );
    }

    #[test]
    fn the_weighted_plane_of_points_on_a_plane_is_that_plane() {
        let m = DVec3::new(0.3, -0.2, 1.0).normalize();
        let (a, b) = (m.any_orthonormal_pair().0, m.any_orthonormal_pair().1);
        let q0 = DVec3::new(1.0, 2.0, 3.0);
        let pts: Vec<(DVec3, f64)> = (0..40)
            .map(|k| {
                let (s, t) = ((k as f64 * 0.77).sin(), (k as f64 * 1.31).cos());
                (q0 + a * s + b * t, 1.0 + 0.1 * k as f64)
            })
            .collect();
        let (q, got) = weighted_plane(&pts).unwrap();
        assert!(got.dot(m).abs() > 1.0 - 1e-12);
        assert!((q - q0).dot(m).abs() < 1e-12);
        assert!(weighted_plane(&[]).is_none());
    }

    #[test]
    fn bad_strokes_are_refused() {
        let good = dab(SculptKind::Crease, 0.2);
        for (what, b) in [
            (
                "nan point",
                SculptBrush {
                    path: vec![DVec3::NAN],
                    ..good.clone()
                },
            ),
            (
                "huge point",
                SculptBrush {
                    path: vec![DVec3::splat(1e308)],
                    ..good.clone()
                },
            ),
            (
                "no point",
                SculptBrush {
                    path: vec![],
                    ..good.clone()
                },
            ),
            (
                "negative radius",
                SculptBrush {
                    radius: -1.0,
                    ..good.clone()
                },
            ),
            (
                "huge radius",
                SculptBrush {
                    radius: 1e308,
                    ..good.clone()
                },
            ),
            (
                "nan depth",
                SculptBrush {
                    depth: f64::NAN,
                    ..good.clone()
                },
            ),
            (
                "huge depth",
                SculptBrush {
                    depth: 1e308,
                    ..good.clone()
                },
            ),
            (
                "pinch depth",
                SculptBrush {
                    kind: SculptKind::Pinch,
                    ..good.clone()
                },
            ),
        ] {
            assert!(
                matches!(b.validate(), Err(SurfaceError::BadOp(_))),
                "{what}"
            );
        }
    }
}
