//! `shooting-lm` (single shooting, Levenberg–Marquardt): it solves a pair, its plans pass the
//! validator and replay bit for bit, a seed reproduces its plan, and bad parameter values are
//! refused naming the parameter and its bound.

mod common;

use common::{ROOMY, assert_solution, problem, scenario};

/// A pair 2 BL apart moved 1.5 BL along its axis in an empty field: one window's reach.
const SHORT: &str = r#"
name = "short"
[world]
width = 20.0
height = 20.0
[start]
agents = [[8.0, 10.0], [10.0, 10.0]]
[goal]
agents = [[9.5, 10.0], [11.5, 10.0]]
tolerance = 0.5
"#;
use magbench_planners::registry::Planners;
use magbench_planners::{PlannerResult, Problem, validate_plan};

fn solve(p: &Problem, params: &[(&str, &str)]) -> PlannerResult {
    let params: Vec<(String, String)> = params
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    Planners::builtin()
        .create("shooting-lm", &params)
        .unwrap()
        .solve(p)
}

/// The pair moved 1.5 BL across an empty field under the exact flow: solved from the
/// straight-line guess, and the plan passes the validator, replays bit for bit and lasts
/// whole control periods (common::assert_solution).
#[test]
fn solves_the_pair_from_the_straight_line_guess() {
    let p = problem(&scenario(SHORT), 0, 2000);
    assert!(
        p.model.flow.pair_exact(),
        "the pair plans under the exact flow"
    );
    let r = solve(&p, &[]);
    assert_solution(&p, &r);
    // every segment is one edge of the same whole number of periods
    let d = r.plan.durations[0];
    assert!(r.plan.durations.iter().all(|&x| x == d));
}

/// The same seed gives the same plan and the same iteration count.
#[test]
fn a_seed_reproduces_its_plan() {
    let p = problem(&scenario(ROOMY), 3, 300);
    let (a, b) = (solve(&p, &[]), solve(&p, &[]));
    assert_eq!(a.plan, b.plan);
    assert_eq!(a.iterations, b.iterations);
}

/// A run stopped early on a 7 BL move keeps the windows it has committed: every edge valid and
/// every control within the coil's limits, so the validator objects only that the plan does
/// not end in the goal.
#[test]
fn an_unsolved_plan_is_valid_up_to_its_end() {
    let p = problem(&scenario(ROOMY), 0, 20);
    let r = solve(&p, &[]);
    assert!(!r.solved && r.plan.edges() > 0, "{} edges", r.plan.edges());
    match validate_plan(&p, &r.plan) {
        Err(magbench_planners::PlanError::NotInGoal { .. }) => {}
        other => panic!("{other:?}"),
    }
}

/// Values outside a parameter's bounds are refused, naming `param.<key>` and the bound.
#[test]
fn bad_values_are_refused_naming_the_parameter_and_bound() {
    for (key, value, bound) in [
        ("speed", "0", "0.01"),
        ("speed", "1.5", "1"),
        ("effort", "2", "1"),
        ("margin", "0.5", "0.25"),
        ("penalty", "0", "0.000001"),
        ("growth", "1", "2"),
        ("raises", "31", "30"),
        ("min_duration", "-1", "0"),
    ] {
        let params = vec![(key.to_string(), value.to_string())];
        let e = match Planners::builtin().create("shooting-lm", &params) {
            Ok(_) => panic!("{key}={value} accepted"),
            Err(e) => e,
        };
        assert_eq!(e.field, format!("param.{key}"), "{e}");
        assert!(e.reason.contains(bound), "{key}={value}: {e}");
    }
}
