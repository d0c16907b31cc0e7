//! The rig factory: every rig a run can use, opened from one description.
//!
//! The command line says *which* rig ([`RigSource`]: a simulated one under a disturbance
//! preset, or a rig file); [`open`] opens it as a [`RunRig`], the tracking loop's [`Rig`] plus
//! what a plan-track run needs around it (its label, its start, its counters). A new rig is its
//! own file implementing [`RunRig`] and one arm in [`open`]; the command line does not change.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use magbench_env::plant::{DisturbancePreset, Medium};
use magbench_env::{InputError, Scenario, Vec2};
use magbench_trackers::{Rig, SimRig};

use crate::hardware::{HardwareRig, RigStats};
use crate::interrupt;
use crate::rigfile::RigConfig;

/// Which rig a run uses.
#[derive(Debug, Clone, PartialEq)]
pub enum RigSource {
    /// env's simulated plant and camera under a disturbance preset.
    Simulated {
        /// A built-in preset's name (`ideal`, `realistic`, `hardware`) or a preset file.
        preset: String,
    },
    /// The coil-and-camera rig described by a rig file.
    File(PathBuf),
}

impl RigSource {
    /// Seconds between the rig's frames, read without opening it: the control period of every
    /// plan it runs (a plan must be in whole frames of its rig). Bad input (an unknown preset,
    /// a bad rig file) names `option`.
    pub fn frame_period(&self, option: &str) -> Result<f64, OpenError> {
        Ok(match self {
            RigSource::Simulated { preset } => 1.0 / preset_named(preset, option)?.camera.fps,
            RigSource::File(path) => 1.0 / RigConfig::load(path)?.camera.fps,
        })
    }
}

/// The plant a rig drives, as far as planning needs it: the medium when the scenario names none
/// and the coil's elevation range.
#[derive(Debug, Clone, PartialEq)]
pub struct RigPlant {
    /// The preset's medium; a rig file does not describe the liquid, so bulk (a scenario's
    /// `[medium]` says otherwise).
    pub medium: Medium,
    /// The coil's elevation range (degrees): the preset's `coil.alpha_max_deg` or the rig
    /// file's.
    pub coil_alpha_max_deg: f64,
    /// Where the range comes from, for messages: the preset file or name, or the rig file.
    pub coil_source: String,
}

impl RigSource {
    /// What planning needs of the rig's plant, read without opening it. Bad input names
    /// `option`.
    pub fn plant(&self, option: &str) -> Result<RigPlant, OpenError> {
        Ok(match self {
            RigSource::Simulated { preset } => {
                let p = preset_named(preset, option)?;
                RigPlant {
                    medium: p.medium,
                    coil_alpha_max_deg: p.coil.alpha_max_deg,
                    coil_source: format!("{preset}: coil.alpha_max_deg"),
                }
            }
            RigSource::File(path) => RigPlant {
                medium: Medium::Bulk,
                coil_alpha_max_deg: RigConfig::load(path)?.coil.alpha_max_deg,
                coil_source: format!("{}: coil.alpha_max_deg", path.display()),
            },
        })
    }
}

/// The disturbance preset `name_or_file`: a built-in name, or a preset file (validated: a bad
/// file is an [`InputError`] naming the file, the field and its line). A name that is neither
/// is an [`InputError`] naming `option`.
pub fn preset_named(name_or_file: &str, option: &str) -> Result<DisturbancePreset, InputError> {
    if DisturbancePreset::by_name(name_or_file).is_none() && !Path::new(name_or_file).exists() {
        return Err(InputError::new(
            "<command line>",
            option,
            format!(
                "unknown preset `{name_or_file}`: neither a built-in preset ({}) nor a file",
                DisturbancePreset::NAMES.join(", ")
            ),
        ));
    }
    DisturbancePreset::resolve(name_or_file)
}

/// A rig opened for one run: the loop's [`Rig`] and what the runner needs around it.
pub trait RunRig: Rig {
    /// What the results call the rig: the preset's name, or `rig:NAME`.
    fn label(&self) -> String;

    /// The rig as the tracking loop drives it.
    fn as_rig(&mut self) -> &mut dyn Rig;

    /// One line on the coil link and camera, for the operator; `None` for a simulation.
    fn describe(&self) -> Option<String> {
        None
    }

    /// Where the team starts: `None` for the scenario's start (a simulation puts it there),
    /// else the start the rig observes. `Err` when it cannot tell (the field is zero).
    fn observe_start(&mut self, _scenario: &Scenario) -> Result<Option<Vec<Vec2>>, String> {
        Ok(None)
    }

