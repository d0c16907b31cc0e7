//! Trajectory optimisation by sequential convex programming (SCP) over a plan's controls
//! (docs/planners.md, "Trajectory optimisation").
//!
//! ```text
//! SCP(controls U, durations D)               D are kept: whole control periods
//!   X ← rollout(U)                           the planning model's flow, checked edge by edge
//!   Δ ← trust
//!   repeat while the iterations and the limits allow:
//!     (A_k, B_k) ← ∂F/∂x, ∂F/∂u at (X_k, U_k)             central differences of the flow
//!     δU ← argmin  cost_lin(X + δX) + μ Σ slack            the convex subproblem (Clarabel)
//!            s.t.  δX_{k+1} = A_k δX_k + B_k δU_k,  δX_0 = 0
//!                  walls, proximity range and goal, linearised and softened by slack
//!                  the coil's gradient limits;  |δU| ≤ Δ
//!     U' ← U + δU;  X' ← rollout(U')
//!     ρ ← (J(U) − J(U')) / (J(U) − J_lin(δU))  actual over predicted decrease of the merit
//!     accept U' when ρ > η and (U' is feasible or U was not);  Δ grows or shrinks with ρ
//!   return U and whether it is feasible: every edge valid, the end in the goal
//! ```
//!
//! The merit `J = cost + μ V` is the objective's cost plus the exact penalty of the violations
//! at the waypoints (walls and proximity range by [`Settings::margin`], the goal by its
//! tolerance less that margin). Each linearised constraint is met by the subproblem or paid for
//! by its slack, so the subproblem is always feasible, from a guess that collides too.
//!
//! The fields keep their elevation and every edge its duration: the plan keeps its timing on
//! the camera's frames, and only its field angles and gradients move. The cost the subproblem
//! models is the objective's: the agents' chord lengths between waypoints (the SOC epigraph of
//! path length), the squared gradient (control effort), or nothing it can change (duration).

mod guess;
mod land;
mod linearise;
mod rollout;
mod subproblem;

pub use guess::straight_line;
pub use rollout::{End, LANDING, Rollout};

use magbench_env::params::Reals;
use magbench_env::{Control, Vec2, declare_params};

use crate::{Plan, Problem};
use land::land;
use linearise::jacobians;
use subproblem::{Step, Trust, solve_step};

declare_params! {
    /// The settings of sequential convex programming over a plan's controls.
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct Settings {
        /// The longest edge the optimiser works with (control periods): longer edges are cut
        /// into pieces of at most this many periods, each holding the same control, so that
        /// the waypoints where walls and the proximity range are checked lie close together.
        #[param("edge_periods", 1..=100_000)]
        pub edge_periods: usize = 15,
        /// The first trust region: the largest change of a field angle (rad) and of a gradient
        /// command (fraction of the coil's limit) in one step.
        #[param("trust", Reals::closed(1e-6, 10.0))]
        pub trust: f64 = 0.1,
        /// The clearance kept from walls and from the proximity range's ends at every waypoint,
        /// and subtracted from the goal's tolerance (BL).
        #[param("margin", Reals::closed(0.0, 1.0))]
        pub margin: f64 = 0.02,
        /// The edges (after cutting) optimised at a time: a refinement's horizon, which ends
        /// on the plan's own state (the last one in the goal) and keeps its first half
        /// ([`refine`]), and the `trajopt` planner's first tail.
        #[param("window", 1..=100_000)]
        pub window: usize = 8,
    }
}

/// The exact penalty's weight (cost units per BL of violation): far above the cost a BL of
/// violation could save under any built-in objective (path length pays at most the agents'
/// count per BL moved), so that the subproblem pays a violation only where it cannot meet it.
pub const PENALTY: f64 = 1e3;

// The trust-region rules are TrajOpt's (Schulman et al., "Motion planning with sequential
// convex optimization and convex collision checking", IJRR 2014; the defaults of its
// `BasicTrustRegionSQP`): a step is taken when the merit falls by at least a quarter of what the
// subproblem predicted, the region then grows by half and shrinks tenfold on a step refused, and
// the optimiser stops when the region or the predicted decrease falls below 1e-4.

/// The smallest ratio of actual to predicted decrease at which a step is taken.
const ACCEPT: f64 = 0.25;

/// The trust region's factor after a step taken.
const EXPAND: f64 = 1.5;

/// The trust region's factor after a step refused (or a subproblem the solver did not solve).
const SHRINK: f64 = 0.1;

