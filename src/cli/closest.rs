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
//! A line that cannot be answered gets `{"error":"<what is wrong>"}`; later lines are still
//! answered, and the exit status is 1 if any line failed. Blank lines are skipped.

use crate::curve::json::{DynCurve, curve_from_json, point_to_json, typed_point};
use crate::curve::{Curve, CurveError, Point, check_radius, pick};
use clap::Args as ClapArgs;
use glam::{DVec2, DVec3};
use serde_json::{Value, json};
use std::io::{self, BufRead, Write};
use std::process::ExitCode;

/// Arguments of `nendo closest`.
#[derive(Debug, ClapArgs)]
pub struct Args {
    /// Read JSON Lines requests from stdin and answer each on stdout (the only mode).
    #[arg(long)]
    pub batch: bool,
}

/// Runs `nendo closest`.
pub fn run(args: Args) -> ExitCode {
    if !args.batch {
        eprintln!(
            "nendo closest: only --batch mode exists: JSON Lines requests on stdin (see `nendo closest --help`)"
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
            eprintln!("nendo closest: {e}");
            ExitCode::from(2)
        }
    }
}

/// Answers every request line of `input` on `output`; returns how many lines failed.
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

/// Answers one request line.
pub fn answer(line: &str) -> Result<Value, String> {
    let req: Value = serde_json::from_str(line).map_err(|e| format!("malformed JSON: {e}"))?;
    let op = req
        .get("op")
        .and_then(Value::as_str)
        .ok_or("missing \"op\" (closest, pick, sphere or ray)")?;
    let e = |e: CurveError| e.to_string();
    match op {
        "closest" => {
            let curve = curve_from_json(field(&req, "curve")?).map_err(e)?;
            let rmax = rmax(&req)?;
            match curve {
                DynCurve::D2(c) => closest_reply(
                    &c,
                    typed_point(field(&req, "point")?, "point").map_err(e)?,
                    rmax,
                ),
                DynCurve::D3(c) => closest_reply(
                    &c,
                    typed_point(field(&req, "point")?, "point").map_err(e)?,
                    rmax,
                ),
            }
        }
        "pick" => {
            let list = field(&req, "curves")?
                .as_array()
                .ok_or("\"curves\" must be an array")?;
            let mut curves = Vec::with_capacity(list.len());
            for (i, c) in list.iter().enumerate() {
                curves.push(curve_from_json(c).map_err(|err| format!("curve {i}: {err}"))?);
            }
            let rmax = rmax(&req)?;
            let q = field(&req, "point")?;
            match curves.first().map(DynCurve::dim) {
                None => {
                    // No curve to pick; the point must still be a valid 2D or 3D point.
                    typed_point::<DVec2>(q, "point")
                        .map(|_| ())
                        .or_else(|_| typed_point::<DVec3>(q, "point").map(|_| ()))
                        .map_err(e)?;
                    Ok(json!({ "index": null }))
                }
                Some(2) => pick_reply::<DVec2>(
                    &same_dim(curves, |c| match c {
                        DynCurve::D2(c) => Some(c),
                        DynCurve::D3(_) => None,
                    })?,
                    typed_point(q, "point").map_err(e)?,
                    rmax,
                ),
                Some(_) => pick_reply::<DVec3>(
                    &same_dim(curves, |c| match c {
                        DynCurve::D3(c) => Some(c),
                        DynCurve::D2(_) => None,
                    })?,
                    typed_point(q, "point").map_err(e)?,
                    rmax,
                ),
            }
        }
        "sphere" => {
            let curve = curve_from_json(field(&req, "curve")?).map_err(e)?;
            let radius = number(&req, "radius")?;
            check_radius("radius", radius).map_err(e)?;
            let c = field(&req, "center")?;
            let iv = match curve {
                DynCurve::D2(cv) => {
                    cv.sphere_intervals(typed_point(c, "center").map_err(e)?, radius)
                }
                DynCurve::D3(cv) => {
                    cv.sphere_intervals(typed_point(c, "center").map_err(e)?, radius)
                }
            };
            Ok(json!({ "intervals": iv.iter().map(|&(a, b)| json!([a, b])).collect::<Vec<_>>() }))
        }
        "ray" => {
            let curve = curve_from_json(field(&req, "curve")?).map_err(e)?;
            match curve {
                DynCurve::D2(c) => ray_reply(&c, &req),
                DynCurve::D3(c) => ray_reply(&c, &req),
            }
        }
        other => Err(format!(
            "unknown op {other:?}; expected closest, pick, sphere or ray"
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

fn rmax(req: &Value) -> Result<f64, String> {
    match req.get("rmax") {
        None | Some(Value::Null) => Ok(f64::INFINITY),
        Some(_) => {
            let r = number(req, "rmax")?;
            check_radius("rmax", r).map_err(|e| e.to_string())
        }
    }
}

fn same_dim<P: Point>(
    curves: Vec<DynCurve>,
    take: impl Fn(DynCurve) -> Option<Curve<P>>,
) -> Result<Vec<Curve<P>>, String> {
    curves
        .into_iter()
        .enumerate()
        .map(|(i, c)| {
            let d = c.dim();
            take(c).ok_or_else(|| format!("curve {i} is {d}D but curve 0 is {}D", P::DIM))
        })
        .collect()
}

/// `Ok` when every number of an answer is finite: a result that overflows a double (two
/// points farther apart than ~1.8e308) is an error, never a JSON `null`.
fn finite_answer<P: Point>(numbers: &[f64], point: P) -> Result<(), String> {
    if numbers.iter().all(|v| v.is_finite()) && point.is_finite_coeff() {
        Ok(())
    } else {
        Err("the answer is not representable: a distance overflows a double".to_string())
    }
}

fn closest_reply<P: Point>(c: &Curve<P>, q: P, rmax: f64) -> Result<Value, String> {
    Ok(match c.closest(q, rmax) {
        Some(n) => {
            finite_answer(&[n.u, n.distance], n.point)?;
            json!({ "u": n.u, "point": point_to_json(n.point), "distance": n.distance })
        }
        None => json!({ "u": null }),
    })
}

fn pick_reply<P: Point>(curves: &[Curve<P>], q: P, rmax: f64) -> Result<Value, String> {
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

fn ray_reply<P: Point>(c: &Curve<P>, req: &Value) -> Result<Value, String> {
    let e = |e: CurveError| e.to_string();
    let o: P = typed_point(field(req, "origin")?, "origin").map_err(e)?;
    let d: P = typed_point(field(req, "dir")?, "dir").map_err(e)?;
    if (0..P::DIM).all(|i| d.coord(i) == 0.0) {
        return Err(CurveError::ZeroVector("dir").to_string());
    }
    let r = c
        .ray_closest(o, d)
        .ok_or("the ray query has no answer (non-finite input)")?;
    finite_answer(&[r.u, r.ray_t, r.distance], r.point)?;
    Ok(
        json!({ "u": r.u, "point": point_to_json(r.point), "ray_t": r.ray_t, "distance": r.distance }),
    )
}
