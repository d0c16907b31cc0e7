//! `rrt-star` and `informed-rrt-star`: kinodynamic RRT* (Karaman & Frazzoli) with shooting
//! connections, and its informed variant (Gammell, Srinivasa & Barfoot).
//!
//! ```text
//! for i = 1, 2, … until the limits:
//!   x_rand ← SAMPLE()               goal-zoom coin toss; informed: rejected unless ĝ + ĥ < c_best
//!   x_nearest ← NEAREST(x_rand)
//!   (x_new, u, T) ← EXTEND(x_nearest, x_rand); continue unless collision-free
//!   X_near ← the k_RRT·ln(n) nearest nodes of x_new within η
//!   // choose the parent by cost
//!   x_min ← x_nearest; c_min ← c(x_nearest) + c(u, T)
//!   for x_near ∈ X_near with c(x_near) + ĉ(x_near, x_new) < c_min:
//!     if CONNECT(x_near, x_new) lands within ε, is collision-free and costs less: x_min ← x_near
//!   add x_new — where x_min's edge ends — with parent x_min
//!   // rewire
//!   for x_near ∈ X_near with c(x_new) + ĉ(x_new, x_near) < c(x_near):
//!     if CONNECT(x_new, x_near) lands within ε at x′_near, is collision-free and costs less, and
//!     x_near's subtree replayed from x′_near stays valid: move x_near to x′_near under x_new and
//!     re-propagate its descendants, updating their states and costs
//!   a node that enters the goal region cheaper than c_best becomes the best solution
//! ```
//!
//! **The approximation.** No exact steering function exists for this system (underactuated,
//! with drift). CONNECT shoots: it runs the EXTEND optimiser (random (control, duration) tries,
//! keep the end closest to the target) with `connect_tries` tries and accepts the connection
//! only when the best end lies within `connect_tolerance` (metric distance, BL) of the target.
//! A connection therefore reaches a point *near* its target, not the target itself:
//!
//! - choosing a parent, the new node is placed where the chosen parent's edge ends;
//! - rewiring moves `x_near` to where the new edge ends, and its descendants' states change
//!   when their stored controls are replayed from there. The whole subtree is re-propagated
//!   (and re-checked) before the rewire is accepted, so every stored state is exactly what its
//!   edge replays to; rewires whose subtree would collide, or that exceed `max_subtree` nodes,
//!   are skipped.
//!
//! Costs are re-computed along the replayed edges, so they stay exact. The best solution is
//! kept as a plan snapshot whenever it improves, so its cost never increases even if a later
//! rewire moves its goal node. The asymptotic optimality of RRT* holds for this scheme only up
//! to the tolerance ε.

use magbench_env::{MAX_AGENTS, Vec2};
use rand::{RngExt, SeedableRng};

use crate::extend::{Extend, Extension};
use crate::informed::InformedSet;
use crate::motion::propagate_checked;
use crate::nn::NearestNeighbors;
use crate::objective::Motion;
use crate::params::{boolean, check_durations, number, positive, to_periods, whole};
use crate::planner::{Param, ParamError};
use crate::progress::Progress;
use crate::result::{Best, finish};
use crate::sampler::{GoalZoom, SAMPLE_TRIES, StateSampler};
use crate::steer::Connect;
use crate::tree::Tree;
use crate::{Planner, PlannerResult, Problem, Rng};

/// One sample drawn by RRT*, with the best cost when it was drawn (for tests and diagnostics).
#[derive(Debug, Clone, PartialEq)]
pub struct LoggedSample {
    /// The iteration.
    pub iteration: u64,
    /// The sampled state.
    pub state: Vec<Vec2>,
    /// The best solution cost at that moment.
    pub c_best: Option<f64>,
}