/// The trust region below which the optimiser stops (the same units as [`Settings::trust`]).
const SMALLEST_TRUST: f64 = 1e-4;

/// The predicted decrease of the merit (cost units) below which the optimiser stops: a local
/// minimum.
const SMALLEST_DECREASE: f64 = 1e-4;

/// The largest trust region (the same units as [`Settings::trust`]).
const LARGEST_TRUST: f64 = 1.0;

/// The trust region after a step `taken` or refused.
fn resized(trust: f64, taken: bool) -> f64 {
    if taken {
        (EXPAND * trust).min(LARGEST_TRUST)
    } else {
        SHRINK * trust
    }
}

/// Why a run of the optimiser stopped.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Stop {
    /// The caller's limits (subproblems, time) ran out.
    #[default]
    Limits,
    /// No step was predicted to lower the merit: a local minimum.
    Converged,
    /// The trust region shrank below its smallest size: no step the linearisation proposed
    /// lowered the merit.
    TrustRegion,
}

impl std::fmt::Display for Stop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Stop::Limits => "its subproblem or time limit ran out",
            Stop::Converged => "it converged onto a local minimum of the penalised violations",
            Stop::TrustRegion => "its trust region vanished (no step lowered the merit)",
        })
    }
}

/// Work counts of a run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Stats {
    /// Subproblems solved.
    pub iterations: u64,
    /// Steps taken.
    pub accepted: u64,
    /// Subproblems the solver did not solve.
    pub solver_failures: u64,
    /// Why the run stopped.
    pub stopped: Stop,
}

impl Stats {
    /// Why an optimisation that ended infeasible stopped, with its work counts: the reason a
    /// run gives in its `error` column.
    pub fn infeasible_reason(&self) -> String {
        let mut s = format!(
            "trajopt: no feasible plan; {} after {} subproblems ({} steps taken",
            self.stopped, self.iterations, self.accepted
        );
        if self.solver_failures > 0 {
            s += &format!(", {} the solver did not solve", self.solver_failures);
        }
        s + ")"
    }
}

/// The end of a run: the best iterate and its work counts.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The last accepted iterate.
    pub rollout: Rollout,
    /// Work counts.
    pub stats: Stats,
}

/// Runs SCP from `start` until it converges, its trust region vanishes, or
/// `stop(iterations, current)` says so. A step of a window that must land on a state is landed
/// ([`land`]) before it is judged.
pub fn optimise(
    problem: &Problem,
    start: Rollout,
    settings: &Settings,
    mut stop: impl FnMut(u64, &Rollout) -> bool,
) -> Outcome {
    let mut current = start;
    let mut trust = settings.trust;
    let mut stats = Stats::default();
    while !stop(stats.iterations, &current) {
        if trust < SMALLEST_TRUST {
            stats.stopped = Stop::TrustRegion;
            break;
        }
        stats.iterations += 1;
        let model = jacobians(problem, &current);
        let region = Trust {
            size: trust,
            gradient_limit: problem.model.coil.gradient_limit(),
        };
        let Some(Step {
            delta,
            now,
            predicted,
        }) = solve_step(problem, &current, &model, region, settings.margin, PENALTY)
        else {
            stats.solver_failures += 1;
            trust = resized(trust, false);
            continue;
        };
        let expected = now - predicted;
        if expected <= SMALLEST_DECREASE {
            stats.stopped = Stop::Converged;
            break;
        }
        let stepped = current.stepped(&delta, region.gradient_limit);
        let candidate = land(
            problem,
            current.rerun(problem, stepped, settings.margin),
            &model,
            settings.margin,
        );
        let rho = (current.merit(PENALTY) - candidate.merit(PENALTY)) / expected;
        if rho > ACCEPT && (candidate.feasible || !current.feasible) {
            current = candidate;
            stats.accepted += 1;
            trust = resized(trust, true);
        } else {
            trust = resized(trust, false);
        }
    }
    Outcome {
        rollout: current,
        stats,
    }
}

/// `edges` (control, control periods) cut into pieces of at most `max_periods` periods, each
/// holding its edge's control: their controls and durations.
pub fn cut(
    problem: &Problem,
    edges: impl IntoIterator<Item = (Control, usize)>,
    max_periods: usize,
) -> (Vec<Control>, Vec<f64>) {
    let mut controls = Vec::new();
    let mut durations = Vec::new();
    for (u, mut left) in edges {
        while left > 0 {
            let piece = left.min(max_periods);
            controls.push(u);
            durations.push(problem.periods(piece as u32));
            left -= piece;
        }
    }
    (controls, durations)
}

