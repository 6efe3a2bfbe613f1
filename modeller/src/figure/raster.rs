//! Drawing a figure into an RGBA image, anti-aliased.
//!
//! The density is evaluated once at every pixel corner through a [`CircleGrid`] whose cells are
//! 16 × 16-pixel tiles (each tile sums only the metacircles whose support touches it). A pixel
//! whose four corners lie on one side of the threshold is taken as wholly inside or outside; a
//! pixel the iso-curve crosses is supersampled on an `n × n` grid (`n = 4` by default) and its
//! coverage is the fraction of samples inside. Colours are blended in linear light. Features
//! thinner than a pixel that cross no pixel corner are missed, as in any point-sampled raster.
//!
//! The colour inside is the mean of the metacircles' colours weighted by their positive
//! contributions `max(q_i f_i, 0)`.

use glam::DVec2;

use super::error::FigureError;
use super::index::CircleGrid;
use super::metacircle::{Figure, Rgb};

/// Side of the tiles, in pixels.
pub const TILE: usize = 16;

/// The map from figure coordinates to pixels: `pixel = (p − origin) · scale`. Both have y
/// pointing down (figures use SVG's convention); pixel `(i, j)` covers `[i, i+1] × [j, j+1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RasterView {
    /// The figure point at the image's top-left corner.
    pub origin: DVec2,
    /// Pixels per figure unit.
    pub scale: f64,
}

impl RasterView {
    /// The view that shows `[min, max]` centred in a `width × height` image with `margin`
    /// pixels left free on every side, at a uniform scale.
    #[must_use]
    pub fn fit(min: DVec2, max: DVec2, size: ImageSize, margin: f64) -> Self {
        let span = (max - min).max(DVec2::splat(1e-12));
        let free = DVec2::new(size.width as f64, size.height as f64) - 2.0 * margin;
        let scale = (free.x / span.x).min(free.y / span.y).max(1e-12);
        let centre = 0.5 * (min + max);
        let half = DVec2::new(size.width as f64, size.height as f64) * 0.5 / scale;
        Self {
            origin: centre - half,
            scale,
        }
    }

    /// The pixel position of a figure point.
    #[must_use]
    pub fn to_pixel(&self, p: DVec2) -> DVec2 {
        (p - self.origin) * self.scale
    }

    /// The figure point at a pixel position.
    #[must_use]
    pub fn to_figure(&self, px: DVec2) -> DVec2 {
        self.origin + px / self.scale
    }

    /// Checks that the view is finite with a positive scale.
    ///
    /// # Errors
    /// [`FigureError::Option`].
    pub fn validate(&self) -> Result<(), FigureError> {
        if self.origin.is_finite() && self.scale.is_finite() && self.scale > 0.0 {
            Ok(())
        } else {
            Err(FigureError::Option(format!(
                "invalid view: origin {} scale {}",
                self.origin, self.scale
            )))
        }
    }
}

/// An image size in pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ImageSize {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
}

impl ImageSize {
    /// Largest side accepted.
    pub const MAX_SIDE: u32 = 16_384;

    /// Most pixels in a picture: 8192 × 8192 = 67 108 864, about 1 GB at the peak of drawing
    /// and encoding ([`Self::BYTES_PER_PIXEL`] each).
    pub const MAX_PIXELS: u64 = 8192 * 8192;
    /// Peak memory per pixel while drawing and encoding, measured: `16384x16384` took 4.2 GB,
    /// 16 bytes a pixel (the RGBA image, the coverage and density planes, the PNG's copy).
    pub const BYTES_PER_PIXEL: u64 = 16;

    /// A size, checked to be 1..=[`Self::MAX_SIDE`] on each side and at most
    /// [`Self::MAX_PIXELS`] in all (refused with the memory it would take).
    ///
    /// # Errors
    /// [`FigureError::Option`].
    pub fn new(width: u32, height: u32) -> Result<Self, FigureError> {
        let pixels = u64::from(width) * u64::from(height);
        let sides = (1..=Self::MAX_SIDE).contains(&width) && (1..=Self::MAX_SIDE).contains(&height);
        if sides && pixels > Self::MAX_PIXELS {
            Err(FigureError::Option(format!(
                "image size {width}x{height}: {pixels} pixels would take about {:.1} GB while drawing; at most {} pixels (8192x8192, about {:.1} GB)",
                (pixels * Self::BYTES_PER_PIXEL) as f64 / 1e9,
                Self::MAX_PIXELS,
                (Self::MAX_PIXELS * Self::BYTES_PER_PIXEL) as f64 / 1e9,
            )))
        } else if sides {
            Ok(Self { width, height })
        } else {
            Err(FigureError::Option(format!(
                "image size {width}x{height}: each side must be 1 to {}",
                Self::MAX_SIDE
            )))
        }
    }
}

