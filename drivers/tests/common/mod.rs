//! What the calibration tests share: the preset of an emulated rig.

use magbench_env::plant::{DisturbancePreset, Fitted};

/// The preset of a rig the fit should recover: the `ideal` plant with hydrodynamic interaction,
/// the per-agent factors and coil errors of `fitted`, a camera `latency` frames late (off at 0)
/// with `noise` BL of detection noise.
pub fn emulated(name: &str, fitted: Fitted, latency: f64, noise: f64) -> DisturbancePreset {
    let mut p = DisturbancePreset::ideal();
    p.name = name.into();
    p.hydrodynamics.enabled = true;
    p.fitted = fitted;
    p.camera.latency.enabled = latency > 0.0;
    p.camera.latency.frames = latency;
    p.camera.noise.enabled = true;
    p.camera.noise.sigma_bl = noise;
    p
}
