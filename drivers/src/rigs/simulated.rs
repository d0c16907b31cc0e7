//! The `simulated` rig: env's plant and camera under a disturbance preset.

use std::path::Path;

use magbench_env::Scenario;
use magbench_env::plant::DisturbancePreset;
use magbench_trackers::{Rig, SimRig};

use super::forward::forward_rig;
use super::{OpenError, RigDescription, RigKind, RigPlant, RunRig, preset_named};

/// The simulated rig of a disturbance preset (a built-in name or a preset file).
#[derive(Debug, Clone)]
pub struct SimulatedRig {
    preset: DisturbancePreset,
    source: String,
}

impl SimulatedRig {
    /// The simulated rig of `preset`; `source` names it in messages (its name or file).
    pub fn new(preset: DisturbancePreset, source: &str) -> Self {
        SimulatedRig {
            preset,
            source: source.to_string(),
        }
    }

    /// The preset.
    pub fn preset(&self) -> &DisturbancePreset {
        &self.preset
    }
}

impl RigKind for SimulatedRig {
    fn load(arg: &str, option: &str) -> Result<Self, OpenError> {
        Ok(SimulatedRig::new(preset_named(arg, option)?, arg))
    }
}

impl RigDescription for SimulatedRig {
    fn frame_period(&self) -> f64 {
        1.0 / self.preset.camera.fps
    }

    fn plant(&self) -> RigPlant {
        RigPlant {
            medium: self.preset.medium.clone(),
            coil_alpha_max_deg: self.preset.coil.alpha_max_deg,
            coil_source: format!("{}: coil.alpha_max_deg", self.source),
        }
    }

    fn open(
        &self,
        scenario: &Scenario,
        seed: u64,
        _log_dir: Option<&Path>,
    ) -> Result<Box<dyn RunRig>, OpenError> {
        Ok(Box::new(OpenSim {
            rig: SimRig::new(scenario, &self.preset, seed),
            preset: self.preset.name.clone(),
        }))
    }
}

/// A simulated rig opened for one run.
struct OpenSim {
    rig: SimRig,
    preset: String,
}

forward_rig!(OpenSim, rig);

impl RunRig for OpenSim {
    fn label(&self) -> String {
        self.preset.clone()
    }

    fn as_rig(&mut self) -> &mut dyn Rig {
        self
    }
}
