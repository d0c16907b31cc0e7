//! The ranges the benchmark's rigs are drawn from, as a TOML file (`--ranges`): every key of
//! [`Ranges::default`] (the ranges docs/calibration.md documents), each optional, each checked against what it means.

use std::path::Path;

use serde::{Deserialize, Serialize};

use magbench_env::InputError;
use magbench_env::input::{self, Bound, Rejection};

/// Where the rigs' values are drawn from: `[low, high]` for each number (drawn uniformly), a
/// share of rigs for each switch.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Ranges {
    /// Camera latency (frames, fractions included).
    pub latency_frames: [f64; 2],
    /// Detection noise σ (BL per coordinate).
    pub noise_bl: [f64; 2],
    /// Time constant of the field (Helmholtz) coils (ms).
    pub field_tau_ms: [f64; 2],
    /// Time constant of the gradient (Maxwell) coils (ms).
    pub gradient_tau_ms: [f64; 2],
    /// Gain of each gradient axis (1 = as commanded).
    pub gradient_gain: [f64; 2],
    /// Each agent's moment factor.
    pub moment: [f64; 2],
    /// Each agent's drag factor.
    pub drag: [f64; 2],
    /// Rotation of the coil frame against the camera's (degrees).
    pub field_bias_deg: [f64; 2],
    /// Share of rigs whose agents sit at a liquid–air interface (the rest in bulk liquid).
    pub interface_share: f64,
    /// Share of rigs with hydrodynamic interaction between the agents.
    pub hydrodynamics_share: f64,
}

impl Default for Ranges {
    /// The default ranges: latency 0–4 frames, noise 0.005–0.08 BL, coil τ 2–40 ms, gradient
    /// gains ±20%, moments and drags ±30%, a coil frame rotated up to ±2° (twice the
    /// `hardware` preset's estimate of 1°, either way), half the rigs at an interface, half
    /// with hydrodynamic interaction.
    fn default() -> Self {
        Self {
            latency_frames: [0.0, 4.0],
            noise_bl: [0.005, 0.08],
            field_tau_ms: [2.0, 40.0],
            gradient_tau_ms: [2.0, 40.0],
            gradient_gain: [0.8, 1.2],
            moment: [0.7, 1.3],
            drag: [0.7, 1.3],
            field_bias_deg: [-2.0, 2.0],
            interface_share: 0.5,
            hydrodynamics_share: 0.5,
        }
    }
}

/// Latencies a rig may have: the fit's own bound on `--max-latency`.
const LATENCY: Bound = Bound::closed(
    0.0,
    30.0,
    " frames",
    "the fit searches up to 30 frames, half a second at 60 fps",
);
/// Detection noise a rig may have.
const NOISE: Bound = Bound::closed(
    0.0,
    0.5,
    " BL",
    "beyond half a body length the detector no longer tells the agents apart",
);
/// Coil time constants a rig may have (the preset's own bound).
const TAU: Bound = Bound::above(
    0.0,
    1000.0,
    " ms",
    "0 is no coil dynamics, which the fit then does not model; a preset takes at most 1000 ms",
);
/// Gains and factors a rig may have.
const FACTOR: Bound = Bound::closed(
    0.1,
    10.0,
    "",
    "a factor is relative to the scenario's agent or coil; beyond 10× it is another agent or coil",
);
/// Rotations of the coil frame a rig may have.
const BIAS: Bound = Bound::closed(
    -45.0,
    45.0,
    "°",
    "a coil frame rotated further is mounted wrongly, not biased",
);
/// A share of rigs.
const SHARE: Bound = Bound::closed(0.0, 1.0, "", "a share of the rigs");

impl Ranges {
    /// Reads and checks the ranges file at `path`; errors name the file, the field and the
    /// reason (with its line).
    pub fn load(path: &Path) -> Result<Self, InputError> {
        let file = path.display().to_string();
        let text = input::read_text(path, &file)?;
        let r: Self = input::parse_toml(&text, &file)?;
        r.check().map_err(|e| {
            let line = input::field_line(&text, &e.field);
            InputError::new(&file, &e.field, format!("{}{line}", e.reason))
        })?;
        Ok(r)
    }

    /// Checks every value against its bound and every range's order.
    pub fn check(&self) -> Result<(), Rejection> {
        let pairs: [(&str, [f64; 2], &Bound); 8] = [
            ("latency_frames", self.latency_frames, &LATENCY),
            ("noise_bl", self.noise_bl, &NOISE),
            ("field_tau_ms", self.field_tau_ms, &TAU),
            ("gradient_tau_ms", self.gradient_tau_ms, &TAU),
            ("gradient_gain", self.gradient_gain, &FACTOR),
            ("moment", self.moment, &FACTOR),
            ("drag", self.drag, &FACTOR),
            ("field_bias_deg", self.field_bias_deg, &BIAS),
        ];
        for (name, [lo, hi], bound) in pairs {
            bound.check(name, lo)?;
            bound.check(name, hi)?;
            if lo > hi {
                return Err(Rejection::new(
                    name,
                    format!("a range is [low, high]; got low {lo} above high {hi}"),
                ));
            }
        }
        SHARE.check("interface_share", self.interface_share)?;
        SHARE.check("hydrodynamics_share", self.hydrodynamics_share)?;
        Ok(())
    }

    /// The largest latency a rig can have, in whole frames: the fit's `max_latency`.
    pub fn max_latency(&self) -> usize {
        self.latency_frames[1].ceil() as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_pass_and_a_reversed_range_does_not() {
        Ranges::default().check().unwrap();
        let r = Ranges {
            drag: [1.3, 0.7],
            ..Ranges::default()
        };
        assert_eq!(r.check().unwrap_err().field, "drag");
        let r = Ranges {
            noise_bl: [0.0, f64::NAN],
            ..Ranges::default()
        };
        assert_eq!(r.check().unwrap_err().field, "noise_bl");
        let r = Ranges {
            field_bias_deg: [-50.0, 2.0],
            ..Ranges::default()
        };
        assert_eq!(r.check().unwrap_err().field, "field_bias_deg");
    }
}
