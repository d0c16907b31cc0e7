//! The `simulated` rig: env's plant and camera under a disturbance preset. Given a log folder,
//! it writes `rig-log.csv` as a coil rig does (its commands without coil currents), so that
//! `calibrate` reads a simulated run's log like a physical one's.

use std::path::Path;

use magbench_env::plant::{DisturbancePreset, Observation};
use magbench_env::{Control, Scenario};
use magbench_trackers::{GroundTruth, Rig, RigError, SimRig};

use crate::rig_log::RigLog;

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
        log_dir: Option<&Path>,
    ) -> Result<Box<dyn RunRig>, OpenError> {
        let log = match log_dir {
            Some(d) => {
                let path = d.join("rig-log.csv");
                let log = RigLog::create(&path, scenario.agents(), std::time::Instant::now())
                    .map_err(|e| OpenError::Failed(format!("{}: {e}", path.display())))?;
                Some(log)
            }
            None => None,
        };
        Ok(Box::new(OpenSim {
            rig: SimRig::new(scenario, &self.preset, seed),
            preset: self.preset.name.clone(),
            log,
            frame: 0,
            last_t: 0.0,
        }))
    }
}

/// A simulated rig opened for one run, with its log when it keeps one.
struct OpenSim {
    rig: SimRig,
    preset: String,
    log: Option<RigLog>,
    /// Frames observed so far.
    frame: u64,
    /// The capture time of the last frame observed (s).
    last_t: f64,
}

impl Rig for OpenSim {
    fn frame_period(&self) -> f64 {
        self.rig.frame_period()
    }

    fn observe(&mut self) -> Result<Observation, RigError> {
        let obs = self.rig.observe()?;
        self.frame += 1;
        self.last_t = obs.t;
        if let Some(l) = &mut self.log {
            l.observation(obs.t, self.frame, &obs.agents);
        }
        Ok(obs)
    }

    fn command(&mut self, u: &Control) -> Result<(), RigError> {
        self.rig.command(u)?;
        if let Some(l) = &mut self.log {
            l.command_without_currents(self.last_t, Some(self.frame), u);
        }
        Ok(())
    }

    fn stop(&mut self) -> Result<(), RigError> {
        let stopped = self.rig.stop();
        if let Some(l) = &mut self.log {
            l.stop(self.last_t, "stop: field zeroed");
            l.flush();
        }
        stopped
    }

    fn latency(&self) -> f64 {
        self.rig.latency()
    }

    fn set_world(&mut self, w: &magbench_env::World) -> Result<(), RigError> {
        self.rig.set_world(w)
    }

    fn ground_truth(&self) -> Option<GroundTruth> {
        self.rig.ground_truth()
    }
}

impl RunRig for OpenSim {
    fn label(&self) -> String {
        self.preset.clone()
    }

    fn as_rig(&mut self) -> &mut dyn Rig {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::read_log;

    #[test]
    fn a_run_given_a_log_folder_writes_a_rig_log_that_calibrate_reads() {
        let scenario = Scenario::load("open-field").unwrap();
        let rig = SimulatedRig::new(
            DisturbancePreset::by_name("realistic").unwrap(),
            "realistic",
        );
        let dir = tempfile::tempdir().unwrap();
        let mut run = rig.open(&scenario, 3, Some(dir.path())).unwrap();
        let u = Control {
            theta: 0.3,
            alpha: 0.0,
            grad: [0.01, -0.02],
        };
        let r = run.as_rig();
        let mut seen = vec![];
        for _ in 0..5 {
            seen.push(r.observe().unwrap());
            r.command(&u).unwrap();
        }
        r.stop().unwrap();
        let log = read_log(dir.path(), scenario.agents()).unwrap();
        assert_eq!(log.frames.len(), 5);
        for (i, (f, o)) in log.frames.iter().zip(&seen).enumerate() {
            assert_eq!(f.frame, i as u64 + 1);
            assert!(
                (f.t - o.t).abs() < 1e-6,
                "frame {i}: {} against {}",
                f.t,
                o.t
            );
            for (a, b) in f.agents.iter().zip(&o.agents) {
                let (a, b) = (a.unwrap(), b.unwrap());
                assert!((a - b).norm() < 1e-4, "frame {i}: {a} against {b}");
            }
        }
        // each frame carries the command sent after it; the stop ends the last one's
        assert!(log.frames[..4].iter().all(|f| f.command == Some(u)));
        assert_eq!(log.frames[4].command, None);
    }
}
