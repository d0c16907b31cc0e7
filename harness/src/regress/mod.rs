//! Regression checks between two results folders (a baseline and a candidate).
//!
//! Per configuration (scenario, planner, tracker, preset) and metric, one of three verdicts:
//!
//! - **regression**: a change beyond the tolerance is shown — a one-sided test that the change
//!   exceeds the tolerance, Holm-adjusted over the gated metrics of the whole table (and, for
//!   the metrics shown but not gated, apart over those);
//! - **ok**: the change is shown to be within the tolerance — the worse end of the two-sided
//!   `1 − 2α` interval lies inside it (the non-inferiority half of TOST);
//! - **inconclusive**: neither, with the seeds per folder that would likely resolve it.
//!
//! Runs are deterministic per seed, so a configuration whose seeds are the same in both
//! folders is compared seed by seed (an unchanged build gives a zero-width interval); other
//! configurations as independent samples. Success rates: Tango's paired or Newcombe's
//! unpaired score interval of the difference. Other metrics (tracking errors, cost,
//! iterations, times): the Hodges–Lehmann shift of the log values with the signed-rank
//! (paired) or Mann–Whitney (unpaired) interval, reported as a ratio. A configuration of the
//! baseline missing from the candidate fails the check; the manifests are compared first
//! ([`manifests`]).
//!
//! Two stages over plain data, as criterion separates them: [`analysis`] turns two sets of runs
//! into [`Comparison`]s (numbers, intervals, verdicts), and [`report`] turns those into text.

pub mod analysis;
pub mod manifests;
pub mod metric;
pub mod report;
pub mod runs;
pub mod verdict;

pub use crate::stats::holm;
pub use analysis::{Comparison, Design, Tolerances, Value, compare, compare_runs, table_metrics};
pub use metric::Change;
pub use report::{OnInconclusive, failures, footer, new_metrics, table};
pub use runs::Runs;
pub use verdict::Verdict;

#[cfg(test)]
mod tests;
