//! What a results folder's figures and report read of its runs, gathered in one pass over
//! `runs.csv`, in memory that does not grow with the number of runs per configuration: each
//! configuration's exact counts (runs, crashes, successes, contacts, each agent's worst runs)
//! and each metric's exact count, mean, smallest and largest value, and at most [`SAMPLE`] of
//! its runs, evenly spread in run order, with where their traces are in `progress.csv`, for the
//! quartiles, box plots, CDFs and curves.
//!
//! A configuration of at most [`SAMPLE`] runs keeps them all, so its figures and report are
//! those of every run. A larger one keeps every `2^j`-th of its runs (the smallest `j` that
//! leaves at most [`SAMPLE`]): between half of [`SAMPLE`] and [`SAMPLE`] runs, chosen by their
//! position alone, so the same folder always gives the same figures.

use std::collections::HashMap;
use std::path::Path;

use super::summary::{GroupSummary, summarize};
use super::traces::Stretch;
use crate::metrics::Metric;
use crate::run::{RunRecord, Status};
use crate::stats::wilson;

/// The most runs a configuration keeps for its figures and quartiles: a kept sample's median is,
/// 19 times in 20, within 1.4% in rank of the whole's at 5,000 runs (1.96 standard errors of
/// √(p(1-p)/n)) and 1.0% at 10,000; a million runs of ten configurations keep 50,000 to
/// 100,000 rows.
pub const SAMPLE: usize = 10_000;

/// A metric's exact count, sum, smallest and largest value over a configuration's runs that
/// have a finite value of it.
#[derive(Debug, Clone, Copy)]
struct Moments {
    n: usize,
    sum: f64,
    min: f64,
    max: f64,
}

impl Default for Moments {
    fn default() -> Self {
        Moments {
            n: 0,
            sum: 0.0,
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
        }
    }
}

/// One configuration's exact counts and its kept runs.
#[derive(Debug)]
struct Config {
    runs: usize,
    crashed: usize,
    solved: usize,
    succeeded: usize,
    contacts: usize,
    /// Runs in which each agent was the worst.
    worst: Vec<usize>,
    /// Indexed by [`Metric`].
    metrics: Vec<Moments>,
    /// Its runs kept: every `stride`-th, in run order.
    kept: usize,
    stride: usize,
}

impl Config {
    fn new() -> Config {
        Config {
            runs: 0,
            crashed: 0,
            solved: 0,
            succeeded: 0,
            contacts: 0,
            worst: vec![],
            metrics: vec![Moments::default(); Metric::ALL.len()],
            kept: 0,
            stride: 1,
        }
    }

    /// Counts run `r`; whether the configuration keeps it.
    fn push(&mut self, r: &RunRecord) -> bool {
        let keep = self.runs.is_multiple_of(self.stride);
        self.kept += usize::from(keep);
        self.runs += 1;
        self.crashed += usize::from(r.status == Status::Crash);
        self.solved += usize::from(r.solved);
        self.succeeded += usize::from(r.success());
        self.contacts += usize::from(r.agent_contact == Some(true));
        if let Some(w) = r.worst_agent.and_then(|w| usize::try_from(w).ok()) {
            if self.worst.len() <= w {
                self.worst.resize(w + 1, 0);
            }
            self.worst[w] += 1;
        }
        for (m, s) in Metric::ALL.iter().zip(&mut self.metrics) {
            if let Some(v) = r.get(*m).filter(|v| v.is_finite()) {
                s.n += 1;
                s.sum += v;
                s.min = s.min.min(v);
                s.max = s.max.max(v);
            }
        }
        keep
    }

