//! The tick context: what one control tick knows once the frame is in.

use magbench_env::Vec2;
use magbench_env::plant::Observation;

use crate::rig::GroundTruth;

/// One control tick's view of the team, shared by the planner, the tracker, the contact
/// detector and the metrics recorder.
#[derive(Debug, Clone)]
pub struct TickContext {
    /// Rig time now (s): the observation's capture time plus the camera latency.
    pub now: f64,
    /// Rig time of the run's first tick (s).
    pub first: f64,
    /// The raw observation (capture-time positions; `None` = missed).
    pub observation: Observation,
    /// The estimate of the team now (latency compensated, misses filled).
    pub estimate: Vec<Vec2>,
    /// The true state, when the rig knows it.
    pub truth: Option<GroundTruth>,
}

impl TickContext {
    /// Rig time since the run's first tick (s).
    pub fn elapsed(&self) -> f64 {
        self.now - self.first
    }
}
