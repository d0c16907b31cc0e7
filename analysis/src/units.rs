//! The units lengths are shown in: body lengths (the model's unit), or micrometres and
//! millimetres per second from the scenario's agent diameter (`[physics] diameter_um`).

use std::path::Path;

use magbench_env::Scenario;

/// Units of lengths and speeds in the report and plots.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Units {
    /// Body lengths (1 BL = one agent diameter) and BL/s, as the model computes them.
    #[default]
    Bl,
    /// µm and mm/s, from the scenario's agent diameter.
    Physical,
}

/// How one scenario's values are shown: its scale, or none (body lengths).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shown {
    /// Micrometres per body length (the agent diameter), when shown physically.
    pub um_per_bl: Option<f64>,
}

impl Shown {
    /// Body lengths.
    pub const BL: Shown = Shown { um_per_bl: None };

    /// `units` for scenario `name` of results folder `dir`: its agent diameter read from the
    /// folder's kept scenario file (`dir/scenarios/<name>.toml`, generated scenarios) or the
    /// built-in or file `name`; body lengths when the scenario cannot be read, so no value is
    /// shown in a unit it was not converted to.
    pub fn for_scenario(units: Units, name: &str, dir: &Path) -> Shown {
        if units == Units::Bl {
            return Shown::BL;
        }
        let kept = dir.join("scenarios").join(format!("{name}.toml"));
        let s = if kept.is_file() {
            Scenario::load(&kept.display().to_string())
        } else {
            Scenario::load(name)
        };
        match s {
            Ok(s) if s.physics.diameter_um.is_finite() && s.physics.diameter_um > 0.0 => Shown {
                um_per_bl: Some(s.physics.diameter_um),
            },
            _ => Shown::BL,
        }
    }

    /// The unit `unit` (a metric's, e.g. `BL`) is shown in.
    pub fn unit<'a>(&self, unit: &'a str) -> &'a str {
        match (self.um_per_bl, unit) {
            (Some(_), "BL") => "µm",
            (Some(_), "BL/s") => "mm/s",
            _ => unit,
        }
    }

    /// `v` in `unit`, as shown.
    pub fn value(&self, unit: &str, v: f64) -> f64 {
        match (self.um_per_bl, unit) {
            (Some(k), "BL") => v * k,
            (Some(k), "BL/s") => v * k * 1e-3,
            _ => v,
        }
    }

    /// An axis label `label (unit)` with the unit as shown.
    pub fn axis(&self, label: &str, unit: &str) -> String {
        match self.unit(unit) {
            "" => label.to_string(),
            u => format!("{label} ({u})"),
        }
    }

    /// Digits after the point for a value shown in `unit` that has `digits` in body lengths:
    /// micrometres of a 500 µm agent need about three fewer.
    pub fn digits(&self, unit: &str, digits: usize) -> usize {
        match (self.um_per_bl, unit) {
            (Some(k), "BL") => digits.saturating_sub(k.log10().floor().max(0.0) as usize),
            _ => digits,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn body_lengths_become_micrometres_and_speeds_millimetres_per_second() {
        let s = Shown {
            um_per_bl: Some(500.0),
        };
        assert_eq!(s.unit("BL"), "µm");
        assert_eq!(s.value("BL", 0.035), 17.5);
        assert_eq!(s.unit("BL/s"), "mm/s");
        assert!((s.value("BL/s", 2.0) - 1.0).abs() < 1e-12);
        assert_eq!(s.value("s", 3.0), 3.0);
        assert_eq!(s.axis("RMS error", "BL"), "RMS error (µm)");
        assert_eq!(s.digits("BL", 3), 1);
        assert_eq!(Shown::BL.axis("RMS error", "BL"), "RMS error (BL)");
        assert_eq!(Shown::BL.value("BL", 0.035), 0.035);
    }

    #[test]
    fn a_built_in_scenario_gives_its_agent_diameter() {
        let d = std::env::temp_dir();
        let s = Shown::for_scenario(Units::Physical, "open-field", &d);
        let want = Scenario::load("open-field").unwrap().physics.diameter_um;
        assert_eq!(s.um_per_bl, Some(want));
        assert_eq!(Shown::for_scenario(Units::Bl, "open-field", &d), Shown::BL);
        assert_eq!(
            Shown::for_scenario(Units::Physical, "no-such-scenario", &d),
            Shown::BL
        );
    }
}
