//! Helpers shared by every test module: the `nendo` binary, fresh temporary directories,
//! near-equality, random curves with fixed seeds, and the independent curve references.
#![allow(dead_code)]

pub mod random;
pub mod reference;

use std::path::PathBuf;
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The release `nendo` binary built with these tests.
pub fn nendo() -> Command {
    Command::new(env!("CARGO_BIN_EXE_nendo"))
}

/// Runs `nendo ARGS` to the end and returns what it printed.
pub fn run(args: &[&str]) -> Output {
    nendo().args(args).output().expect("the nendo binary runs")
}

/// Runs `nendo ARGS` with `input` on standard input, to the end.
pub fn run_with_input(args: &[&str], input: &str) -> Output {
    use std::io::Write;
    use std::process::Stdio;
    let mut child = nendo()
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the nendo binary runs");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(input.as_bytes())
        .expect("input written");
    child.wait_with_output().expect("nendo ends")
}

/// A fresh, empty directory for one test: unique per process and per call, so tests running in
/// parallel in this one binary never share one.
pub fn temp_dir(name: &str) -> PathBuf {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("nendo-test-{}-{n}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    dir
}

/// Asserts `|a - b| <= tol`, naming both values and the tolerance.
#[macro_export]
macro_rules! assert_near {
    ($a:expr, $b:expr, $tol:expr $(,)?) => {{
        let (a, b, tol): (f64, f64, f64) = ($a, $b, $tol);
        assert!(
            (a - b).abs() <= tol,
            "{} = {a} and {} = {b} differ by {} > {tol}",
            stringify!($a),
            stringify!($b),
            (a - b).abs()
        );
    }};
    ($a:expr, $b:expr, $tol:expr, $($msg:tt)+) => {{
        let (a, b, tol): (f64, f64, f64) = ($a, $b, $tol);
        assert!(
            (a - b).abs() <= tol,
            "{} = {a} and {} = {b} differ by {} > {tol}: {}",
            stringify!($a),
            stringify!($b),
            (a - b).abs(),
            format!($($msg)+)
        );
    }};
}
