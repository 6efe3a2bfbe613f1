//! The binary's one handler of stop signals (SIGINT, SIGTERM and SIGHUP, through the `ctrlc`
//! crate's `termination` feature).
//!
//! By default a stop signal removes the temporary files of unfinished writes
//! ([`nendo_file::remove_live_temporaries`]) and exits with status 130, so an interrupted
//! `nendo export`, `nendo sculpt` or window autosave leaves neither a partial file nor a
//! temporary behind. A command that wants to end gracefully instead (`nendo record`, which
//! finishes its trace) holds a [`DeferredStop`] while it runs: the signal then only sets a flag
//! the command polls.
//!
//! Limits: the handler runs on `ctrlc`'s own thread; SIGKILL cannot be handled (its temporary
//! is removed by the next write to the same target).

use std::sync::atomic::{AtomicBool, Ordering};

/// The exit status after a stop signal.
pub const SIGNAL_EXIT: i32 = 130;

/// Whether a [`DeferredStop`] is held.
static DEFERRED: AtomicBool = AtomicBool::new(false);
/// Whether a stop signal arrived while deferred.
static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Installs the handler. Called once at start; a failure (another handler already installed)
/// is reported as a warning and leaves the default signal behaviour.
pub fn install() {
    let installed = ctrlc::set_handler(|| {
        if DEFERRED.load(Ordering::SeqCst) {
            REQUESTED.store(true, Ordering::SeqCst);
        } else {
            nendo_file::remove_live_temporaries();
            std::process::exit(SIGNAL_EXIT);
        }
    });
    if let Err(e) = installed {
        eprintln!("nendo: warning: cannot handle stop signals: {e}");
    }
}

/// While held, a stop signal does not exit: it sets a flag that [`DeferredStop::requested`]
/// reports, for a command that ends gracefully.
#[derive(Debug)]
pub struct DeferredStop(());

impl DeferredStop {
    /// Defers stop signals until the value is dropped.
    #[must_use]
    pub fn new() -> Self {
        REQUESTED.store(false, Ordering::SeqCst);
        DEFERRED.store(true, Ordering::SeqCst);
        Self(())
    }

    /// Whether a stop signal has arrived since [`DeferredStop::new`].
    #[must_use]
    pub fn requested(&self) -> bool {
        REQUESTED.load(Ordering::SeqCst)
    }
}

impl Default for DeferredStop {
    fn default() -> Self {
        Self::new()
    }
}

impl Drop for DeferredStop {
    fn drop(&mut self) {
        DEFERRED.store(false, Ordering::SeqCst);
    }
}
