//! Reading JSON documents and requests into typed structures (serde derive), with errors that
//! say *where*: the path of the bad member (`surface.patches[3][7]`) and its line and column.
//!
//! Every file and batch format of nendo (model files, sculpt ops, curve JSON, the
//! `closest`/`curve` batch protocols, figure and shape documents) is read through
//! [`from_str`] (or [`from_value`] for a document already parsed), into structures that refuse
//! unknown members (`deny_unknown_fields`) and duplicate members (serde's "duplicate field").
//! The text is deserialized directly, without an intermediate `serde_json::Value` tree, so a
//! big model costs the text and the typed result only.
//!
//! Messages are serde's, with member names in JSON's double quotes (`unknown field "curvs",
//! expected one of "format", ...`, `duplicate field "surface"`).
//!
//! Limits: a UTF-8 byte-order mark is refused (named as such), not skipped; the column is
//! serde_json's (1-based, counted in bytes); errors found while checking a value *after* it
//! was read (a validation inside a `Deserialize` impl) are placed at the end of that value.

use serde::de::DeserializeOwned;

/// The UTF-8 byte-order mark.
const BOM: char = '\u{feff}';

/// Why a JSON document or request could not be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum JsonError {
    /// The text starts with a UTF-8 byte-order mark.
    #[error("the file starts with a UTF-8 byte-order mark (BOM); save it without one")]
    Bom,
    /// The text is not JSON, or a member is missing, unknown, repeated or invalid.
    #[error("{}", describe(path, *line, *column, message))]
    Invalid {
        /// Path of the bad member (`surface.patches[3][7]`); empty for the document itself.
        path: String,
        /// 1-based line (0 when the document was not read from text).
        line: usize,
        /// 1-based column (0 when the document was not read from text).
        column: usize,
        /// What is wrong.
        message: String,
    },
}

impl JsonError {
    /// The path of the bad member (empty for the document itself or a BOM).
    #[must_use]
    pub fn path(&self) -> &str {
        match self {
            JsonError::Bom => "",
            JsonError::Invalid { path, .. } => path,
        }
    }

    /// The same error with `prefix` put in front of its path (a document embedded in another,
    /// as a curve in a request).
    #[must_use]
    pub fn within(self, prefix: &str) -> Self {
        match self {
            JsonError::Invalid {
                path,
                line,
                column,
                message,
            } => JsonError::Invalid {
                path: join(prefix, &path),
                line,
                column,
                message,
            },
            bom => bom,
        }
    }

    /// An error about the member at `path` found after reading (no position in the text).
    #[must_use]
    pub fn at(path: &str, message: impl Into<String>) -> Self {
        JsonError::Invalid {
            path: path.to_string(),
            line: 0,
            column: 0,
            message: message.into(),
        }
    }
}

fn join(prefix: &str, path: &str) -> String {
    match (prefix.is_empty(), path.is_empty()) {
        (true, _) => path.to_string(),
        (false, true) => prefix.to_string(),
        (false, false) if path.starts_with('[') => format!("{prefix}{path}"),
        (false, false) => format!("{prefix}.{path}"),
    }
}

fn describe(path: &str, line: usize, column: usize, message: &str) -> String {
    let at = if line == 0 {
        String::new()
    } else {
        format!(" (line {line} column {column})")
    };
    if path.is_empty() {
        format!("{message}{at}")
    } else {
        format!("{path}: {message}{at}")
    }
}

/// The path serde_path_to_error found, with the root (".") as the empty string.
fn path_text(path: &serde_path_to_error::Path) -> String {
    let s = path.to_string();
    if s == "." { String::new() } else { s }
}

/// serde_json's message without its " at line L column C" suffix, with member names quoted
/// as JSON writes them (`"surface"`, not serde's `` `surface` ``).
fn bare_message(e: &serde_json::Error) -> String {
    let full = e.to_string();
    let suffix = format!(" at line {} column {}", e.line(), e.column());
    full.strip_suffix(&suffix)
        .unwrap_or(&full)
        .replace('`', "\"")
}

