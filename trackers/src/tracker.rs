//! The tracker seam: one coil command per control tick.

use magbench_env::params::ParamSet;
use magbench_env::plant::Observation;
use magbench_env::{Control, Goal, PlanningModel, ValidityChecker, Vec2, World};

use crate::Reference;
use crate::closed_loop::LoopOptions;

/// What a tracker may use: the reference, the planning model, the leg's validity checker, the
/// control period and the run's seed.
#[derive(Debug, Clone, Copy)]
pub struct TrackerContext<'a> {
    /// The reference being followed.
    pub reference: &'a Reference,
    /// The planning model (nominal physics and coil).
    pub model: &'a PlanningModel,
    /// The current leg's world: its bounds (`[0, width] × [0, height]`) and obstacles.
    pub world: &'a World,
    /// Walls, obstacles and proximity range of the current leg.
    pub checker: &'a ValidityChecker,
    /// Seconds between control ticks (the camera frame).
    pub period: f64,
    /// The current leg's goal region.
    pub goal: &'a Goal,
    /// The run's seed: a randomized tracker draws from streams of it.
    pub seed: u64,
}

/// One control tick's input.
#[derive(Debug, Clone, Copy)]
pub struct Tick<'a> {
    /// Seconds since the reference started.
    pub t: f64,
    /// The estimated team state now (latency compensated, misses filled).
    pub estimate: &'a [Vec2],
    /// The raw observation the estimate came from.
    pub observation: &'a Observation,
}

/// What a tracker is doing, for logs and plots.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TrackerStatus {
    /// Mode name (`open-loop`, `follow`, `recover`, `pursue`, `hold`).
    pub mode: &'static str,
    /// Reference sample the tracker is at.
    pub progress: usize,
    /// Per-agent target positions of the last command, if the tracker has targets.
    pub targets: Option<Vec<Vec2>>,
}

/// A plan tracker: turns the estimated state into a coil command, once per tick. Its
/// parameters are declared once ([`magbench_env::declare_params!`]), which makes it a
/// [`ParamSet`].
pub trait Tracker: ParamSet + Send {
    /// The registry name.
    fn name(&self) -> &str;
    /// The loop's options with this tracker's defaults (the loop's parameters are set like the
    /// tracker's own).
    fn loop_options(&self) -> LoopOptions {
        LoopOptions::default()
    }
    /// Starts following a new reference (the first plan, a new leg or a replan).
    fn reset(&mut self, ctx: &TrackerContext);
    /// The command for this tick.
    fn command(&mut self, ctx: &TrackerContext, tick: &Tick) -> Control;
    /// What it is doing now.
    fn status(&self) -> TrackerStatus;
    /// True once the tracker has nothing left to do (open-loop at the plan's end).
    fn finished(&self) -> bool {
        false
    }
}
