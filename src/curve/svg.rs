//! SVG import and export of planar curves (seed 003 §3.1 kept its curves in SVG): path data with
//! line, quadratic and cubic segments.
//!
//! * Reading ([`read_svg`], [`parse_path_data`]): every `<path d="…">` of a document (comments
//!   skipped; other elements, `transform` attributes and styles ignored), every subpath as a list
//!   of Bezier segments — `L`/`H`/`V` as degree 1, `Q`/`T` as degree 2, `C`/`S` as degree 3, in
//!   absolute and relative forms, with `S`/`T` reflecting the previous control point as the SVG
//!   specification says; `Z` closes the subpath with a line when it is not closed already.
//!   Elliptical arcs (`A`) are refused with an error rather than approximated.
//! * Writing ([`path_data`], [`write_svg`]): segments of degree 1–3 as `L`, `Q`, `C`, consecutive
//!   segments that meet in one subpath. Numbers are written in Rust's shortest round-trip form, so
//!   reading what was written gives back the same control points bit for bit. Higher degrees have
//!   no SVG form and are refused (a B-spline of degree ≤ 3 is written as its Bezier segments).
//!
//! Coordinates are written as they are; SVG's y axis points down, so [`SvgOptions::flip_y`]
//! mirrors y on the way out for curves drawn with y up.

use glam::DVec2;
use nendo_geom::curve::Bezier;
use nendo_geom::curve::Curve;
use nendo_geom::curve::CurveError;
use std::fmt::Write as _;

/// One subpath read from SVG path data.
#[derive(Debug, Clone, PartialEq)]
pub struct SvgPath {
    /// Its segments in order; each starts where the previous one ends.
    pub segments: Vec<Bezier<DVec2>>,
    /// The subpath ended with `Z`.
    pub closed: bool,
}

/// How [`write_svg`] lays out its document.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SvgOptions {
    /// Mirror y (`y → −y`) so that curves drawn with y up appear upright.
    pub flip_y: bool,
    /// Stroke width of the paths, in user units.
    pub stroke_width: f64,
    /// Margin around the curves' control points in the view box, in user units.
    pub margin: f64,
}

impl Default for SvgOptions {
    fn default() -> Self {
        Self {
            flip_y: false,
            stroke_width: 0.01,
            margin: 0.1,
        }
    }
}

fn svg_err(msg: impl Into<String>) -> CurveError {
    CurveError::Svg(msg.into())
}

/// Reads every path of an SVG document (see the module docs).
///
/// # Errors
/// [`CurveError::Svg`] for a `<path>` without a readable `d` attribute or with path data that
/// cannot be read (the message names the path by its position).
pub fn read_svg(text: &str) -> Result<Vec<SvgPath>, CurveError> {
    let text = strip_comments(text);
    let mut out = Vec::new();
    let mut rest = text.as_str();
    let mut index = 0;
    while let Some(at) = find_tag(rest, "path") {
        let tag_end = rest[at..]
            .find('>')
            .map(|e| at + e)
            .ok_or_else(|| svg_err(format!("path {index}: the tag is not closed")))?;
        let tag = &rest[at..tag_end];
        let d = attribute(tag, "d")
            .ok_or_else(|| svg_err(format!("path {index} has no d attribute")))?;
        let paths = parse_path_data(&d).map_err(|e| match e {
            CurveError::Svg(m) => svg_err(format!("path {index}: {m}")),
            other => other,
        })?;
        out.extend(paths);
        rest = &rest[tag_end..];
        index += 1;
    }
    Ok(out)
}

fn strip_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(start) = rest.find("<!--") {
        out.push_str(&rest[..start]);
        match rest[start..].find("-->") {
            Some(end) => rest = &rest[start + end + 3..],
            None => return out,
        }
    }
    out.push_str(rest);
    out
}

