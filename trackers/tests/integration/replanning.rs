//! Replanning: cargo-delivery's two legs (a replan from the observed state at the map switch),
//! and a replan when the tracking error persists.

use crate::common;

use common::*;
use magbench_env::Vec2;
use magbench_env::plant::DisturbancePreset;
use magbench_planners::{FirstPlan, Limits, Planner, PlanningSetup, Problem, solve_validated};
use magbench_trackers::{Mission, PlanReason, RunStatus, Trackers, simulate};

#[test]
fn cargo_delivery_completes_both_legs_with_replanning() {
    let s = scenario("cargo-delivery");
    for name in ["obc", "lookahead"] {
        let mut planner = WaypointPlanner {
            legs: cargo_waypoints(&s),
            calls: 0,
        };
        let spec = Trackers::builtin().spec(name, &[], "test").unwrap();
        let setup = PlanningSetup::default();
        let first = solve_validated(&mut planner, &setup.problem(&s, 0, None, 3))
            .followable()
            .unwrap();
        let mission = Mission {
            scenario: &s,
            first,
            planner: Some(&mut planner as &mut dyn Planner),
            setup,
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
    let spec = Trackers::builtin()
        .spec(
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
        first: FirstPlan {
            plan: first.plan,
            solved: true,
            time_s: first.time_s,
        },
        planner: Some(&mut planner as &mut dyn Planner),
        setup: Default::default(),
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

/// A simulated rig whose clock, like a physical rig's, runs on while the host replans at the
/// map switch: the first frame after `set_world` comes `JUMP` seconds late.
struct RunningClockRig {
    inner: magbench_trackers::SimRig,
    offset: f64,
    switched: bool,
}

const JUMP: f64 = 100.0;

impl magbench_trackers::Rig for RunningClockRig {
    fn frame_period(&self) -> f64 {
        self.inner.frame_period()
    }
    fn observe(&mut self) -> Result<magbench_env::plant::Observation, magbench_trackers::RigError> {
        let mut o = self.inner.observe()?;
        if std::mem::take(&mut self.switched) {
            self.offset += JUMP;
        }
        o.t += self.offset;
        Ok(o)
    }
    fn command(&mut self, u: &magbench_env::Control) -> Result<(), magbench_trackers::RigError> {
        self.inner.command(u)
    }
    fn stop(&mut self) -> Result<(), magbench_trackers::RigError> {
        self.inner.stop()
    }
    fn latency(&self) -> f64 {
        self.inner.latency()
    }
    fn set_world(&mut self, w: &magbench_env::World) -> Result<(), magbench_trackers::RigError> {
        self.switched = true;
        self.inner.set_world(w)
    }
    fn ground_truth(&self) -> Option<magbench_trackers::GroundTruth> {
        self.inner.ground_truth()
    }
}

/// `total_time_s` counts the map switch's replan once: on a rig whose clock ran through it the
/// replan is in the tracking time already; on the simulated rig (clock paused) it is added.
#[test]
fn total_time_counts_a_replan_once_whatever_the_rig_clock() {
    let s = scenario("cargo-delivery");
    let first_plan_time = 1.5;
    let run = |running: bool| {
        let mut planner = WaypointPlanner {
            legs: cargo_waypoints(&s),
            calls: 0,
        };
        let first = planner.solve(&Problem::from_scenario(&s, 0, None, 3)).plan;
        let mission = Mission {
            scenario: &s,
            first: FirstPlan {
                plan: first,
                solved: true,
                time_s: first_plan_time,
            },
            planner: Some(&mut planner as &mut dyn Planner),
            setup: Default::default(),
            seed: 3,
        };
        let spec = Trackers::builtin().spec("obc", &[], "test").unwrap();
        let mut opts = spec.loop_options();
        opts.record_ticks = false;
        let preset = DisturbancePreset::ideal();
        let sim = magbench_trackers::SimRig::new(&s, &preset, 3);
        let out = if running {
            let mut rig = RunningClockRig {
                inner: sim,
                offset: 0.0,
                switched: false,
            };
            magbench_trackers::track(&mut rig, spec.build().as_mut(), mission, &opts)
        } else {
            let mut rig = sim;
            magbench_trackers::track(&mut rig, spec.build().as_mut(), mission, &opts)
        };
        out.metrics
    };
    let paused = run(false);
    assert!(paused.replans >= 1 && paused.planning_time_s > first_plan_time);
    assert_eq!(
        paused.total_time_s,
        paused.planning_time_s + paused.duration_s
    );
    let running = run(true);
    assert!(running.replans >= 1, "{running:?}");
    assert!(running.duration_s > JUMP, "{running:?}");
    // the replan's wall time is inside the 100 s the clock jumped: only the first plan (made
    // before the first tick) is added to the rig time
    assert!(
        (running.total_time_s - (first_plan_time + running.duration_s)).abs() < 1e-9,
        "{running:?}"
    );
}

/// A planner that records the problem of every call, then plans with goal-zoom-rrt.
struct Recording {
    inner: Box<dyn Planner>,
    seen: Vec<Problem>,
}

impl magbench_env::params::ParamSet for Recording {}

impl Planner for Recording {
    fn name(&self) -> &str {
        "recording"
    }

    fn solve(&mut self, problem: &Problem) -> magbench_planners::PlannerResult {
        self.seen.push(problem.clone());
        self.inner.solve(problem)
    }
}

/// The planning setup reaches every plan of a run, the first and each new leg's, and every plan
/// is in whole frames of the rig that runs it (a 30 fps camera here), whatever control period
/// the mission's setup carried.
#[test]
fn every_plan_of_a_run_is_made_under_its_setup_in_the_rigs_frames() {
    let s = scenario("cargo-delivery");
    let mut planner = Recording {
        inner: magbench_planners::Planners::builtin()
            .create("goal-zoom-rrt", &[])
            .unwrap(),
        seen: vec![],
    };
    let mut setup = PlanningSetup {
        limits: Limits {
            max_iterations: Some(60_000),
            time_limit: None,
        },
        ..PlanningSetup::default()
    };
    setup.set("test", "objective", "duration").unwrap();
    setup.set("test", "metric", "centroid-shape:1:1").unwrap();
    setup.set("test", "flow", "rk4").unwrap();
    let mut preset = DisturbancePreset::ideal();
    preset.camera.fps = 30.0;
    let spec = Trackers::builtin().spec("obc", &[], "test").unwrap();
    let first = solve_validated(
        &mut planner,
        &setup
            .clone()
            .in_frames_of(1.0 / 30.0)
            .problem(&s, 0, None, 5),
    )
    .followable()
    .unwrap();
    let mission = Mission {
        scenario: &s,
        first,
        planner: Some(&mut planner as &mut dyn Planner),
        setup,
        seed: 5,
    };
    let out = simulate(
        mission,
        spec.build().as_mut(),
        &preset,
        &spec.loop_options(),
    );
    assert!(
        out.metrics.legs_completed >= 1,
        "{:?} {:?}",
        out.metrics,
        out.message
    );
    let legs: Vec<usize> = out.plans.iter().map(|p| p.leg).collect();
    assert!(legs.contains(&1), "the second leg was planned: {legs:?}");
    assert_eq!(planner.seen.len(), out.plans.len());
    for p in &planner.seen {
        assert_eq!(p.objective.name(), "duration");
        assert_eq!(
            p.metric,
            magbench_planners::Distance::CentroidShape {
                centroid: 1.0,
                shape: 1.0
            }
        );
        assert_eq!(p.model.flow, magbench_env::model::Flow::Rk4);
        assert_eq!(p.limits.max_iterations, Some(60_000));
        assert_eq!(
            p.control_period,
            1.0 / 30.0,
            "the rig's frame, not the setup's"
        );
    }
    for record in &out.plans {
        assert_eq!(record.plan.flow, magbench_env::model::Flow::Rk4);
        for d in &record.plan.durations {
            let frames = d * 30.0;
            assert!(
                (frames - frames.round()).abs() < 1e-9 && frames >= 1.0,
                "{d} s is not whole 30 fps frames"
            );
        }
    }
}

/// The evenly spaced row is an invariant set of the nominal model, so goal-zoom-rrt's
/// plan from trio-row's start keeps the team a row for its first seconds, while the real,
/// unequal agents (realistic preset) bend out of it; the OBC then cannot get back onto the plan
/// and stalls near the start. A replan from the observed (bent) state on the stall — the
/// default for three agents — reaches the goal; without it the run times out.
#[test]
fn a_stalled_three_agent_team_replans_and_reaches_the_goal() {
    // trio-row floats at an interface, with half the bulk drag: twice the viscosity gives it
    // the bulk's time scale, at which the realistic 60 fps loop tracks a team of three (at the
    // interface's own time scale the replanned run ends in contact on seeds 0 to 5)
    let mut s = scenario("trio-row");
    s.physics.viscosity_mpa_s *= 2.0;
    let preset = DisturbancePreset::realistic();
    let run = |stall: &str| {
        let setup = PlanningSetup {
            limits: Limits {
                max_iterations: Some(200_000),
                time_limit: None,
            },
            ..PlanningSetup::default()
        }
        .in_frames_of(1.0 / preset.camera.fps);
        let mut planner = magbench_planners::Planners::builtin()
            .create("goal-zoom-rrt", &[])
            .unwrap();
        let first = planner.solve(&setup.problem(&s, 0, None, 0));
        assert!(first.solved);
        let spec = Trackers::builtin()
            .spec("obc", &[("replan_stall".into(), stall.into())], "t")
            .unwrap();
        let mission = Mission {
            scenario: &s,
            first: FirstPlan {
                plan: first.plan,
                solved: true,
                time_s: first.time_s,
            },
            planner: Some(planner.as_mut()),
            setup,
            seed: 0,
        };
        let mut opts = spec.loop_options();
        opts.record_ticks = false;
        simulate(mission, spec.build().as_mut(), &preset, &opts)
    };
    let stalled = run("false");
    assert_eq!(
        stalled.metrics.status,
        RunStatus::Timeout,
        "{:?}",
        stalled.metrics
    );
    assert_eq!(stalled.metrics.replans, 0);
    let replanned = run("auto");
    let m = &replanned.metrics;
    assert_eq!(m.status, RunStatus::ReachedGoal, "{m:?}");
    assert!(!m.agent_contact);
    assert!(m.error_replans >= 1, "{m:?}");
    let reasons: Vec<_> = replanned.plans[1..].iter().map(|p| p.reason).collect();
    assert!(reasons.contains(&PlanReason::Stall), "{reasons:?}");
    assert!(
        reasons
            .iter()
            .all(|r| matches!(r, PlanReason::Error | PlanReason::Stall))
    );
}
