//! `team`: N = 2…16 agents moved from one formation to another across an open field, at a
//! liquid–air interface (the `hardware` preset's), where a tilted field is free to use.

use std::f64::consts::{PI, TAU};

use rand::RngExt;

use super::place::round_pt;
use super::{Family, Refusal, Rng};
use crate::declare_params;
use crate::math::{MAX_AGENTS, Vec2, centroid};
use crate::params::{BadValue, ParamType, Reals, Value, choose};
use crate::physics::PhysicalParams;
use crate::plant::{DisturbancePreset, Interface, Medium};
use crate::scenario::Draft;

/// A formation of `team`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Formation {
    /// Evenly spaced on a line.
    Row,
    /// A regular polygon (two agents: a pair).
    Ring,
    /// Rows of ⌈√N⌉ agents.
    Grid,
    /// A triangular patch of the hexagonal lattice: rows of 1, 2, 3, … agents, each row half a
    /// spacing further out on both sides (the last row partly filled).
    Triangle,
    /// Random points at least `spacing` apart and within the proximity range of each other.
    Random,
}

impl ParamType for Formation {
    type Domain = ();

    fn parse(text: &str, _: &()) -> Result<Self, BadValue> {
        choose(
            text,
            &[
                ("row", Formation::Row),
                ("ring", Formation::Ring),
                ("grid", Formation::Grid),
                ("triangle", Formation::Triangle),
                ("random", Formation::Random),
            ],
        )
    }

    fn value(&self) -> Value {
        Value::Name(match self {
            Formation::Row => "row",
            Formation::Ring => "ring",
            Formation::Grid => "grid",
            Formation::Triangle => "triangle",
            Formation::Random => "random",
        })
    }

    fn describe(_: &()) -> String {
        "row|ring|grid|triangle|random".into()
    }
}

declare_params! {
    /// The parameters of `team`.
    #[derive(Debug, Clone)]
    pub struct Team {
        /// Number of agents N.
        #[param("agents", 2..=MAX_AGENTS)]
        pub agents: usize = 3,
        /// Formation at the start.
        #[param("start")]
        pub start: Formation = Formation::Ring,
        /// Formation at the goal.
        #[param("goal")]
        pub goal: Formation = Formation::Ring,
        /// Distance between neighbours in a formation (BL; the least distance, for random).
        #[param("spacing", Reals::closed(1.0, 20.0))]
        pub spacing: f64 = 2.5,
        /// How far the centroid moves (BL).
        #[param("distance", Reals::closed(0.0, 100.0))]
        pub distance: f64 = 8.0,
        /// Rotation of the goal formation against the start formation (degrees).
        #[param("rotation", Reals::closed(-180.0, 180.0))]
        pub rotation: f64 = 0.0,
        /// Goal tolerance (BL).
        #[param("tolerance", Reals::closed(0.05, 2.0))]
        pub tolerance: f64 = 0.75,
    }
}

/// Room (BL) between the team and the field's sides.
const ROOM: f64 = 3.0;

/// Distance (BL) kept inside the proximity range.
const INSIDE: f64 = 0.05;

/// Draws of a random formation before giving up.
const TRIES: usize = 2000;

impl Team {
    /// Positions of `f` about the origin, before any rotation.
    fn formation(&self, f: Formation, rng: &mut Rng, physics: &PhysicalParams) -> Vec<Vec2> {
        let (n, s) = (self.agents, self.spacing);
        let v: Vec<Vec2> = match f {
            Formation::Row => (0..n).map(|i| Vec2::new(i as f64 * s, 0.0)).collect(),
            Formation::Ring => {
                let r = s / (2.0 * (PI / n as f64).sin());
                (0..n)
                    .map(|i| {
                        let a = TAU * i as f64 / n as f64;
                        Vec2::new(a.cos(), a.sin()) * r
                    })
                    .collect()
            }
            Formation::Grid => {
                let cols = (n as f64).sqrt().ceil() as usize;
                (0..n)
                    .map(|i| Vec2::new((i % cols) as f64 * s, (i / cols) as f64 * s))
                    .collect()
            }
            Formation::Triangle => {
                let h = s * 3f64.sqrt() / 2.0;
                (0..)
                    .flat_map(|row: usize| {
                        (0..=row).map(move |i| {
                            Vec2::new((i as f64 - row as f64 / 2.0) * s, row as f64 * h)
                        })
                    })
                    .take(n)
                    .collect()
            }
            Formation::Random => {
                // inside a disk whose diameter is within the proximity range
                let radius = (physics.r_max - INSIDE) / 2.0;
                let mut v: Vec<Vec2> = Vec::new();
                for _ in 0..TRIES {
                    if v.len() == n {
                        break;
                    }
                    let (a, r) = (rng.random_range(0.0..TAU), rng.random_range(0.0f64..1.0));
                    let p = Vec2::new(a.cos(), a.sin()) * radius * r.sqrt();
                    if v.iter().all(|q| (p - q).norm() >= s) {
                        v.push(p);
                    }
                }
                v
            }
        };
        let c = centroid(&v);
        v.iter().map(|p| p - c).collect()
    }

