//! Finalizing a results folder: the files it derives from its runs, written once its runs are
//! all there (at the end of `bench` and `merge`, and by `results plot`).

use std::path::Path;

use super::manifest::{self, Manifest};
use super::{ompl, parquet, plots, progress_parquet, report, sort, store, traces, verify};
use crate::Error;
use crate::run::Status;

/// Writes the derived files of a results folder from its runs: sorts `runs.csv` and
/// `progress.csv` into run order ([`sort`], on disk), writes `runs.parquet` and
/// `progress.parquet` from them, `ompl.log`, the plots and `report.html`, and records
/// the counts, end time and every file's hash in the manifest.
pub fn finalize(dir: &Path) -> Result<(), Error> {
    finalize_with(dir, &crate::plot::export::FigureOptions::default())
}

/// [`finalize`] with figure options (size preset, DPI, axes, PDF).
pub fn finalize_with(dir: &Path, opts: &crate::plot::export::FigureOptions) -> Result<(), Error> {
    let mut m = Manifest::read(dir)?;
    sort::sort_files(dir)?;
    // the Parquet files are written from the sorted run files, a row group at a time
    let runs_csv = store::Snapshot::open(&dir.join(store::RUNS))?;
    let runs_pq = dir.join(parquet::PARQUET);
    match &runs_csv {
        Some(s) => parquet::write(&runs_pq, store::file_agents(dir), s.runs()?)?,
        None => parquet::write(&runs_pq, 0, std::iter::empty())?,
    }
    // the traces' index and progress.parquet, from one pass over progress.csv
    let mut progress_pq =
        progress_parquet::Writer::create(&dir.join(progress_parquet::PROGRESS_PARQUET))?;
    let progress = traces::Traces::read_each(dir, |row| progress_pq.push(row))?;
    progress_pq.finish()?;
    let runs = store::read_runs(dir)?;
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
