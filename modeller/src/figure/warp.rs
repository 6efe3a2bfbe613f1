//! Warping a figure by the curves laid over it (P0 §4.1, Fig. 9–10): every point the
//! figure is made of — metacircle centres, contour and polygon vertices — is carried by the
//! curve warp of [`crate::curve::warp`] (`P = C_k(u_k) + v_k N(u_k)` against each original
//! curve, `P^d = Σ ŵ_k (C_k^d(u_k) + v_k N^d(u_k))`, Beier–Neely weights).
//!
//! Radii and densities are kept, as in P0 ("moving the vertex coordinates by the method
//! above deforms the figure"); polygon edges are divided before warping so that they bend with
//! the curves. Curves that did not move warp nothing: the warp by unchanged curves is the
//! identity, and then no edge is divided either (the polygons keep their vertices).

use glam::DVec2;

use crate::curve::Curve;
use crate::curve::warp::{CurveWarp, WarpParams};
use crate::curve::warp_work::check_warp_work;

use super::contour::Contour;
use super::document::{FigureDocument, FilledPolygon};
use super::error::FigureError;
use super::metacircle::Figure;

/// How a figure is warped.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WarpOptions {
    /// The Beier–Neely weights.
    pub params: WarpParams,
    /// Polygon edges longer than this are divided before warping (`None`: 1/200 of the
    /// diagonal of the document's frame; `f64::INFINITY`: none). Ignored when no curve moved.
    pub max_edge: Option<f64>,
}

/// The warp taking `originals[k]` to `deformed[k]`, to carry `points` points: its work,
/// `pairs × points` weight evaluations, is checked against the cap of
/// [`crate::curve::warp_work`] before the warp is built. Every warp of the figure part is made
/// here.
///
/// # Errors
/// [`FigureError::Mismatch`] when the lists differ in length, [`FigureError::WarpTooLarge`]
/// over the cap, [`FigureError::Warp`] when the curve warp refuses them.
pub fn curve_warp(
    originals: &[Curve<DVec2>],
    deformed: &[Curve<DVec2>],
    params: WarpParams,
    points: u64,
) -> Result<CurveWarp<DVec2>, FigureError> {
    if originals.len() != deformed.len() {
        return Err(FigureError::Mismatch {
            what: "original and deformed curves".into(),
            left: originals.len(),
            right: deformed.len(),
        });
    }
    check_warp_work(originals.len() as u64, points)?;
    CurveWarp::new(
        originals
            .iter()
            .cloned()
            .zip(deformed.iter().cloned())
            .collect(),
        params,
    )
    .map_err(FigureError::Warp)
}

/// The vertices a contour has once its edges are divided so that none is longer than
/// `max_edge` (`Σ max(1, ⌈|e| / max_edge⌉)` over its edges; its own vertex count when
/// `max_edge` is not a positive finite number), as a float: it may be beyond any integer.
#[must_use]
pub fn divided_vertices(contour: &Contour, max_edge: f64) -> f64 {
    if max_edge.is_finite() && max_edge > 0.0 {
        contour
            .edges()
            .map(|(a, b)| (a.distance(b) / max_edge).ceil().max(1.0))
            .sum()
    } else {
        contour.points().len() as f64
    }
}

/// A vertex count of [`divided_vertices`] as a whole number (saturating).
pub(crate) fn whole(n: f64) -> u64 {
    if n >= u64::MAX as f64 {
        u64::MAX
    } else {
        n as u64
    }
}

/// The figure with every metacircle centre warped.
#[must_use]
pub fn warp_figure(figure: &Figure, warp: &CurveWarp<DVec2>) -> Figure {
    let mut out = figure.clone();
    out.map_centres(|p| warp.warp_point(p));
    out
}

/// Most vertices a warped contour may get from dividing its edges.
pub const MAX_WARPED_VERTICES: usize = 1_000_000;

/// A contour warped, its edges divided first so that none is longer than `max_edge`.
///
/// # Errors
/// [`FigureError::Warp`] for a bad `max_edge`, [`FigureError::Option`] when the division would
/// make more than [`MAX_WARPED_VERTICES`] vertices, [`FigureError::Contour`] if the warped
/// polygon degenerates.
pub fn warp_contour(
    contour: &Contour,
    warp: &CurveWarp<DVec2>,
    max_edge: f64,
    what: &str,
) -> Result<Contour, FigureError> {
    if max_edge.is_finite() && max_edge > 0.0 {
        let pieces = divided_vertices(contour, max_edge);
        if pieces > MAX_WARPED_VERTICES as f64 {
            return Err(FigureError::Option(format!(
                "{what}: edges divided to at most {} would make {:.0} vertices (at most {MAX_WARPED_VERTICES})",
                crate::num::Compact(max_edge),
                crate::num::Compact(pieces)
            )));
        }
    }
    let pts = warp
        .warp_polygon(contour.points(), max_edge)
        .map_err(FigureError::Warp)?;
    Contour::new(pts, what)
}

