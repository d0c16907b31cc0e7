//! Disturbance presets as data: one TOML table per term, each with `enabled` and its values.
//!
//! A table left out of a file is off. `ideal`, `realistic` and `hardware` ship as files in
//! `presets/` and are built in (embedded), so their names work from any directory.

use std::path::Path;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::term::{Contribution, RunContext, Term};
use super::{AgentFactors, CameraParams, Fitted, Medium, Walls};
use crate::coil::COIL_ALPHA_MAX_DEG;
use crate::error::InputError;
use crate::input;
use crate::input::Rejection;
use crate::input::bounds::within;
use crate::physics::PhysicalParams;

/// The preset struct, its term names, switches, checks and draws, from the term table.
macro_rules! disturbance_preset {
    ($($name:ident : $module:ident :: $ty:ident,)*) => {
        /// Everything the simulated plant and camera add to the planning model (see
        /// docs/plant.md, "The simulated plant", for each term's physics and the `hardware`
        /// values' sources).
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct DisturbancePreset {
            /// Preset name.
            pub name: String,
            /// One line on what the preset describes.
            #[serde(default)]
            pub description: String,
            /// Whether the map's walls stop the agents (`physical`, the default) or only
            /// count as violations (`virtual`).
            #[serde(default, skip_serializing_if = "Walls::is_physical")]
            pub walls: Walls,
            /// Where the agents move: `bulk` or `interface`.
            #[serde(default)]
            pub medium: Medium,
            /// The simulated coil's reach: its elevation range.
            #[serde(default)]
            pub coil: CoilRange,
            $(
                #[doc = concat!("The `[", stringify!($name), "]` term (a [`super::", stringify!($ty), "`]).")]
                #[serde(default)]
                pub $name: super::$ty,
            )*
            /// The camera.
            #[serde(default)]
            pub camera: CameraParams,
            /// Values measured on one rig (`magbench calibrate`) in place of per-run draws.
            #[serde(default, skip_serializing_if = "Fitted::is_off")]
            pub fitted: Fitted,
        }

        impl DisturbancePreset {
            /// Every term that can be switched on and off, by its table name: the plant terms
            /// in table order, then the camera's.
            pub const TERMS: [&'static str; [$(stringify!($name),)*].len() + CAMERA_TERMS.len()] =
                concat_names(&[$(stringify!($name),)*], &CAMERA_TERMS);

            fn check_terms(&self) -> Result<(), Rejection> {
                $(
                    Term::check(&self.$name).map_err(|r| r.under(stringify!($name)))?;
                )*
                Ok(())
            }

            fn term_enabled(&self, term: &str) -> Option<bool> {
                $(
                    if term == stringify!($name) {
                        return Some(Term::enabled(&self.$name));
                    }
                )*
                self.camera_switch(term).map(|s| *s)
            }

            fn set_term(&mut self, term: &str, on: bool) -> Option<()> {
                $(
                    if term == stringify!($name) {
                        Term::set_enabled(&mut self.$name, on);
                        return Some(());
                    }
                )*
                self.camera_switch_mut(term).map(|s| *s = on)
            }

            /// The contributions to the equations of motion of the terms that are on and add
            /// one, drawn for the run seeded with `seed` (in table order).
            pub fn contributions(
                &self,
                params: &PhysicalParams,
                factors: &AgentFactors,
                n: usize,
                seed: u64,
            ) -> Vec<Arc<dyn Contribution>> {
                let mut out = Vec::new();
                $(
                    if Term::enabled(&self.$name) {
                        let run = RunContext {
                            name: stringify!($name),
                            params,
                            medium: &self.medium,
                            factors,
                            n,
                            seed,
                        };
                        out.extend(Term::draw(&self.$name, &run));
                    }
                )*
                out
            }
        }
    };
}

plant_terms!(disturbance_preset);

/// The camera's terms, switched in its `[camera]` table.
const CAMERA_TERMS: [&str; 5] = [
    "camera.latency",
    "camera.noise",
    "camera.misses",
    "camera.swaps",
    "camera.pixels",
];

/// `a` then `b`, as one array of `N = a.len() + b.len()` names.
const fn concat_names<const N: usize>(a: &[&'static str], b: &[&'static str]) -> [&'static str; N] {
    assert!(a.len() + b.len() == N, "N is the total length");
    let mut out = [""; N];
    let mut i = 0;
    while i < a.len() {
        out[i] = a[i];
        i += 1;
    }
    let mut j = 0;
    while j < b.len() {
        out[i + j] = b[j];
        j += 1;
    }
    out
}

/// The simulated coil's reach (`[coil]`): how far out of the plane it can tilt the field.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoilRange {
    /// Largest field elevation |α| (degrees, in [0, 90]): 90 for a tri-axial Helmholtz coil
    /// (its z pair sets any B_z), 0 for a planar coil set.
    #[serde(default = "coil_alpha_max")]
    pub alpha_max_deg: f64,
}

