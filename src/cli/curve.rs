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
//!   seed 004), `"nearest"` (the control point of the nearest parameter, seed 000) or
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
//!
//! A line that cannot be answered gets `{"error":"<what is wrong>"}`; later lines are still
//! answered, and the exit status is 1 if any line failed. Blank lines are skipped.

use crate::curve::edit::{self, Follow, Grab, GrabMethod, GrabOptions, Side};
use crate::curve::json::{DynCurve, curve_from_json, curve_to_json, point_to_json, typed_point};
use crate::curve::refine::{self, Constraint, Similarity};
use crate::curve::warp::{CurveWarp, WarpParams, WarpSpace};
use crate::curve::{Bezier, Curve, CurveError, Point, svg};
use clap::Args as ClapArgs;
use glam::{DVec2, DVec3};
use serde_json::{Value, json};
use std::io::{self, BufRead, Write};
use std::process::ExitCode;

/// Arguments of `nendo curve`.
#[derive(Debug, ClapArgs)]
pub struct Args {
    /// Read JSON Lines requests from stdin and answer each on stdout (the only mode).
    #[arg(long)]
    pub batch: bool,
}

/// Runs `nendo curve`.
pub fn run(args: Args) -> ExitCode {
    if !args.batch {
        eprintln!(
            "nendo curve: only --batch mode exists: JSON Lines requests on stdin (see `nendo curve --help` and the module docs)"
        );
        return ExitCode::from(2);
    }
    let stdin = io::stdin();
    let stdout = io::stdout();
    let mut out = io::BufWriter::new(stdout.lock());
    match answer_lines(stdin.lock(), &mut out) {
        Ok(0) => ExitCode::SUCCESS,
        Ok(_) => ExitCode::from(1),
        // A closed pipe ends the command quietly (see `super::output`).
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => {
            ExitCode::from(super::output::BROKEN_PIPE_EXIT)
        }
        Err(e) => {
            eprintln!("nendo curve: {e}");
            ExitCode::from(2)
        }
    }
}

/// Answers every request line of `input` on `output`; returns how many lines failed.
///
/// # Errors
/// Reading the input or writing the output failed.
pub fn answer_lines(input: impl BufRead, mut output: impl Write) -> io::Result<usize> {
    let mut failed = 0;
    for line in input.lines() {
        let line = match line {
            Ok(l) => l,
            Err(e) if e.kind() == io::ErrorKind::InvalidData => {
                failed += 1;
                writeln!(output, "{}", json!({ "error": "line is not valid UTF-8" }))?;
                continue;
            }
            Err(e) => return Err(e),
        };
        if line.trim().is_empty() {
            continue;
        }
        let reply = match answer(&line) {
            Ok(v) => v,
            Err(msg) => {
                failed += 1;
                json!({ "error": msg })
            }
        };
        writeln!(output, "{reply}")?;
        output.flush()?;
    }
    Ok(failed)
}

fn e(err: CurveError) -> String {
    err.to_string()
}

