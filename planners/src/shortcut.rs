//! Shortcutting by exact steering: a post-processing pass any planner's solution can go
//! through (docs/steering.md).
//!
//! The pass sweeps the plan from start to goal, rebuilding it as it goes. At old waypoint `k`,
//! reached at state `at` (within a few 1e-6 BL of it), it asks env's `steer_pair` for commands
//! from `at` onto old waypoint `k + s` for each span `s` of a descending ladder; the first steer
//! whose edges all pass the same checked propagation as EXTEND's and cost less under the
//! problem's objective than old edges `k..k + s` is appended, and the sweep goes on from
//! waypoint `k + s`. When no span steers, old edge `k` is replayed from `at`. Each steer lands
//! within 1e-6 BL of an old waypoint, so the replayed edges drift only between steers and the
//! rest of the plan is replayed once per sweep, not once per steer. If a replayed edge turns
//! invalid, a steer onto one of the next old waypoints, at any cost, takes its place; if none
//! does, or the sweep's plan misses the goal, the sweep is dropped.
//!
//! Runs of consecutive edges under one command (a planner such as OMPL's returns one edge per
//! control period) are first replayed as one edge each, so that spans count commands.
//!
//! Sweeps repeat on the shorter plan until one finds nothing or `rounds` steer solves have been
//! spent: the work is a count, so the result depends only on the plan and the problem. The
//! result replays bit for bit like any plan and never costs more than the input. Pairs under
//! the exact flow only; other plans come back unchanged.

use magbench_env::model::{SteerEdge, SteerLimits, steer_pair};
use magbench_env::{Control, MAX_AGENTS, Vec2};

use crate::motion::{propagate_checked, propagate_valid, replay_onto};
use crate::objective::{Motion, plan_cost};
use crate::{Plan, Problem};

/// Spans (edges replaced) tried at each waypoint, longest first.
pub const SPANS: [usize; 3] = [12, 6, 3];

/// Old waypoints ahead (2 up to this many edges) a steer may aim at when a replayed edge is
/// invalid.
const REANCHOR_SPAN: usize = 6;

/// Shortcut settings.
#[derive(Debug, Clone, PartialEq)]
pub struct Shortcut {
    /// The most steer solves (rounds) the pass spends.
    pub rounds: usize,
    /// The longest steered edge, in control periods.
    pub max_periods: u32,
    /// Spans tried at each waypoint, longest first ([`SPANS`]).
    pub spans: Vec<usize>,
}

/// Work counts of a pass.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Stats {
    /// Sweeps run (the last may be dropped).
    pub sweeps: usize,
    /// Steer solves (rounds) spent.
    pub rounds: usize,
    /// Solves without a steer within the limits.
    pub no_steer: usize,
    /// Steers refused: an edge is invalid.
    pub invalid: usize,
    /// Steers refused: they cost no less than the edges they replace.
    pub not_cheaper: usize,
    /// Steers appended.
    pub accepted: usize,
    /// Propagations of steered edges.
    pub steer_propagations: usize,
    /// Propagations of replayed old edges.
    pub replay_propagations: usize,
    /// Replayed edges that turned invalid.
    pub replay_invalid: usize,
    /// Sweeps dropped (an edge could not be replaced, or the goal was missed).
    pub dropped: usize,
}

impl Shortcut {
    /// The pass with [`SPANS`].
    pub fn new(rounds: usize, max_periods: u32) -> Self {
        Shortcut {
            rounds,
            max_periods,
            spans: SPANS.to_vec(),
        }
    }

    /// The plan shortened; `plan` itself when nothing shorter was found or it is not a pair's
    /// plan under the problem's exact flow. `plan` must be valid for `problem`.
    pub fn run(&self, problem: &Problem, plan: &Plan) -> Plan {
        self.run_with_stats(problem, plan).0
    }

    /// [`Shortcut::run`] with its work counts.
    pub fn run_with_stats(&self, problem: &Problem, plan: &Plan) -> (Plan, Stats) {
        let mut stats = Stats::default();
        if problem.agents() != 2 || plan.flow != problem.model.flow || plan.elevation_free() {
            return (plan.clone(), stats);
        }
        let limits = problem.steer_limits(self.max_periods);
        let input_cost = plan_cost(problem, plan);
        let mut best = merge_runs(problem, plan).unwrap_or_else(|| plan.clone());
        let mut best_cost = plan_cost(problem, &best);
        while stats.rounds < self.rounds {
            stats.sweeps += 1;
            let Some(next) = self.sweep(problem, &best, &limits, &mut stats) else {
                stats.dropped += 1;
                break;
            };
            let cost = plan_cost(problem, &next);
            if cost >= best_cost {
                break;
            }
            best = next;
            best_cost = cost;
        }
        if best_cost >= input_cost {
            return (plan.clone(), stats);
        }
        best.alpha_max = plan.alpha_max;
        (best, stats)
    }

