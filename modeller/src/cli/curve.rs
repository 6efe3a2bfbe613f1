//! `nendo curve --batch`: curve editing, refinement, warping and SVG as JSON Lines (one request
//! per input line on stdin, one answer per output line on stdout, same order), like
//! `nendo closest --batch`.
//!
//! Curves and points are in the JSON form of [`crate::curve::json`] (2D or 3D unless said).
//!
//! | request | answer |
//! |---|---|
//! | `{"op":"grab","curve":C,"from":P,"to":T, "rmax":R?, "method":M?, "keep_ends":B?}` | `{"curve":C',"u":u}` with `C'(u) = C(u) + (T − P)`, `u` the closest point to `P`; `{"curve":null,"u":null}` when nothing lies within `R` |
//! | `{"op":"split","curve":C,"u":u}` | `{"curves":[C1,C2]}` |
//! | `{"op":"tangent","left":L,"right":R,"side":"left"\|"right","to":T,"follow":"length"\|"ratio"?}` | `{"curves":[L',R']}` |
//! | `{"op":"insert","curve":C,"u":u}` | `{"curve":C',"index":k}` |
//! | `{"op":"refine","curve":C,"mode":"curvature"\|"variation","constraints":[…]}` | `{"curve":C',"residual":r,"similarity":s}` |
//! | `{"op":"refine","curves":[B…],"mode":…,"constraints":[…]}` | `{"curves":[B'…],"residual":r,"similarity":s}` |
//! | `{"op":"warp","pairs":[[C,C_d],…],"points":[P…],"a":a?,"b":b?,"p":p?,"reach":r?}` | `{"points":[P_d…]}` |
//! | `{"op":"svg_read","svg":"<svg …>"}` | `{"paths":[{"curves":[B…],"closed":bool},…]}` |
//! | `{"op":"svg_write","curves":[C…],"flip_y":bool?}` | `{"svg":"<svg …>"}` |
//!
//! * `method` of a grab: `"largest"` (default: the control point with the largest basis weight,
//!   P4), `"nearest"` (the control point of the nearest parameter, P0) or
//!   `"least_change"` (every control point, least total move); `keep_ends: true` never moves the
//!   end control points. See [`crate::curve::edit`].
//! * Refinement (2D only; [`crate::curve::refine`]) takes one curve (Bezier or B-spline,
//!   parameter in its domain) or `"curves"`, a piecewise curve of Bezier segments end to end
//!   (global parameter `u ∈ [0, segments]`, segment `i` on `[i, i+1]`). The constraints:
//!   - `{"u":u,"point":[x,y]}` — the curve passes through the point at `u`;
//!   - `{"u":u,"tangent":[dx,dy]}` — the tangent at `u` is parallel to the direction;
//!   - `{"u":u,"derivative":[dx,dy]}` — the first derivative at `u` is the vector;
//!   - `{"join":i,"order":k}` — segments `i` and `i+1` of a piecewise curve meet with C^k
//!     continuity (`k` = 0, 1, 2); joints not named keep the continuity they have.
//!
//!   `residual` is `|A V − b|` of the constraints (0 unless they contradict each other),
//!   `similarity` the root mean square of the similarity variables (0 for a similar copy).
//!
//!   Which constraints return the *similar copy* (the curve rotated, scaled and moved) when the
//!   constraints admit one — see [`crate::curve::refine`], "Which constraints give the similar
//!   copy":
//!   - `"curvature"`: the two end points suffice (`{"u":u0,"point":…}`, `{"u":u1,"point":…}`),
//!     or any two points, or a point and a `derivative`;
//!   - `"variation"`: the end points alone do **not** — that mode leaves the first derivative
//!     free, so a straight-line term `c u` stays undetermined and the answer is the curve of
//!     `similarity` 0 nearest the original, generally not the copy. Add the `tangent` at both
//!     ends, or a `derivative` at one parameter, or a third `point` (off uniform motion along
//!     the chord).
//! * Strings are strict: `method` and `follow` must be strings from their lists (a number or
//!   another type is refused, not defaulted); a B-spline's `degree` may be written `3` or `3.0`.
//! * Curves whose control points are so far apart that arithmetic overflows (e.g. `±1e308`)
//!   give an error from `grab` and `split`, never null coordinates.
//! * Warping ([`crate::curve::warp`]): Beier–Neely weights with `a` (default 0), `b` (2), `p`
//!   (0.5) and an optional still background `reach`; all curves and points of one dimension.
//!   The work of one request, `pairs × points` weight evaluations, is at most
//!   [`MAX_WARP_WORK`] (10 000 000, a few seconds on one core: 1 000 pairs × 100 000 points took
//!   24 s); a larger request is refused before any work, with its size and an estimate of
//!   its time.
//!
//! A request has exactly the members listed (optional ones may be absent or null): an unknown
//! or repeated member is refused, as is a line starting with a byte-order mark; a constraint
//! has one form only. A line that cannot be answered gets `{"error":"<what is wrong>"}`,
//! naming the bad member's path and column (e.g. `pairs[0][1].bezier[2]: ...`); later lines
//! are still answered, and the exit status is 1 if any line failed. Blank lines are skipped.

