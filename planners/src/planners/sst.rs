//! `sst`: Stable Sparse RRT (Li, Littlefield & Bekris, "Asymptotically optimal sampling-based
//! kinodynamic planning", IJRR 2016).
//!
//! ```text
//! SST(x_0, T_prop, δ_BN, δ_s)
//!   V_active ← {x_0}; V_inactive ← ∅; s_0 ← x_0; s_0.rep ← x_0; S ← {s_0}
//!   for i = 1, 2, … until the limits:
//!     x_selected ← BEST_FIRST_SELECTION(V_active, δ_BN)
//!     x_new ← MONTE_CARLO_PROP(x_selected, T_prop)
//!     if COLLISION_FREE(x_selected → x_new) and IS_NODE_LOCALLY_THE_BEST(x_new, S, δ_s):
//!       V_active ← V_active ∪ {x_new}; E ← E ∪ {x_selected → x_new}
//!       PRUNE_DOMINATED_NODES(x_new)
//!
//! BEST_FIRST_SELECTION: x_rand ← SAMPLE(); X_near ← NEAR(V_active, x_rand, δ_BN)
//!   return argmin_{x ∈ X_near} cost(x), or NEAREST(V_active, x_rand) if X_near = ∅
//! IS_NODE_LOCALLY_THE_BEST: s_new ← NEAREST(S, x_new)
//!   if ‖x_new − s_new‖ > δ_s: S ← S ∪ {x_new}; s_new ← x_new; s_new.rep ← NULL
//!   return s_new.rep = NULL or cost(x_new) < cost(s_new.rep)
//! PRUNE_DOMINATED_NODES: x_peer ← s_new.rep
//!   if x_peer ≠ NULL: V_active ← V_active \ {x_peer}; V_inactive ← V_inactive ∪ {x_peer}
//!   s_new.rep ← x_new
//!   while x_peer ≠ NULL and IS_LEAF(x_peer) and x_peer ∈ V_inactive:
//!     x_parent ← PARENT(x_peer); E ← E \ {x_parent → x_peer}; V_inactive ← V_inactive \ {x_peer}
//!     x_peer ← x_parent
//! ```
//!
//! Pruning really removes nodes: a dominated leaf leaves the tree (its slot is reused) and the
//! walk continues up through inactive ancestors that became leaves. (OMPL's `control::SST`
//! collects inactive nodes but its `inactive_` loop never runs, so its tree keeps growing.)
//! Active nodes are at most one per witness, so the tree stays about as large as the witness
//! set, which a δ_s-cover of the reachable space bounds.
//!
//! MONTE_CARLO_PROP draws one random control and one random duration when `k = 1`, as in the
//! paper; with `k > 1` it runs EXTEND's k tries toward the sample and keeps the closest. The
//! default `k = 5` solved micro-factory in 6 of 6 seeds within 60k iterations (median 7.2k)
//! where `k = 1` solved 4 of 6; δ_s = 0.25 and δ_BN = 0.5 BL (metric) keep the witnesses finer
//! than one edge, so that a node can escape its parent's witness. SAMPLE is the goal-zoom coin
//! toss.
//! A node that enters the goal region cheaper than the best solution becomes the best solution
//! (kept as a plan, so later pruning cannot take it away).

use magbench_env::params::Reals;
use magbench_env::{MAX_AGENTS, Vec2, declare_params};
use rand::SeedableRng;

use crate::motion::propagate_checked;
use crate::nn::NearestNeighbors;
use crate::objective::Motion;
use crate::progress::Progress;
use crate::result::{Best, finish};
use crate::sampler::StateSampler;
use crate::search_settings::SearchSettings;
use crate::tree::{NONE, Tree};
use crate::{Plan, Planner, PlannerResult, Problem, Rng};

declare_params! {
    /// Stable Sparse RRT.
    #[derive(Debug, Clone)]
    pub struct Sst {
        /// δ_BN: best-first selection radius (metric, BL).
        #[param("selection_radius", Reals::POSITIVE)]
        pub selection_radius: f64 = 0.5,
        /// δ_s: witness spacing; a witness keeps only its cheapest node (metric, BL).
        #[param("pruning_radius", Reals::POSITIVE)]
        pub pruning_radius: f64 = 0.25,
        /// MONTE_CARLO_PROP's tries (`k`) and durations (T_prop = `max_duration`), the
        /// goal-zoom sampler.
        #[params]
        pub search: SearchSettings,
        /// Stop at the first solution (success-rate runs) instead of improving until the
        /// limits.
        #[param("stop_on_solution")]
        pub stop_on_solution: bool = false,
        /// The tree of the last solve.
        pub last_tree: Option<Tree> = None,
    }
}

/// The counts a run ends with (for tests and reports).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SstStats {
    /// Witnesses |S|.
    pub witnesses: usize,
    /// Active nodes.
    pub active: usize,
    /// Nodes in the tree (active and inactive).
    pub nodes: usize,
    /// Nodes added over the run (what a tree that never prunes would hold, plus the root).
    pub added: u64,
    /// Nodes pruned over the run.
    pub pruned: u64,
}

