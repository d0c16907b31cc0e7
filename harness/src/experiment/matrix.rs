//! An experiment's run matrix, run by run: a run made from its index when it is needed, and the
//! index of a run found from its id, so that no list of all the runs is ever held.

use std::collections::HashMap;

use super::Experiment;
use crate::run::RunSpec;

/// One configuration of the matrix: a scenario, a planner and, for a tracked run, a tracker and
/// a preset (positions in the experiment's lists).
#[derive(Debug, Clone)]
struct Config {
    scenario: usize,
    planner: usize,
    tracked: Option<(usize, usize)>,
    /// `scenario|planner|tracker|preset`, as [`crate::run::spec::config_id`].
    id: String,
}

/// Shard `k` of `n` as the index of its first run and the step between its runs: the runs whose
/// index is `k − 1` modulo `n` (every run for `None`).
fn stride(shard: Option<(usize, usize)>) -> (usize, usize) {
    shard.map_or((0, 1), |(k, n)| (k - 1, n))
}

/// The run matrix of an experiment: its configurations in order (scenario, planner, tracker,
/// preset; a planner's planning runs before its tracked runs), each with every seed. Run `i` is
/// seed `i mod seeds` of configuration `i div seeds`.
#[derive(Debug, Clone)]
pub struct Matrix<'a> {
    e: &'a Experiment,
    configs: Vec<Config>,
    /// A configuration's id → its position.
    by_id: HashMap<String, usize>,
    /// A seed → its position in the experiment's seeds (each seed is listed once).
    seed_at: HashMap<u64, usize>,
}

impl<'a> Matrix<'a> {
    /// The run matrix of `e`.
    pub fn of(e: &'a Experiment) -> Matrix<'a> {
        let mut configs = vec![];
        for (s, (label, _)) in e.scenarios.iter().enumerate() {
            for (p, planner) in e.planners.iter().enumerate() {
                let mut tracked = vec![];
                if e.tracking.has_planning_runs() {
                    tracked.push(None);
                }
                if e.tracking.tracks(planner) {
                    for t in 0..e.trackers.len() {
                        tracked.extend((0..e.presets.len()).map(|pr| Some((t, pr))));
                    }
                }
                for tracked in tracked {
                    let id = crate::run::spec::config_id(
                        label,
                        planner,
                        tracked.map(|(t, _)| &e.trackers[t]),
                        tracked.map(|(_, pr)| e.presets[pr].0.as_str()),
                    );
                    configs.push(Config {
                        scenario: s,
                        planner: p,
                        tracked,
                        id,
                    });
                }
            }
        }
        let by_id = configs
            .iter()
            .enumerate()
            .map(|(i, c)| (c.id.clone(), i))
            .collect();
        let seed_at = e.seeds.iter().enumerate().map(|(i, &s)| (s, i)).collect();
        Matrix {
            e,
            configs,
            by_id,
            seed_at,
        }
    }

    /// The number of runs.
    pub fn len(&self) -> usize {
        self.configs.len() * self.e.seeds.len()
    }

    /// Whether the matrix has no run.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The seed of run `index`.
    pub fn seed(&self, index: usize) -> u64 {
        self.e.seeds[index % self.e.seeds.len()]
    }

    /// The id of run `index` (`scenario|planner|tracker|preset|seed`, as [`RunSpec::id`]).
    pub fn id(&self, index: usize) -> String {
        let config = &self.configs[index / self.e.seeds.len()];
        format!("{}|{}", config.id, self.seed(index))
    }

    /// Run `index` (below [`Matrix::len`]).
    pub fn spec(&self, index: usize) -> RunSpec {
        let e = self.e;
        let c = &self.configs[index / e.seeds.len()];
        let (label, scenario) = &e.scenarios[c.scenario];
        let preset = c.tracked.map(|(_, pr)| &e.presets[pr]);
        RunSpec {
            index,
            experiment: e.name.clone(),
            scenario_label: label.clone(),
            scenario: scenario.clone(),
            planner: e.planners[c.planner].clone(),
            tracker: c.tracked.map(|(t, _)| e.trackers[t].clone()),
            preset: preset.map(|(label, _)| label.clone()),
            plant: preset.map(|(_, p)| p.clone()),
            seed: self.seed(index),
            limits: e.limits,
        }
    }

    /// The index of the run with id `id`, or `None` if it is not a run of the matrix.
    pub fn index_of(&self, id: &str) -> Option<usize> {
        let (config, seed) = id.rsplit_once('|')?;
        let c = self.by_id.get(config)?;
        let s = self.seed_at.get(&seed.parse().ok()?)?;
        Some(c * self.e.seeds.len() + s)
    }

    /// The indices of shard `k` of `n` (`Some((k, n))`, 1-based: the runs whose index is
    /// `k − 1` modulo `n`), or of every run, in order.
    pub fn indices(
        &self,
        shard: Option<(usize, usize)>,
    ) -> std::iter::StepBy<std::ops::Range<usize>> {
        let (first, step) = stride(shard);
        (first..self.len()).step_by(step)
    }

    /// The index of the `j`-th run (from 0) of `shard`, in the order of [`Matrix::indices`].
    pub fn nth_of(shard: Option<(usize, usize)>, j: usize) -> usize {
        let (first, step) = stride(shard);
        first + j * step
    }

    /// Whether run `index` is a run of `shard` (every run is when `shard` is `None`).
    pub fn in_shard(index: usize, shard: Option<(usize, usize)>) -> bool {
        let (first, step) = stride(shard);
        index % step == first
    }

    /// The first run of every configuration that has a run among `indices`, in order: one run
    /// for what depends on a run's configuration and not on its seed.
    pub fn firsts(&self, indices: impl Iterator<Item = usize>) -> Vec<RunSpec> {
        let per = self.e.seeds.len();
        let mut seen = vec![false; self.configs.len()];
        for i in indices {
            seen[i / per] = true;
        }
        (0..self.configs.len())
            .filter(|&c| seen[c])
            .map(|c| self.spec(c * per))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shards_runs_listed_counted_and_recognised_by_one_rule() {
        for n in [1usize, 2, 3, 7] {
            let mut seen = [0; 20];
            for k in 1..=n {
                let shard = Some((k, n));
                let listed: Vec<usize> = (k - 1..20).step_by(n).collect();
                let nth: Vec<usize> = (0..listed.len())
                    .map(|j| Matrix::nth_of(shard, j))
                    .collect();
                assert_eq!(nth, listed, "shard {k} of {n}");
                for i in 0..20 {
                    assert_eq!(Matrix::in_shard(i, shard), listed.contains(&i));
                }
                for &i in &listed {
                    seen[i] += 1;
                }
            }
            assert!(
                seen.iter().all(|&c| c == 1),
                "every run in one shard of {n}"
            );
        }
        assert!((0..20).all(|i| Matrix::in_shard(i, None) && Matrix::nth_of(None, i) == i));
    }
}
