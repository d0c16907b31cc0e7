//! The tidy result row of one run and its progress trace.

use serde::{Deserialize, Serialize};

use magbench_analysis::metrics::difficulty::{Measure, Measures};
use magbench_analysis::metrics::{Metric, Values};

/// How a run ended, named after OMPL's `PlannerStatus`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// The planner found a plan that ends in the goal region.
    Exact,
    /// The planner stopped with a plan that ends near the goal.
    Approximate,
    /// The planner stopped without a plan.
    Timeout,
    /// The run panicked or returned an error (see the `error` column).
    Crash,
    /// The problem was rejected (an invalid start or goal).
    InvalidStart,
}

impl Status {
    /// The value of OMPL's `ompl::base::PlannerStatus::StatusType` enum.
    pub fn ompl_code(self) -> u32 {
        match self {
            Status::InvalidStart => 1,
            Status::Timeout => 4,
            Status::Approximate => 5,
            Status::Exact => 6,
            Status::Crash => 7,
        }
    }

    /// The CSV spelling.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Exact => "exact",
            Status::Approximate => "approximate",
            Status::Timeout => "timeout",
            Status::Crash => "crash",
            Status::InvalidStart => "invalid-start",
        }
    }
}

/// One row of `runs.csv`: every input column, how the run ended, and every metric of the table
/// ([`magbench_analysis::metrics`]). Tracker columns are empty for runs without a tracker; a metric is empty
/// when the run has none (e.g. `cost` of an unsolved run).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// Position in the experiment's run matrix.
    pub run: usize,
    /// `scenario|planner|tracker|preset|seed`.
    pub run_id: String,
    /// Experiment name.
    pub experiment: String,
    /// Scenario (built-in name or path, as in the experiment file).
    pub scenario: String,
    /// Number of agents.
    pub agents: usize,
    /// Planner variant label, e.g. `goal-zoom-rrt{k=5}`.
    pub planner: String,
    /// Planner registry name.
    pub planner_name: String,
    /// Planner parameter overrides, `a=1,b=2`.
    pub planner_params: String,
    /// Tracker variant label (empty: planning only).
    pub tracker: String,
    /// Disturbance preset (empty: planning only).
    pub preset: String,
    /// Seed.
    pub seed: u64,
    /// Iteration limit.
    pub max_iterations: Option<u64>,
    /// Planning time limit (s).
    pub time_limit_s: Option<f64>,

    /// How the planner ended.
    pub status: Status,
    /// Exact solution found.
    pub solved: bool,
    /// Approximate solution only.
    pub approximate: bool,
    /// Points of this run's trace in `progress.csv`, set when the row is written: a resume and
    /// `results verify` check the trace against it (empty in files of older versions).
    #[serde(default)]
    pub progress_rows: Option<u64>,

    /// How tracking ended (`reached-goal`, `timeout`, `agent-contact`, ...; empty: no tracking).
    pub track_status: String,
    /// The tracked run reached the goal.
    pub reached_goal: Option<bool>,
    /// The worst agent (0-based): the largest RMS path error of its observed positions.
    pub worst_agent: Option<u64>,
    /// Agents touched (they stick: a failure).
    pub agent_contact: Option<bool>,

    /// Error message of a crashed run; for a run whose planner stopped unsolved and said why
    /// ([`magbench_planners::Planner::stop_reason`]), that reason.
    pub error: String,

    /// Every metric of the table ([`magbench_analysis::metrics`]). Not a serde field: `runs.csv` writes
    /// one column per table entry after `error` (see `results::store`).
    #[serde(skip)]
    pub metrics: Values,

    /// The difficulty measures of the run's scenario ([`magbench_analysis::metrics::difficulty`]). Not a
    /// serde field: `runs.csv` writes one column per measure after the metric columns.
    #[serde(skip)]
    pub difficulty: Measures,

    /// Each agent's path error of a tracked run (empty otherwise). Not a serde field: `runs.csv`
    /// writes it after the metric columns as [`agent_columns`] for as many agents as the experiment's
    /// largest team (see `results::store`).
    #[serde(skip)]
    pub per_agent: Vec<AgentErrors>,
}

/// One agent's path errors in a run (BL; empty when there is no sample or no truth).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AgentErrors {
    /// RMS of the observed positions.
    pub rms_bl: Option<f64>,
    /// Largest error of an observed position.
    pub max_bl: Option<f64>,
    /// RMS of the true positions.
    pub rms_true_bl: Option<f64>,
    /// Largest error of a true position.
    pub max_true_bl: Option<f64>,
}

impl AgentErrors {
    /// The values in the order of [`agent_columns`].
    pub fn values(&self) -> [Option<f64>; 4] {
        [self.rms_bl, self.max_bl, self.rms_true_bl, self.max_true_bl]
    }

    /// From values in the order of [`agent_columns`].
    pub fn from_values(v: [Option<f64>; 4]) -> Self {
        AgentErrors {
            rms_bl: v[0],
            max_bl: v[1],
            rms_true_bl: v[2],
            max_true_bl: v[3],
        }
    }
}

