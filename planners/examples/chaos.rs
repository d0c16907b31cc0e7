//! How far a plan's end moves when its start moves by 1e-9 BL: goal-zoom RRT's first solution
//! of each built-in scenario's first leg, seeds 0–9, replayed open loop in the planning model
//! (walls ignored) from the plan's start with the first agent moved 1e-9 BL along x, against the
//! plan's own states. Per scenario: the plans' median duration; the perturbed replays that leave the
//! proximity range (agents in contact or out of range, where the model stops holding); the
//! time along the plan, at an edge's end, when the two replays are first more than 0.1 BL apart
//! (the larger of the agents' distances; median over the replays that get so far apart); and
//! how far apart they end (median and maximum over the replays that stay in range). `cargo run
//! --release -p magbench-planners --example chaos` (`cargo xtask measure --only chaos` runs
//! it), printing a Markdown table.

use magbench_env::{Scenario, Vec2};
use magbench_planners::registry::Planners;
use magbench_planners::{Limits, Plan, Problem};

/// Seeds per scenario.
const SEEDS: u64 = 10;

/// How far the first agent's start is moved (BL).
const OFFSET: f64 = 1e-9;

/// Two replays this far apart (BL) have visibly parted.
const APART: f64 = 0.1;

/// One perturbed replay beside the plan's own.
struct Replay {
    /// It left the proximity range: with two agents in contact (closer than its lower bound),
    /// or apart (farther than its upper bound).
    left: Option<Leave>,
    /// The time along the plan (s) at the end of the first edge after which the replays are
    /// more than [`APART`] apart.
    apart_at: Option<f64>,
    /// How far apart the replays end (BL), when the perturbed one stayed in range.
    end: Option<f64>,
}

/// How a replay left the proximity range.
#[derive(Clone, Copy, PartialEq)]
enum Leave {
    Contact,
    Apart,
}

fn main() {
    println!(
        "| scenario | plans | duration, median (s) | perturbed replays that end in contact | that end out of range | time until 0.1 BL apart, median (s) | replays 0.1 BL apart | end moved, median (BL) | end moved, max (BL) |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for name in magbench_env::scenario::builtin_names() {
        let s = Scenario::load(name).expect("built-in scenario");
        let (mut durations, mut replays) = (vec![], vec![]);
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
            durations.push(r.plan.duration());
            replays.push(replay(&p, &r.plan));
        }
        let mut apart: Vec<f64> = replays.iter().filter_map(|r| r.apart_at).collect();
        let mut ends: Vec<f64> = replays.iter().filter_map(|r| r.end).collect();
        println!(
            "| {name} | {SEEDS} | {:.1} | {}/{SEEDS} | {}/{SEEDS} | {} | {}/{SEEDS} | {} | {} |",
            median(&mut durations).unwrap_or(f64::NAN),
            replays
                .iter()
                .filter(|r| r.left == Some(Leave::Contact))
                .count(),
            replays
                .iter()
                .filter(|r| r.left == Some(Leave::Apart))
                .count(),
            fmt(median(&mut apart), 1),
            apart.len(),
            fmt(median(&mut ends), 2),
            fmt(ends.iter().copied().reduce(f64::max), 2),
        );
    }
}

/// `plan`'s controls applied open loop from its start with the first agent moved [`OFFSET`],
/// edge by edge until the plan ends or the replay leaves the proximity range, against the
/// plan's own states (the model's replay of its start, which the validator checked).
fn replay(p: &Problem, plan: &Plan) -> Replay {
    let mut b = plan.states[0].clone();
    b[0].x += OFFSET;
    let mut next_b = b.clone();
    let (mut t, mut apart_at) = (0.0, None);
    for ((u, &d), a) in plan
        .controls
        .iter()
        .zip(&plan.durations)
        .zip(&plan.states[1..])
    {
        let mut left = None;
        p.model.propagate_with(&b, u, d, &mut next_b, |s| {
            left = leave(p, s);
            left.is_none()
        });
        if left.is_some() {
            return Replay {
                left,
                apart_at,
                end: None,
            };
        }
        std::mem::swap(&mut b, &mut next_b);
        t += d;
        if apart_at.is_none() && distance(a, &b) > APART {
            apart_at = Some(t);
        }
    }
    Replay {
        left: None,
        apart_at,
        end: Some(distance(plan.end(), &b)),
    }
}

/// How state `s` is out of the proximity range, `None` when it is in.
fn leave(p: &Problem, s: &[Vec2]) -> Option<Leave> {
    if p.checker.proximity_ok(s) {
        return None;
    }
    let closest = (0..s.len())
        .flat_map(|i| (i + 1..s.len()).map(move |j| (i, j)))
        .map(|(i, j)| (s[i] - s[j]).norm())
        .fold(f64::INFINITY, f64::min);
    // a non-finite state comes from agents that met
    Some(if closest.is_nan() || closest <= p.checker.r_min {
        Leave::Contact
    } else {
        Leave::Apart
    })
}

/// The larger of the agents' distances between `a` and `b` (BL).
fn distance(a: &[Vec2], b: &[Vec2]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
}

/// The median of `v`, `None` when empty.
fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    Some(0.5 * (v[(v.len() - 1) / 2] + v[v.len() / 2]))
}

/// `x` to `digits` decimals, or "–".
fn fmt(x: Option<f64>, digits: usize) -> String {
    x.map_or_else(|| "–".into(), |x| format!("{x:.digits$}"))
}
