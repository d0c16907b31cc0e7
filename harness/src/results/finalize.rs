//! Finalizing a results folder: the files it derives from its runs, written once its runs are
//! all there (at the end of `bench` and `merge`, and by `results plot`).

use std::path::Path;

use super::manifest::{self, Manifest};
use super::{ompl, parquet, plots, report, sort, store, traces, verify};
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
