//! The table of the edge-length study (`edge-length`): what a longer edge buys in planning and
//! costs in tracking.

use super::tables::{scenario, share, values};
use magbench::metrics::Metric;
use magbench::results::summary::groups;
use magbench::run::RunRecord;
use magbench::table::{Table, median, median_p90};

/// Per scenario and planner (its `max_duration`): runs solved, iterations to the first
/// solution and the plan's cost (medians over solved runs), then the tracked runs that reached
/// the goal (of all) and their RMS path error (median / p90, BL).
pub fn edge_length(runs: &[RunRecord]) -> Table {
    let mut t = Table::new(&[
        "scenario",
        "planner",
        "solved",
        "iterations to 1st solution, median",
        "cost, median",
        "tracker",
        "goal reached",
        "path error (observed)",
    ]);
    for g in groups(runs) {
        let solved: Vec<&RunRecord> = g.iter().copied().filter(|r| r.solved).collect();
        t.row(vec![
            scenario(&g[0].scenario),
            g[0].planner.clone(),
            share(&g, |r| r.solved),
            median(&values(&solved, Metric::FirstSolutionIteration)),
            median(&values(&solved, Metric::Cost)),
            g[0].tracker.clone(),
            share(&g, |r| r.reached_goal == Some(true)),
            median_p90(&values(&g, Metric::RmsError)),
        ]);
    }
    t
}
