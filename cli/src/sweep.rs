//! Sweeps: the runs of an experiment (or of one shard of it) as independent jobs on a rayon
//! pool, each row written as soon as its run finishes.

use crate::metrics::Metric;
use crate::metrics::difficulty::Measures;
use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use magbench_env::input::Rejection;
use rayon::prelude::*;

use crate::Error;
use crate::experiment::{Experiment, Matrix};
use crate::results::manifest::{Session, host, now};
use crate::results::store::RunWriter;
use crate::results::{self, resume, verify};
use crate::run::{Executor, RunOutput, RunSpec, Status, execute_caught};

/// How to display progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProgressMode {
    /// A progress bar if stdout is a terminal, else one plain line per run.
    Auto,
    /// One plain line per run.
    Lines,
    /// Nothing.
    Quiet,
}

/// Options of a sweep.
#[derive(Debug, Clone)]
pub struct SweepOptions {
    /// Results folder.
    pub out: PathBuf,
    /// Worker threads.
    pub threads: usize,
    /// `(i, n)`: run only the runs whose index is `i − 1` modulo `n` (1 ≤ i ≤ n).
    pub shard: Option<(usize, usize)>,
    /// Complete an interrupted sweep in `out` instead of refusing to touch it.
    pub resume: bool,
    /// Progress display.
    pub progress: ProgressMode,
}

/// What a sweep did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SweepSummary {
    /// Runs in this sweep's slice of the matrix.
    pub total: usize,
    /// Runs found finished in `out` and skipped.
    pub skipped: usize,
    /// Runs executed now.
    pub executed: usize,
    /// Executed runs that crashed.
    pub failed: usize,
}

/// Parses `I/N` with 1 ≤ I ≤ N; a refusal's field is empty (the caller names the option).
pub fn parse_shard(s: &str) -> Result<(usize, usize), Rejection> {
    let refuse = |reason: &str| Rejection::new("", format!("{s:?}: {reason}"));
    let (i, n) = s
        .split_once('/')
        .ok_or_else(|| refuse("expected I/N, e.g. 1/4"))?;
    let (i, n): (usize, usize) = (
        i.trim().parse().map_err(|_| refuse("I is not a number"))?,
        n.trim().parse().map_err(|_| refuse("N is not a number"))?,
    );
    if n == 0 || i == 0 || i > n {
        return Err(refuse("need 1 ≤ I ≤ N"));
    }
    Ok((i, n))
}

enum Reporter {
    Bar(ProgressBar),
    Lines { done: AtomicUsize, total: usize },
    Quiet,
}

impl Reporter {
    fn new(mode: ProgressMode, total: usize, done: usize) -> Reporter {
        let tty = std::io::stdout().is_terminal();
        match mode {
            ProgressMode::Auto if tty => {
                let bar =
                    ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::stdout());
                bar.set_style(
                    ProgressStyle::with_template(
                        "{elapsed_precise} [{bar:40.cyan/blue}] {pos}/{len} runs, ETA {eta} {msg}",
                    )
                    .expect("template")
                    .progress_chars("=> "),
                );
                bar.set_position(done as u64);
                bar.set_message("0 failed");
                Reporter::Bar(bar)
            }
            ProgressMode::Auto | ProgressMode::Lines => Reporter::Lines {
                done: AtomicUsize::new(done),
                total,
            },
            ProgressMode::Quiet => Reporter::Quiet,
        }
    }

    fn finished(&self, out: &RunOutput, failed: usize) {
        match self {
            Reporter::Bar(b) => {
                b.inc(1);
                b.set_message(format!("{failed} failed"));
            }
            Reporter::Lines { done, total } => {
                let k = done.fetch_add(1, Ordering::SeqCst) + 1;
                let _ = crate::output::emit(&format!("[{k}/{total}] {}\n", line(out)));
            }
            Reporter::Quiet => {}
        }
    }

    fn end(&self) {
        if let Reporter::Bar(b) = self {
            // the bar stays on its line; what follows starts on the next
            b.finish();
            let _ = crate::output::emit("\n");
        }
    }
}

/// A one-line summary of a finished run.
pub fn line(out: &RunOutput) -> String {
    let r = &out.record;
    let mut s = format!("{} {} ", r.scenario, r.planner);
    if !r.tracker.is_empty() {
        s += &format!("{} {} ", r.tracker, r.preset);
    }
    s += &format!("seed {}: {}", r.seed, r.status.as_str());
    if let Some(c) = r.get(Metric::Cost) {
        s += &format!(", cost {c:.3}");
    }
    if let Some(e) = r.get(Metric::RmsError) {
        s += &format!(", rms {e:.3} BL");
    }
    if let Some(g) = r.reached_goal {
        s += if g { ", reached goal" } else { ", missed goal" };
    }
    s += &format!(
        ", {:.2} s",
        r.get(Metric::PlanTime).unwrap_or(0.0) + r.get(Metric::TrackTime).unwrap_or(0.0)
    );
    if !r.error.is_empty() {
        s += &format!(" ({})", r.error);
    }
    s
}