use crate::curve::edit::{self, Follow, Grab, GrabMethod, GrabOptions, JointSide};
use crate::curve::json::{DynCurve, JsonPoint, curve_to_json, point_to_json};
use crate::curve::refine::{self, Constraint, Similarity};
use crate::curve::warp::{CurveWarp, WarpParams, WarpSpace};
use crate::curve::{Bezier, Curve, CurveError, Point, svg};
use crate::json_doc::{self, JsonError};
use clap::Args as ClapArgs;
use glam::{DVec2, DVec3};
use serde::Deserialize;
use serde::de::IgnoredAny;
use serde_json::{Value, json};
use std::process::ExitCode;

/// Arguments of `nendo curve`.
#[derive(Debug, ClapArgs)]
pub struct CurveArgs {
    /// Read JSON Lines requests from stdin and answer each on stdout (the only mode).
    #[arg(long)]
    pub batch: bool,
}

/// Runs `nendo curve`.
pub fn run(args: CurveArgs) -> ExitCode {
    super::json_lines::run("curve", args.batch, answer)
}

/// Most `pairs × points` one warp request may ask for (see the module docs).
pub use crate::curve::warp_work::MAX_WARP_WORK;

/// Why one request line cannot be answered.
#[derive(Debug, thiserror::Error)]
pub enum CurveRequestError {
    /// Not JSON, or a member missing, unknown, repeated or invalid (with its path).
    #[error("{0}")]
    Json(#[from] JsonError),
    /// An `op` this protocol does not have.
    #[error(
        "unknown op {0:?}; expected grab, split, tangent, insert, refine, warp, svg_read or svg_write"
    )]
    UnknownOp(String),
    /// The edit, refinement or warp refused its input.
    #[error("{0}")]
    Curve(#[from] CurveError),
    /// A warp asks for more than [`MAX_WARP_WORK`] pair-point evaluations.
    #[error("{0}; split the points over several requests")]
    WarpTooLarge(#[from] crate::curve::warp_work::WarpTooLarge),
    /// The SVG document could not be read or the curves written as SVG.
    #[error("svg: {0}")]
    Svg(#[from] svg::SvgError),
}

/// Only the `op` member (the others are read by the request's own structure).
#[derive(Deserialize)]
#[serde(expecting = "a request (a JSON object with an \"op\")")]
struct OpOnly {
    op: String,
}

/// `{"op":"grab","curve":C,"from":P,"to":T,"rmax":R?,"method":M?,"keep_ends":B?}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GrabRequest {
    #[allow(dead_code)]
    op: IgnoredAny,
    curve: DynCurve,
    from: JsonPoint,
    to: JsonPoint,
    #[serde(default)]
    rmax: Option<f64>,
    #[serde(default)]
    method: Option<Value>,
    #[serde(default)]
    keep_ends: Option<bool>,
}

/// `{"op":"split"|"insert","curve":C,"u":u}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AtRequest {
    #[allow(dead_code)]
    op: IgnoredAny,
    curve: DynCurve,
    u: f64,
}