    /// Refuses a formation whose agents are not inside the proximity range of each other.
    fn fits(&self, f: Formation, v: &[Vec2], physics: &PhysicalParams) -> Result<(), Refusal> {
        let name = f.value();
        if v.len() < self.agents {
            return Err(Refusal::new(
                "spacing",
                format!(
                    "found no {name} formation of {} agents at least {} BL apart within {} BL of each other",
                    self.agents, self.spacing, physics.r_max
                ),
            ));
        }
        let (lo, hi) = (physics.r_min + INSIDE, physics.r_max - INSIDE);
        for i in 0..v.len() {
            for j in (i + 1)..v.len() {
                let d = (v[i] - v[j]).norm();
                if d < lo || d > hi {
                    return Err(Refusal::new(
                        "spacing",
                        format!(
                            "a {name} of {} agents at {} BL puts agents {i} and {j} {d:.2} BL apart, outside the proximity range ({}, {}) BL",
                            self.agents, self.spacing, physics.r_min, physics.r_max
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// `v` turned by `a` (radians) about the origin and moved to `c`, rounded.
fn place(v: &[Vec2], a: f64, c: Vec2) -> Vec<Vec2> {
    let (cs, sn) = (a.cos(), a.sin());
    v.iter()
        .map(|p| round_pt(c + Vec2::new(cs * p.x - sn * p.y, sn * p.x + cs * p.y)))
        .collect()
}

impl Family for Team {
    fn feasible(&self, physics: &PhysicalParams) -> Result<(), Refusal> {
        let mut rng = <Rng as rand::SeedableRng>::seed_from_u64(0);
        for f in [self.start, self.goal] {
            if f != Formation::Random {
                self.fits(f, &self.formation(f, &mut rng, physics), physics)?;
            } else if self.spacing <= physics.r_min + INSIDE {
                return Err(Refusal::new(
                    "spacing",
                    format!(
                        "a random formation needs a spacing over r_min = {} BL",
                        physics.r_min
                    ),
                ));
            }
        }
        if self.distance == 0.0 && self.rotation == 0.0 && self.start == self.goal {
            let fixed = self.start != Formation::Random;
            if fixed {
                return Err(Refusal::new(
                    "distance",
                    "start and goal are the same formation in the same place: nothing to plan",
                ));
            }
        }
        Ok(())
    }

    fn build(&self, rng: &mut Rng, physics: &PhysicalParams) -> Result<Draft, Refusal> {
        let a = self.formation(self.start, rng, physics);
        self.fits(self.start, &a, physics)?;
        let b = self.formation(self.goal, rng, physics);
        self.fits(self.goal, &b, physics)?;
        let reach = a.iter().chain(&b).map(|p| p.norm()).fold(0.0, f64::max) + 0.5;
        let margin = reach + ROOM;
        let (width, height) = (2.0 * margin + self.distance, 2.0 * margin);
        let heading = rng.random_range(0.0..TAU);
        let c0 = Vec2::new(margin, height / 2.0);
        let start = place(&a, heading, c0);
        let goal = place(
            &b,
            heading + self.rotation.to_radians(),
            c0 + Vec2::new(self.distance, 0.0),
        );
        Ok(Draft {
            name: String::new(),
            description: format!(
                "team: {} agents from a {} to a {} ({} BL spacing) {} BL across, turned {}°, at a liquid–air interface",
                self.agents,
                self.start.value(),
                self.goal.value(),
                self.spacing,
                self.distance,
                self.rotation
            ),
            width,
            height,
            obstacles: vec![],
            // the hardware interface without contact-angle hysteresis, as the built-in team
            // scenarios and the frozen team suite have it
            medium: Some(match DisturbancePreset::hardware().medium {
                Medium::Interface(i) => Medium::Interface(Interface {
                    contact_angle_hysteresis_deg: 0.0,
                    ..i
                }),
                m => m,
            }),
            start,
            goal,
            tolerance: self.tolerance,
        })
    }

    fn hardest(&self) -> &'static str {
        "spacing"
    }
}