/// Runs the experiment's runs (of one shard, if asked) into `opts.out`, then writes the
/// folder's derived files (sorted CSVs, `ompl.log`, plots, `report.html`) if every run of the
/// slice is done.
pub fn run_sweep(
    e: &Experiment,
    ex: &dyn Executor,
    opts: &SweepOptions,
) -> Result<SweepSummary, Error> {
    let matrix = e.matrix();
    let indices = matrix.indices(opts.shard);
    let out = &opts.out;
    let shard_arr = opts.shard.map(|(i, n)| [i, n]);
    let opened = resume::open_for_sweep(
        out,
        e,
        &resume::OpenOptions {
            executor: ex.name(),
            threads: opts.threads,
            shard: shard_arr,
            resume: opts.resume,
        },
    )?;
    // the lock is held to the end of the sweep, through finalize and verify
    let (mut manifest, done, _lock) = (opened.manifest, opened.done, opened.lock);
    let total = indices.len();
    let skipped = done.len();
    let t0 = Instant::now();
    manifest.threads = opts.threads;
    manifest.host = host();
    manifest.sessions.push(Session {
        kind: if opts.resume {
            "bench --resume".into()
        } else {
            "bench".into()
        },
        started: now(),
        finished: None,
        threads: opts.threads,
        runs_executed: 0,
        wall_time_s: None,
        host: manifest.host.clone(),
    });
    // what depends on a run's configuration and not its seed, from one run of each
    let firsts = matrix.firsts(indices.clone());
    for s in &firsts {
        for name in ex.one_at_a_time(s) {
            if !manifest.one_at_a_time.contains(&name) {
                manifest.one_at_a_time.push(name);
            }
        }
    }
    manifest.one_at_a_time.sort();
    manifest.replays = Some(e.replays.to_string());
    manifest.write(out)?;
    // the sample is drawn from the whole matrix, so that every shard draws the same one
    let replays = e.replays;
    let sampled = replays.sampled(e.run_ids());
    if !replays.is_none() {
        crate::replay::files::write_player(out)?;
    }

    let agents = firsts
        .iter()
        .filter(|s| s.tracker.is_some())
        .map(|s| s.scenario.agents())
        .max()
        .unwrap_or(0);
    let writer = Mutex::new(RunWriter::open(out, agents)?);
    crate::replay::files::write_previews(
        out,
        firsts
            .iter()
            .map(|s| (s.scenario_label.as_str(), &*s.scenario)),
    )?;
    let failed = AtomicUsize::new(0);
    // runs of a component that holds a global lock (Python's GIL) take turns, so that each one's
    // times are its own and not the wait for the lock
    let turn = Mutex::new(());
    let reporter = Reporter::new(opts.progress, total, skipped);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.max(1))
        .build()
        .map_err(|err| Error::Failed(format!("thread pool: {err}")))?;
    // each scenario's difficulty measures, once, for the rows of all its runs
    let mut scenarios: Vec<&RunSpec> = vec![];
    for s in &firsts {
        if !scenarios
            .iter()
            .any(|t| t.scenario_label == s.scenario_label)
        {
            scenarios.push(s);
        }
    }
    let difficulty: BTreeMap<&str, Measures> = pool.install(|| {
        scenarios
            .par_iter()
            .map(|s| (s.scenario_label.as_str(), Measures::of(&s.scenario)))
            .collect()
    });
    // the runs are made one at a time, as they start
    let result: Result<(), Error> = pool.install(|| {
        (0..total)
            .into_par_iter()
            .with_max_len(1)
            .map(|j| Matrix::nth_of(opts.shard, j))
            .filter(|i| done.binary_search(i).is_err())
            .try_for_each(|index| {
                let spec = matrix.spec(index);
                let mut o = if ex.one_at_a_time(&spec).is_empty() {
                    execute_caught(ex, &spec)
                } else {
                    let _turn = turn.lock().unwrap_or_else(|p| p.into_inner());
                    execute_caught(ex, &spec)
                };
                let f = if o.record.status == Status::Crash {
                    failed.fetch_add(1, Ordering::SeqCst) + 1
                } else {
                    failed.load(Ordering::SeqCst)
                };
                o.record.difficulty = difficulty
                    .get(spec.scenario_label.as_str())
                    .copied()
                    .unwrap_or_default();
                if !replays.keeps(&sampled, &o.record) {
                    o.replay = None;
                }
                // the page before the row, so that a run with a row has its page; a page an
                // interrupted sweep left for this run (another policy, or an attempt that ended
                // otherwise) would show another run than the row
                match &o.replay {
                    Some(r) => crate::replay::files::write_replay(out, spec.index, r)?,
                    None => crate::replay::files::remove_replay(out, spec.index)?,
                }
                writer
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .write(&o.record, &o.progress)?;
                reporter.finished(&o, f);
                Ok(())
            })
    });
    reporter.end();
    result?;
    let executed = total - skipped;
    // finalize and verify read the folder, not the runs it held before
    drop(done);
    let failed = failed.into_inner();
    let session = manifest.sessions.last_mut().expect("pushed above");
    session.finished = Some(now());
    session.runs_executed = executed;
    session.wall_time_s = Some(t0.elapsed().as_secs_f64());
    manifest.write(out)?;
    results::finalize(out)?;
    verify::require_sound(out, true)?;
    Ok(SweepSummary {
        total,
        skipped,
        executed,
        failed,
    })
}
