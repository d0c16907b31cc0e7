//! Replanning: cargo-delivery's two legs (a replan from the observed state at the map switch),
//! and a replan when the tracking error persists.

mod common;

use common::*;
use magbench_env::Vec2;
use magbench_env::plant::DisturbancePreset;
use magbench_planners::{Planner, Problem};
use magbench_trackers::{Mission, PlanReason, RunStatus, TrackerSpec, simulate};

#[test]
fn cargo_delivery_completes_both_legs_with_replanning() {
    let s = scenario("cargo-delivery");
    for name in ["obc", "lookahead"] {
        let mut planner = WaypointPlanner {
            legs: cargo_waypoints(&s),
            calls: 0,
        };
        let spec = TrackerSpec::parse(name, &[], "test").unwrap();
        let mission = Mission {
            scenario: &s,
            plan: None,
            plan_time_s: 0.0,
            plan_solved: false,
            planner: Some(&mut planner as &mut dyn Planner),
            limits: None,
            seed: 3,
        };
        let mut opts = spec.loop_options();
        opts.record_ticks = true;
        let out = simulate(
            mission,
            spec.build().as_mut(),
            &DisturbancePreset::realistic(),
            &opts,
        );
        let m = &out.metrics;
        assert_eq!(
            m.status,
            RunStatus::ReachedGoal,
            "{name}: {:?} {:?}",
            m,
            out.message
        );
        assert!(
            m.reached_goal && m.legs_completed == 2 && m.legs == 2,
            "{name}: {m:?}"
        );
        assert!(!m.agent_contact);
        assert!(
            m.replans >= 1,
            "{name}: the second leg was planned from the observed state"
        );
        assert_eq!(out.plans[0].reason, PlanReason::Initial);
        let leg2 = out
            .plans
            .iter()
            .find(|p| p.reason == PlanReason::Leg)
            .expect("a leg replan");
        assert_eq!(leg2.leg, 1);
        // the new leg's plan starts where the team was seen, not at the old plan's end
        let tick = out.ticks.iter().find(|t| t.leg == 1).unwrap();
        let d = leg2
            .plan
            .start()
            .iter()
            .zip(&tick.estimate)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        assert!(
            d < 0.05,
            "{name}: leg-2 plan starts {d} BL from the estimate"
        );
        assert!(m.rms_error_bl < 0.2, "{name}: rms {}", m.rms_error_bl);
    }
}

#[test]
fn persistent_error_triggers_a_replan() {
    let s = scenario("open-field");
    let legs = vec![vec![
        pair([12.0, 10.0], 2.5, 45.0),
        s.legs[0].goal.agents.clone(),
    ]];
    let mut planner = WaypointPlanner { legs, calls: 0 };
    // a plan for a team that starts 1.5 BL above where the team really is
    let shifted: Vec<Vec2> = s.start.iter().map(|p| p + Vec2::new(0.0, 1.5)).collect();
    let problem = Problem::from_scenario(&s, 0, Some(&shifted), 0);
    let first = planner.solve(&problem);
    assert!(first.solved);
    let spec = TrackerSpec::parse(
        "obc",
        &[
            ("replan_error".into(), "0.5".into()),
            ("replan_after".into(), "0.5".into()),
        ],
        "test",
    )
    .unwrap();
    let mission = Mission {
        scenario: &s,
        plan: Some(first.plan),
        plan_time_s: first.time_s,
        plan_solved: true,
        planner: Some(&mut planner as &mut dyn Planner),
        limits: None,
        seed: 1,
    };
    let out = simulate(
        mission,
        spec.build().as_mut(),
        &DisturbancePreset::realistic(),
        &spec.loop_options(),
    );
    let m = &out.metrics;
    assert!(m.error_replans >= 1 && m.replans >= 1, "{m:?}");
    assert_eq!(out.plans[1].reason, PlanReason::Error);
    assert_eq!(m.status, RunStatus::ReachedGoal, "{m:?}");
}
