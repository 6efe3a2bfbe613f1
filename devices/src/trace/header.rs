//! The header lines of a trace (see the format in [`super`]), read one at a time by both
//! readers: the whole-text [`super::Trace::parse`] and the line stream [`super::TraceStream`].

use super::{
    DeviceError, HELD_FIELD, HandSize, Joint, OLDEST_TRACE_VERSION, SceneText, TRACE_FORMAT,
    TRACE_VERSION, TraceHeader, WorldFromTracker, skeleton,
};

/// The version a trace's first line names.
///
/// # Errors
/// [`DeviceError::TraceSyntax`] at line 1 when it is not `nendo-hand-trace V` with a version
/// this crate reads.
pub(crate) fn parse_version_line(first: &str) -> Result<u32, DeviceError> {
    let err = |line: usize, message: String| DeviceError::TraceSyntax { line, message };
    let mut words = first.split_whitespace();
    if words.next() != Some(TRACE_FORMAT) {
        return Err(err(
            1,
            format!("not a nendo hand trace (expected `{TRACE_FORMAT} {TRACE_VERSION}`)"),
        ));
    }
    match words.next().map(str::parse::<u32>) {
        Some(Ok(v)) if (OLDEST_TRACE_VERSION..=TRACE_VERSION).contains(&v) => Ok(v),
        Some(Ok(v)) => Err(err(
            1,
            format!(
                "trace version {v}; this nendo reads versions {OLDEST_TRACE_VERSION} to {TRACE_VERSION}"
            ),
        )),
        _ => Err(err(1, "missing or malformed version".into())),
    }
}

/// Reads header line `n` (1-based) of a trace of `version` into `header`; `true` when it is
/// the `frames` line that ends the header. Comments and blank lines are passed over.
///
/// # Errors
/// [`DeviceError::TraceSyntax`] naming line `n`.
pub(crate) fn parse_header_line(
    header: &mut TraceHeader,
    version: u32,
    n: usize,
    line: &str,
) -> Result<bool, DeviceError> {
    let err = |line: usize, message: String| DeviceError::TraceSyntax { line, message };
    if line.starts_with('#') || line.trim().is_empty() {
        return Ok(false);
    }
    let (key, rest) = line.split_once(' ').unwrap_or((line, ""));
    match key {
        "profile" => header.profile = Some(rest.to_string()),
        "world_from_tracker" => {
            let w: WorldFromTracker =
                serde_json::from_str(rest).map_err(|e| err(n, e.to_string()))?;
            w.validate().map_err(|e| err(n, e.to_string()))?;
            header.world_from_tracker = w;
        }
        "hand" => {
            let hand: HandSize = serde_json::from_str(rest).map_err(|e| err(n, e.to_string()))?;
            hand.validate().map_err(|e| err(n, e.to_string()))?;
            header.hand = hand;
        }
        "joints" => {
            header.joints = rest
                .split_whitespace()
                .map(|w| Joint::from_name(w).ok_or_else(|| err(n, format!("unknown joint `{w}`"))))
                .collect::<Result<_, _>>()?;
            let mut seen = 0u32;
            for j in &header.joints {
                if seen & (1 << j.index()) != 0 {
                    return Err(err(n, format!("joint {j} listed twice")));
                }
                seen |= 1 << j.index();
            }
        }
        "scene" if version < 2 => {
            return Err(err(
                n,
                format!(
                    "a `scene` header line needs trace version 2; this trace says version {version}"
                ),
            ));
        }
        "scene" => {
            header.scene = match rest.trim() {
                "none" => None,
                json => Some(SceneText::new(json).map_err(|e| match e {
                    DeviceError::InvalidValue(m) => err(n, m),
                    other => err(n, other.to_string()),
                })?),
            };
        }
        "skeleton" if version < 3 => {
            return Err(err(
                n,
                format!(
                    "a `skeleton` header line needs trace version 3; this trace says version {version}"
                ),
            ));
        }
        "skeleton" => {
            header.skeleton =
                Some(skeleton::parse_side(rest.trim()).ok_or_else(|| {
                    err(n, format!("skeleton `{rest}`: expected `left` or `right`"))
                })?);
        }
        "marks" if version < 4 => {
            return Err(err(
                n,
                format!(
                    "a `marks` header line needs trace version 4; this trace says version {version}"
                ),
            ));
        }
        "marks" => match rest.trim() {
            HELD_FIELD => header.marks_held = true,
            other => {
                return Err(err(
                    n,
                    format!(
                        "marks `{}`: this nendo knows only `marks {HELD_FIELD}`",
                        super::held::clip(other)
                    ),
                ));
            }
        },
        "frames" => return Ok(true),
        other => return Err(err(n, format!("unknown header keyword `{other}`"))),
    }
    Ok(false)
}
