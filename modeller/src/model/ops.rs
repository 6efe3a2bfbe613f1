//! Operations as JSON lines — the script `nendo sculpt --ops` replays:
//!
//! ```json
//! {"op": "push", "at": [x, y, z], "dir": [dx, dy, dz], "depth": d, "radius": r_f}
//! {"op": "drag", "path": [[x, y, z], …], "dir": [dx, dy, dz], "depth": d, "radius": r_f}
//! {"op": "push", "at": [x, y, z], "dir": "normal", "depth": d, "radius": r_f}
//! {"op": "drag", "path": [[x, y, z], …], "dir": "normal", "depth": d, "radius": r_f}
//! {"op": "drag", "path": [[x, y, z], …], "dirs": [[dx, dy, dz], …], "depth": d, "radius": r_f}
//! {"op": "move", "at": [x, y, z], "to": [x, y, z], "radius": r_f}
//! {"op": "smooth", "at": [x, y, z], "radius": r, "strength": s}
//! {"op": "push", …, "brush": "soft", "strength": s}
//! {"op": "inflate", "at": [x, y, z], "depth": h, "radius": R}
//! {"op": "flatten", "at": [x, y, z], "radius": R}
//! {"op": "pinch", "path": [[x, y, z], …], "radius": R, "brush": "soft", "strength": s}
//! {"op": "crease", "path": [[x, y, z], …], "depth": h, "radius": R}
//! ```
//!
//! A negative depth pulls (push) or raises a ridge (drag); see [`crate::surface::shape_fn`].
//! `"dir": "normal"` presses each point along the surface's inward normal at the surface point
//! nearest to it (outward for a negative depth); `"dirs"` gives one direction per path point
//! (a drag has exactly one of `dir` and `dirs`). `move` takes the surface point nearest `at`
//! exactly to `to` ([`crate::surface::grab`]); `smooth` (`0 < strength ≤ 1`) fairs the
//! surface within `radius` of `at` (an implicit diffusion step, [`crate::surface::fairing`]).
//! A push or drag may name a brush (`"brush"`: `"finger"`, the default, `"soft"` or `"flat"`)
//! and a `"strength"` (`0 < s ≤ 1`, default 1): the fraction of the depth it presses
//! ([`crate::surface::brush`]); either member makes it an [`Op::Brushed`].
//! The surface brushes ([`crate::surface::sculpt_brush`], an [`Op::Sculpt`]) take a dab point
//! `at` or a stroke `path` (one or more points; exactly one of the two), a radius, the optional
//! `"brush"` and `"strength"` (default `"finger"` and 1), and a depth for `inflate` (`h > 0`
//! outward along the surface normal, `h < 0` inward) and `crease` (`h > 0` a valley pressed in,
//! `h < 0` a ridge); `flatten` (toward the weighted average plane under the brush) and `pinch`
//! (toward the stroke along the surface) take none. Numbers beyond `1e30` in size are refused.
//! Blank lines are skipped. Every line is validated completely (members, numbers, the
//! operation's own constraints) before any is applied: a missing, unknown or repeated member
//! is refused with its path and column (see [`crate::json_doc`]), and a `dir` whose length
//! overflows a double is refused as not finite after normalising.

use glam::DVec3;
use serde::Deserialize;
use serde::de::IgnoredAny;
use serde_json::{Value, json};

use crate::json_doc::{self, JsonError};
use crate::surface::{Brush, Dirs, Falloff, Op, SculptBrush, SculptKind, SurfaceError};

/// A bad line of an operations file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct OpLineError {
    /// 1-based line number.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// Why one operation line cannot be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OpError {
    /// Not JSON, or a member missing, unknown, repeated or of the wrong type (with its path).
    #[error("{0}")]
    Json(#[from] JsonError),
    /// An `op` other than `push`, `drag`, `move`, `smooth`, `inflate`, `flatten`, `pinch` and
    /// `crease`.
    #[error(
        "unknown op {0:?}: expected \"push\", \"drag\", \"move\", \"smooth\", \"inflate\", \"flatten\", \"pinch\" or \"crease\""
    )]
    UnknownOp(String),
    /// A non-zero direction whose length over- or underflows a double, so that normalising it
    /// gives no finite unit vector (e.g. `[1e308, 1e308, -1e308]`).
    #[error(
        "dir is not finite after normalising: its length over- or underflows a double; rescale it"
    )]
    DirOverflow,
    /// The operation's own constraints (a zero `dir`, a radius that is not positive, …).
    #[error("{0}")]
    Invalid(#[from] SurfaceError),
}

