//! The `formation` tracker on a team of ten: under the ideal preset it follows formation-rrt's
//! plan into the goal without contact and within 1e-4 BL of it (its prediction is the plant,
//! so it keeps the plan's own field).

use magbench_env::plant::DisturbancePreset;
use magbench_env::scenario::generate::generate;
use magbench_planners::registry::Planners;
use magbench_planners::{Limits, PlanningSetup};
use magbench_trackers::{Formation, LoopOptions, Mission, RunStatus, simulate};

#[test]
fn ten_agents_are_tracked_into_the_goal_under_the_ideal_preset() {
    let params: Vec<(String, String)> = [("agents", "10"), ("spacing", "1.8")]
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let s = generate("<test>", "team", &params, 1, 0).unwrap().scenario;
    let setup = PlanningSetup {
        limits: Limits {
            max_iterations: Some(2_000),
            time_limit: None,
        },
        ..PlanningSetup::default()
    };
    let p = setup.problem(&s, 0, None, 1);
    let r = Planners::builtin()
        .create("formation-rrt", &[])
        .unwrap()
        .solve(&p);
    assert!(r.solved, "goal distance {}", r.goal_distance);
    let out = simulate(
        Mission::with_plan(&s, r.plan.clone()),
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
