//! The planners' headline figures on micro-factory, over 50 seeds (one thread), for
//! goal-zoom-rrt with the paper's settings and with aimed gradients, the guide path and edges up
//! to 5 s ([`CONFIGS`], one column each):
//!
//! - the median time to first solution (and its quartiles);
//! - its median iterations to first solution (and their quartiles);
//! - iterations per second (all iterations / all time);
//! - bytes per tree node: the peak of the heap bytes a `solve` holds (tree arrays with their
//!   growth slack, k-d tree, buffers, the plan; a counting global allocator) divided by the
//!   tree's nodes.
//!
//! The figures are printed as a Markdown table (`cargo xtask measure --only planner-figures`
//! keeps it).
//!
//! ```sh
//! cargo bench -p magbench-benches --bench planner_figures [-- SEEDS]
//! ```

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use magbench_env::Scenario;
use magbench_planners::nn::NearestNeighbors;
use magbench_planners::{Limits, Planners, Problem};

/// Counts live heap bytes and their peak.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let now = LIVE.fetch_add(l.size(), Ordering::Relaxed) + l.size();
        PEAK.fetch_max(now, Ordering::Relaxed);
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        LIVE.fetch_sub(l.size(), Ordering::Relaxed);
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        if new > l.size() {
            let now = LIVE.fetch_add(new - l.size(), Ordering::Relaxed) + new - l.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        } else {
            LIVE.fetch_sub(l.size() - new, Ordering::Relaxed);
        }
        unsafe { System.realloc(p, l, new) }
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

fn quartiles(v: &mut [f64]) -> (f64, f64, f64) {
    v.sort_by(f64::total_cmp);
    let q = |f: f64| v[((v.len() - 1) as f64 * f).round() as usize];
    (q(0.25), q(0.5), q(0.75))
}

/// goal-zoom-rrt's settings measured, one column each: the paper's, and aimed gradients with
/// the guide path and edges up to 5 s.
const CONFIGS: [&[(&str, &str)]; 2] = [
    &[],
    &[("aim", "true"), ("guide", "true"), ("max_duration", "5")],
];

/// One column's figures over the seeds.
#[derive(Default)]
struct Figures {
    solved: u64,
    times: Vec<f64>,
    first_iterations: Vec<f64>,
    iterations: u64,
    seconds: f64,
    per_node: Vec<f64>,
    tree_bytes: Vec<f64>,
    kd_bytes: Vec<f64>,
}

fn measure(s: &Scenario, seeds: u64, params: &[(&str, &str)]) -> Figures {
    let params: Vec<(String, String)> = params
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    let mut f = Figures::default();
    for seed in 0..seeds {
        let mut p = Problem::from_scenario(s, 0, None, seed);
        p.limits = Limits {
            max_iterations: Some(200_000),
            time_limit: None,
        };
        let mut planner = Planners::builtin()
            .create("goal-zoom-rrt", &params)
            .unwrap();
        let base = LIVE.load(Ordering::Relaxed);
        PEAK.store(base, Ordering::Relaxed);
        let r = planner.solve(&p);
        f.per_node
            .push((PEAK.load(Ordering::Relaxed) - base) as f64 / r.nodes as f64);
        if let Some(tree) = planner.tree() {
            f.tree_bytes
                .push(tree.heap_bytes() as f64 / tree.len() as f64);
            // the k-d tree alone, rebuilt in the same insertion order
            let before = LIVE.load(Ordering::Relaxed);
            let mut nn = NearestNeighbors::new(p.metric, p.agents());
            for i in 0..tree.slots() as u32 {
                nn.add(tree.state(i), i);
            }
            f.kd_bytes
                .push((LIVE.load(Ordering::Relaxed) - before) as f64 / tree.len() as f64);
        }
        f.iterations += r.iterations;
        f.seconds += r.time_s;
        if let Some((i, t)) = r.first_solution {
            f.times.push(t);
            f.first_iterations.push(i as f64);
            f.solved += 1;
        }
    }
    f
}

fn main() {
    let seeds: u64 = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(50);
    let s = Scenario::load("micro-factory").unwrap();
    let mut columns: Vec<Figures> = CONFIGS.iter().map(|c| measure(&s, seeds, c)).collect();
    let names: Vec<String> = CONFIGS
        .iter()
        .map(|c| {
            let set: Vec<String> = c.iter().map(|(k, v)| format!("{k}={v}")).collect();
            if set.is_empty() {
                "goal-zoom-rrt".to_string()
            } else {
                format!("goal-zoom-rrt{{{}}}", set.join(","))
            }
        })
        .collect();
    println!("goal-zoom-rrt on micro-factory, {seeds} seeds, one thread\n");
    println!("| figure | {} |", names.join(" | "));
    println!("| --- |{}", " --- |".repeat(names.len()));
    let row = |label: &str, cells: Vec<String>| println!("| {label} | {} |", cells.join(" | "));
    row(
        "runs solved",
        columns
            .iter()
            .map(|f| format!("{}/{seeds}", f.solved))
            .collect(),
    );
    row(
        "time to first solution, median (quartiles)",
        columns
            .iter_mut()
            .map(|f| {
                let (t1, t2, t3) = quartiles(&mut f.times);
                format!("{:.1} ms ({:.1}–{:.1} ms)", t2 * 1e3, t1 * 1e3, t3 * 1e3)
            })
            .collect(),
    );
    row(
        "iterations to first solution, median (quartiles)",
        columns
            .iter_mut()
            .map(|f| {
                let (i1, i2, i3) = quartiles(&mut f.first_iterations);
                format!("{i2:.0} ({i1:.0}–{i3:.0})")
            })
            .collect(),
    );
    row(
        "iterations per second (all iterations / all time)",
        columns
            .iter()
            .map(|f| format!("{:.0}", f.iterations as f64 / f.seconds))
            .collect(),
    );
    row(
        "peak heap bytes per tree node, median (quartiles)",
        columns
            .iter_mut()
            .map(|f| {
                let (b1, b2, b3) = quartiles(&mut f.per_node);
                format!("{b2:.0} B ({b1:.0}–{b3:.0} B)")
            })
            .collect(),
    );
    row(
        "of which tree arrays, median",
        columns
            .iter_mut()
            .map(|f| format!("{:.0} B", quartiles(&mut f.tree_bytes).1))
            .collect(),
    );
    row(
        "of which k-d tree, median",
        columns
            .iter_mut()
            .map(|f| format!("{:.0} B", quartiles(&mut f.kd_bytes).1))
            .collect(),
    );
}
