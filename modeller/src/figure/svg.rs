//! SVG pictures of figures: the traced boundary ([`super::iso`]) as one even–odd filled path,
//! the polygons, and the curves laid over the figure as strokes, in the pixel frame of a
//! [`RasterView`] so that the SVG and the PNG of a figure line up.

use std::fmt::Write;

use glam::DVec2;

use crate::curve::Curve;

use super::document::FilledPolygon;
use super::iso::IsoLine;
use super::metacircle::{Figure, Rgb};
use super::raster::{ImageSize, RasterView};

/// What goes into the picture besides the boundary.
#[derive(Debug, Clone, Copy, Default)]
pub struct SvgLayers<'a> {
    /// Background, or none (transparent).
    pub background: Option<Rgb>,
    /// Polygons drawn under the figure.
    pub polygons: &'a [FilledPolygon],
    /// Curves drawn over it.
    pub curves: &'a [Curve<DVec2>],
}

/// The mean colour of a figure: its metacircles' colours weighted by `q R²` over those of
/// positive density (the clay colour when there is none).
#[must_use]
pub fn mean_colour(figure: &Figure) -> Rgb {
    let mut acc = [0.0f64; 3];
    let mut w = 0.0;
    for m in figure
        .metacircles
        .iter()
        .filter(|m| m.density > 0.0 && m.radius > 0.0)
    {
        let k = m.density * m.radius * m.radius;
        for (a, c) in acc.iter_mut().zip(m.colour.0) {
            *a += k * c as f64;
        }
        w += k;
    }
    if w > 0.0 {
        Rgb(acc.map(|a| (a / w).round().clamp(0.0, 255.0) as u8))
    } else {
        Rgb::CLAY
    }
}

/// An SVG document of `size` pixels: background, polygons, the figure's boundary filled with
/// `fill` (even–odd, so holes stay open) and the curves as dark strokes.
#[must_use]
pub fn figure_svg(
    boundary: &[IsoLine],
    fill: Rgb,
    view: &RasterView,
    size: ImageSize,
    layers: &SvgLayers<'_>,
) -> String {
    let (w, h) = (size.width, size.height);
    let mut s = String::new();
    let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}">"#
    );
    if let Some(b) = layers.background {
        let _ = writeln!(
            s,
            r#"  <rect width="{w}" height="{h}" fill="{}"/>"#,
            b.to_hex()
        );
    }
    for p in layers.polygons {
        let d = path_data(p.contour.points().iter().copied(), true, view);
        let _ = writeln!(s, r#"  <path d="{d}" fill="{}"/>"#, p.colour.to_hex());
    }
    let mut d = String::new();
    for line in boundary.iter().filter(|l| l.points.len() >= 2) {
        if !d.is_empty() {
            d.push(' ');
        }
        d.push_str(&path_data(line.points.iter().copied(), line.closed, view));
    }
    if !d.is_empty() {
        let _ = writeln!(
            s,
            r#"  <path d="{d}" fill="{}" fill-rule="evenodd"/>"#,
            fill.to_hex()
        );
    }
    for c in layers.curves {
        let (a, b) = c.domain();
        let pts = (0..=128).map(|k| c.eval(a + (b - a) * k as f64 / 128.0));
        let d = path_data(pts, false, view);
        let _ = writeln!(
            s,
            r##"  <path d="{d}" fill="none" stroke="#1f3a93" stroke-width="1.5"/>"##
        );
    }
    s.push_str("</svg>\n");
    s
}

fn path_data(points: impl Iterator<Item = DVec2>, closed: bool, view: &RasterView) -> String {
    let mut d = String::new();
    for (i, p) in points.enumerate() {
        let q = view.to_pixel(p);
        let _ = write!(
            d,
            "{}{:.3} {:.3}",
            if i == 0 { "M" } else { " L" },
            q.x,
            q.y
        );
    }
    if closed {
        d.push_str(" Z");
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figure::Metacircle;
    use crate::figure::iso::{Lattice, iso_lines};

    #[test]
    fn svg_holds_one_closed_path_per_loop() {
        let fig = Figure::new(vec![
            Metacircle::new(DVec2::new(5.0, 5.0), 4.0, 1.0),
            Metacircle::new(DVec2::new(20.0, 5.0), 4.0, 1.0),
        ]);
        let lines = iso_lines(&fig, &Lattice::around(&fig, 0.5).unwrap(), 2);
        let size = ImageSize::new(100, 50).unwrap();
        let view = RasterView::fit(DVec2::ZERO, DVec2::new(25.0, 10.0), size, 0.0);
        let svg = figure_svg(
            &lines,
            mean_colour(&fig),
            &view,
            size,
            &SvgLayers {
                background: Some(Rgb::WHITE),
                ..Default::default()
            },
        );
        assert!(svg.starts_with("<?xml"));
        assert_eq!(svg.matches(" Z").count(), 2);
        assert!(svg.contains(&Rgb::CLAY.to_hex()));
        assert!(svg.trim_end().ends_with("</svg>"));
    }
}