impl From<&magbench_trackers::AgentError> for AgentErrors {
    fn from(a: &magbench_trackers::AgentError) -> Self {
        let seen = a.samples > 0;
        AgentErrors {
            rms_bl: seen.then_some(a.rms_bl),
            max_bl: seen.then_some(a.max_bl),
            rms_true_bl: a.rms_true_bl,
            max_true_bl: a.max_true_bl,
        }
    }
}

/// The per-agent columns of agent `i` (0-based, as in `ticks.csv`), in the order of
/// [`AgentErrors::values`].
pub fn agent_columns(i: usize) -> [String; 4] {
    [
        format!("rms_error_agent{i}_bl"),
        format!("max_error_agent{i}_bl"),
        format!("rms_error_true_agent{i}_bl"),
        format!("max_error_true_agent{i}_bl"),
    ]
}

impl RunRecord {
    /// Columns that hold wall-clock times: they differ between two executions of the same run
    /// (the time limit, and the table's wall-clock metrics).
    pub fn timing_columns() -> Vec<&'static str> {
        std::iter::once("time_limit_s")
            .chain(
                Metric::ALL
                    .iter()
                    .map(|m| m.def())
                    .filter(|d| d.wall_clock)
                    .map(|d| d.column),
            )
            .collect()
    }

    /// The CSV header without per-agent columns: the serde columns, one per metric, then one per
    /// difficulty measure.
    pub fn header() -> Vec<String> {
        let mut w = csv::WriterBuilder::new()
            .has_headers(true)
            .from_writer(vec![]);
        w.serialize(RunRecord::example()).expect("serialize");
        let text = String::from_utf8(w.into_inner().expect("flush")).expect("utf8");
        text.lines()
            .next()
            .unwrap_or_default()
            .split(',')
            .map(str::to_string)
            .chain(Metric::ALL.iter().map(|m| m.def().column.to_string()))
            .chain(Measure::ALL.iter().map(|m| m.def().column.to_string()))
            .collect()
    }

    /// The value of metric `m` (`None`: the run has none).
    pub fn get(&self, m: Metric) -> Option<f64> {
        self.metrics.get(m)
    }

    /// Sets the value of metric `m`.
    pub fn set(&mut self, m: Metric, v: Option<f64>) {
        self.metrics.set(m, v);
    }

    /// True if the run reached its goal: tracked to the goal, or (planning only) solved.
    pub fn success(&self) -> bool {
        match self.reached_goal {
            Some(r) => r && self.agent_contact != Some(true),
            None => self.solved,
        }
    }

    /// A placeholder record (for headers and tests).
    pub fn example() -> RunRecord {
        RunRecord {
            run: 0,
            run_id: String::new(),
            experiment: String::new(),
            scenario: String::new(),
            agents: 0,
            planner: String::new(),
            planner_name: String::new(),
            planner_params: String::new(),
            tracker: String::new(),
            preset: String::new(),
            seed: 0,
            max_iterations: None,
            time_limit_s: None,
            status: Status::Timeout,
            solved: false,
            approximate: false,
            progress_rows: None,
            track_status: String::new(),
            reached_goal: None,
            worst_agent: None,
            agent_contact: None,
            error: String::new(),
            metrics: Values::default(),
            difficulty: Measures::default(),
            per_agent: vec![],
        }
    }
}

/// One row of `progress.csv`: a point of a run's progress trace.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProgressRow {
    /// Position of the run in the run matrix.
    pub run: usize,
    /// The run's id.
    pub run_id: String,
    /// Iterations done.
    pub iteration: u64,
    /// Seconds since the start of planning.
    pub time_s: f64,
    /// Best exact-solution cost so far (empty before the first solution).
    pub best_cost: Option<f64>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_lists_inputs_then_metrics_then_difficulty() {
        let h = RunRecord::header();
        assert_eq!(h[0], "run");
        assert!(h.contains(&"planner".to_string()) && h.contains(&"rms_error_bl".to_string()));
        for c in RunRecord::timing_columns() {
            assert!(h.contains(&c.to_string()), "{c}");
        }
        let mut t = RunRecord::timing_columns();
        t.sort();
        assert_eq!(
            t,
            [
                "first_solution_time_s",
                "plan_time_s",
                "time_limit_s",
                "track_time_s"
            ]
        );
        assert_eq!(h.last().unwrap(), Measure::ALL.last().unwrap().def().column);
        let last_metric = h.len() - Measure::ALL.len() - 1;
        assert_eq!(h[last_metric], Metric::ALL.last().unwrap().def().column);
    }

    #[test]
    fn round_trips_through_csv() {
        let mut r = RunRecord::example();
        r.run_id = "micro-factory|goal-zoom-rrt{k=5,x=\"a, b\"}|-|-|3".into();
        r.status = Status::Exact;
        r.error = "line one\nline two".into();
        let mut w = csv::Writer::from_writer(vec![]);
        w.serialize(&r).unwrap();
        let data = w.into_inner().unwrap();
        let mut rd = csv::Reader::from_reader(&data[..]);
        let back: RunRecord = rd.deserialize().next().unwrap().unwrap();
        assert_eq!(back, r);
    }
}
