//! Finalizing a results folder: the files it derives from its runs, written once its runs are
//! all there (at the end of `bench` and `merge`, and by `results plot`).

use std::path::Path;

use super::manifest::{self, Manifest};
use super::sample::Sample;
use super::{ompl, parquet, plots, progress_parquet, report, sort, store, traces, verify};
use crate::Error;

/// Writes the derived files of a results folder from its runs: sorts `runs.csv` and
/// `progress.csv` into run order ([`sort`], on disk), writes `runs.parquet` and
/// `progress.parquet` from them, `ompl.log`, the plots and `report.html`, and records
/// the counts, end time and every file's hash in the manifest. Each run file is read once
/// more after the sort, a row at a time; memory holds the runs the figures and report keep
/// ([`super::sample`]) and a few numbers per run (the traces' and the OMPL log's positions).
pub fn finalize(dir: &Path) -> Result<(), Error> {
    finalize_with(dir, &crate::plot::export::FigureOptions::default())
}

/// [`finalize`] with figure options (size preset, DPI, axes, PDF).
pub fn finalize_with(dir: &Path, opts: &crate::plot::export::FigureOptions) -> Result<(), Error> {
    let mut m = Manifest::read(dir)?;
    sort::sort_files(dir)?;
    // the traces' index and progress.parquet, from one pass over progress.csv
    let mut progress_pq =
        progress_parquet::Writer::create(&dir.join(progress_parquet::PROGRESS_PARQUET))?;
    let progress = traces::Traces::read_each(dir, |row| progress_pq.push(row))?;
    progress_pq.finish()?;
    // runs.parquet, the OMPL logs' runs and the figures' and report's sample, from one pass
    // over runs.csv
    let mut sample = Sample::default();
    let mut log = ompl::Gather::create(dir)?;
    let runs_csv = store::Snapshot::open(&dir.join(store::RUNS))?;
    let agents = runs_csv.as_ref().map(header_agents).transpose()?;
    let mut runs_pq = parquet::Writer::create(&dir.join(parquet::PARQUET), agents.unwrap_or(0))?;
    if let Some(s) = &runs_csv {
        for r in s.runs()? {
            let r = r?;
            sample.push(dir, &r);
            log.push(&r, &progress)?;
            runs_pq.push(r)?;
        }
    }
    runs_pq.finish()?;
    m.runs_done = sample.runs;
    m.runs_failed = sample.crashed;
    m.finished = Some(manifest::now());
    ompl::write(dir, &m, log.finish()?)?;
    let (sums, replays) = (sample.summaries(), sample.replays);
    let runs = sample.into_runs();
    let figures = plots::write_all_with(dir, &m, (&runs, &sums), &progress, opts)?;
    drop(progress);
    report::write(dir, &m, (&sums, &runs, replays), &figures, opts.units)?;
    drop(runs);
    m.files = verify::file_hashes(dir)?;
    m.write(dir)
}

/// The number of agents whose per-agent columns the header of `runs` has (its first line).
fn header_agents(runs: &store::Snapshot) -> Result<usize, Error> {
    let mut header = String::new();
    std::io::BufRead::read_line(&mut runs.reader()?, &mut header)
        .map_err(|e| Error::Failed(format!("{}: {e}", runs.path().display())))?;
    Ok(store::header_agents(header.trim_end()).unwrap_or(0))
}