/// Only the `op` member (the others are read by the operation's own structure).
#[derive(Deserialize)]
#[serde(
    expecting = "an operation (a JSON object with \"op\": \"push\", \"drag\", \"move\" or \"smooth\")"
)]
struct OpKind {
    op: String,
}

/// `{"op": "push", "at", "dir", "depth", "radius"}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PushDoc {
    #[allow(dead_code)]
    op: IgnoredAny,
    at: [f64; 3],
    dir: DirDoc,
    depth: f64,
    radius: f64,
    brush: Option<String>,
    strength: Option<f64>,
}

/// `{"op": "drag", "path", "dir" | "dirs", "depth", "radius"}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DragDoc {
    #[allow(dead_code)]
    op: IgnoredAny,
    path: Vec<[f64; 3]>,
    dir: Option<DirDoc>,
    dirs: Option<Vec<[f64; 3]>>,
    depth: f64,
    radius: f64,
    brush: Option<String>,
    strength: Option<f64>,
}

/// `{"op": "move", "at", "to", "radius"}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MoveDoc {
    #[allow(dead_code)]
    op: IgnoredAny,
    at: [f64; 3],
    to: [f64; 3],
    radius: f64,
}

/// `{"op": "smooth", "at", "radius", "strength"}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SmoothDoc {
    #[allow(dead_code)]
    op: IgnoredAny,
    at: [f64; 3],
    radius: f64,
    strength: f64,
}

/// `{"op": "inflate" | "flatten" | "pinch" | "crease", "at" | "path", "depth", "radius"}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SculptDoc {
    #[allow(dead_code)]
    op: IgnoredAny,
    at: Option<[f64; 3]>,
    path: Option<Vec<[f64; 3]>>,
    depth: Option<f64>,
    radius: f64,
    brush: Option<String>,
    strength: Option<f64>,
}

/// A `dir` member: a vector `[dx, dy, dz]` or the word `"normal"`.
enum DirDoc {
    Vector([f64; 3]),
    Normal,
}

impl<'de> Deserialize<'de> for DirDoc {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visit;
        impl<'de> serde::de::Visitor<'de> for Visit {
            type Value = DirDoc;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a direction [dx, dy, dz] or \"normal\"")
            }

            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<DirDoc, E> {
                if v == "normal" {
                    Ok(DirDoc::Normal)
                } else {
                    Err(E::invalid_value(serde::de::Unexpected::Str(v), &self))
                }
            }

            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<DirDoc, A::Error> {
                let mut x = [0.0; 3];
                for (k, slot) in x.iter_mut().enumerate() {
                    *slot = seq
                        .next_element::<f64>()?
                        .ok_or_else(|| serde::de::Error::invalid_length(k, &self))?;
                }
                if seq.next_element::<IgnoredAny>()?.is_some() {
                    return Err(serde::de::Error::invalid_length(4, &self));
                }
                Ok(DirDoc::Vector(x))
            }
        }
        d.deserialize_any(Visit)
    }
}

/// Refuses a non-zero direction whose length over- or underflows a double.
fn check_dir(dir: DVec3) -> Result<(), OpError> {
    if dir.is_finite() && dir != DVec3::ZERO && dir.try_normalize().is_none() {
        return Err(OpError::DirOverflow);
    }
    Ok(())
}

