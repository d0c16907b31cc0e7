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
use magbench_env::{Control, declare_params};

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
        /// The edges (after cutting) optimised at a time when a plan is refined: each window
        /// lands on the state the rest of the plan replays from, the last one on the plan's
        /// own end.
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

/// `plan` refined window by window ([`Settings::window`] edges, after cutting them to
/// [`Settings::edge_periods`]), with at most `iterations` subproblems per window: the refined
/// plan when it costs less than `plan`, else `None`. Each window's SCP keeps it valid and lands
/// it on the state the rest of the plan replays from (the last window on the plan's end); the
/// rest is then replayed from the window's end and the window kept when the replay is valid,
/// ends in the goal and the plan costs less. The landing's rounding, amplified by the chaotic
/// rest, moves the plan's end within the goal. The
/// edges are cut only when the cut plan still replays into the goal (the rounding of a cut edge,
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
    let replay = |controls: Vec<Control>, durations: Vec<f64>| {
        Rollout::run(
            problem,
            &problem.start,
            controls,
            durations,
            End::Goal,
            settings.margin,
        )
    };
    let periods = |d: &f64| (d / problem.control_period).round() as usize;
    let edges = plan.controls.iter().zip(&plan.durations);
    let (controls, durations) = cut(
        problem,
        edges.map(|(u, d)| (*u, periods(d))),
        settings.edge_periods,
    );
    let mut whole = replay(controls, durations);
    if !whole.feasible {
        whole = replay(plan.controls.clone(), plan.durations.clone());
    }
    if !whole.feasible {
        return None;
    }
    let before = crate::plan_cost(problem, plan);
    let mut k = 0;
    while k < whole.edges() {
        let hi = (k + settings.window).min(whole.edges());
        let end = End::Land(whole.states[hi].clone());
        let window = Rollout::run(
            problem,
            &whole.states[k],
            whole.controls[k..hi].to_vec(),
            whole.durations[k..hi].to_vec(),
            end,
            settings.margin,
        );
        let outcome = optimise(problem, window, settings, |i, _| i >= iterations);
        if outcome.stats.accepted > 0 && outcome.rollout.feasible {
            let mut controls = outcome.rollout.controls;
            controls.extend_from_slice(&whole.controls[hi..]);
            let next = whole.resumed(problem, k, controls, settings.margin);
            if next.feasible && next.cost < whole.cost {
                whole = next;
            }
        }
        k = hi;
    }
    (whole.cost < before).then(|| {
        let mut next = whole.plan(problem, whole.edges());
        next.alpha_max = plan.alpha_max;
        next.made_for = plan.made_for.clone();
        next
    })
}

#[cfg(test)]
mod tests;
