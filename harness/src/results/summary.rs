//! Per-configuration summaries of runs: one row per (scenario, planner, tracker, preset).

use crate::metrics::Metric;
use crate::run::{RunRecord, Status};
use crate::stats::{Summary, wilson};

/// The summary of one configuration's runs.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupSummary {
    /// Scenario.
    pub scenario: String,
    /// Planner variant.
    pub planner: String,
    /// Tracker variant (empty: planning only).
    pub tracker: String,
    /// Preset (empty: planning only).
    pub preset: String,
    /// Runs.
    pub n: usize,
    /// Crashed runs.
    pub crashed: usize,
    /// Runs with an exact plan.
    pub solved: usize,
    /// Runs that succeeded: solved (planning only) or reached the goal without agent contact.
    pub succeeded: usize,
    /// 95% Wilson interval of the success rate.
    pub success_ci: (f64, f64),
    /// Each metric's summary over the runs that have it, indexed by [`Metric`] (see
    /// [`GroupSummary::metric`]).
    pub metrics: Vec<Option<Summary>>,
    /// Each agent's errors, for the largest team of the configuration's tracked runs.
    pub per_agent: Vec<AgentSummary>,
    /// Runs with agent contact.
    pub agent_contacts: usize,
}

/// One agent's errors over a configuration's tracked runs.
#[derive(Debug, Clone, PartialEq)]
pub struct AgentSummary {
    /// RMS path error of its observed positions (BL).
    pub rms_error: Option<Summary>,
    /// Largest path error of its observed positions (BL).
    pub max_error: Option<Summary>,
    /// RMS path error of its true positions (BL).
    pub rms_error_true: Option<Summary>,
    /// Runs in which it was the worst agent.
    pub worst: usize,
}

impl GroupSummary {
    /// `planner`, or `planner + tracker (preset)` for tracked runs.
    pub fn config_label(&self) -> String {
        if self.tracker.is_empty() {
            self.planner.clone()
        } else {
            format!("{} + {} ({})", self.planner, self.tracker, self.preset)
        }
    }

    /// The summary of metric `m` over the configuration's runs that have it.
    pub fn metric(&self, m: Metric) -> Option<&Summary> {
        self.metrics[m as usize].as_ref()
    }

    /// True if the configuration tracks.
    pub fn tracked(&self) -> bool {
        !self.tracker.is_empty()
    }
}

/// The key of a run's configuration.
pub fn key(r: &RunRecord) -> (String, String, String, String) {
    (
        r.scenario.clone(),
        r.planner.clone(),
        r.tracker.clone(),
        r.preset.clone(),
    )
}

/// Groups runs by configuration, in run order of first appearance.
pub fn groups(runs: &[RunRecord]) -> Vec<Vec<&RunRecord>> {
    let mut sorted: Vec<&RunRecord> = runs.iter().collect();
    sorted.sort_by_key(|r| r.run);
    group_by(sorted, |r| key(r))
}

/// `items` grouped by `key`, the groups in order of their key's first appearance and each
/// group's items in their order.
pub fn group_by<T, K: PartialEq>(
    items: impl IntoIterator<Item = T>,
    key: impl Fn(&T) -> K,
) -> Vec<Vec<T>> {
    let mut keys: Vec<K> = vec![];
    let mut out: Vec<Vec<T>> = vec![];
    for item in items {
        let k = key(&item);
        match keys.iter().position(|x| *x == k) {
            Some(i) => out[i].push(item),
            None => {
                keys.push(k);
                out.push(vec![item]);
            }
        }
    }
    out
}

fn summary_of(v: impl Iterator<Item = f64>) -> Option<Summary> {
    Summary::of(&v.collect::<Vec<_>>())
}

/// Summarises one configuration's runs (non-empty).
pub fn summarize(g: &[&RunRecord]) -> GroupSummary {
    let r0 = g[0];
    let n = g.len();
    let succeeded = g.iter().filter(|r| r.success()).count();
    GroupSummary {
        scenario: r0.scenario.clone(),
        planner: r0.planner.clone(),
        tracker: r0.tracker.clone(),
        preset: r0.preset.clone(),
        n,
        crashed: g.iter().filter(|r| r.status == Status::Crash).count(),
        solved: g.iter().filter(|r| r.solved).count(),
        succeeded,
        success_ci: wilson(succeeded as u64, n as u64, 0.95),
        metrics: Metric::ALL
            .iter()
            .map(|m| summary_of(g.iter().filter_map(|r| r.get(*m))))
            .collect(),
        per_agent: agent_summaries(g),
        agent_contacts: g.iter().filter(|r| r.agent_contact == Some(true)).count(),
    }
}

/// Each agent's summary over `g` (as many as the largest team with per-agent errors).
fn agent_summaries(g: &[&RunRecord]) -> Vec<AgentSummary> {
    let n = g.iter().map(|r| r.per_agent.len()).max().unwrap_or(0);
    (0..n)
        .map(|i| {
            let of = |f: fn(&crate::run::record::AgentErrors) -> Option<f64>| {
                summary_of(g.iter().filter_map(|r| r.per_agent.get(i).and_then(f)))
            };
            AgentSummary {
                rms_error: of(|a| a.rms_bl),
                max_error: of(|a| a.max_bl),
                rms_error_true: of(|a| a.rms_true_bl),
                worst: g.iter().filter(|r| r.worst_agent == Some(i as u64)).count(),
            }
        })
        .collect()
}

/// Summaries of every configuration.
pub fn summaries(runs: &[RunRecord]) -> Vec<GroupSummary> {
    groups(runs).iter().map(|g| summarize(g)).collect()
}
