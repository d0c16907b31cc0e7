//! `shooting-lm`: trajectory optimisation by single shooting over piecewise-constant controls,
//! solved by Levenberg–Marquardt (the `levenberg-marquardt` crate, the workspace's
//! least-squares solver, also behind `magbench calibrate`).
//!
//! The horizon is M segments of δ = `min_duration` (whole control periods); segment k holds
//! one command u_k = (θ_k, α_k, G_x,k, G_y,k), each bounded control the sine of a free variable
//! (controls.rs), so every iterate is within the coil's limits. The cost is a sum of squares
//! (residuals.rs): the end's miss of the goal in tolerances, the gradients' effort, and the
//! quadratic penalty of the validity rules (the proximity range and the walls, within
//! `margin` of their bounds, at every integration sample), weighted by μ.
//!
//! ```text
//! SHOOTING-LM(q_start, q_goal)
//!   M ← ⌈largest agent move / (speed · v_centroid) / δ⌉       v: the coil's centroid speed
//!   z ← GUESS()                                               the straight line, fields that
//!                                                             cancel the pair forces on average
//!   μ ← penalty
//!   loop until the limits:                                    one iteration = one Jacobian
//!     z ← LM minimise ½‖r(z; μ)‖²,  r = [ (q_M − q_goal)/tol ;  √(effort/M)·g_k/G ;
//!                                          √μ·violation_k/margin ]
//!         where q_{k+1} = f(q_k, u_k(z), δ)                     env's propagate
//!         Jacobian by forward differences, columns in parallel (rayon)
//!         at each accepted z: REPLAY(z); if it ends in the goal: return it
//!     if REPLAY(z) breaks a rule and μ was raised < raises times: μ ← growth · μ
//!     else: z ← GUESS(random field angles), μ ← penalty        multi-start, the seed's stream
//!   return the closest valid REPLAY prefix
//!
//! REPLAY(z)
//!   each segment one edge of δ, checked as every planner's edges are (propagate_valid)
//! ```
//!
//! Of the search settings every planner embeds it reads `min_duration` (δ) and `planar`
//! (whether the elevation is free); the sampling settings (`k`, `max_duration`, `goal_bias`,
//! `zoom_radius`, `timing`, `guide`, `aim`) have no role in it.

mod controls;
mod residuals;

use std::cell::RefCell;

use levenberg_marquardt::{LevenbergMarquardt, TerminationReason};
use magbench_env::declare_params;
use magbench_env::params::Reals;
use rand::SeedableRng;

use self::controls::{Layout, guess, reach, waypoint};
use self::residuals::{Replay, Shooting, Weights, Window, replay};
use crate::objective::plan_cost;
use crate::progress::Progress;
use crate::result::{Best, finish};
use crate::search_settings::{SearchSettings, to_periods};
use crate::{Plan, Planner, PlannerResult, Problem, Rng};
use magbench_env::Vec2;

declare_params! {
    /// Single shooting over piecewise-constant controls, solved by Levenberg–Marquardt.
    #[derive(Debug, Clone)]
    pub struct ShootingLm {
        /// The search settings every planner embeds: `min_duration` is the segment length δ
        /// and `planar` whether the elevation is free; the sampling settings are unused.
        #[params]
        pub search: SearchSettings,
        /// Fraction of the coil's centroid speed along the line at which the guess covers the
        /// largest agent move: it sets the horizon (half: the optimiser can speed up or slow
        /// down every segment alike).
        #[param("speed", Reals::closed(0.01, 1.0))]
        pub speed: f64 = 0.5,
        /// Weight of a horizon held at full gradient, in squared goal tolerances. Below 1 a
        /// plan that ends on the goal outweighs every plan that misses it by a tolerance; at
        /// 0.25 the optimum of a problem with such a plan misses by at most half a tolerance.
        #[param("effort", Reals::closed(0.0, 1.0))]
        pub effort: f64 = 0.25,
        /// Distance (BL) from a bound of the proximity range or from a wall at which the
        /// penalty starts: the largest step of an agent between integration samples at the
        /// default step (about 0.09 BL, env's ValidityChecker), at most env's exact-clearance
        /// band (0.25 BL).
        #[param("margin", Reals::closed(0.001, 0.25))]
        pub margin: f64 = 0.1,
        /// The first penalty parameter μ (a violation of one margin weighs as much as a miss
        /// of √μ tolerances).
        #[param("penalty", Reals::closed(1.0e-6, 1.0e6))]
        pub penalty: f64 = 1.0,
        /// Factor by which μ grows while a solve's replay breaks a rule (the quadratic
        /// penalty method, Nocedal & Wright, Framework 17.1).
        #[param("growth", Reals::closed(2.0, 1000.0))]
        pub growth: f64 = 10.0,
        /// Raises of μ before a restart from a random guess (6: μ up to 10⁶ times the
        /// first, a margin's violation outweighing a miss of a thousand tolerances).
        #[param("raises", 0..=30)]
        pub raises: usize = 6,
    }
}

/// The solver's patience: a solve stops after `PATIENCE · (n + 1)` residual evaluations for `n`
/// variables, about one trust-region step per variable (MINPACK's `lmder` default is 100, for
/// one long solve; a window is one of many, and a stalled one is better restarted).
const PATIENCE: usize = 1;

