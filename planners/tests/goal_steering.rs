//! Goal-zoom RRT's goal steering: on the short moves (a turn in place and a swap, open field)
//! and a built-in maze, plans that end with a steer into the goal pass the validator, and the
//! steer ends on the goal centres.

mod common;

use common::assert_solution;
use magbench_env::Scenario;
use magbench_planners::{Limits, Problem, check_result, registry::Planners};

fn solve(
    scenario: &Scenario,
    seed: u64,
    steer_radius: &str,
) -> (Problem, magbench_planners::PlannerResult) {
    let mut p = Problem::from_scenario(scenario, 0, None, seed);
    p.limits = Limits {
        max_iterations: Some(50_000),
        time_limit: None,
    };
    let params = vec![("steer_radius".to_string(), steer_radius.to_string())];
    let r = Planners::builtin()
        .create("goal-zoom-rrt", &params)
        .unwrap()
        .solve(&p);
    (p, r)
}

fn short(kind: &str) -> Scenario {
    let path = format!(
        "{}/../experiments/short-moves/{kind}.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    Scenario::load(&path).unwrap()
}

#[test]
fn steered_plans_pass_the_validator_and_end_on_the_goal_centres() {
    let mut exact = 0;
    for s in [
        short("turn"),
        short("swap"),
        Scenario::load("micro-factory").unwrap(),
    ] {
        for seed in 0..4 {
            let (p, r) = solve(&s, seed, "3");
            assert!(r.solved, "{}: seed {seed} not solved", s.name);
            check_result(&p, &r).unwrap_or_else(|e| panic!("{}: {e:?}", s.name));
            assert_solution(&p, &r);
            if p.goal.distance(r.plan.end()) < 1e-6 {
                exact += 1;
            }
        }
    }
    // every short move ends with a steer (its goal is steered to from the start)
    assert!(exact >= 8, "{exact} of 12 plans end on the goal centres");
}

#[test]
fn without_steering_no_plan_ends_on_the_goal_centres() {
    let s = short("turn");
    let (p, r) = solve(&s, 0, "0");
    assert!(r.solved);
    check_result(&p, &r).unwrap();
    assert!(p.goal.distance(r.plan.end()) > 1e-6);
}

#[test]
fn shortcut_plans_pass_the_validator_and_cost_no_more() {
    let s = Scenario::load("micro-factory").unwrap();
    let mut shorter = 0;
    for seed in 0..3 {
        let (_, before) = solve(&s, seed, "3");
        let mut p = Problem::from_scenario(&s, 0, None, seed);
        p.limits = Limits {
            max_iterations: Some(50_000),
            time_limit: None,
        };
        let params = vec![("shortcut".to_string(), "200".to_string())];
        let r = Planners::builtin()
            .create("goal-zoom-rrt", &params)
            .unwrap()
            .solve(&p);
        check_result(&p, &r).unwrap();
        let (a, b) = (before.cost.unwrap(), r.cost.unwrap());
        eprintln!(
            "seed {seed}: cost {a:.1} -> {b:.1}, {} -> {} edges",
            before.plan.edges(),
            r.plan.edges()
        );
        assert!(b <= a + 1e-9);
        shorter += usize::from(b < a);
    }
    assert!(shorter >= 2, "{shorter} of 3 plans shortened");
}
