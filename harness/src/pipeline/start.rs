//! The start rule: where a plan of a run may start.
//!
//! - A leg is planned only from a start that is valid in the leg's map (the validator refuses
//!   every plan from any other); the first leg's start is the scenario's or a given one, a
//!   later leg's the end of the previous leg's plan.
//! - A given plan (a plan file, or a plan handed to the library) replaces the first leg: it
//!   must name this scenario if it names one, move its team, and start each agent within the
//!   first leg's goal tolerance of the scenario's start
//!   ([`magbench_trackers::plan_file::check_origin`]); then it must fit the run's setup
//!   ([`magbench_trackers::plan_file::check_plan`]).

use magbench_env::{InputError, Scenario};
use magbench_planners::{Plan, PlanningSetup, Problem};
use magbench_trackers::plan_file::{check_origin, check_plan};

use super::Failure;

/// `Ok` when `problem` (leg `leg`) starts in a valid state of its map.
pub fn check_leg_start(problem: &Problem, leg: usize) -> Result<(), Failure> {
    if problem.checker.is_valid(&problem.start) {
        Ok(())
    } else {
        Err(Failure::InvalidStart { leg })
    }
}

/// `Ok` when `plan`, named `source` in errors, may replace the first leg of `scenario` under
/// `setup`: its origin ([`check_origin`]), then its fit ([`check_plan`]).
pub fn check_given_plan(
    plan: &Plan,
    scenario: &Scenario,
    source: &str,
    setup: &PlanningSetup,
) -> Result<(), InputError> {
    check_origin(plan, scenario, source)?;
    check_plan(plan, scenario, source, setup)
}
