//! The one path to a plan a tracker can follow: [`solve_validated`] solves a problem and checks
//! the result with [`validate_result`]; only a result that passed becomes a [`FirstPlan`].

use crate::{Plan, Planner, PlannerResult, Problem, Unusable, validate_result};

/// A plan to follow and how it was made: a planner's plan that passed [`validate_result`] (from
/// [`Validated::followable`]) or a plan file that passed its check ([`FirstPlan::given`]).
#[derive(Debug, Clone, PartialEq)]
pub struct FirstPlan {
    /// The plan.
    pub plan: Plan,
    /// Whether it is an exact solution (it ends in the goal region).
    pub solved: bool,
    /// Wall time it took to make (s); 0 for a given plan.
    pub time_s: f64,
}

impl FirstPlan {
    /// A plan made elsewhere (a plan file, checked by its reader); `solved` when it ends in the
    /// goal region.
    pub fn given(plan: Plan, solved: bool) -> Self {
        FirstPlan {
            plan,
            solved,
            time_s: 0.0,
        }
    }
}

/// A planner's result with the verdict of [`validate_result`] on it.
#[derive(Debug, Clone)]
pub struct Validated {
    /// The planner's result, as a planning-only run records it.
    pub result: PlannerResult,
    /// `Ok` when its plan can be followed, else why not.
    pub verdict: Result<(), Unusable>,
}

impl Validated {
    /// The plan to follow, or why there is none.
    pub fn followable(self) -> Result<FirstPlan, Unusable> {
        self.verdict?;
        Ok(FirstPlan {
            plan: self.result.plan,
            solved: self.result.solved,
            time_s: self.result.time_s,
        })
    }

    /// The planner's plan fails the independent validator (a planner bug): its error.
    pub fn invalid(&self) -> Option<&crate::PlanError> {
        match &self.verdict {
            Err(Unusable::Invalid(e)) => Some(e),
            _ => None,
        }
    }
}

/// Solves `problem` with `planner` and checks the result ([`validate_result`]).
pub fn solve_validated(planner: &mut dyn Planner, problem: &Problem) -> Validated {
    let result = planner.solve(problem);
    let verdict = validate_result(problem, &result);
    Validated { result, verdict }
}
