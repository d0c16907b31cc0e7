//! `goal-zoom-rrt`: the seed's RRT (Salehizadeh & Diller, Algorithms 1–3).
//!
//! ```text
//! Algorithm 1  makeTree(T, q_start, q_goal)
//!   T ⇐ q_start
//!   while i ≤ k:                              (the limits)
//!     q_new ← T.BUILD-RRT()
//!     if T.hasReachedGoal(): break
//!   τ ← computePlan(T) by backtracking
//!
//! Algorithm 2  BUILD-RRT(T)
//!   q_sample ← T.randomStateGoalZoom()        biased coin: goal-zoom region or whole space
//!   q_near   ← T.nearestNeighbour(q_sample)   k-d tree, the problem's metric
//!   (q_new, u_new, δt_new) ← T.EXTEND(q_near, q_sample)
//!   if collisionFree(q_near, u_new, δt_new): add node q_new and edge (q_near, q_new, u_new, δt_new)
//!
//! Algorithm 3  EXTEND(T, q_near, q_sample)    see crate::extend
//!   k random (u, δt); keep argmin ρ(P_new, P_sample) = ‖P_new − P_sample‖²
//! ```
//!
//! From the root and from every new node within `steer_radius` of the goal that is closer to
//! it than every earlier node, a pair under the exact flow is steered straight onto the goal
//! centres, and from every new node within `approach_radius` of one of a pocket goal's
//! approaches that is closer to it than every earlier node, by way of that approach
//! (crate::goal_connect); the steer joins the tree only if every edge passes the same check as
//! EXTEND's and it ends in the goal.
//!
//! Like the seed's, this RRT keeps no costs: the plan's cost under the problem's objective is
//! measured once, on the plan it returns (`plan_cost`).
//!
//! Defaults: the search settings' (docs/planners.md, "Parameters and defaults", with the
//! experiments behind each): `k = 12` tries, durations from 0.25 s to 2 s (a random edge
//! moves the centroid up to 1 BL, the pull being at most 0.5 BL/s, while a constant field held
//! much longer collapses or splits a close pair: at r = 2 BL the separation changes at up to
//! 3 BL/s), goal bias 0.2 into a zoom region of 1.5 BL about each agent's goal centre. With aimed gradients
//! (`aim=true`) longer edges pay: `aim=true,guide=true,max_duration=5` is the fastest setting
//! measured on micro-factory (docs/planners.md, "Speed").

use magbench_env::params::Reals;
use magbench_env::{MAX_AGENTS, Vec2, declare_params};
use rand::SeedableRng;

use crate::goal_connect::GoalConnect;
use crate::motion::propagate_valid;
use crate::nn::NearestNeighbors;
use crate::objective::plan_cost;
use crate::progress::Progress;
use crate::result::{Best, finish};
use crate::sampler::StateSampler;
use crate::search_settings::SearchSettings;
use crate::tree::Tree;
use crate::{Planner, PlannerResult, Problem, Rng};

declare_params! {
    /// The seed's goal-zoom RRT.
    #[derive(Debug, Clone)]
    pub struct GoalZoomRrt {
        /// EXTEND's tries and durations, the goal-zoom sampler.
        #[params]
        pub search: SearchSettings,
        /// Steer exactly into the goal from the root and from every new node within this
        /// distance of the goal that is closer to it than any before (BL; 0 never; pairs under the exact flow only).
        #[param("steer_radius", Reals::closed(0.0, 1.0e6))]
        pub steer_radius: f64 = 3.0,
        /// Steer into the goal by way of one of its approaches (crate::goal_connect) from every
        /// new node within this distance of the approach that is closer to it than any before
        /// (BL; 0 never; pairs under the exact flow only).
        #[param("approach_radius", Reals::closed(0.0, 1.0e6))]
        pub approach_radius: f64 = 5.0,
        /// The tree of the last solve.
        pub last_tree: Option<Tree> = None,
    }
}

impl Planner for GoalZoomRrt {
    fn name(&self) -> &str {
        "goal-zoom-rrt"
    }

    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        let n = problem.agents();
        let mut rng = Rng::seed_from_u64(problem.seed);
        let extend = self.search.extend(problem);
        let zoom = self.search.zoom();
        let mut guide = self.search.guide(problem);
        let sampler = StateSampler::new(problem);
        let mut progress = Progress::start(problem);

        // Algorithm 1: T ⇐ q_start
        let mut tree = Tree::new(&problem.start);
        let mut nn = NearestNeighbors::new(problem.metric, n);
        nn.add(&problem.start, 0);
        let mut closest = (0u32, problem.goal.distance(&problem.start));
        let mut reached = problem.goal.contains(&problem.start).then_some(0u32);
        let mut connect = GoalConnect::new(
            problem,
            self.steer_radius,
            self.approach_radius,
            extend.max_periods,
        );
        if reached.is_none() {
            reached = connect.attempt(problem, &mut tree, Some(&mut nn), 0, closest.1, true);
        }

        let mut q_sample = [Vec2::zeros(); MAX_AGENTS];
        let mut q_new = [Vec2::zeros(); MAX_AGENTS];
        let mut i = 0u64;
        while reached.is_none() && !progress.done(i) {
            i += 1;
            // Algorithm 2: BUILD-RRT
            if zoom.sample(
                problem,
                &sampler,
                guide.as_ref(),
                &mut rng,
                &mut q_sample[..n],
            ) {
                let (near, _) = nn.nearest(&q_sample[..n]).expect("the tree has its root");
                let ext = extend.run(problem, &mut rng, tree.state(near), &q_sample[..n]);
                let (u, periods) = (ext.control, ext.periods);
                let d = problem.periods(periods);
                if periods > 0 && propagate_valid(problem, tree.state(near), &u, d, &mut q_new[..n])
                {
                    let id = tree.add(near, &q_new[..n], u, periods, 0.0);
                    nn.add(&q_new[..n], id);
                    if let Some(g) = guide.as_mut() {
                        g.observe(&q_new[..n]);
                    }
                    let dist = problem.goal.distance(&q_new[..n]);
                    let closer = dist < closest.1;
                    if closer {
                        closest = (id, dist);
                    }
                    if problem.goal.contains(&q_new[..n]) {
                        reached = Some(id); // T.hasReachedGoal()
                    } else {
                        reached =
                            connect.attempt(problem, &mut tree, Some(&mut nn), id, dist, closer);
                    }
                }
            }
            if reached.is_none() {
                progress.record(i, None);
            }
        }

        let first = reached.map(|_| (i, progress.elapsed()));

        // τ ← computePlan(T) by backtracking
        let node = reached.unwrap_or(closest.0);
        let plan = tree.plan_to(node, problem);
        let cost = plan_cost(problem, &plan);
        if reached.is_some() {
            progress.record(i, Some(cost));
        }
        let best = Best {
            plan,
            solved: reached.is_some(),
            cost,
        };
        let nodes = tree.len();
        self.last_tree = Some(tree);
        finish(problem, best, i, nodes, progress, first, extend.alpha_max)
    }

    fn tree(&self) -> Option<&Tree> {
        self.last_tree.as_ref()
    }
}
