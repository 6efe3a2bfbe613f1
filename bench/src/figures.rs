//! `nendo bench figures`: the figures of issue 8 — the frame time of a 300-metacircle figure
//! at 512 × 512 (the filled iso-region rasterised, the full picture with its SVG boundary, and
//! one morph frame), the fit time of the shipped figures and their fit residuals, and the
//! metaball torso's fit, drag-and-re-fit and mesh times.
//!
//! Set-up: the shipped `tests/data/figures/horse.json` and `tiger.json` (compiled in).
//!
//! * **Fit**: [`fit_contour`] with the default options (200 medial-axis seeds, Levenberg–
//!   Marquardt, 200 iterations) on each shipped contour, timed over repeated fits; the residual
//!   columns are those of [`FitReport`]: RMS and largest distance from the contour samples to
//!   the iso-curve, and the largest distance from the traced iso-curve back to the contour
//!   (figure units; the figures are about 500 units across, one unit ≈ one pixel at 512²).
//! * **Shipped**: the residual of the metacircles stored in the files, measured, not refitted.
//! * **300 metacircles**: the horse's contour seeded with exactly 300 metacircles on its medial
//!   axis (grid of 384 cells, the fit's starting figure with its densities scaled to the
//!   threshold; seeding is what sets their number and sizes, the optimiser only adjusts them);
//!   the tiger likewise, with as many as its narrower medial axis gives (about 200). Frames are 512 × 512 with 4 × 4 supersampling of boundary pixels:
//!   *render* is the coverage and the composed RGBA image ([`render`]); *picture* adds the
//!   boundary traced for the SVG ([`draw`]); *morph frame* is the interpolated figure
//!   ([`Morph::at`], `t` walking through `[0, 1]`) rendered, horse to tiger through the files'
//!   four curves.
//!
//! * **Torso** (§4.3): the metaball shape of `tests/data/shapes/torso.json` fitted to its five
//!   sections (12 seeds per section); its two front chest curves dragged 3 cm as the file says,
//!   the chest section warped along and the balls re-fitted (warm start); the iso-surface
//!   meshed by marching tetrahedra at 64 cells on the long side. Distances in cm (the torso is
//!   about 36 cm wide and 44 cm tall), from the contour samples to the iso-surface.
//!
//! Times are medians over batches, in CPU time of the measuring thread where Linux reports it
//! ([`super::cpu_median_ns`]).

use std::hint::black_box;

use super::{Table, cpu_median_ns, format_ns};
use nendo::curve::warp::WarpParams;
use nendo::figure::fit::{FitOptions, FitReport, fit_contour, measure};
use nendo::figure::marching::{MeshOptions, iso_surface};
use nendo::figure::morph::{Morph, MorphOptions};
use nendo::figure::optimise::Stopping;
use nendo::figure::picture::{Backdrop, PictureOptions, draw};
use nendo::figure::raster::{RasterStyle, render};
use nendo::figure::shape::{ShapeFitOptions, ShapeFitReport, deform, fit_sections};
use nendo::figure::{FigureDocument, FigureError, ImageSize, RasterView, ShapeDocument};

/// The shipped horse figure file.
pub const HORSE: &str = include_str!("../../tests/data/figures/horse.json");
/// The shipped tiger figure file.
pub const TIGER: &str = include_str!("../../tests/data/figures/tiger.json");
/// The shipped torso shape file (five sections, the chest dragged).
pub const TORSO: &str = include_str!("../../tests/data/shapes/torso.json");

/// Metacircles of the frame-time figure.
pub const FRAME_METACIRCLES: usize = 300;

/// A shipped document with its contour.
///
/// # Errors
/// [`FigureError`] if the compiled-in file does not read (it is tested to).
pub fn shipped(text: &str) -> Result<FigureDocument, FigureError> {
    let doc = FigureDocument::from_json(text)?;
    if doc.contour.is_none() {
        return Err(FigureError::Empty(
            "the shipped figure has no contour".into(),
        ));
    }
    Ok(doc)
}

/// The document with its metacircles replaced by `count` seeded on its contour's medial axis
/// (the fit's starting figure: no optimiser step).
///
/// # Errors
/// [`FigureError::Empty`] without a contour, and the errors of [`fit_contour`].
pub fn seeded(doc: &FigureDocument, count: usize) -> Result<FigureDocument, FigureError> {
    let contour = doc
        .contour
        .as_ref()
        .ok_or_else(|| FigureError::Empty("no contour to seed".into()))?;
    let mut options = FitOptions {
        stopping: Stopping {
            max_iterations: 0,
            ..Stopping::default()
        },
        ..FitOptions::default()
    };
    options.seeds.max_seeds = count;
    options.seeds.resolution = 384;
    let (figure, _) = fit_contour(contour, &options)?;
    Ok(FigureDocument {
        figure,
        ..doc.clone()
    })
}

