//! The scenario file format (serde) and its validation.

use std::sync::Arc;

use serde::Deserialize;

use super::{Goal, Leg, Scenario};
use crate::collision::{CollisionWorld, ValidityChecker};
use crate::error::InputError;
use crate::input::{Fixed, InputChecks, parse_toml};
use crate::math::{MAX_AGENTS, Vec2};
use crate::physics::{PhysicalOverrides, PhysicalParams};
use crate::plant::Medium;
use crate::world::{Obstacle, World, check_polygon};

/// A point `[x, y]`: exactly two numbers.
type Point = Fixed<f64, 2>;

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
    polygon: Option<Vec<Point>>,
    circle: Option<CircleFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CircleFile {
    center: Point,
    radius: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StartFile {
    agents: Vec<Point>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GoalFile {
    agents: Vec<Point>,
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

/// Most polygon vertices in one map (all its obstacles together). A choice: every collision
/// query of a planner step walks the map, and the largest shipped map has a few hundred; this
/// bound keeps a check under a second and a planner's step under a millisecond.
pub const MAX_MAP_VERTICES: usize = 20_000;

/// Largest scenario file (bytes): 4 MiB holds a map of [`MAX_MAP_VERTICES`] vertices several
/// times over; parsing it takes well under a second.
pub const MAX_SCENARIO_BYTES: u64 = 4 << 20;

/// Most legs of a scenario.
pub const MAX_LEGS: usize = 100;

/// Parses and validates scenario TOML `text`; `file` names it in errors.
pub fn parse_scenario(text: &str, file: &str) -> Result<Scenario, InputError> {
    let raw: ScenarioFile = parse_toml(text, file)?;
    scenario(InputChecks::new(file), raw).map_err(|mut e| {
        // a medium out of range: point at its line, as the preset loader does
        if e.field.starts_with("medium.") {
            e.reason += &crate::input::field_line(text, &e.field);
        }
        e
    })
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

fn point(c: InputChecks, field: &str, p: Point) -> Result<Vec2, InputError> {
    let [x, y] = p.0;
    Ok(Vec2::new(
        c.finite(&format!("{field}[0]"), x)?,
        c.finite(&format!("{field}[1]"), y)?,
    ))
}

fn points(c: InputChecks, field: &str, ps: &[Point]) -> Result<Vec<Vec2>, InputError> {
    ps.iter()
        .enumerate()
        .map(|(i, p)| point(c, &format!("{field}[{i}]"), *p))
        .collect()
}

fn obstacles(
    c: InputChecks,
    field: &str,
    obs: &[ObstacleFile],
    ext: Extent,
) -> Result<Vec<Obstacle>, InputError> {
    if obs.len() > MAX_OBSTACLES {
        return Err(c.err(
            field,
            format!(
                "a map has at most {MAX_OBSTACLES} obstacles, got {}",
                obs.len()
            ),
        ));
    }
    let vertices: usize = obs
        .iter()
        .map(|o| o.polygon.as_ref().map_or(0, Vec::len))
        .sum();
    if vertices > MAX_MAP_VERTICES {
        return Err(c.err(
                field,
                format!(
                    "a map has at most {MAX_MAP_VERTICES} polygon vertices in all (so that a check takes under a second and a planner step under a millisecond), got {vertices}: simplify the polygons"
                ),
            ));
    }
    let near = |f: &str, p: Vec2| {
        if ext.near(p) {
            Ok(p)
        } else {
            Err(c.err(
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
                let v = points(c, &f, poly)?;
                for (k, p) in v.iter().enumerate() {
                    near(&format!("{f}[{k}]"), *p)?;
                }
                check_polygon(&v).map_err(|r| c.err(&f, r.to_string()))?;
                out.push(Obstacle::Polygon(v));
            }
            (None, Some(circle)) => {
                let center = point(c, &format!("{f}.circle.center"), circle.center)?;
                near(&format!("{f}.circle.center"), center)?;
                let radius = c.finite(&format!("{f}.circle.radius"), circle.radius)?;
                let largest = ext.width.max(ext.height);
                if radius <= 0.0 || radius > largest {
                    return Err(c.err(
                            format!("{f}.circle.radius"),
                            format!(
                                "must be > 0 and at most the world's larger side ({largest} BL), got {radius}"
                            ),
                        ));
                }
                out.push(Obstacle::Circle { center, radius });
            }
            _ => {
                return Err(c.err(f, "an obstacle has exactly one of `polygon` or `circle`"));
            }
        }
    }
    Ok(out)
}

/// Agent positions `ps` (field `field`), each inside the world.
fn agents(c: InputChecks, field: &str, ps: &[Point], ext: Extent) -> Result<Vec<Vec2>, InputError> {
    let v = points(c, field, ps)?;
    for (i, p) in v.iter().enumerate() {
        if !ext.inside(*p) {
            return Err(c.err(
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
    c: InputChecks,
    field: &str,
    g: &GoalFile,
    n_agents: usize,
    ext: Extent,
) -> Result<Goal, InputError> {
    let agents = agents(c, &format!("{field}.agents"), &g.agents, ext)?;
    if agents.len() != n_agents {
        return Err(c.err(
            format!("{field}.agents"),
            format!(
                "has {} agents but start.agents has {n_agents}; the counts must match",
                agents.len()
            ),
        ));
    }
    let tolerance = c.finite(&format!("{field}.tolerance"), g.tolerance)?;
    if tolerance <= 0.0 {
        return Err(c.err(
            format!("{field}.tolerance"),
            format!("must be > 0, got {tolerance}"),
        ));
    }
    Ok(Goal { agents, tolerance })
}

/// Rejects a configuration in collision or outside the proximity range.
fn placement(
    c: InputChecks,
    field: &str,
    s: &[Vec2],
    checker: &ValidityChecker,
) -> Result<(), InputError> {
    for (i, p) in s.iter().enumerate() {
        if !checker.collision.agent_clear(*p) {
            return Err(c.err(
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
                return Err(c.err(
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

fn scenario(c: InputChecks, raw: ScenarioFile) -> Result<Scenario, InputError> {
    let physics = PhysicalParams::default().with_overrides(&raw.physics);
    physics
        .check()
        .map_err(|r| r.under("physics").in_file(c.file))?;
    let width = c.finite("world.width", raw.world.width)?;
    let height = c.finite("world.height", raw.world.height)?;
    for (f, v) in [("world.width", width), ("world.height", height)] {
        if v <= 2.0 || v > MAX_WORLD_BL {
            return Err(c.err(
                f,
                format!("must be > 2 BL and at most {MAX_WORLD_BL} BL, got {v}"),
            ));
        }
    }
    let ext = Extent { width, height };
    let world = World {
        width,
        height,
        obstacles: obstacles(c, "world.obstacles", &raw.world.obstacles, ext)?,
    };
    let start = agents(c, "start.agents", &raw.start.agents, ext)?;
    if !(2..=MAX_AGENTS).contains(&start.len()) {
        return Err(c.err(
            "start.agents",
            format!("needs 2 to {MAX_AGENTS} agents, got {}", start.len()),
        ));
    }
    let legs = match (&raw.goal, &raw.legs) {
        (Some(_), Some(_)) => {
            return Err(c.err("legs", "a scenario has `[goal]` or `[[legs]]`, never both"));
        }
        (None, None) => {
            return Err(c.err("goal", "missing: a scenario needs `[goal]` or `[[legs]]`"));
        }
        (Some(g), None) => vec![Leg {
            goal: goal(c, "goal", g, start.len(), ext)?,
            obstacles: None,
        }],
        (None, Some(ls)) => {
            if ls.is_empty() || ls.len() > MAX_LEGS {
                return Err(c.err(
                    "legs",
                    format!("needs 1 to {MAX_LEGS} legs, got {}", ls.len()),
                ));
            }
            let mut legs = Vec::with_capacity(ls.len());
            for (i, l) in ls.iter().enumerate() {
                let goal = goal(c, &format!("legs[{i}].goal"), &l.goal, start.len(), ext)?;
                let obstacles = match &l.obstacles {
                    Some(o) => Some(obstacles(c, &format!("legs[{i}].obstacles"), o, ext)?),
                    None => None,
                };
                legs.push(Leg { goal, obstacles });
            }
            legs
        }
    };
    let (r_min, r_max) = (physics.r_min, physics.r_max);
    if let Some(m) = &raw.medium {
        c.at(m.check())?;
    }
    let scenario = Scenario {
        name: raw.name,
        description: raw.description,
        source: c.file.to_string(),
        world,
        start,
        legs,
        physics,
        medium: raw.medium,
    };
    let checker =
        |w: &World| ValidityChecker::new(Arc::new(CollisionWorld::new(w, 0.5)), r_min, r_max);
    let single = raw.goal.is_some();
    let goal_field = |i: usize| {
        if single {
            "goal.agents".to_string()
        } else {
            format!("legs[{i}].goal.agents")
        }
    };
    for i in 0..scenario.legs.len() {
        let map = checker(&scenario.world_for_leg(i));
        // where leg i starts: the scenario's start, then the previous leg's goal
        let (from, from_field) = if i == 0 {
            (&scenario.start, "start.agents".to_string())
        } else {
            (&scenario.legs[i - 1].goal.agents, goal_field(i - 1))
        };
        placement(c, &from_field, from, &map).map_err(|e| {
            if i == 0 && scenario.legs[0].obstacles.is_none() {
                return e;
            }
            let what = if i == 0 {
                "the start".to_string()
            } else {
                format!("leg {i}'s goal ({from_field})")
            };
            let map_field = if scenario.legs[i].obstacles.is_some() {
                format!("legs[{i}].obstacles")
            } else {
                "world.obstacles".to_string()
            };
            c.err(
                map_field,
                format!(
                    "leg {} starts at {what}, which its map blocks: {}",
                    i + 1,
                    e.reason
                ),
            )
        })?;
        placement(c, &goal_field(i), &scenario.legs[i].goal.agents, &map)?;
    }
    Ok(scenario)
}
