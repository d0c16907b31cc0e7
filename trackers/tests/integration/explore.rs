//! Tuning and benchmark helpers, ignored by the test suite; run by hand:
//!
//! ```sh
//! # the 50 goal-zoom-rrt plans of micro-factory used for the tracker benchmarks
//! SEEDS=50 cargo test --release -p magbench-trackers --test integration explore::write_rrt_plans -- --ignored --nocapture
//! # trackers on random valid plans in open-field (TRACKERS, TP="key=value ...", PRESET, SEEDS, V=1)
//! cargo test --release -p magbench-trackers --test integration explore::explore_random_plans -- --ignored --nocapture
//! ```

use crate::common;

use common::*;
use magbench_env::PlanningModel;
use magbench_env::plant::DisturbancePreset;
use magbench_trackers::{Mission, Trackers, simulate};

fn params() -> Vec<(String, String)> {
    std::env::var("TP")
        .unwrap_or_default()
        .split_whitespace()
        .map(|kv| {
            let (k, v) = kv.split_once('=').unwrap();
            (k.to_string(), v.to_string())
        })
        .collect()
}

#[test]
#[ignore]
fn explore_random_plans() {
    let s = scenario("open-field");
    let model = PlanningModel::new(&s.physics);
    let checker = s.checker_for_leg(0);
    let preset =
        DisturbancePreset::by_name(&std::env::var("PRESET").unwrap_or("realistic".into())).unwrap();
    let seeds: u64 = std::env::var("SEEDS")
        .map(|x| x.parse().unwrap())
        .unwrap_or(10);
    let trackers = std::env::var("TRACKERS").unwrap_or("open-loop obc lookahead".into());
    for name in trackers.split_whitespace() {
        let spec = Trackers::builtin().spec(name, &params(), "env").unwrap();
        let mut rms = vec![];
        let mut contact = 0;
        let mut maxe: f64 = 0.0;
        for seed in 0..seeds {
            let plan = random_plan(&model, &checker, &s.start, 25, 100 + seed);
            let mut opts = spec.loop_options();
            opts.time_slack = 5.0;
            let mut m = Mission::with_plan(&s, plan);
            m.seed = seed;
            let out = simulate(m, spec.build().as_mut(), &preset, &opts);
            rms.push(out.metrics.rms_error_bl);
            maxe = maxe.max(out.metrics.max_error_bl);
            contact += usize::from(out.metrics.agent_contact);
            if std::env::var("V").is_ok() {
                println!(
                    "  seed {seed}: {:?} rms {:.3} max {:.3} ticks {} walls {}",
                    out.metrics.status,
                    out.metrics.rms_error_bl,
                    out.metrics.max_error_bl,
                    out.metrics.ticks,
                    out.metrics.wall_contacts
                );
            }
        }
        rms.sort_by(f64::total_cmp);
        println!(
            "{}: rms median {:.3} p90 {:.3} max {:.3} contact {}/{}",
            spec.label(),
            rms[rms.len() / 2],
            rms[(rms.len() * 9) / 10],
            maxe,
            contact,
            seeds
        );
    }
}

#[test]
#[ignore]
fn write_micro_factory_plan() {
    let s = scenario("micro-factory");
    let model = PlanningModel::new(&s.physics);
    let checker = s.checker_for_leg(0);
    let plan = steer_plan(
        &model,
        &checker,
        &s.start,
        &micro_factory_waypoints(&s),
        0.4,
        0.2,
        600.0,
    )
    .expect("a plan");
    println!(
        "plan: {} edges, {:.1} s, ends in goal: {}",
        plan.edges(),
        plan.duration(),
        s.legs[0].goal.contains(plan.end())
    );
    std::fs::write("/tmp/mf-plan.json", serde_json::to_string(&plan).unwrap()).unwrap();
}

#[test]
#[ignore]
fn write_rrt_plans() {
    let name = std::env::var("SCEN").unwrap_or("micro-factory".into());
    let s = scenario(&name);
    let n: u64 = std::env::var("SEEDS")
        .map(|x| x.parse().unwrap())
        .unwrap_or(20);
    std::fs::create_dir_all("/tmp/plans").unwrap();
    let first: u64 = std::env::var("FIRST")
        .map(|x| x.parse().unwrap())
        .unwrap_or(0);
    for seed in first..n {
        let mut p = magbench_planners::Planners::builtin()
            .create("goal-zoom-rrt", &[])
            .unwrap();
        let r = p.solve(&magbench_planners::Problem::from_scenario(
            &s, 0, None, seed,
        ));
        println!(
            "seed {seed}: solved {} edges {} duration {:.1} s time {:.2} s",
            r.solved,
            r.plan.edges(),
            r.plan.duration(),
            r.time_s
        );
        std::fs::write(
            format!("/tmp/plans/{name}-{seed}.json"),
            serde_json::to_string(&r.plan).unwrap(),
        )
        .unwrap();
    }
}