/// The 512 × 512 view of a document's frame.
fn frame_view(doc: &FigureDocument, size: ImageSize) -> Option<RasterView> {
    doc.frame()
        .map(|(lo, hi)| RasterView::fit(lo, hi, size, 0.0))
}

fn residual_cells(r: &FitReport) -> Vec<String> {
    vec![
        format!("{:.3}", r.rms_distance),
        format!("{:.3}", r.max_distance),
        format!("{:.2}", r.boundary_distance),
        r.guards_violated.to_string(),
    ]
}

/// Runs the suite and returns the report. `scale` multiplies the repetitions (1.0: 3 fits per
/// figure, 15 batches of frames).
#[must_use]
pub fn report(scale: f64) -> String {
    match try_report(scale) {
        Ok(s) => s,
        Err(e) => format!("nendo bench figures: {e}\n"),
    }
}

fn try_report(scale: f64) -> Result<String, FigureError> {
    let fits = ((3.0 * scale).round() as usize).max(1);
    let batches = ((15.0 * scale).round() as usize).max(3);
    let size = ImageSize::new(512, 512)?;
    let mut table = Table::new(&[
        "case",
        "metacircles",
        "median",
        "iterations",
        "rms dist",
        "max dist",
        "iso→contour",
        "guards wrong",
    ]);
    let docs = [("horse", shipped(HORSE)?), ("tiger", shipped(TIGER)?)];
    let defaults = FitOptions::default();
    for (name, doc) in &docs {
        let Some(contour) = doc.contour.as_ref() else {
            continue;
        };
        let shipped_report = measure(
            &doc.figure,
            contour,
            defaults.samples,
            defaults.guard_resolution,
        );
        let mut row = vec![
            format!("{name}: shipped metacircles (measured)"),
            doc.figure.metacircles.len().to_string(),
            String::new(),
            String::new(),
        ];
        row.extend(residual_cells(&shipped_report));
        table.row(row);
        let mut last: Option<FitReport> = None;
        let mut failure = None;
        let ns = cpu_median_ns(fits, 1, |_| match fit_contour(contour, &defaults) {
            Ok((_, r)) => last = Some(r),
            Err(e) => failure = Some(e),
        });
        if let Some(e) = failure {
            return Err(e);
        }
        if let Some(r) = last {
            let mut row = vec![
                format!("{name}: fit to the contour (default options)"),
                r.metacircles.to_string(),
                format_ns(ns),
                r.iterations.to_string(),
            ];
            row.extend(residual_cells(&r));
            table.row(row);
        }
    }

    let horse = seeded(&docs[0].1, FRAME_METACIRCLES)?;
    let tiger = seeded(&docs[1].1, FRAME_METACIRCLES)?;
    let count = horse.figure.metacircles.len();
    let view = frame_view(&horse, size)
        .ok_or_else(|| FigureError::Empty("the horse has no frame".into()))?;
    let style = RasterStyle::default();
    let ns = cpu_median_ns(batches, 1, |_| {
        black_box(render(&horse.figure, &view, size, &style).ok());
    });
    table.row(vec![
        "render 512x512 (filled iso-region, 4x4 AA)".into(),
        count.to_string(),
        format_ns(ns),
    ]);
    let options = PictureOptions {
        size,
        ..PictureOptions::default()
    };
    let backdrop = Backdrop {
        background: horse.background,
        polygons: &[],
        curves: &horse.curves,
    };
    let ns = cpu_median_ns(batches, 1, |_| {
        black_box(draw(&horse.figure, &backdrop, &view, &options).ok());
    });
    table.row(vec![
        "picture 512x512 (render + SVG boundary)".into(),
        count.to_string(),
        format_ns(ns),
    ]);
    let morph = Morph::new(
        (&horse.figure, &horse.curves),
        (&tiger.figure, &tiger.curves),
        MorphOptions::default(),
    )?;
    let both = match (horse.frame(), tiger.frame()) {
        (Some(a), Some(b)) => RasterView::fit(a.0.min(b.0), a.1.max(b.1), size, 0.0),
        _ => view,
    };
    let steps = 16usize;
    let ns = cpu_median_ns(batches, steps, |k| {
        let t = (k % steps) as f64 / (steps - 1) as f64;
        if let Ok(f) = morph.at(t) {
            black_box(render(&f, &both, size, &style).ok());
        }
    });
    table.row(vec![
        format!(
            "morph frame 512x512 (horse → tiger, {} pairs)",
            morph.pairs().len()
        ),
        format!("{count} → {}", tiger.figure.metacircles.len()),
        format_ns(ns),
    ]);
    shape_rows(&mut table, fits, batches)?;
    let mut out = table.render();
    let diagonal = |d: &FigureDocument| {
        d.contour
            .as_ref()
            .map_or(0.0, |c| (c.bounds().1 - c.bounds().0).length())
    };
    out.push_str(&format!(
        "distances in figure units (about pixels at 512x512); contour diagonals: horse {:.0}, tiger {:.0}\n",
        diagonal(&docs[0].1),
        diagonal(&docs[1].1),
    ));
    Ok(out)
}

