//! The one run pipeline: `magbench plan --seed s` makes the plans a sweep's run of seed `s`
//! makes, leg by leg, `magbench track --seed s` tracks them to the metrics of the sweep's row,
//! and a plugin planner's plans are post-processed (`shortcut`, `straighten`) without a call of
//! its own.

use crate::common;

use std::path::Path;

use magbench::Registry;
use magbench::experiment::Experiment;
use magbench::run::RunSpec;
use magbench::run::real::{RealExecutor, plan_legs, setup};
use magbench_env::declare_params;
use magbench_planners::planners::GoalZoomRrt;
use magbench_planners::search_settings::to_periods;
use magbench_planners::shortcut::Shortcut;
use magbench_planners::straighten::straighten;
use magbench_planners::{Planner, PlannerResult, Problem, validate_plan};
use magbench_trackers::plan_file::plan_json_for;

use common::magbench;

/// The runs of a one-planner, one-scenario planning experiment.
fn runs(
    planner: &str,
    scenario: &str,
    seeds: u32,
    iterations: u64,
    ex: &RealExecutor,
) -> Vec<RunSpec> {
    let text = format!(
        "scenarios = [\"{scenario}\"]\nplanners = [{planner:?}]\nseeds = {seeds}\n[limits]\niterations = {iterations}\n"
    );
    Experiment::parse(&text, "x.toml", Path::new("."), "x", ex)
        .unwrap()
        .runs()
}

#[test]
fn plan_gives_the_plans_of_the_sweeps_run_of_the_same_seed_on_every_leg() {
    let ex = RealExecutor::default();
    let specs = runs("goal-zoom-rrt", "cargo-delivery", 2, 5000, &ex);
    assert_eq!(specs.len(), 2);
    for spec in &specs {
        let legs = plan_legs(ex.registry(), spec, &setup(spec).unwrap()).unwrap();
        assert_eq!(legs.len(), 2, "seed {}: both legs planned", spec.seed);
        let dir = tempfile::tempdir().unwrap();
        let seed = spec.seed.to_string();
        let out = dir.path().to_str().unwrap();
        let (code, _, err) = magbench(&[
            "plan",
            "cargo-delivery",
            "--planner",
            "goal-zoom-rrt",
            "--seed",
            &seed,
            "--max-iters",
            "5000",
            "--out",
            out,
        ]);
        assert_eq!(code, 0, "{err}");
        for (k, leg) in legs.iter().enumerate() {
            let file = dir.path().join(format!("plan-leg{}.json", k + 1));
            let planned = std::fs::read_to_string(&file).unwrap();
            assert!(
                planned == plan_json_for(&leg.plan, &spec.scenario, k + 1),
                "seed {}: leg {} of `plan` is not the sweep's",
                spec.seed,
                k + 1
            );
        }
    }
}

/// A results row's columns whose value `track --json` gives under another key: the row's
/// `status` is the planner's, and the tracking loop's is `track_status`.
const TRACK_KEYS: &[(&str, &str)] = &[
    ("track_status", "status"),
    ("final_distance_bl", "final_goal_distance_bl"),
    ("track_duration_s", "duration_s"),
];

