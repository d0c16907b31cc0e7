//! Whole team plans by goal-zoom-rrt to the first solution, seeds `0..SEEDS`, under one flow:
//! prints the summed iterations, the summed planning time and iterations/s. A fixed seed range
//! makes two builds comparable plan for plan (same trees when the model's results agree), and
//! the whole process can be timed from outside or profiled. The scenario is trio-triangle unless
//! a third argument names another (a built-in or a file).
//!
//! ```sh
//! cargo run --release -p magbench-benches --example trio_plans -- pair-adaptive 20
//! cargo run --release -p magbench-benches --example trio_plans -- pair-adaptive 6 experiments/teams/team6-hexagon.toml
//! ```

use magbench_benches::first_plan;
use magbench_env::Scenario;
use magbench_env::model::Flow;
use magbench_planners::Problem;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let flow_name = args.first().map(String::as_str).unwrap_or("pair-adaptive");
    let Some(flow) = Flow::ALL.into_iter().find(|f| f.name() == flow_name) else {
        eprintln!("trio_plans: flow: unknown flow {flow_name:?}");
        std::process::exit(2);
    };
    let seeds: u64 = match args.get(1).map(|s| s.parse()) {
        None => 20,
        Some(Ok(n)) if (1..=10_000).contains(&n) => n,
        Some(_) => {
            eprintln!("trio_plans: seeds: not a whole number in 1..=10000");
            std::process::exit(2);
        }
    };
    let name = args.get(2).map(String::as_str).unwrap_or("trio-triangle");
    let s = match Scenario::load(name) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("trio_plans: scenario: {e}");
            std::process::exit(2);
        }
    };
    let p = Problem::from_scenario(&s, 0, None, 0);
    let (mut iterations, mut seconds, mut solved) = (0u64, 0.0, 0u64);
    for seed in 0..seeds {
        let (r, s) = first_plan(&p, flow, seed);
        seconds += s;
        iterations += r.iterations;
        solved += u64::from(r.solved);
    }
    println!(
        "flow {} seeds {seeds} solved {solved} iterations {iterations} seconds {seconds:.3} iterations/s {:.0}",
        flow.name(),
        iterations as f64 / seconds
    );
}