/// `plan` refined over a receding horizon ([`Settings::window`] edges, after cutting them to
/// [`Settings::edge_periods`]), with at most `iterations` subproblems per horizon: the refined
/// plan when it costs less than `plan`, else `None`.
///
/// ```text
/// REFINE(plan P with states X, horizon h)            the edges cut; else P's own edges
///   x ← start;  U ← [];  C ← []                      C: the last horizon's unkept edges
///   k ← 0
///   while k < |P|:
///     e ← min(k + h, |P|)
///     W ← SCP(C, then P's edges up to e, from x;     lands on X_e, within LANDING;
///             end X_e, or the goal when e = |P|)     the last horizon ends in the goal
///     if W is not feasible:
///       if C is empty: return none
///       keep C (it lands on P's state where it ends); x, k move past it;  C ← []
///     else:
///       keep W's first ⌈h/2⌉ edges (all of them at the end); x, k move past them
///       C ← W's other edges
///   return U replayed from the start, when it is valid, ends in the goal and costs less
/// ```
///
/// Each horizon starts where the kept edges end, which the horizon before chose freely, and
/// ends on the plan's own state `h` edges on; the edges it does not keep are a feasible way
/// back onto the plan, so the next horizon starts from a guess that lands (its first part)
/// and from the plan itself (the rest). The kept edges are replayed from the start as they
/// were solved, so the whole replays bit for bit through every horizon's checks. The edges
/// are cut only when the cut plan still replays into the goal (the rounding of a cut edge,
/// amplified by the chaotic relative motion, can carry it out); else the plan's own edges are
/// refined.
pub fn refine(
    problem: &Problem,
    plan: &Plan,
    settings: &Settings,
    iterations: u64,
) -> Option<Plan> {
    if plan.flow != problem.model.flow || plan.edges() == 0 {
        return None;
    }
    let margin = settings.margin;
    let run = |from: &[Vec2], controls: Vec<Control>, durations: &[f64], end: End| {
        Rollout::run(problem, from, controls, durations.to_vec(), end, margin)
    };
    let periods = |d: &f64| (d / problem.control_period).round() as usize;
    let edges = plan.controls.iter().zip(&plan.durations);
    let (controls, durations) = cut(
        problem,
        edges.map(|(u, d)| (*u, periods(d))),
        settings.edge_periods,
    );
    let mut guide = run(&problem.start, controls, &durations, End::Goal);
    if !guide.feasible {
        guide = run(
            &problem.start,
            plan.controls.clone(),
            &plan.durations,
            End::Goal,
        );
    }
    if !guide.feasible {
        return None;
    }
    let before = crate::plan_cost(problem, plan);
    let total = guide.edges();
    let keep = settings.window.div_ceil(2);
    let mut at = problem.start.clone();
    let mut kept: Vec<Control> = Vec::with_capacity(total);
    let mut carry: Vec<Control> = Vec::new();
    let mut k = 0;
    while k < total {
        let hi = (k + settings.window).min(total);
        let end = if hi == total {
            End::Goal
        } else {
            End::Land(guide.states[hi].clone())
        };
        let carried = std::mem::take(&mut carry);
        let back = carried.len();
        let mut guess = carried.clone();
        guess.extend_from_slice(&guide.controls[k + back..hi]);
        let window = run(&at, guess, &guide.durations[k..hi], end);
        let model = jacobians(problem, &window);
        let window = land(problem, window, &model, margin);
        let outcome = optimise(problem, window, settings, |i, _| i >= iterations);
        let (controls, states, taken) = if outcome.rollout.feasible {
            let r = outcome.rollout;
            let taken = if hi == total { r.edges() } else { keep };
            (r.controls, r.states, taken)
        } else if back > 0 {
            // the way back the horizon before found
            let r = run(
                &at,
                carried,
                &guide.durations[k..k + back],
                End::Land(guide.states[k + back].clone()),
            );
            (r.controls, r.states, back)
        } else {
            return None;
        };
        kept.extend_from_slice(&controls[..taken]);
        carry = controls[taken..].to_vec();
        at = states[taken].clone();
        k += taken;
    }
    let whole = run(&problem.start, kept, &guide.durations, End::Goal);
    (whole.feasible && whole.cost < before).then(|| {
        let mut next = whole.plan(problem, whole.edges());
        next.alpha_max = plan.alpha_max;
        next.made_for = plan.made_for.clone();
        next
    })
}

#[cfg(test)]
mod tests;
