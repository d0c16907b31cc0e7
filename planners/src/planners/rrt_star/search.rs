//! The RRT* search: the iteration loop, choosing parents, CONNECT and rewiring.

use magbench_env::math::centroid;
use magbench_env::{MAX_AGENTS, Vec2};
use rand::SeedableRng;

use super::{LoggedSample, RrtStar};
use crate::connect::Connect;
use crate::extend::{Extend, Extension};
use crate::informed::InformedSet;
use crate::motion::propagate_checked;
use crate::nn::NearestNeighbors;
use crate::objective::Motion;
use crate::progress::Progress;
use crate::result::{Best, finish};
use crate::sampler::StateSampler;
use crate::tree::Tree;
use crate::{PlannerResult, Problem, Rng};

impl RrtStar {
    /// Runs RRT* and also returns its counts.
    pub fn solve_with_stats(&mut self, problem: &Problem) -> (PlannerResult, RrtStarStats) {
        let n = problem.agents();
        let extend = self.search.extend(problem);
        let speed =
            problem.model.kinematics.pull_coeff * problem.model.coil.gradient_limit() * 2f64.sqrt();
        let mut s = Search {
            problem,
            n,
            rng: Rng::seed_from_u64(problem.seed),
            tree: Tree::new(&problem.start),
            nn: NearestNeighbors::new(problem.metric, n),
            extend,
            connect: Connect {
                seed: self.search.extend_with(problem, self.connect_tries),
                iterations: self.connect_iterations,
                window: 3,
                tolerance: self.connect_tolerance,
                basin: self.connect_basin,
            },
            near_radius: self.near_radius,
            tolerance: self.connect_tolerance,
            reach: speed * problem.periods(extend.max_periods),
            max_subtree: self.max_subtree,
            best: Best {
                plan: crate::Plan::at(&problem.start),
                solved: false,
                cost: f64::INFINITY,
            },
            subtree: Vec::new(),
            new_states: Vec::new(),
            new_costs: Vec::new(),
            stats: RrtStarStats::default(),
        };
        s.nn.add(&problem.start, 0);
        let zoom = self.search.zoom();
        let mut guide = self.search.guide(problem);
        let sampler = StateSampler::new(problem);
        let informed = InformedSet::new(problem);
        let k_rrt = self.rewire_factor * std::f64::consts::E * (1.0 + 1.0 / (2 * n) as f64);
        let mut progress = Progress::start(problem);
        let mut closest = (0u32, problem.goal.distance(&problem.start));
        let mut first = None;
        if problem.goal.contains(&problem.start) {
            s.best = Best {
                plan: crate::Plan::at(&problem.start),
                solved: true,
                cost: 0.0,
            };
            first = Some((0, 0.0));
        }

        let mut x_rand = [Vec2::zeros(); MAX_AGENTS];
        let mut near = Vec::new();
        let mut i = 0u64;
        while !progress.done(i) && (!self.stop_on_solution || !s.best.solved) {
            i += 1;
            let c_best = s.best.solved_cost();
            // x_rand ← SAMPLE()
            let sampled = match c_best {
                Some(c) if self.informed => {
                    informed.sample(problem, &mut s.rng, &sampler, &zoom, c, &mut x_rand[..n])
                }
                _ => zoom.sample(
                    problem,
                    &sampler,
                    guide.as_ref(),
                    &mut s.rng,
                    &mut x_rand[..n],
                ),
            };
            if let Some(log) = self.sample_log.as_mut().filter(|_| sampled) {
                log.push(LoggedSample {
                    iteration: i,
                    state: x_rand[..n].to_vec(),
                    c_best,
                });
            }
            if sampled && let Some(x_new) = s.iterate(&x_rand[..n], k_rrt, &mut near) {
                if let Some(g) = guide.as_mut() {
                    g.observe(s.tree.state(x_new));
                }
                let d = problem.goal.distance(s.tree.state(x_new));
                if d < closest.1 {
                    closest = (x_new, d);
                }
                if first.is_none() && s.best.solved {
                    first = Some((i, progress.elapsed()));
                }
            }
            progress.record(i, s.best.solved_cost());
        }
        if !s.best.solved {
            s.best = Best {
                plan: s.tree.plan_to(closest.0, problem),
                solved: false,
                cost: s.tree.cost(closest.0),
            };
        }
        let nodes = s.tree.len();
        let stats = s.stats;
        self.last_tree = Some(std::mem::replace(&mut s.tree, Tree::new(&problem.start)));
        let alpha_max = s.extend.alpha_max;
        (
            finish(problem, s.best, i, nodes, progress, first, alpha_max),
            stats,
        )
    }
}