impl Sst {
    /// Runs SST and also returns its final counts.
    pub fn solve_with_stats(&mut self, problem: &Problem) -> (PlannerResult, SstStats) {
        let n = problem.agents();
        let mut rng = Rng::seed_from_u64(problem.seed);
        let propagate = self.search.extend(problem);
        let zoom = self.search.zoom();
        let mut guide = self.search.guide(problem);
        let sampler = StateSampler::new(problem);
        let mut progress = Progress::start(problem);

        // V_active ← {x_0}; s_0 ← x_0; s_0.rep ← x_0; S ← {s_0}
        let mut tree = Tree::new(&problem.start);
        let mut active = vec![true];
        let mut v_active = NearestNeighbors::new(problem.metric, n);
        v_active.add(&problem.start, 0);
        let mut witnesses = NearestNeighbors::new(problem.metric, n);
        witnesses.add(&problem.start, 0);
        let mut rep: Vec<u32> = vec![0];
        let mut pruned = 0u64;
        let mut added = 0u64;

        let mut best = Best {
            plan: Plan::at(&problem.start),
            solved: false,
            cost: f64::INFINITY,
        };
        let mut closest = (
            problem.goal.distance(&problem.start),
            Plan::at(&problem.start),
            0.0,
        );
        let mut first = None;
        if problem.goal.contains(&problem.start) {
            best = Best {
                plan: Plan::at(&problem.start),
                solved: true,
                cost: 0.0,
            };
            first = Some((0, 0.0));
        }

        let mut x_rand = [Vec2::zeros(); MAX_AGENTS];
        let mut x_new = [Vec2::zeros(); MAX_AGENTS];
        let mut near = Vec::new();
        let mut i = 0u64;
        while !progress.done(i) && (!self.stop_on_solution || !best.solved) {
            i += 1;
            // x_selected ← BEST_FIRST_SELECTION(V_active, δ_BN)
            if !zoom.sample(
                problem,
                &sampler,
                guide.as_ref(),
                &mut rng,
                &mut x_rand[..n],
            ) {
                progress.record(i, best.solved_cost());
                continue;
            }
            v_active.within(&x_rand[..n], self.selection_radius, &mut near);
            let x_selected = match near
                .iter()
                .map(|&(x, _)| x)
                .min_by(|&a, &b| tree.cost(a).total_cmp(&tree.cost(b)))
            {
                Some(x) => x,
                None => {
                    v_active
                        .nearest(&x_rand[..n])
                        .expect("the root is never pruned")
                        .0
                }
            };

            // x_new ← MONTE_CARLO_PROP(x_selected, T_prop)
            let ext = propagate.run(problem, &mut rng, tree.state(x_selected), &x_rand[..n]);
            let d = problem.periods(ext.periods);
            let Some(length) = (ext.periods > 0)
                .then(|| {
                    propagate_checked(
                        problem,
                        tree.state(x_selected),
                        &ext.control,
                        d,
                        &mut x_new[..n],
                    )
                })
                .flatten()
            else {
                progress.record(i, best.solved_cost());
                continue;
            };
            let cost = tree.cost(x_selected)
                + problem.objective.motion_cost(&Motion {
                    control: ext.control,
                    duration: d,
                    path_length: length,
                });

            // IS_NODE_LOCALLY_THE_BEST(x_new, S, δ_s)
            let (mut s_new, dist) = witnesses.nearest(&x_new[..n]).expect("S is never empty");
            if dist > self.pruning_radius {
                s_new = rep.len() as u32;
                witnesses.add(&x_new[..n], s_new);
                rep.push(NONE);
            }
            let x_peer = rep[s_new as usize];
            if x_peer != NONE && cost >= tree.cost(x_peer) {
                progress.record(i, best.solved_cost());
                continue;
            }

            // V_active ← V_active ∪ {x_new}; E ← E ∪ {x_selected → x_new}
            let id = tree.add(x_selected, &x_new[..n], ext.control, ext.periods, cost);
            if id as usize == active.len() {
                active.push(true);
            } else {
                active[id as usize] = true;
            }
            v_active.add(&x_new[..n], id);
            if let Some(g) = guide.as_mut() {
                g.observe(&x_new[..n]);
            }
            added += 1;

            // PRUNE_DOMINATED_NODES
            if x_peer != NONE && x_peer != 0 {
                active[x_peer as usize] = false;
                v_active.remove(tree.state(x_peer), x_peer);
            }
            rep[s_new as usize] = id;
            let mut x_peer = x_peer;
            while x_peer != NONE && x_peer != 0 && tree.is_leaf(x_peer) && !active[x_peer as usize]
            {
                let x_parent = tree.parent(x_peer);
                tree.remove_leaf(x_peer);
                pruned += 1;
                x_peer = x_parent;
            }

            // the goal
            let gd = problem.goal.distance(&x_new[..n]);
            if problem.goal.contains(&x_new[..n]) && cost < best.cost {
                best = Best {
                    plan: tree.plan_to(id, problem),
                    solved: true,
                    cost,
                };
                first = first.or(Some((i, progress.elapsed())));
            } else if !best.solved && gd < closest.0 {
                closest = (gd, tree.plan_to(id, problem), cost);
            }
            progress.record(i, best.solved_cost());
        }
        if !best.solved {
            best = Best {
                plan: closest.1,
                solved: false,
                cost: closest.2,
            };
        }
        let stats = SstStats {
            witnesses: rep.len(),
            active: v_active.len(),
            nodes: tree.len(),
            added,
            pruned,
        };
        let nodes = tree.len();
        self.last_tree = Some(tree);
        (
            finish(
                problem,
                best,
                i,
                nodes,
                progress,
                first,
                propagate.alpha_max,
            ),
            stats,
        )
    }
}

impl Planner for Sst {
    fn name(&self) -> &str {
        "sst"
    }

    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        self.solve_with_stats(problem).0
    }

    fn tree(&self) -> Option<&Tree> {
        self.last_tree.as_ref()
    }
}
