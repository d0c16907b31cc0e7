//! Why the pipeline could not plan a leg.

use magbench_planners::PlanError;

/// A leg the pipeline could not plan: its start breaks the start rule, or the planner's plan
/// fails the independent validator (a planner bug).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Failure {
    /// The leg's start is invalid in its map (collision or proximity range).
    #[error("leg {}: the start is invalid in this leg's map (collision or proximity range)", .leg + 1)]
    InvalidStart {
        /// The leg (from 0).
        leg: usize,
    },
    /// The planner's plan fails the validator.
    #[error("leg {}: the planner's plan is invalid: {error}", .leg + 1)]
    InvalidPlan {
        /// The leg (from 0).
        leg: usize,
        /// What the validator found.
        error: PlanError,
    },
}

impl Failure {
    /// The leg (from 0).
    pub fn leg(&self) -> usize {
        match self {
            Failure::InvalidStart { leg } | Failure::InvalidPlan { leg, .. } => *leg,
        }
    }

    /// What the validator says of it: an invalid start is the validator's
    /// [`PlanError::InvalidStart`].
    pub fn plan_error(&self) -> PlanError {
        match self {
            Failure::InvalidStart { .. } => PlanError::InvalidStart,
            Failure::InvalidPlan { error, .. } => error.clone(),
        }
    }
}
