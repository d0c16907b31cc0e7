//! `plain-rrt`: the textbook kinodynamic RRT, written only with the problem's sampler,
//! propagation with its motion check, and goal test.
//!
//! ```text
//! tree ⇐ start
//! until the goal is reached or the limits are hit:
//!     target ← the goal region with probability goal_bias, else anywhere (a valid state)
//!     near   ← the tree's node closest to target
//!     try `tries` random (control, duration) from near; keep the valid one ending closest
//!     add it to the tree
//! plan ← the path from the start to the node in the goal (or the closest one)
//! ```

use magbench::prelude::*;

declare_params! {
    /// A plain RRT.
    #[derive(Debug, Clone)]
    pub struct PlainRrt {
        /// Probability of aiming at the goal region instead of the whole space.
        #[param("goal_bias", Reals::closed(0.0, 1.0))]
        pub goal_bias: f64 = 0.1,
        /// Random (control, duration) pairs tried from the nearest node per iteration.
        #[param("tries", 1..=1000)]
        pub tries: usize = 5,
        /// Longest edge (s); edges last whole control periods.
        #[param("max_duration", Reals::POSITIVE)]
        pub max_duration: f64 = 1.0,
    }
}

/// A node of the tree: its state and the edge that reached it.
struct Node {
    state: Vec<Vec2>,
    parent: usize,
    control: Control,
    duration: f64,
}

/// Sum of the agents' squared distances between two team states.
fn distance(a: &[Vec2], b: &[Vec2]) -> f64 {
    a.iter().zip(b).map(|(p, q)| (p - q).norm_squared()).sum()
}

impl Planner for PlainRrt {
    fn name(&self) -> &str {
        "plain-rrt"
    }

    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        let n = problem.agents();
        let mut rng = Rng::seed_from_u64(problem.seed);
        let sampler = StateSampler::new(problem);
        let mut progress = Progress::start(problem);
        let max_periods = ((self.max_duration / problem.control_period) as u32).max(1);
        let gradient_limit = problem.model.coil.gradient_limit();

        let root = Node {
            state: problem.start.clone(),
            parent: 0,
            control: Control::default(),
            duration: 0.0,
        };
        let mut tree = vec![root];
        let mut reached = problem.goal.contains(&problem.start).then_some(0);
        let mut target = vec![Vec2::zeros(); n];
        let mut end = vec![Vec2::zeros(); n];
        let mut i = 0;
        while reached.is_none() && !progress.done(i) {
            i += 1;
            let to_goal = rng.random_bool(self.goal_bias);
            let found = valid_sample(problem, 100, &mut target, |s| {
                if to_goal {
                    sampler.zoom(&mut rng, &problem.goal, problem.goal.tolerance, s)
                } else {
                    sampler.uniform(&mut rng, s)
                }
            });
            if found {
                let near = (0..tree.len())
                    .min_by(|&a, &b| {
                        let da = distance(&tree[a].state, &target);
                        da.total_cmp(&distance(&tree[b].state, &target))
                    })
                    .expect("the tree has its root");
                let mut best: Option<Node> = None;
                for _ in 0..self.tries {
                    let u = random_control(&mut rng, gradient_limit);
                    let d = problem.periods(rng.random_range(1..=max_periods));
                    if propagate_valid(problem, &tree[near].state, &u, d, &mut end)
                        && best
                            .as_ref()
                            .is_none_or(|b| distance(&end, &target) < distance(&b.state, &target))
                    {
                        let node = Node {
                            state: end.clone(),
                            parent: near,
                            control: u,
                            duration: d,
                        };
                        best = Some(node);
                    }
                }
                if let Some(node) = best {
                    if problem.goal.contains(&node.state) {
                        reached = Some(tree.len());
                    }
                    tree.push(node);
                }
            }
            progress.record(i, None);
        }

        // the path to the goal, or to the node closest to it
        let last = reached.unwrap_or_else(|| {
            (0..tree.len())
                .min_by(|&a, &b| {
                    let da = problem.goal.distance(&tree[a].state);
                    da.total_cmp(&problem.goal.distance(&tree[b].state))
                })
                .expect("the tree has its root")
        });
        let mut path = vec![last];
        while let Some(&k) = path.last().filter(|&&k| k != 0) {
            path.push(tree[k].parent);
        }
        let mut plan = Plan::at(&problem.start);
        for &k in path.iter().rev().skip(1) {
            plan.push(tree[k].control, tree[k].duration, tree[k].state.clone());
        }

        let solved = reached.is_some();
        let cost = solved.then(|| plan_cost(problem, &plan));
        let (trace, time_s) = progress.finish(i, cost);
        PlannerResult {
            solved,
            approximate: !solved,
            goal_distance: problem.goal.distance(plan.end()),
            plan,
            iterations: i,
            nodes: tree.len(),
            time_s,
            cost,
            first_solution: solved.then_some((i, time_s)),
            progress: trace,
        }
    }
}