/// How a figure is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RasterStyle {
    /// The background colour; `None` for a transparent background (alpha = coverage).
    pub background: Option<Rgb>,
    /// Supersampling of boundary pixels: `n × n` samples (1..=16).
    pub samples: u32,
}

impl Default for RasterStyle {
    fn default() -> Self {
        Self {
            background: Some(Rgb::WHITE),
            samples: 4,
        }
    }
}

/// An 8-bit RGBA image (sRGB, straight alpha), rows top to bottom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// Size in pixels.
    pub size: ImageSize,
    /// `4 · width · height` bytes.
    pub pixels: Vec<u8>,
}

impl Image {
    /// The RGBA bytes of pixel `(x, y)`.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = 4 * (y as usize * self.size.width as usize + x as usize);
        [
            self.pixels[i],
            self.pixels[i + 1],
            self.pixels[i + 2],
            self.pixels[i + 3],
        ]
    }
}

/// The fraction of each pixel inside a figure (row-major), and the linear-light colour there.
#[derive(Debug, Clone, PartialEq)]
pub struct Coverage {
    /// Size in pixels.
    pub size: ImageSize,
    /// Coverage in `[0, 1]` per pixel.
    pub alpha: Vec<f32>,
    /// Linear-light RGB of the figure per pixel (meaningful where `alpha > 0`).
    pub colour: Vec<[f32; 3]>,
}

/// Linear-light value of an sRGB byte.
fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

struct Gamma {
    to_linear: [f32; 256],
    to_srgb: Vec<u8>,
}

const TO_SRGB_STEPS: usize = 4096;

impl Gamma {
    fn new() -> Self {
        let mut to_linear = [0.0f32; 256];
        for (i, v) in to_linear.iter_mut().enumerate() {
            *v = srgb_to_linear(i as u8);
        }
        let to_srgb = (0..=TO_SRGB_STEPS)
            .map(|i| {
                let l = i as f32 / TO_SRGB_STEPS as f32;
                let s = if l <= 0.003_130_8 {
                    12.92 * l
                } else {
                    1.055 * l.powf(1.0 / 2.4) - 0.055
                };
                (s * 255.0).round().clamp(0.0, 255.0) as u8
            })
            .collect();
        Self { to_linear, to_srgb }
    }

    fn encode(&self, l: f32) -> u8 {
        let i = (l.clamp(0.0, 1.0) * TO_SRGB_STEPS as f32).round() as usize;
        self.to_srgb[i.min(TO_SRGB_STEPS)]
    }
}

/// One metacircle, prepared for the inner loop.
#[derive(Clone, Copy)]
struct Prepared {
    centre: DVec2,
    inv_r2: f64,
    q: f64,
    colour: [f32; 3],
}

impl Prepared {
    /// Density contribution and its colour weight at `p`.
    #[inline]
    fn eval(&self, p: DVec2) -> f64 {
        let s = (p - self.centre).length_squared() * self.inv_r2;
        self.q * super::falloff::density(s)
    }
}

/// Fills `local` with the metacircles of grid cell `(ix, iy)`.
fn prepare_tile(
    grid: &CircleGrid<'_>,
    ix: usize,
    iy: usize,
    gamma: &Gamma,
    local: &mut Vec<Prepared>,
) {
    local.clear();
    local.extend(grid.cell_circles(ix, iy).map(|m| Prepared {
        centre: m.centre,
        inv_r2: 1.0 / (m.radius * m.radius),
        q: m.density,
        colour: m.colour.0.map(|c| gamma.to_linear[c as usize]),
    }));
}

/// Density and weighted colour at `p` from a tile's metacircles.
#[inline]
fn shade(circles: &[Prepared], p: DVec2) -> (f64, [f32; 4]) {
    let mut f = 0.0;
    let mut acc = [0.0f32; 4];
    for c in circles {
        let v = c.eval(p);
        f += v;
        if v > 0.0 {
            let w = v as f32;
            acc[0] += w * c.colour[0];
            acc[1] += w * c.colour[1];
            acc[2] += w * c.colour[2];
            acc[3] += w;
        }
    }
    (f, acc)
}