/// Parses one operation.
///
/// # Errors
/// An [`OpError`] saying what is wrong with the line (and at which member).
pub fn parse_op(text: &str) -> Result<Op, OpError> {
    // serde reads a struct from an array too: an operation must be an object.
    if !text.trim_start().starts_with(['{', '\u{feff}']) {
        return Err(JsonError::at("", "an operation must be a JSON object").into());
    }
    let kind = json_doc::from_str::<OpKind>(text)?.op;
    let v = DVec3::from_array;
    let mut brush = (None, None);
    let op = match kind.as_str() {
        "push" => {
            let d: PushDoc = json_doc::from_str(text)?;
            brush = (d.brush, d.strength);
            match d.dir {
                DirDoc::Vector(dir) => Op::Push {
                    at: v(d.at),
                    dir: v(dir),
                    depth: d.depth,
                    radius: d.radius,
                },
                DirDoc::Normal => Op::PushNormal {
                    at: v(d.at),
                    depth: d.depth,
                    radius: d.radius,
                },
            }
        }
        "drag" => {
            let d: DragDoc = json_doc::from_str(text)?;
            brush = (d.brush, d.strength);
            let path: Vec<DVec3> = d.path.into_iter().map(v).collect();
            match (d.dir, d.dirs) {
                (Some(DirDoc::Vector(dir)), None) => Op::Drag {
                    path,
                    dir: v(dir),
                    depth: d.depth,
                    radius: d.radius,
                },
                (Some(DirDoc::Normal), None) => Op::Groove {
                    path,
                    dirs: Dirs::Normal,
                    depth: d.depth,
                    radius: d.radius,
                },
                (None, Some(dirs)) => {
                    let dirs: Vec<DVec3> = dirs.into_iter().map(v).collect();
                    for &x in &dirs {
                        check_dir(x)?;
                    }
                    Op::Groove {
                        path,
                        dirs: Dirs::Each(dirs),
                        depth: d.depth,
                        radius: d.radius,
                    }
                }
                (Some(_), Some(_)) => {
                    return Err(
                        JsonError::at("dirs", "give either \"dir\" or \"dirs\", not both").into(),
                    );
                }
                (None, None) => {
                    return Err(JsonError::at(
                        "dir",
                        "missing field \"dir\" (a direction or \"normal\"; or \"dirs\", one per path point)",
                    )
                    .into());
                }
            }
        }
        "move" => {
            let d: MoveDoc = json_doc::from_str(text)?;
            Op::Move {
                at: v(d.at),
                to: v(d.to),
                radius: d.radius,
            }
        }
        "smooth" => {
            let d: SmoothDoc = json_doc::from_str(text)?;
            Op::Smooth {
                at: v(d.at),
                radius: d.radius,
                strength: d.strength,
            }
        }
        name => match SculptKind::from_name(name) {
            Some(kind) => return sculpt_op(kind, json_doc::from_str(text)?),
            None => return Err(OpError::UnknownOp(kind)),
        },
    };
    if let Op::Push { dir, .. } | Op::Drag { dir, .. } = &op {
        check_dir(*dir)?;
    }
    let op = match brush {
        (None, None) => op,
        (name, strength) => Op::Brushed {
            op: Box::new(op),
            brush: brush_of(name, strength)?,
        },
    };
    op.validate()?;
    Ok(op)
}

/// An op line's `"brush"` and `"strength"` members as a [`Brush`] (the finger and full strength
/// where missing; the strength is checked with the op).
fn brush_of(name: Option<String>, strength: Option<f64>) -> Result<Brush, JsonError> {
    let falloff = match name {
        None => Falloff::Finger,
        Some(n) => Falloff::from_name(&n).ok_or_else(|| {
            JsonError::at(
                "brush",
                format!("unknown brush {n:?}: expected \"finger\", \"soft\" or \"flat\""),
            )
        })?,
    };
    Ok(Brush {
        falloff,
        strength: strength.unwrap_or(1.0),
    })
}

/// The surface brush of a [`SculptDoc`], validated.
fn sculpt_op(kind: SculptKind, d: SculptDoc) -> Result<Op, OpError> {
    let path: Vec<DVec3> = match (d.at, d.path) {
        (Some(at), None) => vec![DVec3::from_array(at)],
        (None, Some(path)) => path.into_iter().map(DVec3::from_array).collect(),
        (Some(_), Some(_)) => {
            return Err(JsonError::at("path", "give either \"at\" or \"path\", not both").into());
        }
        (None, None) => {
            return Err(JsonError::at(
                "at",
                "missing field \"at\" (a point; or \"path\", the stroke's points)",
            )
            .into());
        }
    };
    let depth = match (kind.has_depth(), d.depth) {
        (true, Some(h)) => h,
        (true, None) => {
            return Err(JsonError::at("depth", format!("{} needs \"depth\"", kind.name())).into());
        }
        (false, None) => 0.0,
        (false, Some(_)) => {
            return Err(
                JsonError::at("depth", format!("{} takes no \"depth\"", kind.name())).into(),
            );
        }
    };
    let brush = brush_of(d.brush, d.strength)?;
    Ok(Op::Sculpt(SculptBrush::try_new(
        kind, path, d.radius, depth, brush,
    )?))
}

