//! Post-processing: the passes a solved plan goes through after its planner returns it, the
//! shortcut pass (crate::shortcut), straightening (crate::straighten) and then trajectory
//! optimisation (crate::trajopt), declared once.
//!
//! The passes see only the plan, so they apply to any planner's solution alike, a plugin's
//! included: [`crate::PostProcessed`] applies them to every planner the registry makes, from
//! the run's `shortcut` and `straighten` parameters.

use std::time::Instant;

use magbench_env::declare_params;

use crate::objective::plan_cost;
use crate::search_settings::{SearchSettings, to_periods};
use crate::shortcut::Shortcut;
use crate::straighten::straighten;
use crate::trajopt::{self, refine};
use crate::{Plan, PlannerResult, Problem, ProgressPoint};

declare_params! {
    /// The post-processing passes of a run's solutions, in the order they run.
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct PostProcess {
        /// Steer solves (rounds) of shortcutting spent on a solution after its planner returns
        /// it (crate::shortcut; 0 none; pairs under the exact flow only).
        #[param("shortcut", 0..=1_000_000)]
        pub shortcut: usize = 0,
        /// Whether a solution's centroid is straightened after the shortcut pass
        /// (crate::straighten: the same fields and durations, gradients that run the centroid
        /// straight).
        #[param("straighten")]
        pub straighten: bool = false,
        /// Convex subproblems of trajectory optimisation spent on each horizon of a solution
        /// after straightening (crate::trajopt: fields and gradients optimised over a receding
        /// horizon, durations kept; 0 none).
        #[param("trajopt", 0..=1_000_000)]
        pub trajopt: usize = 0,
    }
}

/// The longest steered edge of the shortcut pass when the planner declares no `max_duration`
/// (s): the built-in planners' default longest edge.
pub fn default_max_duration() -> f64 {
    SearchSettings::default().max_duration
}

impl PostProcess {
    /// True when no pass runs.
    pub fn is_none(&self) -> bool {
        *self == PostProcess::default()
    }

    /// `plan` after the passes, or `None` when no pass runs: the shortcut pass with steered
    /// edges at most `max_duration` seconds, then straightening, then trajectory optimisation.
    pub fn plan(&self, problem: &Problem, plan: &Plan, max_duration: f64) -> Option<Plan> {
        if self.is_none() {
            return None;
        }
        let mut plan = plan.clone();
        if self.shortcut > 0 {
            let max_periods = to_periods(max_duration, problem.control_period);
            plan = Shortcut::new(self.shortcut, max_periods).run(problem, &plan);
        }
        if self.straighten {
            plan = straighten(problem, &plan);
        }
        if self.trajopt > 0
            && let Some(better) = refine(
                problem,
                &plan,
                &trajopt::Settings::default(),
                self.trajopt as u64,
            )
        {
            plan = better;
        }
        Some(plan)
    }

    /// `result` after the passes when it is solved ([`PostProcess::plan`]): its plan, cost and
    /// goal distance those of the processed plan, the passes' wall time added to its time, and
    /// the processed cost closing its progress trace at its last iteration (when it differs
    /// from the trace's last cost). An unsolved result is returned as it is.
    pub fn result(
        &self,
        problem: &Problem,
        mut result: PlannerResult,
        max_duration: f64,
    ) -> PlannerResult {
        if !result.solved || self.is_none() {
            return result;
        }
        let t0 = Instant::now();
        let Some(plan) = self.plan(problem, &result.plan, max_duration) else {
            return result;
        };
        let cost = plan_cost(problem, &plan);
        result.time_s += t0.elapsed().as_secs_f64();
        result.goal_distance = problem.goal.distance(plan.end());
        result.plan = plan;
        result.cost = Some(cost);
        if result
            .progress
            .last()
            .is_none_or(|p| p.best_cost != Some(cost))
        {
            result.progress.push(ProgressPoint {
                iteration: result.iterations,
                time_s: result.time_s,
                best_cost: Some(cost),
            });
        }
        result
    }
}
