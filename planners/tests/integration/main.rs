//! The planners' integration tests, a module per file, in one binary.
//!
//! Cargo runs test binaries one after another; in one binary the tests of every file share
//! the test threads, so a file whose tests wait (on Slurm, a browser, a child process) no
//! longer holds a core idle. Run one file's tests with a filter:
//! `cargo test -p magbench-planners --test integration FILE::`.

#[path = "../common/mod.rs"]
mod common;

mod adaptive_plans;
mod aim;
mod builtin_plans;
mod edge_checkers;
mod elevation;
mod formation;
mod goal_steering;
mod guide;
mod optimizing;
mod planners;
mod shortcut;
mod straighten;
mod validate;
