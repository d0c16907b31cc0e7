//! Repair: a replan that starts from the plan being followed instead of from nothing
//! (docs/replanning.md).
//!
//! The team has drifted off its plan and a new plan must start at the observed state. Repair
//! looks for one in the remaining plan, cheapest first; the caller plans from scratch only
//! when both ways fail:
//!
//! 1. **Rejoin**: the remaining controls, from the plan's waypoint nearest the team, replayed
//!    from the observed state; then, for a pair under the exact flow, env's `steer_pair` onto
//!    each of the next `ahead` waypoints in turn, followed by the rest of the plan replayed
//!    from where the steer ends (within 1e-6 BL of the waypoint).
//! 2. **Tree**: an RRT from the observed state of at most `iterations` iterations whose goal
//!    region is the remaining plan's waypoints, not only the final goal: samples are drawn
//!    about the waypoints ahead of the team, and each new node that comes closer to the plan
//!    than every earlier node tries the rejoin from where it is.
//!
//! A candidate is accepted only when each of its edges passes EXTEND's checked propagation
//! ([`propagate_valid`]) and the replay ends in the problem's goal region, so the spliced plan
//! replays bit for bit like any plan; the caller still puts it through
//! [`crate::validate_result`]. Repair draws from the problem's seed only: with no time limit it is
//! deterministic.

use std::time::Instant;

use magbench_env::model::steer_pair;
use magbench_env::{MAX_AGENTS, Vec2};
use rand::{RngExt, SeedableRng};

use crate::extend::Extend;
use crate::motion::{propagate_valid, replay_onto};
use crate::nn::NearestNeighbors;
use crate::objective::plan_cost;
use crate::sampler::{SAMPLE_TRIES, in_disk, valid_sample};
use crate::tree::Tree;
use crate::{Plan, PlannerResult, Problem, Rng};

/// Radius of each agent's disk about a waypoint ahead, where the tree samples (BL).
const SAMPLE_RADIUS: f64 = 1.0;

/// A tree node tries the rejoin only within this distance of the plan (BL, the metric's).
const JOIN_RADIUS: f64 = 3.0;

/// Repair settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Repair {
    /// The tree's EXTEND (its tries and duration range); its longest edge is also the
    /// longest steered edge.
    pub extend: Extend,
    /// The tree's iterations at most (0: no tree).
    pub iterations: u64,
    /// Waypoints ahead of the nearest one that the rejoin steers onto, nearest first.
    pub ahead: usize,
}

/// How a repair found its plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RepairHow {
    /// By rejoining the plan from the observed state.
    Rejoin,
    /// By a tree from the observed state onto the plan.
    Tree,
}

/// What a repair did: the result when it found a plan, and its work (load-independent).
#[derive(Debug, Clone)]
pub struct Repaired {
    /// A solved result with a plan from the problem's start into its goal, and how it was
    /// found; `None` when both ways failed.
    pub found: Option<(PlannerResult, RepairHow)>,
    /// Rejoins tried (each a replay of the remaining plan, after a steer or none).
    pub rejoins: u64,
    /// Tree iterations run.
    pub iterations: u64,
    /// Edges propagated and checked: the tree's, the steers' and the replayed ones.
    pub edges: u64,
}

impl Repair {
    /// Repairs `plan` (the plan being followed, made under `problem`'s model and flow) into a
    /// plan from `problem.start` into `problem.goal`.
    pub fn run(&self, problem: &Problem, plan: &Plan) -> Repaired {
        let started = Instant::now();
        let mut out = Repaired {
            found: None,
            rejoins: 0,
            iterations: 0,
            edges: 0,
        };
        let n = problem.agents();
        let fits = plan.flow == problem.model.flow
            && plan.states.iter().all(|s| s.len() == n)
            && plan.states.len() == plan.controls.len() + 1
            && plan.controls.len() == plan.durations.len()
            && problem.checker.is_valid(&problem.start);
        if !fits {
            return out;
        }
        let mut root = Plan::at(&problem.start);
        root.flow = plan.flow;
        let near = nearest_waypoint(problem, plan, &problem.start, 0);
        if let Some(p) = self.rejoin(problem, &root, plan, near, &mut out) {
            out.found = Some((
                self.result(problem, plan, p, &out, 1, started),
                RepairHow::Rejoin,
            ));
            return out;
        }
        if let Some((p, nodes)) = self.tree(problem, plan, near, &mut out) {
            out.found = Some((
                self.result(problem, plan, p, &out, nodes, started),
                RepairHow::Tree,
            ));
        }
        out
    }

    /// The rejoin from the end of `head` (a plan from the problem's start): the remaining
    /// controls from waypoint `near` replayed, then steers onto the next `ahead` waypoints.
    fn rejoin(
        &self,
        problem: &Problem,
        head: &Plan,
        plan: &Plan,
        near: usize,
        work: &mut Repaired,
    ) -> Option<Plan> {
        work.rejoins += 1;
        if let Some(p) = replay_rest(problem, head.clone(), plan, near, &mut work.edges) {
            return Some(p);
        }
        if problem.agents() != 2 {
            return None;
        }
        let limits = problem.steer_limits(self.extend.max_periods);
        let from: Vec<Vec2> = head.end().to_vec();
        let last = plan.edges().min(near + self.ahead);
        for j in near + 1..=last {
            work.rejoins += 1;
            let mut found = None;
            let mut replayed = false;
            steer_pair(&problem.model, &from, &plan.states[j], &limits, |edges| {
                if replayed {
                    // every steer ends within the tolerance of waypoint j: the rest of the
                    // plan replays alike from each, so one replay decides for all
                    return true;
                }
                let steered = edges
                    .iter()
                    .map(|e| (e.control, problem.periods(e.periods)));
                let counted = steered.inspect(|_| work.edges += 1);
                let Some(p) = replay_onto(problem, head.clone(), counted) else {
                    return false;
                };
                replayed = true;
                found = replay_rest(problem, p, plan, j, &mut work.edges);
                true
            });
            if found.is_some() {
                return found;
            }
        }
        None
    }

