//! Informed sampling (Gammell, Srinivasa & Barfoot): once a solution of cost `c_best` exists,
//! sample only states that could improve it.
//!
//! A state `x` can improve the solution only if `ĝ(x) + ĥ(x) < c_best`, with `ĝ` the objective's
//! admissible cost-to-come heuristic from the start and `ĥ` its cost-to-go heuristic. For the
//! path-length objective `ĝ(x) + ĥ(x) = Σ_i ‖x_i − s_i‖ + max(0, ‖x_i − g_i‖ − tol)`. Each term
//! is at least `d_i = max(0, ‖s_i − g_i‖ − tol)`, so agent `i` must satisfy
//! `‖x_i − s_i‖ + ‖x_i − g_i‖ < c_best − Σ_{j≠i} d_j + tol`: a prolate ellipse with foci at its
//! start and goal centre. Each agent is drawn uniformly from its ellipse and the team is rejected
//! on the summed heuristic — uniform over the informed set. For other objectives the team is
//! drawn from the fallback sampler and rejected on the same test.

use std::f64::consts::PI;

use magbench_env::Vec2;
use rand::RngExt;

use crate::sampler::{GoalZoom, SAMPLE_TRIES, StateSampler};
use crate::{Problem, Rng};

/// The informed set of one problem.
#[derive(Debug, Clone)]
pub struct InformedSet {
    starts: Vec<Vec2>,
    goals: Vec<Vec2>,
    tolerance: f64,
    /// `d_i`: agent i's smallest possible contribution to the heuristic.
    least: Vec<f64>,
    ellipses: bool,
}

impl InformedSet {
    /// The informed set of `problem` (ellipses when the objective is path length).
    pub fn new(problem: &Problem) -> Self {
        let tol = problem.goal.tolerance;
        let least = problem
            .start
            .iter()
            .zip(&problem.goal.agents)
            .map(|(s, g)| ((s - g).norm() - tol).max(0.0))
            .collect();
        InformedSet {
            starts: problem.start.clone(),
            goals: problem.goal.agents.clone(),
            tolerance: tol,
            least,
            ellipses: problem.objective.is_path_length(),
        }
    }

    /// The heuristic `ĝ(x) + ĥ(x)`: a lower bound on the cost of any solution through `x`.
    pub fn heuristic(&self, problem: &Problem, x: &[Vec2]) -> f64 {
        problem.objective.motion_cost_heuristic(&self.starts, x)
            + problem.objective.cost_to_go(x, &problem.goal)
    }

    /// True when `x` could improve a solution of cost `c_best`.
    pub fn contains(&self, problem: &Problem, x: &[Vec2], c_best: f64) -> bool {
        self.heuristic(problem, x) < c_best
    }

    /// True when per-agent ellipse sampling applies (the path-length objective).
    pub fn uses_ellipses(&self) -> bool {
        self.ellipses
    }

    /// Agent `i`'s ellipse for `c_best`: its semi-axes `(a, b)`, or `None` when it is empty.
    fn semi_axes(&self, i: usize, c_best: f64) -> Option<(f64, f64)> {
        let total: f64 = self.least.iter().sum();
        let focal = (self.goals[i] - self.starts[i]).norm();
        // transverse diameter: ‖x − s‖ + ‖x − g‖ < c_i + tol
        let major = c_best - (total - self.least[i]) + self.tolerance;
        if major.is_nan() || major <= focal {
            return None;
        }
        let a = 0.5 * major;
        Some((a, (a * a - 0.25 * focal * focal).sqrt()))
    }

    /// True when some agent's ellipse for `c_best` is larger than the world: then most ellipse
    /// draws fall outside the map, and drawing from the whole space and rejecting is the more
    /// efficient way to sample the same set (OMPL's direct informed sampler does the same).
    pub fn ellipses_exceed(&self, c_best: f64, world_area: f64) -> bool {
        (0..self.starts.len()).any(|i| {
            self.semi_axes(i, c_best)
                .is_some_and(|(a, b)| PI * a * b > world_area)
        })
    }

    /// Draws each agent uniformly from its prolate ellipse for `c_best` into `out`. False when
    /// some ellipse is empty (no state can improve `c_best`).
    pub fn sample_ellipses(&self, rng: &mut Rng, c_best: f64, out: &mut [Vec2]) -> bool {
        for (i, slot) in out.iter_mut().enumerate() {
            let (s, g) = (self.starts[i], self.goals[i]);
            let focal = (g - s).norm();
            let Some((a, b)) = self.semi_axes(i, c_best) else {
                return false;
            };
            let (cos, sin) = if focal > 0.0 {
                ((g.x - s.x) / focal, (g.y - s.y) / focal)
            } else {
                (1.0, 0.0)
            };
            let rho = rng.random::<f64>().sqrt();
            let t = rng.random_range(-PI..PI);
            let (x, y) = (a * rho * t.cos(), b * rho * t.sin());
            *slot = (s + g) * 0.5 + Vec2::new(cos * x - sin * y, sin * x + cos * y);
        }
        true
    }

    /// Draws a valid sample of the informed set for `c_best` into `out`. The goal-zoom coin
    /// toss is kept (as OMPL's informed RRT* keeps its goal bias): heads draws from the zoom
    /// region, tails from the per-agent ellipses (path length, while no ellipse is larger than
    /// the world) or the whole space (otherwise); either way a draw is rejected unless it is in
    /// the informed set and valid.
    /// False when [`SAMPLE_TRIES`] draws were all rejected.
    pub fn sample(
        &self,
        problem: &Problem,
        rng: &mut Rng,
        sampler: &StateSampler,
        zoom: &GoalZoom,
        c_best: f64,
        out: &mut [Vec2],
    ) -> bool {
        let heads = rng.random::<f64>() < zoom.bias;
        let ellipses = self.uses_ellipses()
            && !self.ellipses_exceed(c_best, problem.world.width * problem.world.height);
        for _ in 0..SAMPLE_TRIES {
            let drawn = if heads {
                sampler.zoom(rng, &problem.goal, zoom.radius, out);
                true
            } else if ellipses {
                self.sample_ellipses(rng, c_best, out)
            } else {
                sampler.uniform(rng, out);
                true
            };
            if drawn && self.contains(problem, out, c_best) && problem.checker.is_valid(out) {
                return true;
            }
        }
        false
    }
}
