//! Repair replans in the loop: micro-factory under the hardware preset, with a low replan
//! threshold so that drift calls for replans; every adopted plan passes the validator, repair
//! finds most plans without the planner, and a run is reproducible per seed.

use magbench_env::Scenario;
use magbench_env::plant::DisturbancePreset;
use magbench_planners::{Planner, Planners, PlanningSetup, solve_validated, validate_plan};
use magbench_trackers::{Mission, PlanReason, ReplanHow, TrackOutcome, Trackers, simulate};

/// A run of lookahead on micro-factory (hardware preset, seed `seed`), replanning when the
/// error stays above 0.1 BL for 0.5 s, with `replan_mode = mode`.
fn run(seed: u64, mode: &str) -> (Scenario, PlanningSetup, TrackOutcome) {
    let s = Scenario::load("micro-factory").unwrap();
    let preset = DisturbancePreset::hardware();
    let setup = PlanningSetup::default()
        .in_frames_of(1.0 / preset.camera.fps)
        .on_plant(&preset.medium, preset.coil.alpha_max_deg);
    let mut planner = Planners::builtin().create("goal-zoom-rrt", &[]).unwrap();
    let first = solve_validated(planner.as_mut(), &setup.problem(&s, 0, None, seed))
        .followable()
        .unwrap();
    let spec = Trackers::builtin()
        .spec(
            "lookahead",
            &[
                ("replan_error".into(), "0.1".into()),
                ("replan_after".into(), "0.5".into()),
                ("max_replans".into(), "100".into()),
                ("replan_mode".into(), mode.into()),
            ],
            "test",
        )
        .unwrap();
    let mut opts = spec.loop_options();
    opts.record_ticks = false;
    let mission = Mission {
        scenario: &s,
        first,
        planner: Some(planner.as_mut() as &mut dyn Planner),
        setup: setup.clone(),
        seed,
    };
    let out = simulate(mission, spec.build().as_mut(), &preset, &opts);
    (s, setup, out)
}

/// Every plan after the first passes the validator from where it starts.
fn assert_valid(s: &Scenario, setup: &PlanningSetup, out: &TrackOutcome) {
    for (k, p) in out.plans.iter().enumerate().skip(1) {
        let problem = setup.problem(s, p.leg, Some(p.plan.start()), 0);
        assert_eq!(validate_plan(&problem, &p.plan), Ok(()), "plan {k}");
    }
}

#[test]
fn repaired_replans_are_valid_and_mostly_need_no_planner() {
    let mut repaired = 0;
    let mut replans = 0;
    for seed in [1, 2] {
        let (s, setup, out) = run(seed, "repair");
        assert_valid(&s, &setup, &out);
        let drift: Vec<_> = out
            .replans
            .iter()
            .filter(|r| r.reason == PlanReason::Error)
            .collect();
        replans += drift.len();
        for r in &drift {
            match r.how {
                ReplanHow::Rejoin | ReplanHow::Tree => {
                    assert_eq!(r.planner_iterations, 0);
                    assert!(r.rejoins >= 1);
                    repaired += 1;
                }
                ReplanHow::Full => assert!(r.planner_iterations > 0),
                ReplanHow::Failed => {}
            }
        }
        let adopted = out
            .replans
            .iter()
            .filter(|r| r.how != ReplanHow::Failed)
            .count();
        assert_eq!(adopted, out.plans.len() - 1, "one plan per adopted replan");
    }
    assert!(replans >= 4, "drift called for {replans} replans");
    assert!(2 * repaired > replans, "{repaired} of {replans} repaired");
}

#[test]
fn restart_plans_every_replan_from_scratch() {
    let (s, setup, out) = run(1, "restart");
    assert_valid(&s, &setup, &out);
    assert!(!out.replans.is_empty());
    for r in &out.replans {
        assert!(
            matches!(r.how, ReplanHow::Full | ReplanHow::Failed),
            "{r:?}"
        );
        assert_eq!((r.rejoins, r.tree_iterations), (0, 0));
    }
}

#[test]
fn a_repairing_run_is_reproducible_per_seed() {
    let (_, _, a) = run(2, "repair");
    let (_, _, b) = run(2, "repair");
    let work = |o: &TrackOutcome| {
        o.replans
            .iter()
            .map(|r| (r.how, r.rejoins, r.tree_iterations, r.planner_iterations))
            .collect::<Vec<_>>()
    };
    assert_eq!(work(&a), work(&b));
    let plans = |o: &TrackOutcome| o.plans.iter().map(|p| p.plan.clone()).collect::<Vec<_>>();
    assert_eq!(plans(&a), plans(&b));
    assert_eq!(a.metrics.rms_error_bl, b.metrics.rms_error_bl);
}
