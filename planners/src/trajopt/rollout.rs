//! An iterate of the optimiser: controls and durations, the states the planning model's flow
//! takes them through from the start, their cost, their violations and whether they are a
//! valid plan.

use magbench_env::math::max_agent_distance;
use magbench_env::{Control, MAX_AGENTS, Vec2};

use crate::motion::propagate_checked;
use crate::objective::Motion;
use crate::{Plan, Problem};

/// Where a rollout must end.
#[derive(Debug, Clone, PartialEq)]
pub enum End {
    /// In the problem's goal region.
    Goal,
    /// On this state, within [`LANDING`] (a window of a longer plan whose rest replays from
    /// there).
    Land(Vec<Vec2>),
}

/// How far (BL, any agent) a window may end from the state it must land on: the rounding of
/// the flow's arithmetic, so that the rest of the plan replays from it as from the old state.
pub const LANDING: f64 = 1e-11;

/// Controls and durations with their replay from a start.
#[derive(Debug, Clone)]
pub struct Rollout {
    /// Where it must end.
    pub end: End,
    /// The control of each edge.
    pub controls: Vec<Control>,
    /// The duration of each edge (s).
    pub durations: Vec<f64>,
    /// The start and the end of every edge.
    pub states: Vec<Vec<Vec2>>,
    /// The objective's cost of each edge.
    pub edge_costs: Vec<f64>,
    /// The violations at each waypoint after the start (BL; see `violation`).
    pub waypoint_violations: Vec<f64>,
    /// The objective's cost of the edges.
    pub cost: f64,
    /// The violations at the waypoints (BL): walls and proximity range by the margin, the goal
    /// by its tolerance less the margin; infinite when the rollout diverged.
    pub violation: f64,
    /// Every edge passes the checked propagation.
    pub valid: bool,
    /// The edges before the first that fails the checked propagation (all of them when
    /// valid).
    pub valid_edges: usize,
    /// Every edge is valid and the rollout ends where it must.
    pub feasible: bool,
}

impl Rollout {
    /// Replays `controls` held for `durations` from `start`. Each edge is solved and checked as
    /// EXTEND's are; an invalid edge is solved again without checks, so that the rollout goes
    /// on to the end. Once an edge starts from a state the flow is not defined at (not finite,
    /// or two agents at one point: a pair the unchecked flow collapsed, whose force is
    /// infinite), the rollout has diverged: its later waypoints repeat that state without
    /// solving the flow, and its violation is infinite.
    pub fn run(
        problem: &Problem,
        start: &[Vec2],
        controls: Vec<Control>,
        durations: Vec<f64>,
        end: End,
        margin: f64,
    ) -> Self {
        let n = problem.agents();
        let mut states = Vec::with_capacity(controls.len() + 1);
        states.push(start.to_vec());
        let mut out = [Vec2::zeros(); MAX_AGENTS];
        let mut edge_costs = Vec::with_capacity(controls.len());
        let mut valid = true;
        let mut valid_edges = 0;
        let mut diverged = false;
        for (u, &d) in controls.iter().zip(&durations) {
            let from = states.last().expect("the start");
            diverged |= !is_finite(from) || coincide(from);
            let path_length = if diverged {
                valid = false;
                out[..n].copy_from_slice(from);
                f64::NAN
            } else {
                match propagate_checked(problem, from, u, d, &mut out[..n]) {
                    Some(length) => {
                        valid_edges += usize::from(valid);
                        length
                    }
                    None => {
                        valid = false;
                        problem.model.propagate(from, u, d, &mut out[..n]);
                        problem.model.path_length(from, u, d)
                    }
                }
            };
            edge_costs.push(problem.objective.motion_cost(&Motion {
                control: *u,
                duration: d,
                path_length,
            }));
            states.push(out[..n].to_vec());
        }
        let last = states.last().expect("the start");
        diverged |= !is_finite(last);
        let arrived = match &end {
            End::Goal => problem.goal.contains(last),
            End::Land(target) => max_agent_distance(last, target) <= LANDING,
        };
        let feasible = valid && arrived;
        let waypoint_violations: Vec<f64> = states[1..]
            .iter()
            .map(|s| state_violation(problem, s, margin))
            .collect();
        let violation = if diverged {
            f64::INFINITY
        } else {
            waypoint_violations.iter().sum::<f64>() + end_violation(problem, &end, last, margin)
        };
        Rollout {
            end,
            controls,
            durations,
            states,
            cost: edge_costs.iter().sum(),
            edge_costs,
            waypoint_violations,
            violation,
            valid,
            valid_edges,
            feasible,
        }
    }