/// Kinodynamic RRT* (and informed RRT* when `informed`).
#[derive(Debug, Clone)]
pub struct RrtStar {
    /// Sample only the informed set once a solution exists.
    pub informed: bool,
    /// EXTEND's random tries toward a sample.
    pub tries: usize,
    /// Shortest edge duration (s), rounded to whole control periods.
    pub min_duration: f64,
    /// Longest edge duration (s), rounded to whole control periods.
    pub max_duration: f64,
    /// Probability of sampling the goal-zoom region.
    pub goal_bias: f64,
    /// Radius of the goal-zoom region about each agent's goal centre (BL).
    pub zoom_radius: f64,
    /// CONNECT's random seeding tries (the shooting steer).
    pub connect_tries: usize,
    /// CONNECT's Gauss–Newton refinement iterations.
    pub connect_iterations: usize,
    /// Largest distance (metric, BL) between a connection's end and its target.
    pub connect_tolerance: f64,
    /// Refine a connection only when its best seed ends this close to the target (BL).
    pub connect_basin: f64,
    /// η: neighbours farther than this (metric, BL) are not connected to.
    pub near_radius: f64,
    /// Multiplies k_RRT = e (1 + 1/d) in the k_RRT·ln(n) nearest neighbours.
    pub rewire_factor: f64,
    /// Largest subtree a rewire re-propagates.
    pub max_subtree: usize,
    /// When `Some`, every sample is appended here (tests, diagnostics).
    pub sample_log: Option<Vec<LoggedSample>>,
    /// The tree of the last solve.
    pub last_tree: Option<Tree>,
}

impl Default for RrtStar {
    fn default() -> Self {
        RrtStar {
            informed: false,
            tries: 5,
            min_duration: 0.25,
            max_duration: 2.0,
            goal_bias: 0.1,
            zoom_radius: 1.5,
            connect_tries: 4,
            connect_iterations: 8,
            connect_basin: 0.75,
            near_radius: 1.0,
            connect_tolerance: 0.1,
            rewire_factor: 1.0,
            max_subtree: 500,
            sample_log: None,
            last_tree: None,
        }
    }
}

impl RrtStar {
    /// Informed RRT* with the default parameters.
    pub fn informed() -> Self {
        RrtStar {
            informed: true,
            ..RrtStar::default()
        }
    }

