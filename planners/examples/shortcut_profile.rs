//! Where a shortcut pass's work goes on the built-in pair mazes, summed over seeds:
//! `cargo run -p magbench-planners --example shortcut_profile [rounds] [seeds] [spans, e.g. 12,6,3]
//! [planner params, e.g. "aim=true;guide=true;max_duration=5"]`. With `MAZE=name` only that
//! maze; with `STRAIGHTEN=1` the centroid is straightened after the pass (its counts on a line
//! of their own, the cost ratio and pass time include it).

use std::time::Instant;

use magbench_env::Scenario;
use magbench_planners::registry::Planners;
use magbench_planners::search_settings::to_periods;
use magbench_planners::shortcut::{SPANS, Shortcut, Stats};
use magbench_planners::{Limits, Problem, plan_cost};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let rounds = args.first().map_or(200, |a| a.parse().unwrap());
    let seeds: u64 = args.get(1).map_or(10, |a| a.parse().unwrap());
    let spans: Vec<usize> = args.get(2).map_or(SPANS.to_vec(), |a| {
        a.split(',').map(|x| x.parse().unwrap()).collect()
    });
    let params: Vec<(String, String)> = args.get(3).map_or(vec![], |a| {
        a.split(';')
            .map(|kv| magbench_env::params::split_assignment("<args>", kv).unwrap())
            .collect()
    });
    let max_duration: f64 = params
        .iter()
        .find(|(k, _)| k == "max_duration")
        .map_or(2.0, |(_, v)| v.parse().unwrap());
    println!("rounds {rounds}, seeds {seeds}, spans {spans:?}, params {params:?}");
    println!(
        "| maze | edges | sweeps | rounds | no steer | invalid | not cheaper | accepted | steer props | replay props | replay invalid | dropped | search s | pass s | cost ratio |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for name in [
        "open-field",
        "micro-factory",
        "narrow-passage",
        "cargo-delivery",
    ] {
        if std::env::var("MAZE").is_ok_and(|m| m != name) {
            continue;
        }
        let s = Scenario::load(name).unwrap();
        let mut t = Stats::default();
        let mut sst = magbench_planners::straighten::Stats::default();
        let (mut edges, mut ratio, mut search, mut pass_s) = (0, 0.0, 0.0, 0.0);
        for seed in 0..seeds {
            let mut p = Problem::from_scenario(&s, 0, None, seed);
            p.limits = Limits {
                max_iterations: Some(50_000),
                time_limit: None,
            };
            let r = Planners::builtin()
                .create("goal-zoom-rrt", &params)
                .unwrap()
                .solve(&p);
            assert!(r.solved);
            search += r.time_s;
            edges += r.plan.edges();
            let pass = Shortcut {
                rounds,
                max_periods: to_periods(max_duration, p.control_period),
                spans: spans.clone(),
            };
            let t0 = Instant::now();
            let (out, st) = pass.run_with_stats(&p, &r.plan);
            let out = if std::env::var("STRAIGHTEN").is_ok() {
                let (o, ss) = magbench_planners::straighten::straighten_with_stats(&p, &out);
                sst.tries += ss.tries;
                sst.accepted += ss.accepted;
                sst.propagations += ss.propagations;
                sst.rests += ss.rests;
                sst.rests_failed += ss.rests_failed;
                assert!(magbench_planners::validate_plan(&p, &o).is_ok());
                o
            } else {
                out
            };
            pass_s += t0.elapsed().as_secs_f64();
            ratio += plan_cost(&p, &out) / plan_cost(&p, &r.plan);
            t.sweeps += st.sweeps;
            t.rounds += st.rounds;
            t.no_steer += st.no_steer;
            t.invalid += st.invalid;
            t.not_cheaper += st.not_cheaper;
            t.accepted += st.accepted;
            t.steer_propagations += st.steer_propagations;
            t.replay_propagations += st.replay_propagations;
            t.replay_invalid += st.replay_invalid;
            t.dropped += st.dropped;
        }
        let n = seeds as f64;
        println!("straighten {sst:?}");
        println!(
            "| {name} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.4} | {:.4} | {:.3} |",
            edges,
            t.sweeps,
            t.rounds,
            t.no_steer,
            t.invalid,
            t.not_cheaper,
            t.accepted,
            t.steer_propagations,
            t.replay_propagations,
            t.replay_invalid,
            t.dropped,
            search / n,
            pass_s / n,
            ratio / n
        );
    }
}
