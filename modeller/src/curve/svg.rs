//! SVG import and export of planar curves (P3 §3.1 kept its curves in SVG): path data with
//! line, quadratic and cubic segments.
//!
//! * Reading ([`read_svg`], [`parse_path_data`]): the document is parsed as XML by `roxmltree`
//!   (entities — predefined, numeric and declared in an internal DTD — quoting with `"` or `'`,
//!   comments, CDATA and a `>` inside an attribute value are all XML's business), path data and
//!   transform lists by `svgtypes`. Every `<path d="…">` of the document (in the SVG namespace
//!   or none, in document order, including those inside `<defs>`; `<use>` references are not
//!   followed, styles are ignored) is read with the `transform` attributes of the path and of
//!   all its ancestors applied (`matrix`, `translate`, `scale`, `rotate` with or without a
//!   centre, `skewX`, `skewY`); an affine map of a Bezier segment is the segment of the mapped
//!   control points, so this is exact. Every subpath becomes a list of Bezier segments —
//!   `L`/`H`/`V` as degree 1, `Q`/`T` as degree 2, `C`/`S` as degree 3, in absolute and
//!   relative forms, with `S`/`T` reflecting the previous control point as the SVG
//!   specification says; `Z` closes the subpath with a line when it is not closed already.
//!   Elliptical arcs (`A`) are refused with an error rather than approximated (no Bezier
//!   segment holds an arc exactly).
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
use svgtypes::Transform;

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

