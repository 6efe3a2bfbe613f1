//! Horizontal cross-sections of a metaball shape and their deformation by curves laid along
//! their boundaries (P0 §4.3, Fig. 12 (a)).
//!
//! A section is a closed contour in the horizontal plane at a height `z` (coordinates `(x, y)`,
//! `z` up), the sampling points its metaballs are fitted to ([`super::shape`]), and the 2D
//! curves laid along its boundary. Dragging a curve moves the section's points with it: each
//! contour vertex `X` is carried by the curve warp of [`crate::curve::warp`] (Beier–Neely
//! weights; `X = C_k(u_k) + v_k N(u_k)` against each original curve,
//! `X^d = X + Σ_k ŵ_k (C_k^d(u_k) + v_k N^d(u_k) − X)`), the contour's edges first divided so
//! that none is longer than `max_edge` (so the outline bends with the curves). A vertex on a
//! dragged curve follows it exactly, a vertex on a curve left still stays, and a section none
//! of whose curves moved is left exactly as it was (no edge divided).
//!
//! A drag is a [`CurveMove`]: a grab of the curve anywhere along it ([`crate::curve::edit`]:
//! the closest point to `from` moves by `to − from`, `C'(u) = C(u) + (to − from)`, exactly), or
//! the deformed curve itself.

use glam::DVec2;

use crate::curve::Curve;
use crate::curve::edit::{Grab, GrabOptions};
use crate::curve::warp::WarpParams;

use super::contour::Contour;
use super::error::FigureError;
use super::warp::{curve_warp, divided_vertices, warp_contour, whole};

/// A horizontal section: a closed contour at height `z` and the curves laid along it.
#[derive(Debug, Clone, PartialEq)]
pub struct Section {
    /// The height of the section's plane.
    pub z: f64,
    /// The outline in the plane (its vertices are the sampling points of P0).
    pub contour: Contour,
    /// 2D curves laid along (or near) the outline; dragging them deforms the section.
    pub curves: Vec<Curve<DVec2>>,
}

/// One drag of a section's curve.
#[derive(Debug, Clone, PartialEq)]
pub enum CurveMove {
    /// Grab curve `curve` at its point closest to `from` and move that point by `to − from`.
    Grab {
        /// Index of the curve in the section.
        curve: usize,
        /// Where the hand takes hold.
        from: DVec2,
        /// Where it lets go.
        to: DVec2,
        /// Which control points move.
        options: GrabOptions,
    },
    /// Replace curve `curve` by its deformed state (same parameter domain).
    Replace {
        /// Index of the curve in the section.
        curve: usize,
        /// The deformed curve.
        deformed: Curve<DVec2>,
    },
}

impl CurveMove {
    /// The index of the curve moved.
    #[must_use]
    pub fn curve(&self) -> usize {
        match self {
            CurveMove::Grab { curve, .. } | CurveMove::Replace { curve, .. } => *curve,
        }
    }
}

impl Section {
    /// A section, its height checked to be finite.
    ///
    /// # Errors
    /// [`FigureError::NotFinite`] for a non-finite `z`.
    pub fn new(z: f64, contour: Contour, curves: Vec<Curve<DVec2>>) -> Result<Self, FigureError> {
        if !z.is_finite() {
            return Err(FigureError::NotFinite {
                what: "section height".into(),
            });
        }
        Ok(Self { z, contour, curves })
    }

    /// The section's curves after `moves`, applied in order (a later move of the same curve
    /// grabs the already moved curve).
    ///
    /// # Errors
    /// [`FigureError::Option`] for a move naming no curve of the section; [`FigureError::Warp`]
    /// when a grab fails (e.g. an overflowing curve) or a replacement's domain differs.
    pub fn moved_curves(&self, moves: &[CurveMove]) -> Result<Vec<Curve<DVec2>>, FigureError> {
        let mut curves = self.curves.clone();
        for (i, m) in moves.iter().enumerate() {
            let k = m.curve();
            let len = curves.len();
            let slot = curves.get_mut(k).ok_or_else(|| {
                FigureError::Option(format!(
                    "move {i} names curve {k}, but the section has {len} curves"
                ))
            })?;
            *slot = match m {
                CurveMove::Grab {
                    from, to, options, ..
                } => match Grab::at_point(slot, *from, f64::INFINITY, *options)
                    .map_err(FigureError::Warp)?
                {
                    Some(g) => g.moved_by(*to - *from).map_err(FigureError::Warp)?,
                    None => {
                        return Err(FigureError::Option(format!(
                            "move {i}: no point of curve {k} to grab"
                        )));
                    }
                },
                CurveMove::Replace { deformed, .. } => {
                    if deformed.domain() != slot.domain() {
                        return Err(FigureError::Option(format!(
                            "move {i}: the deformed curve {k} has the domain {:?}, the curve {:?}",
                            deformed.domain(),
                            slot.domain()
                        )));
                    }
                    deformed.clone()
                }
            };
        }
        Ok(curves)
    }

