//! `nendo closest --batch`: curve queries as JSON Lines (one request per input line on stdin,
//! one answer per output line on stdout, same order).
//!
//! Requests (curves in the form of [`crate::curve::json`]):
//! * `{"op":"closest","curve":C,"point":Q,"rmax":R?}` → `{"u":u,"point":[...],"distance":d}` or
//!   `{"u":null}` when nothing lies within R;
//! * `{"op":"pick","curves":[C...],"point":Q,"rmax":R?}` →
//!   `{"index":i,"u":u,"point":[...],"distance":d}` or `{"index":null}`;
//! * `{"op":"sphere","curve":C,"center":Q,"radius":R}` → `{"intervals":[[a,b],...]}`;
//! * `{"op":"ray","curve":C,"origin":O,"dir":D}` → `{"u":u,"point":[...],"ray_t":s,"distance":d}`.
//!
//! A request has exactly the members listed (`rmax` may be absent or null): an unknown member
//! (a misspelled `"rMax"`) or a repeated one is refused, as is a line starting with a
//! byte-order mark. A line that cannot be answered gets `{"error":"<what is wrong>"}`, naming
//! the bad member's path and column (e.g. `curve.bezier[2]: ...`); later lines are still
//! answered, and the exit status is 1 if any line failed. Blank lines are skipped.

use crate::curve::json::{DynCurve, JsonPoint, point_to_json};
use crate::curve::{Curve, CurveError, Point, check_radius, pick};
use crate::json_doc::{self, JsonError};
use clap::Args as ClapArgs;
use glam::{DVec2, DVec3};
use serde::Deserialize;
use serde::de::IgnoredAny;
use serde_json::{Value, json};
use std::process::ExitCode;

/// Arguments of `nendo closest`.
#[derive(Debug, ClapArgs)]
pub struct ClosestArgs {
    /// Read JSON Lines requests from stdin and answer each on stdout (the only mode).
    #[arg(long)]
    pub batch: bool,
}

/// Runs `nendo closest`.
pub fn run(args: ClosestArgs) -> ExitCode {
    super::json_lines::run("closest", args.batch, answer)
}

/// Why one request line cannot be answered.
#[derive(Debug, thiserror::Error)]
pub enum ClosestRequestError {
    /// Not JSON, or a member missing, unknown, repeated or invalid (with its path).
    #[error("{0}")]
    Json(#[from] JsonError),
    /// An `op` this protocol does not have.
    #[error("unknown op {0:?}; expected closest, pick, sphere or ray")]
    UnknownOp(String),
    /// The query's own constraints (a negative radius, a zero direction).
    #[error("{0}")]
    Curve(#[from] CurveError),
    /// The ray query has no answer (non-finite input).
    #[error("the ray query has no answer (non-finite input)")]
    NoRayAnswer,
    /// A number of the answer overflows a double.
    #[error("the answer is not representable: a distance overflows a double")]
    NotRepresentable,
}

/// Only the `op` member (the others are read by the request's own structure).
#[derive(Deserialize)]
#[serde(expecting = "a request (a JSON object with an \"op\")")]
struct OpOnly {
    op: String,
}

/// `{"op":"closest","curve":C,"point":Q,"rmax":R?}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ClosestRequest {
    #[allow(dead_code)]
    op: IgnoredAny,
    curve: DynCurve,
    point: JsonPoint,
    #[serde(default)]
    rmax: Option<f64>,
}

/// `{"op":"pick","curves":[C...],"point":Q,"rmax":R?}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PickRequest {
    #[allow(dead_code)]
    op: IgnoredAny,
    curves: Vec<DynCurve>,
    point: JsonPoint,
    #[serde(default)]
    rmax: Option<f64>,
}

/// `{"op":"sphere","curve":C,"center":Q,"radius":R}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SphereRequest {
    #[allow(dead_code)]
    op: IgnoredAny,
    curve: DynCurve,
    center: JsonPoint,
    radius: f64,
}

/// `{"op":"ray","curve":C,"origin":O,"dir":D}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RayRequest {
    #[allow(dead_code)]
    op: IgnoredAny,
    curve: DynCurve,
    origin: JsonPoint,
    dir: JsonPoint,
}

