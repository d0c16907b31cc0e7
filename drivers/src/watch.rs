//! A simulated rig watched for the moment its agents touch (env's plant sticks a pair in
//! contact for the rest of the run, so an excitation whose pair touched logs a stuck team) and
//! the moment an agent leaves the workspace (the plant's integration diverged).

use magbench_env::plant::Observation;
use magbench_env::{Control, World};
use magbench_trackers::{GroundTruth, Rig, RigError};

/// A rig, and the times (s, from its first observation) at which its agents first touched
/// and first left the workspace.
pub struct Watched<'a> {
    inner: &'a mut dyn Rig,
    world: (f64, f64),
    start: Option<f64>,
    /// When the agents first touched (s into the run), if they did.
    pub touched_at: Option<f64>,
    /// When an agent's true position first left `world` by more than 1 BL or stopped being
    /// finite (s into the run), if it did.
    pub left_at: Option<f64>,
}

impl<'a> Watched<'a> {
    /// Watches `inner` (a rig that knows its ground truth) in a workspace of `world` (width,
    /// height in BL).
    pub fn new(inner: &'a mut dyn Rig, world: (f64, f64)) -> Self {
        Self {
            inner,
            world,
            start: None,
            touched_at: None,
            left_at: None,
        }
    }
}

impl Rig for Watched<'_> {
    fn frame_period(&self) -> f64 {
        self.inner.frame_period()
    }

    fn observe(&mut self) -> Result<Observation, RigError> {
        let obs = self.inner.observe()?;
        let t = obs.t - *self.start.get_or_insert(obs.t);
        if let Some(g) = self.inner.ground_truth() {
            if g.agent_contact && self.touched_at.is_none() {
                self.touched_at = Some(t);
            }
            let (w, h) = self.world;
            let inside = |p: &magbench_env::Vec2| {
                p.x >= -1.0 && p.y >= -1.0 && p.x <= w + 1.0 && p.y <= h + 1.0
            };
            if !g.positions.iter().all(inside) && self.left_at.is_none() {
                self.left_at = Some(t);
            }
        }
        Ok(obs)
    }

    fn command(&mut self, u: &Control) -> Result<(), RigError> {
        self.inner.command(u)
    }

    fn stop(&mut self) -> Result<(), RigError> {
        self.inner.stop()
    }

    fn latency(&self) -> f64 {
        self.inner.latency()
    }

    fn set_world(&mut self, world: &World) -> Result<(), RigError> {
        self.inner.set_world(world)
    }

    fn ground_truth(&self) -> Option<GroundTruth> {
        self.inner.ground_truth()
    }
}
