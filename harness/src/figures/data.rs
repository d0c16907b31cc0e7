//! The runs behind the paper figures: plan the first leg with a registered planner from a fixed
//! seed through the run pipeline, then track the plan in closed loop against the simulated
//! plant, keeping every tick.

use magbench_env::{Scenario, Vec2};
use magbench_planners::{Limits, PlannerResult, PlanningSetup};
use magbench_trackers::{Reference, track};

use crate::error::Error;
use crate::pipeline::Pipeline;
use crate::registry::Registry;

/// A planned and tracked run of a scenario's first leg.
pub struct TrackedRun {
    /// The scenario.
    pub scenario: Scenario,
    /// The planner's result.
    pub planned: PlannerResult,
    /// Planned states at every integration step, with their times (s).
    pub plan_samples: Vec<(f64, Vec<Vec2>)>,
    /// Tracked (true) positions at every control tick, with their times (s).
    pub tracked: Vec<(f64, Vec<Vec2>)>,
    /// Label of the run: planner, tracker, preset, seed.
    pub label: String,
    /// The tracked run reached the goal.
    pub reached_goal: bool,
    /// RMS tracking error (BL).
    pub rms_error: f64,
}

/// What a figure runs: one planned and tracked run.
pub struct FigureRun<'a> {
    /// Scenario name or path.
    pub scenario: &'a str,
    /// Planner name and `key=value` parameters.
    pub planner: (&'a str, &'a [(&'a str, &'a str)]),
    /// Iteration limit.
    pub iterations: u64,
    /// Tracker name.
    pub tracker: &'a str,
    /// Disturbance preset.
    pub preset: &'a str,
    /// Seed of the planner, plant and camera.
    pub seed: u64,
}

/// Plans (the pipeline's first leg: start rule, post-processing, validator) and tracks, with the
/// planner, tracker and `simulated` rig of `registry`.
pub fn plan_and_track(s: &FigureRun, registry: &Registry) -> Result<TrackedRun, Error> {
    let scenario = Scenario::load(s.scenario)?;
    let params = magbench_env::params::owned(s.planner.1);
    let mut planner = registry.planners().create(s.planner.0, &params)?;
    let rig = registry.rigs().load("simulated", s.preset, "preset")?;
    let period = rig.frame_period();
    let setup = PlanningSetup {
        limits: Limits {
            max_iterations: Some(s.iterations),
            time_limit: None,
        },
        ..PlanningSetup::default()
    }
    .in_frames_of(period);
    let pipeline = Pipeline::new(&scenario, setup, s.seed);
    let failed = |e: String| Error::Failed(format!("{} seed {}: {e}", s.planner.0, s.seed));
    let leg = pipeline
        .plan_leg(planner.as_mut(), 0, None)
        .map_err(|e| failed(e.to_string()))?;
    let planned = leg.validated.result.clone();
    let first = leg
        .validated
        .followable()
        .map_err(|e| failed(e.to_string()))?;
    let reference = Reference::from_plan(&planned.plan, &leg.problem.model);
    let plan_samples = (0..reference.len())
        .map(|k| (reference.time(k), reference.state(k).to_vec()))
        .collect();
    let spec = registry.trackers().spec(s.tracker, &[], "<figures>")?;
    let mission = pipeline.mission(first, Some(planner.as_mut()));
    let mut tracker = spec.build();
    let mut opts = spec.loop_options();
    opts.record_ticks = true;
    let mut sim = rig.open(&scenario, s.seed, None)?;
    let out = track(sim.as_rig(), tracker.as_mut(), mission, &opts);
    let n = scenario.agents();
    let tracked = out
        .ticks
        .iter()
        .map(|t| (t.t, (0..n).map(|i| t.position(i)).collect()))
        .collect();
    let label = format!(
        "{} seed {}, {} ({}), {}",
        s.planner.0,
        s.seed,
        s.tracker,
        s.preset,
        if planned.solved {
            "solved"
        } else {
            "approximate plan"
        }
    );
    Ok(TrackedRun {
        reached_goal: out.metrics.reached_goal,
        rms_error: out.metrics.rms_error_bl,
        scenario,
        planned,
        plan_samples,
        tracked,
        label,
    })
}

impl TrackedRun {
    /// Planned path of agent `i`.
    pub fn planned_path(&self, i: usize) -> Vec<Vec2> {
        self.plan_samples.iter().map(|(_, s)| s[i]).collect()
    }

    /// Tracked path of agent `i`.
    pub fn tracked_path(&self, i: usize) -> Vec<Vec2> {
        self.tracked.iter().map(|(_, s)| s[i]).collect()
    }
}
