//! Which runs of a sweep get a replay page: the policy of `bench --replays` and of the
//! experiment file's `replays` key (docs/replay.md, "Which runs get a replay").
//!
//! - `all`: every run; `none`: no run;
//! - `failed`: every run that failed ([`failed`]);
//! - `sample:N`: N runs chosen from the run matrix by [`sample`], whatever their outcome;
//! - `failed+sample:N`: both ([`DEFAULT`]).
//!
//! The choice of a run depends only on its id, its outcome and the experiment's run matrix: not
//! on the order in which runs finish, the number of threads, the shard or an interruption, so a
//! resumed sweep or the merge of shards has the pages one sweep would have written.

use std::collections::{BTreeMap, BTreeSet, BinaryHeap};
use std::fmt;
use std::str::FromStr;

use crate::experiment::MAX_RUNS;
use crate::run::fake::seed_of;
use crate::run::{RunRecord, Status};

/// The policy when neither `--replays` nor the experiment file names one: the failed runs,
/// which are what one opens a replay for, and a sample of 30 for a look at every configuration
/// that works (one run each of up to 30 configurations), whatever the run count.
pub const DEFAULT: &str = "failed+sample:30";

/// Which runs of a sweep get a replay page.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReplayPolicy {
    /// Every run.
    pub all: bool,
    /// Every failed run ([`failed`]).
    pub failed: bool,
    /// This many runs chosen by [`sample`] (0: none).
    pub sample: usize,
}

impl Default for ReplayPolicy {
    fn default() -> Self {
        DEFAULT.parse().expect("the default policy parses")
    }
}

impl ReplayPolicy {
    /// No replays.
    pub const NONE: ReplayPolicy = ReplayPolicy {
        all: false,
        failed: false,
        sample: 0,
    };

    /// True if the policy writes no page whatever the runs.
    pub fn is_none(&self) -> bool {
        *self == ReplayPolicy::NONE
    }

    /// The runs of `matrix` (an experiment's whole run matrix) this policy samples, by run
    /// index.
    pub fn sampled(&self, matrix: impl IntoIterator<Item = (usize, String)>) -> BTreeSet<usize> {
        if self.all || self.sample == 0 {
            return BTreeSet::new();
        }
        sample(matrix, self.sample)
    }

    /// True if the run of `record`, of index `record.run`, gets a page; `sampled` is
    /// [`ReplayPolicy::sampled`] of the experiment's run matrix.
    pub fn keeps(&self, sampled: &BTreeSet<usize>, record: &RunRecord) -> bool {
        self.all || (self.failed && failed(record)) || sampled.contains(&record.run)
    }
}

/// True if a run failed: it crashed, or it was tracked and did not reach the goal, or it was
/// a planning run without an exact plan (a crashed run has no replay to write).
pub fn failed(r: &RunRecord) -> bool {
    r.status == Status::Crash || r.reached_goal.map_or(!r.solved, |reached| !reached)
}

/// `n` runs of `matrix` chosen by hashing: each run's rank is the place of the SHA-256 of its
/// id (`scenario|planner|tracker|preset|seed`) among the runs of its configuration; the runs
/// are taken by rank, and within a rank by their hash. So the sample spreads over the
/// configurations (one run of each before a second of any), and it depends only on the ids.
/// A run of rank `n` or more follows at least `n` runs of its own configuration, so only each
/// configuration's `n` first are held.
pub fn sample(matrix: impl IntoIterator<Item = (usize, String)>, n: usize) -> BTreeSet<usize> {
    let mut configs: BTreeMap<String, BinaryHeap<(u64, usize)>> = BTreeMap::new();
    for (index, id) in matrix {
        let config = id.rsplit_once('|').map_or(id.as_str(), |(c, _)| c);
        let firsts = match configs.get_mut(config) {
            Some(e) => e,
            None => configs.entry(config.to_string()).or_default(),
        };
        firsts.push((seed_of(&id), index));
        if firsts.len() > n {
            firsts.pop();
        }
    }
    let mut ranked: Vec<(usize, u64, usize)> = vec![];
    for firsts in configs.into_values() {
        let runs = firsts.into_sorted_vec();
        ranked.extend(runs.iter().enumerate().map(|(k, &(h, i))| (k, h, i)));
    }
    ranked.sort_unstable();
    ranked.into_iter().take(n).map(|(_, _, i)| i).collect()
}

impl fmt::Display for ReplayPolicy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.all {
            return f.write_str("all");
        }
        match (self.failed, self.sample) {
            (false, 0) => f.write_str("none"),
            (true, 0) => f.write_str("failed"),
            (false, n) => write!(f, "sample:{n}"),
            (true, n) => write!(f, "failed+sample:{n}"),
        }
    }
}

