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
//! with drift). CONNECT shoots ([`crate::connect`]): the EXTEND optimiser's random (control,
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

use magbench_env::params::Reals;
use magbench_env::{Vec2, declare_params};

use crate::search_settings::SearchSettings;
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

declare_params! {
    /// Kinodynamic RRT* (and informed RRT* when `informed`).
    #[derive(Debug, Clone)]
    pub struct RrtStar {
        /// The registry name it was made as (`rrt-star` or `informed-rrt-star`); parameters
        /// never rename it.
        name: &'static str = "rrt-star",
        /// EXTEND's tries (toward a sample) and durations, the goal-zoom sampler.
        #[params]
        pub search: SearchSettings,
        /// CONNECT's random seeding tries (the shooting connection).
        #[param("connect_tries", 1..=100_000)]
        pub connect_tries: usize = 4,
        /// CONNECT's Gauss-Newton refinement iterations.
        #[param("connect_iterations", 0..=1000)]
        pub connect_iterations: usize = 8,
        /// Largest metric distance (BL) a connection may miss its target by (ε).
        #[param("connect_tolerance", Reals::POSITIVE)]
        pub connect_tolerance: f64 = 0.1,
        /// Refine a connection only when its best seed ends this close to the target (BL).
        #[param("connect_basin", Reals::POSITIVE)]
        pub connect_basin: f64 = 0.75,
        /// η: largest metric distance (BL) of a neighbour to connect.
        #[param("near_radius", Reals::POSITIVE)]
        pub near_radius: f64 = 1.0,
        /// Multiplies k_RRT = e (1 + 1/d) in the k_RRT·ln(n) near neighbours.
        #[param("rewire_factor", Reals::POSITIVE)]
        pub rewire_factor: f64 = 1.0,
        /// Largest subtree a rewire re-propagates.
        #[param("max_subtree", 1..=u32::MAX as usize)]
        pub max_subtree: usize = 500,
        /// Stop at the first solution (success-rate runs) instead of improving until the
        /// limits.
        #[param("stop_on_solution")]
        pub stop_on_solution: bool = false,
        /// Sample only states that can improve the best solution, once there is one.
        #[param("informed")]
        pub informed: bool = false,
        /// When `Some`, every sample is appended here (tests, diagnostics).
        pub sample_log: Option<Vec<LoggedSample>> = None,
        /// The tree of the last solve.
        pub last_tree: Option<Tree> = None,
    }
}

impl RrtStar {
    /// Informed RRT* with the default parameters (registered as `informed-rrt-star`).
    pub fn informed() -> Self {
        RrtStar {
            name: "informed-rrt-star",
            informed: true,
            ..RrtStar::default()
        }
    }
}

impl Planner for RrtStar {
    fn name(&self) -> &str {
        self.name
    }

    fn solve(&mut self, problem: &Problem) -> PlannerResult {
        self.solve_with_stats(problem).0
    }

    fn tree(&self) -> Option<&Tree> {
        self.last_tree.as_ref()
    }
}