/// Answers one request line.
///
/// # Errors
/// A message saying what is wrong with the request.
pub fn answer(line: &str) -> Result<Value, String> {
    let req: Value = serde_json::from_str(line).map_err(|err| format!("malformed JSON: {err}"))?;
    let op = req.get("op").and_then(Value::as_str).ok_or(
        "missing \"op\" (grab, split, tangent, insert, refine, warp, svg_read or svg_write)",
    )?;
    match op {
        "grab" => match curve_from_json(field(&req, "curve")?).map_err(e)? {
            DynCurve::D2(c) => grab_reply(&c, &req),
            DynCurve::D3(c) => grab_reply(&c, &req),
        },
        "split" => {
            let u = number(&req, "u")?;
            match curve_from_json(field(&req, "curve")?).map_err(e)? {
                DynCurve::D2(c) => pair_reply(edit::split(&c, u)),
                DynCurve::D3(c) => pair_reply(edit::split(&c, u)),
            }
        }
        "tangent" => {
            let left =
                curve_from_json(field(&req, "left")?).map_err(|err| format!("left: {err}"))?;
            let right =
                curve_from_json(field(&req, "right")?).map_err(|err| format!("right: {err}"))?;
            match (left, right) {
                (DynCurve::D2(l), DynCurve::D2(r)) => tangent_reply(&l, &r, &req),
                (DynCurve::D3(l), DynCurve::D3(r)) => tangent_reply(&l, &r, &req),
                _ => Err("\"left\" and \"right\" must have the same dimension".into()),
            }
        }
        "insert" => {
            let u = number(&req, "u")?;
            let (curve, index) = match curve_from_json(field(&req, "curve")?).map_err(e)? {
                DynCurve::D2(c) => {
                    edit::insert_control_point(&c, u).map(|(c, k)| (curve_to_json(&c), k))
                }
                DynCurve::D3(c) => {
                    edit::insert_control_point(&c, u).map(|(c, k)| (curve_to_json(&c), k))
                }
            }
            .map_err(e)?;
            Ok(json!({ "curve": curve, "index": index }))
        }
        "refine" => refine_reply(&req),
        "warp" => warp_reply(&req),
        "svg_read" => {
            let text = field(&req, "svg")?
                .as_str()
                .ok_or("\"svg\" must be a string")?;
            let paths = svg::read_svg(text).map_err(|err| format!("svg: {err}"))?;
            Ok(json!({ "paths": paths.iter().map(|p| json!({
                "curves": p.segments.iter().map(|b| curve_to_json(&Curve::Bezier(b.clone()))).collect::<Vec<_>>(),
                "closed": p.closed,
            })).collect::<Vec<_>>() }))
        }
        "svg_write" => {
            let list = field(&req, "curves")?
                .as_array()
                .ok_or("\"curves\" must be an array")?;
            let mut curves = Vec::with_capacity(list.len());
            for (i, c) in list.iter().enumerate() {
                match curve_from_json(c).map_err(|err| format!("curve {i}: {err}"))? {
                    DynCurve::D2(c) => curves.push(c),
                    DynCurve::D3(_) => {
                        return Err(format!("curve {i} is 3D; SVG holds planar curves"));
                    }
                }
            }
            let flip_y = match req.get("flip_y") {
                None | Some(Value::Null) => false,
                Some(v) => v.as_bool().ok_or("\"flip_y\" must be true or false")?,
            };
            let text = svg::write_svg(
                &curves,
                svg::SvgOptions {
                    flip_y,
                    ..svg::SvgOptions::default()
                },
            )
            .map_err(|err| format!("svg: {err}"))?;
            Ok(json!({ "svg": text }))
        }
        other => Err(format!(
            "unknown op {other:?}; expected grab, split, tangent, insert, refine, warp, svg_read or svg_write"
        )),
    }
}

fn field<'a>(req: &'a Value, name: &str) -> Result<&'a Value, String> {
    req.get(name).ok_or_else(|| format!("missing \"{name}\""))
}

fn number(req: &Value, name: &str) -> Result<f64, String> {
    let v = field(req, name)?
        .as_f64()
        .ok_or_else(|| format!("\"{name}\" must be a number"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("\"{name}\" is not a finite number"))
    }
}

fn optional_number(req: &Value, name: &str, default: f64) -> Result<f64, String> {
    match req.get(name) {
        None | Some(Value::Null) => Ok(default),
        Some(_) => number(req, name),
    }
}

/// An optional string member: absent or null gives `None`; anything but a string is an error.
fn optional_string<'a>(req: &'a Value, name: &str) -> Result<Option<&'a str>, String> {
    match req.get(name) {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(s)) => Ok(Some(s)),
        Some(other) => Err(format!("\"{name}\" must be a string, got {other}")),
    }
}

fn grab_reply<P: Point>(c: &Curve<P>, req: &Value) -> Result<Value, String> {
    let from: P = typed_point(field(req, "from")?, "from").map_err(e)?;
    let to: P = typed_point(field(req, "to")?, "to").map_err(e)?;
    let rmax = match req.get("rmax") {
        None | Some(Value::Null) => f64::INFINITY,
        Some(_) => crate::curve::check_radius("rmax", number(req, "rmax")?).map_err(e)?,
    };
    let method = match optional_string(req, "method")? {
        None | Some("largest") => GrabMethod::LargestWeight,
        Some("nearest") => GrabMethod::NearestParameter,
        Some("least_change") => GrabMethod::LeastChange,
        Some(other) => {
            return Err(format!(
                "unknown grab method {other:?}; expected largest, nearest or least_change"
            ));
        }
    };
    let keep_ends = match req.get("keep_ends") {
        None | Some(Value::Null) => false,
        Some(v) => v.as_bool().ok_or("\"keep_ends\" must be true or false")?,
    };
    match Grab::at_point(c, from, rmax, GrabOptions { method, keep_ends }).map_err(e)? {
        Some(g) => {
            let moved = g.moved_by(to - from).map_err(e)?;
            Ok(json!({ "curve": curve_to_json(&moved), "u": g.u() }))
        }
        None => Ok(json!({ "curve": null, "u": null })),
    }
}

