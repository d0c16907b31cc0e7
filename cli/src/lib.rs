//! # magbench
//!
//! The magbench command line, over the harness (`magbench-harness`, re-exported here whole).
//! The physics, planners, trackers and rig drivers live in their own crates.
//!
//! As a library it runs the whole command line with planners and trackers of your own: a
//! plugin crate depends on `magbench`, writes its planner or tracker against
//! [`prelude`], and its `main` is `magbench::Cli::new().planner::<MyRrt>("my-rrt").run()`
//! ([`Cli`], [`Registry`]; see `docs/plugins.md`).

#![warn(missing_docs)]

mod app;
pub mod cli;
pub mod output;
pub mod sweep;

pub use app::Cli;
pub use magbench_harness::*;
