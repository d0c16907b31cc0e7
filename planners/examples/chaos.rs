//! How far a plan's end moves when its start moves by 1e-9 BL: goal-zoom RRT's first solution
//! of each built-in pair maze's first leg, seeds 0–9, replayed open loop in the planning model
//! (the exact pair flow, walls ignored) from the plan's start and from that start with the
//! first agent moved 1e-9 BL along x. Per maze: the plans' median duration, the end's distance
//! between the two replays (the larger of the two agents'), its minimum, median and maximum,
//! and the unperturbed replay's distance from the plan's stored end. `cargo run --release -p
//! magbench-planners --example chaos` (`magbench docs measure --only chaos` runs it), printing
//! a Markdown table.

use magbench_env::{Scenario, Vec2};
use magbench_planners::registry::Planners;
use magbench_planners::{Limits, Plan, Problem};

/// Seeds per maze.
const SEEDS: u64 = 10;

/// How far the first agent's start is moved (BL).
const OFFSET: f64 = 1e-9;

fn main() {
    println!(
        "| scenario | plans | duration (s), median | end moved, min (BL) | end moved, median (BL) | end moved, max (BL) | unperturbed replay off the plan's end, max (BL) |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    for name in [
        "open-field",
        "micro-factory",
        "narrow-passage",
        "cargo-delivery",
    ] {
        let s = Scenario::load(name).expect("built-in scenario");
        let (mut durations, mut moved, mut exact) = (vec![], vec![], 0.0f64);
        for seed in 0..SEEDS {
            let mut p = Problem::from_scenario(&s, 0, None, seed);
            p.limits = Limits {
                max_iterations: Some(200_000),
                time_limit: None,
            };
            let r = Planners::builtin()
                .create("goal-zoom-rrt", &[])
                .expect("built-in planner")
                .solve(&p);
            assert!(r.solved, "{name} seed {seed}: no plan");
            let start = r.plan.states[0].clone();
            let mut shifted = start.clone();
            shifted[0].x += OFFSET;
            let end = replay(&p, &r.plan, &start);
            exact = exact.max(distance(&end, r.plan.end()));
            moved.push(distance(&replay(&p, &r.plan, &shifted), &end));
            durations.push(r.plan.duration());
        }
        println!(
            "| {name} | {SEEDS} | {:.1} | {:.3} | {:.2} | {:.2} | {:.1e} |",
            median(&mut durations),
            moved.iter().copied().fold(f64::INFINITY, f64::min),
            median(&mut moved),
            moved.iter().copied().fold(0.0, f64::max),
            exact
        );
    }
}

/// The end of `plan`'s controls and durations applied open loop from `start`.
fn replay(p: &Problem, plan: &Plan, start: &[Vec2]) -> Vec<Vec2> {
    let mut state = start.to_vec();
    let mut end = state.clone();
    for (u, &d) in plan.controls.iter().zip(&plan.durations) {
        p.model.propagate(&state, u, d, &mut end);
        std::mem::swap(&mut state, &mut end);
    }
    state
}

/// The larger of the agents' distances between `a` and `b` (BL).
fn distance(a: &[Vec2], b: &[Vec2]) -> f64 {
    a.iter().zip(b).map(|(p, q)| (p - q).norm()).fold(0.0, f64::max)
}

/// The median of `v`.
fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    0.5 * (v[(v.len() - 1) / 2] + v[v.len() / 2])
}
