//! The curvature map's legend drawn into a rendered image (`nendo render --display
//! curvature`): a colour bar of the map's ramp ([`legend_colour`]) with the range's numbers,
//! written with a small built-in 5 × 7 bitmap font, in a dark box at the image's top right.
//!
//! The bar runs from the range's low end (bottom) to its high end (top); each of its pixel rows
//! has the colour a fully lit surface point of that value shows: the ramp's colour at
//! `t = (row's centre from the bottom) / height`, sRGB-encoded as the offscreen target encodes the
//! shader's output. Beside it, right-aligned, the high end, the middle and the low end of the
//! range; above it the curvature's name. An image too small to hold the box gets none
//! ([`draw_legend`] returns `None`).

use super::display_mode::{CurvatureKind, legend_colour};

/// A rectangle of pixels: `x .. x + width`, `y .. y + height` (rows from the top).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelRect {
    /// Left column.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

/// Where the legend went.
#[derive(Debug, Clone, PartialEq)]
pub struct LegendLayout {
    /// The dark box behind it.
    pub panel: PixelRect,
    /// The colour bar (high end at the top).
    pub bar: PixelRect,
    /// The texts drawn: (text, its rectangle).
    pub labels: Vec<(String, PixelRect)>,
    /// The glyphs' scale (pixels per font dot).
    pub scale: u32,
}

/// Width and height of a glyph in font dots, and the gap after it.
const GLYPH: (u32, u32) = (5, 7);
const GAP: u32 = 1;

/// The 5 × 7 glyphs: rows top to bottom, the high bit of 5 the leftmost dot.
fn glyph(c: char) -> [u8; 7] {
    match c {
        '0' => [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E],
        '1' => [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E],
        '2' => [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F],
        '3' => [0x1E, 0x01, 0x01, 0x0E, 0x01, 0x01, 0x1E],
        '4' => [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02],
        '5' => [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E],
        '6' => [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E],
        '7' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E],
        '9' => [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C],
        '-' => [0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00],
        '+' => [0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00],
        '.' => [0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C],
        '/' => [0x01, 0x02, 0x02, 0x04, 0x08, 0x08, 0x10],
        ' ' => [0x00; 7],
        'a' => [0x00, 0x00, 0x0E, 0x01, 0x0F, 0x11, 0x0F],
        'c' => [0x00, 0x00, 0x0E, 0x10, 0x10, 0x11, 0x0E],
        'e' => [0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E],
        'g' => [0x00, 0x0F, 0x11, 0x11, 0x0F, 0x01, 0x0E],
        'i' => [0x04, 0x00, 0x0C, 0x04, 0x04, 0x04, 0x0E],
        'm' => [0x00, 0x00, 0x1A, 0x15, 0x15, 0x11, 0x11],
        'n' => [0x00, 0x00, 0x16, 0x19, 0x11, 0x11, 0x11],
        'r' => [0x00, 0x00, 0x16, 0x19, 0x10, 0x10, 0x10],
        's' => [0x00, 0x00, 0x0F, 0x10, 0x0E, 0x01, 0x1E],
        't' => [0x08, 0x08, 0x1C, 0x08, 0x08, 0x09, 0x06],
        'u' => [0x00, 0x00, 0x11, 0x11, 0x11, 0x13, 0x0D],
        'v' => [0x00, 0x00, 0x11, 0x11, 0x11, 0x0A, 0x04],
        'x' => [0x00, 0x00, 0x11, 0x0A, 0x04, 0x0A, 0x11],
        // Anything else (not expected in a legend): a hollow box, never dropped silently.
        _ => [0x1F, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1F],
    }
}

/// Width of `text` in pixels at `scale`.
fn text_width(text: &str, scale: u32) -> u32 {
    let n = text.chars().count() as u32;
    (n * (GLYPH.0 + GAP)).saturating_sub(GAP) * scale
}

/// A legend number: four significant digits, plain between 10⁻³ and 10⁴, else `d.ddde±x`.
#[must_use]
pub fn label_number(x: f32) -> String {
    let x = f64::from(x);
    let m = x.abs();
    if x == 0.0 {
        return "0".to_owned();
    }
    if (1e-3..1e4).contains(&m) {
        let digits = (3 - m.log10().floor() as i32).clamp(0, 6) as usize;
        let s = format!("{x:.digits$}");
        let s = if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_owned()
        } else {
            s
        };
        if s == "-0" { "0".to_owned() } else { s }
    } else {
        format!("{x:.3e}")
    }
}

/// sRGB encoding of a linear channel (what an `…Srgb` target stores), as a byte.
#[must_use]
pub fn srgb_byte(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// The bar's colour `t` of the way from the low end, as stored in the image.
#[must_use]
pub fn bar_colour(t: f32) -> [u8; 3] {
    legend_colour(t).map(srgb_byte)
}

/// An RGBA8 image to draw into: `4 · width · height` bytes, rows from the top.
struct Canvas<'a> {
    pixels: &'a mut [u8],
    width: u32,
}

