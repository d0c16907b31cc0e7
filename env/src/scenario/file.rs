//! The scenario file format (serde) and its validation.

use std::sync::Arc;

use serde::Deserialize;

use super::{Goal, Leg, Scenario};
use crate::collision::{CollisionWorld, ValidityChecker};
use crate::error::InputError;
use crate::input::parse_toml;
use crate::math::{MAX_AGENTS, Vec2};
use crate::physics::{PhysicalOverrides, PhysicalParams};
use crate::plant::Medium;
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
    /// Where the agents move; replaces the preset's medium.
    medium: Option<Medium>,
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

/// Largest world side (BL): ten thousand body lengths, a metre of 100 µm agents.
pub const MAX_WORLD_BL: f64 = 10_000.0;

/// Most obstacles in one map.
pub const MAX_OBSTACLES: usize = 1000;

/// Most legs of a scenario.
pub const MAX_LEGS: usize = 100;

/// Parses and validates scenario TOML `text`; `file` names it in errors.
pub fn parse_scenario(text: &str, file: &str) -> Result<Scenario, InputError> {
    let raw: ScenarioFile = parse_toml(text, file)?;
    Validator { file }.scenario(raw).map_err(|mut e| {
        // a medium out of range: point at its line, as the preset loader does
        if e.field.starts_with("medium.") {
            e.reason += &crate::input::field_line(text, &e.field);
        }
        e
    })
}

struct Validator<'a> {
    file: &'a str,
}

/// The world's extent, for checking where things are.
#[derive(Clone, Copy)]
struct Extent {
    width: f64,
    height: f64,
}

impl Extent {
    /// Inside the walls.
    fn inside(&self, p: Vec2) -> bool {
        (0.0..=self.width).contains(&p.x) && (0.0..=self.height).contains(&p.y)
    }

    /// Within one world size of the walls: where an obstacle's vertices may be.
    fn near(&self, p: Vec2) -> bool {
        (-self.width..=2.0 * self.width).contains(&p.x)
            && (-self.height..=2.0 * self.height).contains(&p.y)
    }
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

    fn obstacles(
        &self,
        field: &str,
        obs: &[ObstacleFile],
        ext: Extent,
    ) -> Result<Vec<Obstacle>, InputError> {
        if obs.len() > MAX_OBSTACLES {
            return Err(self.err(
                field,
                format!(
                    "a map has at most {MAX_OBSTACLES} obstacles, got {}",
                    obs.len()
                ),
            ));
        }
        let near = |f: &str, p: Vec2| {
            if ext.near(p) {
                Ok(p)
            } else {
                Err(self.err(
                    f,
                    format!(
                        "({}, {}) is more than one world size outside the {} × {} BL world",
                        p.x, p.y, ext.width, ext.height
                    ),
                ))
            }
        };
        let mut out = Vec::with_capacity(obs.len());
        for (i, o) in obs.iter().enumerate() {
            let f = format!("{field}[{i}]");
            match (&o.polygon, &o.circle) {
                (Some(poly), None) => {
                    let f = format!("{f}.polygon");
                    let v = self.points(&f, poly)?;
                    for (k, p) in v.iter().enumerate() {
                        near(&format!("{f}[{k}]"), *p)?;
                    }
                    check_polygon(&v).map_err(|r| self.err(&f, r))?;
                    out.push(Obstacle::Polygon(v));
                }
                (None, Some(c)) => {
                    let center = self.point(&format!("{f}.circle.center"), c.center)?;
                    near(&format!("{f}.circle.center"), center)?;
                    let radius = self.finite(&format!("{f}.circle.radius"), c.radius)?;
                    let largest = ext.width.max(ext.height);
                    if radius <= 0.0 || radius > largest {
                        return Err(self.err(
                            format!("{f}.circle.radius"),
                            format!(
                                "must be > 0 and at most the world's larger side ({largest} BL), got {radius}"
                            ),
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

    /// Agent positions `ps` (field `field`), each inside the world.
    fn agents(&self, field: &str, ps: &[[f64; 2]], ext: Extent) -> Result<Vec<Vec2>, InputError> {
        let v = self.points(field, ps)?;
        for (i, p) in v.iter().enumerate() {
            if !ext.inside(*p) {
                return Err(self.err(
                    format!("{field}[{i}]"),
                    format!(
                        "({}, {}) is outside the world [0, {}] × [0, {}]",
                        p.x, p.y, ext.width, ext.height
                    ),
                ));
            }
        }
        Ok(v)
    }

    fn goal(
        &self,
        field: &str,
        g: &GoalFile,
        n_agents: usize,
        ext: Extent,
    ) -> Result<Goal, InputError> {
        let agents = self.agents(&format!("{field}.agents"), &g.agents, ext)?;
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
            if v <= 2.0 || v > MAX_WORLD_BL {
                return Err(self.err(
                    f,
                    format!("must be > 2 BL and at most {MAX_WORLD_BL} BL, got {v}"),
                ));
            }
        }
        let ext = Extent { width, height };
        let world = World {
            width,
            height,
            obstacles: self.obstacles("world.obstacles", &raw.world.obstacles, ext)?,
        };
        let start = self.agents("start.agents", &raw.start.agents, ext)?;
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
                goal: self.goal("goal", g, start.len(), ext)?,
                obstacles: None,
            }],
            (None, Some(ls)) => {
                if ls.is_empty() || ls.len() > MAX_LEGS {
                    return Err(self.err(
                        "legs",
                        format!("needs 1 to {MAX_LEGS} legs, got {}", ls.len()),
                    ));
                }
                let mut legs = Vec::with_capacity(ls.len());
                for (i, l) in ls.iter().enumerate() {
                    let goal = self.goal(&format!("legs[{i}].goal"), &l.goal, start.len(), ext)?;
                    let obstacles = match &l.obstacles {
                        Some(o) => Some(self.obstacles(&format!("legs[{i}].obstacles"), o, ext)?),
                        None => None,
                    };
                    legs.push(Leg { goal, obstacles });
                }
                legs
            }
        };
        let (r_min, r_max) = (physics.r_min, physics.r_max);
        if let Some(m) = &raw.medium {
            m.check()
                .map_err(|(field, reason)| self.err(field, reason))?;
        }
        let scenario = Scenario {
            name: raw.name,
            description: raw.description,
            source: self.file.to_string(),
            world,
            start,
            legs,
            physics,
            medium: raw.medium,
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
            // the next leg starts where this one ends: its map must leave that place free
            if scenario
                .legs
                .get(i + 1)
                .is_some_and(|l| l.obstacles.is_some())
            {
                self.placement(
                    &field,
                    &scenario.legs[i].goal.agents,
                    &checker(&scenario.world_for_leg(i + 1)),
                )
                .map_err(|e| {
                    self.err(
                        format!("legs[{}].obstacles", i + 1),
                        format!(
                            "leg {} starts at leg {}'s goal ({field}), which this map blocks: {}",
                            i + 2,
                            i + 1,
                            e.reason
                        ),
                    )
                })?;
            }
        }
        Ok(scenario)
    }
}