    /// The section with its curves moved to `deformed` (curve `k` to `deformed[k]`) and its
    /// contour carried along; edges longer than `max_edge` are divided first (`None`: 1/100 of
    /// the contour's diagonal). Returns the section and whether any curve moved (when none did,
    /// the section is returned unchanged).
    ///
    /// # Errors
    /// [`FigureError::Mismatch`] for a wrong number of curves, [`FigureError::Warp`] when the
    /// curve warp refuses them, [`FigureError::Option`] for a bad `max_edge`,
    /// [`FigureError::Contour`] when the warped outline degenerates.
    pub fn warped(
        &self,
        deformed: &[Curve<DVec2>],
        params: WarpParams,
        max_edge: Option<f64>,
    ) -> Result<(Section, bool), FigureError> {
        // The points carried: the contour's vertices once divided (as below).
        let points = match max_edge {
            Some(m) if m > 0.0 => divided_vertices(&self.contour, m),
            Some(_) => self.contour.points().len() as f64,
            None => {
                let (lo, hi) = self.contour.bounds();
                divided_vertices(&self.contour, (hi - lo).length() / 100.0)
            }
        };
        let warp = curve_warp(&self.curves, deformed, params, whole(points))?;
        if self.curves.as_slice() == deformed {
            return Ok((self.clone(), false));
        }
        let max_edge = match max_edge {
            Some(m) if m.is_nan() || m <= 0.0 => {
                return Err(FigureError::Option(format!(
                    "the longest contour edge must be a positive number, got {m}"
                )));
            }
            Some(m) => m,
            None => {
                let (lo, hi) = self.contour.bounds();
                (hi - lo).length() / 100.0
            }
        };
        let contour = warp_contour(
            &self.contour,
            &warp,
            max_edge,
            &format!("section at z = {}", self.z),
        )?;
        Ok((
            Section {
                z: self.z,
                contour,
                curves: deformed.to_vec(),
            },
            true,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::Bezier;

    fn square() -> Contour {
        Contour::new(
            vec![
                DVec2::new(-1.0, -1.0),
                DVec2::new(1.0, -1.0),
                DVec2::new(1.0, 1.0),
                DVec2::new(-1.0, 1.0),
            ],
            "square",
        )
        .unwrap()
    }

    fn line(a: DVec2, b: DVec2) -> Curve<DVec2> {
        Bezier::new(vec![a, a.lerp(b, 1.0 / 3.0), a.lerp(b, 2.0 / 3.0), b]).into()
    }

    #[test]
    fn a_grab_moves_the_side_under_the_curve() {
        let curves = vec![
            line(DVec2::new(1.0, -1.0), DVec2::new(1.0, 1.0)),
            line(DVec2::new(-1.0, 1.0), DVec2::new(-1.0, -1.0)),
        ];
        let s = Section::new(0.5, square(), curves).unwrap();
        let moves = [CurveMove::Grab {
            curve: 0,
            from: DVec2::new(1.0, 0.0),
            to: DVec2::new(1.5, 0.0),
            options: GrabOptions::default(),
        }];
        let deformed = s.moved_curves(&moves).unwrap();
        assert!((deformed[0].eval(0.5) - DVec2::new(1.5, 0.0)).length() < 1e-12);
        let (w, moved) = s
            .warped(&deformed, WarpParams::default(), Some(0.1))
            .unwrap();
        assert!(moved);
        // The point of the right side under the grab follows it exactly: (1, 0) is at u = 1/2
        // on the original line and goes to C'(1/2) = (1.5, 0); the left side, under a still
        // curve, stays at x = -1.
        assert!(
            w.contour
                .points()
                .iter()
                .any(|p| (*p - DVec2::new(1.5, 0.0)).length() < 1e-9)
        );
        for p in w.contour.points().iter().filter(|p| p.x < -0.99) {
            assert!((p.x + 1.0).abs() < 1e-9);
        }
        // Unmoved curves: the same section, no edge divided.
        let (same, moved) = s
            .warped(&s.curves, WarpParams::default(), Some(0.01))
            .unwrap();
        assert!(!moved);
        assert_eq!(same, s);
        // Bad moves are refused.
        let bad = [CurveMove::Replace {
            curve: 5,
            deformed: s.curves[0].clone(),
        }];
        assert!(s.moved_curves(&bad).is_err());
        assert!(Section::new(f64::NAN, square(), Vec::new()).is_err());
    }
}