    /// `g`, the summary of the kept runs, with this configuration's exact counts, means and
    /// extremes in place of the sample's.
    fn exact(&self, mut g: GroupSummary) -> GroupSummary {
        g.n = self.runs;
        g.crashed = self.crashed;
        g.solved = self.solved;
        g.succeeded = self.succeeded;
        g.success_ci = wilson(self.succeeded as u64, self.runs as u64, 0.95);
        g.agent_contacts = self.contacts;
        for (a, w) in g.per_agent.iter_mut().zip(&self.worst) {
            a.worst = *w;
        }
        for (s, e) in g.metrics.iter_mut().zip(&self.metrics) {
            if let Some(s) = s {
                s.n = e.n;
                s.mean = e.sum / e.n as f64;
                s.min = e.min;
                s.max = e.max;
            }
        }
        g
    }
}

/// A configuration's key: scenario, planner, tracker and preset.
fn key(r: &RunRecord) -> String {
    format!(
        "{}\u{1f}{}\u{1f}{}\u{1f}{}",
        r.scenario, r.planner, r.tracker, r.preset
    )
}

/// The runs of a results folder, gathered one at a time ([`Sample::push`]) in run order.
#[derive(Debug, Default)]
pub struct Sample {
    configs: Vec<Config>,
    index: HashMap<String, usize>,
    /// The runs kept, of every configuration, in the order pushed: held in one vector, so that
    /// they are handed on as they are ([`Sample::into_kept`]), not copied.
    kept: Vec<RunRecord>,
    /// The configuration of each kept run.
    of: Vec<usize>,
    /// Where the trace of each kept run is in `progress.csv`.
    traces: Vec<Stretch>,
    /// Runs pushed.
    pub runs: usize,
    /// Crashed runs.
    pub crashed: usize,
    /// Runs with a replay page in the folder.
    pub replays: usize,
}

impl Sample {
    /// Counts run `r` of results folder `dir`, whose trace is at `trace` in its
    /// `progress.csv`, and keeps it if its configuration keeps it.
    pub fn push(&mut self, dir: &Path, r: &RunRecord, trace: Stretch) {
        let k = key(r);
        let i = match self.index.get(&k) {
            Some(i) => *i,
            None => {
                self.configs.push(Config::new());
                self.index.insert(k, self.configs.len() - 1);
                self.configs.len() - 1
            }
        };
        if self.configs[i].push(r) {
            self.kept.push(r.clone());
            self.of.push(i);
            self.traces.push(trace);
            if self.configs[i].kept > SAMPLE {
                self.halve(i);
            }
        }
        self.runs += 1;
        self.crashed += usize::from(r.status == Status::Crash);
        self.replays += crate::replay::files::with_replay(dir, std::slice::from_ref(r));
    }

    /// Keeps every other kept run of configuration `i` (the runs whose position is a multiple
    /// of twice its stride), and doubles its stride.
    fn halve(&mut self, i: usize) {
        let mut nth = 0;
        let keep: Vec<bool> = self
            .of
            .iter()
            .map(|&c| {
                nth += usize::from(c == i);
                c != i || nth % 2 == 1
            })
            .collect();
        /// Keeps the items of `v` whose place in `keep` is true.
        fn retain<T>(v: &mut Vec<T>, keep: &[bool]) {
            let mut k = keep.iter();
            v.retain(|_| *k.next().unwrap_or(&true));
        }
        retain(&mut self.kept, &keep);
        retain(&mut self.of, &keep);
        retain(&mut self.traces, &keep);
        let c = &mut self.configs[i];
        c.kept = c.kept.div_ceil(2);
        c.stride *= 2;
    }

    /// The summary of every configuration, in run order of first appearance: the kept runs'
    /// quartiles with the exact counts, means and extremes.
    pub fn summaries(&self) -> Vec<GroupSummary> {
        let mut mine: Vec<Vec<&RunRecord>> = vec![vec![]; self.configs.len()];
        for (r, &c) in self.kept.iter().zip(&self.of) {
            mine[c].push(r);
        }
        self.configs
            .iter()
            .zip(mine)
            .map(|(c, runs)| c.exact(summarize(&runs)))
            .collect()
    }

