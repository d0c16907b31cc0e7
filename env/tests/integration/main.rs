//! The physics' integration tests, a module per file, in one binary.
//!
//! Cargo runs test binaries one after another; in one binary the tests of every file share
//! the test threads, so a file whose tests wait (on Slurm, a browser, a child process) no
//! longer holds a core idle. Run one file's tests with a filter:
//! `cargo test -p magbench-env --test integration FILE::`.
//!
//! `adaptive_flow.rs` stays a binary of its own: `cargo xtask measure` runs it by name.

mod heterogeneous_shape;
mod integration_step;
mod pair_flow;
mod plant_terms;
mod scenarios;
