//! Scenarios: the world, the start and one goal or several legs, in a stable TOML format.
//!
//! See docs/scenarios.md for the format. [`Scenario::load`] accepts a built-in name
//! or a path; every rejection is an [`InputError`](crate::InputError) naming the file, the field
//! and the reason.

mod builtin;
pub mod difficulty;
mod file;
pub mod freespace;
pub mod generate;
mod write;

pub use builtin::{BUILTIN, builtin_names, builtin_source};
pub use difficulty::Difficulty;
pub use file::{MAX_WORLD_BL, parse_scenario};
pub use write::Draft;

use std::sync::Arc;

use crate::collision::{CollisionWorld, ValidityChecker};
use crate::error::InputError;
use crate::math::Vec2;
use crate::physics::PhysicalParams;
use crate::plant::{DisturbancePreset, Medium};
use crate::team_symmetry::symmetry_note;
use crate::world::{Obstacle, World};

/// A goal region: every agent within `tolerance` of its goal centre.
#[derive(Debug, Clone, PartialEq)]
pub struct Goal {
    /// Goal centre per agent (BL).
    pub agents: Vec<Vec2>,
    /// Radius of each agent's goal disk (BL).
    pub tolerance: f64,
}

impl Goal {
    /// Largest distance of an agent from its goal centre (BL); NaN when a position is not a
    /// number (so a lost estimate is never inside a goal).
    pub fn distance(&self, s: &[Vec2]) -> f64 {
        crate::math::max_agent_distance(s, &self.agents)
    }

    /// True when every agent is within the tolerance of its goal centre.
    pub fn contains(&self, s: &[Vec2]) -> bool {
        self.distance(s) <= self.tolerance
    }
}

/// One leg: a goal, and optionally the obstacles that replace the world's from this leg on.
#[derive(Debug, Clone, PartialEq)]
pub struct Leg {
    /// The leg's goal region.
    pub goal: Goal,
    /// New obstacles (a map switch), if any.
    pub obstacles: Option<Vec<Obstacle>>,
}

/// A validated scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// Scenario name.
    pub name: String,
    /// Free text.
    pub description: String,
    /// Where it came from (a path, or `built-in:NAME`).
    pub source: String,
    /// The world at the start.
    pub world: World,
    /// Start position per agent (BL).
    pub start: Vec<Vec2>,
    /// The legs; a scenario with a single `[goal]` has one leg without a map switch.
    pub legs: Vec<Leg>,
    /// The physical preset with the scenario's overrides applied.
    pub physics: PhysicalParams,
    /// Where the agents move (`[medium]`), when the scenario says: it replaces the disturbance
    /// preset's medium, and with it switches capillary attraction (at an interface).
    pub medium: Option<Medium>,
}

impl Scenario {
    /// A fingerprint of what the scenario asks — its maps, start, legs, physics and medium,
    /// not its name, description or file: 16 hex digits of FNV-1a over the exact text of
    /// those values. Plan files carry it to name the scenario they were made for.
    pub fn content_hash(&self) -> String {
        let text = format!(
            "{:?}|{:?}|{:?}|{:?}|{:?}",
            self.world, self.start, self.legs, self.physics, self.medium
        );
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in text.bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
        format!("{h:016x}")
    }

    /// `preset` as it applies to this scenario: with the scenario's medium, if it sets one.
    pub fn plant_preset(&self, preset: &DisturbancePreset) -> DisturbancePreset {
        let mut p = preset.clone();
        if let Some(m) = &self.medium {
            p.medium = m.clone();
        }
        p
    }

    /// Loads a built-in scenario by name, or a scenario file by path.
    pub fn load(name_or_path: &str) -> Result<Scenario, InputError> {
        if let Some(src) = builtin_source(name_or_path) {
            return parse_scenario(src, &format!("built-in:{name_or_path}"));
        }
        let path = std::path::Path::new(name_or_path);
        if !path.exists() {
            let names = builtin_names().join(", ");
            return Err(InputError::new(
                name_or_path,
                "",
                format!("no such file, and not a built-in scenario (built-ins: {names})"),
            ));
        }
        let text =
            crate::input::file::read_text_at_most(path, name_or_path, file::MAX_SCENARIO_BYTES)?;
        parse_scenario(&text, name_or_path)
    }

    /// Number of agents.
    pub fn agents(&self) -> usize {
        self.start.len()
    }

    /// The world during leg `i` (the latest map switch at or before `i` applies).
    pub fn world_for_leg(&self, i: usize) -> World {
        match self.legs[..=i]
            .iter()
            .rev()
            .find_map(|l| l.obstacles.clone())
        {
            Some(obs) => self.world.with_obstacles(obs),
            None => self.world.clone(),
        }
    }

    /// The first leg whose goal lies off the symmetric set of a start symmetric about its
    /// centroid, with its field and the note ([`crate::team_symmetry::symmetry_note`]): in exact
    /// arithmetic no field leaves that set, so the goal is reached only through the growth of an
    /// asymmetry (every leg is checked against the scenario's start).
    pub fn symmetric_leg(&self) -> Option<(usize, String, String)> {
        self.legs.iter().enumerate().find_map(|(i, leg)| {
            let reason = symmetry_note(&self.start, &leg.goal.agents, leg.goal.tolerance)?;
            let field = if self.legs.len() == 1 {
                "goal.agents".to_string()
            } else {
                format!("legs[{i}].goal.agents")
            };
            Some((i, field, reason))
        })
    }

    /// The validity checker of leg `i`.
    pub fn checker_for_leg(&self, i: usize) -> ValidityChecker {
        let cw = Arc::new(CollisionWorld::new(&self.world_for_leg(i), 0.5));
        ValidityChecker::new(cw, self.physics.r_min, self.physics.r_max)
    }

    /// The final goal.
    pub fn final_goal(&self) -> &Goal {
        &self
            .legs
            .last()
            .expect("a scenario has at least one leg")
            .goal
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_position_that_is_not_a_number_is_never_in_the_goal() {
        let g = Goal {
            agents: vec![Vec2::new(1.0, 1.0), Vec2::new(3.0, 1.0)],
            tolerance: 0.5,
        };
        assert!(g.contains(&[Vec2::new(1.1, 1.0), Vec2::new(3.0, 1.2)]));
        let lost = [Vec2::new(f64::NAN, f64::NAN), Vec2::new(3.0, 1.0)];
        assert!(g.distance(&lost).is_nan() && !g.contains(&lost));
        let lost = [Vec2::new(1.0, 1.0), Vec2::new(f64::NAN, 1.0)];
        assert!(!g.contains(&lost));
    }
}