/// `{"op":"tangent","left":L,"right":R,"side":S,"to":T,"follow":F?}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TangentRequest {
    #[allow(dead_code)]
    op: IgnoredAny,
    left: DynCurve,
    right: DynCurve,
    side: SideDoc,
    to: JsonPoint,
    #[serde(default)]
    follow: Option<Value>,
}

/// The side of a tangent edit.
#[derive(Deserialize)]
#[serde(rename_all = "lowercase")]
enum SideDoc {
    Left,
    Right,
}

/// `{"op":"refine","curve":C | "curves":[B…],"mode":M,"constraints":[…]?}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RefineRequest {
    #[allow(dead_code)]
    op: IgnoredAny,
    mode: ModeDoc,
    #[serde(default)]
    constraints: Option<Vec<ConstraintDoc>>,
    #[serde(default)]
    curve: Option<DynCurve>,
    #[serde(default)]
    curves: Option<Vec<DynCurve>>,
}

/// The similarity of a refinement.
#[derive(Deserialize)]
#[serde(rename_all = "lowercase")]
enum ModeDoc {
    Curvature,
    Variation,
}

/// One refinement constraint, of the forms listed in the module docs.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ConstraintDoc {
    #[serde(default)]
    join: Option<usize>,
    #[serde(default)]
    order: Option<usize>,
    #[serde(default)]
    u: Option<f64>,
    #[serde(default)]
    point: Option<JsonPoint>,
    #[serde(default)]
    tangent: Option<JsonPoint>,
    #[serde(default)]
    derivative: Option<JsonPoint>,
}

/// `{"op":"warp","pairs":[[C,C_d],…],"points":[P…],"a":a?,"b":b?,"p":p?,"reach":r?}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct WarpRequest {
    #[allow(dead_code)]
    op: IgnoredAny,
    pairs: Vec<(DynCurve, DynCurve)>,
    points: Vec<JsonPoint>,
    #[serde(default)]
    a: Option<f64>,
    #[serde(default)]
    b: Option<f64>,
    #[serde(default)]
    p: Option<f64>,
    #[serde(default)]
    reach: Option<f64>,
}

/// `{"op":"svg_read","svg":"<svg …>"}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SvgReadRequest {
    #[allow(dead_code)]
    op: IgnoredAny,
    svg: String,
}

/// `{"op":"svg_write","curves":[C…],"flip_y":bool?}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SvgWriteRequest {
    #[allow(dead_code)]
    op: IgnoredAny,
    curves: Vec<DynCurve>,
    #[serde(default)]
    flip_y: Option<bool>,
}

