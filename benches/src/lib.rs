//! Criterion benchmarks live in `benches/benches/`; this library holds what they share with the
//! examples in `benches/examples/`.

#![warn(missing_docs)]

use std::time::Instant;

use magbench_env::model::Flow;
use magbench_planners::{Limits, PlannerResult, Planners, Problem};

/// Goal-zoom RRT's plan of `problem` under `flow` and `seed`, to its first solution within
/// 200,000 iterations and no time limit: the planner's result and its wall time (s, the
/// problem's setup excluded).
pub fn first_plan(problem: &Problem, flow: Flow, seed: u64) -> (PlannerResult, f64) {
    let mut q = problem.clone();
    q.model = q.model.with_flow(flow);
    q.seed = seed;
    q.limits = Limits {
        max_iterations: Some(200_000),
        time_limit: None,
    };
    let mut planner = Planners::builtin()
        .create("goal-zoom-rrt", &[])
        .expect("a built-in planner");
    let t = Instant::now();
    let r = planner.solve(&q);
    (r, t.elapsed().as_secs_f64())
}