/// A figure document warped by moving its curves to `deformed` (curve `k` of the document to
/// `deformed[k]`): metacircles, contour and polygons follow, and the document's curves become
/// the deformed ones.
///
/// # Errors
/// As [`curve_warp`] (the work counts every metacircle centre and every vertex of the divided
/// contour and polygons) and [`warp_contour`]; [`FigureError::Option`] for a `max_edge` that
/// is not positive.
pub fn warp_document(
    doc: &FigureDocument,
    deformed: &[Curve<DVec2>],
    options: &WarpOptions,
) -> Result<FigureDocument, FigureError> {
    let moved = doc.curves.as_slice() != deformed;
    let max_edge = match options.max_edge {
        // Nothing moves: dividing the edges would only add vertices on them.
        _ if !moved => f64::INFINITY,
        Some(m) if m.is_nan() || m <= 0.0 => {
            return Err(FigureError::Option(format!(
                "the longest polygon edge must be a positive number, got {m}"
            )));
        }
        Some(m) => m,
        None => doc
            .frame()
            .map_or(f64::INFINITY, |(lo, hi)| (hi - lo).length() / 200.0),
    };
    let max_edge = if max_edge > 0.0 {
        max_edge
    } else {
        f64::INFINITY
    };
    // The points carried: every centre and every vertex of the divided outlines.
    let points = doc.figure.metacircles.len() as f64
        + doc
            .contour
            .iter()
            .chain(doc.polygons.iter().map(|p| &p.contour))
            .map(|c| divided_vertices(c, max_edge))
            .sum::<f64>();
    let warp = curve_warp(&doc.curves, deformed, options.params, whole(points))?;
    let contour = match &doc.contour {
        Some(c) => Some(warp_contour(c, &warp, max_edge, "warped contour")?),
        None => None,
    };
    let polygons = doc
        .polygons
        .iter()
        .enumerate()
        .map(|(i, p)| {
            Ok(FilledPolygon {
                contour: warp_contour(&p.contour, &warp, max_edge, &format!("warped polygon {i}"))?,
                colour: p.colour,
            })
        })
        .collect::<Result<Vec<_>, FigureError>>()?;
    Ok(FigureDocument {
        name: doc.name.clone(),
        figure: warp_figure(&doc.figure, &warp),
        view: doc.view,
        background: doc.background,
        contour,
        polygons,
        curves: deformed.to_vec(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::Bezier;
    use crate::figure::Metacircle;

    fn line(a: DVec2, b: DVec2) -> Curve<DVec2> {
        Bezier::new(vec![a, a.lerp(b, 1.0 / 3.0), a.lerp(b, 2.0 / 3.0), b]).into()
    }

    #[test]
    fn unchanged_curves_are_the_identity() {
        let curves = vec![
            line(DVec2::ZERO, DVec2::new(10.0, 0.0)),
            line(DVec2::new(0.0, 5.0), DVec2::new(10.0, 8.0)),
        ];
        let doc = FigureDocument {
            figure: Figure::new(vec![
                Metacircle::new(DVec2::new(3.0, 2.0), 2.0, 1.0),
                Metacircle::new(DVec2::new(7.0, -1.0), 1.0, 0.5),
            ]),
            contour: Some(
                Contour::new(
                    vec![DVec2::ZERO, DVec2::new(9.0, 1.0), DVec2::new(4.0, 6.0)],
                    "c",
                )
                .unwrap(),
            ),
            curves: curves.clone(),
            ..Default::default()
        };
        // Whatever the longest edge asked for: unchanged curves divide no edge.
        for max_edge in [None, Some(0.01), Some(f64::INFINITY)] {
            let out = warp_document(
                &doc,
                &curves,
                &WarpOptions {
                    max_edge,
                    ..Default::default()
                },
            )
            .unwrap();
            assert_eq!(out, doc);
        }
    }

    #[test]
    fn a_translated_curve_carries_the_figure() {
        let c = line(DVec2::ZERO, DVec2::new(10.0, 0.0));
        let moved = line(DVec2::new(1.0, 2.0), DVec2::new(11.0, 2.0));
        let doc = FigureDocument {
            figure: Figure::new(vec![Metacircle::new(DVec2::new(4.0, 3.0), 2.0, 1.0)]),
            curves: vec![c],
            ..Default::default()
        };
        let out =
            warp_document(&doc, std::slice::from_ref(&moved), &WarpOptions::default()).unwrap();
        assert!((out.figure.metacircles[0].centre - DVec2::new(5.0, 5.0)).length() < 1e-9);
        assert!(warp_document(&doc, &[], &WarpOptions::default()).is_err());
        let bad = WarpOptions {
            max_edge: Some(-1.0),
            ..Default::default()
        };
        assert!(warp_document(&doc, std::slice::from_ref(&moved), &bad).is_err());
    }
}