/// Why an SVG document or path data could not be read, or curves could not be written as SVG.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum SvgError {
    /// The document is not well-formed XML (the message says where).
    #[error("the document is not well-formed XML: {0}")]
    Xml(#[from] roxmltree::Error),
    /// A `<path>` without a `d` attribute.
    #[error("path {index} has no d attribute")]
    NoPathData {
        /// The path's position among the document's paths.
        index: usize,
    },
    /// A `transform` attribute (on the path or an ancestor) that is not a transform list.
    #[error("path {index}: the transform {value:?} of <{element}> cannot be read: {reason}")]
    Transform {
        /// The path's position among the document's paths.
        index: usize,
        /// The element carrying the attribute.
        element: String,
        /// The attribute's value.
        value: String,
        /// What `svgtypes` found wrong.
        reason: svgtypes::Error,
    },
    /// Path data that could not be read, in the path at `index`.
    #[error("path {index}: {source}")]
    InPath {
        /// The path's position among the document's paths.
        index: usize,
        /// What was wrong with its data.
        #[source]
        source: Box<SvgError>,
    },
    /// Malformed path data: an unknown command, a missing or malformed number.
    #[error("path data: {0}")]
    Data(svgtypes::Error),
    /// Path data whose first command is not a move.
    #[error("path data must start with a move (M)")]
    NoMove,
    /// An elliptical arc command, which no Bezier segment holds exactly.
    #[error("elliptical arc commands (A) are not supported")]
    Arc,
    /// A number (or a transformed coordinate) that is NaN or infinite.
    #[error("{what} is not a finite number")]
    NotFinite {
        /// Which value.
        what: String,
    },
    /// A segment whose degree SVG path data cannot hold.
    #[error("segment {index} has degree {degree}; SVG paths hold degrees 1 to 3")]
    Degree {
        /// The segment's position.
        index: usize,
        /// Its degree.
        degree: usize,
    },
    /// A segment that is not a valid curve.
    #[error(transparent)]
    Curve(#[from] CurveError),
}

/// The SVG namespace.
const SVG_NS: &str = "http://www.w3.org/2000/svg";

/// Reads every path of an SVG document (see the module docs).
///
/// # Errors
/// [`SvgError::Xml`] for a document that is not well-formed XML, [`SvgError::NoPathData`] for a
/// `<path>` without a `d` attribute, [`SvgError::Transform`] for an unreadable transform, and
/// [`SvgError::InPath`] for path data that cannot be read (naming the path by its position).
pub fn read_svg(text: &str) -> Result<Vec<SvgPath>, SvgError> {
    let options = roxmltree::ParsingOptions {
        // Documents from drawing tools declare entities in an internal DTD; roxmltree bounds
        // their expansion.
        allow_dtd: true,
        ..roxmltree::ParsingOptions::default()
    };
    let doc = roxmltree::Document::parse_with_options(text, options)?;
    let mut out = Vec::new();
    let is_path = |n: &roxmltree::Node<'_, '_>| {
        n.is_element()
            && n.tag_name().name() == "path"
            && n.tag_name().namespace().is_none_or(|ns| ns == SVG_NS)
    };
    for (index, node) in doc.descendants().filter(is_path).enumerate() {
        let d = node.attribute("d").ok_or(SvgError::NoPathData { index })?;
        let transform = node_transform(node, index)?;
        let mut paths = parse_path_data(d).map_err(|e| SvgError::InPath {
            index,
            source: Box::new(e),
        })?;
        if !is_identity(&transform) {
            for path in &mut paths {
                for segment in &mut path.segments {
                    let points = segment
                        .points()
                        .iter()
                        .map(|&p| apply(&transform, p))
                        .collect::<Result<Vec<_>, _>>()
                        .map_err(|e| SvgError::InPath {
                            index,
                            source: Box::new(e),
                        })?;
                    *segment = Bezier::try_new(points)?;
                }
            }
        }
        out.extend(paths);
    }
    Ok(out)
}

/// The transform from a node's user space to the document's: the product of the `transform`
/// attributes of the node and all its ancestors, outermost first.
fn node_transform(node: roxmltree::Node<'_, '_>, index: usize) -> Result<Transform, SvgError> {
    let mut total = Transform::default();
    for n in node.ancestors().filter(roxmltree::Node::is_element) {
        let Some(value) = n.attribute("transform") else {
            continue;
        };
        let t: Transform = value.parse().map_err(|reason| SvgError::Transform {
            index,
            element: n.tag_name().name().to_string(),
            value: value.to_string(),
            reason,
        })?;
        total = multiply(&t, &total);
    }
    Ok(total)
}

/// `a ∘ b`: first `b`, then `a`.
fn multiply(a: &Transform, b: &Transform) -> Transform {
    Transform::new(
        a.a * b.a + a.c * b.b,
        a.b * b.a + a.d * b.b,
        a.a * b.c + a.c * b.d,
        a.b * b.c + a.d * b.d,
        a.a * b.e + a.c * b.f + a.e,
        a.b * b.e + a.d * b.f + a.f,
    )
}

fn is_identity(t: &Transform) -> bool {
    (t.a, t.b, t.c, t.d, t.e, t.f) == (1.0, 0.0, 0.0, 1.0, 0.0, 0.0)
}

fn apply(t: &Transform, p: DVec2) -> Result<DVec2, SvgError> {
    let q = DVec2::new(t.a * p.x + t.c * p.y + t.e, t.b * p.x + t.d * p.y + t.f);
    if q.is_finite() {
        Ok(q)
    } else {
        Err(SvgError::NotFinite {
            what: format!("the transformed point ({}, {})", p.x, p.y),
        })
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
/// # Ok::<(), nendo::curve::svg::SvgError>(())
/// ```
///
/// # Errors
/// [`SvgError::Data`] for unknown commands or missing or malformed numbers, [`SvgError::Arc`]
/// for arcs, [`SvgError::NoMove`] for data that does not start with a move, and
/// [`SvgError::NotFinite`] for numbers out of `f64`'s range.
pub fn parse_path_data(d: &str) -> Result<Vec<SvgPath>, SvgError> {
    use svgtypes::PathSegment as S;
    let mut paths: Vec<SvgPath> = Vec::new();
    let mut current: Option<SvgPath> = None;
    let mut pos = DVec2::ZERO;
    let mut start = DVec2::ZERO;
    // The last control point of the previous C/S (for S) or Q/T (for T).
    let mut last_cubic: Option<DVec2> = None;
    let mut last_quad: Option<DVec2> = None;
    let mut moved = false;
    for segment in svgtypes::PathParser::from(d) {
        let segment = segment.map_err(SvgError::Data)?;
        let finite = |v: f64| {
            if v.is_finite() {
                Ok(v)
            } else {
                Err(SvgError::NotFinite {
                    what: format!("path number {v}"),
                })
            }
        };
        let base = if segment.is_abs() { DVec2::ZERO } else { pos };
        let at = |x: f64, y: f64| -> Result<DVec2, SvgError> {
            Ok(base + DVec2::new(finite(x)?, finite(y)?))
        };
        let is_move = matches!(segment, S::MoveTo { .. });
        let is_close = matches!(segment, S::ClosePath { .. });
        if !is_move && current.is_none() {
            if !moved {
                return Err(SvgError::NoMove);
            }
            if is_close {
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
        match segment {
            S::MoveTo { x, y, .. } => {
                if let Some(p) = current.take() {
                    paths.push(p);
                }
                pos = at(x, y)?;
                start = pos;
                moved = true;
                current = Some(SvgPath {
                    segments: Vec::new(),
                    closed: false,
                });
            }
            S::LineTo { x, y, .. } => {
                let to = at(x, y)?;
                push(&mut current, vec![pos, to])?;
                pos = to;
            }
            S::HorizontalLineTo { x, .. } => {
                let to = DVec2::new(base.x + finite(x)?, pos.y);
                push(&mut current, vec![pos, to])?;
                pos = to;
            }
            S::VerticalLineTo { y, .. } => {
                let to = DVec2::new(pos.x, base.y + finite(y)?);
                push(&mut current, vec![pos, to])?;
                pos = to;
            }
            S::CurveTo {
                x1,
                y1,
                x2,
                y2,
                x,
                y,
                ..
            } => {
                let (c1, c2, to) = (at(x1, y1)?, at(x2, y2)?, at(x, y)?);
                push(&mut current, vec![pos, c1, c2, to])?;
                cubic = Some(c2);
                pos = to;
            }
            S::SmoothCurveTo { x2, y2, x, y, .. } => {
                let c1 = last_cubic.map_or(pos, |q| pos * 2.0 - q);
                let (c2, to) = (at(x2, y2)?, at(x, y)?);
                push(&mut current, vec![pos, c1, c2, to])?;
                cubic = Some(c2);
                pos = to;
            }
            S::Quadratic { x1, y1, x, y, .. } => {
                let (c1, to) = (at(x1, y1)?, at(x, y)?);
                push(&mut current, vec![pos, c1, to])?;
                quad = Some(c1);
                pos = to;
            }
            S::SmoothQuadratic { x, y, .. } => {
                let c1 = last_quad.map_or(pos, |q| pos * 2.0 - q);
                let to = at(x, y)?;
                push(&mut current, vec![pos, c1, to])?;
                quad = Some(c1);
                pos = to;
            }
            S::ClosePath { .. } => {
                if pos != start {
                    push(&mut current, vec![pos, start])?;
                }
                if let Some(mut p) = current.take() {
                    p.closed = true;
                    paths.push(p);
                }
                pos = start;
            }
            S::EllipticalArc { .. } => return Err(SvgError::Arc),
        }
        last_cubic = cubic;
        last_quad = quad;
    }
    if let Some(p) = current.take() {
        paths.push(p);
    }
    paths.retain(|p| !p.segments.is_empty());
    Ok(paths)
}

fn push(current: &mut Option<SvgPath>, points: Vec<DVec2>) -> Result<(), SvgError> {
    let p = current.as_mut().ok_or(SvgError::NoMove)?;
    p.segments.push(Bezier::try_new(points)?);
    Ok(())
}

/// SVG path data for segments of degree 1–3: one subpath per run of segments that meet.
///
/// # Errors
/// [`SvgError::Degree`] for a segment of degree 0 or above 3.
pub fn path_data(segments: &[Bezier<DVec2>], flip_y: bool) -> Result<String, SvgError> {
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
            degree => return Err(SvgError::Degree { index: i, degree }),
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
/// [`SvgError::Degree`] for a segment of degree 0 or above 3.
pub fn write_svg(curves: &[Curve<DVec2>], options: SvgOptions) -> Result<String, SvgError> {
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
