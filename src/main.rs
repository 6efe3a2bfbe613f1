#![forbid(unsafe_code)]
//! The `nendo` binary: the modeller window, and the headless subcommands (see `nendo --help`).
//!
//! It parses the top level of the command line: the window's options and the library's
//! subcommands ([`nendo::cli`]), and `nendo bench`, whose measurement suites are their own crate
//! ([`nendo_bench`]) depending on the library — which is why the binary, not the library, joins
//! them.

use clap::{Parser, Subcommand};
use nendo::cli::{signal, window};
use std::process::ExitCode;

/// nendo (粘土) — a clay-like modeller of exact Bezier surfaces and curves.
#[derive(Debug, Parser)]
#[command(name = "nendo", version, about, long_about = None, args_conflicts_with_subcommands = true)]
struct Cli {
    /// The subcommand; without one, the modeller window opens.
    #[command(subcommand)]
    command: Option<Command>,
    /// The window's options (without a subcommand).
    #[command(flatten)]
    window: window::WindowArgs,
}

/// Every subcommand: `nendo bench`, then the library's (in this order in `nendo --help`).
#[derive(Debug, Subcommand)]
enum Command {
    /// Run a measurement suite and print its table.
    Bench(nendo_bench::cli::BenchArgs),
    // Boxed: the library's enum is large beside `Bench` (clippy's large_enum_variant).
    #[command(flatten)]
    Modeller(Box<nendo::cli::Subcommand>),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // One handler for the whole binary: a stop signal removes unfinished writes' temporaries.
    signal::install();
    match cli.command {
        None => window::run(cli.window),
        Some(Command::Bench(args)) => nendo_bench::cli::run(args),
        Some(Command::Modeller(command)) => command.run(),
    }
}
