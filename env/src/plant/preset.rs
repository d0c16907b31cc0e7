//! Named disturbance presets: "ideal" and "realistic".

use serde::{Deserialize, Serialize};

use super::CameraParams;

/// The disturbances a plant run draws from (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DisturbancePreset {
    /// Preset name.
    pub name: String,
    /// Per-agent moment factor drawn uniformly from `[1 − s, 1 + s]` once per run.
    pub moment_spread: f64,
    /// Per-agent drag factor drawn uniformly from `[1 − s, 1 + s]` once per run.
    pub drag_spread: f64,
    /// Standard deviation of a per-run field-angle bias (degrees).
    pub field_angle_bias_deg: f64,
    /// Standard deviation of white field-angle jitter, drawn every integration step (degrees).
    pub field_angle_jitter_deg: f64,
    /// Largest speed of the uniform drift flow (BL/s); speed and direction drawn once per run.
    pub drift_speed_bl_s: f64,
    /// Brownian motion at the physical diffusion constant of the preset.
    pub brownian: bool,
    /// The camera that observes the plant.
    pub camera: CameraParams,
}

impl DisturbancePreset {
    /// No disturbance, a perfect camera with no latency: the plant is the planning model.
    pub fn ideal() -> Self {
        Self {
            name: "ideal".into(),
            moment_spread: 0.0,
            drag_spread: 0.0,
            field_angle_bias_deg: 0.0,
            field_angle_jitter_deg: 0.0,
            drift_speed_bl_s: 0.0,
            brownian: false,
            camera: CameraParams {
                fps: 60.0,
                latency_frames: 0,
                noise_bl: 0.0,
                miss_prob: 0.0,
            },
        }
    }

    /// What a bench-top rig looks like: ±10% moment and drag, a 1° field bias with 0.5°
    /// jitter, a drift flow up to 0.02 BL/s, Brownian motion, and a 60 fps camera with one frame
    /// of latency, 0.02 BL (≈ 1 px at 50 px/BL) detection noise and 1% missed detections.
    pub fn realistic() -> Self {
        Self {
            name: "realistic".into(),
            moment_spread: 0.10,
            drag_spread: 0.10,
            field_angle_bias_deg: 1.0,
            field_angle_jitter_deg: 0.5,
            drift_speed_bl_s: 0.02,
            brownian: true,
            camera: CameraParams::default(),
        }
    }

    /// The preset of that name.
    pub fn by_name(name: &str) -> Option<Self> {
        match name {
            "ideal" => Some(Self::ideal()),
            "realistic" => Some(Self::realistic()),
            _ => None,
        }
    }

    /// Names accepted by [`DisturbancePreset::by_name`].
    pub const NAMES: [&'static str; 2] = ["ideal", "realistic"];
}
