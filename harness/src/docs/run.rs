//! Running one measurement: its experiment's sweep, then its table under a [`Header`].

use std::path::Path;
use std::time::Instant;

use super::header::{Header, parse};
use super::measures::{Kind, Measure};
use crate::CliError;
use crate::experiment::Experiment;
use crate::results::manifest::{git_revision, host, now};
use crate::results::store::read_runs;
use crate::run::{Executor, RunOutput, Status, execute_caught};
use crate::sweep::{ProgressMode, SweepOptions, run_sweep};

/// How a measurement runs.
#[derive(Debug, Clone)]
pub struct RunOptions<'a> {
    /// The repository root (experiments are read relative to it).
    pub root: &'a Path,
    /// Folder for the sweeps' results (`NAME/` in it is replaced).
    pub work: &'a Path,
    /// Keep only the measurement's `quick_seeds` seeds.
    pub quick: bool,
    /// Worker threads.
    pub threads: usize,
    /// Progress display of the sweep.
    pub progress: ProgressMode,
}

/// The load average over 1, 5 and 15 minutes from `/proc/loadavg` ("unknown" elsewhere).
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .map(|t| t.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

/// Runs measurement `m` with executor `ex` and returns the text of `docs/measured/NAME.md`.
pub fn measure(m: &Measure, ex: &dyn Executor, o: &RunOptions) -> Result<String, CliError> {
    let load = load_average();
    let mut e = Experiment::load(&o.root.join(m.experiment), ex)?;
    let all = e.seeds.len();
    if o.quick {
        e.seeds.truncate(m.quick_seeds);
    }
    let dir = o.work.join(m.name);
    if dir.exists() {
        std::fs::remove_dir_all(&dir)?;
    }
    crate::cli::output::prepare_dir(&dir, "--work")?;
    let t0 = Instant::now();
    let (count, table) = match m.table {
        Kind::Runs(f) => {
            let runs = sweep(m, &e, ex, o, &dir)?;
            (runs.len(), f(&runs))
        }
        Kind::Folder(f) => {
            let runs = sweep(m, &e, ex, o, &dir)?;
            (runs.len(), f(&dir, &runs)?)
        }
        Kind::Outputs(f) => {
            let outs = run_each(m, &e, ex, o.threads)?;
            (outs.len(), f(&outs))
        }
    };
    let secs = t0.elapsed().as_secs_f64();
    let h = host();
    let seeds = match o.quick {
        true => format!("the first {} of its {all} seeds (`--quick`)", e.seeds.len()),
        false => format!("{all} seeds"),
    };
    let build = if cfg!(debug_assertions) {
        "dev (debug assertions on)"
    } else {
        "release"
    };
    let header = Header {
        command: format!(
            "magbench docs measure --only {}{}{}",
            m.name,
            if o.quick { " --quick" } else { "" },
            match m.feature {
                Some(f) => format!(" (a build with --features {f})"),
                None => String::new(),
            }
        ),
        runs: format!(
            "`{}`, {seeds}: {} runs in {secs:.0} s on {} threads, {build} build",
            m.experiment, count, o.threads
        ),
        machine: format!("{}, {} logical cores", h.cpu_model, h.cpus),
        load: format!("{load} (1, 5, 15 min) at the start; the machine may be shared"),
        date: now(),
        version: format!("{} (git {})", env!("CARGO_PKG_VERSION"), git_revision()),
    };
    let text = format!("{}\n{}", header.render(), table.markdown());
    parse(&text).map_err(|err| CliError::Failed(format!("{}: generated file: {err}", m.name)))?;
    Ok(text)
}

/// Sweeps experiment `e` of `m` into `dir` and returns its runs; a crashed run is an error.
fn sweep(
    m: &Measure,
    e: &Experiment,
    ex: &dyn Executor,
    o: &RunOptions,
    dir: &Path,
) -> Result<Vec<crate::run::RunRecord>, CliError> {
    let opts = SweepOptions {
        out: dir.to_path_buf(),
        threads: o.threads,
        shard: None,
        resume: false,
        progress: o.progress,
    };
    let s = run_sweep(e, ex, &opts)?;
    if s.failed > 0 {
        return Err(CliError::Failed(format!(
            "{}: {} runs crashed: see the `error` column of {}",
            m.name,
            s.failed,
            dir.join("runs.csv").display()
        )));
    }
    read_runs(dir)
}

/// Runs every run of experiment `e` of `m` on `threads` threads and keeps each whole output,
/// in run order; a crashed run is an error naming it.
fn run_each(
    m: &Measure,
    e: &Experiment,
    ex: &dyn Executor,
    threads: usize,
) -> Result<Vec<RunOutput>, CliError> {
    use rayon::prelude::*;
    let specs = e.runs();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|err| CliError::Failed(format!("{}: thread pool: {err}", m.name)))?;
    let outs: Vec<RunOutput> = pool.install(|| {
        specs
            .par_iter()
            .map(|spec| execute_caught(ex, spec))
            .collect()
    });
    if let Some(c) = outs.iter().find(|o| o.record.status == Status::Crash) {
        return Err(CliError::Failed(format!(
            "{}: run {} crashed: {}",
            m.name, c.record.run_id, c.record.error
        )));
    }
    Ok(outs)
}
