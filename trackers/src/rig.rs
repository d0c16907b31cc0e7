//! The rig seam: what the tracking loop sees of the world.
//!
//! A [`Rig`] delivers observations at the camera rate, takes coil commands and stops (zero
//! field). The tracking loop ([`crate::track`]) drives any `&mut dyn Rig` and does not know
//! whether it is the simulated [`SimRig`](crate::SimRig) or a coil-and-camera rig.

use magbench_env::plant::Observation;
use magbench_env::{Control, Vec2, World};

/// A rig failure. A recoverable fault (a dropped frame, a retried message) lets the loop go
/// on; a fatal one (a lost connection, a stuck device) ends the run with the field stopped.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RigError {
    /// The rig can go on; the loop counts the fault and continues.
    #[error("recoverable rig fault: {0}")]
    Recoverable(String),
    /// The rig cannot go on; the loop stops it and ends the run.
    #[error("fatal rig fault: {0}")]
    Fatal(String),
}

impl RigError {
    /// True for a fault the loop may continue after.
    pub fn is_recoverable(&self) -> bool {
        matches!(self, RigError::Recoverable(_))
    }
}

/// What only a simulated rig knows: the true state, for honest metrics.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundTruth {
    /// True agent positions now (BL).
    pub positions: Vec<Vec2>,
    /// Wall contact events so far.
    pub wall_contacts: usize,
    /// True once two agents have touched and stuck.
    pub agent_contact: bool,
}

/// A coil-and-camera rig, simulated or physical.
///
/// One control tick is: [`Rig::observe`] (blocks until the next frame's observation), then
/// [`Rig::command`]. The command holds until the next command or [`Rig::stop`].
pub trait Rig {
    /// Seconds between observations (the camera frame period, 1/60 s by default).
    fn frame_period(&self) -> f64;
    /// Blocks until the next frame's observation: capture time and per-agent position
    /// (`None` = missed detection).
    fn observe(&mut self) -> Result<Observation, RigError>;
    /// Sends a coil command; the rig clamps it to its limits.
    fn command(&mut self, u: &Control) -> Result<(), RigError>;
    /// Zeroes the field. Idempotent; the loop calls it on every exit path.
    fn stop(&mut self) -> Result<(), RigError>;

    /// Seconds from a frame's capture to the delivery of its observation (the camera
    /// pipeline's latency). The loop predicts the state over it with the planning model.
    fn latency(&self) -> f64 {
        0.0
    }

    /// The obstacles changed (a leg's map switch). A simulated rig switches its collision
    /// world; a physical rig whose obstacles are virtual has nothing to do.
    fn set_world(&mut self, _world: &World) -> Result<(), RigError> {
        Ok(())
    }

    /// The true state, if the rig knows it (a simulated rig does, a physical one does not).
    fn ground_truth(&self) -> Option<GroundTruth> {
        None
    }
}
