//! Why one run of a sweep failed: its `crash` row's `error` column is this error's text.

use magbench_env::InputError;
use magbench_planners::PlanError;

/// Why a run could not be executed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RunError {
    /// A planning-setup key of the planner variant refused its value (`KEY: REASON`).
    #[error("{}: {}", .0.field, .0.reason)]
    Setup(InputError),
    /// The planner or tracker refused its parameters (the reason).
    #[error("{}", .0.reason)]
    Component(InputError),
    /// A leg's plan fails the independent validator: a planner bug.
    #[error("leg {}: the planner's plan is invalid: {error}", .leg + 1)]
    InvalidPlan {
        /// The leg (from 0).
        leg: usize,
        /// What the validator found.
        error: PlanError,
    },
}
