//! # magbench-planners
//!
//! Kinodynamic planners behind one [`Planner`] trait. A [`Problem`] (scenario leg, planning
//! model, validity checker, objective, limits, seed) goes in; a [`PlannerResult`] with a
//! [`Plan`] — a sequence of (state, control, duration) — comes out. [`validate_plan`] checks any
//! plan independently of the planner that made it.

pub mod plan;
pub mod planner;
pub mod problem;

pub use plan::Plan;
pub use planner::{Planner, PlannerResult, ProgressPoint};
pub use problem::{Limits, Problem};
