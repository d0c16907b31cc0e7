//! The planner seam.

use magbench_env::params::ParamSet;

use crate::tree::Tree;
use crate::{Plan, Problem};

/// A planner. `solve` is deterministic for a given problem and seed when only iterations
/// limit it. Its parameters are declared once ([`magbench_env::declare_params!`]), which makes
/// it a [`ParamSet`]: listed, set by `key=value` and checked by the [`crate::registry`].
pub trait Planner: ParamSet + Send {
    /// The registry name, e.g. `goal-zoom-rrt`.
    fn name(&self) -> &str;
    /// Plans for `problem`.
    fn solve(&mut self, problem: &Problem) -> PlannerResult;
    /// The search tree of the last `solve`, if the planner keeps one (for plots).
    fn tree(&self) -> Option<&Tree> {
        None
    }
    /// Why the last `solve` ended without an exact solution, when the planner can say more
    /// than that its limits ran out (the optimiser converged onto an infeasible plan, say);
    /// `None` otherwise. A run writes it to its `error` column.
    fn stop_reason(&self) -> Option<&str> {
        None
    }
}

/// One point of a planner's progress trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProgressPoint {
    /// Iterations done.
    pub iteration: u64,
    /// Seconds since the start of `solve`.
    pub time_s: f64,
    /// Best exact-solution cost so far, if any.
    pub best_cost: Option<f64>,
}

/// What a planner returns.
#[derive(Debug, Clone)]
pub struct PlannerResult {
    /// An exact solution: the plan ends in the goal region.
    pub solved: bool,
    /// Not solved; the plan ends at the tree's closest approach to the goal.
    pub approximate: bool,
    /// The plan (exact, approximate, or just the start).
    pub plan: Plan,
    /// Iterations run.
    pub iterations: u64,
    /// Nodes in the tree (or graph) at the end.
    pub nodes: usize,
    /// Wall time (s).
    pub time_s: f64,
    /// Cost of the plan under the problem's objective, if solved.
    pub cost: Option<f64>,
    /// Distance of the plan's end from the goal (largest agent distance to its goal centre, BL).
    pub goal_distance: f64,
    /// Iteration and time of the first exact solution.
    pub first_solution: Option<(u64, f64)>,
    /// Best cost against iteration and time: on every change and at least every 1% of the budget.
    pub progress: Vec<ProgressPoint>,
}