#[test]
fn track_gives_the_tracking_metrics_of_the_sweeps_run_of_the_same_seed() {
    let dir = tempfile::tempdir().unwrap();
    // two legs and a disturbed plant, so the loop plans the second leg and may replan
    let exp = common::write(
        dir.path(),
        "e.toml",
        "name = \"e\"\nscenarios = [\"cargo-delivery\"]\nplanners = [\"goal-zoom-rrt\"]\n\
         trackers = [\"obc\"]\npresets = [\"realistic\"]\nseeds = 2\n[limits]\niterations = 5000\n",
    );
    let out = dir.path().join("out");
    let (code, _, err) = magbench(&[
        "bench",
        exp.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let mut rd = csv::Reader::from_path(out.join("runs.csv")).unwrap();
    let header = rd.headers().unwrap().clone();
    let mut compared = 0;
    for record in rd.records() {
        let record = record.unwrap();
        let row: std::collections::HashMap<&str, &str> = header.iter().zip(&record).collect();
        let (code, json, err) = magbench(&[
            "track",
            "cargo-delivery",
            "--planner",
            "goal-zoom-rrt",
            "--tracker",
            "obc",
            "--preset",
            "realistic",
            "--seed",
            row["seed"],
            "--max-iters",
            "5000",
            "--json",
        ]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        let o = v.as_object().unwrap();
        assert_eq!(
            row["legs_completed"], "2",
            "seed {}: both legs tracked",
            row["seed"]
        );
        for (&column, &cell) in &row {
            let key = TRACK_KEYS
                .iter()
                .find(|(c, _)| *c == column)
                .map_or(column, |(_, k)| *k);
            if column == "status" {
                continue;
            }
            let Some(value) = o.get(key) else { continue };
            let same = match value {
                serde_json::Value::Null => cell.is_empty(),
                serde_json::Value::Bool(b) => cell.parse::<bool>() == Ok(*b),
                serde_json::Value::Number(n) => cell.parse::<f64>().ok() == n.as_f64(),
                serde_json::Value::String(t) => cell == t,
                // lists and objects (per agent, parameters, replans): no column holds one
                serde_json::Value::Array(_) | serde_json::Value::Object(_) => continue,
            };
            assert!(
                same,
                "seed {}: `track --json` gives {key} = {value}, the sweep's row {column} = {cell}",
                row["seed"]
            );
            compared += 1;
        }
    }
    // the identity and every tracking metric the row and the JSON share
    assert!(compared >= 2 * 25, "only {compared} values compared");
}

declare_params! {
    /// A plugin's planner with no parameters of its own: goal-zoom RRT's search (with its
    /// defaults), its solution returned as it is.
    #[derive(Debug, Clone)]
    struct PlainPlugin {
        /// The search (state, not a parameter).
        search: GoalZoomRrt = GoalZoomRrt::default(),
    }
}

impl Planner for PlainPlugin {
    fn name(&self) -> &str {
        "plain-plugin"
    }
    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        self.search.solve(problem)
    }
}

#[test]
fn a_plugin_planners_plans_are_post_processed_without_a_call_of_its_own() {
    let mut registry = Registry::builtin();
    registry
        .add_planner("plain-plugin", "a plugin's planner", || {
            Box::new(PlainPlugin::default())
        })
        .unwrap();
    let ex = RealExecutor::new(registry);
    let plain = runs(
        "plain-plugin{flow=\"pair-exact\"}",
        "open-field",
        1,
        3000,
        &ex,
    );
    let passes = runs(
        "plain-plugin{flow=\"pair-exact\", shortcut=200, straighten=true}",
        "open-field",
        1,
        3000,
        &ex,
    );
    let raw = &plan_legs(ex.registry(), &plain[0], &setup(&plain[0]).unwrap()).unwrap()[0];
    let spec = &passes[0];
    let s = setup(spec).unwrap();
    let done = &plan_legs(ex.registry(), spec, &s).unwrap()[0];
    assert!(raw.solved && done.solved);
    let problem = s.problem(&spec.scenario, 0, None, spec.seed);
    // the shortcut pass (its steered edges at most the built-ins' default 2 s), then
    // straightening
    let max_periods = to_periods(2.0, problem.control_period);
    let expected = straighten(
        &problem,
        &Shortcut::new(200, max_periods).run(&problem, &raw.plan),
    );
    assert_ne!(expected, raw.plan, "the passes change this plan");
    assert_eq!(done.plan, expected, "the sweep's plan is the processed one");
    assert!(
        done.cost.unwrap() < raw.cost.unwrap(),
        "{:?} {:?}",
        done.cost,
        raw.cost
    );
    validate_plan(&problem, &done.plan).unwrap();
    // the passes are listed with the plugin's own parameters
    let listed = ex.registry().planners().list();
    let (_, _, params) = listed
        .iter()
        .find(|(n, _, _)| *n == "plain-plugin")
        .unwrap();
    for key in ["shortcut", "straighten"] {
        assert!(params.iter().any(|p| p.name == key), "{key}");
    }
}
