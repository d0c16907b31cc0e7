//! What the shortcut pass and straightening change in a plan besides its cost: goal-zoom RRT's
//! first solution and the same seed's plan after `shortcut=200` or `straighten=true`, and the
//! aimed, guided 5 s first solution without and with `straighten=true`, on the built-in pair
//! mazes, seeds 0–9, medians of
//! the plans' edges, duration, closest approach of the two agents, and how hard the plan drives
//! the coil's gradient (the time-weighted mean of `max(|g_x|, |g_y|)` over the limit, and the
//! share of the plan's time at the limit), which is the headroom a tracker has left to correct
//! with. `cargo run --release -p magbench-planners --example shortcut_plans`
//! (`cargo xtask measure --only shortcut-plans` runs it), printing a Markdown table.

use magbench_env::Vec2;
use magbench_planners::registry::Planners;
use magbench_planners::{Limits, Plan, Problem};

/// goal-zoom-rrt's settings compared, each with its label.
const PLANNERS: [(&str, &[(&str, &str)]); 5] = [
    ("goal-zoom-rrt", &[]),
    ("goal-zoom-rrt{shortcut=200}", &[("shortcut", "200")]),
    ("goal-zoom-rrt{straighten=true}", &[("straighten", "true")]),
    (
        "goal-zoom-rrt{aim=true,guide=true,max_duration=5}",
        &[("aim", "true"), ("guide", "true"), ("max_duration", "5")],
    ),
    (
        "goal-zoom-rrt{aim=true,guide=true,max_duration=5,straighten=true}",
        &[
            ("aim", "true"),
            ("guide", "true"),
            ("max_duration", "5"),
            ("straighten", "true"),
        ],
    ),
];

/// Seeds per maze.
const SEEDS: u64 = 10;

/// A gradient at least this share of the limit counts as at the limit.
const AT_LIMIT: f64 = 0.99;

fn main() {
    println!(
        "| scenario | planner | edges | duration (s) | closest approach (BL) | gradient use, time-weighted mean | time at the gradient limit |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    for name in [
        "open-field",
        "micro-factory",
        "narrow-passage",
        "cargo-delivery",
    ] {
        let s = magbench_env::Scenario::load(name).expect("built-in scenario");
        for (planner, settings) in PLANNERS {
            let params: Vec<(String, String)> = settings
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect();
            let mut rows: Vec<[f64; 5]> = vec![];
            for seed in 0..SEEDS {
                let mut p = Problem::from_scenario(&s, 0, None, seed);
                p.limits = Limits {
                    max_iterations: Some(50_000),
                    time_limit: None,
                };
                let r = Planners::builtin()
                    .create("goal-zoom-rrt", &params)
                    .expect("built-in planner")
                    .solve(&p);
                assert!(r.solved, "{name} seed {seed}: no plan");
                rows.push(stats(&p, &r.plan));
            }
            let median = |k: usize| {
                let mut v: Vec<f64> = rows.iter().map(|r| r[k]).collect();
                v.sort_by(f64::total_cmp);
                0.5 * (v[(v.len() - 1) / 2] + v[v.len() / 2])
            };
            println!(
                "| {name} | {planner} | {:.0} | {:.1} | {:.2} | {:.2} | {:.0}% |",
                median(0),
                median(1),
                median(2),
                median(3),
                100.0 * median(4)
            );
        }
    }
}

/// Edges, duration (s), the agents' closest approach at the samples (BL), the time-weighted
/// mean gradient use and the share of time at the limit.
fn stats(p: &Problem, plan: &Plan) -> [f64; 5] {
    let limit = p.model.coil.gradient_limit();
    let (mut closest, mut used, mut at_limit) = (f64::INFINITY, 0.0, 0.0);
    let mut state = plan.states[0].clone();
    let mut end = vec![Vec2::zeros(); state.len()];
    for (u, &d) in plan.controls.iter().zip(&plan.durations) {
        p.model.propagate_with(&state, u, d, &mut end, |s| {
            closest = closest.min((s[1] - s[0]).norm());
            true
        });
        let share = u.grad[0].abs().max(u.grad[1].abs()) / limit;
        used += share * d;
        if share >= AT_LIMIT {
            at_limit += d;
        }
        std::mem::swap(&mut state, &mut end);
    }
    let duration = plan.duration();
    [
        plan.edges() as f64,
        duration,
        closest,
        used / duration,
        at_limit / duration,
    ]
}
