//! The rigs a run can use, by name: a table of rig kinds, each loaded from one argument (a
//! preset, a rig file) into a [`RigDescription`] that planning reads and a run opens.
//!
//! [`Rigs::builtin`] holds `simulated` (env's plant and camera under a disturbance preset) and
//! `coil` (a coil-and-camera rig, or its emulator, described by a rig file); [`Rigs::add`] and
//! [`Rigs::add_kind`] take more at run time (a plugin's). A rig is its own type implementing
//! [`RigKind`] and one entry in the table; the command line and the runner do not change.

mod coil;
mod forward;
mod simulated;
mod table;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use magbench_env::plant::{DisturbancePreset, Medium};
use magbench_env::{InputError, Scenario, Vec2};
use magbench_trackers::Rig;

use crate::hardware::{HardwareError, RigStats};

pub use self::coil::CoilRig;
pub use self::simulated::SimulatedRig;
pub use self::table::{LoadRig, Rigs};

/// The plant a rig drives, as far as planning needs it: the medium when the scenario names none
/// and the coil's elevation range.
#[derive(Debug, Clone, PartialEq)]
pub struct RigPlant {
    /// The medium; a rig file does not describe the liquid, so bulk (a scenario's `[medium]`
    /// says otherwise).
    pub medium: Medium,
    /// The coil's elevation range (degrees): a preset's `coil.alpha_max_deg` or a rig file's.
    pub coil_alpha_max_deg: f64,
    /// Where the range comes from, for messages: the preset file or name, or the rig file.
    pub coil_source: String,
}

/// A rig as its description (a preset, a rig file) gives it, not yet opened: what planning
/// needs of it, and a way to open it for one run.
pub trait RigDescription: Send + Sync {
    /// Seconds between the rig's frames: the control period of every plan it runs (a plan must
    /// be in whole frames of its rig).
    fn frame_period(&self) -> f64;

    /// What planning needs of the rig's plant.
    fn plant(&self) -> RigPlant;

    /// Opens the rig for a run of `scenario` with `seed`; a rig that logs writes its log into
    /// `log_dir`. A rig that does not answer is `Err(Failed)`.
    fn open(
        &self,
        scenario: &Scenario,
        seed: u64,
        log_dir: Option<&Path>,
    ) -> Result<Box<dyn RunRig>, OpenError>;
}

/// A kind of rig a registry names: a [`RigDescription`] loaded from one argument.
pub trait RigKind: RigDescription + Sized + 'static {
    /// The rig described by `arg` (a preset, a rig file, whatever the kind reads). Bad input
    /// is an [`OpenError::Input`]; `option` names where `arg` came from (`--rig`, `--preset`).
    fn load(arg: &str, option: &str) -> Result<Self, OpenError>;
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
    fn observe_start(&mut self, _scenario: &Scenario) -> Result<Option<Vec<Vec2>>, StartError> {
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

/// Why a rig did not load or open.
#[derive(Debug, thiserror::Error)]
pub enum OpenError {
    /// Bad input: the rig's name, its preset or its rig file.
    #[error("{0}")]
    Input(#[from] InputError),
    /// The coil link or camera did not answer.
    #[error(transparent)]
    Hardware(#[from] HardwareError),
    /// The rig did not answer (a rig kind's own message).
    #[error("{0}")]
    Failed(String),
}

/// Why a rig cannot tell where the team starts.
#[derive(Debug, thiserror::Error)]
pub enum StartError {
    /// The coil link or camera failed.
    #[error(transparent)]
    Hardware(#[from] HardwareError),
    /// The detector did not find every agent in enough of the first frames.
    #[error(
        "the detector found every agent in only {found} of {frames} frames at the start; check the rig's [detector] and [pixels] calibration (magbench rig redetect helps)"
    )]
    Undetected {
        /// Frames in which every agent was found.
        found: usize,
        /// Frames looked at.
        frames: usize,
    },
    /// The observed start is not a valid state of the scenario.
    #[error(
        "the observed start is in collision or outside the proximity range; place the agents at the scenario's start"
    )]
    InvalidStart,
}
