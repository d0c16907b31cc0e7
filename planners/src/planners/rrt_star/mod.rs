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
//! with drift). CONNECT shoots ([`crate::steer`]): the EXTEND optimiser's random (control,
//! duration) tries (`connect_tries`) seed a damped Gauss–Newton refinement of the control
//! (`connect_iterations`, only when the best seed ends within `connect_basin`), and the
//! connection is accepted only when its end lies within `connect_tolerance` ε (metric distance,
//! BL) of the target. Neighbours farther than η = `near_radius` are not tried: beyond ~1 BL a
//! single constant control almost never lands within ε. A connection therefore reaches a point
//! *near* its target, not the target itself:
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

mod search;

pub use search::RrtStarStats;

use magbench_env::Vec2;

use crate::params::{boolean, check_durations, number, positive, whole};
use crate::planner::{Param, ParamError};
use crate::tree::Tree;
use crate::{Planner, PlannerResult, Problem};

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
    /// Stop at the first exact solution instead of improving until the limits.
    pub stop_on_solution: bool,
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
            stop_on_solution: false,
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
                name: "stop_on_solution",
                value: self.stop_on_solution.to_string(),
                help: "stop at the first solution (success-rate runs)",
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
            "stop_on_solution" => self.stop_on_solution = boolean(key, value)?,
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
