//! Where a shortcut pass's work goes on the built-in pair mazes, summed over seeds:
//! `cargo run -p magbench-planners --example shortcut_profile [rounds] [seeds] [spans, e.g. 12,6,3]`.

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
    println!("rounds {rounds}, seeds {seeds}, spans {spans:?}");
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
        let s = Scenario::load(name).unwrap();
        let mut t = Stats::default();
        let (mut edges, mut ratio, mut search, mut pass_s) = (0, 0.0, 0.0, 0.0);
        for seed in 0..seeds {
            let mut p = Problem::from_scenario(&s, 0, None, seed);
            p.limits = Limits {
                max_iterations: Some(50_000),
                time_limit: None,
            };
            let r = Planners::builtin()
                .create("goal-zoom-rrt", &[])
                .unwrap()
                .solve(&p);
            assert!(r.solved);
            search += r.time_s;
            edges += r.plan.edges();
            let pass = Shortcut {
                rounds,
                max_periods: to_periods(2.0, p.control_period),
                spans: spans.clone(),
            };
            let t0 = Instant::now();
            let (out, st) = pass.run_with_stats(&p, &r.plan);
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