/// Answers one request line.
///
/// # Errors
/// A [`CurveRequestError`] saying what is wrong with the request (and at which member).
pub fn answer(line: &str) -> Result<Value, CurveRequestError> {
    let op = json_doc::from_str::<OpOnly>(line)?.op;
    match op.as_str() {
        "grab" => {
            let r: GrabRequest = json_doc::from_str(line)?;
            match &r.curve {
                DynCurve::D2(c) => grab_reply(c, &r),
                DynCurve::D3(c) => grab_reply(c, &r),
            }
        }
        "split" => {
            let r: AtRequest = json_doc::from_str(line)?;
            match r.curve {
                DynCurve::D2(c) => pair_reply(edit::split(&c, r.u)),
                DynCurve::D3(c) => pair_reply(edit::split(&c, r.u)),
            }
        }
        "tangent" => {
            let r: TangentRequest = json_doc::from_str(line)?;
            match (&r.left, &r.right) {
                (DynCurve::D2(le), DynCurve::D2(ri)) => tangent_reply(le, ri, &r),
                (DynCurve::D3(le), DynCurve::D3(ri)) => tangent_reply(le, ri, &r),
                _ => Err(JsonError::at(
                    "right",
                    "\"left\" and \"right\" must have the same dimension",
                )
                .into()),
            }
        }
        "insert" => {
            let r: AtRequest = json_doc::from_str(line)?;
            let (curve, index) = match r.curve {
                DynCurve::D2(c) => {
                    edit::insert_control_point(&c, r.u).map(|(c, k)| (curve_to_json(&c), k))
                }
                DynCurve::D3(c) => {
                    edit::insert_control_point(&c, r.u).map(|(c, k)| (curve_to_json(&c), k))
                }
            }?;
            Ok(json!({ "curve": curve, "index": index }))
        }
        "refine" => refine_reply(json_doc::from_str(line)?),
        "warp" => warp_reply(json_doc::from_str(line)?),
        "svg_read" => {
            let r: SvgReadRequest = json_doc::from_str(line)?;
            let paths = svg::read_svg(&r.svg)?;
            Ok(json!({ "paths": paths.iter().map(|p| json!({
                "curves": p.segments.iter().map(|b| curve_to_json(&Curve::Bezier(b.clone()))).collect::<Vec<_>>(),
                "closed": p.closed,
            })).collect::<Vec<_>>() }))
        }
        "svg_write" => {
            let r: SvgWriteRequest = json_doc::from_str(line)?;
            let mut curves = Vec::with_capacity(r.curves.len());
            for (i, c) in r.curves.into_iter().enumerate() {
                match c {
                    DynCurve::D2(c) => curves.push(c),
                    DynCurve::D3(_) => {
                        return Err(JsonError::at(
                            &format!("curves[{i}]"),
                            "the curve is 3D; SVG holds planar curves",
                        )
                        .into());
                    }
                }
            }
            let text = svg::write_svg(
                &curves,
                svg::SvgOptions {
                    flip_y: r.flip_y.unwrap_or(false),
                    ..svg::SvgOptions::default()
                },
            )?;
            Ok(json!({ "svg": text }))
        }
        _ => Err(CurveRequestError::UnknownOp(op)),
    }
}

/// An optional string member: absent or null gives `None`; anything but a string is an error.
fn optional_string<'a>(v: Option<&'a Value>, name: &str) -> Result<Option<&'a str>, JsonError> {
    match v {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(s)) => Ok(Some(s)),
        Some(other) => Err(JsonError::at(
            name,
            format!("\"{name}\" must be a string, got {other}"),
        )),
    }
}

fn grab_reply<P: Point>(c: &Curve<P>, r: &GrabRequest) -> Result<Value, CurveRequestError> {
    let from: P = r.from.typed("from")?;
    let to: P = r.to.typed("to")?;
    let rmax = match r.rmax {
        None => f64::INFINITY,
        Some(x) => crate::curve::check_radius("rmax", x)?,
    };
    let method = match optional_string(r.method.as_ref(), "method")? {
        None | Some("largest") => GrabMethod::LargestWeight,
        Some("nearest") => GrabMethod::NearestParameter,
        Some("least_change") => GrabMethod::LeastChange,
        Some(other) => {
            return Err(JsonError::at(
                "method",
                format!("unknown grab method {other:?}; expected largest, nearest or least_change"),
            )
            .into());
        }
    };
    let keep_ends = r.keep_ends.unwrap_or(false);
    match Grab::at_point(c, from, rmax, GrabOptions { method, keep_ends })? {
        Some(g) => {
            let moved = g.moved_by(to - from)?;
            Ok(json!({ "curve": curve_to_json(&moved), "u": g.u() }))
        }
        None => Ok(json!({ "curve": null, "u": null })),
    }
}

