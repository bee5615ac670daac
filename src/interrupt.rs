//! The user's request to stop (SIGINT, Ctrl-C), polled by long runs at
//! their safe points.
//!
//! A run that is killed mid-step loses everything since its last file; a
//! run that polls [`requested`] between steps (`flank run` between roll
//! positions) can instead write what is complete and say how to resume.
//! [`install_sigint_handler`] (called by the binary) makes the first SIGINT
//! set the flag, and a second one end the process at once with exit code
//! 130 (the shell's code for SIGINT): a user who does not want to wait for
//! the position under way presses Ctrl-C again.
//!
//! The handler only stores into an atomic flag (async-signal-safe), through
//! the `signal-hook` crate's `flag` module.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

use crate::error::FlankError;

/// The flag (shared with the signal handler).
fn flag() -> &'static Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    FLAG.get_or_init(|| Arc::new(AtomicBool::new(false)))
}

/// Installs the SIGINT handler (idempotent): the first SIGINT sets the
/// flag, the second ends the process with exit code 130.
pub fn install_sigint_handler() -> Result<(), FlankError> {
    static INSTALLED: OnceLock<std::result::Result<(), String>> = OnceLock::new();
    INSTALLED
        .get_or_init(|| {
            #[cfg(unix)]
            {
                use signal_hook::consts::SIGINT;
                use signal_hook::flag as f;
                // order matters: the shutdown handler sees the flag as it
                // was before this signal
                f::register_conditional_shutdown(SIGINT, 130, flag().clone())
                    .and_then(|_| f::register(SIGINT, flag().clone()))
                    .map(|_| ())
                    .map_err(|e| e.to_string())
            }
            #[cfg(not(unix))]
            {
                Ok(())
            }
        })
        .clone()
        .map_err(|e| FlankError::Model(format!("cannot install the SIGINT handler: {e}")))
}

/// Whether a stop was requested (SIGINT or [`request`]).
pub fn requested() -> bool {
    flag().load(Ordering::Relaxed)
}

/// Requests a stop, as SIGINT does (tests, embedding programs).
pub fn request() {
    flag().store(true, Ordering::Relaxed);
}

/// Clears a request (tests, embedding programs that go on).
pub fn clear() {
    flag().store(false, Ordering::Relaxed);
}