/// Counts of one run (for reports and tests).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RrtStarStats {
    /// CONNECT calls past the reachability filter.
    pub connects: u64,
    /// CONNECT calls that landed within the tolerance.
    pub connected: u64,
    /// Rewires committed.
    pub rewires: u64,
    /// Nodes moved by rewires (each rewired node and its descendants).
    pub moved: u64,
    /// Rewires skipped because the subtree exceeded `max_subtree`.
    pub too_big: u64,
    /// Rewires skipped because a descendant's replayed edge was invalid.
    pub broke: u64,
}

/// What one run keeps.
struct Search<'a> {
    problem: &'a Problem,
    n: usize,
    rng: Rng,
    tree: Tree,
    nn: NearestNeighbors,
    extend: Extend,
    connect: Connect,
    tolerance: f64,
    /// Largest centroid displacement one edge can make (BL), to skip hopeless connections.
    reach: f64,
    max_subtree: usize,
    near_radius: f64,
    best: Best,
    /// Scratch: subtree nodes, their new states and costs.
    subtree: Vec<u32>,
    new_states: Vec<Vec2>,
    new_costs: Vec<f64>,
    stats: RrtStarStats,
}

impl Search<'_> {
    /// One RRT* iteration toward `x_rand`; returns the new node.
    fn iterate(&mut self, x_rand: &[Vec2], k_rrt: f64, near: &mut Vec<(u32, f64)>) -> Option<u32> {
        let (problem, n) = (self.problem, self.n);
        let (x_nearest, _) = self.nn.nearest(x_rand)?;
        let ext = self
            .extend
            .run(problem, &mut self.rng, self.tree.state(x_nearest), x_rand);
        let (mut x_min, mut edge, mut c_min) = (x_nearest, ext, 0.0);
        c_min += self.tree.cost(x_nearest) + self.edge_cost(x_nearest, &ext)?;
        let x_new_target = ext.end;

        // X_near ← the k_RRT·ln(n) nearest nodes of x_new within η
        let k = (k_rrt * (self.tree.len() as f64).ln()).ceil().max(1.0) as usize;
        self.nn.nearest_k(&x_new_target[..n], k, near);
        near.retain(|&(_, d)| d <= self.near_radius);

        // choose the parent by cost
        for &(x_near, _) in near.iter() {
            if x_near == x_nearest {
                continue;
            }
            let bound = self.tree.cost(x_near)
                + problem
                    .objective
                    .motion_cost_heuristic(self.tree.state(x_near), &x_new_target[..n]);
            if bound >= c_min {
                continue;
            }
            if let Some(shot) = self.shoot(x_near, &x_new_target[..n])
                && let Some(c) = self.edge_cost(x_near, &shot)
                && self.tree.cost(x_near) + c < c_min
            {
                (x_min, edge, c_min) = (x_near, shot, self.tree.cost(x_near) + c);
            }
        }
        let x_new = self
            .tree
            .add(x_min, edge.end(n), edge.control, edge.periods, c_min);
        self.nn.add(edge.end(n), x_new);
        self.consider_solution(x_new);

        // rewire
        for &(x_near, _) in near.iter() {
            if x_near == x_min || x_near == 0 {
                continue;
            }
            let c_new = self.tree.cost(x_new);
            let bound = c_new
                + problem
                    .objective
                    .motion_cost_heuristic(self.tree.state(x_new), self.tree.state(x_near));
            if bound >= self.tree.cost(x_near) {
                continue;
            }
            let target: Vec<Vec2> = self.tree.state(x_near).to_vec();
            if let Some(shot) = self.shoot(x_new, &target)
                && let Some(c) = self.edge_cost(x_new, &shot)
                && c_new + c < self.tree.cost(x_near)
            {
                self.rewire(x_near, x_new, &shot, c_new + c);
            }
        }
        Some(x_new)
    }

    /// CONNECT(from, to): the EXTEND optimiser with `connect_tries`, accepted within ε.
    fn shoot(&mut self, from: u32, to: &[Vec2]) -> Option<Extension> {
        let a = self.tree.state(from);
        if (centroid(a) - centroid(to)).norm() > self.reach + self.tolerance {
            return None;
        }
        let shot = self.connect.run(self.problem, &mut self.rng, a, to);
        self.stats.connects += 1;
        self.stats.connected += shot.is_some() as u64;
        shot
    }

    /// The cost of `ext` from node `from` if its motion is valid.
    fn edge_cost(&self, from: u32, ext: &Extension) -> Option<f64> {
        if ext.periods == 0 {
            return None;
        }
        let d = self.problem.periods(ext.periods);
        let mut end = [Vec2::zeros(); MAX_AGENTS];
        let length = propagate_checked(
            self.problem,
            self.tree.state(from),
            &ext.control,
            d,
            &mut end[..self.n],
        )?;
        debug_assert_eq!(
            &end[..self.n],
            ext.end(self.n),
            "checked and unchecked propagation agree"
        );
        Some(self.problem.objective.motion_cost(&Motion {
            control: ext.control,
            duration: d,
            path_length: length,
        }))
    }

    /// Moves `x_near` under `x_new` along `shot` if its whole subtree replays validly.
    fn rewire(&mut self, x_near: u32, x_new: u32, shot: &Extension, cost: f64) {
        let (problem, n) = (self.problem, self.n);
        self.tree.subtree(x_near, &mut self.subtree);
        if self.subtree.len() > self.max_subtree {
            self.stats.too_big += 1;
            return;
        }
        // dry run: replay every descendant's edge from its parent's new state
        self.new_states.clear();
        self.new_states.extend_from_slice(shot.end(n));
        self.new_costs.clear();
        self.new_costs.push(cost);
        let mut end = [Vec2::zeros(); MAX_AGENTS];
        for k in 1..self.subtree.len() {
            let m = self.subtree[k];
            let p = self.subtree[..k]
                .iter()
                .position(|&q| q == self.tree.parent(m))
                .expect("BFS order");
            let (u, d) = (self.tree.control(m), problem.periods(self.tree.periods(m)));
            let from = &self.new_states[p * n..(p + 1) * n];
            let length = match propagate_checked(problem, from, &u, d, &mut end[..n]) {
                Some(l) => l,
                None => {
                    self.stats.broke += 1;
                    return;
                }
            };
            let c = self.new_costs[p]
                + problem.objective.motion_cost(&Motion {
                    control: u,
                    duration: d,
                    path_length: length,
                });
            self.new_states.extend_from_slice(&end[..n]);
            self.new_costs.push(c);
        }
        // commit
        self.stats.rewires += 1;
        self.stats.moved += self.subtree.len() as u64;
        self.tree
            .reparent(x_near, x_new, shot.control, shot.periods);
        for k in 0..self.subtree.len() {
            let m = self.subtree[k];
            self.nn.remove(self.tree.state(m), m);
            self.tree
                .state_mut(m)
                .copy_from_slice(&self.new_states[k * n..(k + 1) * n]);
            self.tree.set_cost(m, self.new_costs[k]);
            self.nn.add(self.tree.state(m), m);
        }
        for k in 0..self.subtree.len() {
            self.consider_solution(self.subtree[k]);
        }
    }

    /// Takes node `x` as the best solution if it is in the goal region and cheaper.
    fn consider_solution(&mut self, x: u32) {
        let problem = self.problem;
        if self.tree.cost(x) < self.best.cost && problem.goal.contains(self.tree.state(x)) {
            self.best = Best {
                plan: self.tree.plan_to(x, problem),
                solved: true,
                cost: self.tree.cost(x),
            };
        }
    }
}
