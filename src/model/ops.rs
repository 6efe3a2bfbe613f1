//! Operations as JSON lines — the script `nendo sculpt --ops` replays:
//!
//! ```json
//! {"op": "push", "at": [x, y, z], "dir": [dx, dy, dz], "depth": d, "radius": r_f}
//! {"op": "drag", "path": [[x, y, z], …], "dir": [dx, dy, dz], "depth": d, "radius": r_f}
//! ```
//!
//! A negative depth pulls (push) or raises a ridge (drag); see [`crate::surface::shape_fn`].
//! Blank lines are skipped. Every line is validated completely (members, numbers, the
//! operation's own constraints) before any is applied: a missing, unknown or repeated member
//! is refused with its path and column (see [`crate::json_doc`]), and a `dir` whose length
//! overflows a double is refused as not finite after normalising.

use glam::DVec3;
use serde::Deserialize;
use serde::de::IgnoredAny;
use serde_json::{Value, json};

use crate::json_doc::{self, JsonError};
use crate::surface::{Op, SurfaceError};

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
    /// An `op` other than `push` and `drag`.
    #[error("unknown op {0:?}: expected \"push\" or \"drag\"")]
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
#[serde(expecting = "an operation (a JSON object with \"op\": \"push\" or \"drag\")")]
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
    dir: [f64; 3],
    depth: f64,
    radius: f64,
}

/// `{"op": "drag", "path", "dir", "depth", "radius"}`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DragDoc {
    #[allow(dead_code)]
    op: IgnoredAny,
    path: Vec<[f64; 3]>,
    dir: [f64; 3],
    depth: f64,
    radius: f64,
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
    let op = match kind.as_str() {
        "push" => {
            let d: PushDoc = json_doc::from_str(text)?;
            Op::Push {
                at: DVec3::from_array(d.at),
                dir: DVec3::from_array(d.dir),
                depth: d.depth,
                radius: d.radius,
            }
        }
        "drag" => {
            let d: DragDoc = json_doc::from_str(text)?;
            Op::Drag {
                path: d.path.into_iter().map(DVec3::from_array).collect(),
                dir: DVec3::from_array(d.dir),
                depth: d.depth,
                radius: d.radius,
            }
        }
        _ => return Err(OpError::UnknownOp(kind)),
    };
    let (Op::Push { dir, .. } | Op::Drag { dir, .. }) = &op;
    if dir.is_finite() && *dir != DVec3::ZERO && dir.try_normalize().is_none() {
        return Err(OpError::DirOverflow);
    }
    op.finger()?;
    Ok(op)
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

/// The JSON line of an operation.
#[must_use]
pub fn op_to_json(op: &Op) -> Value {
    let p = |x: &DVec3| json!([x.x, x.y, x.z]);
    match op {
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
        ];
        for op in ops {
            assert_eq!(parse_op(&op_to_json(&op).to_string()), Ok(op));
        }
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
        ] {
            let e = parse_op(line).unwrap_err().to_string();
            assert!(e.contains(what), "{line}: {e}");
        }
    }
}
