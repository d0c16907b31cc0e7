//! The `coil` rig: a coil-and-camera rig (or the emulator standing in for one) described by a
//! rig file.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use magbench_env::plant::Medium;
use magbench_env::{Scenario, Vec2};
use magbench_trackers::Rig;

use super::forward::forward_rig;
use super::{OpenError, RigDescription, RigKind, RigPlant, RunRig, StartError};
use crate::hardware::{HardwareError, HardwareRig, RigStats};
use crate::interrupt;
use crate::rigfile::RigConfig;

/// A coil-and-camera rig as its rig file describes it.
#[derive(Debug, Clone)]
pub struct CoilRig {
    config: RigConfig,
    file: String,
}

impl CoilRig {
    /// The rig of `config`, read from `file` (named in messages).
    pub fn new(config: RigConfig, file: &str) -> Self {
        CoilRig {
            config,
            file: file.to_string(),
        }
    }
}

impl RigKind for CoilRig {
    fn load(arg: &str, _option: &str) -> Result<Self, OpenError> {
        Ok(CoilRig::new(RigConfig::load(Path::new(arg))?, arg))
    }
}

impl RigDescription for CoilRig {
    fn frame_period(&self) -> f64 {
        1.0 / self.config.camera.fps
    }

    fn plant(&self) -> RigPlant {
        RigPlant {
            medium: Medium::Bulk,
            coil_alpha_max_deg: self.config.coil.alpha_max_deg,
            coil_source: format!("{}: coil.alpha_max_deg", self.file),
        }
    }

    fn open(
        &self,
        scenario: &Scenario,
        _seed: u64,
        log_dir: Option<&Path>,
    ) -> Result<Box<dyn RunRig>, OpenError> {
        let log = log_dir.map(|d| d.join("rig-log.csv"));
        Ok(Box::new(PhysicalRig::open(&self.config, scenario, log)?))
    }
}

/// A coil-and-camera rig (or the emulator standing in for one).
struct PhysicalRig {
    rig: HardwareRig,
    name: String,
    log: Option<PathBuf>,
    abort: Arc<AtomicBool>,
}

/// Frames in which every agent is found that make up the observed start.
const START_FRAMES: usize = 10;

/// Frames the detector may take to find every agent [`START_FRAMES`] times.
const START_FRAME_LIMIT: usize = 120;

impl PhysicalRig {
    fn open(
        cfg: &RigConfig,
        scenario: &Scenario,
        log: Option<PathBuf>,
    ) -> Result<Self, HardwareError> {
        let field = cfg.coil.field_mt.unwrap_or(scenario.physics.field_mt);
        let abort = interrupt::interrupt_flag()?;
        let rig = HardwareRig::open(cfg, field, &scenario.start, abort.clone(), log.as_deref())?;
        Ok(Self {
            rig,
            name: cfg.name.clone(),
            log,
            abort,
        })
    }

    /// The mean of the first frames in which every agent is found.
    fn mean_start(&mut self, agents: usize) -> Result<Vec<Vec2>, StartError> {
        let mut sum = vec![Vec2::zeros(); agents];
        let (mut n, mut frames) = (0, 0);
        while n < START_FRAMES {
            let o = self.rig.observe()?;
            frames += 1;
            if frames > START_FRAME_LIMIT {
                return Err(StartError::Undetected { found: n, frames });
            }
            if o.agents.iter().all(|a| a.is_some()) {
                for (s, a) in sum.iter_mut().zip(&o.agents) {
                    *s += a.expect("checked");
                }
                n += 1;
            }
        }
        Ok(sum.into_iter().map(|s| s / n as f64).collect())
    }
}

forward_rig!(PhysicalRig, rig);

impl RunRig for PhysicalRig {
    fn label(&self) -> String {
        format!("rig:{}", self.name)
    }

    fn as_rig(&mut self) -> &mut dyn Rig {
        self
    }

    fn describe(&self) -> Option<String> {
        Some(self.rig.describe())
    }

    fn observe_start(&mut self, scenario: &Scenario) -> Result<Option<Vec<Vec2>>, StartError> {
        let start = self.mean_start(scenario.agents())?;
        if !scenario.checker_for_leg(0).is_valid(&start) {
            return Err(StartError::InvalidStart);
        }
        Ok(Some(start))
    }

    fn cancel_flag(&self) -> Option<Arc<AtomicBool>> {
        Some(self.abort.clone())
    }

    fn stats(&self) -> Option<RigStats> {
        Some(self.rig.stats().clone())
    }

    fn log_path(&self) -> Option<PathBuf> {
        self.log.clone()
    }
}
