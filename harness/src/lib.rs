//! # magbench
//!
//! The harness of magbench: the command line, experiments, results, plots and figures.
//! The physics, planners, trackers and rig drivers live in their own crates.
//!
//! As a library it runs the whole command line with planners and trackers of your own: a
//! plugin crate depends on `magbench`, writes its planner or tracker against
//! [`prelude`], and its `main` is `magbench::Cli::new().planner::<MyRrt>("my-rrt").run()`
//! ([`Cli`], [`Registry`]; see `docs/plugins.md`).

#![warn(missing_docs)]

pub mod ablation;
pub mod api;
mod app;
pub mod cli;
pub mod compare;
pub mod error;
pub mod experiment;
pub mod figures;
pub mod metrics;
pub mod output;
pub mod pipeline;
pub mod plot;
pub mod prelude;
pub mod registry;
pub mod regress;
pub mod replay;
pub mod results;
pub mod run;
pub mod stats;
pub mod suite;
pub mod sweep;
pub mod table;
pub mod units;

pub use app::Cli;
pub use error::Error;
pub use magbench_env::registry::RegistryError;
pub use registry::Registry;
