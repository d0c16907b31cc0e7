//! Shortcutting by exact steering: a post-processing pass any planner's solution can go
//! through (docs/steering.md).
//!
//! Each round picks two waypoints `i < j − 1` of the plan at random, at most [`MAX_SPAN`]
//! edges apart, and asks env's
//! `steer_pair` for commands from waypoint `i` onto waypoint `j`. The steer replaces edges
//! `i..j` when every one of its edges passes the same checked propagation as EXTEND's, the
//! rest of the plan, replayed from where the steer ends (within 1e-6 BL of waypoint `j`), stays
//! valid and ends in the goal, and the new edges cost less than the old ones under the
//! problem's objective. The result replays bit for bit like any plan. Pairs under the exact flow
//! only; other plans come back unchanged.

use magbench_env::model::{SteerLimits, steer_pair};
use magbench_env::{MAX_AGENTS, Vec2};
use rand::RngExt;

use crate::motion::propagate_valid;
use crate::objective::Motion;
use crate::{Plan, Problem, Rng};

/// Largest miss of a steer (BL, any agent) onto a waypoint.
const STEER_TOLERANCE: f64 = 1e-6;

/// The most edges one shortcut replaces: a steer covers a few body lengths of the centre's
/// travel (the pull is slow), so longer spans almost never connect.
const MAX_SPAN: usize = 12;

/// Shortcut settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shortcut {
    /// Rounds (random waypoint pairs tried).
    pub rounds: usize,
    /// The longest steered edge, in control periods.
    pub max_periods: u32,
}

impl Shortcut {
    /// The plan shortened; `plan` itself when nothing shorter was found or it is not a pair's
    /// plan under the problem's exact flow. `plan` must be valid for `problem`.
    pub fn run(&self, problem: &Problem, plan: &Plan, rng: &mut Rng) -> Plan {
        self.run_with_stats(problem, plan, rng).0
    }

    /// [`Shortcut::run`] with its work counts.
    pub fn run_with_stats(&self, problem: &Problem, plan: &Plan, rng: &mut Rng) -> (Plan, Stats) {
        let mut st = Stats::default();
        if problem.agents() != 2 || plan.flow != problem.model.flow || plan.elevation_free() {
            return (plan.clone(), st);
        }
        let limits = SteerLimits {
            period: problem.control_period,
            max_periods: self.max_periods,
            separation: [problem.checker.r_min, problem.checker.r_max],
            tolerance: STEER_TOLERANCE,
        };
        let mut best = plan.clone();
        let mut costs: Vec<f64> = (0..best.edges())
            .map(|k| edge_cost(problem, &best, k))
            .collect();
        for _ in 0..self.rounds {
            let m = best.edges();
            if m < 2 {
                break;
            }
            let i = rng.random_range(0..m - 1);
            let j = rng.random_range(i + 2..=(i + MAX_SPAN).min(m));
            let old: f64 = costs[i..j].iter().sum();
            let mut candidate = None;
            st.rounds += 1;
            let mut why = Why::NoSteer;
            let t0 = std::time::Instant::now();
            let mut in_accept = std::time::Duration::ZERO;
            steer_pair(
                &problem.model,
                &best.states[i],
                &best.states[j],
                &limits,
                |edges| {
                    let ta = std::time::Instant::now();
                    st.candidates += 1;
                    let r = (|| {
                    let mut next = Plan::at(&best.states[0]);
                    next.flow = best.flow;
                    for k in 0..i {
                        next.push(
                            best.controls[k],
                            best.durations[k],
                            best.states[k + 1].clone(),
                        );
                    }
                    let mut new_costs = costs[..i].to_vec();
                    let mut at = best.states[i].clone();
                    let mut out = [Vec2::zeros(); MAX_AGENTS];
                    let tail = best.controls[j..].iter().zip(&best.durations[j..]);
                    let steered = edges
                        .iter()
                        .map(|e| (e.control, problem.periods(e.periods)));
                    for (step, (u, d)) in steered.chain(tail.map(|(u, d)| (*u, *d))).enumerate() {
                        if step < edges.len() { st.steer_props += 1; } else { st.tail_props += 1; }
                        if !propagate_valid(problem, &at, &u, d, &mut out[..2]) {
                            why = if step < edges.len() { Why::SteerCollides } else { Why::TailInvalid };
                            return false;
                        }
                        next.push(u, d, out[..2].to_vec());
                        new_costs.push(motion_cost(problem, &at, &u, d));
                        at.copy_from_slice(&out[..2]);
                        if step + 1 == edges.len() && new_costs[i..].iter().sum::<f64>() >= old {
                            why = Why::NotCheaper;
                            return false;
                        }
                    }
                    if !problem.goal.contains(&at) {
                        why = Why::MissesGoal;
                        return false;
                    }
                    why = Why::Accepted;
                    candidate = Some((next, new_costs));
                    true
                    })();
                    in_accept += ta.elapsed();
                    r
                },
            );
            st.steer_time += t0.elapsed() - in_accept;
            st.check_time += in_accept;
            st.outcome[why as usize] += 1;
            if matches!(why, Why::NoSteer) {
                st.no_steer_time += t0.elapsed();
            }
            if let Some((next, new_costs)) = candidate {
                best = next;
                costs = new_costs;
            }
        }
        best.alpha_max = plan.alpha_max;
        (best, st)
    }
}

/// How a round ended (the last candidate's verdict).
#[derive(Debug, Clone, Copy)]
pub enum Why {
    /// No steer found.
    NoSteer,
    /// A steered edge is invalid.
    SteerCollides,
    /// The steer costs no less.
    NotCheaper,
    /// The replayed tail is invalid.
    TailInvalid,
    /// The replayed tail misses the goal.
    MissesGoal,
    /// Accepted.
    Accepted,
}

/// Work counts of a pass.
#[derive(Debug, Clone, Default)]
pub struct Stats {
    /// Rounds run.
    pub rounds: usize,
    /// Steers offered to the check.
    pub candidates: usize,
    /// Propagations of steered edges.
    pub steer_props: usize,
    /// Propagations of replayed tail edges.
    pub tail_props: usize,
    /// Rounds by outcome, indexed by [`Why`].
    pub outcome: [usize; 6],
    /// Time in the steer solver.
    pub steer_time: std::time::Duration,
    /// Time of rounds without a steer.
    pub no_steer_time: std::time::Duration,
    /// Time in the checks.
    pub check_time: std::time::Duration,
}

/// The objective's cost of edge `k` of `plan`.
fn edge_cost(problem: &Problem, plan: &Plan, k: usize) -> f64 {
    motion_cost(
        problem,
        &plan.states[k],
        &plan.controls[k],
        plan.durations[k],
    )
}

/// The objective's cost of one motion.
fn motion_cost(problem: &Problem, from: &[Vec2], u: &magbench_env::Control, d: f64) -> f64 {
    problem.objective.motion_cost(&Motion {
        control: *u,
        duration: d,
        path_length: problem.model.path_length(from, u, d),
    })
}