fn pair_reply<P: Point>(
    r: Result<(Curve<P>, Curve<P>), CurveError>,
) -> Result<Value, CurveRequestError> {
    let (a, b) = r?;
    Ok(json!({ "curves": [curve_to_json(&a), curve_to_json(&b)] }))
}

fn tangent_reply<P: Point>(
    l: &Curve<P>,
    r: &Curve<P>,
    req: &TangentRequest,
) -> Result<Value, CurveRequestError> {
    let side = match req.side {
        SideDoc::Left => JointSide::Left,
        SideDoc::Right => JointSide::Right,
    };
    let follow = match optional_string(req.follow.as_ref(), "follow")? {
        None | Some("length") => Follow::KeepLength,
        Some("ratio") => Follow::KeepRatio,
        Some(other) => {
            return Err(JsonError::at(
                "follow",
                format!("unknown follow {other:?}; expected length or ratio"),
            )
            .into());
        }
    };
    let to: P = req.to.typed("to")?;
    pair_reply(edit::tangent_edit(l, r, side, to, follow))
}

/// One constraint of the forms listed in the module docs; `path` names it in errors.
fn constraint(c: ConstraintDoc, path: &str) -> Result<Constraint, JsonError> {
    let vectors = [&c.point, &c.tangent, &c.derivative]
        .iter()
        .filter(|v| v.is_some())
        .count();
    if let Some(at) = c.join {
        if c.u.is_some() || vectors > 0 {
            return Err(JsonError::at(
                path,
                "a join takes only \"join\" and \"order\"",
            ));
        }
        let order = c
            .order
            .ok_or_else(|| JsonError::at(path, "a join needs \"order\" 0, 1 or 2"))?;
        return Ok(Constraint::Join { at, order });
    }
    if c.order.is_some() {
        return Err(JsonError::at(path, "\"order\" belongs to a \"join\""));
    }
    let u =
        c.u.ok_or_else(|| JsonError::at(path, "needs a finite parameter \"u\""))?;
    if vectors > 1 {
        return Err(JsonError::at(
            path,
            "one of \"point\", \"tangent\" or \"derivative\" per constraint",
        ));
    }
    let vec2 = |p: &JsonPoint, name: &str| p.typed::<DVec2>(&format!("{path}.{name}"));
    if let Some(p) = &c.point {
        Ok(Constraint::Point {
            u,
            point: vec2(p, "point")?,
        })
    } else if let Some(d) = &c.tangent {
        Ok(Constraint::Tangent {
            u,
            direction: vec2(d, "tangent")?,
        })
    } else if let Some(d) = &c.derivative {
        Ok(Constraint::Derivative {
            u,
            vector: vec2(d, "derivative")?,
        })
    } else {
        Err(JsonError::at(
            path,
            "expected \"point\", \"tangent\", \"derivative\" (with \"u\") or \"join\"",
        ))
    }
}

