//! Every planner's plans of every built-in scenario pass the validator: each leg, from where the
//! last one ended, for several seeds.

use crate::common;

use common::assert_solution;
use magbench_env::Scenario;
use magbench_env::scenario::builtin_names;
use magbench_planners::{Limits, Problem, registry::Planners, validate_plan};

#[test]
fn every_plan_of_the_built_in_scenarios_passes_the_validator() {
    let planners = ["goal-zoom-rrt", "rrt-star", "informed-rrt-star", "sst"];
    let mut plans = 0;
    for name in builtin_names() {
        let s = Scenario::load(name).unwrap();
        for planner in planners {
            let params = if planner == "goal-zoom-rrt" {
                vec![]
            } else {
                vec![("stop_on_solution".to_string(), "true".to_string())]
            };
            for seed in 0..3 {
                let mut start = s.start.clone();
                for leg in 0..s.legs.len() {
                    let mut p = Problem::from_scenario(&s, leg, Some(&start), seed + leg as u64);
                    p.limits = Limits {
                        max_iterations: Some(200_000),
                        time_limit: None,
                    };
                    let r = Planners::builtin()
                        .create(planner, &params)
                        .unwrap()
                        .solve(&p);
                    assert!(
                        r.solved,
                        "{name} leg {leg}, {planner}, seed {seed}: not solved"
                    );
                    validate_plan(&p, &r.plan)
                        .unwrap_or_else(|e| panic!("{name} leg {leg}, {planner}: {e}"));
                    assert_solution(&p, &r);
                    start = r.plan.end().to_vec();
                    plans += 1;
                }
            }
        }
    }
    eprintln!("{plans} plans validated");
}
