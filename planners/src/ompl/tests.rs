//! Tests of the OMPL planners (feature `ompl`): real OMPL, magbench's model.

use magbench_env::Scenario;

use super::*;
use crate::registry::create;
use crate::{Limits, check_result, validate_plan};

fn problem(scenario: &str, seed: u64, iterations: u64) -> Problem {
    let s = Scenario::load(scenario).unwrap();
    let mut p = Problem::from_scenario(&s, 0, None, seed);
    p.limits = Limits {
        max_iterations: Some(iterations),
        time_limit: None,
    };
    p
}

#[test]
fn debug_join() {
    let p = problem("open-field", 1, 20_000);
    for name in ["ompl:rrt", "ompl:sst"] {
        let mut planner = create(name, &[]).unwrap();
        let r = planner.solve(&p);
        eprintln!(
            "{name}: solved {} edges {} first {:?} progress {}",
            r.solved,
            r.plan.edges(),
            r.first_solution,
            r.progress.len()
        );
        eprintln!("{:?}", validate_plan(&p, &r.plan));
        let _ = check_result(&p, &r);
    }
}