/// What `--replays` and `replays` accept, for refusals.
pub const SYNTAX: &str = "all, failed, sample:N, failed+sample:N or none";

impl FromStr for ReplayPolicy {
    type Err = String;

    /// Parses a policy; the error is the reason (the caller names the option or the field).
    fn from_str(s: &str) -> Result<Self, String> {
        let refuse = |why: String| format!("{s:?}: {why} (expected {SYNTAX})");
        let mut p = ReplayPolicy::NONE;
        let parts: Vec<&str> = s.split('+').map(str::trim).collect();
        for part in &parts {
            match *part {
                "all" | "none" if parts.len() > 1 => {
                    return Err(refuse(format!("{part} cannot be combined")));
                }
                "all" => p.all = true,
                "none" => {}
                "failed" if p.failed => return Err(refuse("failed is given twice".into())),
                "failed" => p.failed = true,
                _ => {
                    let Some(n) = part.strip_prefix("sample:") else {
                        return Err(refuse(format!("unknown policy {part:?}")));
                    };
                    if p.sample > 0 {
                        return Err(refuse("sample is given twice".into()));
                    }
                    let n: usize = n.trim().parse().map_err(|_| {
                        refuse(format!(
                            "N of sample:N must be a whole number, got {:?}",
                            n.trim()
                        ))
                    })?;
                    if n == 0 {
                        return Err(refuse(
                            "sample:0 samples no run; write none for no replays".into(),
                        ));
                    }
                    if n > MAX_RUNS {
                        return Err(refuse(format!(
                            "N of sample:N is at most {MAX_RUNS}, the most runs an experiment has"
                        )));
                    }
                    p.sample = n;
                }
            }
        }
        Ok(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn policies_parse_and_print_back() {
        for s in [
            "all",
            "none",
            "failed",
            "sample:7",
            "failed+sample:30",
            DEFAULT,
        ] {
            assert_eq!(s.parse::<ReplayPolicy>().unwrap().to_string(), s);
        }
        assert_eq!(
            "sample:3+failed"
                .parse::<ReplayPolicy>()
                .unwrap()
                .to_string(),
            "failed+sample:3"
        );
        assert!("none".parse::<ReplayPolicy>().unwrap().is_none());
    }

    #[test]
    fn bad_policies_say_why() {
        for (s, why) in [
            ("sample:x", "whole number"),
            ("sample:", "whole number"),
            ("sample:-1", "whole number"),
            ("sample:0", "write none"),
            ("sample:1000001", "at most 1000000"),
            ("bogus", "unknown policy \"bogus\""),
            ("", "unknown policy"),
            ("all+failed", "all cannot be combined"),
            ("failed+failed", "twice"),
            ("sample:1+sample:2", "twice"),
        ] {
            let err = s.parse::<ReplayPolicy>().unwrap_err();
            assert!(err.contains(why), "{s:?}: {err}");
            assert!(err.contains(SYNTAX), "{s:?}: {err}");
        }
    }
}

#[cfg(test)]
mod sample_tests {
    use super::*;

    /// The runs of `matrix` ranked as [`sample`] documents, every run held: the `n` first.
    fn every_run_ranked(matrix: &[(usize, String)], n: usize) -> BTreeSet<usize> {
        let mut configs: BTreeMap<&str, Vec<(u64, usize)>> = BTreeMap::new();
        for (index, id) in matrix {
            let config = id.rsplit_once('|').unwrap().0;
            configs
                .entry(config)
                .or_default()
                .push((seed_of(id), *index));
        }
        let mut ranked = vec![];
        for runs in configs.values_mut() {
            runs.sort();
            ranked.extend(runs.iter().enumerate().map(|(k, &(h, i))| (k, h, i)));
        }
        ranked.sort();
        ranked.into_iter().take(n).map(|(_, _, i)| i).collect()
    }

    /// Holding each configuration's `n` first runs draws the sample of holding them all.
    #[test]
    fn the_sample_is_that_of_every_run_ranked() {
        // configurations of 1 to 40 runs
        let matrix: Vec<(usize, String)> = (0..6)
            .flat_map(|c| (0..[1, 3, 40, 7, 12, 2][c]).map(move |s| format!("c{c}|p|-|-|{s}")))
            .enumerate()
            .collect();
        for n in [0, 1, 5, 6, 7, 13, 30, 64, 65, 100] {
            let got = sample(matrix.iter().cloned(), n);
            assert_eq!(got, every_run_ranked(&matrix, n), "n = {n}");
            assert_eq!(got.len(), n.min(matrix.len()));
        }
    }
}
