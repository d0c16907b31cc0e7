//! The trackers' integration tests, a module per file, in one binary.
//!
//! Cargo runs test binaries one after another; in one binary the tests of every file share
//! the test threads, so a file whose tests wait (on Slurm, a browser, a child process) no
//! longer holds a core idle. Run one file's tests with a filter:
//! `cargo test -p magbench-trackers --test integration FILE::`.

#[path = "../common/mod.rs"]
mod common;

mod explore;
mod formation_tracker;
mod late_metric;
mod missed_detection;
mod mppi;
mod open_loop_ideal;
mod repair;
mod replanning;
mod rig_stop;
