//! The convergence table: each planner's best cost at a few iteration counts, read from the
//! progress traces of a sweep (`progress.csv`).
//!
//! A trace has a point at every change of the best cost, so the best cost after `n` iterations
//! is the cost of the run's last point at or before `n`; a run that stopped earlier (at its first
//! solution, or at its limit) keeps its last cost.

use std::collections::HashMap;
use std::path::Path;

use magbench::Error;
use magbench::metrics::Metric;
use magbench::results::store::read_progress;
use magbench::results::summary::groups;
use magbench::run::{ProgressRow, RunRecord};
use magbench::table::{Table, median, num};

/// Iteration counts shown: the largest iteration any trace reached, and the three largest
/// values of 1, 2, 5, 10, 20, 50, … below it.
pub fn checkpoints(last: u64) -> Vec<u64> {
    let mut below = vec![];
    let mut decade = 1u64;
    'outer: loop {
        for k in [1, 2, 5] {
            let v = k * decade;
            if v >= last {
                break 'outer;
            }
            below.push(v);
        }
        decade = match decade.checked_mul(10) {
            Some(d) => d,
            None => break,
        };
    }
    let mut out: Vec<u64> = below.into_iter().rev().take(3).collect();
    out.reverse();
    if last > 0 {
        out.push(last);
    }
    out
}

/// The best cost of `trace` (in iteration order) after `n` iterations, if it had a solution by
/// then.
pub fn best_at(trace: &[&ProgressRow], n: u64) -> Option<f64> {
    trace
        .iter()
        .take_while(|p| p.iteration <= n)
        .filter_map(|p| p.best_cost)
        .last()
}

/// `12.3k` for 12 300, `200k` for 200 000, `950` for 950.
fn iterations(n: u64) -> String {
    match n {
        n if n >= 1000 && n % 1000 == 0 => format!("{}k", n / 1000),
        n if n >= 1000 => format!("{}k", num(n as f64 / 1000.0)),
        n => n.to_string(),
    }
}

/// Per scenario and planner: the median best cost after each of [`checkpoints`] iterations over
/// the runs solved by then (with how many), the median planning time and tree nodes. Reads
/// `progress.csv` of `dir`.
pub fn convergence(dir: &Path, runs: &[RunRecord]) -> Result<Table, Error> {
    let rows = read_progress(dir)?;
    Ok(convergence_of(runs, &rows))
}

/// Each run's progress rows, in iteration order: also time order, since a trace records the
/// clock as the iterations go (the later legs of a run after the earlier).
pub struct Traces<'a>(HashMap<usize, Vec<&'a ProgressRow>>);

impl<'a> Traces<'a> {
    /// The traces of `rows`.
    pub fn of(rows: &'a [ProgressRow]) -> Self {
        let mut traces: HashMap<usize, Vec<&ProgressRow>> = HashMap::new();
        for p in rows {
            traces.entry(p.run).or_default().push(p);
        }
        for t in traces.values_mut() {
            t.sort_by_key(|p| p.iteration);
        }
        Traces(traces)
    }

    /// The best costs of the runs of `group` as `best` reads them off each run's trace (a run
    /// without a trace has none), the runs without one left out.
    pub fn best_costs(
        &self,
        group: &[&RunRecord],
        best: impl Fn(&[&ProgressRow]) -> Option<f64>,
    ) -> Vec<f64> {
        group
            .iter()
            .filter_map(|r| best(self.0.get(&r.run).map_or(&[], Vec::as_slice)))
            .collect()
    }
}

/// [`convergence`] of runs and their progress rows.
pub fn convergence_of(runs: &[RunRecord], rows: &[ProgressRow]) -> Table {
    let traces = Traces::of(rows);
    let last = rows.iter().map(|p| p.iteration).max().unwrap_or(0);
    let marks = checkpoints(last);
    let mut head: Vec<String> = vec!["scenario".into(), "planner".into()];
    head.extend(
        marks
            .iter()
            .map(|&n| format!("best cost at {} iterations, median (solved)", iterations(n))),
    );
    head.push("planning time, median (s)".into());
    head.push("tree nodes, median".into());
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    let mut t = Table::new(&head);
    for g in groups(runs).into_iter().filter(|g| g[0].tracker.is_empty()) {
        let mut row = vec![
            super::tables::scenario(&g[0].scenario),
            g[0].planner.clone(),
        ];
        for &n in &marks {
            let costs = traces.best_costs(&g, |trace| best_at(trace, n));
            row.push(match costs.is_empty() {
                true => format!("– (0/{})", g.len()),
                false => format!("{} ({}/{})", median(&costs), costs.len(), g.len()),
            });
        }
        let of = |m| g.iter().filter_map(|r| r.get(m)).collect::<Vec<f64>>();
        row.push(median(&of(Metric::PlanTime)));
        row.push(median(&of(Metric::Nodes)));
        t.row(row);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(run: usize, iteration: u64, best_cost: Option<f64>) -> ProgressRow {
        ProgressRow {
            run,
            run_id: format!("r{run}"),
            iteration,
            time_s: 0.0,
            best_cost,
        }
    }

    #[test]
    fn checkpoints_end_at_the_last_iteration() {
        assert_eq!(checkpoints(10_000), vec![1000, 2000, 5000, 10_000]);
        assert_eq!(checkpoints(200_000), vec![20_000, 50_000, 100_000, 200_000]);
        assert_eq!(checkpoints(30_000), vec![5000, 10_000, 20_000, 30_000]);
        assert_eq!(checkpoints(3), vec![1, 2, 3]);
        assert_eq!(checkpoints(0), Vec::<u64>::new());
    }

    #[test]
    fn the_best_cost_is_the_last_one_at_or_before_n() {
        let rows = [
            point(0, 0, None),
            point(0, 40, Some(9.0)),
            point(0, 70, Some(7.0)),
            point(0, 100, Some(7.0)),
        ];
        let trace: Vec<&ProgressRow> = rows.iter().collect();
        assert_eq!(best_at(&trace, 39), None);
        assert_eq!(best_at(&trace, 40), Some(9.0));
        assert_eq!(best_at(&trace, 69), Some(9.0));
        assert_eq!(best_at(&trace, 1000), Some(7.0));
    }

    #[test]
    fn a_table_counts_the_runs_solved_by_each_mark() {
        let mut runs = vec![];
        for i in 0..2 {
            let mut r = RunRecord::example();
            r.run = i;
            r.scenario = "../scenarios/open-hall.toml".into();
            r.planner = "rrt-star".into();
            r.tracker = String::new();
            r.set(Metric::Nodes, Some(10.0));
            runs.push(r);
        }
        let rows = [
            point(0, 0, None),
            point(0, 3, Some(8.0)),
            point(0, 10, Some(6.0)),
            point(1, 0, None),
            point(1, 7, Some(4.0)),
            point(1, 10, Some(4.0)),
        ];
        let t = convergence_of(&runs, &rows);
        assert_eq!(t.head.len(), 2 + 4 + 2);
        assert_eq!(t.head[2], "best cost at 1 iterations, median (solved)");
        assert_eq!(t.rows.len(), 1);
        let r = &t.rows[0];
        assert_eq!(r[0], "open-hall");
        assert_eq!(r[2], "– (0/2)");
        assert_eq!(r[4], "8.00 (1/2)");
        assert_eq!(r[5], "5.00 (2/2)");
        assert_eq!(r[7], "10.0");
    }
}