fn refine_reply(req: RefineRequest) -> Result<Value, CurveRequestError> {
    let mode = match req.mode {
        ModeDoc::Curvature => Similarity::Curvature,
        ModeDoc::Variation => Similarity::Variation,
    };
    let constraints = req
        .constraints
        .unwrap_or_default()
        .into_iter()
        .enumerate()
        .map(|(i, c)| constraint(c, &format!("constraints[{i}]")))
        .collect::<Result<Vec<_>, _>>()?;
    match (req.curve, req.curves) {
        (Some(_), Some(_)) => {
            Err(JsonError::at("", "a refinement takes \"curve\" or \"curves\", not both").into())
        }
        (None, None) => Err(JsonError::at("", "a refinement needs \"curve\" or \"curves\"").into()),
        (None, Some(list)) => {
            let mut segs = Vec::with_capacity(list.len());
            for (i, c) in list.into_iter().enumerate() {
                let path = format!("curves[{i}]");
                match c {
                    DynCurve::D2(Curve::Bezier(b)) => segs.push(b),
                    DynCurve::D2(Curve::BSpline(_)) => {
                        return Err(JsonError::at(
                            &path,
                            "a piecewise curve is made of Bezier segments",
                        )
                        .into());
                    }
                    DynCurve::D3(_) => {
                        return Err(
                            JsonError::at(&path, "refinement works on planar (2D) curves").into(),
                        );
                    }
                }
            }
            let r = refine::refine_piecewise(&segs, mode, &constraints)?;
            let out: Vec<Value> = r
                .curve
                .into_iter()
                .map(|b: Bezier<DVec2>| curve_to_json(&Curve::Bezier(b)))
                .collect();
            Ok(
                json!({ "curves": out, "residual": r.constraint_residual, "similarity": r.similarity_rms }),
            )
        }
        (Some(DynCurve::D2(c)), None) => {
            let r = refine::refine(&c, mode, &constraints)?;
            Ok(
                json!({ "curve": curve_to_json(&r.curve), "residual": r.constraint_residual, "similarity": r.similarity_rms }),
            )
        }
        (Some(DynCurve::D3(_)), None) => {
            Err(JsonError::at("curve", "refinement works on planar (2D) curves").into())
        }
    }
}

fn warp_reply(req: WarpRequest) -> Result<Value, CurveRequestError> {
    crate::curve::warp_work::check_warp_work(req.pairs.len() as u64, req.points.len() as u64)?;
    let defaults = WarpParams::default();
    let params = WarpParams {
        a: req.a.unwrap_or(defaults.a),
        b: req.b.unwrap_or(defaults.b),
        p: req.p.unwrap_or(defaults.p),
        reach: req.reach.unwrap_or(f64::INFINITY),
    };
    let dim = match (req.pairs.first(), req.points.first()) {
        (Some((a, _)), _) => a.dim(),
        (None, Some(p)) => p.dim(),
        (None, None) => 2,
    };
    if dim == 2 {
        warp_points::<DVec2>(req.pairs, &req.points, params, |c| match c {
            DynCurve::D2(c) => Some(c),
            DynCurve::D3(_) => None,
        })
    } else {
        warp_points::<DVec3>(req.pairs, &req.points, params, |c| match c {
            DynCurve::D3(c) => Some(c),
            DynCurve::D2(_) => None,
        })
    }
}

fn warp_points<P: WarpSpace>(
    pairs: Vec<(DynCurve, DynCurve)>,
    points: &[JsonPoint],
    params: WarpParams,
    take: impl Fn(DynCurve) -> Option<Curve<P>>,
) -> Result<Value, CurveRequestError> {
    let mut typed = Vec::with_capacity(pairs.len());
    for (i, (a, b)) in pairs.into_iter().enumerate() {
        let mismatch = || {
            JsonError::at(
                &format!("pairs[{i}]"),
                format!("every curve and point of a warp must be {}D", P::DIM),
            )
        };
        typed.push((take(a).ok_or_else(mismatch)?, take(b).ok_or_else(mismatch)?));
    }
    let warp = CurveWarp::new(typed, params)?;
    let mut out = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        let x: P = p.typed(&format!("points[{i}]"))?;
        out.push(point_to_json(warp.warp_point(x)));
    }
    Ok(json!({ "points": out }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failing_line_does_not_stop_the_batch() {
        let input = "{\"op\":\"split\",\"curve\":{\"bezier\":[[0,0],[1,1],[2,0]]},\"u\":0.5}\nnot json\n\n{\"op\":\"nope\"}\n";
        let mut out = Vec::new();
        let failed =
            super::super::json_lines::answer_lines(input.as_bytes(), &mut out, answer).expect("io");
        assert_eq!(failed, 2);
        let text = String::from_utf8(out).expect("utf-8");
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].contains("curves"));
        assert!(lines[1].contains("error") && lines[2].contains("unknown op"));
    }
}
