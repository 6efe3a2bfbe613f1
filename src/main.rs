#![forbid(unsafe_code)]
//! The `nendo` binary: the modeller window, and the headless subcommands (see `nendo --help`).

fn main() -> std::process::ExitCode {
    nendo::cli::run()
}
