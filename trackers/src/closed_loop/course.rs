//! The course of a run: which leg is being driven, its map and goal, and when the team has
//! held a goal long enough to complete the leg.

use magbench_env::{Goal, Scenario, ValidityChecker, Vec2, World};

/// Where the team is goal-wise this tick.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GoalHold {
    /// The estimate is not inside the goal (by the margin).
    Outside,
    /// Inside, not yet for the hold time.
    Holding,
    /// Inside for the hold time: the leg is done.
    Held,
}

/// The legs of a scenario, driven in order.
#[derive(Debug, Clone)]
pub struct Course<'s> {
    scenario: &'s Scenario,
    leg: usize,
    world: World,
    checker: ValidityChecker,
    hold: f64,
    goal_margin: f64,
    in_goal_since: Option<f64>,
    completed: usize,
    time_to_goal: Option<f64>,
}

impl<'s> Course<'s> {
    /// The course of `scenario` from its first leg. The team completes a leg by staying
    /// `goal_margin` BL inside its goal tolerance for `hold` seconds.
    pub fn new(scenario: &'s Scenario, hold: f64, goal_margin: f64) -> Self {
        Self {
            scenario,
            leg: 0,
            world: scenario.world_for_leg(0),
            checker: scenario.checker_for_leg(0),
            hold,
            goal_margin,
            in_goal_since: None,
            completed: 0,
            time_to_goal: None,
        }
    }

    /// The scenario.
    pub fn scenario(&self) -> &'s Scenario {
        self.scenario
    }

    /// The leg being driven (0-based).
    pub fn leg(&self) -> usize {
        self.leg
    }

    /// The world of the current leg (its bounds and obstacles).
    pub fn world(&self) -> &World {
        &self.world
    }

    /// Walls, obstacles and proximity range of the current leg.
    pub fn checker(&self) -> &ValidityChecker {
        &self.checker
    }

    /// The current leg's goal.
    pub fn goal(&self) -> &'s Goal {
        &self.scenario.legs[self.leg].goal
    }

    /// Legs completed, and legs in all.
    pub fn legs(&self) -> (usize, usize) {
        (self.completed, self.scenario.legs.len())
    }

    /// Rig time from the first tick until the final goal was held, once it was.
    pub fn time_to_goal(&self) -> Option<f64> {
        self.time_to_goal
    }

    /// Folds in the estimate `x` at rig time `now`.
    pub fn hold(&mut self, x: &[Vec2], now: f64) -> GoalHold {
        let goal = self.goal();
        let inside = goal.distance(x) <= goal.tolerance - self.goal_margin;
        if !inside {
            self.in_goal_since = None;
            return GoalHold::Outside;
        }
        let since = *self.in_goal_since.get_or_insert(now);
        if now - since + 1e-9 < self.hold {
            GoalHold::Holding
        } else {
            GoalHold::Held
        }
    }

    /// Completes the current leg at `elapsed` seconds since the first tick; returns the next
    /// leg's world, or `None` after the last leg.
    pub fn complete(&mut self, elapsed: f64) -> Option<World> {
        self.completed += 1;
        self.in_goal_since = None;
        if self.leg + 1 == self.scenario.legs.len() {
            self.time_to_goal = Some(elapsed);
            return None;
        }
        self.leg += 1;
        self.checker = self.scenario.checker_for_leg(self.leg);
        self.world = self.scenario.world_for_leg(self.leg);
        Some(self.world.clone())
    }
}
