//! What a results folder's figures and report read of its runs, gathered in one pass over
//! `runs.csv`, in memory that does not grow with the number of runs per configuration: each
//! configuration's exact counts (runs, crashes, successes, contacts, each agent's worst runs)
//! and each metric's exact count, mean, smallest and largest value, and at most [`SAMPLE`] of
//! its runs, evenly spread in run order, for the quartiles, box plots, CDFs and curves.
//!
//! A configuration of at most [`SAMPLE`] runs keeps them all, so its figures and report are
//! those of every run. A larger one keeps every `2^j`-th of its runs (the smallest `j` that
//! leaves at most [`SAMPLE`]): between half of [`SAMPLE`] and [`SAMPLE`] runs, chosen by their
//! position alone, so the same folder always gives the same figures.

use std::collections::HashMap;
use std::path::Path;

use super::summary::{GroupSummary, summarize};
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
    /// Every `stride`-th run of the configuration, in run order.
    kept: Vec<RunRecord>,
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
            kept: vec![],
            stride: 1,
        }
    }

    fn push(&mut self, r: &RunRecord) {
        if self.runs.is_multiple_of(self.stride) {
            if self.kept.len() == self.kept.capacity() {
                // double, but never past the most the configuration holds
                let more = self.kept.len().clamp(1, SAMPLE + 1 - self.kept.len());
                self.kept.reserve_exact(more);
            }
            self.kept.push(r.clone());
            if self.kept.len() > SAMPLE {
                // every other kept run: the runs whose position is a multiple of twice the stride
                let mut i = 0;
                self.kept.retain(|_| {
                    i += 1;
                    i % 2 == 1
                });
                self.stride *= 2;
            }
        }
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

/// The runs of a results folder, gathered one at a time ([`Sample::push`]).
#[derive(Debug, Default)]
pub struct Sample {
    configs: Vec<Config>,
    index: HashMap<String, usize>,
    /// Runs pushed.
    pub runs: usize,
    /// Crashed runs.
    pub crashed: usize,
    /// Runs with a replay page in the folder.
    pub replays: usize,
}

impl Sample {
    /// Counts run `r` of results folder `dir` and keeps it if its configuration keeps it.
    pub fn push(&mut self, dir: &Path, r: &RunRecord) {
        let k = key(r);
        let i = match self.index.get(&k) {
            Some(i) => *i,
            None => {
                self.configs.push(Config::new());
                self.index.insert(k, self.configs.len() - 1);
                self.configs.len() - 1
            }
        };
        self.configs[i].push(r);
        self.runs += 1;
        self.crashed += usize::from(r.status == Status::Crash);
        self.replays += crate::replay::files::with_replay(dir, std::slice::from_ref(r));
    }

    /// The summary of every configuration, in run order of first appearance: the kept runs'
    /// quartiles with the exact counts, means and extremes.
    pub fn summaries(&self) -> Vec<GroupSummary> {
        self.configs
            .iter()
            .map(|c| c.exact(summarize(&c.kept.iter().collect::<Vec<_>>())))
            .collect()
    }

    /// Consumes the sample into its kept runs, in run order.
    pub fn into_runs(self) -> Vec<RunRecord> {
        let mut all = Vec::with_capacity(self.configs.iter().map(|c| c.kept.len()).sum());
        for c in self.configs {
            all.extend(c.kept);
        }
        // run indices are unique: an unstable sort gives the same order, without a buffer
        all.sort_unstable_by_key(|r| r.run);
        all
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

    #[test]
    fn a_configuration_keeps_every_run_up_to_the_sample_and_every_2j_th_beyond() {
        let dir = Path::new("/nonexistent");
        let mut s = Sample::default();
        let big = 3 * SAMPLE + 5;
        // the two configurations' runs interleaved, as a sweep writes them
        let mut next = 0;
        for i in 0..big {
            if i < SAMPLE {
                s.push(dir, &run(next, "a", true, 0.0));
                next += 1;
            }
            s.push(dir, &run(next, "b", true, i as f64));
            next += 1;
        }
        assert_eq!(s.runs, SAMPLE + big);
        // no configuration's buffer outgrows the sample
        assert!(s.configs.iter().all(|c| c.kept.capacity() <= SAMPLE + 1));
        let kept = s.into_runs();
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
    }

    #[test]
    fn a_summary_counts_every_run_and_takes_its_quartiles_from_the_kept_ones() {
        let dir = Path::new("/nonexistent");
        let mut s = Sample::default();
        let n = 2 * SAMPLE + 1;
        for i in 0..n {
            s.push(dir, &run(i, "a", i % 3 == 0, i as f64));
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
