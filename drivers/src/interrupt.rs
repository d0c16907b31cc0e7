//! Ctrl-C: one process-wide flag that the hardware rig's keep-alive thread watches.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

/// The flag, or why its signal handler could not be installed (kept, so every caller hears it).
static FLAG: OnceLock<Result<Arc<AtomicBool>, InterruptError>> = OnceLock::new();

/// The Ctrl-C handler could not be installed: Ctrl-C would not zero the field, so no rig opens.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "cannot install the Ctrl-C (SIGINT/SIGTERM) handler that zeroes the field on an interrupt: {0}"
)]
pub struct InterruptError(pub String);

/// The interrupt flag, raised by Ctrl-C (SIGINT) or SIGTERM; installs the handler on first use.
/// A second Ctrl-C exits at once (the device watchdog then zeroes the field). An error when the
/// handler cannot be installed (another handler owns the signals), on this and every later call.
pub fn interrupt_flag() -> Result<Arc<AtomicBool>, InterruptError> {
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let f = flag.clone();
        ctrlc::set_handler(move || {
            if f.swap(true, Ordering::SeqCst) {
                eprintln!("second interrupt: exiting now (the device watchdog zeroes the field)");
                std::process::exit(130);
            }
            eprintln!("interrupted: zeroing the field and stopping");
        })
        .map_err(|e| InterruptError(e.to_string()))?;
        Ok(flag)
    })
    .clone()
}

/// True once Ctrl-C was pressed.
pub fn interrupted() -> bool {
    FLAG.get()
        .and_then(|f| f.as_ref().ok())
        .is_some_and(|f| f.load(Ordering::SeqCst))
}
