//! How the README's regression check (`magbench regress BASELINE CANDIDATE` at its defaults)
//! behaves at a number of seeds: false alarms when nothing changed, and planted regressions
//! found.
//!
//! The CI experiment (`experiments/ci.toml`: goal-zoom-rrt on open-field, tracked by open-loop,
//! OBC and lookahead on the realistic plant) is run once over a pool of [`POOL`] seeds, and
//! once more for each of the [`PLANTED`] settings of OBC: the planted regressions, their runs
//! labelled `obc` so that the folders compare configuration by configuration as two builds of
//! one experiment do. For each number of seeds n per folder,
//! [`DRAWS`] draws of seeds from the pool make a baseline and a candidate, judged by
//! `regress`'s own analysis (`magbench::regress::compare` with its default tolerances):
//!
//! - **A/A, new draws**: baseline and candidate both unchanged, on 2n distinct seeds, the
//!   candidate's renumbered to the baseline's: what a change to a planner's sampling or the
//!   plant's random draws gives, every seed a new sample and nothing worse;
//! - **planted, same seeds**: the planted pool on the baseline's n seeds (a change that touches
//!   OBC alone: the plans and the plant's draws are the same);
//! - **planted, new draws**: the planted pool on n other seeds, renumbered (the change also
//!   gives every seed a new sample).
//!
//! Each row (n seeds per folder) counts the draws with a gated REGRESSION (a false alarm in A/A; the planted
//! regression found otherwise), the draws that pass at `--inconclusive fail` (the default) and
//! at `--inconclusive pass`, and the median number of gated inconclusive verdicts. Every run has
//! an iteration limit, so the table is the same on every machine.
//!
//! `cargo run --release -p magbench --example regress_power` (docs/regress.md, "At how many
//! seeds"); `cargo xtask measure --only regress-power` keeps the table.

use std::path::Path;

use magbench::Registry;
use magbench::experiment::Experiment;
use magbench::regress::report::{inconclusive, regressions};
use magbench::regress::{OnInconclusive, Tolerances, compare, failures};
use magbench::results::store::read_runs;
use magbench::run::RunRecord;
use magbench::run::real::RealExecutor;
use magbench::sweep::{ProgressMode, SweepOptions, run_sweep};
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

/// Seeds in each pool.
const POOL: usize = 256;
/// Seeds per folder.
const SIZES: [usize; 4] = [8, 16, 32, 64];
/// Draws per size and design.
const DRAWS: usize = 100;
/// The planted regressions: OBC's parameters, and what they change (`magbench track open-field
/// --tracker 'obc{w_rel=0.1}' --seed 1` shows one run's error beside `--tracker obc`'s).
const PLANTED: [(&str, &str); 2] = [
    ("w_rel=0.1", "the formation error's weight at a tenth"),
    (
        "grid=4,refine=0",
        "4 field angles instead of 24, not refined",
    ),
];
/// The draws' random stream.
const DRAW_SEED: u64 = 42;

/// The CI experiment's text over `POOL` seeds, no replay pages, with `obc` replaced by `obc_label`.
fn experiment_text(obc_label: &str) -> String {
    let ci = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../experiments/ci.toml"),
    )
    .expect("experiments/ci.toml");
    let seeds = ci
        .lines()
        .find(|l| l.starts_with("seeds"))
        .expect("ci.toml has seeds");
    ci.replace(seeds, &format!("seeds = {POOL}\nreplays = \"none\""))
        .replace("\"obc\"", &format!("\"{obc_label}\""))
}

/// Runs the experiment `text` into a temporary folder and reads its runs back, the tracker
/// label `obc_label` read as `obc`.
fn pool(text: &str, obc_label: &str) -> Vec<RunRecord> {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let ex = RealExecutor::new(Registry::builtin());
    let e = Experiment::parse(text, "ci.toml", Path::new("."), "ci", &ex).expect("an experiment");
    let opts = SweepOptions {
        out: dir.path().join("pool"),
        threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
        shard: None,
        resume: false,
        progress: ProgressMode::Quiet,
    };
    run_sweep(&e, &ex, &opts).expect("the sweep");
    let mut runs = read_runs(&opts.out).expect("its runs");
    for r in &mut runs {
        if r.tracker == obc_label {
            r.tracker = "obc".into();
        }
    }
    runs
}