/// Position of the next `<name` tag (followed by whitespace, `/` or `>`).
fn find_tag(text: &str, name: &str) -> Option<usize> {
    let pat = format!("<{name}");
    let mut from = 0;
    while let Some(i) = text[from..].find(&pat) {
        let at = from + i;
        let next = text[at + pat.len()..].chars().next();
        if matches!(next, Some(c) if c.is_whitespace() || c == '/' || c == '>') {
            return Some(at);
        }
        from = at + pat.len();
    }
    None
}

/// The value of attribute `name` in a tag's text (quoted with `"` or `'`).
fn attribute(tag: &str, name: &str) -> Option<String> {
    let bytes = tag.as_bytes();
    let mut from = 0;
    while let Some(i) = tag[from..].find(name) {
        let at = from + i;
        from = at + name.len();
        let before_ok = at > 0 && (bytes[at - 1] as char).is_whitespace();
        let after = tag[at + name.len()..].trim_start();
        if !before_ok || !after.starts_with('=') {
            continue;
        }
        let value = after[1..].trim_start();
        let quote = value.chars().next()?;
        if quote != '"' && quote != '\'' {
            return None;
        }
        let end = value[1..].find(quote)?;
        return Some(value[1..1 + end].to_string());
    }
    None
}

/// A tokenizer of SVG path data: command letters and numbers.
struct Tokens<'a> {
    s: &'a [u8],
    i: usize,
}

impl<'a> Tokens<'a> {
    fn skip_separators(&mut self) {
        while self.i < self.s.len()
            && (self.s[self.i].is_ascii_whitespace() || self.s[self.i] == b',')
        {
            self.i += 1;
        }
    }

    fn peek_command(&mut self) -> Option<u8> {
        self.skip_separators();
        self.s
            .get(self.i)
            .copied()
            .filter(|c| c.is_ascii_alphabetic() && *c != b'e' && *c != b'E')
    }

    fn at_number(&mut self) -> bool {
        self.skip_separators();
        matches!(self.s.get(self.i), Some(c) if c.is_ascii_digit() || *c == b'-' || *c == b'+' || *c == b'.')
    }

    fn number(&mut self) -> Result<f64, CurveError> {
        self.skip_separators();
        let start = self.i;
        let s = self.s;
        let mut j = self.i;
        if j < s.len() && (s[j] == b'-' || s[j] == b'+') {
            j += 1;
        }
        let mut digits = 0;
        while j < s.len() && s[j].is_ascii_digit() {
            j += 1;
            digits += 1;
        }
        if j < s.len() && s[j] == b'.' {
            j += 1;
            while j < s.len() && s[j].is_ascii_digit() {
                j += 1;
                digits += 1;
            }
        }
        if digits == 0 {
            return Err(svg_err(format!("a number was expected at byte {start}")));
        }
        if j < s.len() && (s[j] == b'e' || s[j] == b'E') {
            let mut k = j + 1;
            if k < s.len() && (s[k] == b'-' || s[k] == b'+') {
                k += 1;
            }
            if k < s.len() && s[k].is_ascii_digit() {
                while k < s.len() && s[k].is_ascii_digit() {
                    k += 1;
                }
                j = k;
            }
        }
        self.i = j;
        let text =
            std::str::from_utf8(&s[start..j]).map_err(|_| svg_err("path data is not text"))?;
        let v: f64 = text
            .parse()
            .map_err(|_| svg_err(format!("{text:?} is not a number")))?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(CurveError::NotFinite {
                what: format!("path number {text}"),
            })
        }
    }

    fn point(&mut self) -> Result<DVec2, CurveError> {
        Ok(DVec2::new(self.number()?, self.number()?))
    }
}