fn pair_reply<P: Point>(r: Result<(Curve<P>, Curve<P>), CurveError>) -> Result<Value, String> {
    let (a, b) = r.map_err(e)?;
    Ok(json!({ "curves": [curve_to_json(&a), curve_to_json(&b)] }))
}

fn tangent_reply<P: Point>(l: &Curve<P>, r: &Curve<P>, req: &Value) -> Result<Value, String> {
    let side = match field(req, "side")?.as_str() {
        Some("left") => Side::Left,
        Some("right") => Side::Right,
        _ => return Err("\"side\" must be \"left\" or \"right\"".into()),
    };
    let follow = match optional_string(req, "follow")? {
        None | Some("length") => Follow::KeepLength,
        Some("ratio") => Follow::KeepRatio,
        Some(other) => {
            return Err(format!(
                "unknown follow {other:?}; expected length or ratio"
            ));
        }
    };
    let to: P = typed_point(field(req, "to")?, "to").map_err(e)?;
    pair_reply(edit::tangent_edit(l, r, side, to, follow))
}

fn vec2(v: &Value, what: &str) -> Result<DVec2, String> {
    typed_point::<DVec2>(v, what).map_err(e)
}

/// Reads one constraint of the forms listed in the module docs.
fn constraint(v: &Value, i: usize) -> Result<Constraint, String> {
    let what = format!("constraint {i}");
    if !v.is_object() {
        return Err(format!("{what} must be an object"));
    }
    if let Some(at) = v.get("join") {
        let at = at
            .as_u64()
            .ok_or_else(|| format!("{what}: \"join\" must be a segment index"))?;
        let order = v
            .get("order")
            .and_then(Value::as_u64)
            .ok_or_else(|| format!("{what}: a join needs \"order\" 0, 1 or 2"))?;
        return Ok(Constraint::Join {
            at: at as usize,
            order: order as usize,
        });
    }
    let u = v
        .get("u")
        .and_then(Value::as_f64)
        .filter(|u| u.is_finite())
        .ok_or_else(|| format!("{what}: needs a finite parameter \"u\""))?;
    if let Some(p) = v.get("point") {
        Ok(Constraint::Point {
            u,
            point: vec2(p, &format!("{what} point"))?,
        })
    } else if let Some(d) = v.get("tangent") {
        Ok(Constraint::Tangent {
            u,
            direction: vec2(d, &format!("{what} tangent"))?,
        })
    } else if let Some(d) = v.get("derivative") {
        Ok(Constraint::Derivative {
            u,
            vector: vec2(d, &format!("{what} derivative"))?,
        })
    } else {
        Err(format!(
            "{what}: expected \"point\", \"tangent\", \"derivative\" (with \"u\") or \"join\""
        ))
    }
}

