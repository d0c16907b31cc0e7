//! A planning problem: one leg of a scenario, the model, the checker, the objective and limits.

use std::sync::Arc;
use std::time::Duration;

use magbench_env::model::SteerLimits;
use magbench_env::{Goal, PlanningModel, Scenario, ValidityChecker, Vec2, World};

use crate::distance::Distance;
use crate::objective::Objective;
use crate::setup::PlanningSetup;

/// When a planner stops: after `max_iterations` and/or after `time_limit`, whichever first.
/// For bit-for-bit reproducible runs, limit iterations only. With neither set, planners use the
/// default iteration limit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Largest number of iterations.
    pub max_iterations: Option<u64>,
    /// Largest wall time.
    pub time_limit: Option<Duration>,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_iterations: Some(200_000),
            time_limit: None,
        }
    }
}

/// Everything a planner needs.
#[derive(Debug, Clone)]
pub struct Problem {
    /// Name of the scenario (for reports).
    pub scenario: String,
    /// The world of this leg.
    pub world: World,
    /// Start positions (BL).
    pub start: Vec<Vec2>,
    /// Goal region.
    pub goal: Goal,
    /// The deterministic planning model (coil limits included).
    pub model: PlanningModel,
    /// The validity checker of this leg.
    pub checker: ValidityChecker,
    /// Edge durations are whole multiples of this control period (s): the camera frame.
    pub control_period: f64,
    /// Stop conditions.
    pub limits: Limits,
    /// Seed of the planner's random stream.
    pub seed: u64,
    /// The cost to minimise (sum of agent path lengths by default).
    pub objective: Arc<dyn Objective>,
    /// The distance of nearest-neighbour queries and EXTEND (agent positions by default).
    pub metric: Distance,
    /// The largest field elevation |α| a plan may command (rad); the validator enforces it.
    pub alpha_max: f64,
}

/// Largest miss of an exact steer onto its target (BL, any agent): far inside any goal
/// tolerance, so a steer onto a waypoint or goal lands on it for every check that follows.
pub const STEER_TOLERANCE: f64 = 1e-6;

impl Problem {
    /// The problem of leg `leg` of `scenario`, from `start` (the scenario's start if `None`),
    /// under the default [`PlanningSetup`]: path length, agent positions, the default limits,
    /// the default control period (one 60 fps frame) and the default flow. A run that will
    /// be tracked makes its problems from its own setup ([`PlanningSetup::problem`]).
    pub fn from_scenario(
        scenario: &Scenario,
        leg: usize,
        start: Option<&[Vec2]>,
        seed: u64,
    ) -> Self {
        PlanningSetup::default().problem(scenario, leg, start, seed)
    }

    /// Number of agents.
    pub fn agents(&self) -> usize {
        self.start.len()
    }

    /// The limits of env's exact pair steer on this problem: edges of whole control periods, at
    /// most `max_periods` each, between the validity check's separations, landing within
    /// [`STEER_TOLERANCE`] of the target.
    pub fn steer_limits(&self, max_periods: u32) -> SteerLimits {
        SteerLimits {
            period: self.control_period,
            max_periods,
            separation: [self.checker.r_min, self.checker.r_max],
            tolerance: STEER_TOLERANCE,
        }
    }

    /// The duration of `periods` control periods (s); every edge duration is one of these.
    #[inline]
    pub fn periods(&self, periods: u32) -> f64 {
        periods as f64 * self.control_period
    }

    /// The largest iteration count the limits allow (`u64::MAX` when only time limits).
    pub fn max_iterations(&self) -> u64 {
        match (self.limits.max_iterations, self.limits.time_limit) {
            (Some(n), _) => n,
            (None, Some(_)) => u64::MAX,
            (None, None) => Limits::default().max_iterations.unwrap_or(u64::MAX),
        }
    }
}
