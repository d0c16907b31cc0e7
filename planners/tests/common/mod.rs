//! Shared helpers: small problems and the checks every solved plan must pass.
#![allow(dead_code)]

use magbench_env::scenario::parse_scenario;
use magbench_env::{Scenario, Vec2};
use magbench_planners::{
    Limits, Plan, PlannerResult, PlanningSetup, Problem, plan_cost, validate_plan,
};

/// A small walled field with one block: start and goal 7 BL apart, the pair turns by 90°.
pub const SMALL: &str = r#"
name = "small"
[world]
width = 16.0
height = 12.0
[[world.obstacles]]
polygon = [[7.0, 0.0], [9.0, 0.0], [9.0, 4.0], [7.0, 4.0]]
[start]
agents = [[3.0, 3.0], [5.0, 3.0]]
[goal]
agents = [[11.0, 3.0], [11.0, 5.5]]
tolerance = 0.5
"#;

/// A large empty field where start and goal are close: the informed set is much smaller than
/// the world.
pub const ROOMY: &str = r#"
name = "roomy"
[world]
width = 40.0
height = 30.0
[start]
agents = [[10.0, 15.0], [12.0, 15.0]]
[goal]
agents = [[17.0, 15.0], [19.0, 15.0]]
tolerance = 0.5
"#;

/// A small empty box: SST's witnesses cover it in a long run.
pub const BOX: &str = r#"
name = "box"
[world]
width = 8.0
height = 8.0
[start]
agents = [[2.5, 4.0], [4.5, 4.0]]
[goal]
agents = [[4.0, 2.5], [4.0, 5.5]]
tolerance = 0.5
"#;

/// Three agents in a wide triangle move by (3, 1) BL (a three-agent team has far less freedom
/// than a pair: every pair must stay in the proximity range under one field).
pub const TRIO: &str = r#"
name = "trio"
[world]
width = 16.0
height = 14.0
[start]
agents = [[4.0, 5.0], [8.5, 5.0], [6.25, 8.9]]
[goal]
agents = [[7.0, 6.0], [11.5, 6.0], [9.25, 9.9]]
tolerance = 1.0
[medium]
kind = "interface"
surface_tension_mn_per_m = 66.0
liquid_density_kg_per_m3 = 1190.0
agent_density_kg_per_m3 = 1210.0
contact_angle_deg = 90.0
contact_angle_spread_deg = 6.0
"#;

/// A scenario's text without its `[medium]` table: in bulk, the planning setup's default.
pub fn in_bulk(text: &str) -> String {
    text.split("[medium]").next().unwrap_or(text).to_string()
}

/// A scenario's text at the seed's liquid–air interface (TRIO's `[medium]`).
pub fn at_interface(text: &str) -> String {
    let medium = TRIO.split("[medium]").nth(1).unwrap_or("");
    format!("{}[medium]{medium}", in_bulk(text))
}

/// Parses a scenario written in a test.
pub fn scenario(text: &str) -> Scenario {
    parse_scenario(text, "<test>").expect("test scenario parses")
}

/// The problem of leg 0 with an iteration limit.
pub fn problem(s: &Scenario, seed: u64, iterations: u64) -> Problem {
    problem_with(s, seed, iterations, &[])
}

/// [`TRIO`] planned by goal-zoom-rrt (seed 1, 30 000 iterations): the problem and its result,
/// a solution that passes [`assert_solution`].
pub fn solved_trio() -> (Problem, PlannerResult) {
    let p = problem(&scenario(TRIO), 1, 30_000);
    let r = magbench_planners::registry::Planners::builtin()
        .create("goal-zoom-rrt", &[])
        .unwrap()
        .solve(&p);
    assert_solution(&p, &r);
    (p, r)
}

/// The problem of leg 0 with an iteration limit, under a setup with `keys` (objective, metric,
/// flow) set.
pub fn problem_with(s: &Scenario, seed: u64, iterations: u64, keys: &[(&str, &str)]) -> Problem {
    let mut setup = PlanningSetup {
        limits: Limits {
            max_iterations: Some(iterations),
            time_limit: None,
        },
        ..PlanningSetup::default()
    };
    for (k, v) in keys {
        setup.set("<test>", k, v).expect("a known key and value");
    }
    setup.problem(s, 0, None, seed)
}

/// Replays `plan` through the planning model and returns the states it passes.
pub fn replay(problem: &Problem, plan: &Plan) -> Vec<Vec<Vec2>> {
    let mut states = vec![plan.states[0].clone()];
    for (u, &d) in plan.controls.iter().zip(&plan.durations) {
        let mut next = vec![Vec2::zeros(); problem.agents()];
        problem
            .model
            .with_flow(plan.flow)
            .propagate(states.last().unwrap(), u, d, &mut next);
        states.push(next);
    }
    states
}

/// Every check a solved result must pass: the validator, bit-exact replay (same model, same
/// arithmetic: any other code path would only agree approximately — the pair dynamics are
/// extremely sensitive), the reported cost equals a replayed cost, the goal distance, and
/// durations in whole control periods.
pub fn assert_solution(problem: &Problem, r: &PlannerResult) {
    assert!(
        r.solved && !r.approximate,
        "not solved (goal distance {})",
        r.goal_distance
    );
    validate_plan(problem, &r.plan).unwrap_or_else(|e| panic!("invalid plan: {e}"));
    assert_eq!(
        replay(problem, &r.plan),
        r.plan.states,
        "replay is not bit-exact"
    );
    assert_eq!(
        Some(plan_cost(problem, &r.plan)),
        r.cost,
        "reported cost differs from the replayed cost"
    );
    assert_eq!(r.goal_distance, problem.goal.distance(r.plan.end()));
    for &d in &r.plan.durations {
        let k = d / problem.control_period;
        assert!(
            k >= 1.0 && (k - k.round()).abs() < 1e-9,
            "duration {d} is not a whole number of periods"
        );
    }
    assert!(r.first_solution.is_some());
}

/// Best costs along a progress trace (ignoring times).
pub fn trace(r: &PlannerResult) -> Vec<(u64, Option<f64>)> {
    r.progress
        .iter()
        .map(|p| (p.iteration, p.best_cost))
        .collect()
}

/// The built-in planners that take the shared search settings.
pub const BUILTIN_PLANNERS: [&str; 4] = ["goal-zoom-rrt", "rrt-star", "informed-rrt-star", "sst"];

/// `planner`'s first solution of `p` with `key=value` (the planners that go on after one
/// stop at it).
pub fn first_solution(planner: &str, p: &Problem, key: &str, value: &str) -> PlannerResult {
    let mut params = vec![(key.to_string(), value.to_string())];
    if planner != "goal-zoom-rrt" {
        params.push(("stop_on_solution".to_string(), "true".to_string()));
    }
    magbench_planners::registry::Planners::builtin()
        .create(planner, &params)
        .unwrap()
        .solve(p)
}

/// Every value of `bad` for `key` is refused by every built-in planner, naming `param.<key>`
/// and a reason.
pub fn assert_refused(key: &str, bad: &[&str]) {
    for planner in BUILTIN_PLANNERS {
        for value in bad {
            let params = vec![(key.to_string(), value.to_string())];
            let e = match magbench_planners::registry::Planners::builtin().create(planner, &params)
            {
                Ok(_) => panic!("{planner}: {key}={value:?} accepted"),
                Err(e) => e,
            };
            assert_eq!(e.field, format!("param.{key}"), "{planner}, {value:?}: {e}");
            assert!(!e.reason.is_empty());
        }
    }
}