fn refine_reply(req: &Value) -> Result<Value, String> {
    let mode = match field(req, "mode")?.as_str() {
        Some("curvature") => Similarity::Curvature,
        Some("variation") => Similarity::Variation,
        _ => return Err("\"mode\" must be \"curvature\" or \"variation\"".into()),
    };
    let constraints = match req.get("constraints") {
        None | Some(Value::Null) => Vec::new(),
        Some(Value::Array(list)) => list
            .iter()
            .enumerate()
            .map(|(i, c)| constraint(c, i))
            .collect::<Result<Vec<_>, _>>()?,
        Some(_) => return Err("\"constraints\" must be an array".into()),
    };
    if let Some(list) = req.get("curves") {
        let list = list
            .as_array()
            .ok_or("\"curves\" must be an array of Bezier segments")?;
        let mut segs = Vec::with_capacity(list.len());
        for (i, c) in list.iter().enumerate() {
            match curve_from_json(c).map_err(|err| format!("curve {i}: {err}"))? {
                DynCurve::D2(Curve::Bezier(b)) => segs.push(b),
                DynCurve::D2(Curve::BSpline(_)) => {
                    return Err(format!(
                        "curve {i}: a piecewise curve is made of Bezier segments"
                    ));
                }
                DynCurve::D3(_) => {
                    return Err(format!("curve {i}: refinement works on planar (2D) curves"));
                }
            }
        }
        let r = refine::refine_piecewise(&segs, mode, &constraints).map_err(e)?;
        let out: Vec<Value> = r
            .curve
            .into_iter()
            .map(|b: Bezier<DVec2>| curve_to_json(&Curve::Bezier(b)))
            .collect();
        return Ok(
            json!({ "curves": out, "residual": r.constraint_residual, "similarity": r.similarity_rms }),
        );
    }
    match curve_from_json(field(req, "curve")?).map_err(e)? {
        DynCurve::D2(c) => {
            let r = refine::refine(&c, mode, &constraints).map_err(e)?;
            Ok(
                json!({ "curve": curve_to_json(&r.curve), "residual": r.constraint_residual, "similarity": r.similarity_rms }),
            )
        }
        DynCurve::D3(_) => Err("refinement works on planar (2D) curves".into()),
    }
}

fn warp_reply(req: &Value) -> Result<Value, String> {
    let list = field(req, "pairs")?
        .as_array()
        .ok_or("\"pairs\" must be an array of [original, deformed]")?;
    let mut pairs = Vec::with_capacity(list.len());
    for (i, p) in list.iter().enumerate() {
        let two = p
            .as_array()
            .filter(|a| a.len() == 2)
            .ok_or_else(|| format!("pair {i} must be [original, deformed]"))?;
        let a = curve_from_json(&two[0]).map_err(|err| format!("pair {i} original: {err}"))?;
        let b = curve_from_json(&two[1]).map_err(|err| format!("pair {i} deformed: {err}"))?;
        pairs.push((a, b));
    }
    let defaults = WarpParams::default();
    let params = WarpParams {
        a: optional_number(req, "a", defaults.a)?,
        b: optional_number(req, "b", defaults.b)?,
        p: optional_number(req, "p", defaults.p)?,
        reach: match req.get("reach") {
            None | Some(Value::Null) => f64::INFINITY,
            Some(_) => number(req, "reach")?,
        },
    };
    let points = field(req, "points")?
        .as_array()
        .ok_or("\"points\" must be an array")?;
    let dim = match (pairs.first(), points.first()) {
        (Some((a, _)), _) => a.dim(),
        (None, Some(p)) => p.as_array().map_or(2, Vec::len),
        (None, None) => 2,
    };
    if dim == 2 {
        warp_points::<DVec2>(pairs, points, params, |c| match c {
            DynCurve::D2(c) => Some(c),
            DynCurve::D3(_) => None,
        })
    } else {
        warp_points::<DVec3>(pairs, points, params, |c| match c {
            DynCurve::D3(c) => Some(c),
            DynCurve::D2(_) => None,
        })
    }
}

fn warp_points<P: WarpSpace>(
    pairs: Vec<(DynCurve, DynCurve)>,
    points: &[Value],
    params: WarpParams,
    take: impl Fn(DynCurve) -> Option<Curve<P>>,
) -> Result<Value, String> {
    let mut typed = Vec::with_capacity(pairs.len());
    for (i, (a, b)) in pairs.into_iter().enumerate() {
        let mismatch = || {
            format!(
                "pair {i}: every curve and point of a warp must be {}D",
                P::DIM
            )
        };
        typed.push((take(a).ok_or_else(mismatch)?, take(b).ok_or_else(mismatch)?));
    }
    let warp = CurveWarp::new(typed, params).map_err(e)?;
    let mut out = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        let x: P = typed_point(p, &format!("point {i}")).map_err(e)?;
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
        let failed = answer_lines(input.as_bytes(), &mut out).expect("io");
        assert_eq!(failed, 2);
        let text = String::from_utf8(out).expect("utf-8");
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].contains("curves"));
        assert!(lines[1].contains("error") && lines[2].contains("unknown op"));
    }
}
