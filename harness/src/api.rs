//! Library entry points for programs that drive magbench without its command line (the Python
//! package): plan one leg of a scenario, and track a plan in closed loop against the simulated
//! plant, through the same [`Pipeline`] as `magbench plan`, `magbench track` and sweeps.

use magbench_env::Scenario;
use magbench_env::plant::DisturbancePreset;
use magbench_planners::{ElevationRefused, FirstPlan, Plan, Planner, PlanningSetup};
use magbench_trackers::{LoopOptions, TrackOutcome, Tracker, simulate};

use crate::Error;
use crate::pipeline::start::check_given_plan;
use crate::pipeline::{Failure, LegPlan, Pipeline};

/// Plans leg `leg` of `scenario` from `start` (the scenario's start if `None`) with `planner`
/// under `setup`, through the run's [`Pipeline`]: seeded by the seed rule (leg `leg` of a run
/// of seed `seed`, as a sweep plans it), post-processed by the planner the registry made. A
/// start that is invalid in the leg's map is bad input; a plan the validator refuses is a
/// failure naming the planner (a plan without motion is returned, not solved). The leg carries
/// the result and, when the planner stopped unsolved and said why, its reason.
pub fn plan_leg(
    scenario: &Scenario,
    leg: usize,
    start: Option<&[magbench_env::Vec2]>,
    planner: &mut dyn Planner,
    setup: &PlanningSetup,
    seed: u64,
) -> Result<LegPlan, Error> {
    if leg >= scenario.legs.len() {
        return Err(Error::arg(
            "leg",
            format!(
                "scenario {} has {} leg(s)",
                scenario.name,
                scenario.legs.len()
            ),
        ));
    }
    setup
        .check_settings(scenario, &planner.params())
        .map_err(|e| match e {
            ElevationRefused::Planar(r) => Error::arg("param.planar", r.to_string()),
            ElevationRefused::AlphaMax(r) => Error::arg("param.alpha_max", r.to_string()),
            ElevationRefused::SetupAlphaMax(r) => Error::arg("alpha_max", r.to_string()),
        })?;
    let pipe = Pipeline::new(scenario, setup.clone(), seed);
    match pipe.plan_leg(planner, leg, start) {
        Ok(planned) => Ok(planned),
        Err(Failure::InvalidStart { leg }) => Err(Error::arg(
            "start",
            format!(
                "the start is invalid in leg {} of {}",
                leg + 1,
                scenario.name
            ),
        )),
        Err(Failure::InvalidPlan { error, .. }) => Err(Error::Failed(format!(
            "{} returned an invalid plan: {error}",
            planner.name()
        ))),
    }
}

/// One closed-loop run of a given plan against the simulated plant.
pub struct TrackRequest<'a> {
    /// The scenario.
    pub scenario: &'a Scenario,
    /// The plan of the first leg.
    pub plan: Plan,
    /// Where the plan came from, for error messages (a file name or `<plan>`).
    pub plan_source: &'a str,
    /// The tracker, configured.
    pub tracker: Box<dyn Tracker>,
    /// The loop's options (the tracker's defaults with its parameters set).
    pub options: LoopOptions,
    /// A disturbance preset: `ideal`, `realistic`, `hardware` or a preset file.
    pub preset: &'a str,
    /// Seed of the simulated disturbances (and of replans).
    pub seed: u64,
    /// The planner of new legs and replans; without one the loop does not replan.
    pub planner: Option<Box<dyn Planner>>,
    /// The planning setup of replans; its control period becomes the preset camera's.
    pub setup: PlanningSetup,
}

/// Tracks `r.plan` on a simulated rig of `r.scenario` under `r.preset`, recording every tick.
/// The plan is checked first as `magbench track --plan` checks a plan file, by the start rule
/// ([`check_given_plan`]: its origin, then its fit under the preset's frames, medium and coil);
/// a plan that does not fit is an [`magbench_env::InputError`] naming `r.plan_source`.
pub fn track_plan(r: TrackRequest) -> Result<TrackOutcome, Error> {
    let preset = DisturbancePreset::resolve(r.preset).map_err(|e| {
        if e.file == r.preset {
            Error::arg("preset", e.to_string())
        } else {
            Error::Input(e)
        }
    })?;
    let setup = r
        .setup
        .in_frames_of(1.0 / preset.camera.fps)
        .on_plant(&preset.medium, preset.coil.alpha_max_deg);
    check_given_plan(&r.plan, r.scenario, r.plan_source, &setup)?;
    let mut planner = r.planner;
    let solved = r.scenario.legs[0].goal.contains(r.plan.end());
    let pipe = Pipeline::new(r.scenario, setup, r.seed);
    let mission = pipe.mission(
        FirstPlan::given(r.plan, solved),
        planner.as_deref_mut().map(|p| p as &mut dyn Planner),
    );
    let mut tracker = r.tracker;
    let mut opts = r.options;
    opts.record_ticks = true;
    Ok(simulate(mission, tracker.as_mut(), &preset, &opts))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Registry;

    fn planner() -> Box<dyn Planner> {
        Registry::builtin()
            .planners()
            .create("goal-zoom-rrt", &[])
            .expect("a built-in")
    }

    fn request<'a>(s: &'a Scenario, plan: Plan) -> TrackRequest<'a> {
        let (tracker, options) = Registry::builtin()
            .trackers()
            .build("obc", &[], "test")
            .expect("a built-in");
        TrackRequest {
            scenario: s,
            plan,
            plan_source: "<plan>",
            tracker,
            options,
            preset: "ideal",
            seed: 0,
            planner: None,
            setup: PlanningSetup::default(),
        }
    }

    #[test]
    fn a_leg_out_of_range_is_bad_input() {
        let s = Scenario::load("open-field").unwrap();
        let e = plan_leg(
            &s,
            5,
            None,
            planner().as_mut(),
            &PlanningSetup::default(),
            0,
        )
        .unwrap_err();
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().contains("leg"), "{e}");
    }

    #[test]
    fn a_plan_for_another_scenario_is_refused_before_tracking() {
        let s = Scenario::load("open-field").unwrap();
        let other = Scenario::load("micro-factory").unwrap();
        let mut setup = PlanningSetup::default();
        setup.limits.max_iterations = Some(3000);
        let r = plan_leg(&other, 0, None, planner().as_mut(), &setup, 0)
            .unwrap()
            .validated
            .result;
        let e = track_plan(request(&s, r.plan)).map(|_| ()).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        // within the goal tolerance of the start (0.5 BL), and refused by its fit: it leaves the
        // world
        assert!(e.to_string().contains("<plan>: states["), "{e}");
        let trio = Scenario::load("trio-row").unwrap();
        let e = track_plan(request(&trio, Plan::at(&s.start)))
            .map(|_| ())
            .unwrap_err();
        assert!(e.to_string().contains("the plan moves 2 agents"), "{e}");
    }

    #[test]
    fn a_plan_of_the_scenario_is_tracked_with_every_tick_recorded() {
        let s = Scenario::load("open-field").unwrap();
        let mut setup = PlanningSetup::default().in_frames_of(1.0 / 60.0);
        setup.limits.max_iterations = Some(3000);
        let r = plan_leg(&s, 0, None, planner().as_mut(), &setup, 0)
            .unwrap()
            .validated
            .result;
        assert!(r.solved);
        let out = track_plan(request(&s, r.plan)).unwrap();
        assert!(!out.ticks.is_empty());
    }
}