/// The coverage and colour of every pixel.
///
/// # Errors
/// [`FigureError`] when the figure or the view is invalid or `samples` is outside 1..=16.
pub fn coverage(
    figure: &Figure,
    view: &RasterView,
    size: ImageSize,
    samples: u32,
) -> Result<Coverage, FigureError> {
    figure.validate()?;
    view.validate()?;
    if !(1..=16).contains(&samples) {
        return Err(FigureError::Option(format!(
            "samples per axis must be 1 to 16, got {samples}"
        )));
    }
    let gamma = Gamma::new();
    let (w, h) = (size.width as usize, size.height as usize);
    let tile_world = TILE as f64 / view.scale;
    let grid = CircleGrid::new(
        &figure.metacircles,
        view.origin,
        view.to_figure(DVec2::new(w as f64, h as f64)),
        tile_world,
    );
    let (gnx, gny) = grid.cells();
    let t = figure.threshold;
    let inv_scale = 1.0 / view.scale;
    let (tiles_x, tiles_y) = (w.div_ceil(TILE), h.div_ceil(TILE));
    // Density and weighted colour at every pixel corner.
    let cw = w + 1;
    let mut corner_f = vec![0.0f64; cw * (h + 1)];
    let mut corner_c = vec![[0.0f32; 4]; cw * (h + 1)];
    let mut alpha = vec![0.0f32; w * h];
    let mut colour = vec![[0.0f32; 3]; w * h];
    let mut local: Vec<Prepared> = Vec::new();
    let n = samples as usize;
    let sub = 1.0 / n as f64;
    for ty in 0..tiles_y {
        for tx in 0..tiles_x {
            prepare_tile(&grid, tx.min(gnx - 1), ty.min(gny - 1), &gamma, &mut local);
            let (x0, y0) = (tx * TILE, ty * TILE);
            let x1 = if tx + 1 == tiles_x { w + 1 } else { x0 + TILE };
            let y1 = if ty + 1 == tiles_y { h + 1 } else { y0 + TILE };
            if local.is_empty() {
                continue; // corners stay at density 0; pixels stay empty
            }
            for j in y0..y1 {
                for i in x0..x1 {
                    let p = view.origin + DVec2::new(i as f64, j as f64) * inv_scale;
                    let (f, c) = shade(&local, p);
                    corner_f[j * cw + i] = f;
                    corner_c[j * cw + i] = c;
                }
            }
        }
    }
    for ty in 0..tiles_y {
        for tx in 0..tiles_x {
            let (x0, y0) = (tx * TILE, ty * TILE);
            let (x1, y1) = ((x0 + TILE).min(w), (y0 + TILE).min(h));
            let mut prepared = false;
            for j in y0..y1 {
                for i in x0..x1 {
                    let k = [
                        j * cw + i,
                        j * cw + i + 1,
                        (j + 1) * cw + i,
                        (j + 1) * cw + i + 1,
                    ];
                    let inside = k.iter().filter(|&&k| corner_f[k] >= t).count();
                    let px = j * w + i;
                    if inside == 0 {
                        continue;
                    }
                    if inside == 4 {
                        alpha[px] = 1.0;
                        colour[px] = mean_colour(k.iter().map(|&k| corner_c[k]));
                        continue;
                    }
                    if !prepared {
                        prepare_tile(&grid, tx.min(gnx - 1), ty.min(gny - 1), &gamma, &mut local);
                        prepared = true;
                    }
                    let mut hits = 0usize;
                    let mut acc = [0.0f32; 4];
                    for b in 0..n {
                        for a in 0..n {
                            let q = DVec2::new(
                                i as f64 + (a as f64 + 0.5) * sub,
                                j as f64 + (b as f64 + 0.5) * sub,
                            );
                            let (f, c) = shade(&local, view.origin + q * inv_scale);
                            if f >= t {
                                hits += 1;
                                let norm = if c[3] > 0.0 { 1.0 / c[3] } else { 0.0 };
                                for ch in 0..3 {
                                    acc[ch] += c[ch] * norm;
                                }
                            }
                        }
                    }
                    if hits > 0 {
                        alpha[px] = hits as f32 / (n * n) as f32;
                        colour[px] = [
                            acc[0] / hits as f32,
                            acc[1] / hits as f32,
                            acc[2] / hits as f32,
                        ];
                    }
                }
            }
        }
    }
    Ok(Coverage {
        size,
        alpha,
        colour,
    })
}

/// Mean of normalised weighted colours.
fn mean_colour(cs: impl Iterator<Item = [f32; 4]>) -> [f32; 3] {
    let mut out = [0.0f32; 3];
    let mut k = 0.0f32;
    for c in cs {
        if c[3] > 0.0 {
            for ch in 0..3 {
                out[ch] += c[ch] / c[3];
            }
            k += 1.0;
        }
    }
    if k > 0.0 {
        for v in &mut out {
            *v /= k;
        }
    }
    out
}

/// Draws a figure: the region `F ≥ T` filled with its colours over the background,
/// anti-aliased.
///
/// # Errors
/// As [`coverage`].
pub fn render(
    figure: &Figure,
    view: &RasterView,
    size: ImageSize,
    style: &RasterStyle,
) -> Result<Image, FigureError> {
    let cov = coverage(figure, view, size, style.samples)?;
    Ok(compose(&cov, style.background))
}

