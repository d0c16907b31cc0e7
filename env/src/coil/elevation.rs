//! Whether a command may tilt the field out of the plane, and how far.
//!
//! The elevation α scales every in-plane pair force by cos²α (the seed's eq. 1) and adds the
//! all-repelling part of the dipole force; for three or more agents it is the control that lets
//! a formation be held (see README, "Elevation as a control"). Planners and trackers take the
//! same `planar` setting: `auto` keeps two agents in the plane (today's behaviour, bit for bit)
//! and frees the elevation for three or more.

use crate::params::{ParamType, Value, choose};

/// The largest elevation a planner or tracker uses when nothing else says (degrees). It
/// covers the cone cos²α = 2/3 (α = 35.26°) on which the pair forces cancel on average, so any
/// formation can be held, and keeps at least cos 45° ≈ 71% of the in-plane pull. (The coil
/// allows 90°; with it, lookahead tracked three-agent plans to the goal on the realistic plant
/// in 11 of 20 seeds of trio-triangle, against 19 of 20 at 45°: steep fields leave little pull
/// against drift.)
pub const DEFAULT_ALPHA_MAX_DEG: f64 = 45.0;

/// Whether the field stays in the plane (α = 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Planar {
    /// In the plane for two agents, elevated for three or more.
    #[default]
    Auto,
    /// Always in the plane.
    Yes,
    /// The elevation is a control for any team.
    No,
}

impl Planar {
    /// True when a team of `agents` keeps the field in the plane.
    pub fn is_planar(self, agents: usize) -> bool {
        match self {
            Planar::Auto => agents <= 2,
            Planar::Yes => true,
            Planar::No => false,
        }
    }

    /// The parameter value naming it.
    pub fn name(self) -> &'static str {
        match self {
            Planar::Auto => "auto",
            Planar::Yes => "true",
            Planar::No => "false",
        }
    }
}

impl ParamType for Planar {
    type Domain = ();

    fn parse(text: &str, _: &()) -> Result<Self, String> {
        choose(
            text,
            &[
                ("auto", Planar::Auto),
                ("true", Planar::Yes),
                ("false", Planar::No),
            ],
        )
    }

    fn value(&self) -> Value {
        Value::Name(self.name())
    }

    fn describe(_: &()) -> String {
        "auto|true|false".into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_is_planar_for_pairs_only_and_names_round_trip() {
        assert!(Planar::Auto.is_planar(2) && !Planar::Auto.is_planar(3));
        assert!(Planar::Yes.is_planar(4) && !Planar::No.is_planar(2));
        for p in [Planar::Auto, Planar::Yes, Planar::No] {
            assert_eq!(Planar::parse(p.name(), &()), Ok(p));
        }
        assert!(Planar::parse("maybe", &()).is_err());
    }
}
