//! Cost objectives behind one trait, like OMPL's `OptimizationObjective`: sum of agent path
//! lengths (the default), duration and control effort. Costs are additive along a plan.

use std::fmt::Debug;
use std::sync::Arc;

use magbench_env::math::centroid;
use magbench_env::{Control, Goal, PlanningModel, Vec2};

/// What one edge did: the input to [`Objective::motion_cost`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion {
    /// The control held along the edge.
    pub control: Control,
    /// Its duration (s).
    pub duration: f64,
    /// The agents' summed path length along the integration samples (BL).
    pub path_length: f64,
}

/// A cost objective: an additive cost per edge and admissible heuristics.
pub trait Objective: Send + Sync + Debug {
    /// The objective's name (`path-length`, `duration`, `control-effort`).
    fn name(&self) -> &str;
    /// The cost of one edge.
    fn motion_cost(&self, m: &Motion) -> f64;
    /// A lower bound on the cost of any motion from state `a` to state `b` (admissible).
    fn motion_cost_heuristic(&self, a: &[Vec2], b: &[Vec2]) -> f64;
    /// A lower bound on the cost from state `s` into the goal region (admissible).
    fn cost_to_go(&self, s: &[Vec2], goal: &Goal) -> f64;
    /// True when the cost is the sum of the agents' path lengths, so that a state can improve a
    /// solution of cost `c` only if `Σ_i ‖P_i − start_i‖ + ‖P_i − goal_i‖ − tol < c` — the
    /// per-agent prolate ellipses of informed sampling.
    fn is_path_length(&self) -> bool {
        false
    }
}

/// Sum over agents of the length travelled (BL), measured along the integration samples.
#[derive(Debug, Clone, Copy, Default)]
pub struct PathLength;

impl Objective for PathLength {
    fn name(&self) -> &str {
        "path-length"
    }

    fn motion_cost(&self, m: &Motion) -> f64 {
        m.path_length
    }

    fn motion_cost_heuristic(&self, a: &[Vec2], b: &[Vec2]) -> f64 {
        a.iter().zip(b).map(|(p, q)| (p - q).norm()).sum()
    }

    fn cost_to_go(&self, s: &[Vec2], goal: &Goal) -> f64 {
        s.iter()
            .zip(&goal.agents)
            .map(|(p, g)| ((p - g).norm() - goal.tolerance).max(0.0))
            .sum()
    }

    fn is_path_length(&self) -> bool {
        true
    }
}

/// Plan duration (s). Only the gradient moves the centroid, at most `max_centroid_speed`.
#[derive(Debug, Clone, Copy)]
pub struct Duration {
    /// Largest centroid speed (BL/s): the pull speed at full gradient.
    pub max_centroid_speed: f64,
}

impl Objective for Duration {
    fn name(&self) -> &str {
        "duration"
    }

    fn motion_cost(&self, m: &Motion) -> f64 {
        m.duration
    }

    fn motion_cost_heuristic(&self, a: &[Vec2], b: &[Vec2]) -> f64 {
        (centroid(a) - centroid(b)).norm() / self.max_centroid_speed
    }

    fn cost_to_go(&self, s: &[Vec2], goal: &Goal) -> f64 {
        // every agent within tol of its goal centre puts the centroid within tol of theirs
        ((centroid(s) - centroid(&goal.agents)).norm() - goal.tolerance).max(0.0)
            / self.max_centroid_speed
    }
}

/// Control effort: `∫ (G_x² + G_y²) / G_max² dt` (s), the normalised squared gradient — the
/// Maxwell coils' power. Holding a field without a gradient costs nothing; the heuristics are 0.
#[derive(Debug, Clone, Copy)]
pub struct ControlEffort {
    /// The coil's gradient limit (T/m).
    pub gradient_limit: f64,
}

impl Objective for ControlEffort {
    fn name(&self) -> &str {
        "control-effort"
    }

    fn motion_cost(&self, m: &Motion) -> f64 {
        let [gx, gy] = m.control.grad;
        m.duration * (gx * gx + gy * gy) / (self.gradient_limit * self.gradient_limit)
    }

    fn motion_cost_heuristic(&self, _a: &[Vec2], _b: &[Vec2]) -> f64 {
        0.0
    }

    fn cost_to_go(&self, _s: &[Vec2], _goal: &Goal) -> f64 {
        0.0
    }
}

/// Names of the objectives [`objective_by_name`] knows.
pub const OBJECTIVES: [&str; 3] = ["path-length", "duration", "control-effort"];

/// The objective called `name` for a planning model (its coil limit and pull speed).
pub fn objective_by_name(name: &str, model: &PlanningModel) -> Option<Arc<dyn Objective>> {
    let g = model.coil.gradient_limit();
    match name {
        "path-length" => Some(Arc::new(PathLength)),
        "duration" => Some(Arc::new(Duration {
            max_centroid_speed: model.kinematics.pull_coeff * g,
        })),
        "control-effort" => Some(Arc::new(ControlEffort { gradient_limit: g })),
        _ => None,
    }
}

/// The cost of `plan` under `problem`'s objective, from a replay of its controls from its first
/// state with the plan's flow (each edge's path length measured as planners measure it,
/// [`PlanningModel::path_length`]).
pub fn plan_cost(problem: &crate::Problem, plan: &crate::Plan) -> f64 {
    let model = problem.model.with_flow(plan.flow);
    let mut state = plan.states[0].clone();
    let mut next = state.clone();
    let mut cost = 0.0;
    for (u, &d) in plan.controls.iter().zip(&plan.durations) {
        let length = model.path_length(&state, u, d);
        model.propagate(&state, u, d, &mut next);
        cost += problem.objective.motion_cost(&Motion {
            control: *u,
            duration: d,
            path_length: length,
        });
        std::mem::swap(&mut state, &mut next);
    }
    cost
}
