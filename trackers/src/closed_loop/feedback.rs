//! Visual feedback: the camera's frame, through the estimator, into a [`TickContext`].
//!
//! This is the observation seam of the loop: whatever a rig's camera delivers (a simulated
//! frame, a detector's output, nothing at all this tick) becomes one tick's context here.

use magbench_env::plant::Observation;
use magbench_env::{Control, PlanningModel, Vec2};

use super::recorder::Recorder;
use super::tick::TickContext;
use crate::estimator::Estimator;
use crate::rig::{Rig, RigError};

/// Why the loop cannot go on after an observation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SenseError {
    /// The rig observed another number of agents than the scenario has.
    #[error("the rig reported {got} agents, the scenario has {expected}")]
    AgentCount {
        /// Agents in the observation.
        got: usize,
        /// Agents in the scenario.
        expected: usize,
    },
    /// A fatal rig fault.
    #[error(transparent)]
    Rig(#[from] RigError),
}

/// The loop's eyes: the estimator and the rig clock as the observations tell it.
#[derive(Debug, Clone)]
pub struct Feedback {
    estimator: Estimator,
    agents: usize,
    period: f64,
    latency: f64,
    now: f64,
    first: Option<f64>,
}

impl Feedback {
    /// Feedback from a rig with frame `period` and camera `latency` (s), for a team starting
    /// at `start`, predicting with `model`.
    pub fn new(
        model: &PlanningModel,
        period: f64,
        latency: f64,
        obs_weight: f64,
        start: &[Vec2],
    ) -> Self {
        Self {
            estimator: Estimator::new(model.clone(), latency, obs_weight, start),
            agents: start.len(),
            period,
            latency,
            now: 0.0,
            first: None,
        }
    }

    /// Seconds between ticks (the rig's frame period).
    pub fn period(&self) -> f64 {
        self.period
    }

    /// Rig time of the latest tick (s).
    pub fn now(&self) -> f64 {
        self.now
    }

    /// Rig time from the first tick to the latest (s); 0 before any tick.
    pub fn duration(&self) -> f64 {
        self.first.map_or(0.0, |t0| self.now - t0)
    }

    /// Waits for the rig's next observation and folds it into the estimate. A recoverable
    /// fault is a frame with every agent missed (the model predicts); `Err` is a fatal fault.
    pub fn sense(
        &mut self,
        rig: &mut dyn Rig,
        rec: &mut Recorder,
    ) -> Result<TickContext, SenseError> {
        let observation = match rig.observe() {
            Ok(o) if o.agents.len() == self.agents => o,
            Ok(o) => {
                return Err(SenseError::AgentCount {
                    got: o.agents.len(),
                    expected: self.agents,
                });
            }
            Err(RigError::Recoverable(_)) => {
                rec.rig_fault();
                Observation {
                    t: self.now + self.period - self.latency,
                    agents: vec![None; self.agents],
                }
            }
            Err(e) => return Err(e.into()),
        };
        rec.observation(&observation);
        let (now, estimate) = self.estimator.update(&observation);
        if self.first.is_some() {
            rec.tick_gap(now - self.now, self.period);
        }
        self.now = now;
        let first = *self.first.get_or_insert(now);
        Ok(TickContext {
            now,
            first,
            observation,
            estimate,
            truth: rig.ground_truth(),
        })
    }

    /// The command sent at this tick, for the estimator's prediction.
    pub fn command_sent(&mut self, u: &Control) {
        self.estimator.command_sent(self.now, u);
    }
}
