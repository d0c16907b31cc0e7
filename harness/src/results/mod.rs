//! A results folder `results/<experiment>/`:
//!
//! - `runs.csv`: one tidy row per run ([`crate::run::RunRecord`]);
//! - `runs.parquet`: the same runs, typed, in Parquet ([`parquet`]), once the folder is
//!   finalized;
//! - `progress.csv`: the planners' progress traces, and `progress.parquet` the same in Parquet
//!   ([`progress_parquet`]) once the folder is finalized;
//! - `manifest.json`: the experiment, code revision, crate versions, host, threads, times;
//! - `ompl.log`: the runs in OMPL's benchmark log format;
//! - `plots/`: SVG and PNG plots;
//! - `report.html`: one self-contained page with every plot and summary tables;
//! - `replays/run-<index>.html`: each run played back in a browser, `scenarios/<name>.svg`:
//!   each scenario's preview ([`crate::replay`], docs/replay.md);
//! - `.magbench.lock`: the lock a `bench` or `merge` holds while it writes the folder.
//!
//! docs/results.md describes the files, the lock, crash safety and `results verify`.

pub mod finalize;
pub mod lock;
pub mod manifest;
pub mod merge;
pub mod ompl;
pub mod parquet;
pub mod plots;
pub mod progress_parquet;
pub mod repair;
pub mod report;
pub mod resume;
pub mod sample;
pub mod sort;
pub mod store;
pub mod summary;
mod temporary;
pub mod traces;
pub mod verify;
mod verify_rows;

pub use finalize::{finalize, finalize_with};
pub use manifest::{MANIFEST, Manifest};
