//! `short-moves`: the relative moves that are hard for a pair steered by one field, in open
//! space: turn in place, swap the two agents, or shift the pair without turning it.

use std::f64::consts::TAU;

use rand::RngExt;

use super::place::{pair_at, round_pt};
use super::{Family, Refusal, Rng};
use crate::declare_params;
use crate::math::Vec2;
use crate::params::{BadValue, ParamType, Reals, Value, choose};
use crate::physics::PhysicalParams;
use crate::scenario::Draft;

/// The relative move of `short-moves`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Move {
    /// Turn about the pair's centre by `angle`.
    Turn,
    /// The agents exchange places (a half turn about the centre).
    Swap,
    /// Translate by `distance` at `angle` from the pair's axis, keeping the heading.
    Shift,
}

impl ParamType for Move {
    type Domain = ();

    fn parse(text: &str, _: &()) -> Result<Self, BadValue> {
        choose(
            text,
            &[
                ("turn", Move::Turn),
                ("swap", Move::Swap),
                ("shift", Move::Shift),
            ],
        )
    }

    fn value(&self) -> Value {
        Value::Name(match self {
            Move::Turn => "turn",
            Move::Swap => "swap",
            Move::Shift => "shift",
        })
    }

    fn describe(_: &()) -> String {
        "turn|swap|shift".into()
    }
}

declare_params! {
    /// The parameters of `short-moves`.
    #[derive(Debug, Clone)]
    pub struct ShortMoves {
        /// The move: turn in place, swap, or shift.
        #[param("move")]
        pub kind: Move = Move::Turn,
        /// turn: the heading change; shift: the direction from the pair's axis (degrees).
        #[param("angle", Reals::closed(0.0, 180.0))]
        pub angle: f64 = 90.0,
        /// shift: how far the pair moves (BL).
        #[param("distance", Reals::closed(0.0, 40.0))]
        pub distance: f64 = 2.0,
        /// Separation of the pair at start and goal (BL).
        #[param("separation", Reals::closed(1.0, 20.0))]
        pub separation: f64 = 2.0,
        /// Goal tolerance (BL).
        #[param("tolerance", Reals::closed(0.05, 2.0))]
        pub tolerance: f64 = 0.25,
        /// Side of the square field (BL).
        #[param("size", Reals::closed(6.0, 100.0))]
        pub size: f64 = 20.0,
    }
}

/// How far (BL) the pair's centre may be drawn from the field's centre, each way.
const JITTER: f64 = 1.0;

impl ShortMoves {
    /// How far each agent must move.
    fn displacement(&self) -> f64 {
        match self.kind {
            Move::Turn => self.separation * (self.angle.to_radians() / 2.0).sin(),
            Move::Swap => self.separation,
            Move::Shift => self.distance,
        }
    }
}

impl Family for ShortMoves {
    fn feasible(&self, physics: &PhysicalParams) -> Result<(), Refusal> {
        let r = self.separation;
        if r <= physics.r_min || r >= physics.r_max {
            return Err(Refusal::new(
                "separation",
                format!(
                    "{r} BL is outside the proximity range ({}, {}) BL",
                    physics.r_min, physics.r_max
                ),
            ));
        }
        let moved = self.displacement();
        if moved <= self.tolerance {
            let param = if self.kind == Move::Shift {
                "distance"
            } else {
                "angle"
            };
            return Err(Refusal::new(
                param,
                format!(
                    "the agents move {moved:.3} BL, within the goal tolerance {} BL: the start is already in the goal",
                    self.tolerance
                ),
            ));
        }
        let reach = r / 2.0 + 0.5 + JITTER + 0.1;
        let shift = if self.kind == Move::Shift {
            self.distance
        } else {
            0.0
        };
        if 2.0 * reach + shift > self.size {
            return Err(Refusal::new(
                "size",
                format!(
                    "a field {} BL across does not hold the pair ({r} BL) and its move ({shift} BL)",
                    self.size
                ),
            ));
        }
        Ok(())
    }

    fn build(&self, rng: &mut Rng, _: &PhysicalParams) -> Result<Draft, Refusal> {
        let heading = rng.random_range(0.0..TAU);
        let side = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
        let a = side * self.angle.to_radians();
        let mut c = Vec2::new(self.size / 2.0, self.size / 2.0)
            + Vec2::new(
                rng.random_range(-JITTER..=JITTER),
                rng.random_range(-JITTER..=JITTER),
            );
        let shift = Vec2::new((heading + a).cos(), (heading + a).sin()) * self.distance;
        if self.kind == Move::Shift {
            c -= shift / 2.0;
        }
        let start = pair_at(c, self.separation, heading);
        let (goal, what) = match self.kind {
            Move::Turn => (
                pair_at(c, self.separation, heading + a),
                format!("turn by {:.0}° in place", a.to_degrees()),
            ),
            Move::Swap => (vec![start[1], start[0]], "swap the two agents".to_string()),
            Move::Shift => (
                start.iter().map(|p| round_pt(p + shift)).collect(),
                format!(
                    "shift {} BL at {:.0}° from the pair's axis",
                    self.distance,
                    a.to_degrees()
                ),
            ),
        };
        Ok(Draft {
            name: String::new(),
            description: format!(
                "short-moves: a pair {} BL apart: {what}, in an open {} BL square",
                self.separation, self.size
            ),
            width: self.size,
            height: self.size,
            obstacles: vec![],
            medium: None,
            start,
            goal,
            tolerance: self.tolerance,
        })
    }

    fn hardest(&self) -> &'static str {
        "size"
    }
}
