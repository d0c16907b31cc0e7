//! Where a team of three stalls without the loop's stall replan: OBC and lookahead follow
//! goal-zoom-rrt's first plan of trio-row and trio-triangle on the realistic plant with
//! `replan_stall=false`, seeds 0 to 4, every tick recorded (`magbench track SCENARIO --tracker T
//! --param replan_stall=false --seed N --out DIR` writes the same ticks). Prints one Markdown
//! table row per scenario and tracker: the first plan's duration, how far along it the tracker
//! got (its best progress, as a share of the plan), the largest path error of any agent, the
//! share of ticks the OBC spent in `recover`, how far the team ended from its goal and how far
//! from the goal's shape, and on trio-row how far the middle agent leaves the line through the
//! other two, on the plan (its first 10 s) and in the run (at 10 s). Medians over seeds with
//! the range in brackets.
//!
//! `cargo run --release -p magbench --example team_stall` (docs/physics.md, "Why teams stall").

use std::thread;

use magbench::Registry;
use magbench::api::{TrackRequest, plan_leg, track_plan};
use magbench_env::plant::DisturbancePreset;
use magbench_env::{Scenario, Vec2};
use magbench_planners::{Limits, PlanningSetup};
use magbench_trackers::{Reference, TrackOutcome};

/// Seeds per scenario and tracker.
const SEEDS: u64 = 5;
/// The plant.
const PRESET: &str = "realistic";
/// Iterations of each planning call, as in `experiments/trio-tracking.toml`.
const ITERATIONS: u64 = 200_000;
/// Time into the plan and the run at which the row's bend is read (s).
const BEND_AT_S: f64 = 10.0;

/// One run's figures.
struct Figures {
    plan_s: f64,
    progress: f64,
    max_error: f64,
    recover: f64,
    final_distance: f64,
    shape: f64,
    reached: bool,
    plan_bend: f64,
    run_bend: f64,
}

/// Distance of `p[1]` from the line through `p[0]` and `p[2]` (BL).
fn bend(p: &[Vec2]) -> f64 {
    let d = p[2] - p[0];
    let v = p[1] - p[0];
    (d.x * v.y - d.y * v.x).abs() / d.norm()
}

/// Largest distance of an agent from its goal centre once both team's centroids are matched
/// (BL): the shape's error without the centroid's.
fn shape_error(s: &[Vec2], goal: &[Vec2]) -> f64 {
    let n = s.len() as f64;
    let c = s.iter().fold(Vec2::zeros(), |a, p| a + p) / n;
    let g = goal.iter().fold(Vec2::zeros(), |a, p| a + p) / n;
    s.iter()
        .zip(goal)
        .map(|(p, q)| ((p - c) - (q - g)).norm())
        .fold(0.0, f64::max)
}

/// Plans and tracks one run, then reads its figures.
fn run(name: &str, tracker: &str, seed: u64) -> Figures {
    let scenario = Scenario::load(name).expect("a built-in scenario");
    let preset = DisturbancePreset::resolve(PRESET).expect("a built-in preset");
    let setup = PlanningSetup {
        limits: Limits {
            max_iterations: Some(ITERATIONS),
            time_limit: None,
        },
        ..PlanningSetup::default()
    }
    .in_frames_of(1.0 / preset.camera.fps)
    .on_plant(&preset.medium, preset.coil.alpha_max_deg);
    let registry = Registry::builtin();
    let mut planner = registry
        .planners()
        .create("goal-zoom-rrt", &[])
        .expect("a built-in planner");
    let first = plan_leg(&scenario, 0, None, planner.as_mut(), &setup, seed)
        .expect("a checked plan")
        .validated
        .result;
    let params = [("replan_stall".to_string(), "false".to_string())];
    let (tracker, options) = registry
        .trackers()
        .build(tracker, &params, "team_stall")
        .expect("a built-in tracker");
    let out: TrackOutcome = track_plan(TrackRequest {
        scenario: &scenario,
        plan: first.plan.clone(),
        plan_source: "<plan>",
        tracker,
        options,
        preset: PRESET,
        seed,
        planner: Some(planner),
        setup: setup.clone(),
    })
    .expect("a run");
    let plan = &out.plans[0].plan;
    let on_first = out.ticks.iter().filter(|t| t.plan == 0);
    let best = on_first.map(|t| t.progress_s).fold(0.0, f64::max);
    let max_error = out
        .ticks
        .iter()
        .flat_map(|t| t.error.iter().copied())
        .filter(|e| e.is_finite())
        .fold(0.0, f64::max);
    let recover = out.ticks.iter().filter(|t| t.mode == "recover").count() as f64
        / out.ticks.len().max(1) as f64;
    let last = out.ticks.last().expect("ticks");
    let end: Vec<Vec2> = (0..scenario.agents()).map(|i| last.position(i)).collect();
    let goal = &scenario.legs.last().expect("a leg").goal.agents;
    let model = setup.model(&scenario);
    let reference = Reference::from_plan(plan, &model);
    let plan_bend = (0..reference.len())
        .take_while(|&k| reference.time(k) <= BEND_AT_S)
        .map(|k| bend(reference.state(k)))
        .fold(0.0, f64::max);
    let at = out.ticks.iter().find(|t| t.t >= BEND_AT_S).unwrap_or(last);
    let now: Vec<Vec2> = (0..scenario.agents()).map(|i| at.position(i)).collect();
    Figures {
        plan_s: plan.duration(),
        progress: best / plan.duration(),
        max_error,
        recover,
        final_distance: out.metrics.final_goal_distance_bl,
        shape: shape_error(&end, goal),
        reached: out.metrics.reached_goal,
        plan_bend,
        run_bend: bend(&now),
    }
}

