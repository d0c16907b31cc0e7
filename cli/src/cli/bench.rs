//! `magbench bench`: run an experiment into a results folder.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use magbench_env::input::{Bound, Rejection};

use super::number::count;
use crate::Error;
use crate::experiment::{Experiment, MAX_RUNS, Tracking};
use crate::output::outln;
use crate::registry::Registry;
use crate::replay::ReplayPolicy;
use crate::run::Executor;
use crate::run::fake::FakeExecutor;
use crate::run::real::RealExecutor;
use crate::sweep::{ProgressMode, SweepOptions, parse_shard, run_sweep};

/// Which executor runs the runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ExecutorKind {
    /// The real planners and trackers.
    Real,
    /// Synthetic results (tests of the harness itself).
    Fake,
}

impl ExecutorKind {
    /// The executor (a real one runs the planners and trackers of `registry`).
    pub fn executor(self, registry: &Registry) -> Box<dyn Executor> {
        match self {
            ExecutorKind::Real => Box::new(RealExecutor::new(registry.clone())),
            ExecutorKind::Fake => Box::new(FakeExecutor),
        }
    }
}

/// Arguments of `magbench bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// The experiment file (default: experiments/default.toml).
    pub file: Option<PathBuf>,
    /// Run a frozen suite (`suites/NAME`, or a suite folder) with its default planners, seeds
    /// and limits instead of an experiment file.
    #[arg(long, conflicts_with = "file")]
    pub suite: Option<String>,
    /// Results folder (default: results/<experiment name>, or results/<name>-shard-I-of-N).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads (default: all CPUs).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Run only slice I of N of the run matrix (1 ≤ I ≤ N); join slices with `magbench merge`.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Complete an interrupted sweep in --out: run only the missing runs.
    #[arg(long)]
    pub resume: bool,
    /// Which runs get a replay page: all, failed, sample:N, failed+sample:N or none (default:
    /// the experiment file's `replays`, else failed+sample:30; docs/replay.md).
    #[arg(long, value_name = "POLICY")]
    pub replays: Option<String>,
    /// One plain line per run even on a terminal.
    #[arg(long, conflicts_with = "quiet")]
    pub lines: bool,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
    /// Validate the experiment and print the run matrix size, without running.
    #[arg(long)]
    pub dry_run: bool,
    /// Executor (hidden: `fake` exercises the harness without planners).
    #[arg(long, value_enum, default_value_t = ExecutorKind::Real, hide = true)]
    pub executor: ExecutorKind,
}

/// The default experiment file: `experiments/default.toml` in the working directory, else in
/// the source tree this binary was built from.
pub fn default_experiment() -> PathBuf {
    let local = PathBuf::from("experiments/default.toml");
    if local.exists() {
        return local;
    }
    let built = Path::new(env!("CARGO_MANIFEST_DIR")).join("../experiments/default.toml");
    if built.exists() {
        eprintln!(
            "note: no experiments/default.toml here; using the source tree's, {}",
            built.display()
        );
        built
    } else {
        local
    }
}

/// Parses `--replays`.
pub fn replay_policy(text: &str) -> Result<ReplayPolicy, Error> {
    text.parse()
        .map_err(|why: String| Error::rejected("--replays", Rejection::new("", why)))
}

/// `--shard I/N`: N shards, at most one run each.
const SHARDS: Bound = Bound::closed(
    1.0,
    MAX_RUNS as f64,
    " shards (N of I/N)",
    "an experiment has at most 1000000 runs, and a shard beyond them would be empty",
);

/// Runs `magbench bench` with the planners and trackers of `registry`.
pub fn run(a: BenchArgs, registry: &Registry) -> Result<(), Error> {
    let executor = a.executor.executor(registry);
    let ex = executor.as_ref();
    let mut e = match &a.suite {
        Some(name) => super::suite::experiment(name, registry, ex)?,
        None => Experiment::load(&a.file.clone().unwrap_or_else(default_experiment), ex)?,
    };
    if let Some(p) = &a.replays {
        e.replays = replay_policy(p)?;
    }
    let shard = a
        .shard
        .as_deref()
        .map(parse_shard)
        .transpose()
        .map_err(|r| Error::rejected("--shard", r))?;
    if let Some((_, n)) = shard {
        count("--shard", &SHARDS, n as u64)?;
    }
    let threads = super::number::threads(a.threads)?;
    let out = a.out.clone().unwrap_or_else(|| match shard {
        Some((i, n)) => PathBuf::from("results").join(format!("{}-shard-{i}-of-{n}", e.name)),
        None => PathBuf::from("results").join(&e.name),
    });
    let total = e.run_count_of(shard);
    if a.dry_run {
        let combos = e.trackers.len() * e.presets.len();
        let matrix = match &e.tracking {
            Tracking::Plans(p) => format!(
                "{} scenarios × ({} planners' planning runs + {} tracked planners × {combos} tracker/preset combinations) × {} seeds",
                e.scenarios.len(),
                e.planners.len(),
                p.len(),
                e.seeds.len(),
            ),
            Tracking::None | Tracking::Every => format!(
                "{} scenarios × {} planners × {} tracker/preset combinations × {} seeds",
                e.scenarios.len(),
                e.planners.len(),
                combos.max(1),
                e.seeds.len(),
            ),
        };
        outln!(
            "{}: {} runs ({matrix}){}",
            e.source,
            total,
            shard
                .map(|(i, n)| format!(", shard {i}/{n}"))
                .unwrap_or_default()
        );
        return Ok(());
    }
    crate::output::prepare_dir(&out, "--out")?;
    crate::experiment::generated::keep_files(&e.text, &e.source, &out)?;
    let progress = if a.quiet {
        ProgressMode::Quiet
    } else if a.lines {
        ProgressMode::Lines
    } else {
        ProgressMode::Auto
    };
    let opts = SweepOptions {
        out: out.clone(),
        threads,
        shard,
        resume: a.resume,
        progress,
    };
    let t0 = std::time::Instant::now();
    let s = run_sweep(&e, ex, &opts)?;
    outln!(
        "{}: {} runs in {} ({} done before, {} now, {} crashed) in {:.1} s on {threads} threads",
        e.name,
        s.total,
        out.display(),
        s.skipped,
        s.executed,
        s.failed,
        t0.elapsed().as_secs_f64()
    );
    if s.failed > 0 {
        return Err(Error::Failed(format!(
            "{} runs crashed: see the `error` column of {}",
            s.failed,
            out.join("runs.csv").display()
        )));
    }
    Ok(())
}
