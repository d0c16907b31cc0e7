//! The shortcut pass every planner's solution can go through (`shortcut=N`): its plans pass
//! the validator and cost no more than the same run's plan without it; bad values are refused.

use crate::common;

use magbench_env::Scenario;
use magbench_planners::search_settings::to_periods;
use magbench_planners::shortcut::Shortcut;
use magbench_planners::{Limits, PlannerResult, Problem, validate_plan, validate_result};

use common::{BUILTIN_PLANNERS as PLANNERS, first_solution};

fn solve(planner: &str, p: &Problem, shortcut: &str) -> PlannerResult {
    first_solution(planner, p, "shortcut", shortcut)
}

#[test]
fn every_planners_shortcut_plans_validate_and_cost_no_more() {
    let s = Scenario::load("narrow-passage").unwrap();
    for planner in PLANNERS {
        let mut shorter = 0;
        for seed in 0..2 {
            let mut p = Problem::from_scenario(&s, 0, None, seed);
            p.limits = Limits {
                max_iterations: Some(200_000),
                time_limit: None,
            };
            let before = solve(planner, &p, "0");
            let after = solve(planner, &p, "100");
            assert!(before.solved && after.solved, "{planner}, seed {seed}");
            validate_plan(&p, &after.plan).unwrap_or_else(|e| panic!("{planner}: {e}"));
            validate_result(&p, &after).unwrap();
            let (a, b) = (before.cost.unwrap(), after.cost.unwrap());
            eprintln!("{planner}, seed {seed}: cost {a:.1} -> {b:.1}");
            assert!(b <= a + 1e-9, "{planner}, seed {seed}: {a} -> {b}");
            assert_eq!(after.progress.last().unwrap().best_cost, Some(b));
            shorter += usize::from(b < 0.95 * a);
        }
        assert_eq!(
            shorter, 2,
            "{planner}: {shorter} of 2 plans shortened by 5%"
        );
    }
}

#[test]
fn the_pass_is_reproducible_and_keeps_its_budget() {
    let s = Scenario::load("open-field").unwrap();
    let mut p = Problem::from_scenario(&s, 0, None, 3);
    p.limits = Limits {
        max_iterations: Some(50_000),
        time_limit: None,
    };
    let r = solve("goal-zoom-rrt", &p, "0");
    let pass = Shortcut::new(40, to_periods(2.0, p.control_period));
    let (a, stats) = pass.run_with_stats(&p, &r.plan);
    let (b, again) = pass.run_with_stats(&p, &r.plan);
    assert_eq!(a, b);
    assert_eq!(stats, again);
    assert!(stats.rounds >= 40 && stats.rounds <= 45, "{stats:?}");
    assert!(stats.accepted > 0, "{stats:?}");
    validate_plan(&p, &a).unwrap();
    // a plan the pass cannot shorten (no rounds) comes back as it was
    let (same, none) = Shortcut::new(0, 60).run_with_stats(&p, &r.plan);
    assert_eq!(same, r.plan);
    assert_eq!(none.rounds, 0);
}

#[test]
fn a_trio_plan_comes_back_unchanged() {
    let (p, r) = common::solved_trio();
    let pass = Shortcut::new(50, to_periods(2.0, p.control_period));
    let (out, stats) = pass.run_with_stats(&p, &r.plan);
    assert_eq!(out, r.plan);
    assert_eq!(stats.rounds, 0);
}

#[test]
fn bad_shortcut_values_are_refused() {
    common::assert_refused("shortcut", &["-1", "1.5", "many", "1000001", ""]);
}
