//! The one pipeline of a run, in the spirit of OMPL's `SimpleSetup`: plan every leg → check →
//! post-process → track. Sweeps (`run::real`), `magbench plan`, `track`, `rig run`, the paper
//! figures ([`crate::figures`]) and the library entry points of the Python package
//! ([`crate::api`]) all plan and track through it.
//!
//! - **Plan.** Leg `k` is planned from the end of leg `k − 1`'s plan (the first from the
//!   scenario's start, or a given start) with a fresh planner, seeded by the seed rule
//!   ([`magbench_planners::seeds::leg_seed`]); planning stops at the first unsolved leg.
//! - **Check.** The start rule ([`start`]) before the planner runs, the independent validator
//!   ([`magbench_planners::solve_validated`]) after: a refused plan is a [`Failure`].
//! - **Post-process.** The passes of the run's `shortcut` and `straighten` parameters, applied
//!   to every planner the registry makes ([`magbench_planners::PostProcessed`]), so a plugin's
//!   plans get them with no code of its own; the validator checks the processed plan.
//! - **Track.** [`Pipeline::mission`] hands the first plan, the planner and the setup to the
//!   tracking loop, which plans later legs and replans with the same setup and seed.
//!
//! What each caller records (a results row, the command line's files, Python objects) stays
//! the caller's.

pub mod failure;
pub mod start;

use magbench_env::{Scenario, Vec2};
use magbench_planners::seeds::leg_seed;
use magbench_planners::{
    FirstPlan, Planner, PlannerResult, PlanningSetup, Problem, Validated, solve_validated,
};
use magbench_trackers::Mission;

pub use failure::Failure;

use crate::replay::LegTree;

/// A run's scenario, planning setup and seed: what every plan of the run is made from.
#[derive(Debug, Clone)]
pub struct Pipeline<'a> {
    /// The scenario.
    pub scenario: &'a Scenario,
    /// What every planning call is made under.
    pub setup: PlanningSetup,
    /// The run's seed.
    pub seed: u64,
}

/// One planned leg: its problem, the planner's result with the validator's verdict, and the
/// planner's search tree (when it keeps one).
#[derive(Debug, Clone)]
pub struct LegPlan {
    /// The leg (from 0).
    pub leg: usize,
    /// The problem it was planned for.
    pub problem: Problem,
    /// The result and its verdict.
    pub validated: Validated,
    /// The search tree of the leg, when the planner keeps one.
    pub tree: Option<LegTree>,
    /// Why the planner stopped without an exact solution, when it says
    /// ([`Planner::stop_reason`]).
    pub stopped: Option<String>,
}

impl AsRef<PlannerResult> for LegPlan {
    fn as_ref(&self) -> &PlannerResult {
        &self.validated.result
    }
}

impl<'a> Pipeline<'a> {
    /// The pipeline of `scenario` under `setup` with seed `seed`.
    pub fn new(scenario: &'a Scenario, setup: PlanningSetup, seed: u64) -> Self {
        Pipeline {
            scenario,
            setup,
            seed,
        }
    }

    /// The problem of leg `leg` from `start` (the scenario's start if `None`), seeded by the
    /// seed rule.
    pub fn problem(&self, leg: usize, start: Option<&[Vec2]>) -> Problem {
        self.setup
            .problem(self.scenario, leg, start, leg_seed(self.seed, leg))
    }

    /// Plans leg `leg` from `start` with `planner`: the start rule, the planner's solve (its
    /// post-processing included), then the validator. A plan without motion is returned (not
    /// followable); an invalid start or a plan the validator refuses is a [`Failure`].
    pub fn plan_leg(
        &self,
        planner: &mut dyn Planner,
        leg: usize,
        start: Option<&[Vec2]>,
    ) -> Result<LegPlan, Failure> {
        let problem = self.problem(leg, start);
        start::check_leg_start(&problem, leg)?;
        let validated = solve_validated(planner, &problem);
        if let Some(error) = validated.invalid() {
            return Err(Failure::InvalidPlan {
                leg,
                error: error.clone(),
            });
        }
        let tree = LegTree::of_planner(planner, &problem, leg);
        let stopped = planner
            .stop_reason()
            .filter(|_| !validated.result.solved)
            .map(str::to_string);
        Ok(LegPlan {
            leg,
            problem,
            validated,
            tree,
            stopped,
        })
    }

    /// Plans every leg in turn with `plan_one(leg, start)` ([`Pipeline::plan_leg`] with a
    /// fresh planner, and whatever the caller keeps of it), each from the end of the previous
    /// leg's plan, the first from the scenario's start; stops after the first unsolved leg.
    pub fn plan_legs<T: AsRef<PlannerResult>, E>(
        &self,
        mut plan_one: impl FnMut(usize, Option<&[Vec2]>) -> Result<T, E>,
    ) -> Result<Vec<T>, E> {
        let mut legs: Vec<T> = vec![];
        for leg in 0..self.scenario.legs.len() {
            let start = legs.last().map(|l| l.as_ref().plan.end().to_vec());
            let planned = plan_one(leg, start.as_deref())?;
            let solved = planned.as_ref().solved;
            legs.push(planned);
            if !solved {
                break;
            }
        }
        Ok(legs)
    }

    /// The tracking loop's mission: follow `first`, and plan later legs and replans with
    /// `planner` under this setup and seed.
    pub fn mission<'p>(
        &'p self,
        first: FirstPlan,
        planner: Option<&'p mut dyn Planner>,
    ) -> Mission<'p> {
        Mission {
            scenario: self.scenario,
            first,
            planner,
            setup: self.setup.clone(),
            seed: self.seed,
        }
    }
}