/// "median (min–max)" of `v`, each by `f`.
fn spread(v: &[f64], f: impl Fn(f64) -> String) -> String {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    let median = if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    };
    format!("{} ({}–{})", f(median), f(s[0]), f(s[n - 1]))
}

fn bl(x: f64) -> String {
    format!("{x:.2}")
}

fn percent(x: f64) -> String {
    format!("{:.0}%", 100.0 * x)
}

fn main() {
    let cases = [
        ("trio-row", "obc"),
        ("trio-row", "lookahead"),
        ("trio-triangle", "obc"),
        ("trio-triangle", "lookahead"),
    ];
    let jobs: Vec<(usize, u64)> = (0..cases.len())
        .flat_map(|c| (0..SEEDS).map(move |s| (c, s)))
        .collect();
    let threads = thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(2);
    let mut results: Vec<(usize, Figures)> = thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|w| {
                let jobs = &jobs;
                let cases = &cases;
                scope.spawn(move || {
                    jobs.iter()
                        .skip(w)
                        .step_by(threads)
                        .map(|&(c, s)| (c, run(cases[c].0, cases[c].1, s)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().expect("a worker"))
            .collect()
    });
    results.sort_by_key(|(c, _)| *c);
    println!(
        "| scenario | tracker (`replan_stall=false`) | goal reached | first plan (s) | best progress along it | largest agent path error (BL) | ticks in `recover` | final goal distance (BL) | final shape error (BL) | row: middle agent off the line, plan's first {BEND_AT_S:.0} s / run at {BEND_AT_S:.0} s (BL) |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for (c, (scenario, tracker)) in cases.iter().enumerate() {
        let f: Vec<&Figures> = results
            .iter()
            .filter(|(k, _)| *k == c)
            .map(|(_, f)| f)
            .collect();
        let col = |g: fn(&Figures) -> f64| f.iter().map(|x| g(x)).collect::<Vec<f64>>();
        let reached = f.iter().filter(|x| x.reached).count();
        let recover = match *tracker {
            "obc" => spread(&col(|x| x.recover), percent),
            _ => "–".into(),
        };
        let row = match *scenario {
            "trio-row" => format!(
                "{} / {}",
                spread(&col(|x| x.plan_bend), |x| format!("{x:.3}")),
                spread(&col(|x| x.run_bend), bl)
            ),
            _ => "–".into(),
        };
        println!(
            "| {scenario} | {tracker} | {reached}/{} | {} | {} | {} | {recover} | {} | {} | {row} |",
            f.len(),
            spread(&col(|x| x.plan_s), |x| format!("{x:.0}")),
            spread(&col(|x| x.progress), percent),
            spread(&col(|x| x.max_error), bl),
            spread(&col(|x| x.final_distance), |x| format!("{x:.1}")),
            spread(&col(|x| x.shape), bl),
        );
    }
}
