//! The drivers' integration tests, a module per file, in one binary.
//!
//! Cargo runs test binaries one after another; in one binary the tests of every file share
//! the test threads, so a file whose tests wait (on Slurm, a browser, a child process) no
//! longer holds a core idle. Run one file's tests with a filter:
//! `cargo test -p magbench-drivers --test integration FILE::`.
//!
//! `interrupt_handler.rs` stays a binary of its own (the Ctrl-C handler is process-wide), and
//! the files `cargo xtask measure` runs by name (`calibrate`, `calibrate_emulator`,
//! `calibrate_noise_bias`, `calibrate_segments`, `detector_accuracy`) stay theirs too.

#[path = "../common/mod.rs"]
mod common;

mod calibrate_bad_input;
mod calibrate_failed_predictions;
mod calibrate_imprecise;
mod calibrate_scale_symmetry;
mod calibrate_strong_noise;
mod calibrate_stuck;
mod calibrate_trade_offs;
mod excite_contact;
mod hardware_rig;
