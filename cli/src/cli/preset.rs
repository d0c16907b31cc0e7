//! `magbench preset list|show|check`: the disturbance presets of the simulated plant.

use clap::Subcommand;
use magbench_env::plant::DisturbancePreset;

use crate::Error;
use crate::output::{out, outln};

/// Preset subcommands.
#[derive(Debug, Subcommand)]
pub enum PresetCmd {
    /// List the built-in presets.
    List,
    /// Print a preset, every term and value with its unit.
    Show {
        /// A built-in name (ideal, realistic, hardware) or a preset file.
        preset: String,
    },
    /// Validate a preset file; exits 2 with FILE: FIELD: REASON (line N) when it is invalid.
    Check {
        /// The preset file (or built-in name) to validate.
        file: String,
    },
}

/// Runs a preset subcommand.
pub fn run(cmd: PresetCmd) -> Result<(), Error> {
    match cmd {
        PresetCmd::List => {
            for name in DisturbancePreset::NAMES {
                let p = DisturbancePreset::resolve(name)?;
                outln!("{name:<12} {}", p.description);
            }
        }
        PresetCmd::Show { preset } => out!("{}", show(&DisturbancePreset::resolve(&preset)?)),
        PresetCmd::Check { file } => {
            let p = DisturbancePreset::resolve(&file)?;
            let on = DisturbancePreset::TERMS
                .iter()
                .filter(|t| p.enabled(t) == Some(true))
                .count();
            outln!(
                "{file}: ok ({}, {on} of {} terms on)",
                p.name,
                DisturbancePreset::TERMS.len()
            );
        }
    }
    Ok(())
}

/// The unit of a preset field, from its name (units are spelt in the field names).
pub fn unit(key: &str) -> &'static str {
    const SUFFIXES: [(&str, &str); 14] = [
        ("px_per_bl", "px per BL"),
        ("_mt_per_m_per_s", "mT/m per s"),
        ("_mn_per_m", "mN/m"),
        ("_kg_per_m3", "kg/m³"),
        ("_mt_per_s", "mT/s"),
        ("_bl_s", "BL/s"),
        ("_ms", "ms"),
        ("_deg", "°"),
        ("_mm", "mm"),
        ("_ut", "µT"),
        ("_px", "px"),
        ("_bl", "BL"),
        ("_s", "s"),
        ("frames", "frames"),
    ];
    if key == "fps" {
        return "frames/s";
    }
    for (suffix, unit) in SUFFIXES {
        if key.ends_with(suffix) {
            return unit;
        }
    }
    if key.ends_with("prob") {
        "probability"
    } else if key.ends_with("spread") || key.ends_with("error") || key.ends_with("crosstalk") {
        "fraction"
    } else {
        ""
    }
}

/// A preset as text: each term on or off, each value with its unit.
pub fn show(p: &DisturbancePreset) -> String {
    let value = toml::Value::try_from(p).expect("a preset serialises");
    let mut out = format!("preset      {}\n", p.name);
    if !p.description.is_empty() {
        out += &format!("            {}\n", p.description);
    }
    let walls = toml::Value::try_from(p.walls).expect("walls serialise");
    out += &format!("walls       {}\n", scalar(&walls));
    if let toml::Value::Table(t) = &value {
        for (key, v) in t {
            if let toml::Value::Table(sub) = v {
                table(&mut out, key, sub, 0);
            }
        }
    }
    out
}

fn scalar(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        toml::Value::Float(f) => format!("{f}"),
        other => other.to_string(),
    }
}

fn table(out: &mut String, name: &str, t: &toml::Table, depth: usize) {
    let pad = "  ".repeat(depth);
    let state = match t.get("enabled") {
        Some(toml::Value::Boolean(true)) => "on",
        Some(toml::Value::Boolean(false)) => "off",
        _ => t.get("kind").and_then(|k| k.as_str()).unwrap_or(""),
    };
    *out += &format!("{pad}{name:<28} {state}\n");
    for (key, v) in t {
        if matches!(key.as_str(), "enabled" | "kind") {
            continue;
        }
        match v {
            toml::Value::Table(sub) => table(out, &format!("{name}.{key}"), sub, depth + 1),
            v => *out += &format!("{pad}  {key:<32} {} {}\n", scalar(v), unit(key)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_come_from_the_field_names() {
        assert_eq!(unit("field_tau_ms"), "ms");
        assert_eq!(unit("gradient_slew_mt_per_m_per_s"), "mT/m per s");
        assert_eq!(unit("field_slew_mt_per_s"), "mT/s");
        assert_eq!(unit("rms_speed_bl_s"), "BL/s");
        assert_eq!(unit("sigma_bl"), "BL");
        assert_eq!(unit("bias_time_s"), "s");
        assert_eq!(unit("jitter_frames"), "frames");
        assert_eq!(unit("close_prob"), "probability");
        assert_eq!(unit("moment_spread"), "fraction");
        assert_eq!(unit("fps"), "frames/s");
        assert_eq!(unit("px_per_bl"), "px per BL");
        assert_eq!(unit("merge_gap_px"), "px");
    }

    #[test]
    fn show_prints_every_term_with_units() {
        let text = show(&DisturbancePreset::hardware());
        assert!(text.starts_with("preset      hardware\n"), "{text}");
        for t in DisturbancePreset::TERMS {
            let last = t.rsplit('.').next().unwrap();
            assert!(text.contains(last), "{t} missing:\n{text}");
        }
        assert!(text.contains("field_tau_ms"), "{text}");
        assert!(text.contains("6 ms"), "{text}");
        assert!(text.contains("camera.latency"), "{text}");
        let ideal = show(&DisturbancePreset::ideal());
        assert!(ideal.contains("off") && !ideal.contains(" on\n"), "{ideal}");
    }
}
