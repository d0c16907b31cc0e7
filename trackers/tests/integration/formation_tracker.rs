//! The `formation` tracker on a team of ten: under the ideal preset it follows formation-rrt's
//! plan into the goal without contact and within 1e-4 BL of it (its prediction is the plant,
//! so it keeps the plan's own field). Under the `realistic` preset, a ring of six is kept apart,
//! which in-plane fields checked over one period did not do.

use magbench_env::plant::DisturbancePreset;
use magbench_env::scenario::generate::generate;
use magbench_planners::registry::Planners;
use magbench_planners::{Limits, PlanningSetup};
use magbench_trackers::{Formation, LoopOptions, Mission, RunStatus, simulate};

/// The team family's ring of `agents` at 1.8 BL, turned and moved.
fn ring(agents: &str) -> magbench_env::Scenario {
    let params: Vec<(String, String)> = [("agents", agents), ("spacing", "1.8")]
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    generate("<test>", "team", &params, 1, 0).unwrap().scenario
}

/// formation-rrt's plan of `s` within `iterations`, seed 1.
fn plan(s: &magbench_env::Scenario, iterations: u64) -> magbench_planners::Plan {
    let setup = PlanningSetup {
        limits: Limits {
            max_iterations: Some(iterations),
            time_limit: None,
        },
        ..PlanningSetup::default()
    };
    let p = setup.problem(s, 0, None, 1);
    let r = Planners::builtin()
        .create("formation-rrt", &[])
        .unwrap()
        .solve(&p);
    assert!(r.solved, "goal distance {}", r.goal_distance);
    r.plan
}

#[test]
fn ten_agents_are_tracked_into_the_goal_under_the_ideal_preset() {
    let s = ring("10");
    let plan = plan(&s, 2_000);
    let out = simulate(
        Mission::with_plan(&s, plan.clone()),
        &mut Formation::default(),
        &DisturbancePreset::ideal(),
        &LoopOptions::default(),
    );
    let m = &out.metrics;
    assert_eq!(m.status, RunStatus::ReachedGoal, "{m:?}");
    assert!(!m.agent_contact && m.wall_contacts == 0);
    // the tracker aims the gradients afresh each tick, so the commands differ from the plan's in
    // their last bits, and the chaotic shape carries that a little
    assert!(m.rms_error_bl <= 1e-4, "{m:?}");
}

#[test]
fn a_ring_of_six_is_kept_apart_under_the_realistic_preset() {
    let s = ring("6");
    let plan = plan(&s, 20_000);
    let run = |tracker: &mut Formation, seed: u64| {
        let mission = Mission {
            seed,
            ..Mission::with_plan(&s, plan.clone())
        };
        let opts = LoopOptions {
            record_ticks: false,
            ..LoopOptions::default()
        };
        simulate(mission, tracker, &DisturbancePreset::realistic(), &opts).metrics
    };
    let mut touched_in_the_plane = 0;
    for seed in 0..3 {
        let m = run(&mut Formation::default(), seed);
        assert!(!m.agent_contact, "seed {seed}: {m:?}");
        let mut planar_one_period = Formation::default();
        planar_one_period.in_plane = true;
        planar_one_period.horizon = 1;
        touched_in_the_plane += usize::from(run(&mut planar_one_period, seed).agent_contact);
    }
    assert!(
        touched_in_the_plane > 0,
        "in-plane fields over one period kept every run apart"
    );
}
