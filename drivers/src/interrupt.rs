//! Ctrl-C: one process-wide flag that the hardware rig's keep-alive thread watches.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();

/// The interrupt flag, raised by Ctrl-C (SIGINT) or SIGTERM; installs the handler on first use.
/// A second Ctrl-C exits at once (the device watchdog then zeroes the field).
pub fn interrupt_flag() -> Arc<AtomicBool> {
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let f = flag.clone();
        let _ = ctrlc::set_handler(move || {
            if f.swap(true, Ordering::SeqCst) {
                eprintln!("second interrupt: exiting now (the device watchdog zeroes the field)");
                std::process::exit(130);
            }
            eprintln!("interrupted: zeroing the field and stopping");
        });
        flag
    })
    .clone()
}

/// True once Ctrl-C was pressed.
pub fn interrupted() -> bool {
    FLAG.get().is_some_and(|f| f.load(Ordering::SeqCst))
}