/// Parses a whole operations file, stopping at the first bad line.
///
/// # Errors
/// The first bad line, with its number.
pub fn parse_ops(text: &str) -> Result<Vec<Op>, OpLineError> {
    let mut ops = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        ops.push(parse_op(line).map_err(|e| OpLineError {
            line: i + 1,
            message: e.to_string(),
        })?);
    }
    Ok(ops)
}

/// Longest line of an operations file: 1 MB (a drag of about 30 000 path points).
pub const MAX_OP_LINE_BYTES: usize = 1 << 20;
/// Largest operations file: 64 MB (about a million pushes).
pub const MAX_OPS_FILE_BYTES: u64 = 64 << 20;

/// Why an operations file cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum OpsFileError {
    /// Reading failed.
    #[error("cannot read: {0}")]
    Io(#[from] std::io::Error),
    /// A line longer than [`MAX_OP_LINE_BYTES`] (or one that never ends, as `/dev/zero`):
    /// refused after reading one byte over the limit.
    #[error("line {line} is longer than {} MB, the limit for an operation line; nothing read on", MAX_OP_LINE_BYTES >> 20)]
    LineTooLong {
        /// 1-based line number.
        line: usize,
    },
    /// The file goes on past [`MAX_OPS_FILE_BYTES`]: refused at that byte.
    #[error("larger than {} MB, the limit for an operations file (at line {line}); split it", MAX_OPS_FILE_BYTES >> 20)]
    TooLarge {
        /// The line being read at the limit.
        line: usize,
    },
    /// A line is not UTF-8 text.
    #[error("line {line}: not UTF-8 text")]
    NotText {
        /// 1-based line number.
        line: usize,
    },
    /// A line does not read as an operation.
    #[error("{0}")]
    Bad(#[from] OpLineError),
}

/// Reads an operations file from `input` line by line, holding one line of at most
/// [`MAX_OP_LINE_BYTES`] at a time and reading at most [`MAX_OPS_FILE_BYTES`] (+ 1): the
/// operations with their 1-based line numbers, or the first bad line. Blank lines are skipped.
///
/// # Errors
/// [`OpsFileError`]: a read error, a line or file over its limit, a line not UTF-8, a bad
/// operation.
pub fn read_ops(input: impl std::io::BufRead) -> Result<Vec<(Op, usize)>, OpsFileError> {
    read_ops_limited(input, MAX_OP_LINE_BYTES, MAX_OPS_FILE_BYTES)
}

/// [`read_ops`] with other limits (`line_limit` bytes a line, `file_limit` bytes in all).
///
/// # Errors
/// As [`read_ops`].
pub fn read_ops_limited(
    input: impl std::io::BufRead,
    line_limit: usize,
    file_limit: u64,
) -> Result<Vec<(Op, usize)>, OpsFileError> {
    use nendo_file::{Line, Overlong, read_line_bounded};
    // One byte over the file limit is read, so that a longer file is told from one at it.
    let mut input = input.take(file_limit.saturating_add(1));
    let mut ops = Vec::new();
    let mut buf = Vec::new();
    let mut line = 0usize;
    loop {
        line += 1;
        let got = read_line_bounded(&mut input, &mut buf, line_limit, Overlong::Stop)?;
        match got {
            Line::End => break,
            // A long line cut by the file limit is the file's excess, not the line's.
            _ if file_limit.saturating_add(1) - input.limit() > file_limit => {
                return Err(OpsFileError::TooLarge { line });
            }
            Line::TooLong { .. } => return Err(OpsFileError::LineTooLong { line }),
            Line::Text { .. } => {}
        }
        let text = std::str::from_utf8(&buf).map_err(|_| OpsFileError::NotText { line })?;
        if text.trim().is_empty() {
            continue;
        }
        let op = parse_op(text).map_err(|e| OpLineError {
            line,
            message: e.to_string(),
        })?;
        ops.push((op, line));
    }
    Ok(ops)
}

/// The JSON line of an operation.
#[must_use]
pub fn op_to_json(op: &Op) -> Value {
    let p = |x: &DVec3| json!([x.x, x.y, x.z]);
    match op {
        Op::Brushed { op, brush } => {
            let mut doc = op_to_json(op);
            if let Some(obj) = doc.as_object_mut() {
                obj.insert("brush".to_string(), json!(brush.falloff.name()));
                obj.insert("strength".to_string(), json!(brush.strength));
            }
            doc
        }
        Op::Push {
            at,
            dir,
            depth,
            radius,
        } => {
            json!({"op": "push", "at": p(at), "dir": p(dir), "depth": depth, "radius": radius})
        }
        Op::Drag {
            path,
            dir,
            depth,
            radius,
        } => json!({
            "op": "drag",
            "path": path.iter().map(p).collect::<Vec<_>>(),
            "dir": p(dir),
            "depth": depth,
            "radius": radius,
        }),
        Op::PushNormal { at, depth, radius } => {
            json!({"op": "push", "at": p(at), "dir": "normal", "depth": depth, "radius": radius})
        }
        Op::Groove {
            path,
            dirs,
            depth,
            radius,
        } => {
            let path: Vec<Value> = path.iter().map(p).collect();
            match dirs {
                Dirs::Normal => json!({
                    "op": "drag", "path": path, "dir": "normal", "depth": depth, "radius": radius,
                }),
                Dirs::Each(d) => json!({
                    "op": "drag",
                    "path": path,
                    "dirs": d.iter().map(p).collect::<Vec<_>>(),
                    "depth": depth,
                    "radius": radius,
                }),
            }
        }
        Op::Move { at, to, radius } => {
            json!({"op": "move", "at": p(at), "to": p(to), "radius": radius})
        }
        Op::Smooth {
            at,
            radius,
            strength,
        } => json!({"op": "smooth", "at": p(at), "radius": radius, "strength": strength}),
        Op::Sculpt(b) => {
            let mut doc = json!({
                "op": b.kind.name(),
                "radius": b.radius,
                "brush": b.brush.falloff.name(),
                "strength": b.brush.strength,
            });
            if let Some(obj) = doc.as_object_mut() {
                match b.path.as_slice() {
                    [at] => obj.insert("at".to_string(), p(at)),
                    path => obj.insert(
                        "path".to_string(),
                        Value::Array(path.iter().map(p).collect()),
                    ),
                };
                if b.kind.has_depth() {
                    obj.insert("depth".to_string(), json!(b.depth));
                }
            }
            doc
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ops_round_trip() {
        let ops = [
            Op::Push {
                at: DVec3::new(0.5, 0.5, 0.0),
                dir: -DVec3::Z,
                depth: 0.3,
                radius: 1.25,
            },
            Op::Drag {
                path: vec![DVec3::ZERO, DVec3::X],
                dir: DVec3::new(0.0, 0.1, -1.0),
                depth: -0.2,
                radius: 0.7,
            },
            Op::PushNormal {
                at: DVec3::new(0.5, 0.5, 0.0),
                depth: -0.3,
                radius: 1.0,
            },
            Op::Groove {
                path: vec![DVec3::ZERO, DVec3::X, DVec3::Y],
                dirs: Dirs::Normal,
                depth: 0.2,
                radius: 0.7,
            },
            Op::Groove {
                path: vec![DVec3::ZERO, DVec3::X],
                dirs: Dirs::Each(vec![-DVec3::Z, DVec3::new(0.1, 0.0, -1.0)]),
                depth: 0.2,
                radius: 0.7,
            },
            Op::Move {
                at: DVec3::new(1.0, 2.0, 3.0),
                to: DVec3::new(1.5, 2.0, 3.25),
                radius: 0.8,
            },
            Op::Smooth {
                at: DVec3::new(1.0, 2.0, 3.0),
                radius: 0.8,
                strength: 0.5,
            },
            Op::Brushed {
                op: Box::new(Op::PushNormal {
                    at: DVec3::new(0.5, 0.5, 0.0),
                    depth: 0.3,
                    radius: 1.0,
                }),
                brush: Brush {
                    falloff: Falloff::Soft,
                    strength: 0.25,
                },
            },
        ];
        let sculpts = SculptKind::ALL.map(|kind| {
            let path = if kind == SculptKind::Pinch {
                vec![DVec3::new(0.5, 0.5, 0.0)]
            } else {
                vec![DVec3::ZERO, DVec3::new(0.5, 0.25, 0.0)]
            };
            let depth = if kind.has_depth() { -0.3 } else { 0.0 };
            let brush = Brush {
                falloff: Falloff::Flat,
                strength: 0.75,
            };
            Op::Sculpt(SculptBrush::try_new(kind, path, 1.5, depth, brush).unwrap())
        });
        let ops = ops.into_iter().chain(sculpts);
        for op in ops {
            assert_eq!(parse_op(&op_to_json(&op).to_string()), Ok(op));
        }
    }

    #[test]
    fn an_operations_file_is_read_line_by_line_within_its_limits() {
        let push = r#"{"op":"push","at":[0,0,0],"dir":[0,0,-1],"depth":0.1,"radius":1}"#;
        let text = format!("{push}\r\n\n{push}\n");
        let ops = read_ops_limited(text.as_bytes(), 100, 1000).expect("two operations");
        assert_eq!(ops.iter().map(|(_, l)| *l).collect::<Vec<_>>(), [1, 3]);
        // A line over its limit, wherever the buffer ends.
        let long = format!("{push}\n{}{push}\n", " ".repeat(100));
        let e = read_ops_limited(
            std::io::BufReader::with_capacity(7, long.as_bytes()),
            100,
            1000,
        )
        .expect_err("a long line");
        assert!(matches!(e, OpsFileError::LineTooLong { line: 2 }), "{e}");
        assert!(e.to_string().contains("line 2 is longer than"), "{e}");
        // The file over its limit: at the limit it reads, one byte more is refused.
        let exact = text.len() as u64;
        assert!(read_ops_limited(text.as_bytes(), 100, exact).is_ok());
        let e = read_ops_limited(text.as_bytes(), 100, exact - 1).expect_err("over");
        assert!(matches!(e, OpsFileError::TooLarge { line: 3 }), "{e}");
        // Not text, and a bad operation, with their lines.
        let e = read_ops_limited(&b"\n\xff\n"[..], 100, 1000).expect_err("not text");
        assert!(matches!(e, OpsFileError::NotText { line: 2 }), "{e}");
        let e = read_ops_limited(&b"\n\n{}\n"[..], 100, 1000).expect_err("bad");
        assert!(
            matches!(e, OpsFileError::Bad(OpLineError { line: 3, .. })),
            "{e}"
        );
        // An endless line (`/dev/zero`) is refused after the line limit.
        let zero = std::io::BufReader::new(std::io::Read::take(std::io::repeat(0), 1 << 40));
        let e = read_ops(zero).expect_err("endless");
        assert!(matches!(e, OpsFileError::LineTooLong { line: 1 }), "{e}");
    }

    #[test]
    fn bad_lines_say_what_and_where() {
        let text = "{\"op\":\"push\",\"at\":[0,0,0],\"dir\":[0,0,-1],\"depth\":0.1,\"radius\":1}\n\n\
                    {\"op\":\"push\",\"at\":[0,0,0],\"dir\":[0,0,0],\"depth\":0.1,\"radius\":1}\n";
        let err = parse_ops(text).unwrap_err();
        assert_eq!(err.line, 3);
        assert!(err.message.contains("dir"), "{err}");
        for (line, what) in [
            ("[1,2]", "object"),
            ("{\"op\":\"poke\"}", "unknown op"),
            (
                "{\"op\":\"push\",\"at\":[0,0],\"dir\":[0,0,1],\"depth\":0.1,\"radius\":1}",
                "at: invalid length",
            ),
            (
                "{\"op\":\"push\",\"at\":[0,0,0],\"dir\":[0,0,1],\"depth\":0.1,\"radius\":-1}",
                "radius",
            ),
            (
                "{\"op\":\"push\",\"at\":[0,0,0],\"dir\":[0,0,1],\"depth\":0.1,\"radius\":1,\"x\":2}",
                "unknown field \"x\"",
            ),
            (
                "{\"op\":\"drag\",\"path\":[[0,0,0]],\"dir\":[0,0,1],\"depth\":0.1,\"radius\":1}",
                "two points",
            ),
            (
                "{\"op\":\"drag\",\"path\":[[0,0,0],[1,\"a\",0]],\"dir\":[0,0,1],\"depth\":0.1,\"radius\":1}",
                "path[1]",
            ),
            ("{\"op\":", "EOF"),
            (
                "{\"op\":\"push\",\"at\":[0,0,0],\"dir\":[1e308,1e308,-1e308],\"depth\":0.1,\"radius\":1}",
                "not finite after normalising",
            ),
            (
                "{\"op\":\"push\",\"op\":\"push\",\"at\":[0,0,0],\"dir\":[0,0,1],\"depth\":0.1,\"radius\":1}",
                "duplicate field \"op\"",
            ),
            (
                "{\"op\":\"push\",\"at\":[0,0,0],\"dir\":[0,0,1],\"depth\":0.1,\"depth\":0.2,\"radius\":1}",
                "duplicate field \"depth\"",
            ),
            (
                "{\"op\":\"push\",\"at\":[0,0,0],\"dir\":\"norm\",\"depth\":0.1,\"radius\":1}",
                "dir: invalid value",
            ),
            (
                "{\"op\":\"push\",\"at\":[0,0,0],\"dir\":[0,0],\"depth\":0.1,\"radius\":1}",
                "dir: invalid length",
            ),
            (
                "{\"op\":\"drag\",\"path\":[[0,0,0],[1,0,0]],\"dir\":[0,0,1],\"dirs\":[[0,0,1],[0,0,1]],\"depth\":0.1,\"radius\":1}",
                "not both",
            ),
            (
                "{\"op\":\"drag\",\"path\":[[0,0,0],[1,0,0]],\"depth\":0.1,\"radius\":1}",
                "missing field \"dir\"",
            ),
            (
                "{\"op\":\"drag\",\"path\":[[0,0,0],[1,0,0]],\"dirs\":[[0,0,1]],\"depth\":0.1,\"radius\":1}",
                "one direction per path point",
            ),
            (
                "{\"op\":\"drag\",\"path\":[[0,0,0],[1,0,0]],\"dirs\":[[0,0,1],[0,\"a\",1]],\"depth\":0.1,\"radius\":1}",
                "dirs[1]",
            ),
            (
                "{\"op\":\"drag\",\"path\":[[0,0,0],[1,0,0]],\"dirs\":[[0,0,1],[1e308,1e308,1e308]],\"depth\":0.1,\"radius\":1}",
                "not finite after normalising",
            ),
            (
                "{\"op\":\"move\",\"at\":[0,0,0],\"to\":[0,0,1e999],\"radius\":1}",
                "to",
            ),
            (
                "{\"op\":\"move\",\"at\":[0,0,0],\"to\":[0,0,1],\"radius\":0}",
                "radius",
            ),
            (
                "{\"op\":\"move\",\"at\":[0,0,0],\"to\":[0,0,1],\"radius\":1,\"depth\":1}",
                "unknown field \"depth\"",
            ),
            (
                "{\"op\":\"smooth\",\"at\":[0,0,0],\"radius\":1,\"strength\":1.5}",
                "strength",
            ),
            (
                "{\"op\":\"smooth\",\"at\":[0,0,0],\"radius\":1,\"strength\":0}",
                "strength",
            ),
            (
                "{\"op\":\"smooth\",\"at\":[0,0,0],\"radius\":1}",
                "missing field \"strength\"",
            ),
            (
                "{\"op\":\"inflate\",\"at\":[0,0,0],\"radius\":1}",
                "needs \"depth\"",
            ),
            (
                "{\"op\":\"pinch\",\"at\":[0,0,0],\"depth\":1,\"radius\":1}",
                "takes no \"depth\"",
            ),
            (
                "{\"op\":\"flatten\",\"at\":[0,0,0],\"path\":[[0,0,0]],\"radius\":1}",
                "not both",
            ),
            ("{\"op\":\"flatten\",\"radius\":1}", "missing field \"at\""),
            (
                "{\"op\":\"crease\",\"at\":[0,0,0],\"depth\":0.1,\"radius\":-1}",
                "radius",
            ),
            (
                "{\"op\":\"crease\",\"at\":[0,0,0],\"depth\":1e308,\"radius\":1}",
                "depth",
            ),
            (
                "{\"op\":\"pinch\",\"at\":[0,0,0],\"radius\":1e308}",
                "radius",
            ),
            (
                "{\"op\":\"pinch\",\"at\":[0,0,0],\"radius\":1,\"brush\":\"hard\"}",
                "unknown brush",
            ),
            (
                "{\"op\":\"inflate\",\"at\":[0,0,0],\"depth\":1,\"radius\":1,\"strength\":2}",
                "strength",
            ),
        ] {
            let e = parse_op(line).unwrap_err().to_string();
            assert!(e.contains(what), "{line}: {e}");
        }
    }
}