fn coil_alpha_max() -> f64 {
    COIL_ALPHA_MAX_DEG
}

impl Default for CoilRange {
    fn default() -> Self {
        CoilRange {
            alpha_max_deg: COIL_ALPHA_MAX_DEG,
        }
    }
}

impl CoilRange {
    /// Checks the range; returns (field, reason).
    pub fn check(&self) -> Result<(), Rejection> {
        within("coil.alpha_max_deg", self.alpha_max_deg, 0.0, 90.0, "°")
    }
}

const IDEAL: &str = include_str!("../../../presets/ideal.toml");
const REALISTIC: &str = include_str!("../../../presets/realistic.toml");
const HARDWARE: &str = include_str!("../../../presets/hardware.toml");

impl DisturbancePreset {
    /// Names of the built-in presets.
    pub const NAMES: [&'static str; 3] = ["ideal", "realistic", "hardware"];

    /// No disturbance and a perfect camera with no latency: the plant is the planning model.
    pub fn ideal() -> Self {
        Self::builtin("ideal", IDEAL)
    }

    /// A bench-top rig as magbench first modelled it: ±10% moment and drag (uniform), a 1°
    /// field bias with 0.5° jitter, a drift flow up to 0.02 BL/s, Brownian motion, and a 60 fps
    /// camera with one frame of latency, 0.02 BL detection noise and 1% missed detections.
    pub fn realistic() -> Self {
        Self::builtin("realistic", REALISTIC)
    }

    /// Every term, with values from sources or derivations (docs/plant.md).
    pub fn hardware() -> Self {
        Self::builtin("hardware", HARDWARE)
    }

    fn builtin(name: &str, text: &str) -> Self {
        Self::parse(text, &format!("<built-in {name}>"))
            .unwrap_or_else(|e| panic!("the built-in preset is valid (a test checks it): {e}"))
    }

    /// The built-in preset of that name.
    pub fn by_name(name: &str) -> Option<Self> {
        match name {
            "ideal" => Some(Self::ideal()),
            "realistic" => Some(Self::realistic()),
            "hardware" => Some(Self::hardware()),
            _ => None,
        }
    }

    /// The TOML text of a built-in preset, as shipped in `presets/`.
    pub fn builtin_text(name: &str) -> Option<&'static str> {
        match name {
            "ideal" => Some(IDEAL),
            "realistic" => Some(REALISTIC),
            "hardware" => Some(HARDWARE),
            _ => None,
        }
    }

    /// A built-in name, or else the path of a preset file.
    pub fn resolve(name_or_file: &str) -> Result<Self, InputError> {
        match Self::by_name(name_or_file) {
            Some(p) => Ok(p),
            None => Self::load(Path::new(name_or_file)),
        }
    }

    /// Reads and validates a preset file (through the shared loader, [`crate::input`]).
    pub fn load(path: &Path) -> Result<Self, InputError> {
        let file = path.display().to_string();
        let text = input::read_text(path, &file).map_err(|e| {
            InputError::new(
                &file,
                "",
                format!("{}; built-in presets: {}", e.reason, Self::NAMES.join(", ")),
            )
        })?;
        Self::parse(&text, &file)
    }