    /// Consumes the sample into its kept runs, in run order, and where their traces are (those
    /// with points).
    pub fn into_kept(self) -> (Vec<RunRecord>, Vec<Stretch>) {
        let mut all = self.kept;
        // pushed in run order; run indices are unique: an unstable sort keeps that order, and
        // puts runs pushed out of order in it, without a buffer
        all.sort_unstable_by_key(|r| r.run);
        let traces = self.traces.into_iter().filter(|t| t.rows > 0).collect();
        (all, traces)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Run `run` of configuration `planner`, solved if `solved`, with the first metric of the
    /// table at `value`.
    fn run(run: usize, planner: &str, solved: bool, value: f64) -> RunRecord {
        let mut r = RunRecord::example();
        r.run = run;
        r.planner = planner.into();
        r.solved = solved;
        r.set(Metric::ALL[0], Some(value));
        r
    }

    /// Where run `run`'s trace is in a made-up file: 2 rows at byte `10 × run` for an even run,
    /// none for an odd one.
    fn at(run: usize) -> Stretch {
        Stretch {
            run,
            offset: 10 * run as u64,
            rows: if run.is_multiple_of(2) { 2 } else { 0 },
        }
    }

    #[test]
    fn a_configuration_keeps_every_run_up_to_the_sample_and_every_2j_th_beyond() {
        let dir = Path::new("/nonexistent");
        let mut s = Sample::default();
        let big = 3 * SAMPLE + 5;
        // the two configurations' runs interleaved, as a sweep writes them
        let mut next = 0;
        for i in 0..big {
            if i < SAMPLE {
                s.push(dir, &run(next, "a", true, 0.0), at(next));
                next += 1;
            }
            s.push(dir, &run(next, "b", true, i as f64), at(next));
            next += 1;
        }
        assert_eq!(s.runs, SAMPLE + big);
        // no configuration keeps more than the sample
        assert!(s.configs.iter().all(|c| c.kept <= SAMPLE));
        let (kept, traces) = s.into_kept();
        let a = kept.iter().filter(|r| r.planner == "a").count();
        let b: Vec<f64> = kept
            .iter()
            .filter(|r| r.planner == "b")
            .map(|r| r.get(Metric::ALL[0]).unwrap())
            .collect();
        assert_eq!(a, SAMPLE);
        // 3 × SAMPLE + 5 runs: every fourth (every other leaves more than SAMPLE)
        let every_fourth: Vec<f64> = (0..big).step_by(4).map(|i| i as f64).collect();
        assert_eq!(b, every_fourth);
        assert!((SAMPLE / 2..=SAMPLE).contains(&b.len()));
        assert!(kept.windows(2).all(|w| w[0].run < w[1].run));
        // each kept run's trace kept with it; odd runs have none
        let mut traced: Vec<usize> = traces.iter().map(|t| t.run).collect();
        traced.sort();
        let even: Vec<usize> = kept
            .iter()
            .map(|r| r.run)
            .filter(|r| r.is_multiple_of(2))
            .collect();
        assert_eq!(traced, even);
        assert!(traces.iter().all(|t| t.offset == 10 * t.run as u64));
    }

    #[test]
    fn a_summary_counts_every_run_and_takes_its_quartiles_from_the_kept_ones() {
        let dir = Path::new("/nonexistent");
        let mut s = Sample::default();
        let n = 2 * SAMPLE + 1;
        for i in 0..n {
            s.push(dir, &run(i, "a", i % 3 == 0, i as f64), at(i));
        }
        let [g] = s.summaries().try_into().unwrap();
        assert_eq!(g.n, n);
        assert_eq!(g.solved, n.div_ceil(3));
        assert_eq!(g.succeeded, n.div_ceil(3));
        let m = g.metric(Metric::ALL[0]).unwrap();
        assert_eq!((m.n, m.min, m.max), (n, 0.0, (n - 1) as f64));
        assert_eq!(m.mean, (n - 1) as f64 / 2.0);
        // the kept runs are every fourth: a median within one stride of the whole's
        assert!((m.median - SAMPLE as f64).abs() <= 4.0, "{}", m.median);
    }
}
