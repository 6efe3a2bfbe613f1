//! Operations as JSON lines — the script `nendo sculpt --ops` replays:
//!
//! ```json
//! {"op": "push", "at": [x, y, z], "dir": [dx, dy, dz], "depth": d, "radius": r_f}
//! {"op": "drag", "path": [[x, y, z], …], "dir": [dx, dy, dz], "depth": d, "radius": r_f}
//! ```
//!
//! A negative depth pulls (push) or raises a ridge (drag); see [`crate::surface::shape_fn`].
//! Blank lines are skipped. Every line is validated completely (members, numbers, the
//! operation's own constraints) before any is applied.

use glam::DVec3;
use serde_json::{Map, Value, json};

use crate::surface::Op;

/// A bad line of an operations file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct OpLineError {
    /// 1-based line number.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// Parses one operation.
///
/// # Errors
/// A message saying what is wrong with the line.
pub fn parse_op(text: &str) -> Result<Op, String> {
    let v: Value = serde_json::from_str(text).map_err(|e| format!("not valid JSON: {e}"))?;
    let o = v.as_object().ok_or("an operation must be a JSON object")?;
    let kind = o
        .get("op")
        .and_then(Value::as_str)
        .ok_or("missing \"op\": \"push\" or \"drag\"")?;
    let allowed: &[&str] = match kind {
        "push" => &["op", "at", "dir", "depth", "radius"],
        "drag" => &["op", "path", "dir", "depth", "radius"],
        other => {
            return Err(format!(
                "unknown op {other:?}: expected \"push\" or \"drag\""
            ));
        }
    };
    if let Some(extra) = o.keys().find(|k| !allowed.contains(&k.as_str())) {
        return Err(format!("unknown member {extra:?} in a {kind} operation"));
    }
    let dir = point(o, "dir")?;
    let depth = number(o, "depth")?;
    let radius = number(o, "radius")?;
    let op = if kind == "push" {
        Op::Push {
            at: point(o, "at")?,
            dir,
            depth,
            radius,
        }
    } else {
        let list = o
            .get("path")
            .and_then(Value::as_array)
            .ok_or("\"path\" must be an array of points [x, y, z]")?;
        let path = list
            .iter()
            .enumerate()
            .map(|(i, p)| {
                to_point(p)
                    .ok_or_else(|| format!("path[{i}] must be a point [x, y, z] of finite numbers"))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Op::Drag {
            path,
            dir,
            depth,
            radius,
        }
    };
    op.finger().map_err(|e| e.to_string())?;
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
        ops.push(parse_op(line).map_err(|message| OpLineError {
            line: i + 1,
            message,
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

fn to_point(v: &Value) -> Option<DVec3> {
    let a = v.as_array().filter(|a| a.len() == 3)?;
    let c = [a[0].as_f64()?, a[1].as_f64()?, a[2].as_f64()?];
    c.iter()
        .all(|x| x.is_finite())
        .then(|| DVec3::from_array(c))
}

fn point(o: &Map<String, Value>, name: &str) -> Result<DVec3, String> {
    let v = o.get(name).ok_or_else(|| format!("missing \"{name}\""))?;
    to_point(v).ok_or_else(|| format!("\"{name}\" must be a point [x, y, z] of finite numbers"))
}

fn number(o: &Map<String, Value>, name: &str) -> Result<f64, String> {
    let v = o.get(name).ok_or_else(|| format!("missing \"{name}\""))?;
    v.as_f64()
        .filter(|x| x.is_finite())
        .ok_or_else(|| format!("\"{name}\" must be a finite number"))
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
                "\"at\"",
            ),
            (
                "{\"op\":\"push\",\"at\":[0,0,0],\"dir\":[0,0,1],\"depth\":0.1,\"radius\":-1}",
                "radius",
            ),
            (
                "{\"op\":\"push\",\"at\":[0,0,0],\"dir\":[0,0,1],\"depth\":0.1,\"radius\":1,\"x\":2}",
                "unknown member",
            ),
            (
                "{\"op\":\"drag\",\"path\":[[0,0,0]],\"dir\":[0,0,1],\"depth\":0.1,\"radius\":1}",
                "two points",
            ),
            (
                "{\"op\":\"drag\",\"path\":[[0,0,0],[1,\"a\",0]],\"dir\":[0,0,1],\"depth\":0.1,\"radius\":1}",
                "path[1]",
            ),
            ("{\"op\":", "JSON"),
        ] {
            let e = parse_op(line).unwrap_err();
            assert!(e.contains(what), "{line}: {e}");
        }
    }
}