/// Turns a coverage into pixels over a background (or transparent).
#[must_use]
pub fn compose(cov: &Coverage, background: Option<Rgb>) -> Image {
    let gamma = Gamma::new();
    let mut pixels = vec![0u8; 4 * cov.alpha.len()];
    let bg = background.map(|b| b.0.map(|c| gamma.to_linear[c as usize]));
    for (k, (&a, c)) in cov.alpha.iter().zip(&cov.colour).enumerate() {
        let px = &mut pixels[4 * k..4 * k + 4];
        match bg {
            Some(bg) => {
                for ch in 0..3 {
                    px[ch] = gamma.encode(bg[ch] + (c[ch] - bg[ch]) * a);
                }
                px[3] = 255;
            }
            None => {
                for ch in 0..3 {
                    px[ch] = gamma.encode(c[ch]);
                }
                px[3] = (a * 255.0).round() as u8;
            }
        }
    }
    Image {
        size: cov.size,
        pixels,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::figure::Metacircle;

    #[test]
    fn lone_circle_area_matches_pi_r_squared() {
        // Iso-circle radius R/2 = 100 px; coverage sums to its area within the AA error.
        let fig = Figure::new(vec![Metacircle::new(DVec2::new(256.0, 256.0), 200.0, 1.0)]);
        let size = ImageSize::new(512, 512).unwrap();
        let view = RasterView {
            origin: DVec2::ZERO,
            scale: 1.0,
        };
        let cov = coverage(&fig, &view, size, 4).unwrap();
        let area: f64 = cov.alpha.iter().map(|&a| a as f64).sum();
        let exact = std::f64::consts::PI * 100.0 * 100.0;
        assert!(
            (area - exact).abs() / exact < 2e-3,
            "area {area} vs {exact}"
        );
        // Supersampled edge pixels exist and lie on the circle.
        let partial = cov.alpha.iter().filter(|&&a| a > 0.0 && a < 1.0).count();
        assert!(partial > 400 && partial < 1600, "{partial}");
    }

    #[test]
    fn matches_brute_force_point_sampling() {
        // Pixel centres inside/outside by the brute-force field agree with the coverage
        // wherever the coverage is 0 or 1.
        let fig = Figure::new(vec![
            Metacircle::new(DVec2::new(20.0, 30.0), 30.0, 1.0),
            Metacircle::new(DVec2::new(45.0, 30.0), 25.0, 1.0),
            Metacircle::new(DVec2::new(35.0, 40.0), 15.0, -0.8),
        ]);
        let size = ImageSize::new(70, 61).unwrap();
        let view = RasterView {
            origin: DVec2::new(-2.0, 1.0),
            scale: 1.0,
        };
        let cov = coverage(&fig, &view, size, 4).unwrap();
        for j in 0..61 {
            for i in 0..70 {
                let a = cov.alpha[j * 70 + i];
                let inside =
                    fig.contains(view.to_figure(DVec2::new(i as f64 + 0.5, j as f64 + 0.5)));
                if a == 1.0 {
                    assert!(inside, "{i},{j}");
                } else if a == 0.0 {
                    assert!(!inside, "{i},{j}");
                }
            }
        }
    }

    #[test]
    fn colours_and_background() {
        let mut m = Metacircle::new(DVec2::new(8.0, 8.0), 12.0, 1.0);
        m.colour = Rgb([255, 0, 0]);
        let fig = Figure::new(vec![m]);
        let size = ImageSize::new(16, 16).unwrap();
        let view = RasterView {
            origin: DVec2::ZERO,
            scale: 1.0,
        };
        let img = render(&fig, &view, size, &RasterStyle::default()).unwrap();
        assert_eq!(img.pixel(8, 8), [255, 0, 0, 255]);
        assert_eq!(img.pixel(0, 0), [255, 255, 255, 255]);
        let clear = render(
            &fig,
            &view,
            size,
            &RasterStyle {
                background: None,
                samples: 2,
            },
        )
        .unwrap();
        assert_eq!(clear.pixel(0, 0)[3], 0);
        assert!(
            render(
                &fig,
                &view,
                size,
                &RasterStyle {
                    background: None,
                    samples: 0
                }
            )
            .is_err()
        );
    }

    #[test]
    fn fit_view_centres_the_box() {
        let size = ImageSize::new(200, 100).unwrap();
        let v = RasterView::fit(DVec2::new(0.0, 0.0), DVec2::new(10.0, 10.0), size, 10.0);
        assert!((v.scale - 8.0).abs() < 1e-12);
        assert!((v.to_pixel(DVec2::new(5.0, 5.0)) - DVec2::new(100.0, 50.0)).length() < 1e-9);
    }
}
