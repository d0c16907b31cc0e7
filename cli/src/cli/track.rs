//! `magbench track`: plan, then track the plan in closed loop against the simulated plant.

use std::path::PathBuf;

use clap::Args;
use magbench_drivers::rigs::Rigs;
use magbench_env::Scenario;
use magbench_trackers::Trackers;

use super::plan_and_track::{TrackRun, tracker_spec};
use super::setup::SetupArgs;
use crate::Error;
use crate::output::out;
use crate::registry::Registry;

/// Arguments of `magbench track`.
#[derive(Debug, Args)]
pub struct TrackArgs {
    /// A built-in scenario name or a scenario file.
    #[arg(required_unless_present = "list")]
    pub scenario: Option<String>,
    /// The planner that makes the plan (and every replan): a name or a label such as
    /// `goal-zoom-rrt{k=5}`; goal-zoom-rrt unless --plan is given.
    #[arg(long)]
    pub planner: Option<String>,
    /// The tracker: a name (open-loop, obc, lookahead, formation, mppi or a plugin's; see
    /// --list) or a label with parameters as experiment files write it, `obc{time_slack=5}`.
    #[arg(long, required_unless_present = "list")]
    pub tracker: Option<String>,
    /// Seed of the planner and of the simulated disturbances.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Disturbance preset of the simulated plant and camera: ideal, realistic, hardware or a
    /// preset file (TOML, as in presets/). With another --rig-type, what that type reads.
    #[arg(long, default_value = "realistic")]
    pub preset: String,
    /// The rig type, by its registry name: `simulated` (env's plant and camera under
    /// --preset), `coil` (--preset is then a rig file) or a plugin's.
    #[arg(long, default_value = "simulated")]
    pub rig_type: String,
    /// A tracker or loop parameter, key=value (repeatable). Added to those of a --tracker
    /// label; a key in both is refused.
    #[arg(long = "param", value_name = "KEY=VALUE")]
    pub params: Vec<String>,
    /// A planner parameter, key=value (repeatable). Added to those of a --planner label; a key
    /// in both is refused.
    #[arg(long = "planner-param", value_name = "KEY=VALUE")]
    pub planner_params: Vec<String>,
    /// Track this plan (JSON, as written by `track --out` or `plan --out`) instead of planning
    /// the first leg; the planner, if given, still makes the replans.
    #[arg(long, value_name = "FILE")]
    pub plan: Option<PathBuf>,
    /// Track a --plan made for another scenario, team or start (a warning instead of exit 2).
    #[arg(long, requires = "plan")]
    pub force: bool,
    /// Planner limits, objective, metric and flow of every planning call.
    #[command(flatten)]
    pub setup: SetupArgs,
    /// Print one JSON object on stdout instead of a summary.
    #[arg(long)]
    pub json: bool,
    /// Write the per-tick CSV, the metrics, the plans, a world plot and a replay page
    /// (replay.html) of the run here.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Also write a GIF of each leg into --out (slow to encode).
    #[arg(long, requires = "out")]
    pub gif: bool,
    /// List the trackers (plugins' included) and their parameters with defaults, the loop's
    /// after each tracker's own, then the rig types, and exit.
    #[arg(long)]
    pub list: bool,
}

/// Runs `magbench track` with the planners, trackers and rigs of `registry`.
pub fn run(a: TrackArgs, registry: &Registry) -> Result<(), Error> {
    if a.list {
        out!("{}", tracker_list(registry.trackers()));
        out!("{}", rig_type_list(registry.rigs()));
        return Ok(());
    }
    let (Some(scenario), Some(tracker)) = (a.scenario.as_deref(), a.tracker.as_deref()) else {
        return Err(Error::arg(
            "SCENARIO",
            "a scenario and --tracker are required",
        ));
    };
    let scenario = Scenario::load(scenario)?;
    let rig = registry.rigs().load(&a.rig_type, &a.preset, "--preset")?;
    let tracker = tracker_spec(registry, tracker, &a.params)?;
    let setup = a.setup.setup()?;
    // without a plan file, the seed's planner makes the plan unless another is named
    let planner = match (&a.planner, &a.plan) {
        (Some(name), _) => Some(name.clone()),
        (None, None) => Some("goal-zoom-rrt".to_string()),
        (None, Some(_)) => None,
    };
    super::plan_and_track::run(TrackRun {
        registry,
        scenario: &scenario,
        rig,
        planner,
        planner_params: &a.planner_params,
        plan: a.plan,
        force: a.force,
        tracker,
        seed: a.seed,
        setup,
        out: a.out,
        gif: a.gif,
        json: a.json,
    })
}

/// The rig types of `rigs` (the values of `--rig-type`) with their summaries, for `--list`.
pub fn rig_type_list(rigs: &Rigs) -> String {
    let mut s = String::from("\nrig types (--rig-type; each reads one argument, no parameters)\n");
    for (name, summary) in rigs.list() {
        s += &format!("{name}\n    {summary}\n");
    }
    s
}

/// The trackers of `trackers` and their parameters (each tracker's own, then the loop's) with
/// defaults, for `--list`.
pub fn tracker_list(trackers: &Trackers) -> String {
    let mut s = String::new();
    for (name, summary, params) in trackers.list() {
        s += &format!("{name}\n    {summary}\n");
        for p in params {
            s += &p.listing_line([20, 10, 16]);
        }
    }
    s
}
