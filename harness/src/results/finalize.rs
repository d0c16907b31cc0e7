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
/// the counts, end time and every file's hash in the manifest. The run files are read once more
/// after the sort, side by side, a run at a time ([`traces::InOrder`]); memory holds the runs
/// the figures and report keep ([`super::sample`]) and one file position per run (the OMPL
/// log's).
pub fn finalize(dir: &Path) -> Result<(), Error> {
    finalize_with(dir, &crate::plot::export::FigureOptions::default())
}

/// [`finalize`] with figure options (size preset, DPI, axes, PDF).
pub fn finalize_with(dir: &Path, opts: &crate::plot::export::FigureOptions) -> Result<(), Error> {
    let mut m = Manifest::read(dir)?;
    sort::sort_files(dir)?;
    // runs.parquet, progress.parquet, the OMPL logs' runs and the figures' and report's sample,
    // from one pass over runs.csv and progress.csv side by side
    let mut progress_pq =
        progress_parquet::Writer::create(&dir.join(progress_parquet::PROGRESS_PARQUET))?;
    let mut each_point = |row| progress_pq.push(row);
    let mut progress = traces::InOrder::open(dir)?;
    let mut sample = Sample::default();
    let mut log = ompl::Gather::create(dir)?;
    let runs_csv = store::Snapshot::open(&dir.join(store::RUNS))?;
    let agents = runs_csv.as_ref().map(header_agents).transpose()?;
    let mut runs_pq = parquet::Writer::create(&dir.join(parquet::PARQUET), agents.unwrap_or(0))?;
    if let Some(s) = &runs_csv {
        for r in s.runs()? {
            let r = r?;
            let (points, at) = progress.trace(r.run, &mut each_point)?;
            sample.push(dir, &r, at);
            log.push(&r, &points)?;
            runs_pq.push(r)?;
        }
    }
    progress.finish(&mut each_point)?;
    progress_pq.finish()?;
    runs_pq.finish()?;
    m.runs_done = sample.runs;
    m.runs_failed = sample.crashed;
    m.finished = Some(manifest::now());
    ompl::write(dir, &m, log.finish()?)?;
    let (sums, replays) = (sample.summaries(), sample.replays);
    let (runs, kept_traces) = sample.into_kept();
    let progress = traces::Traces::at(dir, kept_traces)?;
    let figures = plots::write_all_with(dir, &m, (&runs, &sums), &progress, opts)?;
    drop(progress);
    report::write(dir, &m, (&sums, &runs, replays), &figures, opts.units)?;
    drop(runs);
    m.files = verify::file_hashes(dir)?;
    Ok(m.write(dir)?)
}

/// The number of agents whose per-agent columns the header of `runs` has (its first line).
fn header_agents(runs: &store::Snapshot) -> Result<usize, Error> {
    let mut header = String::new();
    std::io::BufRead::read_line(&mut runs.reader()?, &mut header)
        .map_err(|e| Error::Failed(format!("{}: {e}", runs.path().display())))?;
    Ok(store::header_agents(header.trim_end()).unwrap_or(0))
}
