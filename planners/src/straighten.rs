//! Straightening the centroid: a local trajectory optimisation any solution can go through
//! after shortcutting (docs/steering.md).
//!
//! Every agent feels the same pull, so the team's relative motion depends on the field alone
//! and the centroid moves at a velocity affine in the gradient commands
//! ([`centroid_map`]). A run of edges can therefore keep its field angles and durations — and so
//! its relative motion, exactly — while its gradients are chosen afresh: the pass chooses them
//! so that the centroid goes from where the run starts to where it ends as straight as the
//! coil's limits allow ([`line_commands`]: per axis one common velocity, clipped where an
//! edge's field cannot reach it: the least `Σ t |v|²` for the run's shift, the straight line at
//! one speed where nothing clips). The run then ends where it did.
//!
//! The pass sweeps the plan from start to goal. At waypoint `k` it tries the run to the goal,
//! then runs half as long, down to two edges; it keeps the first whose edges all pass the same
//! checked propagation as EXTEND's, which ends at the old waypoint ([`LANDING`]), costs less
//! under the problem's objective than the old edges, and after which the old rest of the plan
//! still replays valid into the goal. The relative dynamics are chaotic: a run's rounding,
//! amplified over the rest of a long plan, can carry it out of the goal or into a wall, so the
//! rest is replayed before a run is kept, and those replayed states are the ones later edges
//! start from. When no run is straightened, edge `k` is kept. The result replays bit for bit
//! like any plan and never costs more than the input; a plan whose agents' mobilities differ
//! (no centroid velocity of its own), or whose flow is not the problem's, comes back
//! unchanged. Runs of consecutive edges under one command (OMPL's planners return one edge per
//! control period) are first replayed as one edge each, as the shortcut pass does. The work is
//! a count: the pass stops trying runs after [`WORK_PER_EDGE`] propagations per edge.

use magbench_env::math::{centroid, max_agent_distance};
use magbench_env::{Control, MAX_AGENTS, Vec2};

use crate::motion::{centroid_map, propagate_valid};
use crate::objective::plan_cost;
use crate::shortcut::{checked_motion_cost, edge_cost, merge_runs};
use crate::{Plan, Problem};

/// Work counts of a pass.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Stats {
    /// Runs tried.
    pub tries: usize,
    /// Runs straightened.
    pub accepted: usize,
    /// Edges propagated (straightened, and the old edges after them replayed).
    pub propagations: usize,
    /// Replays of the rest of the plan after a run.
    pub rests: usize,
    /// Runs refused because the rest of the plan, replayed after them, turned invalid or
    /// missed the goal.
    pub rests_failed: usize,
}

/// The most propagations the pass spends, per edge of the plan: a bound on the work of a very
/// long plan (a pass over goal-zoom RRT's micro-factory plans, about 260 edges, spends about 70
/// an edge; `STRAIGHTEN=1 shortcut_profile 0`).
const WORK_PER_EDGE: usize = 100;

/// The plan with its centroid straightened; `plan` itself when nothing cheaper was found.
/// `plan` must be valid for `problem`.
pub fn straighten(problem: &Problem, plan: &Plan) -> Plan {
    straighten_with_stats(problem, plan).0
}

/// [`straighten`] with its work counts.
pub fn straighten_with_stats(problem: &Problem, plan: &Plan) -> (Plan, Stats) {
    let mut stats = Stats::default();
    if plan.flow != problem.model.flow || plan.edges() < 2 {
        return (plan.clone(), stats);
    }
    let merged = merge_runs(problem, plan);
    let base = merged.as_ref().unwrap_or(plan);
    match sweep(problem, base, &mut stats) {
        Some(mut next) if plan_cost(problem, &next) < plan_cost(problem, plan) => {
            next.alpha_max = plan.alpha_max;
            next.made_for = plan.made_for.clone();
            (next, stats)
        }
        _ => (plan.clone(), stats),
    }
}

/// The sweep over `plan`: its rebuilt plan if a run was straightened.
fn sweep(problem: &Problem, plan: &Plan, stats: &mut Stats) -> Option<Plan> {
    let m = plan.edges();
    let costs: Vec<f64> = (0..m).map(|k| edge_cost(problem, plan, k)).collect();
    let mut next = Plan::at(&plan.states[0]);
    next.flow = plan.flow;
    // where the old edges lead from where the sweep stands: the plan's own states until a run
    // is straightened, then the checked replay from its end
    let mut tail = plan.states.clone();
    let mut accepted = false;
    let budget = WORK_PER_EDGE * m;
    let mut k = 0;
    while k < m {
        let mut span = m - k;
        let mut straightened = None;
        while span >= 2 && stats.propagations < budget {
            stats.tries += 1;
            let old: f64 = costs[k..k + span].iter().sum();
            if let Some(edges) = line(problem, plan, &tail[k], k, span, old, stats)
                && let Some(rest) = replay_rest(problem, plan, k + span, &edges, stats)
            {
                straightened = Some((edges, rest));
                break;
            }
            span /= 2;
        }
        let Some((edges, rest)) = straightened else {
            next.push(plan.controls[k], plan.durations[k], tail[k + 1].clone());
            k += 1;
            continue;
        };
        for (u, d, end) in edges {
            next.push(u, d, end);
        }
        k += span;
        tail.splice(k.., rest);
        stats.accepted += 1;
        accepted = true;
    }
    accepted.then_some(next)
}

