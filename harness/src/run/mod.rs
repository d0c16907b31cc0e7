//! Runs: the unit of a benchmark. A [`RunSpec`] (scenario, planner variant, optional tracker
//! variant and disturbance preset, seed, limits) goes into an [`Executor`]; a [`RunRecord`]
//! (one tidy row) and its progress trace come out. A run's result depends only on its spec.

pub mod error;
pub mod executor;
pub mod fake;
pub mod real;
pub mod spec;
pub mod variant;

pub use error::RunError;
pub use executor::{Executor, RunOutput, execute_caught};
pub use magbench_store::record::{self, ProgressRow, RunRecord, Status};
pub use spec::{RunLimits, RunSpec};
pub use variant::{ParamValue, Variant};
