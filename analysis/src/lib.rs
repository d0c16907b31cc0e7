//! # magbench-analysis
//!
//! What a run's numbers mean and how they are summarised: the metric table (every per-run
//! metric with its name, unit and computation), the units lengths are shown in, the statistics
//! of comparisons and summaries, and the Markdown tables of generated files. It knows nothing
//! of experiments, results folders or figures (`magbench-harness` and `magbench-plot` use it).

#![warn(missing_docs)]

pub mod metrics;
pub mod stats;
pub mod table;
pub mod units;
