//! The scenario file format (serde) and its validation.

use std::sync::Arc;

use serde::Deserialize;

use super::{Goal, Leg, Scenario};
use crate::collision::{CollisionWorld, ValidityChecker};
use crate::error::InputError;
use crate::input::parse_toml;
use crate::math::{MAX_AGENTS, Vec2};
use crate::physics::{PhysicalOverrides, PhysicalParams};
use crate::world::{Obstacle, World, check_polygon};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ScenarioFile {
    name: String,
    #[serde(default)]
    description: String,
    world: WorldFile,
    start: StartFile,
    goal: Option<GoalFile>,
    legs: Option<Vec<LegFile>>,
    #[serde(default)]
    physics: PhysicalOverrides,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct WorldFile {
    width: f64,
    height: f64,
    #[serde(default)]
    obstacles: Vec<ObstacleFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ObstacleFile {
    polygon: Option<Vec<[f64; 2]>>,
    circle: Option<CircleFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CircleFile {
    center: [f64; 2],
    radius: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StartFile {
    agents: Vec<[f64; 2]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GoalFile {
    agents: Vec<[f64; 2]>,
    tolerance: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LegFile {
    goal: GoalFile,
    obstacles: Option<Vec<ObstacleFile>>,
}

/// Parses and validates scenario TOML `text`; `file` names it in errors.
pub fn parse_scenario(text: &str, file: &str) -> Result<Scenario, InputError> {
    let raw: ScenarioFile = parse_toml(text, file)?;
    Validator { file }.scenario(raw)
}

struct Validator<'a> {
    file: &'a str,
}

impl Validator<'_> {
    fn err(&self, field: impl Into<String>, reason: impl Into<String>) -> InputError {
        InputError::new(self.file, field, reason)
    }

    fn finite(&self, field: &str, v: f64) -> Result<f64, InputError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(field, format!("must be a finite number, got {v}")))
        }
    }

    fn point(&self, field: &str, p: [f64; 2]) -> Result<Vec2, InputError> {
        Ok(Vec2::new(
            self.finite(field, p[0])?,
            self.finite(field, p[1])?,
        ))
    }

    fn points(&self, field: &str, ps: &[[f64; 2]]) -> Result<Vec<Vec2>, InputError> {
        ps.iter()
            .enumerate()
            .map(|(i, p)| self.point(&format!("{field}[{i}]"), *p))
            .collect()
    }

    fn obstacles(&self, field: &str, obs: &[ObstacleFile]) -> Result<Vec<Obstacle>, InputError> {
        let mut out = Vec::with_capacity(obs.len());
        for (i, o) in obs.iter().enumerate() {
            let f = format!("{field}[{i}]");
            match (&o.polygon, &o.circle) {
                (Some(poly), None) => {
                    let f = format!("{f}.polygon");
                    let v = self.points(&f, poly)?;
                    check_polygon(&v).map_err(|r| self.err(&f, r))?;
                    out.push(Obstacle::Polygon(v));
                }
                (None, Some(c)) => {
                    let center = self.point(&format!("{f}.circle.center"), c.center)?;
                    let radius = self.finite(&format!("{f}.circle.radius"), c.radius)?;
                    if radius <= 0.0 {
                        return Err(self.err(
                            format!("{f}.circle.radius"),
                            format!("must be > 0, got {radius}"),
                        ));
                    }
                    out.push(Obstacle::Circle { center, radius });
                }
                _ => {
                    return Err(self.err(f, "an obstacle has exactly one of `polygon` or `circle`"));
                }
            }
        }
        Ok(out)
    }

    fn goal(&self, field: &str, g: &GoalFile, n_agents: usize) -> Result<Goal, InputError> {
        let agents = self.points(&format!("{field}.agents"), &g.agents)?;
        if agents.len() != n_agents {
            return Err(self.err(
                format!("{field}.agents"),
                format!(
                    "has {} agents but start.agents has {n_agents}; the counts must match",
                    agents.len()
                ),
            ));
        }
        let tolerance = self.finite(&format!("{field}.tolerance"), g.tolerance)?;
        if tolerance <= 0.0 {
            return Err(self.err(
                format!("{field}.tolerance"),
                format!("must be > 0, got {tolerance}"),
            ));
        }
        Ok(Goal { agents, tolerance })
    }

    /// Rejects a configuration in collision or outside the proximity range.
    fn placement(
        &self,
        field: &str,
        s: &[Vec2],
        checker: &ValidityChecker,
    ) -> Result<(), InputError> {
        for (i, p) in s.iter().enumerate() {
            if !checker.collision.agent_clear(*p) {
                return Err(self.err(
                    format!("{field}[{i}]"),
                    format!(
                        "agent at ({}, {}) is in collision with a wall or obstacle",
                        p.x, p.y
                    ),
                ));
            }
        }
        for i in 0..s.len() {
            for j in (i + 1)..s.len() {
                let r = (s[j] - s[i]).norm();
                if r <= checker.r_min || r >= checker.r_max {
                    return Err(self.err(
                        field,
                        format!(
                            "agents {i} and {j} are {r:.3} BL apart, outside the proximity range ({}, {}) BL",
                            checker.r_min, checker.r_max
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    fn scenario(&self, raw: ScenarioFile) -> Result<Scenario, InputError> {
        let physics = PhysicalParams::default().with_overrides(&raw.physics);
        physics
            .check()
            .map_err(|(f, r)| self.err(format!("physics.{f}"), r))?;
        let width = self.finite("world.width", raw.world.width)?;
        let height = self.finite("world.height", raw.world.height)?;
        for (f, v) in [("world.width", width), ("world.height", height)] {
            if v <= 2.0 {
                return Err(self.err(f, format!("must be > 2 BL, got {v}")));
            }
        }
        let world = World {
            width,
            height,
            obstacles: self.obstacles("world.obstacles", &raw.world.obstacles)?,
        };
        let start = self.points("start.agents", &raw.start.agents)?;
        if !(2..=MAX_AGENTS).contains(&start.len()) {
            return Err(self.err(
                "start.agents",
                format!("needs 2 to {MAX_AGENTS} agents, got {}", start.len()),
            ));
        }
        let legs = match (&raw.goal, &raw.legs) {
            (Some(_), Some(_)) => {
                return Err(self.err("legs", "a scenario has `[goal]` or `[[legs]]`, never both"));
            }
            (None, None) => {
                return Err(self.err("goal", "missing: a scenario needs `[goal]` or `[[legs]]`"));
            }
            (Some(g), None) => vec![Leg {
                goal: self.goal("goal", g, start.len())?,
                obstacles: None,
            }],
            (None, Some(ls)) => {
                if ls.is_empty() {
                    return Err(self.err("legs", "needs at least one leg"));
                }
                let mut legs = Vec::with_capacity(ls.len());
                for (i, l) in ls.iter().enumerate() {
                    let goal = self.goal(&format!("legs[{i}].goal"), &l.goal, start.len())?;
                    let obstacles = match &l.obstacles {
                        Some(o) => Some(self.obstacles(&format!("legs[{i}].obstacles"), o)?),
                        None => None,
                    };
                    legs.push(Leg { goal, obstacles });
                }
                legs
            }
        };
        let (r_min, r_max) = (physics.r_min, physics.r_max);
        let scenario = Scenario {
            name: raw.name,
            description: raw.description,
            source: self.file.to_string(),
            world,
            start,
            legs,
            physics,
        };
        let checker =
            |w: &World| ValidityChecker::new(Arc::new(CollisionWorld::new(w, 0.5)), r_min, r_max);
        self.placement("start.agents", &scenario.start, &checker(&scenario.world))?;
        let single = raw.goal.is_some();
        for i in 0..scenario.legs.len() {
            let field = if single {
                "goal.agents".to_string()
            } else {
                format!("legs[{i}].goal.agents")
            };
            self.placement(
                &field,
                &scenario.legs[i].goal.agents,
                &checker(&scenario.world_for_leg(i)),
            )?;
        }
        Ok(scenario)
    }
}
