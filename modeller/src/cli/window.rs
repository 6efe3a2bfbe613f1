//! `nendo [MODEL] [--autosave PATH] [--profile FILE_OR_NAME]`: the modeller window (the command
//! without a subcommand).

use clap::Args as ClapArgs;
use std::path::PathBuf;
use std::process::ExitCode;

/// Options of the window (given without a subcommand).
#[derive(Debug, Clone, Default, ClapArgs)]
pub struct WindowArgs {
    /// A nendo model (JSON) to open; without one, the paper's 10 × 10 plane.
    #[arg(value_name = "MODEL")]
    pub model: Option<PathBuf>,
    /// Where to autosave [default: $XDG_STATE_HOME/nendo/autosave.nendo.json].
    #[arg(long, value_name = "PATH")]
    pub autosave: Option<PathBuf>,
    /// Do not autosave.
    #[arg(long, conflicts_with = "autosave")]
    pub no_autosave: bool,
    /// Do not offer to recover the autosave of a session that did not close cleanly.
    #[arg(long)]
    pub no_recover: bool,
    /// Connect to a device profile's glove and tracker at start: a shipped profile's name
    /// (`cyberglove2-18-fastrak`) or a profile file; the Devices panel opens.
    #[arg(long, value_name = "FILE_OR_NAME")]
    pub profile: Option<String>,
}

/// Opens the window.
#[cfg(feature = "gui")]
pub fn run(args: WindowArgs) -> ExitCode {
    let options = crate::app::WindowOptions {
        model: args.model,
        autosave: args.autosave,
        no_autosave: args.no_autosave,
        no_recover: args.no_recover,
        profile: args.profile,
    };
    match crate::app::run(options) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("nendo: {e:#}");
            ExitCode::FAILURE
        }
    }
}

/// Without the `gui` feature there is no window.
#[cfg(not(feature = "gui"))]
pub fn run(_args: WindowArgs) -> ExitCode {
    eprintln!(
        "nendo: this build has no window (built without the `gui` feature); see `nendo --help`"
    );
    ExitCode::from(2)
}