    /// One sweep over `plan`: its rebuilt plan if that ends in the goal.
    fn sweep(
        &self,
        problem: &Problem,
        plan: &Plan,
        limits: &SteerLimits,
        stats: &mut Stats,
    ) -> Option<Plan> {
        let m = plan.edges();
        let costs: Vec<f64> = (0..m).map(|k| edge_cost(problem, plan, k)).collect();
        let mut next = Plan::at(&plan.states[0]);
        next.flow = plan.flow;
        let mut at = plan.states[0].clone();
        let mut out = [Vec2::zeros(); MAX_AGENTS];
        let mut k = 0;
        while k < m {
            let mut stepped = None;
            for &span in &self.spans {
                if stats.rounds >= self.rounds {
                    break;
                }
                if span < 2 || k + span > m {
                    continue;
                }
                let old: f64 = costs[k..k + span].iter().sum();
                let target = &plan.states[k + span];
                if let Some(steer) = self.steer(problem, &at, target, limits, Some(old), stats) {
                    stepped = Some((span, steer));
                    break;
                }
            }
            if stepped.is_none() {
                stats.replay_propagations += 1;
                let (u, d) = (plan.controls[k], plan.durations[k]);
                if propagate_valid(problem, &at, &u, d, &mut out[..2]) {
                    next.push(u, d, out[..2].to_vec());
                    at.copy_from_slice(&out[..2]);
                    k += 1;
                    continue;
                }
                stats.replay_invalid += 1;
                stepped = (2..=REANCHOR_SPAN.min(m - k)).find_map(|span| {
                    let target = &plan.states[k + span];
                    let steer = self.steer(problem, &at, target, limits, None, stats)?;
                    Some((span, steer))
                });
            }
            let (span, steer) = stepped?;
            for (u, d, end) in steer {
                next.push(u, d, end);
            }
            at.copy_from_slice(next.end());
            k += span;
        }
        problem.goal.contains(&at).then_some(next)
    }

    /// A steer from `from` onto `to` whose edges are valid and, when `old` is given, cost
    /// less than `old`: its (command, duration, end) edges. Spends one round.
    #[allow(clippy::type_complexity)]
    fn steer(
        &self,
        problem: &Problem,
        from: &[Vec2],
        to: &[Vec2],
        limits: &SteerLimits,
        old: Option<f64>,
        stats: &mut Stats,
    ) -> Option<Vec<(Control, f64, Vec<Vec2>)>> {
        stats.rounds += 1;
        let mut offered = false;
        let mut found = None;
        steer_pair(&problem.model, from, to, limits, |edges: &[SteerEdge]| {
            offered = true;
            let mut at = from.to_vec();
            let mut out = [Vec2::zeros(); MAX_AGENTS];
            let mut cost = 0.0;
            let mut steered = Vec::with_capacity(edges.len());
            for e in edges {
                let d = problem.periods(e.periods);
                stats.steer_propagations += 1;
                let Some(c) = checked_motion_cost(problem, &at, &e.control, d, &mut out[..2])
                else {
                    stats.invalid += 1;
                    return false;
                };
                cost += c;
                if old.is_some_and(|old| cost >= old) {
                    stats.not_cheaper += 1;
                    return false;
                }
                steered.push((e.control, d, out[..2].to_vec()));
                at.copy_from_slice(&out[..2]);
            }
            stats.accepted += 1;
            found = Some(steered);
            true
        });
        if !offered {
            stats.no_steer += 1;
        }
        found
    }
}

/// `plan` with each run of consecutive edges under one command replayed as one edge (a
/// planner such as OMPL's returns one edge per control period), so that the spans count
/// commands; `None` when no two consecutive edges share a command, or a merged edge fails the
/// checked propagation, or the replay misses the goal.
pub(crate) fn merge_runs(problem: &Problem, plan: &Plan) -> Option<Plan> {
    let m = plan.edges();
    if !(1..m).any(|k| plan.controls[k] == plan.controls[k - 1]) {
        return None;
    }
    let mut runs: Vec<(Control, u32)> = Vec::new();
    for (u, d) in plan.controls.iter().zip(&plan.durations) {
        let periods = (d / problem.control_period).round() as u32;
        match runs.last_mut() {
            Some((v, p)) if v == u => *p += periods,
            _ => runs.push((*u, periods)),
        }
    }
    let mut start = Plan::at(&plan.states[0]);
    start.flow = plan.flow;
    let edges = runs.into_iter().map(|(u, p)| (u, problem.periods(p)));
    let merged = replay_onto(problem, start, edges)?;
    problem.goal.contains(merged.end()).then_some(merged)
}

/// The objective's cost of edge `k` of `plan`.
pub(crate) fn edge_cost(problem: &Problem, plan: &Plan, k: usize) -> f64 {
    motion_cost(
        problem,
        &plan.states[k],
        &plan.controls[k],
        plan.durations[k],
    )
}

/// The objective's cost of one motion from `from`, solved into `out` and checked as EXTEND's
/// are ([`propagate_checked`], which measures the path length on the way); `None` when the
/// motion is invalid.
pub(crate) fn checked_motion_cost(
    problem: &Problem,
    from: &[Vec2],
    u: &Control,
    d: f64,
    out: &mut [Vec2],
) -> Option<f64> {
    let path_length = propagate_checked(problem, from, u, d, out)?;
    Some(problem.objective.motion_cost(&Motion {
        control: *u,
        duration: d,
        path_length,
    }))
}

/// The objective's cost of one motion.
fn motion_cost(problem: &Problem, from: &[Vec2], u: &Control, d: f64) -> f64 {
    problem.objective.motion_cost(&Motion {
        control: *u,
        duration: d,
        path_length: problem.model.path_length(from, u, d),
    })
}