/// The runs of `pool` whose seeds are `seeds`, renumbered to `0..seeds.len()` in that order.
fn subset(pool: &[RunRecord], seeds: &[u64]) -> Vec<RunRecord> {
    let mut out = vec![];
    for (i, s) in seeds.iter().enumerate() {
        for r in pool.iter().filter(|r| r.seed == *s) {
            let mut r = r.clone();
            r.seed = i as u64;
            out.push(r);
        }
    }
    out
}

/// What one design gave over its draws.
#[derive(Default)]
struct Tally {
    regression: usize,
    pass_fail: usize,
    pass_pass: usize,
    inconclusive: Vec<usize>,
}

impl Tally {
    fn add(&mut self, baseline: &[RunRecord], candidate: &[RunRecord]) {
        let rows = compare(baseline, candidate, &Tolerances::default());
        if regressions(&rows) > 0 {
            self.regression += 1;
        }
        if failures(&rows, OnInconclusive::Fail) == 0 {
            self.pass_fail += 1;
        }
        if failures(&rows, OnInconclusive::Pass) == 0 {
            self.pass_pass += 1;
        }
        self.inconclusive.push(inconclusive(&rows));
    }

    fn row(&mut self, candidate: &str, seeds: &str, n: usize) -> String {
        self.inconclusive.sort_unstable();
        let median = self.inconclusive[self.inconclusive.len() / 2];
        format!(
            "| {candidate} | {seeds} | {n} | {DRAWS} | {} | {} | {} | {median} |",
            self.regression, self.pass_fail, self.pass_pass
        )
    }
}

fn main() {
    let unchanged = pool(&experiment_text("obc"), "obc");
    let planted: Vec<(String, Vec<RunRecord>)> = PLANTED
        .iter()
        .map(|(params, what)| {
            let label = format!("obc{{{params}}}");
            (
                format!("`{label}`: {what}"),
                pool(&experiment_text(&label), &label),
            )
        })
        .collect();
    let seeds: Vec<u64> = {
        let mut s: Vec<u64> = unchanged.iter().map(|r| r.seed).collect();
        s.sort_unstable();
        s.dedup();
        s
    };
    assert_eq!(seeds.len(), POOL, "every seed of the pool ran");
    let gated_metrics = compare(&unchanged, &unchanged, &Tolerances::default())
        .iter()
        .filter(|r| r.gated)
        .count();
    println!(
        "| candidate | seeds | n | draws | draws with a gated REGRESSION | pass (`--inconclusive fail`) | pass (`--inconclusive pass`) | median gated inconclusive (of {gated_metrics}) |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    let mut rng = ChaCha8Rng::seed_from_u64(DRAW_SEED);
    for n in SIZES {
        let mut aa = Tally::default();
        let mut same: Vec<Tally> = planted.iter().map(|_| Tally::default()).collect();
        let mut new: Vec<Tally> = planted.iter().map(|_| Tally::default()).collect();
        for _ in 0..DRAWS {
            let mut s = seeds.clone();
            s.shuffle(&mut rng);
            let (a, b) = (&s[..n], &s[n..2 * n]);
            let baseline = subset(&unchanged, a);
            aa.add(&baseline, &subset(&unchanged, b));
            for (k, (_, runs)) in planted.iter().enumerate() {
                same[k].add(&baseline, &subset(runs, a));
                new[k].add(&baseline, &subset(runs, b));
            }
        }
        println!("{}", aa.row("unchanged (A/A)", "new draws", n));
        for (k, (what, _)) in planted.iter().enumerate() {
            println!("{}", same[k].row(what, "the same", n));
            println!("{}", new[k].row(what, "new draws", n));
        }
    }
}
