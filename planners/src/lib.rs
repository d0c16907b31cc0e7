//! # magbench-planners
//!
//! Kinodynamic planners behind one [`Planner`] trait. A [`Problem`] (scenario leg, planning
//! model, validity checker, objective, metric, limits, seed) goes in; a [`PlannerResult`] with a
//! [`Plan`] — a sequence of (state, control, duration) — comes out. [`validate_plan`] checks any
//! plan independently of the planner that made it.
//!
//! The planners ([`registry::Planners`] creates them by name and `key=value` parameters):
//!
//! - `goal-zoom-rrt`: the seed's Algorithms 1–3 ([`planners::GoalZoomRrt`]);
//! - `rrt-star`: kinodynamic RRT* with shooting connections ([`planners::RrtStar`]);
//! - `informed-rrt-star`: RRT* sampling only states that can improve the solution;
//! - `sst`: Stable Sparse RRT ([`planners::Sst`]);
//! - `formation-rrt`: for teams, shapes sampled apart from the centroid
//!   ([`planners::FormationRrt`]);
//! - `trajopt`: trajectory optimisation from a straight line by sequential convex programming
//!   ([`planners::Trajopt`], [`trajopt`]);
//! - `ompl:rrt`, `ompl:sst`, `ompl:kpiece`, `ompl:est`, `ompl:pdst`: OMPL's control planners on
//!   this model (cargo feature `ompl`; [`ompl`]).
//!
//! The physics is env's: planners propagate with `PlanningModel::propagate_with` and check with
//! `ValidityChecker`; every edge lasts a whole number of control periods (the camera frames of
//! the rig that will run the plan). A run's [`PlanningSetup`] (objective, metric, limits,
//! control period, flow) makes every problem it plans, and [`validate_result`] is the one rule for
//! whether a result can be followed.

#![warn(missing_docs)]

pub mod connect;
pub mod distance;
pub mod extend;
pub mod extend_batch;
pub mod first_plan;
pub mod goal_connect;
pub mod guide;
pub mod informed;
pub mod motion;
pub mod nn;
pub mod objective;
#[cfg(feature = "ompl")]
pub mod ompl;
pub mod plan;
pub mod planner;
pub mod planners;
pub mod post_process;
pub mod post_processed;
pub mod problem;
pub mod progress;
pub mod registry;
pub mod repair;
pub mod result;
pub mod sampler;
pub mod search_settings;
pub mod seeds;
pub mod setup;
pub mod shortcut;
pub mod straighten;
pub mod trajopt;
pub mod tree;
pub mod validate;

pub use distance::{Distance, DistanceError};
pub use first_plan::{FirstPlan, Validated, solve_validated};
pub use objective::{Objective, plan_cost};
pub use plan::{MadeFor, Plan};
pub use planner::{Planner, PlannerResult, ProgressPoint};
pub use post_process::PostProcess;
pub use post_processed::PostProcessed;
pub use problem::{Limits, Problem};
pub use registry::Planners;
pub use setup::{ElevationError, ElevationRefused, PlanningSetup, Unusable, validate_result};
pub use validate::{PlanError, validate_path, validate_plan};

/// The planners' random stream: portable and seedable (ChaCha8), never a thread or OS RNG.
pub type Rng = rand_chacha::ChaCha8Rng;
