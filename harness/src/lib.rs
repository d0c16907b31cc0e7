//! # magbench-harness
//!
//! The harness of magbench: experiments, runs and their pipeline, results, replays, reports,
//! comparisons, regression checks and figures. The command line is the `magbench` crate
//! (`cli/`), which re-exports this crate whole; the physics, planners, trackers and rig drivers
//! live in their own crates.

#![warn(missing_docs)]

pub mod ablation;
pub mod api;
pub mod compare;
pub mod error;
pub mod experiment;
pub mod figures;
pub mod pipeline;
pub mod prelude;
pub mod registry;
pub mod regress;
pub mod replay;
pub mod results;
pub mod run;
pub mod suite;

pub use error::Error;
pub use magbench_analysis::{metrics, stats, table, units};
pub use magbench_env::registry::RegistryError;
pub use magbench_plot::plot;
pub use registry::Registry;
