//! Output paths that would destroy what the command reads or writes: a subcommand checks, before
//! it reads anything, that no output is the same file as an input of another kind (the trace
//! being replayed given as `--out`, the operations file as the model written) and that no two
//! outputs are the same file (`--png x --svg x`, where the second write would silently replace
//! the first).
//!
//! Writing a document over its own input of the same kind stays allowed and safe: the input
//! is read completely before the output is written atomically (`nendo refine m.json --out
//! m.json`, `nendo sculpt --model m.json --ops o.jsonl --out m.json`).
//!
//! Two paths are the same file when both exist and have the same device and inode (through
//! symbolic and hard links), or, when one does not exist yet, when their directories are the
//! same existing directory and their file names are equal, or, failing that, when their
//! absolute forms are equal.

use std::path::{Path, PathBuf};

/// An output path that coincides with an input or with another output.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PathClash {
    /// An output is a file the command reads as something else.
    #[error(
        "{output} {} is the {input} the command reads: writing there would replace it; give {output} another path",
        path.display()
    )]
    OverInput {
        /// The output option (`--out`).
        output: &'static str,
        /// What the input is (`trace`, `operations file`).
        input: &'static str,
        /// The path.
        path: PathBuf,
    },
    /// Two outputs are the same file.
    #[error(
        "{first} and {second} are the same file {}: the second would replace the first; give each its own path",
        path.display()
    )]
    TwoOutputs {
        /// The first output option.
        first: &'static str,
        /// The second.
        second: &'static str,
        /// The path.
        path: PathBuf,
    },
}

/// Whether `a` and `b` name the same file (see the module docs).
#[must_use]
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    if let (Some(x), Some(y)) = (resolved(a), resolved(b)) {
        return x == y;
    }
    absolute(a) == absolute(b)
}

/// The path with its directory resolved (symbolic links, `..`), when that directory exists.
fn resolved(p: &Path) -> Option<PathBuf> {
    if let Ok(full) = std::fs::canonicalize(p) {
        return Some(full);
    }
    let name = p.file_name()?;
    let parent = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    std::fs::canonicalize(parent).ok().map(|d| d.join(name))
}

fn absolute(p: &Path) -> PathBuf {
    std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf())
}

/// Checks `outputs` (option name, path) against `inputs` of another kind (option or role
/// name, path) and against each other. An input that is not an existing file (a shipped
/// profile's name, `-` for standard input) cannot be replaced and is passed over.
///
/// # Errors
/// The first [`PathClash`] found.
pub fn check(
    outputs: &[(&'static str, Option<&Path>)],
    inputs: &[(&'static str, Option<&Path>)],
) -> Result<(), PathClash> {
    let outputs: Vec<(&'static str, &Path)> =
        outputs.iter().filter_map(|&(n, p)| Some((n, p?))).collect();
    for (k, &(name, out)) in outputs.iter().enumerate() {
        for &(input, path) in inputs {
            if let Some(path) = path
                && path.is_file()
                && same_file(out, path)
            {
                return Err(PathClash::OverInput {
                    output: name,
                    input,
                    path: out.to_path_buf(),
                });
            }
        }
        for &(other, path) in &outputs[k + 1..] {
            if same_file(out, path) {
                return Err(PathClash::TwoOutputs {
                    first: name,
                    second: other,
                    path: path.to_path_buf(),
                });
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_file_by_any_name_is_found_and_different_files_are_not() {
        let dir = std::env::temp_dir().join(format!("nendo-paths-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("sub")).expect("temporary directory");
        let a = dir.join("a.json");
        std::fs::write(&a, "{}").expect("written");
        let dotted = dir.join("sub").join("..").join("a.json");
        assert!(same_file(&a, &dotted));
        #[cfg(unix)]
        {
            let link = dir.join("link.json");
            std::os::unix::fs::symlink(&a, &link).expect("symlink");
            assert!(same_file(&a, &link));
        }
        // Not yet written: the same directory and name.
        let new = dir.join("new.png");
        assert!(same_file(&new, &dir.join("sub").join("..").join("new.png")));
        assert!(!same_file(&new, &dir.join("new.svg")));
        assert!(!same_file(&a, &new));
        let clash = check(
            &[("--png", Some(&new)), ("--svg", Some(&new))],
            &[("figure", Some(&a))],
        );
        assert!(
            matches!(clash, Err(PathClash::TwoOutputs { .. })),
            "{clash:?}"
        );
        let clash = check(&[("--out", Some(&dotted))], &[("trace", Some(&a))]);
        assert!(
            matches!(clash, Err(PathClash::OverInput { .. })),
            "{clash:?}"
        );
        assert_eq!(
            check(
                &[("--out", Some(&new)), ("--png", None)],
                &[("trace", Some(&a))]
            ),
            Ok(())
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
