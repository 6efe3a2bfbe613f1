#![forbid(unsafe_code)]
//! Writes the hand traces shipped in `devices/traces/` (see `devices/README.md`):
//!
//! ```text
//! cargo run --release --example hand_traces -- devices/traces
//! ```
//!
//! Each trace is a scripted hand motion (`nendo::hand::shipped`) written through the real trace
//! writer of `nendo-devices`; the generators are deterministic, and `tests/it/hand_traces.rs`
//! checks that the shipped files are what they write.

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "devices/traces".into()),
    );
    let shipped = match nendo::hand::shipped::shipped() {
        Ok(s) => s,
        Err(e) => {
            eprintln!("hand_traces: {e}");
            return ExitCode::FAILURE;
        }
    };
    if let Err(e) = std::fs::create_dir_all(&dir) {
        eprintln!("hand_traces: {}: {e}", dir.display());
        return ExitCode::FAILURE;
    }
    for s in shipped {
        let path = dir.join(format!("{}.trace", s.name));
        match s.trace.write(&path) {
            Ok(()) => println!(
                "{}: {} frames — {}",
                path.display(),
                s.trace.frames.len(),
                s.about
            ),
            Err(e) => {
                eprintln!("hand_traces: {}: {e}", path.display());
                return ExitCode::FAILURE;
            }
        }
    }
    ExitCode::SUCCESS
}
