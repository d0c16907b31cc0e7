//! Runs planners over seeds and scenarios and prints success rates, iterations, costs and time.
//!
//! ```sh
//! cargo run --release -p magbench-planners --example sweep -- \
//!     --planner goal-zoom-rrt --scenario micro-factory --seeds 50 --max-iters 200000 [--threads 2] \
//!     [--param k=v]... [--at 10000,50000,200000] [--stop-at-first]
//! ```
//! `--at` prints the median best cost at those iterations (from the progress trace).

use std::sync::{Arc, Mutex};

use magbench_env::Scenario;
use magbench_planners::{Limits, Problem, registry::Planners, validate_plan};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut planners = vec![];
    let mut scenarios = vec![];
    let mut seeds = 10u64;
    let mut first_seed = 0u64;
    let mut max_iters = 200_000u64;
    let mut threads = 1usize;
    let mut params = vec![];
    let mut at: Vec<u64> = vec![];
    let mut verbose = false;
    let mut i = 0;
    while i < args.len() {
        let v = args.get(i + 1).cloned().unwrap_or_default();
        match args[i].as_str() {
            "--planner" => planners.push(v),
            "--scenario" => scenarios.push(v),
            "--seeds" => seeds = v.parse().unwrap(),
            "--first-seed" => first_seed = v.parse().unwrap(),
            "--max-iters" => max_iters = v.parse().unwrap(),
            "--threads" => threads = v.parse().unwrap(),
            "--param" => params.push(magbench_env::params::split_assignment("<args>", &v).unwrap()),
            "--at" => at = v.split(',').map(|x| x.parse().unwrap()).collect(),
            "--verbose" => {
                verbose = true;
                i -= 1;
            }
            a => panic!("unknown argument {a}"),
        }
        i += 2;
    }
    for planner in &planners {
        for scenario in &scenarios {
            let s = Scenario::load(scenario).unwrap();
            let next = Arc::new(Mutex::new(first_seed));
            let rows = Arc::new(Mutex::new(vec![]));
            std::thread::scope(|scope| {
                for _ in 0..threads {
                    let (next, rows, s, params, planner, at) =
                        (next.clone(), rows.clone(), &s, &params, planner, &at);
                    scope.spawn(move || loop {
                        let seed = {
                            let mut n = next.lock().unwrap();
                            if *n >= first_seed + seeds {
                                break;
                            }
                            *n += 1;
                            *n - 1
                        };
                        let mut p = Problem::from_scenario(s, 0, None, seed);
                        p.limits = Limits { max_iterations: Some(max_iters), time_limit: None };
                        let r = if verbose && planner.contains("rrt-star") {
                            let mut pl = if planner.starts_with("informed") {
                                magbench_planners::planners::RrtStar::informed()
                            } else {
                                magbench_planners::planners::RrtStar::default()
                            };
                            magbench_env::params::apply("<args>", planner, &mut pl, params).unwrap();
                            let (r, st) = pl.solve_with_stats(&p);
                            eprintln!("seed {seed}: {st:?}");
                            r
                        } else if verbose && planner == "sst" {
                            let mut pl = magbench_planners::planners::Sst::default();
                            magbench_env::params::apply("<args>", planner, &mut pl, params).unwrap();
                            let (r, st) = pl.solve_with_stats(&p);
                            eprintln!("seed {seed}: {st:?}");
                            r
                        } else {
                            Planners::builtin().create(planner, params).unwrap().solve(&p)
                        };
                        if r.solved {
                            validate_plan(&p, &r.plan).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
                        }
                        let costs: Vec<Option<f64>> = at
                            .iter()
                            .map(|&it| r.progress.iter().rev().find(|q| q.iteration <= it).and_then(|q| q.best_cost))
                            .collect();
                        if verbose {
                            eprintln!(
                                "seed {seed}: solved {} first {:?} iters {} nodes {} time {:.3}s cost {:?} gd {:.3} at {:?}",
                                r.solved, r.first_solution, r.iterations, r.nodes, r.time_s, r.cost, r.goal_distance, costs
                            );
                        }
                        rows.lock().unwrap().push((seed, r.solved, r.first_solution, r.iterations, r.nodes, r.time_s, r.cost, costs));
                    });
                }
            });
            let rows = rows.lock().unwrap();
            let solved = rows.iter().filter(|r| r.1).count();
            let mut first_it: Vec<f64> = rows
                .iter()
                .filter_map(|r| r.2.map(|f| f.0 as f64))
                .collect();
            let mut first_t: Vec<f64> = rows.iter().filter_map(|r| r.2.map(|f| f.1)).collect();
            let its: u64 = rows.iter().map(|r| r.3).sum();
            let time: f64 = rows.iter().map(|r| r.5).sum();
            let mut costs: Vec<f64> = rows.iter().filter_map(|r| r.6).collect();
            println!(
                "{planner:18} {scenario:15} solved {solved}/{} median first-solution iters {:.0} time {:.4}s  median cost {:.2}  it/s {:.0}  mean nodes {:.0}",
                rows.len(),
                median(&mut first_it),
                median(&mut first_t),
                median(&mut costs),
                its as f64 / time,
                rows.iter().map(|r| r.4 as f64).sum::<f64>() / rows.len() as f64,
            );
            for (k, &it) in at.iter().enumerate() {
                let mut c: Vec<f64> = rows.iter().filter_map(|r| r.7[k]).collect();
                let n = c.len();
                println!(
                    "    at {it:>7} iterations: solved {n}/{}  median cost {:.2}",
                    rows.len(),
                    median(&mut c)
                );
            }
        }
    }
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}