/// Reads SVG path data (the `d` attribute) into subpaths (see the module docs).
///
/// ```
/// use nendo::curve::svg::parse_path_data;
/// let paths = parse_path_data("M0 0 C 1 2, 3 2, 4 0 s 3 -2 4 0")?;
/// assert_eq!(paths.len(), 1);
/// assert_eq!(paths[0].segments.len(), 2);
/// // `s` reflects the previous control point (3, 2) about (4, 0).
/// assert_eq!(paths[0].segments[1].points()[1], glam::DVec2::new(5.0, -2.0));
/// # Ok::<(), nendo::curve::CurveError>(())
/// ```
///
/// # Errors
/// [`CurveError::Svg`] for unknown or unsupported commands (arcs), missing or malformed
/// numbers, or data that does not start with a move.
pub fn parse_path_data(d: &str) -> Result<Vec<SvgPath>, CurveError> {
    let mut t = Tokens {
        s: d.as_bytes(),
        i: 0,
    };
    let mut paths: Vec<SvgPath> = Vec::new();
    let mut current: Option<SvgPath> = None;
    let mut pos = DVec2::ZERO;
    let mut start = DVec2::ZERO;
    // The last control point of the previous C/S (for S) or Q/T (for T).
    let mut last_cubic: Option<DVec2> = None;
    let mut last_quad: Option<DVec2> = None;
    let mut cmd: Option<u8> = None;
    let mut moved = false;
    loop {
        let c = match t.peek_command() {
            Some(c) => {
                t.i += 1;
                c
            }
            None if t.i >= t.s.len() => break,
            None => match cmd {
                // Repeated arguments: after a move, further pairs are lines.
                Some(b'M') if t.at_number() => b'L',
                Some(b'm') if t.at_number() => b'l',
                Some(c) if c != b'Z' && c != b'z' && t.at_number() => c,
                _ => {
                    t.skip_separators();
                    if t.i >= t.s.len() {
                        break;
                    }
                    return Err(svg_err(format!(
                        "unexpected {:?} at byte {}",
                        t.s[t.i] as char, t.i
                    )));
                }
            },
        };
        let rel = c.is_ascii_lowercase();
        let base = if rel { pos } else { DVec2::ZERO };
        let upper = c.to_ascii_uppercase();
        if upper != b'M' && current.is_none() {
            if !moved {
                return Err(svg_err("path data must start with a move (M)"));
            }
            if upper == b'Z' {
                cmd = Some(c);
                continue;
            }
            // A drawing command after Z starts a new subpath at the current point.
            current = Some(SvgPath {
                segments: Vec::new(),
                closed: false,
            });
            start = pos;
        }
        let (mut cubic, mut quad) = (None, None);
        match upper {
            b'M' => {
                if let Some(p) = current.take() {
                    paths.push(p);
                }
                pos = base + t.point()?;
                start = pos;
                moved = true;
                current = Some(SvgPath {
                    segments: Vec::new(),
                    closed: false,
                });
            }
            b'L' | b'H' | b'V' => {
                let to = match upper {
                    b'L' => base + t.point()?,
                    b'H' => DVec2::new(t.number()? + if rel { pos.x } else { 0.0 }, pos.y),
                    _ => DVec2::new(pos.x, t.number()? + if rel { pos.y } else { 0.0 }),
                };
                push(&mut current, vec![pos, to])?;
                pos = to;
            }
            b'C' | b'S' => {
                let c1 = if upper == b'C' {
                    base + t.point()?
                } else {
                    last_cubic.map_or(pos, |q| pos * 2.0 - q)
                };
                let c2 = base + t.point()?;
                let to = base + t.point()?;
                push(&mut current, vec![pos, c1, c2, to])?;
                cubic = Some(c2);
                pos = to;
            }
            b'Q' | b'T' => {
                let c1 = if upper == b'Q' {
                    base + t.point()?
                } else {
                    last_quad.map_or(pos, |q| pos * 2.0 - q)
                };
                let to = base + t.point()?;
                push(&mut current, vec![pos, c1, to])?;
                quad = Some(c1);
                pos = to;
            }
            b'Z' => {
                if pos != start {
                    push(&mut current, vec![pos, start])?;
                }
                if let Some(mut p) = current.take() {
                    p.closed = true;
                    paths.push(p);
                }
                pos = start;
            }
            b'A' => return Err(svg_err("elliptical arc commands (A) are not supported")),
            other => return Err(svg_err(format!("unknown path command {:?}", other as char))),
        }
        last_cubic = cubic;
        last_quad = quad;
        cmd = Some(c);
    }
    if let Some(p) = current.take() {
        paths.push(p);
    }
    paths.retain(|p| !p.segments.is_empty());
    Ok(paths)
}

