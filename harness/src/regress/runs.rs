//! One folder's runs as `regress` compares them: per configuration, each run's seed, whether it
//! succeeded and each compared metric's value, in columns. The rows of `runs.csv` stream
//! through and are not kept (a row held whole costs about 1.3 kB); a run costs 9 bytes and 8 a
//! compared value, and 8 more while the folder is read (its index, to put it in run order).
//!
//! A configuration keeps at most [`SEEDS`] runs, so that memory does not grow with the folder:
//! beyond, the runs of the seeds whose hash ([`seed_hash`]) ends in `j` zero bits, for the
//! smallest `j` that leaves at most [`SEEDS`]. A seed's hash is the same in every folder, so two
//! folders of the same seeds keep the same seeds and stay paired ([`Config::thinned`] brings
//! the side that kept more down to the other's `j`).

use std::collections::HashMap;
use std::path::Path;

use crate::Error;
use crate::metrics::Metric;
use crate::results::store::{RUNS, Snapshot};
use crate::run::RunRecord;

/// A configuration: scenario, planner, tracker and preset.
pub type Key = (String, String, String, String);

/// The most runs a configuration keeps: at 10,000 pairs the interval of a median change is
/// about ±1.6% wide at 90% for values whose log ratio has a standard deviation of 1 (1.645 ×
/// 1/√10,000), far inside the 10% tolerance, so a larger folder would change few verdicts.
pub const SEEDS: usize = 10_000;

/// A seed's hash: SplitMix64's finalizer, a bijection of the 64-bit integers whose low bits
/// are evenly spread for consecutive seeds.
pub fn seed_hash(seed: u64) -> u64 {
    let mut z = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Keeps the items of `v` whose place in `keep` is true.
fn retain_by<T>(v: &mut Vec<T>, keep: &[bool]) {
    let mut k = keep.iter();
    v.retain(|_| k.next().copied().unwrap_or(false));
}

/// Whether a configuration that keeps the seeds of level `level` keeps `seed`.
fn kept(seed: u64, level: u32) -> bool {
    seed_hash(seed).trailing_zeros() >= level
}

/// One configuration's runs, in run order, in columns.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Scenario, planner, tracker and preset.
    pub key: Key,
    /// Each run's seed.
    pub seeds: Vec<u64>,
    /// Whether each run succeeded ([`RunRecord::success`]).
    pub success: Vec<bool>,
    /// Each compared column's value in each run (NaN: none): the metrics of
    /// [`Runs::metrics`], then each agent's RMS path error, observed and true.
    columns: Vec<Vec<f64>>,
    /// Each run's index while the folder is read (emptied once the runs are in run order).
    runs: Vec<usize>,
    /// The runs of the configuration in the folder, kept or not.
    pub all: usize,
    /// The smallest run index of the configuration, kept or not.
    first: usize,
    /// The seeds kept: those whose hash ends in `level` zero bits (0: every seed).
    pub level: u32,
}

impl Config {
    fn new(key: Key) -> Self {
        Config {
            key,
            seeds: vec![],
            success: vec![],
            columns: vec![],
            runs: vec![],
            all: 0,
            first: usize::MAX,
            level: 0,
        }
    }

    /// Adds run `r`: its values of `metrics` and of its agents, if its seed is kept.
    fn push(&mut self, r: &RunRecord, metrics: &[Metric]) {
        self.all += 1;
        self.first = self.first.min(r.run);
        if !kept(r.seed, self.level) {
            return;
        }
        self.append(r, metrics);
        while self.len() > SEEDS {
            self.level += 1;
            self.keep_level();
        }
    }

    /// Drops the runs whose seeds the level does not keep.
    fn keep_level(&mut self) {
        let keep: Vec<bool> = self.seeds.iter().map(|&s| kept(s, self.level)).collect();
        retain_by(&mut self.seeds, &keep);
        retain_by(&mut self.success, &keep);
        if !self.runs.is_empty() {
            retain_by(&mut self.runs, &keep);
        }
        for col in &mut self.columns {
            retain_by(col, &keep);
        }
    }

