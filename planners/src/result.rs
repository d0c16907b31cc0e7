//! Assembling a [`PlannerResult`] at the end of a run.

use crate::progress::Progress;
use crate::{Plan, PlannerResult, Problem};

/// The best plan a run holds: an exact solution with its cost, or the closest approach.
#[derive(Debug, Clone)]
pub struct Best {
    /// The plan.
    pub plan: Plan,
    /// True when it ends in the goal region.
    pub solved: bool,
    /// Its cost under the problem's objective (meaningful when solved).
    pub cost: f64,
}

impl Best {
    /// The cost if solved.
    pub fn solved_cost(&self) -> Option<f64> {
        self.solved.then_some(self.cost)
    }
}

/// Closes the progress trace and builds the result; the plan records `alpha_max`, the largest
/// elevation the planner could draw (`None` when it kept the field in the plane).
pub fn finish(
    problem: &Problem,
    mut best: Best,
    iterations: u64,
    nodes: usize,
    progress: Progress,
    first_solution: Option<(u64, f64)>,
    alpha_max: Option<f64>,
) -> PlannerResult {
    best.plan.alpha_max = alpha_max;
    let cost = best.solved_cost();
    let (trace, time_s) = progress.finish(iterations, cost);
    PlannerResult {
        solved: best.solved,
        approximate: !best.solved,
        goal_distance: problem.goal.distance(best.plan.end()),
        plan: best.plan,
        iterations,
        nodes,
        time_s,
        cost,
        first_solution,
        progress: trace,
    }
}
