//! The planners' headline figures on micro-factory, over 50 seeds (one thread):
//!
//! - goal-zoom-rrt's median time to first solution (and its quartiles);
//! - its median iterations to first solution (and their quartiles);
//! - iterations per second (all iterations / all time);
//! - bytes per tree node: the peak of the heap bytes a `solve` holds (tree arrays with their
//!   growth slack, k-d tree, buffers, the plan; a counting global allocator) divided by the
//!   tree's nodes.
//!
//! The figures are printed as a Markdown table (`magbench docs measure --only planner-figures`
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

fn main() {
    let seeds: u64 = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(50);
    let s = Scenario::load("micro-factory").unwrap();
    let mut first_iterations = vec![];
    let (mut times, mut per_node, mut tree_bytes, mut kd_bytes) = (vec![], vec![], vec![], vec![]);
    let (mut iterations, mut seconds, mut solved) = (0u64, 0.0, 0);
    for seed in 0..seeds {
        let mut p = Problem::from_scenario(&s, 0, None, seed);
        p.limits = Limits {
            max_iterations: Some(200_000),
            time_limit: None,
        };
        let mut planner = Planners::builtin().create("goal-zoom-rrt", &[]).unwrap();
        let base = LIVE.load(Ordering::Relaxed);
        PEAK.store(base, Ordering::Relaxed);
        let r = planner.solve(&p);
        per_node.push((PEAK.load(Ordering::Relaxed) - base) as f64 / r.nodes as f64);
        if let Some(tree) = planner.tree() {
            tree_bytes.push(tree.heap_bytes() as f64 / tree.len() as f64);
            // the k-d tree alone, rebuilt in the same insertion order
            let before = LIVE.load(Ordering::Relaxed);
            let mut nn = NearestNeighbors::new(p.metric, p.agents());
            for i in 0..tree.slots() as u32 {
                nn.add(tree.state(i), i);
            }
            kd_bytes.push((LIVE.load(Ordering::Relaxed) - before) as f64 / tree.len() as f64);
        }
        iterations += r.iterations;
        seconds += r.time_s;
        if let Some((i, t)) = r.first_solution {
            times.push(t);
            first_iterations.push(i as f64);
            solved += 1;
        }
    }
    let (t1, t2, t3) = quartiles(&mut times);
    let (b1, b2, b3) = quartiles(&mut per_node);
    println!("goal-zoom-rrt on micro-factory, {seeds} seeds, one thread\n");
    println!("| figure | value |\n| --- | --- |");
    println!("| runs solved | {solved}/{seeds} |");
    println!(
        "| time to first solution, median (quartiles) | {:.1} ms ({:.1}–{:.1} ms) |",
        t2 * 1e3,
        t1 * 1e3,
        t3 * 1e3
    );
    let (i1, i2, i3) = quartiles(&mut first_iterations);
    println!("| iterations to first solution, median (quartiles) | {i2:.0} ({i1:.0}–{i3:.0}) |");
    println!(
        "| iterations per second (all iterations / all time) | {:.0} |",
        iterations as f64 / seconds
    );
    println!(
        "| peak heap bytes per tree node, median (quartiles) | {b2:.0} B ({b1:.0}–{b3:.0} B) |"
    );
    println!(
        "| of which tree arrays, median | {:.0} B |",
        quartiles(&mut tree_bytes).1
    );
    println!(
        "| of which k-d tree, median | {:.0} B |",
        quartiles(&mut kd_bytes).1
    );
}