    /// This configuration with only the seeds of level `level` (itself if it keeps no more).
    pub fn thinned(&self, level: u32) -> std::borrow::Cow<'_, Config> {
        if level <= self.level {
            return std::borrow::Cow::Borrowed(self);
        }
        let mut c = self.clone();
        c.level = level;
        c.keep_level();
        std::borrow::Cow::Owned(c)
    }

    /// Whether some of its runs are left out.
    pub fn sampled(&self) -> bool {
        self.len() < self.all
    }

    /// Appends run `r`'s values of `metrics` and of its agents.
    fn append(&mut self, r: &RunRecord, metrics: &[Metric]) {
        let row = self.seeds.len();
        self.seeds.push(r.seed);
        self.success.push(r.success());
        self.runs.push(r.run);
        while self.columns.len() < metrics.len() + 2 * r.per_agent.len() {
            self.columns.push(vec![f64::NAN; row]);
        }
        for (k, col) in self.columns.iter_mut().enumerate() {
            let v = match k.checked_sub(metrics.len()) {
                None => r.get(metrics[k]),
                Some(a) => r.per_agent.get(a / 2).and_then(|e| match a % 2 {
                    0 => e.rms_bl,
                    _ => e.rms_true_bl,
                }),
            };
            col.push(v.unwrap_or(f64::NAN));
        }
    }

    /// Puts the runs in run order and drops the run indices.
    fn finish(&mut self) {
        if !self.runs.is_sorted() {
            let mut order: Vec<usize> = (0..self.runs.len()).collect();
            order.sort_by_key(|&i| self.runs[i]);
            self.seeds = order.iter().map(|&i| self.seeds[i]).collect();
            self.success = order.iter().map(|&i| self.success[i]).collect();
            for col in &mut self.columns {
                *col = order.iter().map(|&i| col[i]).collect();
            }
        }
        self.runs = vec![];
        self.seeds.shrink_to_fit();
        self.success.shrink_to_fit();
        self.columns.iter_mut().for_each(Vec::shrink_to_fit);
    }

    /// Runs.
    pub fn len(&self) -> usize {
        self.seeds.len()
    }

    /// True without runs.
    pub fn is_empty(&self) -> bool {
        self.seeds.is_empty()
    }

    /// Agents with per-agent columns, of a folder that compares `metrics` metrics.
    pub fn agents(&self, metrics: usize) -> usize {
        self.columns.len().saturating_sub(metrics) / 2
    }

    /// Column `k`'s value in run `i` (None: the run has none, or the column is absent).
    pub fn value(&self, k: usize, i: usize) -> Option<f64> {
        self.columns.get(k).map(|c| c[i]).filter(|v| !v.is_nan())
    }

    /// `scenario / planner`, or `scenario / planner / tracker (preset)` for tracked runs.
    pub fn label(&self) -> String {
        let (scenario, planner, tracker, preset) = &self.key;
        let mut s = format!("{scenario} / {planner}");
        if !tracker.is_empty() {
            s += &format!(" / {tracker} ({preset})");
        }
        s
    }
}

/// A folder's configurations, in the order of their first runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Runs {
    /// The table's metrics that are compared, in table order (the first columns).
    pub metrics: Vec<Metric>,
    /// The configurations.
    pub configs: Vec<Config>,
    index: HashMap<Key, usize>,
}

impl Runs {
    fn new() -> Self {
        Runs {
            metrics: super::analysis::table_metrics(),
            configs: vec![],
            index: HashMap::new(),
        }
    }

    /// Adds run `r`.
    fn push(&mut self, r: &RunRecord) {
        let key = (
            r.scenario.clone(),
            r.planner.clone(),
            r.tracker.clone(),
            r.preset.clone(),
        );
        let c = match self.index.get(&key) {
            Some(&c) => c,
            None => {
                self.configs.push(Config::new(key.clone()));
                self.index.insert(key, self.configs.len() - 1);
                self.configs.len() - 1
            }
        };
        self.configs[c].push(r, &self.metrics);
    }

    /// Orders the configurations by their first runs and each one's runs by index.
    fn finish(mut self) -> Self {
        self.configs.sort_by_key(|c| c.first);
        self.configs.iter_mut().for_each(Config::finish);
        self.index = self
            .configs
            .iter()
            .enumerate()
            .map(|(i, c)| (c.key.clone(), i))
            .collect();
        self
    }

    /// The runs `runs`.
    pub fn of<'a>(runs: impl IntoIterator<Item = &'a RunRecord>) -> Runs {
        let mut out = Runs::new();
        for r in runs {
            out.push(r);
        }
        out.finish()
    }

    /// The complete rows of `dir`'s `runs.csv`, read one at a time.
    pub fn read(dir: &Path) -> Result<Runs, Error> {
        let mut out = Runs::new();
        if let Some(s) = Snapshot::open(&dir.join(RUNS))? {
            for r in s.runs()? {
                out.push(&r?);
            }
        }
        Ok(out.finish())
    }

    /// The configuration `key`, if the folder has it.
    pub fn get(&self, key: &Key) -> Option<&Config> {
        self.index.get(key).map(|&i| &self.configs[i])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(index: usize, planner: &str, seed: u64, agents: usize) -> RunRecord {
        let mut r = RunRecord::example();
        r.run = index;
        r.planner = planner.into();
        r.seed = seed;
        r.per_agent = (0..agents)
            .map(|a| crate::run::record::AgentErrors {
                rms_bl: Some(a as f64 + seed as f64),
                ..Default::default()
            })
            .collect();
        r
    }

    /// Runs out of order come out grouped by configuration in the order of their first runs,
    /// each configuration's runs in run order, and a run with more agents than the earlier ones
    /// adds columns that the earlier runs lack.
    #[test]
    fn runs_are_grouped_in_run_order() {
        let rs = [
            run(3, "b", 30, 1),
            run(1, "a", 10, 1),
            run(2, "b", 20, 2),
            run(0, "a", 0, 1),
        ];
        let r = Runs::of(&rs);
        let planners: Vec<&str> = r.configs.iter().map(|c| c.key.1.as_str()).collect();
        assert_eq!(planners, ["a", "b"]);
        assert_eq!(r.configs[0].seeds, [0, 10]);
        let b = &r.configs[1];
        assert_eq!(b.seeds, [20, 30]);
        let m = r.metrics.len();
        assert_eq!(b.agents(m), 2);
        assert_eq!(b.value(m, 0), Some(20.0));
        assert_eq!(b.value(m, 1), Some(30.0));
        assert_eq!(b.value(m + 2, 0), Some(21.0));
        assert_eq!(b.value(m + 2, 1), None);
        assert_eq!(r.configs[0].value(m + 2, 0), None);
        assert!(r.get(&b.key).is_some_and(|c| c.seeds == [20, 30]));
    }
}
