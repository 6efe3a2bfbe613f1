//! Pictures of a figure document: the PNG-ready image (polygons, then the figure, over the
//! background) and the SVG of the same view (polygons, the traced boundary, the curves).

use glam::DVec2;

use crate::curve::Curve;

use super::contour::Contour;
use super::document::{FigureDocument, FilledPolygon};
use super::error::FigureError;
use super::iso::{IsoLine, Lattice, iso_lines};
use super::metacircle::{Figure, Rgb};
use super::raster::{Image, ImageSize, RasterView, compose, coverage};
use super::svg::{SvgLayers, figure_svg, mean_colour};

/// How pictures are made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PictureOptions {
    /// Image size.
    pub size: ImageSize,
    /// Supersampling of boundary pixels per axis (1..=16).
    pub samples: u32,
    /// Pixels left free around the frame.
    pub margin: f64,
    /// Draw the curves in the SVG.
    pub curves: bool,
}

impl Default for PictureOptions {
    fn default() -> Self {
        Self {
            size: ImageSize {
                width: 512,
                height: 512,
            },
            samples: 4,
            margin: 0.0,
            curves: true,
        }
    }
}

/// A picture: the view it was drawn in, the image, the traced boundary and the SVG text.
#[derive(Debug, Clone, PartialEq)]
pub struct Picture {
    /// Figure units to pixels.
    pub view: RasterView,
    /// The image (RGBA).
    pub image: Image,
    /// The iso-curve, traced on the pixel lattice and refined onto the curve (figure units).
    pub boundary: Vec<IsoLine>,
    /// The SVG document.
    pub svg: String,
}

/// What to draw besides the figure.
#[derive(Debug, Clone, Copy, Default)]
pub struct Backdrop<'a> {
    /// Background (`None`: transparent).
    pub background: Option<Rgb>,
    /// Polygons under the figure.
    pub polygons: &'a [FilledPolygon],
    /// Curves (SVG only).
    pub curves: &'a [Curve<DVec2>],
}

/// Draws a document in its frame (its `view`, else its bounds with a 4 % margin).
///
/// # Errors
/// [`FigureError::Empty`] for a document with nothing to frame, and the errors of [`draw`].
pub fn picture(doc: &FigureDocument, options: &PictureOptions) -> Result<Picture, FigureError> {
    let (lo, hi) = doc
        .frame()
        .ok_or_else(|| FigureError::Empty("the document has nothing to draw".into()))?;
    let (lo, hi) = if doc.view.is_some() {
        (lo, hi)
    } else {
        let pad = 0.04 * (hi - lo).max_element();
        (lo - DVec2::splat(pad), hi + DVec2::splat(pad))
    };
    let view = RasterView::fit(lo, hi, options.size, options.margin);
    let backdrop = Backdrop {
        background: Some(doc.background.unwrap_or(Rgb::WHITE)),
        polygons: &doc.polygons,
        curves: if options.curves { &doc.curves } else { &[] },
    };
    draw(&doc.figure, &backdrop, &view, options)
}

/// Draws a figure and its backdrop in a given view.
///
/// # Errors
/// [`FigureError`] for an invalid figure, view or option.
pub fn draw(
    figure: &Figure,
    backdrop: &Backdrop<'_>,
    view: &RasterView,
    options: &PictureOptions,
) -> Result<Picture, FigureError> {
    let size = options.size;
    let mut cov = coverage(figure, view, size, options.samples)?;
    // Polygons go under the figure: "figure over polygon" per pixel, in linear light.
    if !backdrop.polygons.is_empty() {
        let mut under_alpha = vec![0.0f32; cov.alpha.len()];
        let mut under_colour = vec![[0.0f32; 3]; cov.alpha.len()];
        for p in backdrop.polygons {
            let a = polygon_coverage(&p.contour, view, size, options.samples.max(1) as usize);
            let c = p.colour.0.map(srgb_to_linear);
            for k in 0..a.len() {
                let (ua, pa) = (under_alpha[k], a[k]);
                let out = pa + ua * (1.0 - pa);
                if out > 0.0 {
                    for (u, c) in under_colour[k].iter_mut().zip(c) {
                        *u = (c * pa + *u * ua * (1.0 - pa)) / out;
                    }
                }
                under_alpha[k] = out;
            }
        }
        for k in 0..cov.alpha.len() {
            let (fa, ua) = (cov.alpha[k], under_alpha[k]);
            let out = fa + ua * (1.0 - fa);
            if out > 0.0 {
                for (f, u) in cov.colour[k].iter_mut().zip(under_colour[k]) {
                    *f = (*f * fa + u * ua * (1.0 - fa)) / out;
                }
            }
            cov.alpha[k] = out;
        }
    }
    let image = compose(&cov, backdrop.background);
    let lattice = Lattice {
        origin: view.origin,
        step: 1.0 / view.scale,
        cells: (size.width as usize, size.height as usize),
    };
    let boundary = iso_lines(figure, &lattice, 4);
    let svg = figure_svg(
        &boundary,
        mean_colour(figure),
        view,
        size,
        &SvgLayers {
            background: backdrop.background,
            polygons: backdrop.polygons,
            curves: backdrop.curves,
        },
    );
    Ok(Picture {
        view: *view,
        image,
        boundary,
        svg,
    })
}

fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The fraction of each pixel inside a polygon (even–odd): `n` scanlines per pixel row, each
/// span's overlap with a pixel measured exactly along x.
#[must_use]
pub fn polygon_coverage(
    contour: &Contour,
    view: &RasterView,
    size: ImageSize,
    n: usize,
) -> Vec<f32> {
    let (w, h) = (size.width as usize, size.height as usize);
    let mut out = vec![0.0f32; w * h];
    let pts: Vec<DVec2> = contour.points().iter().map(|&p| view.to_pixel(p)).collect();
    let m = pts.len();
    let weight = 1.0 / n as f32;
    let mut xs: Vec<f64> = Vec::new();
    for j in 0..h {
        for s in 0..n {
            let y = j as f64 + (s as f64 + 0.5) / n as f64;
            xs.clear();
            for i in 0..m {
                let (a, b) = (pts[i], pts[(i + 1) % m]);
                if (a.y > y) != (b.y > y) {
                    xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
                }
            }
            xs.sort_by(f64::total_cmp);
            for span in xs.chunks_exact(2) {
                let (x0, x1) = (span[0].clamp(0.0, w as f64), span[1].clamp(0.0, w as f64));
                if x1 <= x0 {
                    continue;
                }
                let (i0, i1) = (x0.floor() as usize, (x1.ceil() as usize).min(w));
                for i in i0..i1 {
                    let overlap = (x1.min(i as f64 + 1.0) - x0.max(i as f64)).max(0.0);
                    out[j * w + i] += weight * overlap as f32;
                }
            }
        }
    }
    for a in &mut out {
        *a = a.min(1.0);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figure::Metacircle;

    #[test]
    fn polygon_coverage_sums_to_the_area() {
        let c = Contour::new(
            vec![
                DVec2::new(3.3, 2.1),
                DVec2::new(40.7, 9.0),
                DVec2::new(20.2, 30.5),
            ],
            "tri",
        )
        .unwrap();
        let size = ImageSize::new(50, 40).unwrap();
        let view = RasterView {
            origin: DVec2::ZERO,
            scale: 1.0,
        };
        let a: f64 = polygon_coverage(&c, &view, size, 8)
            .iter()
            .map(|&a| a as f64)
            .sum();
        assert!(
            (a - c.signed_area().abs()).abs() < 0.5,
            "{a} vs {}",
            c.signed_area()
        );
    }

    #[test]
    fn picture_of_a_document() {
        let doc = FigureDocument {
            figure: Figure::new(vec![Metacircle::new(DVec2::new(50.0, 50.0), 60.0, 1.0)]),
            polygons: vec![FilledPolygon {
                contour: Contour::new(
                    vec![
                        DVec2::ZERO,
                        DVec2::new(100.0, 0.0),
                        DVec2::new(100.0, 10.0),
                        DVec2::new(0.0, 10.0),
                    ],
                    "bar",
                )
                .unwrap(),
                colour: Rgb([0, 0, 255]),
            }],
            ..Default::default()
        };
        let p = picture(
            &doc,
            &PictureOptions {
                size: ImageSize::new(64, 64).unwrap(),
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(p.boundary.len(), 1);
        let centre = p.view.to_pixel(DVec2::new(50.0, 50.0));
        assert_eq!(
            p.image.pixel(centre.x as u32, centre.y as u32),
            [0x8a, 0x5a, 0x3c, 255]
        );
        let bar = p.view.to_pixel(DVec2::new(5.0, 5.0));
        assert_eq!(p.image.pixel(bar.x as u32, bar.y as u32), [0, 0, 255, 255]);
        assert!(p.svg.contains("#0000ff"));
    }
}