impl Canvas<'_> {
    fn put(&mut self, x: u32, y: u32, rgb: [u8; 3]) {
        let i = 4 * (y as usize * self.width as usize + x as usize);
        if let Some(p) = self.pixels.get_mut(i..i + 4) {
            p.copy_from_slice(&[rgb[0], rgb[1], rgb[2], 255]);
        }
    }

    fn fill(&mut self, r: PixelRect, rgb: [u8; 3]) {
        for y in r.y..r.y + r.height {
            for x in r.x..r.x + r.width {
                self.put(x, y, rgb);
            }
        }
    }

    fn text(&mut self, text: &str, x: u32, y: u32, scale: u32, rgb: [u8; 3]) {
        for (k, c) in text.chars().enumerate() {
            let gx = x + k as u32 * (GLYPH.0 + GAP) * scale;
            for (row, bits) in glyph(c).iter().enumerate() {
                for col in 0..GLYPH.0 {
                    if bits & (1 << (GLYPH.0 - 1 - col)) == 0 {
                        continue;
                    }
                    for dy in 0..scale {
                        for dx in 0..scale {
                            self.put(gx + col * scale + dx, y + row as u32 * scale + dy, rgb);
                        }
                    }
                }
            }
        }
    }
}

/// Draws the legend of a curvature map of `range` (`[low, high]`) and `kind` into the RGBA8
/// image `pixels` of `width × height` (rows from the top); `None` (and nothing drawn) when the
/// image is too small for it or `pixels` is not of that size.
pub fn draw_legend(
    pixels: &mut [u8],
    width: u32,
    height: u32,
    range: [f32; 2],
    kind: CurvatureKind,
) -> Option<LegendLayout> {
    if pixels.len() != 4 * width as usize * height as usize {
        return None;
    }
    let scale = if height >= 480 { 2 } else { 1 };
    let line = (GLYPH.1 + 3) * scale;
    let pad = 4 * scale;
    let bar_w = 8 * scale;
    let title = format!("{} curvature", kind.name());
    let [lo, hi] = range;
    let numbers = [hi, 0.5 * (lo + hi), lo].map(label_number);
    let numbers_w = numbers.iter().map(|s| text_width(s, scale)).max()?;
    let bar_h = (height / 3).max(3 * line);
    let inner_w = (numbers_w + pad + bar_w).max(text_width(&title, scale));
    let panel = PixelRect {
        x: width.checked_sub(inner_w + 2 * pad + pad)?,
        y: pad,
        width: inner_w + 2 * pad,
        height: line + bar_h + GLYPH.1 * scale + 2 * pad,
    };
    if panel.y + panel.height > height || panel.x < pad {
        return None;
    }
    let bar = PixelRect {
        x: panel.x + panel.width - pad - bar_w,
        y: panel.y + pad + line + GLYPH.1 * scale / 2,
        width: bar_w,
        height: bar_h,
    };
    let mut canvas = Canvas { pixels, width };
    canvas.fill(panel, [24, 24, 28]);
    for row in 0..bar.height {
        let t = (bar.height - row) as f32 - 0.5;
        let rgb = bar_colour(t / bar.height as f32);
        canvas.fill(
            PixelRect {
                x: bar.x,
                y: bar.y + row,
                width: bar.width,
                height: 1,
            },
            rgb,
        );
    }
    let white = [235, 235, 235];
    let mut labels = Vec::new();
    let title_at = PixelRect {
        x: panel.x + pad,
        y: panel.y + pad,
        width: text_width(&title, scale),
        height: GLYPH.1 * scale,
    };
    canvas.text(&title, title_at.x, title_at.y, scale, white);
    labels.push((title, title_at));
    // High end at the bar's top, middle, low end at its bottom: each text centred on its row.
    let rows = [bar.y, bar.y + bar.height / 2, bar.y + bar.height];
    for (text, row) in numbers.into_iter().zip(rows) {
        let w = text_width(&text, scale);
        let at = PixelRect {
            x: bar.x - pad - w,
            y: row - GLYPH.1 * scale / 2,
            width: w,
            height: GLYPH.1 * scale,
        };
        canvas.text(&text, at.x, at.y, scale, white);
        labels.push((text, at));
    }
    Some(LegendLayout {
        panel,
        bar,
        labels,
        scale,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_four_significant_digits() {
        assert_eq!(label_number(0.333_29), "0.3333");
        assert_eq!(label_number(-1.5), "-1.5");
        assert_eq!(label_number(12.0), "12");
        assert_eq!(label_number(0.0), "0");
        assert_eq!(label_number(2.5e-5), "2.500e-5");
        assert_eq!(label_number(123_456.0), "1.235e5");
    }

    #[test]
    fn every_legend_character_has_its_own_glyph() {
        let boxed = glyph('\u{1}');
        for c in "0123456789-+./ acegimnrstuvx".chars() {
            assert_ne!(glyph(c), boxed, "{c:?}");
        }
        for kind in CurvatureKind::ALL {
            assert!(kind.name().chars().all(|c| glyph(c) != boxed), "{kind:?}");
        }
    }
}
