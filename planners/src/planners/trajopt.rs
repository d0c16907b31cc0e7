//! `trajopt`: trajectory optimisation from a straight line, by sequential convex programming
//! (crate::trajopt; docs/planners.md, "Trajectory optimisation").
//!
//! ```text
//! TRAJOPT(problem)
//!   (U, D) ← STRAIGHT-LINE(start, goal)     a pair's exact steer onto the goal (walls not
//!                                           checked); a team's centroid along the line, its
//!                                           shape held
//!   for W = w, 2w, 4w, …, all the edges:     the tail of W edges, the rest kept
//!     U ← SCP(U's last W edges, from where they start, into the goal)   an equal share of
//!                                                                        max_subproblems
//!     if U is feasible or the limits are reached: stop
//!   return the rollout of U when feasible, else its valid part up to its closest approach
//! ```
//!
//! The tail grows because the relative motion is chaotic: the linearised flow predicts a
//! step's effect over a few seconds of edges, not over the whole of a long plan, so a short
//! tail converges where the whole plan would not move.
//!
//! A local method: it follows the cost and the penalised violations downhill from its guess,
//! so a maze whose straight line crosses walls it cannot slide around leaves it infeasible. The
//! same optimiser is the `trajopt` post-processing pass, which starts from any planner's plan
//! (crate::post_process).

use magbench_env::declare_params;

use crate::progress::Progress;
use crate::result::{Best, finish};
use crate::trajopt::{End, PENALTY, Rollout, Settings, Stats, optimise, straight_line};
use crate::{Planner, PlannerResult, Problem};

declare_params! {
    /// Trajectory optimisation from a straight-line guess.
    #[derive(Debug, Clone)]
    pub struct Trajopt {
        /// The optimiser's edge length, trust region and margin.
        #[params]
        pub scp: Settings,
        /// The most convex subproblems solved (one per SCP iteration), within the run's
        /// iteration and time limits.
        #[param("max_subproblems", 1..=1_000_000)]
        pub max_subproblems: usize = 200,
        /// Why the last solve ended without a feasible plan (`None` when it found one).
        pub last_stop: Option<String> = None,
    }
}

impl Planner for Trajopt {
    fn name(&self) -> &str {
        "trajopt"
    }

    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        let mut progress = Progress::start(problem);
        let (controls, durations) = straight_line(problem, &self.scp);
        let cap = self.max_subproblems as u64;
        let mut first = None;
        let margin = self.scp.margin;
        let mut whole = Rollout::run(
            problem,
            &problem.start,
            controls,
            durations,
            End::Goal,
            margin,
        );
        let mut i = 0u64;
        let mut stats = Stats::default();
        let mut tail = self.scp.window.min(whole.edges());
        // the subproblems shared evenly among the tails
        let tails = (whole.edges() as f64 / tail as f64).log2().ceil() as u64 + 1;
        let share = (cap / tails).max(1);
        loop {
            let spent = i;
            let best = whole.feasible.then_some(whole.cost);
            let k = whole.edges() - tail;
            let window = Rollout::run(
                problem,
                &whole.states[k],
                whole.controls[k..].to_vec(),
                whole.durations[k..].to_vec(),
                End::Goal,
                margin,
            );
            let outcome = optimise(problem, window, &self.scp, |j, _| {
                progress.record(spent + j, best);
                j >= share || spent + j >= cap || progress.done(spent + j)
            });
            i += outcome.stats.iterations;
            stats = Stats {
                iterations: i,
                accepted: stats.accepted + outcome.stats.accepted,
                solver_failures: stats.solver_failures + outcome.stats.solver_failures,
                stopped: outcome.stats.stopped,
            };
            let next = whole.resumed(problem, k, outcome.rollout.controls, margin);
            if next.merit(PENALTY) < whole.merit(PENALTY) {
                whole = next;
            }
            progress.record(i, whole.feasible.then_some(whole.cost));
            if whole.feasible && first.is_none() {
                first = Some((i, progress.elapsed()));
            }
            if whole.feasible || tail == whole.edges() || i >= cap || progress.done(i) {
                break;
            }
            tail = (2 * tail).min(whole.edges());
        }
        let plan = if whole.feasible {
            whole.plan(problem, whole.edges())
        } else {
            whole.closest_approach(problem)
        };
        self.last_stop = (!whole.feasible).then(|| stats.infeasible_reason());
        let best = Best {
            plan,
            solved: whole.feasible,
            cost: whole.cost,
        };
        let nodes = whole.edges() + 1;
        finish(problem, best, i, nodes, progress, first, None)
    }

    fn stop_reason(&self) -> Option<&str> {
        self.last_stop.as_deref()
    }
}
