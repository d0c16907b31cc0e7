//! Whether a command may tilt the field out of the plane, and how far.
//!
//! The elevation α scales every in-plane pair force by cos²α (the seed's eq. 1) and adds the
//! all-repelling part of the dipole force; for three or more agents it is the control that lets
//! a formation be held (see docs/physics.md, "Elevation as a control"). Planners and trackers take the
//! same `planar` setting: `auto` keeps two agents in the plane (today's behaviour, bit for bit)
//! and frees the elevation for three or more — when the agents' medium carries the
//! out-of-plane force f_z (a liquid–air interface). In bulk liquid nothing holds the agents in
//! the plane under a tilted field, so `auto` keeps the field in the plane and `false` is
//! refused.
//!
//! How far the field may tilt is bounded twice: by the coil ([`COIL_ALPHA_MAX_DEG`] for a
//! tri-axial coil; a rig file's or a preset's `alpha_max_deg`), and within it by the planner's
//! or tracker's `alpha_max` ([`DEFAULT_ALPHA_MAX_DEG`]).

use crate::params::{BadValue, ParamInfo, ParamType, Value, choose};

/// The largest elevation a planner or tracker uses when nothing else says (degrees). It
/// covers the cone cos²α = 2/3 (α = 35.26°) on which the pair forces cancel on average, so any
/// formation can be held, and keeps at least cos 45° ≈ 71% of the in-plane pull. (The coil
/// allows 90°; with it, lookahead tracks trio-triangle's plans on the realistic plant with an
/// RMS median of 0.083 BL against 0.055 at 45° (experiments/trio-alpha-max.toml): steep fields
/// leave little pull against drift.)
pub const DEFAULT_ALPHA_MAX_DEG: f64 = 45.0;

/// The elevation range of a tri-axial Helmholtz coil (degrees): its z pair sets any B_z, so
/// the field may point anywhere up to straight out of the plane. A planar coil set (x and y
/// pairs only) has 0.
pub const COIL_ALPHA_MAX_DEG: f64 = 90.0;

/// Why `planar = false` cannot hold in a medium that does not carry f_z.
pub const NEEDS_INTERFACE: &str =
    "false needs a medium that carries the out-of-plane force (kind = \"interface\")";

/// Whether the field stays in the plane (α = 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Planar {
    /// In the plane for two agents, elevated for three or more at an interface (in the plane
    /// in bulk).
    #[default]
    Auto,
    /// Always in the plane.
    Yes,
    /// The elevation is a control for any team.
    No,
}

impl Planar {
    /// True when a team of `agents` keeps the field in the plane; `carries_fz` says whether
    /// their medium carries the out-of-plane force (an interface does, bulk liquid does not).
    pub fn is_planar(self, agents: usize, carries_fz: bool) -> bool {
        match self {
            Planar::Auto => agents <= 2 || !carries_fz,
            Planar::Yes => true,
            Planar::No => false,
        }
    }

    /// Whether the setting can hold in a medium that does (`carries_fz`) or does not carry
    /// the out-of-plane force: `false` in bulk is refused with the reason.
    pub fn check_medium(self, carries_fz: bool) -> Result<(), &'static str> {
        if self == Planar::No && !carries_fz {
            return Err(NEEDS_INTERFACE);
        }
        Ok(())
    }

    /// Why a team of `agents` under this setting keeps the field in the plane or not, in a
    /// few words (for summaries).
    pub fn reason(self, agents: usize, carries_fz: bool) -> &'static str {
        match self {
            Planar::Yes => "planar = true",
            Planar::No => "planar = false",
            Planar::Auto if agents <= 2 => "planar = auto, two agents",
            Planar::Auto if !carries_fz => {
                "planar = auto, bulk medium: nothing carries the out-of-plane force"
            }
            Planar::Auto => "planar = auto, three or more agents at an interface",
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

    fn parse(text: &str, _: &()) -> Result<Self, BadValue> {
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

/// The elevation settings a planner or tracker declares among its parameters: its `planar`
/// and `alpha_max` (degrees), when it has them.
pub fn elevation_params(params: &[ParamInfo]) -> (Option<Planar>, Option<f64>) {
    let get = |key: &str| params.iter().find(|p| p.name == key).map(|p| &p.value);
    let planar = get("planar").and_then(|v| Planar::parse(&v.to_string(), &()).ok());
    let alpha_max = match get("alpha_max") {
        Some(Value::Real(a)) => Some(*a),
        _ => None,
    };
    (planar, alpha_max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_is_planar_for_pairs_only_and_names_round_trip() {
        assert!(Planar::Auto.is_planar(2, true) && !Planar::Auto.is_planar(3, true));
        assert!(Planar::Yes.is_planar(4, true) && !Planar::No.is_planar(2, true));
        for p in [Planar::Auto, Planar::Yes, Planar::No] {
            assert_eq!(Planar::parse(p.name(), &()), Ok(p));
        }
        assert!(Planar::parse("maybe", &()).is_err());
    }

    #[test]
    fn bulk_keeps_auto_in_the_plane_and_refuses_false() {
        for n in [2, 3, 8] {
            assert!(Planar::Auto.is_planar(n, false));
            assert!(Planar::Yes.is_planar(n, false));
        }
        assert_eq!(Planar::No.check_medium(false), Err(NEEDS_INTERFACE));
        for p in [Planar::Auto, Planar::Yes] {
            assert_eq!(p.check_medium(false), Ok(()));
        }
        assert_eq!(Planar::No.check_medium(true), Ok(()));
        assert!(Planar::Auto.reason(3, false).contains("bulk"));
    }
}
