//! The scenario as the replay page draws it: each leg's walls, obstacles and goal, the start,
//! the agents' size and the proximity range, in BL.

use magbench_env::{Obstacle, Scenario, Vec2};
use serde::Serialize;

/// Rounds to 0.001 BL, enough for drawing, so that the page stays small.
pub fn r3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// A point as `[x, y]` rounded to 0.001 BL.
pub fn xy(p: Vec2) -> [f64; 2] {
    [r3(p.x), r3(p.y)]
}

/// One obstacle: a polygon's vertices or a circle.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum SceneObstacle {
    /// A polygon, vertices in order.
    Polygon {
        /// The vertices.
        poly: Vec<[f64; 2]>,
    },
    /// A circle.
    Circle {
        /// Its centre.
        c: [f64; 2],
        /// Its radius (BL).
        r: f64,
    },
}

/// One leg: its map and its goal.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneLeg {
    /// Width of the world rectangle (BL).
    pub w: f64,
    /// Height of the world rectangle (BL).
    pub h: f64,
    /// The obstacles of this leg's map.
    pub obstacles: Vec<SceneObstacle>,
    /// Goal centre of each agent.
    pub goal: Vec<[f64; 2]>,
    /// Goal tolerance (BL).
    pub tol: f64,
}

/// Everything static on the page.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scene {
    /// The scenario's name.
    pub name: String,
    /// Agents in the team.
    pub agents: usize,
    /// Agent radius (BL): half a body length.
    pub radius: f64,
    /// The start of each agent.
    pub start: Vec<[f64; 2]>,
    /// Smallest allowed pair separation (BL).
    pub r_min: f64,
    /// Largest allowed pair separation (BL).
    pub r_max: f64,
    /// The legs in order.
    pub legs: Vec<SceneLeg>,
}

impl Scene {
    /// The scene of `s`.
    pub fn of(s: &Scenario) -> Scene {
        let legs = (0..s.legs.len())
            .map(|k| {
                let world = s.world_for_leg(k);
                SceneLeg {
                    w: world.width,
                    h: world.height,
                    obstacles: world
                        .obstacles
                        .iter()
                        .map(|o| match o {
                            Obstacle::Polygon(v) => SceneObstacle::Polygon {
                                poly: v.iter().map(|p| xy(*p)).collect(),
                            },
                            Obstacle::Circle { center, radius } => SceneObstacle::Circle {
                                c: xy(*center),
                                r: r3(*radius),
                            },
                        })
                        .collect(),
                    goal: s.legs[k].goal.agents.iter().map(|p| xy(*p)).collect(),
                    tol: s.legs[k].goal.tolerance,
                }
            })
            .collect();
        Scene {
            name: s.name.clone(),
            agents: s.agents(),
            radius: 0.5,
            start: s.start.iter().map(|p| xy(*p)).collect(),
            r_min: s.physics.r_min,
            r_max: s.physics.r_max,
            legs,
        }
    }
}
