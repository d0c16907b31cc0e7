//! What the calibration tests share: the preset of an emulated rig, the strongly noisy one,
//! and an excitation run on env's plant.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use magbench_drivers::excite::{ExciteSetup, excite, log_for};
use magbench_env::Scenario;
use magbench_env::plant::{DisturbancePreset, Fitted};
use magbench_trackers::SimRig;

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

/// The true latency of [`noisy`] (frames).
pub const NOISY_LATENCY: usize = 3;

/// Moments and drags off by up to 22%, gradient gains by 7%, [`NOISY_LATENCY`] frames of
/// latency, 0.03 BL of detection noise (the top of the physical range), hydrodynamic
/// interaction on.
pub fn noisy() -> DisturbancePreset {
    let fitted = Fitted {
        enabled: true,
        moment: vec![1.18, 0.84],
        drag: vec![0.78, 1.22],
        gradient_gain: Some([1.07, 0.94]),
        field_bias_deg: Some(1.5),
        drift_bl_s: Some([0.004, -0.006]),
    };
    emulated("noisy", fitted, NOISY_LATENCY as f64, 0.03)
}

/// A preset of `tests/fixtures`.
pub fn fixture(name: &str) -> DisturbancePreset {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(name);
    DisturbancePreset::load(&path).unwrap()
}

/// `seconds` of excitation on open-field under `truth` (rig and excitation seed 14, the field
/// tilted up to 90°), stepped frame by frame on env's plant and camera (`SimRig`: no sockets, no
/// wall clock); the scenario and the rig log written in `dir`.
pub fn excite_open_field(
    truth: &DisturbancePreset,
    seconds: f64,
    dir: &Path,
) -> (Scenario, PathBuf) {
    excite_seeded(truth, seconds, 14, std::f64::consts::FRAC_PI_2, dir)
}

/// [`excite_open_field`] with the rig and the excitation seeded by `seed` and the field tilted
/// up to `alpha_max` (radians).
pub fn excite_seeded(
    truth: &DisturbancePreset,
    seconds: f64,
    seed: u64,
    alpha_max: f64,
    dir: &Path,
) -> (Scenario, PathBuf) {
    let scenario = Scenario::load("open-field").unwrap();
    let path = dir.join("rig-log.csv");
    let mut rig = SimRig::new(&scenario, truth, seed);
    let mut log = log_for(&path, scenario.agents()).unwrap();
    let setup = ExciteSetup {
        duration: seconds,
        seed,
        gradient_limit: scenario.physics.gradient_limit(),
        alpha_max,
        world: scenario.world.clone(),
    };
    excite(&mut rig, &setup, Some(&mut log)).unwrap();
    (scenario, path)
}
