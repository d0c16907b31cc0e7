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
//! docs/results.md describes the files, the lock, crash safety and `results verify`. The run
//! files, the manifest, the lock, repair, sorting, merging and verification are the results
//! store's (`magbench-store`, its modules re-exported here); the figures, the report, the OMPL
//! log and the replay pages are the harness's.

pub mod finalize;
pub mod merge;
pub mod ompl;
pub mod plots;
pub mod report;
pub mod resume;
pub mod sample;
pub mod summary;

pub use finalize::{finalize, finalize_with};
pub use magbench_store::lock;
pub use magbench_store::manifest;
pub use magbench_store::manifest::{MANIFEST, Manifest};
pub use magbench_store::parquet;
pub use magbench_store::progress_parquet;
pub use magbench_store::repair;
pub use magbench_store::sort;
pub use magbench_store::store;
pub use magbench_store::temporary;
pub use magbench_store::traces;
pub use magbench_store::verify;