    /// The rollout with its edges from `k` on held under `controls` instead (the same
    /// durations), replayed from its waypoint `k`; the edges before `k` are kept as they are.
    pub fn resumed(
        &self,
        problem: &Problem,
        k: usize,
        controls: Vec<Control>,
        margin: f64,
    ) -> Self {
        let rest = Rollout::run(
            problem,
            &self.states[k],
            controls,
            self.durations[k..].to_vec(),
            self.end.clone(),
            margin,
        );
        let join = |a: &[f64], b: &[f64]| [a, b].concat();
        let prefix_valid = self.valid_edges >= k;
        let edge_costs = join(&self.edge_costs[..k], &rest.edge_costs);
        let waypoint_violations = join(&self.waypoint_violations[..k], &rest.waypoint_violations);
        let prefix_violation: f64 = self.waypoint_violations[..k].iter().sum();
        Rollout {
            end: rest.end,
            controls: [&self.controls[..k], &rest.controls[..]].concat(),
            durations: self.durations.clone(),
            states: [&self.states[..k], &rest.states[..]].concat(),
            cost: edge_costs.iter().sum(),
            edge_costs,
            waypoint_violations,
            violation: prefix_violation + rest.violation,
            valid: prefix_valid && rest.valid,
            valid_edges: if prefix_valid {
                k + rest.valid_edges
            } else {
                self.valid_edges
            },
            feasible: prefix_valid && rest.feasible,
        }
    }

    /// Number of edges.
    pub fn edges(&self) -> usize {
        self.controls.len()
    }

    /// The merit `cost + penalty · violation`.
    pub fn merit(&self, penalty: f64) -> f64 {
        self.cost + penalty * self.violation
    }

    /// The controls moved by `delta` (per edge: field angle, gradient x, gradient y), the
    /// gradients clamped to `±gradient_limit`.
    pub fn stepped(&self, delta: &[[f64; 3]], gradient_limit: f64) -> Vec<Control> {
        self.controls
            .iter()
            .zip(delta)
            .map(|(u, d)| Control {
                theta: u.theta + d[0],
                alpha: u.alpha,
                grad: [
                    (u.grad[0] + d[1]).clamp(-gradient_limit, gradient_limit),
                    (u.grad[1] + d[2]).clamp(-gradient_limit, gradient_limit),
                ],
            })
            .collect()
    }

    /// The same durations under `controls`, replayed from the same start.
    pub fn rerun(&self, problem: &Problem, controls: Vec<Control>, margin: f64) -> Self {
        self.resumed(problem, 0, controls, margin)
    }

    /// The rollout as a plan of `problem`'s flow, its first `edges` edges.
    pub fn plan(&self, problem: &Problem, edges: usize) -> Plan {
        let mut plan = Plan::at(&self.states[0]);
        plan.flow = problem.model.flow;
        for k in 0..edges.min(self.edges()) {
            plan.push(
                self.controls[k],
                self.durations[k],
                self.states[k + 1].clone(),
            );
        }
        plan
    }

    /// Its valid part up to the waypoint closest to the goal: the closest approach of a rollout
    /// that is not feasible, as a plan.
    pub fn closest_approach(&self, problem: &Problem) -> Plan {
        let closest = (0..=self.valid_edges)
            .min_by(|&a, &b| {
                let d = |k: usize| problem.goal.distance(&self.states[k]);
                d(a).total_cmp(&d(b))
            })
            .unwrap_or(0);
        self.plan(problem, closest)
    }
}

/// Every coordinate of `s` is finite.
fn is_finite(s: &[Vec2]) -> bool {
    s.iter().all(|p| p.x.is_finite() && p.y.is_finite())
}

/// Whether two agents of `s` are at one point.
fn coincide(s: &[Vec2]) -> bool {
    s.iter()
        .enumerate()
        .any(|(i, p)| s[i + 1..].iter().any(|q| q == p))
}

/// How far state `s` is inside a wall's margin or outside the proximity range less the margin,
/// summed over agents and pairs (BL).
pub fn state_violation(problem: &Problem, s: &[Vec2], margin: f64) -> f64 {
    let checker = &problem.checker;
    let walls: f64 = s
        .iter()
        .map(|p| (margin - checker.collision.clearance(*p)).max(0.0))
        .sum();
    let mut range = 0.0;
    for i in 0..s.len() {
        for j in i + 1..s.len() {
            let r = (s[j] - s[i]).norm();
            range += (checker.r_min + margin - r).max(0.0) + (r - checker.r_max + margin).max(0.0);
        }
    }
    walls + range
}

/// The goal's tolerance less `margin`, at least half the tolerance (BL).
pub fn goal_radius(problem: &Problem, margin: f64) -> f64 {
    (problem.goal.tolerance - margin).max(0.5 * problem.goal.tolerance)
}

/// The centres each agent must end near and the radius about them (BL): the goal disks
/// shrunk to [`goal_radius`], or the state to land on.
pub fn end_disks<'a>(problem: &'a Problem, end: &'a End, margin: f64) -> (&'a [Vec2], f64) {
    match end {
        End::Goal => (&problem.goal.agents, goal_radius(problem, margin)),
        End::Land(target) => (target, 0.0),
    }
}

/// How far the agents of `s` are outside their [`end_disks`], summed (BL).
pub fn end_violation(problem: &Problem, end: &End, s: &[Vec2], margin: f64) -> f64 {
    let (centres, radius) = end_disks(problem, end, margin);
    s.iter()
        .zip(centres)
        .map(|(p, g)| ((p - g).norm() - radius).max(0.0))
        .sum()
}