/// Answers one request line.
///
/// # Errors
/// A [`ClosestRequestError`] saying what is wrong with the request (and at which member).
pub fn answer(line: &str) -> Result<Value, ClosestRequestError> {
    let op = json_doc::from_str::<OpOnly>(line)?.op;
    match op.as_str() {
        "closest" => {
            let r: ClosestRequest = json_doc::from_str(line)?;
            let rmax = rmax(r.rmax)?;
            match r.curve {
                DynCurve::D2(c) => closest_reply(&c, r.point.typed("point")?, rmax),
                DynCurve::D3(c) => closest_reply(&c, r.point.typed("point")?, rmax),
            }
        }
        "pick" => {
            let r: PickRequest = json_doc::from_str(line)?;
            let rmax = rmax(r.rmax)?;
            match r.curves.first().map(DynCurve::dim) {
                // No curve to pick; the point was still read as a valid 2D or 3D point.
                None => Ok(json!({ "index": null })),
                Some(2) => pick_reply::<DVec2>(
                    &same_dim(r.curves, |c| match c {
                        DynCurve::D2(c) => Some(c),
                        DynCurve::D3(_) => None,
                    })?,
                    r.point.typed("point")?,
                    rmax,
                ),
                Some(_) => pick_reply::<DVec3>(
                    &same_dim(r.curves, |c| match c {
                        DynCurve::D3(c) => Some(c),
                        DynCurve::D2(_) => None,
                    })?,
                    r.point.typed("point")?,
                    rmax,
                ),
            }
        }
        "sphere" => {
            let r: SphereRequest = json_doc::from_str(line)?;
            check_radius("radius", r.radius)?;
            let iv = match r.curve {
                DynCurve::D2(cv) => cv.sphere_intervals(r.center.typed("center")?, r.radius),
                DynCurve::D3(cv) => cv.sphere_intervals(r.center.typed("center")?, r.radius),
            };
            Ok(json!({ "intervals": iv.iter().map(|&(a, b)| json!([a, b])).collect::<Vec<_>>() }))
        }
        "ray" => {
            let r: RayRequest = json_doc::from_str(line)?;
            match r.curve {
                DynCurve::D2(c) => ray_reply(&c, r.origin.typed("origin")?, r.dir.typed("dir")?),
                DynCurve::D3(c) => ray_reply(&c, r.origin.typed("origin")?, r.dir.typed("dir")?),
            }
        }
        _ => Err(ClosestRequestError::UnknownOp(op)),
    }
}

/// The search radius: infinite when absent or null.
fn rmax(r: Option<f64>) -> Result<f64, ClosestRequestError> {
    match r {
        None => Ok(f64::INFINITY),
        Some(r) => Ok(check_radius("rmax", r)?),
    }
}

fn same_dim<P: Point>(
    curves: Vec<DynCurve>,
    take: impl Fn(DynCurve) -> Option<Curve<P>>,
) -> Result<Vec<Curve<P>>, ClosestRequestError> {
    curves
        .into_iter()
        .enumerate()
        .map(|(i, c)| {
            let d = c.dim();
            take(c).ok_or_else(|| {
                JsonError::at(
                    &format!("curves[{i}]"),
                    format!("the curve is {d}D but curve 0 is {}D", P::DIM),
                )
                .into()
            })
        })
        .collect()
}

/// `Ok` when every number of an answer is finite: a result that overflows a double (two
/// points farther apart than ~1.8e308) is an error, never a JSON `null`.
fn finite_answer<P: Point>(numbers: &[f64], point: P) -> Result<(), ClosestRequestError> {
    if numbers.iter().all(|v| v.is_finite()) && point.is_finite_coeff() {
        Ok(())
    } else {
        Err(ClosestRequestError::NotRepresentable)
    }
}

fn closest_reply<P: Point>(c: &Curve<P>, q: P, rmax: f64) -> Result<Value, ClosestRequestError> {
    Ok(match c.closest(q, rmax) {
        Some(n) => {
            finite_answer(&[n.u, n.distance], n.point)?;
            json!({ "u": n.u, "point": point_to_json(n.point), "distance": n.distance })
        }
        None => json!({ "u": null }),
    })
}

fn pick_reply<P: Point>(
    curves: &[Curve<P>],
    q: P,
    rmax: f64,
) -> Result<Value, ClosestRequestError> {
    Ok(match pick(curves, q, rmax) {
        Some(p) => {
            finite_answer(&[p.nearest.u, p.nearest.distance], p.nearest.point)?;
            json!({
                "index": p.index, "u": p.nearest.u, "point": point_to_json(p.nearest.point), "distance": p.nearest.distance
            })
        }
        None => json!({ "index": null }),
    })
}

fn ray_reply<P: Point>(c: &Curve<P>, o: P, d: P) -> Result<Value, ClosestRequestError> {
    if (0..P::DIM).all(|i| d.coord(i) == 0.0) {
        return Err(CurveError::ZeroVector("dir").into());
    }
    let r = c
        .ray_closest(o, d)
        .ok_or(ClosestRequestError::NoRayAnswer)?;
    finite_answer(&[r.u, r.ray_t, r.distance], r.point)?;
    Ok(
        json!({ "u": r.u, "point": point_to_json(r.point), "ray_t": r.ray_t, "distance": r.distance }),
    )
}