/// The states old edges `j..` of `plan` reach from the end of `run`, the run's end first, if
/// every one is valid and the last is in the goal.
#[allow(clippy::type_complexity)]
fn replay_rest(
    problem: &Problem,
    plan: &Plan,
    j: usize,
    run: &[(Control, f64, Vec<Vec2>)],
    stats: &mut Stats,
) -> Option<Vec<Vec<Vec2>>> {
    let n = problem.agents();
    stats.rests += 1;
    let mut states = Vec::with_capacity(plan.edges() + 1 - j);
    states.push(run.last()?.2.clone());
    let mut out = [Vec2::zeros(); MAX_AGENTS];
    for (u, &d) in plan.controls[j..].iter().zip(&plan.durations[j..]) {
        stats.propagations += 1;
        if !propagate_valid(problem, states.last()?, u, d, &mut out[..n]) {
            stats.rests_failed += 1;
            return None;
        }
        states.push(out[..n].to_vec());
    }
    let end = states.last()?;
    if !problem.goal.contains(end) {
        stats.rests_failed += 1;
        return None;
    }
    Some(states)
}

/// How far (BL) a straightened run may end from the old waypoint. Its centroid lands there
/// exactly and its relative motion is the old one's, but the relative dynamics amplify the
/// rounding of the new positions over a long run; the replayed rest of the plan is checked
/// after it.
const LANDING: f64 = 1e-3;

/// Edges `k..k + span` of `plan` from `from` with their gradients chosen so that the centroid
/// runs straight to its place at waypoint `k + span`: their (command, duration, end), when
/// every edge is valid, the run ends within [`LANDING`] of that waypoint and costs less than
/// `old`.
#[allow(clippy::type_complexity)]
fn line(
    problem: &Problem,
    plan: &Plan,
    from: &[Vec2],
    k: usize,
    span: usize,
    old: f64,
    stats: &mut Stats,
) -> Option<Vec<(Control, f64, Vec<Vec2>)>> {
    let n = from.len();
    let target = &plan.states[k + span];
    let controls = &plan.controls[k..k + span];
    let durations = &plan.durations[k..k + span];
    let commands = line_commands(
        problem,
        n,
        controls,
        durations,
        centroid(target) - centroid(from),
    )?;
    let mut at = from.to_vec();
    let mut out = [Vec2::zeros(); MAX_AGENTS];
    let mut cost = 0.0;
    let mut edges = Vec::with_capacity(span);
    for (u, &d) in commands.into_iter().zip(durations) {
        stats.propagations += 1;
        cost += checked_motion_cost(problem, &at, &u, d, &mut out[..n])?;
        if cost >= old {
            return None;
        }
        edges.push((u, d, out[..n].to_vec()));
        at.copy_from_slice(&out[..n]);
    }
    (max_agent_distance(&at, target) <= LANDING).then_some(edges)
}

/// `controls` with gradient commands that carry the centroid of a team of `n` by `shift` over
/// `durations` as straight and as evenly as the coil's limits allow: per axis, every edge's
/// centroid velocity is one common value `μ`, clipped to what that edge's field lets the
/// gradient reach, with `μ` the one that adds up to the shift (the least `Σ t |v|²` for that
/// shift). Where no edge is clipped, the centroid runs along the straight line at one speed.
/// `None` when the shift is out of reach, or the coil's axes do not pull independently (the
/// tri-axial coil's do).
pub fn line_commands(
    problem: &Problem,
    n: usize,
    controls: &[Control],
    durations: &[f64],
    shift: Vec2,
) -> Option<Vec<Control>> {
    // per edge and axis: the drift and the reach of a full command (velocity = drift + g·reach)
    let mut maps = Vec::with_capacity(controls.len());
    for u in controls {
        let (v0, ax, ay) = centroid_map(problem, u, n)?;
        let independent = ax.y == 0.0 && ay.x == 0.0 && ax.x != 0.0 && ay.y != 0.0;
        if !(independent && ax.x.is_finite() && ay.y.is_finite()) {
            return None;
        }
        maps.push((v0, [ax.x, ay.y]));
    }
    let mut fractions = vec![[0.0; 2]; controls.len()];
    for axis in 0..2 {
        let ranges: Vec<(f64, f64)> = maps
            .iter()
            .map(|(v0, reach)| (v0[axis] - reach[axis].abs(), v0[axis] + reach[axis].abs()))
            .collect();
        let mu = level(&ranges, durations, shift[axis])?;
        for ((g, (v0, reach)), &(lo, hi)) in fractions.iter_mut().zip(&maps).zip(&ranges) {
            g[axis] = ((mu.clamp(lo, hi) - v0[axis]) / reach[axis]).clamp(-1.0, 1.0);
        }
    }
    let limit = problem.model.coil.gradient_limit();
    Some(
        controls
            .iter()
            .zip(fractions)
            .map(|(u, [gx, gy])| Control {
                grad: [gx * limit, gy * limit],
                ..*u
            })
            .collect(),
    )
}

/// The level `μ` at which `Σ tₖ clip(μ, loₖ, hiₖ) = total` (water filling; the sum is
/// nondecreasing in `μ`), found by bisection to the last bit; `None` when `total` lies outside
/// the sum's range.
fn level(ranges: &[(f64, f64)], durations: &[f64], total: f64) -> Option<f64> {
    let sum = |mu: f64| -> f64 {
        ranges
            .iter()
            .zip(durations)
            .map(|(&(lo, hi), t)| t * mu.clamp(lo, hi))
            .sum()
    };
    let mut lo = ranges.iter().map(|r| r.0).fold(f64::INFINITY, f64::min);
    let mut hi = ranges.iter().map(|r| r.1).fold(f64::NEG_INFINITY, f64::max);
    if !(sum(lo) <= total && total <= sum(hi)) {
        return None;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if sum(mid) < total {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(if total - sum(lo) <= sum(hi) - total {
        lo
    } else {
        hi
    })
}
