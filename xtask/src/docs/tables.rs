//! How a measurement's runs become its table: one function per kind of table.

use magbench::metrics::Metric;
use magbench::results::summary::groups;
use magbench::run::RunRecord;
use magbench::table::{Table, int, median, median_p90, quantile};

/// The values of metric `m` over `runs` that have it.
pub(super) fn values(runs: &[&RunRecord], m: Metric) -> Vec<f64> {
    runs.iter().filter_map(|r| r.get(m)).collect()
}

/// A scenario as a reader knows it: a file's stem (`../scenarios/trio-row.toml`: `trio-row`),
/// or the built-in name.
pub(super) fn scenario(label: &str) -> String {
    match label.strip_suffix(".toml") {
        Some(path) => path.rsplit('/').next().unwrap_or(path).to_string(),
        None => label.to_string(),
    }
}

/// Iterations per second of each run that has both: iterations ÷ planning time.
fn rates(runs: &[&RunRecord]) -> Vec<f64> {
    runs.iter()
        .filter_map(|r| Some(r.get(Metric::Iterations)? / r.get(Metric::PlanTime)?))
        .collect()
}

/// The configurations of `runs` that tracked, each its runs.
fn tracked(runs: &[RunRecord]) -> Vec<Vec<&RunRecord>> {
    groups(runs)
        .into_iter()
        .filter(|g| !g[0].tracker.is_empty())
        .collect()
}

/// A tracked configuration's first cells: scenario, tracker, preset, and the runs that reached
/// the goal of all.
fn tracked_cells(g: &[&RunRecord]) -> Vec<String> {
    vec![
        scenario(&g[0].scenario),
        g[0].tracker.clone(),
        g[0].preset.clone(),
        share(g, |r| r.reached_goal == Some(true)),
    ]
}

/// The runs of `g` for which `f` holds, out of all: `k/n`.
pub(super) fn share(g: &[&RunRecord], f: impl Fn(&RunRecord) -> bool) -> String {
    format!("{}/{}", g.iter().filter(|r| f(r)).count(), g.len())
}

/// Planning to a first solution: per scenario and planner, runs solved, iterations to the first
/// solution (median / max), its time (median) and iterations per second (median over runs of
/// iterations ÷ planning time).
pub fn planning(runs: &[RunRecord]) -> Table {
    let mut t = Table::new(&[
        "scenario",
        "planner",
        "solved",
        "iterations to 1st solution, median / max",
        "time to 1st solution, median (s)",
        "iterations/s, median",
    ]);
    for g in groups(runs) {
        let it = values(&g, Metric::FirstSolutionIteration);
        let max = quantile(&it, 1.0).map(int).unwrap_or_else(|| "–".into());
        t.row(vec![
            scenario(&g[0].scenario),
            g[0].planner.clone(),
            share(&g, |r| r.solved),
            format!("{} / {max}", median(&it)),
            median(&values(&g, Metric::FirstSolutionTime)),
            median(&rates(&g)),
        ]);
    }
    t
}

/// Planners side by side to a first solution: per scenario and planner, runs solved, its time
/// (median over solved runs, s), the plan's cost (median over solved runs) and iterations per
/// second (median over runs of iterations ÷ planning time).
pub fn first_solution(runs: &[RunRecord]) -> Table {
    let mut t = Table::new(&[
        "scenario",
        "planner",
        "solved",
        "time to 1st solution, median (s)",
        "cost, median",
        "iterations/s, median",
    ]);
    for g in groups(runs) {
        let solved: Vec<&RunRecord> = g.iter().copied().filter(|r| r.solved).collect();
        t.row(vec![
            scenario(&g[0].scenario),
            g[0].planner.clone(),
            share(&g, |r| r.solved),
            median(&values(&solved, Metric::FirstSolutionTime)),
            median(&values(&solved, Metric::Cost)),
            median(&rates(&g)),
        ]);
    }
    t
}

/// Closed-loop tracking: per tracker and preset, goal reached, agent contacts, the path, true,
/// team-synchronous and time-indexed RMS errors and the max observed error (median / p90, BL),
/// wall contacts over all runs and the median time to goal.
pub fn tracking(runs: &[RunRecord]) -> Table {
    let mut t = Table::new(&[
        "scenario",
        "tracker",
        "preset",
        "goal reached",
        "agent contact",
        "path",
        "true",
        "sync",
        "time",
        "max (observed)",
        "wall contacts (all runs)",
        "replans (all runs)",
        "time to goal, median (s)",
    ]);
    for g in tracked(runs) {
        let sum = |m| values(&g, m).iter().sum::<f64>();
        let mut row = tracked_cells(&g);
        row.extend([
            g.iter()
                .filter(|r| r.agent_contact == Some(true))
                .count()
                .to_string(),
            median_p90(&values(&g, Metric::RmsError)),
            median_p90(&values(&g, Metric::RmsErrorTrue)),
            median_p90(&values(&g, Metric::RmsErrorSync)),
            median_p90(&values(&g, Metric::RmsErrorTime)),
            median_p90(&values(&g, Metric::MaxError)),
            int(sum(Metric::WallContacts)),
            int(sum(Metric::Replans)),
            median(&values(&g, Metric::TimeToGoal)),
        ]);
        t.row(row);
    }
    t
}

/// What a tracker setting costs against how it tracks: per scenario, tracker and preset, runs
/// that reached the goal, the observed and true RMS errors (median / p90, BL) and the whole
/// simulated loop's wall time per simulated second (median over runs of tracking wall time ÷
/// tracking duration; plant, camera, estimator, tracker and metrics together).
pub fn loop_cost(runs: &[RunRecord]) -> Table {
    let mut t = Table::new(&[
        "scenario",
        "tracker",
        "preset",
        "goal reached",
        "path",
        "true",
        "loop wall time per simulated s, median (ms)",
    ]);
    for g in tracked(runs) {
        let per_s: Vec<f64> = g
            .iter()
            .filter_map(|r| Some(1e3 * r.get(Metric::TrackTime)? / r.get(Metric::TrackDuration)?))
            .collect();
        let mut row = tracked_cells(&g);
        row.extend([
            median_p90(&values(&g, Metric::RmsError)),
            median_p90(&values(&g, Metric::RmsErrorTrue)),
            median(&per_s),
        ]);
        t.row(row);
    }
    t
}

/// Each error metric of the tracked runs, median / p90 (BL), one row per metric and
/// configuration: the seed's node error beside magbench's path errors.
pub fn errors(runs: &[RunRecord]) -> Table {
    let mut t = Table::new(&["configuration", "metric", "median / p90 (BL)"]);
    let metrics = [
        Metric::RmsErrorNode,
        Metric::RmsErrorNodeTrue,
        Metric::NodeFloor,
        Metric::RmsErrorSync,
        Metric::RmsError,
        Metric::RmsErrorTrue,
    ];
    for g in tracked(runs) {
        let label = format!("{} + {} ({})", g[0].planner, g[0].tracker, g[0].preset);
        for m in metrics {
            t.row(vec![
                label.clone(),
                format!("`{}`", m.def().column),
                median_p90(&values(&g, m)),
            ]);
        }
    }
    t
}
