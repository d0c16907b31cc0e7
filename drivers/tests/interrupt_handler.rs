//! A Ctrl-C handler that cannot be installed is an error the caller sees, not a rig that opens
//! without one. Its own test binary: the handler and the interrupt flag are process-wide.

use std::path::Path;

use magbench_drivers::HardwareError;
use magbench_drivers::interrupt::interrupt_flag;
use magbench_drivers::rigfile::RigConfig;
use magbench_drivers::rigs::{CoilRig, OpenError, RigDescription};
use magbench_env::Scenario;

#[test]
fn a_handler_that_cannot_be_installed_stops_the_rig_from_opening() {
    // another handler owns SIGINT and SIGTERM: ctrlc refuses a second one
    ctrlc::set_handler(|| {}).unwrap();
    let e = interrupt_flag().unwrap_err();
    assert!(
        e.to_string()
            .starts_with("cannot install the Ctrl-C (SIGINT/SIGTERM) handler"),
        "{e}"
    );
    // and every later caller hears it too
    assert_eq!(interrupt_flag().unwrap_err(), e);
    // a coil rig refuses to open, before it connects to anything
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../rigs/emulator.toml");
    let rig = CoilRig::new(RigConfig::load(&path).unwrap(), "emulator.toml");
    let scenario = Scenario::load("open-field").unwrap();
    match rig.open(&scenario, 1, None) {
        Err(OpenError::Hardware(HardwareError::Interrupt(i))) => assert_eq!(i, e),
        Err(other) => panic!("expected the handler's error, got {other}"),
        Ok(_) => panic!("the rig opened without a Ctrl-C handler"),
    }
}
