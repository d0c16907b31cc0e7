//! Where a shortcut pass's work goes on the built-in pair mazes:
//! `cargo run -p magbench-planners --example shortcut_profile [rounds] [seeds]`.

use magbench_env::Scenario;
use magbench_planners::registry::Planners;
use magbench_planners::shortcut::Shortcut;
use magbench_planners::{Limits, Problem, Rng, plan_cost};
use rand::SeedableRng;

fn main() {
    let args: Vec<usize> = std::env::args().skip(1).map(|a| a.parse().unwrap()).collect();
    let rounds = args.first().copied().unwrap_or(200);
    let seeds = args.get(1).copied().unwrap_or(10) as u64;
    println!("| maze | edges | rounds | candidates | steer props | tail props | no steer | steer collides | not cheaper | tail invalid | misses goal | accepted | steer s | no-steer s | check s | search s | cost ratio |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for name in ["open-field", "micro-factory", "narrow-passage", "cargo-delivery"] {
        let s = Scenario::load(name).unwrap();
        let mut tot = magbench_planners::shortcut::Stats::default();
        let (mut edges, mut ratio, mut search) = (0, 0.0, 0.0);
        for seed in 0..seeds {
            let mut p = Problem::from_scenario(&s, 0, None, seed);
            p.limits = Limits { max_iterations: Some(50_000), time_limit: None };
            let r = Planners::builtin().create("goal-zoom-rrt", &[]).unwrap().solve(&p);
            assert!(r.solved);
            search += r.time_s;
            edges += r.plan.edges();
            let max_periods = magbench_planners::search_settings::to_periods(2.0, p.control_period);
            let pass = Shortcut { rounds, max_periods };
            let mut rng = Rng::seed_from_u64(seed);
            let (out, st) = pass.run_with_stats(&p, &r.plan, &mut rng);
            ratio += plan_cost(&p, &out) / plan_cost(&p, &r.plan);
            tot.rounds += st.rounds;
            tot.candidates += st.candidates;
            tot.steer_props += st.steer_props;
            tot.tail_props += st.tail_props;
            for k in 0..6 { tot.outcome[k] += st.outcome[k]; }
            tot.steer_time += st.steer_time;
            tot.check_time += st.check_time;
            tot.no_steer_time += st.no_steer_time;
        }
        let o = tot.outcome;
        println!("| {name} | {:.0} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.4} | {:.4} | {:.4} | {:.4} | {:.3} |",
            edges as f64 / seeds as f64, tot.rounds, tot.candidates, tot.steer_props, tot.tail_props,
            o[0], o[1], o[2], o[3], o[4], o[5], tot.steer_time.as_secs_f64() / seeds as f64, tot.no_steer_time.as_secs_f64() / seeds as f64,
            tot.check_time.as_secs_f64() / seeds as f64, search / seeds as f64, ratio / seeds as f64);
    }
}