    /// The tree from the problem's start onto the remaining plan (from waypoint `near`): the
    /// plan found and the tree's size.
    fn tree(
        &self,
        problem: &Problem,
        plan: &Plan,
        near: usize,
        out: &mut Repaired,
    ) -> Option<(Plan, usize)> {
        if self.iterations == 0 {
            return None;
        }
        let n = problem.agents();
        let mut rng = Rng::seed_from_u64(problem.seed);
        let mut tree = Tree::new(&problem.start);
        let mut nn = NearestNeighbors::new(problem.metric, n);
        nn.add(&problem.start, 0);
        let window = near..=plan.edges().min(near + 2 * self.ahead.max(1));
        let mut closest = waypoint_distance(problem, plan, &problem.start, near);
        let mut q_sample = [Vec2::zeros(); MAX_AGENTS];
        let mut q_new = [Vec2::zeros(); MAX_AGENTS];
        while out.iterations < self.iterations {
            out.iterations += 1;
            let j = rng.random_range(window.clone());
            let sampled = valid_sample(problem, SAMPLE_TRIES, &mut q_sample[..n], |s| {
                for (p, w) in s.iter_mut().zip(&plan.states[j]) {
                    *p = in_disk(&mut rng, *w, SAMPLE_RADIUS);
                }
            });
            if !sampled {
                continue;
            }
            let (parent, _) = nn.nearest(&q_sample[..n]).expect("the tree has its root");
            let ext = self
                .extend
                .run(problem, &mut rng, tree.state(parent), &q_sample[..n]);
            let d = problem.periods(ext.periods);
            out.edges += 1;
            if ext.periods == 0
                || !propagate_valid(
                    problem,
                    tree.state(parent),
                    &ext.control,
                    d,
                    &mut q_new[..n],
                )
            {
                continue;
            }
            let id = tree.add(parent, &q_new[..n], ext.control, ext.periods, 0.0);
            nn.add(&q_new[..n], id);
            let at = nearest_waypoint(problem, plan, &q_new[..n], near);
            let dist = problem.metric.distance(&q_new[..n], &plan.states[at]);
            if dist < closest && dist <= JOIN_RADIUS {
                closest = dist;
                let head = tree.plan_to(id, problem);
                if let Some(p) = self.rejoin(problem, &head, plan, at, out) {
                    return Some((p, tree.len()));
                }
            }
        }
        None
    }

    /// The solved result of a repaired plan `p` of `plan`.
    fn result(
        &self,
        problem: &Problem,
        plan: &Plan,
        mut p: Plan,
        work: &Repaired,
        nodes: usize,
        started: Instant,
    ) -> PlannerResult {
        p.alpha_max = plan.alpha_max;
        let iterations = work.rejoins + work.iterations;
        let time_s = started.elapsed().as_secs_f64();
        PlannerResult {
            solved: true,
            approximate: false,
            goal_distance: problem.goal.distance(p.end()),
            cost: Some(plan_cost(problem, &p)),
            plan: p,
            iterations,
            nodes,
            time_s,
            first_solution: Some((iterations, time_s)),
            progress: Vec::new(),
        }
    }
}

/// `head` followed by `plan`'s controls from waypoint `j` on, replayed from `head`'s end;
/// `None` when an edge is invalid or the replay does not end in the goal region. Each edge
/// replayed is counted in `edges`.
fn replay_rest(
    problem: &Problem,
    head: Plan,
    plan: &Plan,
    j: usize,
    edges: &mut u64,
) -> Option<Plan> {
    let rest = plan.controls[j..]
        .iter()
        .copied()
        .zip(plan.durations[j..].iter().copied());
    let head = replay_onto(problem, head, rest.inspect(|_| *edges += 1))?;
    (head.edges() > 0 && problem.goal.contains(head.end())).then_some(head)
}

/// The waypoint of `plan` from `from` on nearest to `s` under the problem's metric (the first
/// on ties).
fn nearest_waypoint(problem: &Problem, plan: &Plan, s: &[Vec2], from: usize) -> usize {
    let mut best = (from, f64::INFINITY);
    for (j, w) in plan.states.iter().enumerate().skip(from) {
        let d = problem.metric.distance_squared(s, w);
        if d < best.1 {
            best = (j, d);
        }
    }
    best.0
}

/// The metric distance from `s` to waypoint `j` of `plan`.
fn waypoint_distance(problem: &Problem, plan: &Plan, s: &[Vec2], j: usize) -> f64 {
    problem.metric.distance(s, &plan.states[j])
}

#[cfg(test)]
#[path = "repair_tests.rs"]
mod tests;