    /// Parses and validates preset TOML `text`; `file` names it in errors, which give the
    /// field and its line.
    pub fn parse(text: &str, file: &str) -> Result<Self, InputError> {
        let preset: Self = input::parse_toml(text, file)?;
        preset.check().map_err(|r| {
            let line = input::field_line(text, &r.field);
            InputError::new(file, &r.field, format!("{}{line}", r.reason))
        })?;
        Ok(preset)
    }

    /// The preset as TOML (every table written out).
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a preset serialises")
    }

    /// Checks every value (finite, in range); returns (field, reason).
    pub fn check(&self) -> Result<(), Rejection> {
        if self.name.trim().is_empty() {
            return Err(Rejection::new("name", "must not be empty"));
        }
        self.medium.check()?;
        self.coil.check()?;
        self.check_terms()?;
        self.camera.check()?;
        self.fitted.check()
    }

    fn camera_switch(&self, term: &str) -> Option<&bool> {
        let c = &self.camera;
        Some(match term {
            "camera.latency" => &c.latency.enabled,
            "camera.noise" => &c.noise.enabled,
            "camera.misses" => &c.misses.enabled,
            "camera.swaps" => &c.swaps.enabled,
            "camera.pixels" => &c.pixels.enabled,
            _ => return None,
        })
    }

    fn camera_switch_mut(&mut self, term: &str) -> Option<&mut bool> {
        let c = &mut self.camera;
        Some(match term {
            "camera.latency" => &mut c.latency.enabled,
            "camera.noise" => &mut c.noise.enabled,
            "camera.misses" => &mut c.misses.enabled,
            "camera.swaps" => &mut c.swaps.enabled,
            "camera.pixels" => &mut c.pixels.enabled,
            _ => return None,
        })
    }

    /// Switches a term (one of [`DisturbancePreset::TERMS`]) on or off, keeping its values;
    /// an unknown name is rejected, naming the known ones.
    pub fn set_enabled(&mut self, term: &str, on: bool) -> Result<(), Rejection> {
        self.set_term(term, on).ok_or_else(|| {
            Rejection::new(
                "term",
                format!("unknown term {term:?}; terms: {}", Self::TERMS.join(", ")),
            )
        })
    }

    /// Whether a term is on (`None` for an unknown name).
    pub fn enabled(&self, term: &str) -> Option<bool> {
        self.term_enabled(term)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn built_in_presets_load_and_round_trip() {
        for name in DisturbancePreset::NAMES {
            let p = DisturbancePreset::by_name(name).unwrap();
            assert_eq!(p.name, name);
            let text = p.to_toml();
            let back = DisturbancePreset::parse(&text, "round-trip").unwrap();
            assert_eq!(back, p, "{name} round-trips:\n{text}");
        }
    }

    #[test]
    fn shipped_files_are_the_built_in_presets() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../presets");
        for name in DisturbancePreset::NAMES {
            let file = DisturbancePreset::load(&dir.join(format!("{name}.toml"))).unwrap();
            assert_eq!(file, DisturbancePreset::by_name(name).unwrap());
            assert_eq!(
                DisturbancePreset::resolve(dir.join(format!("{name}.toml")).to_str().unwrap())
                    .unwrap(),
                file
            );
        }
    }

    #[test]
    fn ideal_has_every_term_off_and_hardware_every_term_on() {
        let (ideal, hw) = (DisturbancePreset::ideal(), DisturbancePreset::hardware());
        for t in DisturbancePreset::TERMS {
            assert_eq!(ideal.enabled(t), Some(false), "ideal: {t}");
        }
        for t in DisturbancePreset::TERMS {
            // the hardware rig has no uniform drift (its flow varies), and no sourced image
            // scale for the pixel-level camera
            let off = ["drift", "camera.pixels"].contains(&t);
            assert_eq!(hw.enabled(t), Some(!off), "hardware: {t}");
        }
        assert!(hw.medium.interface().is_some());
        assert_eq!(ideal.camera.fps, 60.0);
    }

    #[test]
    fn realistic_keeps_its_values() {
        let r = DisturbancePreset::realistic();
        assert_eq!(
            (r.heterogeneity.moment_spread, r.heterogeneity.drag_spread),
            (0.1, 0.1)
        );
        assert_eq!(
            (r.field_error.angle_bias_deg, r.field_error.angle_jitter_deg),
            (1.0, 0.5)
        );
        assert_eq!(r.drift.max_speed_bl_s, 0.02);
        assert!(r.brownian.enabled);
        let c = &r.camera;
        assert_eq!(
            (c.fps, c.latency.frames, c.noise.sigma_bl, c.misses.prob),
            (60.0, 1.0, 0.02, 0.01)
        );
        for t in [
            "coil_lag",
            "magnet_lag",
            "nonuniform_field",
            "coil_calibration",
            "ambient_field",
            "hydrodynamics",
            "capillary",
            "flow",
            "camera.swaps",
        ] {
            assert_eq!(r.enabled(t), Some(false), "realistic: {t}");
        }
    }

    #[test]
    fn terms_switch_one_at_a_time() {
        let mut p = DisturbancePreset::hardware();
        for t in DisturbancePreset::TERMS {
            p.set_enabled(t, false).unwrap();
            assert_eq!(p.enabled(t), Some(false));
        }
        assert!(p.set_enabled("gravity", true).is_err());
        assert_eq!(p.enabled("gravity"), None);
    }

    fn rejected(edit: &str) -> InputError {
        let text = format!(
            "{}\n{edit}",
            DisturbancePreset::builtin_text("hardware").unwrap()
        );
        DisturbancePreset::parse(&text, "bad.toml").unwrap_err()
    }

    #[test]
    fn validation_names_the_field() {
        let hw = DisturbancePreset::hardware();
        let mut p = hw.clone();
        p.coil_lag.field_tau_ms = f64::NAN;
        assert_eq!(p.check().unwrap_err().field, "coil_lag.field_tau_ms");
        let mut p = hw.clone();
        p.coil_lag.gradient_slew_mt_per_m_per_s = -1.0;
        assert_eq!(
            p.check().unwrap_err().field,
            "coil_lag.gradient_slew_mt_per_m_per_s"
        );
        let mut p = hw.clone();
        p.camera.misses.close_prob = 2.0;
        assert_eq!(p.check().unwrap_err().field, "camera.misses.close_prob");
        let mut p = hw.clone();
        p.heterogeneity.moment_spread = f64::INFINITY;
        assert_eq!(p.check().unwrap_err().field, "heterogeneity.moment_spread");
        let mut p = hw.clone();
        if let Medium::Interface(i) = &mut p.medium {
            i.contact_angle_deg = 180.0;
        }
        assert_eq!(p.check().unwrap_err().field, "medium.contact_angle_deg");
        let mut p = hw.clone();
        p.flow.length_bl = 0.0;
        assert_eq!(p.check().unwrap_err().field, "flow.length_bl");
        let mut p = hw.clone();
        p.coil.alpha_max_deg = 91.0;
        assert_eq!(p.check().unwrap_err().field, "coil.alpha_max_deg");
        let mut p = hw;
        p.camera.fps = 0.0;
        assert_eq!(p.check().unwrap_err().field, "camera.fps");
        // through the file: FILE: FIELD: REASON
        let e = DisturbancePreset::parse(
            "name = \"x\"\n[drift]\nenabled = true\nmax_speed_bl_s = -0.1\n",
            "bad.toml",
        )
        .unwrap_err();
        assert_eq!(
            (e.file.as_str(), e.field.as_str()),
            ("bad.toml", "drift.max_speed_bl_s")
        );
        assert!(
            e.to_string()
                .starts_with("bad.toml: drift.max_speed_bl_s: must be"),
            "{e}"
        );
        assert!(e.reason.ends_with("(line 4)"), "{e}");
        // a parse error carries its line too
        let e = DisturbancePreset::parse("name = \"x\"\n[camera]\nfps = \"fast\"\n", "bad.toml")
            .unwrap_err();
        assert_eq!(e.field, "camera.fps");
        assert!(e.reason.ends_with("(line 3)"), "{e}");
    }

    #[test]
    fn walls_are_physical_unless_a_preset_says_virtual() {
        assert_eq!(DisturbancePreset::hardware().walls, Walls::Physical);
        assert!(!DisturbancePreset::hardware().to_toml().contains("walls"));
        let p = DisturbancePreset::parse("name = \"x\"\nwalls = \"virtual\"\n", "f.toml").unwrap();
        assert_eq!(p.walls, Walls::Virtual);
        assert_eq!(DisturbancePreset::parse(&p.to_toml(), "back").unwrap(), p);
        let e =
            DisturbancePreset::parse("name = \"x\"\nwalls = \"glass\"\n", "bad.toml").unwrap_err();
        assert_eq!((e.file.as_str(), e.field.as_str()), ("bad.toml", "walls"));
    }

    #[test]
    fn new_fields_are_rejected_naming_file_and_field() {
        for (edit, field) in [
            (
                "[camera.pixels]\nenabled = true\npx_per_bl = 0.5\ncentre_step_px = 0.0\nmerge_gap_px = 1.0",
                "camera.pixels.px_per_bl",
            ),
            (
                "[camera.pixels]\nenabled = true\npx_per_bl = 13.0\ncentre_step_px = 99.0\nmerge_gap_px = 1.0",
                "camera.pixels.centre_step_px",
            ),
            (
                "[camera.pixels]\nenabled = true\npx_per_bl = 13.0\ncentre_step_px = 1.0\nmerge_gap_px = -1.0",
                "camera.pixels.merge_gap_px",
            ),
        ] {
            let e = DisturbancePreset::parse(
                &format!("name = \"x\"\n[camera]\nfps = 60.0\n{edit}\n"),
                "bad.toml",
            )
            .unwrap_err();
            assert_eq!(
                (e.file.as_str(), e.field.as_str()),
                ("bad.toml", field),
                "{e}"
            );
            assert!(e.reason.contains("(line "), "{e}");
        }
        for (field, value) in [
            ("common_moment_factor", "0.0"),
            ("common_moment_spread", "-0.1"),
            ("common_drag_factor", "20.0"),
            ("common_drag_spread", "1.5"),
        ] {
            let text = format!(
                "name = \"x\"\n[heterogeneity]\nenabled = true\ndistribution = \"lognormal\"\nmoment_spread = 0.1\ndrag_spread = 0.1\n{field} = {value}\n"
            );
            let e = DisturbancePreset::parse(&text, "bad.toml").unwrap_err();
            assert_eq!(e.field, format!("heterogeneity.{field}"), "{e}");
        }
        let e = DisturbancePreset::parse(
            "name = \"x\"\n[coil_calibration]\nenabled = true\naxis_gain_error = 0.0\naxis_skew_deg = 0.0\ngradient_gain_error = 0.0\ngradient_crosstalk = 0.0\ngradient_gain_offset = [0.05, 0.9]\n",
            "bad.toml",
        )
        .unwrap_err();
        assert_eq!(e.field, "coil_calibration.gradient_gain_offset", "{e}");
    }

    #[test]
    fn unknown_and_missing_fields_are_rejected() {
        let e = DisturbancePreset::parse(
            "name = \"x\"\n[coil_lag]\nenabled = true\nfield_tau_ms = 1.0\n",
            "f.toml",
        )
        .unwrap_err();
        assert!(e.reason.contains("missing field"), "{e}");
        let e = DisturbancePreset::parse(
            "name = \"x\"\n[hydrodynamics]\nenabled = true\nstrength = 2\n",
            "f.toml",
        )
        .unwrap_err();
        assert!(e.reason.contains("unknown field"), "{e}");
        assert_eq!(e.field, "hydrodynamics.strength");
        let e = rejected("[gravity]\nenabled = true");
        assert!(
            e.reason.contains("duplicate") || e.reason.contains("unknown"),
            "{e}"
        );
        assert!(
            DisturbancePreset::parse("name = \"x\"\n[medium]\nkind = \"vacuum\"\n", "f.toml")
                .is_err()
        );
        assert!(DisturbancePreset::resolve("/no/such/preset.toml").is_err());
    }
}
