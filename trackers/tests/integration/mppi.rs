//! The `mppi` tracker: under the ideal preset it follows goal-zoom-rrt's plan of `open-field`
//! into the goal, and formation-rrt's plan of a ring of ten; a run is the same for the same seed
//! (and the seed is what its noise comes from); a reference that brings the pair into contact is
//! followed only as far as the proximity range allows; bad parameters are refused naming the key.

use magbench_env::coil::DEFAULT_ALPHA_MAX_DEG;
use magbench_env::plant::{DisturbancePreset, Observation};
use magbench_env::scenario::generate::generate;
use magbench_env::{LocalView, PlanningModel, Scenario, Vec2};
use magbench_planners::registry::Planners;
use magbench_planners::{Limits, Plan, PlanningSetup};
use magbench_trackers::{
    Mission, Mppi, Reference, RunStatus, Tick, TrackOutcome, Tracker, TrackerContext, Trackers,
    simulate,
};

fn kv(pairs: &[(&str, &str)]) -> Vec<(String, String)> {
    pairs
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

/// `planner`'s plan of `s`'s first leg (seed 1, at most `iterations` iterations).
fn plan(s: &Scenario, planner: &str, iterations: u64) -> Plan {
    let setup = PlanningSetup {
        limits: Limits {
            max_iterations: Some(iterations),
            time_limit: None,
        },
        ..PlanningSetup::default()
    };
    let p = setup.problem(s, 0, None, 1);
    let r = Planners::builtin().create(planner, &[]).unwrap().solve(&p);
    assert!(r.solved, "{planner}: goal distance {}", r.goal_distance);
    r.plan
}

/// A run of `mppi` with `params` following `plan` under the ideal preset, seeded with `seed`.
fn run(s: &Scenario, plan: &Plan, params: &[(&str, &str)], seed: u64) -> TrackOutcome {
    let spec = Trackers::builtin()
        .spec("mppi", &kv(params), "test")
        .unwrap();
    let mut mission = Mission::with_plan(s, plan.clone());
    mission.seed = seed;
    simulate(
        mission,
        spec.build().as_mut(),
        &DisturbancePreset::ideal(),
        &spec.loop_options(),
    )
}

#[test]
fn the_pair_follows_goal_zoom_rrt_into_the_goal_of_open_field() {
    let s = Scenario::load("open-field").unwrap();
    let p = plan(&s, "goal-zoom-rrt", 20_000);
    let out = run(&s, &p, &[], 1);
    let m = &out.metrics;
    assert_eq!(m.status, RunStatus::ReachedGoal, "{m:?}");
    assert!(!m.agent_contact && m.wall_contacts == 0, "{m:?}");
    assert!(m.rms_error_bl < 0.05, "{m:?}");
}

#[test]
fn ten_agents_follow_formation_rrt_into_the_goal() {
    let s = generate(
        "<test>",
        "team",
        &kv(&[("agents", "10"), ("spacing", "1.8")]),
        1,
        0,
    )
    .unwrap()
    .scenario;
    let p = plan(&s, "formation-rrt", 2_000);
    let out = run(&s, &p, &[("samples", "64"), ("horizon", "6")], 1);
    let m = &out.metrics;
    assert_eq!(m.status, RunStatus::ReachedGoal, "{m:?}");
    assert!(!m.agent_contact && m.wall_contacts == 0, "{m:?}");
    // every command within the coil's limits: the gradients, and the elevation (the team's
    // field leaves the plane) within the tracker's alpha_max, which it reaches
    let model = PlanningModel::new(&s.physics);
    let (g_max, top) = (
        model.coil.gradient_limit(),
        DEFAULT_ALPHA_MAX_DEG
            .to_radians()
            .min(model.coil.alpha_max()),
    );
    for t in &out.ticks {
        let u = t.command;
        assert!(u.grad.iter().all(|g| g.abs() <= g_max), "{u:?}");
        assert!(u.alpha.abs() <= top, "{u:?}");
    }
    assert!(out.ticks.iter().any(|t| t.command.alpha != 0.0));
}

#[test]
fn the_same_seed_gives_the_same_run_and_another_seed_another() {
    let s = Scenario::load("open-field").unwrap();
    let p = plan(&s, "goal-zoom-rrt", 20_000);
    let params = [("samples", "32"), ("horizon", "5"), ("time_slack", "2")];
    let commands = |seed| -> Vec<_> {
        run(&s, &p, &params, seed)
            .ticks
            .iter()
            .map(|t| (t.command, t.truth.clone()))
            .collect()
    };
    let (a, b, c) = (commands(3), commands(3), commands(4));
    assert!(a.len() > 10);
    // (not assert_eq: a failure would print thousands of ticks)
    assert!(a == b, "seed 3 twice gave different runs");
    assert!(a != c, "seeds 3 and 4 drew the same noise");
}

#[test]
fn parallel_and_serial_rollouts_give_the_same_run() {
    let s = Scenario::load("open-field").unwrap();
    let p = plan(&s, "goal-zoom-rrt", 20_000);
    let commands = |parallel_from| -> Vec<_> {
        let params = [
            ("samples", "48"),
            ("horizon", "5"),
            ("time_slack", "1"),
            ("parallel_from", parallel_from),
        ];
        run(&s, &p, &params, 5)
            .ticks
            .iter()
            .map(|t| t.command)
            .collect()
    };
    assert!(
        commands("1") == commands("1000"),
        "parallel and serial scoring differ"
    );
}

/// A reference that closes the pair at 1 BL/s from 2.5 to 0.5 BL apart, below `r_min`: driven
/// by the tracker (the planning model as the plant), the pair closes in but every frame stays
/// valid.
#[test]
fn a_reference_into_contact_is_followed_only_as_far_as_the_proximity_range() {
    let s = Scenario::load("open-field").unwrap();
    let model = PlanningModel::new(&s.physics);
    let checker = s.checker_for_leg(0);
    let steps = (10.0 / model.dt).round() as usize;
    let times: Vec<f64> = (0..=steps).map(|k| k as f64 * model.dt).collect();
    let states: Vec<Vec<Vec2>> = times
        .iter()
        .map(|t| {
            let r = (2.5 - t).max(0.5);
            LocalView::new(15.0, 10.0, r, 0.0).to_pair().to_vec()
        })
        .collect();
    let reference = Reference::from_samples(&times, &states);
    let ctx = TrackerContext {
        reference: &reference,
        model: &model,
        world: &s.world,
        checker: &checker,
        period: 1.0 / 60.0,
        goal: s.final_goal(),
        seed: 1,
    };
    let g_max = model.coil.gradient_limit();
    let mut tracker = Mppi::default();
    tracker.reset(&ctx);
    let mut x = states[0].clone();
    let mut out = x.clone();
    let mut least = f64::INFINITY;
    for frame in 0..600 {
        let t = frame as f64 * ctx.period;
        let observation = Observation {
            t,
            agents: x.iter().map(|p| Some(*p)).collect(),
        };
        let tick = Tick {
            t,
            estimate: &x,
            observation: &observation,
        };
        let u = tracker.command(&ctx, &tick);
        assert_eq!(u.alpha, 0.0, "a pair's field stays in the plane");
        assert!(u.grad.iter().all(|g| g.abs() <= g_max), "{u:?}");
        model.propagate(&x, &u, ctx.period, &mut out);
        x.copy_from_slice(&out);
        let r = (x[1] - x[0]).norm();
        assert!(checker.is_valid(&x), "frame {frame}: r = {r}");
        least = least.min(r);
    }
    assert!(
        least < 2.0,
        "the pair stayed {least} BL apart: the reference was not followed"
    );
}

#[test]
fn bad_values_are_refused_naming_the_key() {
    for (key, value) in [
        ("samples", "1"),
        ("samples", "0"),
        ("samples", "2.5"),
        ("horizon", "0"),
        ("horizon", "10000"),
        ("temperature", "0"),
        ("temperature", "-1"),
        ("noise_angle", "nan"),
        ("noise_angle", "4"),
        ("noise_grad", "-0.1"),
        ("control_weight", "-1"),
        ("parallel_from", "0"),
        ("alpha_max", "91"),
    ] {
        let e = match Trackers::builtin().spec("mppi", &kv(&[(key, value)]), "exp.toml") {
            Ok(_) => panic!("{key}={value} accepted"),
            Err(e) => e,
        };
        assert_eq!(e.field, format!("param.{key}"), "{key}={value}: {e}");
        assert!(!e.reason.is_empty());
    }
    // too much work per tick: refused naming samples, with the bound
    let e = Trackers::builtin()
        .spec(
            "mppi",
            &kv(&[("samples", "100000"), ("horizon", "600")]),
            "x",
        )
        .err()
        .unwrap();
    assert!(e.to_string().contains("samples"), "{e}");
    assert!(e.reason.contains("at most"), "{e}");
}