/// A clearer message where the text holds a number JSON cannot carry (`NaN`, `Infinity`, or
/// a literal too large for a double): every number nendo reads must be finite.
fn message_for(text: &str, e: &serde_json::Error) -> String {
    let at = text
        .lines()
        .nth(e.line().saturating_sub(1))
        .and_then(|l| l.get(e.column().saturating_sub(1)..))
        .unwrap_or("");
    let bad = ["NaN", "-NaN", "Infinity", "-Infinity", "inf", "-inf", "nan"]
        .iter()
        .find(|t| at.starts_with(**t));
    let message = bare_message(e);
    if let Some(token) = bad {
        format!("{token} is not a finite number (every number must be finite)")
    } else if message.contains("number out of range") {
        "a number is out of range (every number must be a finite double)".to_string()
    } else {
        message
    }
}

/// Reads a `T` from JSON text: the whole text must be one value of `T`'s shape.
///
/// # Errors
/// [`JsonError::Bom`] for a text starting with a byte-order mark; [`JsonError::Invalid`] with
/// the member's path, line and column for anything else.
pub fn from_str<T: DeserializeOwned>(text: &str) -> Result<T, JsonError> {
    if text.starts_with(BOM) {
        return Err(JsonError::Bom);
    }
    let mut de = serde_json::Deserializer::from_str(text);
    let value = serde_path_to_error::deserialize::<_, T>(&mut de).map_err(|e| {
        let path = path_text(e.path());
        let inner = e.into_inner();
        JsonError::Invalid {
            path,
            line: inner.line(),
            column: inner.column(),
            message: message_for(text, &inner),
        }
    })?;
    de.end().map_err(|e| JsonError::Invalid {
        path: String::new(),
        line: e.line(),
        column: e.column(),
        message: bare_message(&e),
    })?;
    Ok(value)
}

/// Reads a `T` from an already parsed JSON value (no line or column in errors).
///
/// # Errors
/// [`JsonError::Invalid`] with the member's path.
pub fn from_value<T: DeserializeOwned>(value: &serde_json::Value) -> Result<T, JsonError> {
    serde_path_to_error::deserialize::<_, T>(value).map_err(|e| {
        let path = path_text(e.path());
        JsonError::at(&path, bare_message(e.inner()))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Doc {
        a: Vec<[f64; 2]>,
        #[serde(default)]
        b: Option<u32>,
    }

    #[test]
    fn errors_name_path_line_and_column() {
        let e = from_str::<Doc>("{\"a\": [[1, 2],\n [3, \"x\"]]}").unwrap_err();
        let JsonError::Invalid {
            path, line, column, ..
        } = &e
        else {
            panic!("{e:?}")
        };
        assert_eq!((path.as_str(), *line), ("a[1][1]", 2), "{e}");
        assert!(*column > 0);
        assert!(e.to_string().starts_with("a[1][1]: invalid type"), "{e}");
    }

    #[test]
    fn duplicates_unknowns_bom_and_non_finite_numbers_are_named() {
        let e = from_str::<Doc>("{\"a\": [], \"a\": []}").unwrap_err();
        assert!(e.to_string().contains("duplicate field \"a\""), "{e}");
        let e = from_str::<Doc>("{\"a\": [], \"c\": 1}").unwrap_err();
        assert!(e.to_string().contains("unknown field \"c\""), "{e}");
        let e = from_str::<Doc>("\u{feff}{\"a\": []}").unwrap_err();
        assert_eq!(e, JsonError::Bom);
        assert!(e.to_string().contains("byte-order mark"));
        let e = from_str::<Doc>("{\"a\": [[1, NaN]]}").unwrap_err();
        assert!(e.to_string().contains("NaN is not a finite number"), "{e}");
        let e = from_str::<Doc>("{\"a\": [[1, 1e400]]}").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("a[0][1]: a number is out of range"),
            "{e}"
        );
        let e = from_str::<Doc>("{\"a\": []} x").unwrap_err();
        assert!(e.to_string().contains("trailing characters"), "{e}");
    }
}