fn push(current: &mut Option<SvgPath>, points: Vec<DVec2>) -> Result<(), CurveError> {
    let p = current
        .as_mut()
        .ok_or_else(|| svg_err("path data must start with a move (M)"))?;
    p.segments.push(Bezier::try_new(points)?);
    Ok(())
}

/// SVG path data for segments of degree 1–3: one subpath per run of segments that meet.
///
/// # Errors
/// [`CurveError::Svg`] for a segment of degree 0 or above 3.
pub fn path_data(segments: &[Bezier<DVec2>], flip_y: bool) -> Result<String, CurveError> {
    let f = |p: DVec2| {
        if flip_y {
            DVec2::new(p.x, 0.0 - p.y)
        } else {
            p
        }
    };
    let mut out = String::new();
    let mut pos: Option<DVec2> = None;
    for (i, s) in segments.iter().enumerate() {
        let pts: Vec<DVec2> = s.points().iter().map(|&p| f(p)).collect();
        if pos != Some(pts[0]) {
            if !out.is_empty() {
                out.push(' ');
            }
            let _ = write!(out, "M {} {}", pts[0].x, pts[0].y);
        }
        let letter = match s.degree() {
            1 => 'L',
            2 => 'Q',
            3 => 'C',
            d => {
                return Err(svg_err(format!(
                    "segment {i} has degree {d}; SVG paths hold degrees 1 to 3"
                )));
            }
        };
        let _ = write!(out, " {letter}");
        for p in &pts[1..] {
            let _ = write!(out, " {} {}", p.x, p.y);
        }
        pos = Some(pts[pts.len() - 1]);
    }
    Ok(out)
}

/// An SVG document drawing every curve as a path (a B-spline as its Bezier segments).
///
/// # Errors
/// [`CurveError::Svg`] for a segment of degree 0 or above 3.
pub fn write_svg(curves: &[Curve<DVec2>], options: SvgOptions) -> Result<String, CurveError> {
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    let mut paths = Vec::with_capacity(curves.len());
    for c in curves {
        // A curve's segments meet: join them exactly (a B-spline's may differ by rounding).
        let mut segs: Vec<Bezier<DVec2>> = Vec::new();
        for s in c.segments().iter() {
            let mut pts = s.bezier.points().to_vec();
            if let Some(prev) = segs.last() {
                pts[0] = prev.points()[prev.degree()];
            }
            segs.push(Bezier::try_new(pts)?);
        }
        for p in c.points() {
            let p = if options.flip_y {
                DVec2::new(p.x, -p.y)
            } else {
                *p
            };
            lo = lo.min(p);
            hi = hi.max(p);
        }
        paths.push(path_data(&segs, options.flip_y)?);
    }
    if curves.is_empty() {
        (lo, hi) = (DVec2::ZERO, DVec2::ONE);
    }
    let m = options.margin.max(0.0);
    let (x, y, w, h) = (
        lo.x - m,
        lo.y - m,
        hi.x - lo.x + 2.0 * m,
        hi.y - lo.y + 2.0 * m,
    );
    let mut out = String::new();
    let _ = writeln!(out, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="{x} {y} {w} {h}">"#
    );
    for d in paths {
        let _ = writeln!(
            out,
            r#"  <path d="{d}" fill="none" stroke="black" stroke-width="{}"/>"#,
            options.stroke_width
        );
    }
    out.push_str("</svg>\n");
    Ok(out)
}
