//! A results folder `results/<experiment>/`:
//!
//! - `runs.csv`: one tidy row per run ([`crate::run::RunRecord`]);
//! - `runs.parquet`: the same runs, typed, in Parquet ([`parquet`]), once the folder is
//!   finalized;
//! - `progress.csv`: the planners' progress traces;
//! - `manifest.json`: the experiment, code revision, crate versions, host, threads, times;
//! - `ompl.log`: the runs in OMPL's benchmark log format;
//! - `plots/`: SVG and PNG plots;
//! - `report.html`: one self-contained page with every plot and summary tables;
//! - `replays/run-<index>.html`: each run played back in a browser, `scenarios/<name>.svg`:
//!   each scenario's preview ([`crate::replay`], docs/replay.md);
//! - `.magbench.lock`: the lock a `bench` or `merge` holds while it writes the folder.
//!
//! docs/results.md describes the files, the lock, crash safety and `results verify`.

pub mod lock;
pub mod manifest;
pub mod merge;
pub mod ompl;
pub mod parquet;
pub mod plots;
pub mod repair;
pub mod report;
pub mod resume;
pub mod sort;
pub mod store;
pub mod summary;
pub mod traces;
pub mod verify;

use std::path::Path;

pub use manifest::{MANIFEST, Manifest};

use crate::Error;
use crate::run::Status;

/// Writes the derived files of a results folder from its runs: sorts `runs.csv` and
/// `progress.csv` into run order ([`sort`], on disk), writes `runs.parquet`, `ompl.log`, the plots and
/// `report.html`, and records
/// the counts, end time and every file's hash in the manifest.
pub fn finalize(dir: &Path) -> Result<(), Error> {
    finalize_with(dir, &crate::plot::export::FigureOptions::default())
}

/// [`finalize`] with figure options (size preset, DPI, axes, PDF).
pub fn finalize_with(dir: &Path, opts: &crate::plot::export::FigureOptions) -> Result<(), Error> {
    let mut m = Manifest::read(dir)?;
    sort::sort_files(dir)?;
    let runs = store::read_runs(dir)?;
    parquet::write(&dir.join(parquet::PARQUET), store::file_agents(dir), &runs)?;
    let progress = traces::Traces::read(dir)?;
    m.runs_done = runs.len();
    m.runs_failed = runs.iter().filter(|r| r.status == Status::Crash).count();
    m.finished = Some(manifest::now());
    ompl::write(dir, &m, &runs, &progress)?;
    let figures = plots::write_all_with(dir, &m, &runs, &progress, opts)?;
    drop(progress);
    report::write(dir, &m, &runs, &figures, opts.units)?;
    drop(runs);
    m.files = verify::file_hashes(dir)?;
    m.write(dir)
}