    /// Runs RRT* and also returns its counts.
    pub fn solve_with_stats(&mut self, problem: &Problem) -> (PlannerResult, RrtStarStats) {
        let n = problem.agents();
        let period = problem.control_period;
        let (lo, hi) = (
            to_periods(self.min_duration, period),
            to_periods(self.max_duration, period),
        );
        let speed =
            problem.model.kinematics.pull_coeff * problem.model.coil.gradient_limit() * 2f64.sqrt();
        let mut s = Search {
            problem,
            n,
            rng: Rng::seed_from_u64(problem.seed),
            tree: Tree::new(&problem.start),
            nn: NearestNeighbors::new(problem.metric, n),
            extend: Extend {
                tries: self.tries,
                min_periods: lo,
                max_periods: hi,
            },
            connect: Connect {
                seed: Extend {
                    tries: self.connect_tries,
                    min_periods: lo,
                    max_periods: hi,
                },
                iterations: self.connect_iterations,
                window: 3,
                tolerance: self.connect_tolerance,
                basin: self.connect_basin,
            },
            near_radius: self.near_radius,
            tolerance: self.connect_tolerance,
            reach: speed * problem.periods(hi),
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
        let zoom = GoalZoom {
            bias: self.goal_bias,
            radius: self.zoom_radius,
        };
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
        while !progress.done(i) {
            i += 1;
            let c_best = s.best.solved_cost();
            // x_rand ← SAMPLE()
            let sampled = match c_best {
                Some(c) if self.informed => {
                    sample_informed(&mut s, &informed, &sampler, &zoom, c, &mut x_rand[..n])
                }
                _ => zoom.sample(problem, &sampler, &mut s.rng, &mut x_rand[..n]),
            };
            if let Some(log) = self.sample_log.as_mut().filter(|_| sampled) {
                log.push(LoggedSample {
                    iteration: i,
                    state: x_rand[..n].to_vec(),
                    c_best,
                });
            }
            if sampled && let Some(x_new) = s.iterate(&x_rand[..n], k_rrt, &mut near) {
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
        (finish(problem, s.best, i, nodes, progress, first), stats)
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

impl Planner for RrtStar {
    fn name(&self) -> &str {
        if self.informed {
            "informed-rrt-star"
        } else {
            "rrt-star"
        }
    }

    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        self.solve_with_stats(problem).0
    }

    fn params(&self) -> Vec<Param> {
        vec![
            Param {
                name: "k",
                value: self.tries.to_string(),
                help: "EXTEND's random (control, duration) tries toward a sample",
            },
            Param {
                name: "min_duration",
                value: self.min_duration.to_string(),
                help: "shortest edge (s), rounded to whole 1/60 s periods",
            },
            Param {
                name: "max_duration",
                value: self.max_duration.to_string(),
                help: "longest edge (s), rounded to whole 1/60 s periods",
            },
            Param {
                name: "goal_bias",
                value: self.goal_bias.to_string(),
                help: "probability of sampling the goal-zoom region",
            },
            Param {
                name: "zoom_radius",
                value: self.zoom_radius.to_string(),
                help: "radius of each agent's goal-zoom disk (BL)",
            },
            Param {
                name: "connect_tries",
                value: self.connect_tries.to_string(),
                help: "CONNECT's random seeding tries (shooting steer)",
            },
            Param {
                name: "connect_iterations",
                value: self.connect_iterations.to_string(),
                help: "CONNECT's Gauss-Newton refinement iterations",
            },
            Param {
                name: "connect_tolerance",
                value: self.connect_tolerance.to_string(),
                help: "largest metric distance (BL) a connection may miss its target by",
            },
            Param {
                name: "connect_basin",
                value: self.connect_basin.to_string(),
                help: "refine a connection only when its best seed ends this close (BL)",
            },
            Param {
                name: "near_radius",
                value: self.near_radius.to_string(),
                help: "η: largest metric distance (BL) of a neighbour to connect",
            },
            Param {
                name: "rewire_factor",
                value: self.rewire_factor.to_string(),
                help: "multiplies k_RRT in the k_RRT·ln(n) near neighbours",
            },
            Param {
                name: "max_subtree",
                value: self.max_subtree.to_string(),
                help: "largest subtree a rewire re-propagates",
            },
            Param {
                name: "informed",
                value: self.informed.to_string(),
                help: "sample only states that can improve the best solution",
            },
        ]
    }

    fn set_param(&mut self, key: &str, value: &str) -> Result<(), ParamError> {
        match key {
            "k" => self.tries = whole(key, value, 1, 100_000)? as usize,
            "min_duration" => self.min_duration = positive(key, value)?,
            "max_duration" => self.max_duration = positive(key, value)?,
            "goal_bias" => self.goal_bias = number(key, value, 0.0, 1.0)?,
            "zoom_radius" => self.zoom_radius = positive(key, value)?,
            "connect_tries" => self.connect_tries = whole(key, value, 1, 100_000)? as usize,
            "connect_iterations" => self.connect_iterations = whole(key, value, 0, 1000)? as usize,
            "connect_tolerance" => self.connect_tolerance = positive(key, value)?,
            "connect_basin" => self.connect_basin = positive(key, value)?,
            "near_radius" => self.near_radius = positive(key, value)?,
            "rewire_factor" => self.rewire_factor = positive(key, value)?,
            "max_subtree" => self.max_subtree = whole(key, value, 1, u32::MAX as u64)? as usize,
            "informed" => self.informed = boolean(key, value)?,
            _ => return Err(ParamError::Unknown(key.into())),
        }
        Ok(())
    }

    fn tree(&self) -> Option<&Tree> {
        self.last_tree.as_ref()
    }

    fn check_params(&self) -> Result<(), ParamError> {
        check_durations(self.min_duration, self.max_duration)
    }
}

/// x_rand from the informed set for `c_best`. The goal-zoom coin toss is kept (as OMPL's
/// informed RRT* keeps its goal bias): heads draws from the zoom region, tails from the
/// per-agent ellipses (path length) or the whole space (other objectives); either way the
/// draw is rejected unless it is in the informed set and valid.
fn sample_informed(
    s: &mut Search,
    set: &InformedSet,
    sampler: &StateSampler,
    zoom: &GoalZoom,
    c_best: f64,
    out: &mut [Vec2],
) -> bool {
    let problem = s.problem;
    let heads = s.rng.random::<f64>() < zoom.bias;
    for _ in 0..SAMPLE_TRIES {
        let drawn = if heads {
            sampler.zoom(&mut s.rng, &problem.goal, zoom.radius, out);
            true
        } else if set.uses_ellipses() {
            set.sample_ellipses(&mut s.rng, c_best, out)
        } else {
            sampler.uniform(&mut s.rng, out);
            true
        };
        if drawn && set.contains(problem, out, c_best) && problem.checker.is_valid(out) {
            return true;
        }
    }
    false
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

fn centroid(s: &[Vec2]) -> Vec2 {
    s.iter().sum::<Vec2>() / s.len() as f64
}
