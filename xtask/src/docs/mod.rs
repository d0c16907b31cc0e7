//! The measured figures of the book: `cargo xtask measure` runs each entry of [`MEASURES`]
//! (an experiment, shortened under `--quick`, a criterion bench, a cargo test or example, a
//! Python script, or a transcript of magbench commands) and writes its table to `docs/measured/NAME.md`
//! with a [`Header`] naming the command, machine, date and magbench version. The chapters
//! quote these files by `{{#include measured/NAME.md}}`, never by copying their numbers.

pub mod ablation;
pub mod bench;
pub mod cargo;
pub mod cargo_test;
pub mod convergence;
pub mod cost_at_time;
pub mod criterion;
pub mod edge_tables;
pub mod family_tables;
pub mod freshness;
pub mod header;
pub mod measures;
pub mod planner_tables;
pub mod python;
pub mod replans;
pub mod run;
pub mod tables;
pub mod teams;
pub mod tracker_tables;
pub mod transcript;

pub use header::{Header, Measured, ParseError, parse};
pub use magbench::table::Table;
pub use measures::{MEASURES, Measure};
