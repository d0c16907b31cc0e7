//! What one run is: every input that determines its result.

use std::sync::Arc;
use std::time::Duration;

use magbench_env::Scenario;
use magbench_env::input::{Bound, MEMORY_BUDGET_BYTES, Rejection};
use magbench_env::plant::DisturbancePreset;

use super::Variant;

/// When a planner stops. Iteration limits give reproducible runs; a time limit does not.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunLimits {
    /// Largest number of planner iterations.
    pub iterations: Option<u64>,
    /// Largest planning wall time (s).
    pub time_s: Option<f64>,
}

/// Longest planning time limit accepted (s): a week. Far beyond any useful plan, and far below
/// what a [`Duration`] can hold (1e20 s panicked converting).
pub const MAX_TIME_LIMIT_S: f64 = 7.0 * 24.0 * 3600.0;

/// Planning time limits (`--time-limit`, an experiment's `limits.time`): up to
/// [`MAX_TIME_LIMIT_S`].
pub const TIME_LIMIT: Bound = Bound::above(
    0.0,
    MAX_TIME_LIMIT_S,
    " s",
    "a week, far beyond any useful plan",
);

/// Planning time limit of every planning call of `plan`, `track` and `rig run` when
/// `--time-limit` is not given (s): a minute, several times what 200 000 iterations of the
/// built-in planners take on the built-in scenarios, so only a planner far slower than those
/// (a plugin, a hard scenario) is cut short.
pub const DEFAULT_TIME_LIMIT_S: f64 = 60.0;

/// Memory one planner iteration may take at most (bytes): a planner keeps at most one tree node
/// per iteration (its states, control, links and its place in the neighbour index), about
/// 360 B for four agents (`plan quad-square --planner rrt-star`: 4.3 MB more peak memory for
/// 12 154 more nodes), of which the positions, held twice (tree and index), are 128 B; so about
/// 232 B + 2 × 256 B = 744 B, under 1 KiB, for the sixteen agents of the largest team.
pub const BYTES_PER_ITERATION: u64 = 1 << 10;

/// Planner iteration limits (`--max-iters`, `figures --maze-iterations`, an experiment's
/// `limits.iterations`): as many as the memory budget holds tree nodes, 2 097 152.
pub const ITERATIONS: Bound = Bound::closed(
    1.0,
    (MEMORY_BUDGET_BYTES / BYTES_PER_ITERATION) as f64,
    " iterations",
    "a planner keeps up to one tree node of about 1 KiB per iteration, within the 2 GiB memory budget",
);

/// A planning time limit of `t` seconds, or why not (a rejection with an empty field: the
/// caller names the option or key).
pub fn time_limit(t: f64) -> Result<Duration, Rejection> {
    let t = TIME_LIMIT.check("", t)?;
    Duration::try_from_secs_f64(t).map_err(|e| Rejection::new("", format!("{t} s: {e}")))
}

/// An iteration limit of `n`, or why not (a rejection with an empty field).
pub fn iterations(n: u64) -> Result<u64, Rejection> {
    ITERATIONS.check_count("", n)
}

/// One run of the run matrix.
#[derive(Debug, Clone)]
pub struct RunSpec {
    /// Position in the full run matrix of the experiment (stable for a given experiment file).
    pub index: usize,
    /// The experiment's name.
    pub experiment: String,
    /// The scenario as written in the experiment (a built-in name or a path).
    pub scenario_label: String,
    /// The loaded scenario.
    pub scenario: Arc<Scenario>,
    /// The planner and its parameters.
    pub planner: Variant,
    /// The tracker and its parameters, if the run tracks the plan.
    pub tracker: Option<Variant>,
    /// The plant's disturbance preset as the experiment names it (with a tracker).
    pub preset: Option<String>,
    /// That preset, loaded.
    pub plant: Option<Arc<DisturbancePreset>>,
    /// The seed of every random stream of the run (planner, plant, camera).
    pub seed: u64,
    /// Planner limits.
    pub limits: RunLimits,
}

/// The id of a run's configuration, `scenario|planner|tracker|preset` (`-` for none): a run's
/// id less its seed.
pub fn config_id(
    scenario_label: &str,
    planner: &Variant,
    tracker: Option<&Variant>,
    preset: Option<&str>,
) -> String {
    let t = tracker.map(|t| t.label()).unwrap_or_else(|| "-".into());
    format!(
        "{scenario_label}|{}|{t}|{}",
        planner.label(),
        preset.unwrap_or("-")
    )
}

impl RunSpec {
    /// The run's identity: `scenario|planner|tracker|preset|seed` (`-` for none). Two runs with
    /// the same id have the same inputs.
    pub fn id(&self) -> String {
        let config = config_id(
            &self.scenario_label,
            &self.planner,
            self.tracker.as_ref(),
            self.preset.as_deref(),
        );
        format!("{config}|{}", self.seed)
    }

    /// The comparison group of the run: everything but the seed.
    pub fn group(&self) -> String {
        let id = self.id();
        id[..id.rfind('|').unwrap_or(id.len())].to_string()
    }
}
