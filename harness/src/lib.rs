//! # magbench
//!
//! The harness of magbench: the command line, experiments, results, plots and figures.
//! The physics, planners, trackers and rig drivers live in their own crates.

pub mod cli;
pub mod error;
pub mod plot;

pub use error::CliError;