impl ShootingLm {
    /// The decision vector's shape for `problem`: one window of `max_duration` in segments of
    /// `min_duration`, each in whole control periods.
    fn layout(&self, problem: &Problem) -> Layout {
        let alpha_max = self
            .search
            .elevation_free(problem)
            .then_some(problem.alpha_max);
        let periods = to_periods(self.search.min_duration, problem.control_period);
        let window = to_periods(self.search.max_duration, problem.control_period);
        Layout {
            agents: problem.agents(),
            segments: (window / periods).max(1) as usize,
            periods,
            alpha_max,
            gradient_limit: problem.model.coil.gradient_limit(),
        }
    }
}

/// Where `replay`, appended to the plan so far, first enters the goal: the plan up to that
/// edge.
fn into_goal(problem: &Problem, plan: &Plan, replay: &Replay) -> Option<Plan> {
    let r = &replay.plan;
    let k = (1..r.states.len()).find(|&k| problem.goal.contains(&r.states[k]))?;
    let mut out = plan.clone();
    for e in 0..k {
        out.push(r.controls[e], r.durations[e], r.states[e + 1].clone());
    }
    Some(out)
}

impl Planner for ShootingLm {
    fn name(&self) -> &str {
        "shooting-lm"
    }

    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        let mut rng = Rng::seed_from_u64(problem.seed);
        let layout = self.layout(problem);
        let window_s = problem.periods(layout.periods) * layout.segments as f64;
        let mut progress = Progress::start(problem);
        let goal = &problem.goal;
        let mut plan = Plan::at(&problem.start);
        plan.flow = problem.model.flow;
        let mut found = goal.contains(&problem.start).then(|| plan.clone());
        let mut i = 0u64;

        'windows: while found.is_none() && !progress.done(i) {
            // WINDOW: from the plan's end toward a waypoint on each agent's line to its goal
            let from = plan.end().to_vec();
            let reach = reach(problem, layout.alpha_max, &from, &goal.agents);
            let step = self.speed * reach * window_s;
            let target = waypoint(&from, &goal.agents, step);
            // a window that ends within half a step of its waypoint brings the farthest agent
            // at least half a step closer to its goal (triangle inequality); the last window's
            // target is the goal itself, reached when the plan enters the goal region
            let accept = |end: &[Vec2]| target != goal.agents && within(end, &target, 0.5 * step);
            let window = Window {
                start: &from,
                target: &target,
            };
            let k0 = plan.edges();
            let mut z = guess(problem, &layout, &from, &target, k0, None);
            let (mut mu, mut raised) = (self.penalty, 0);
            loop {
                let before = i;
                let mut stop = |r: Replay| {
                    if r.complete
                        && let Some(p) = into_goal(problem, &plan, &r)
                    {
                        found = Some(p);
                        return true;
                    }
                    if (r.complete && accept(r.plan.end())) || progress.done(i) {
                        return true;
                    }
                    i += 1;
                    progress.record(i, None);
                    false
                };
                let shooting = Shooting {
                    problem,
                    layout,
                    weights: Weights {
                        effort: self.effort,
                        margin: self.margin,
                        mu,
                    },
                    window,
                    z,
                    stop: RefCell::new(&mut stop),
                };
                let (shooting, report) = LevenbergMarquardt::new()
                    .with_patience(PATIENCE)
                    .minimize(shooting);
                z = shooting.z;
                if found.is_some() || progress.done(i) {
                    break 'windows;
                }
                let last = replay(problem, &layout, &from, &z);
                if i == before {
                    // a solve that ended before its first Jacobian still counts
                    i += 1;
                    progress.record(i, None);
                }
                if let Some(p) = into_goal(problem, &plan, &last).filter(|_| last.complete) {
                    found = Some(p);
                    break 'windows;
                }
                if last.complete && accept(last.plan.end()) {
                    // COMMIT: the window's edges join the plan
                    for e in 0..last.plan.edges() {
                        plan.push(
                            last.plan.controls[e],
                            last.plan.durations[e],
                            last.plan.states[e + 1].clone(),
                        );
                    }
                    continue 'windows;
                }
                if matches!(report.termination, TerminationReason::LostPatience) {
                    continue;
                }
                if !last.complete && raised < self.raises {
                    mu *= self.growth;
                    raised += 1;
                } else {
                    z = guess(problem, &layout, &from, &target, k0, Some(&mut rng));
                    (mu, raised) = (self.penalty, 0);
                }
            }
        }

        let solved = found.is_some();
        let first = solved.then(|| (i, progress.elapsed()));
        let plan = found.unwrap_or(plan);
        let cost = plan_cost(problem, &plan);
        if solved {
            progress.record(i, Some(cost));
        }
        let nodes = plan.states.len();
        let best = Best { plan, solved, cost };
        finish(problem, best, i, nodes, progress, first, layout.alpha_max)
    }
}

/// Whether every agent of `s` is within `tolerance` of its position in `target`.
fn within(s: &[Vec2], target: &[Vec2], tolerance: f64) -> bool {
    s.iter()
        .zip(target)
        .all(|(p, q)| (p - q).norm() <= tolerance)
}