    /// Raised to end a run early (Ctrl-C on a physical rig).
    fn cancel_flag(&self) -> Option<Arc<AtomicBool>> {
        None
    }

    /// The rig's counters (frames, commands, latency), if it keeps them.
    fn stats(&self) -> Option<RigStats> {
        None
    }

    /// The rig's own event log, if it writes one.
    fn log_path(&self) -> Option<PathBuf> {
        None
    }
}

/// Opens `source` for a run of `scenario` with `seed`; a physical rig writes its event log into
/// `log_dir` (`rig-log.csv`). Bad input (an unknown preset, a bad rig file) is an
/// [`InputError`] with `option` as the field; a rig that does not answer is `Err(Failed)`.
pub fn open(
    source: &RigSource,
    option: &str,
    scenario: &Scenario,
    seed: u64,
    log_dir: Option<&Path>,
) -> Result<Box<dyn RunRig>, OpenError> {
    match source {
        RigSource::Simulated { preset } => {
            let p = preset_named(preset, option)?;
            Ok(Box::new(SimulatedRig {
                rig: SimRig::new(scenario, &p, seed),
                preset: p.name.clone(),
            }))
        }
        RigSource::File(path) => {
            let cfg = RigConfig::load(path)?;
            let log = log_dir.map(|d| d.join("rig-log.csv"));
            Ok(Box::new(
                PhysicalRig::open(&cfg, scenario, log).map_err(OpenError::Failed)?,
            ))
        }
    }
}

/// Why a rig did not open.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// Bad input: the preset or the rig file.
    #[error("{0}")]
    Input(#[from] InputError),
    /// The rig did not answer (no link, no camera).
    #[error("{0}")]
    Failed(String),
}

/// The simulated rig of a disturbance preset.
struct SimulatedRig {
    rig: SimRig,
    preset: String,
}

/// Forwards the [`Rig`] methods to a field.
macro_rules! forward_rig {
    ($t:ty, $f:ident) => {
        impl Rig for $t {
            fn frame_period(&self) -> f64 {
                Rig::frame_period(&self.$f)
            }
            fn observe(
                &mut self,
            ) -> Result<magbench_env::plant::Observation, magbench_trackers::RigError> {
                Rig::observe(&mut self.$f)
            }
            fn command(
                &mut self,
                u: &magbench_env::Control,
            ) -> Result<(), magbench_trackers::RigError> {
                Rig::command(&mut self.$f, u)
            }
            fn stop(&mut self) -> Result<(), magbench_trackers::RigError> {
                Rig::stop(&mut self.$f)
            }
            fn latency(&self) -> f64 {
                Rig::latency(&self.$f)
            }
            fn set_world(
                &mut self,
                w: &magbench_env::World,
            ) -> Result<(), magbench_trackers::RigError> {
                Rig::set_world(&mut self.$f, w)
            }
            fn ground_truth(&self) -> Option<magbench_trackers::GroundTruth> {
                Rig::ground_truth(&self.$f)
            }
        }
    };
}

forward_rig!(SimulatedRig, rig);

impl RunRig for SimulatedRig {
    fn label(&self) -> String {
        self.preset.clone()
    }

    fn as_rig(&mut self) -> &mut dyn Rig {
        self
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
    fn open(cfg: &RigConfig, scenario: &Scenario, log: Option<PathBuf>) -> Result<Self, String> {
        let field = cfg.coil.field_mt.unwrap_or(scenario.physics.field_mt);
        let abort = interrupt::interrupt_flag();
        let rig = HardwareRig::open(cfg, field, &scenario.start, abort.clone(), log.as_deref())
            .map_err(|e| e.to_string())?;
        Ok(Self {
            rig,
            name: cfg.name.clone(),
            log,
            abort,
        })
    }

    /// The mean of the first frames in which every agent is found.
    fn mean_start(&mut self, agents: usize) -> Result<Vec<Vec2>, String> {
        let mut sum = vec![Vec2::zeros(); agents];
        let (mut n, mut frames) = (0, 0);
        while n < START_FRAMES {
            let o = self.rig.observe().map_err(|e| e.to_string())?;
            frames += 1;
            if frames > START_FRAME_LIMIT {
                return Err(format!(
                    "the detector found every agent in only {n} of {frames} frames at the start; check the rig's [detector] and [pixels] calibration (magbench rig replay helps)"
                ));
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

    fn observe_start(&mut self, scenario: &Scenario) -> Result<Option<Vec<Vec2>>, String> {
        let start = self.mean_start(scenario.agents())?;
        if !scenario.checker_for_leg(0).is_valid(&start) {
            return Err(
                "the observed start is in collision or outside the proximity range; place the agents at the scenario's start".into(),
            );
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
