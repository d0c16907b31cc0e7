//! Under the ideal preset, open-loop reproduces the plan to 1e-6 BL.
//!
//! Sensitivity note (RULES.md): the pair dynamics amplify any difference in arithmetic
//! enormously, so this holds only because the ideal plant integrates with exactly the planning
//! model's arithmetic (same RK4, same step, same force formula; env's test
//! `ideal_plant_is_the_planning_model_bit_for_bit`), and because every edge lasts a whole
//! number of frames, so a frame never straddles two controls.

use crate::common;

use common::*;
use magbench_env::PlanningModel;
use magbench_env::plant::DisturbancePreset;
use magbench_trackers::{LoopOptions, Mission, OpenLoop, Reference, RunStatus, simulate};

#[test]
fn open_loop_reproduces_the_plan_under_the_ideal_preset() {
    let s = scenario("open-field");
    let model = PlanningModel::new(&s.physics);
    let checker = s.checker_for_leg(0);
    for seed in [1, 2, 3] {
        let plan = random_plan(&model, &checker, &s.start, 25, seed);
        let reference = Reference::from_plan(&plan, &model);
        let opts = LoopOptions {
            time_slack: 5.0,
            ..Default::default()
        };
        let out = simulate(
            Mission::with_plan(&s, plan.clone()),
            &mut OpenLoop::new(),
            &DisturbancePreset::ideal(),
            &opts,
        );
        let m = &out.metrics;
        assert!(
            matches!(m.status, RunStatus::PlanFinished | RunStatus::ReachedGoal),
            "{:?}",
            m.status
        );
        assert!(!m.agent_contact && m.wall_contacts == 0);
        let mut worst: f64 = 0.0;
        for t in &out.ticks {
            let k = reference.index_at(t.t);
            let truth = t.truth.as_ref().unwrap();
            for (a, b) in truth.iter().zip(reference.state(k)) {
                worst = worst.max((a - b).norm());
            }
        }
        let last = out.ticks.last().unwrap();
        assert!(
            (last.t - plan.duration()).abs() < 1e-9,
            "played to the end of the plan"
        );
        let end_err = last
            .truth
            .as_ref()
            .unwrap()
            .iter()
            .zip(plan.end())
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        assert!(
            worst <= 1e-6,
            "seed {seed}: largest deviation from the plan {worst:e} BL"
        );
        assert!(
            end_err <= 1e-6,
            "seed {seed}: final deviation {end_err:e} BL"
        );
        assert!(m.rms_error_bl <= 1e-6 && m.max_error_bl <= 1e-6);
        // the ideal camera sees the truth at once: every error metric agrees, and the team is
        // on schedule, so the time-indexed error vanishes too
        assert!(m.rms_error_true_bl.unwrap() <= 1e-6, "{m:?}");
        assert!(m.rms_error_sync_bl <= 1e-6, "{m:?}");
        assert!(m.rms_error_time_bl <= 1e-6, "seed {seed}: {m:?}");
    }
}