/// The metaball torso of `tests/data/shapes/torso.json`: fit, drag and re-fit, mesh.
fn shape_rows(table: &mut Table, fits: usize, batches: usize) -> Result<(), FigureError> {
    let doc = ShapeDocument::from_json(TORSO)?;
    let options = ShapeFitOptions::default();
    let mut fitted = None;
    let mut failure = None;
    let ns = cpu_median_ns(fits, 1, |_| match fit_sections(&doc.sections, &options) {
        Ok(f) => fitted = Some(f),
        Err(e) => failure = Some(e),
    });
    if let Some(e) = failure {
        return Err(e);
    }
    let (shape, report) =
        fitted.ok_or_else(|| FigureError::Empty("the torso was not fitted".into()))?;
    let shape_cells = |r: &ShapeFitReport| {
        vec![
            r.iterations.to_string(),
            format!("{:.3}", r.rms_distance),
            format!("{:.3}", r.max_distance),
            String::new(),
            r.guards_violated.to_string(),
        ]
    };
    let mut row = vec![
        format!("torso: fit to {} sections (3D)", doc.sections.len()),
        format!("{} balls", report.balls),
        format_ns(ns),
    ];
    row.extend(shape_cells(&report));
    table.row(row);
    let deformed = doc
        .sections
        .iter()
        .zip(&doc.moves)
        .map(|(s, m)| s.moved_curves(m))
        .collect::<Result<Vec<_>, _>>()?;
    let mut result = None;
    let ns = cpu_median_ns(fits, 1, |_| {
        match deform(
            &shape,
            &doc.sections,
            &deformed,
            WarpParams::default(),
            None,
            &options,
        ) {
            Ok(d) => result = Some(d),
            Err(e) => failure = Some(e),
        }
    });
    if let Some(e) = failure {
        return Err(e);
    }
    if let Some(report) = result.and_then(|d| d.report) {
        let mut row = vec![
            "torso: chest dragged 3 cm, warp + re-fit".into(),
            format!("{} balls", report.balls),
            format_ns(ns),
        ];
        row.extend(shape_cells(&report));
        table.row(row);
    }
    let mesh_options = MeshOptions::default();
    let mut triangles = 0;
    let ns = cpu_median_ns(batches, 1, |_| {
        if let Ok(m) = iso_surface(&shape, &mesh_options) {
            triangles = m.triangle_count();
        }
    });
    table.row(vec![
        format!(
            "torso: marching tetrahedra, {} cells on the long side",
            mesh_options.resolution
        ),
        format!("{triangles} triangles"),
        format_ns(ns),
    ]);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_frame_figure_has_300_metacircles() {
        let horse = shipped(HORSE).unwrap();
        let seeded_horse = seeded(&horse, FRAME_METACIRCLES).unwrap();
        assert_eq!(seeded_horse.figure.metacircles.len(), FRAME_METACIRCLES);
        // It is still the horse: the seeded figure covers the contour's inside.
        let contour = horse.contour.as_ref().unwrap();
        let r = measure(&seeded_horse.figure, contour, 0, 64);
        assert!(r.rms_distance < 0.02 * r.size, "{r:?}");
        let tiger = seeded(&shipped(TIGER).unwrap(), FRAME_METACIRCLES).unwrap();
        assert!(tiger.figure.metacircles.len() > 150);
    }
}
