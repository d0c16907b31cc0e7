//! Best cost at fixed wall times, with intervals: each planner's anytime curve read at a few
//! times from a sweep's progress traces (`progress.csv`).

use std::path::Path;

use statrs::distribution::{Binomial, DiscreteCDF};

use super::convergence::Traces;
use super::family_tables::{by_family, family};
use super::tables::scenario;
use magbench::Error;
use magbench::results::manifest::Manifest;
use magbench::results::store::read_progress;
use magbench::results::summary::groups;
use magbench::run::{ProgressRow, RunRecord};
use magbench::stats::quantile::{quantile_sorted, sorted_finite};
use magbench::table::{Table, num};

/// The wall times the table reads the curves at (s).
pub const TIMES: [f64; 3] = [0.1, 1.0, 10.0];

/// The interval's confidence: 95%, two-sided.
const LEVEL: f64 = 0.95;

/// The best cost of `trace` (in time order) at `t` seconds of planning, if it had a solution by
/// then.
pub fn best_at_time(trace: &[&ProgressRow], t: f64) -> Option<f64> {
    trace
        .iter()
        .take_while(|p| p.time_s <= t)
        .filter_map(|p| p.best_cost)
        .last()
}

/// The ranks (1-based, into the sorted sample) of the distribution-free interval for the median
/// of `n` values at [`LEVEL`]: `(l, n + 1 − l)` with `l` the largest rank for which
/// `P(B ≤ l − 1) ≤ (1 − LEVEL)/2`, `B ~ Binomial(n, ½)`; `None` when `n` is too small for any.
pub fn median_interval_ranks(n: usize) -> Option<(usize, usize)> {
    let b = Binomial::new(0.5, n as u64).ok()?;
    let tail = (1.0 - LEVEL) / 2.0;
    let l = (1..=n / 2 + 1)
        .take_while(|&l| b.cdf(l as u64 - 1) <= tail)
        .last()?;
    Some((l, n + 1 - l))
}

/// `median [lo, hi]` of `v`, the interval of [`median_interval_ranks`] (`median [–]` when there
/// are too few values for it), or `–`.
fn median_with_interval(v: &[f64]) -> String {
    let s = sorted_finite(v);
    if s.is_empty() {
        return "–".into();
    }
    let m = num(quantile_sorted(&s, 0.5));
    match median_interval_ranks(s.len()) {
        Some((lo, hi)) => format!("{m} [{}, {}]", num(s[lo - 1]), num(s[hi - 1])),
        None => format!("{m} [–]"),
    }
}

/// Per scenario and planner: at each of [`TIMES`], the median best cost over the runs solved by
/// then with its 95% interval, and how many runs had solved. Reads `progress.csv` of `dir`.
pub fn cost_at_time(dir: &Path, runs: &[RunRecord]) -> Result<Table, Error> {
    let rows = read_progress(dir)?;
    Ok(cost_at_time_of(runs, &rows))
}

/// [`cost_at_time`] of runs and their progress rows.
pub fn cost_at_time_of(runs: &[RunRecord], rows: &[ProgressRow]) -> Table {
    let traces = Traces::of(rows);
    let mut head: Vec<String> = vec!["scenario".into(), "planner".into()];
    head.extend(heads(&TIMES));
    let head: Vec<&str> = head.iter().map(String::as_str).collect();
    let mut table = Table::new(&head);
    for g in groups(runs).into_iter().filter(|g| g[0].tracker.is_empty()) {
        let mut row = vec![scenario(&g[0].scenario), g[0].planner.clone()];
        row.extend(cells(&traces, &g, &TIMES));
        table.row(row);
    }
    table
}

/// The column titles of [`cells`] at `times`.
fn heads(times: &[f64]) -> Vec<String> {
    times
        .iter()
        .flat_map(|&t| {
            [
                format!("best cost at {} s, median [95% interval]", num(t)),
                format!("solved by {} s", num(t)),
            ]
        })
        .collect()
}

/// At each of `times`: the median best cost of the runs of `group` solved by then, with its
/// 95% interval, and how many had solved.
fn cells(traces: &Traces, group: &[&RunRecord], times: &[f64]) -> Vec<String> {
    times
        .iter()
        .flat_map(|&t| {
            let costs = traces.best_costs(group, |trace| best_at_time(trace, t));
            [
                median_with_interval(&costs),
                format!("{}/{}", costs.len(), group.len()),
            ]
        })
        .collect()
}

/// [`by_family`] of a suite's sweep with [`cost_at_time`]'s columns after its own, at the
/// [`TIMES`] within the experiment's time limit (a run stopped by it has no later cost).
/// Reads `manifest.json` and `progress.csv` of `dir`.
pub fn by_family_at_times(dir: &Path, runs: &[RunRecord]) -> Result<Table, Error> {
    let limit = Manifest::read(dir)?.experiment.time_limit_s;
    let times: Vec<f64> = TIMES
        .into_iter()
        .filter(|&t| limit.is_none_or(|l| t <= l))
        .collect();
    let rows = read_progress(dir)?;
    let traces = Traces::of(&rows);
    let mut table = by_family(runs);
    table.head.extend(heads(&times));
    for row in &mut table.rows {
        let group: Vec<&RunRecord> = runs
            .iter()
            .filter(|r| r.planner == row[1] && family(&scenario(&r.scenario)) == row[0])
            .collect();
        row.extend(cells(&traces, &group, &times));
    }
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(run: usize, time_s: f64, best_cost: Option<f64>) -> ProgressRow {
        ProgressRow {
            run,
            run_id: format!("r{run}"),
            iteration: 0,
            time_s,
            best_cost,
        }
    }

    #[test]
    fn the_best_cost_is_the_last_one_at_or_before_the_time() {
        let rows = [
            point(0, 0.0, None),
            point(0, 0.05, Some(9.0)),
            point(0, 0.5, Some(7.0)),
            point(0, 3.0, Some(6.0)),
        ];
        let trace: Vec<&ProgressRow> = rows.iter().collect();
        assert_eq!(best_at_time(&trace, 0.01), None);
        assert_eq!(best_at_time(&trace, 0.1), Some(9.0));
        assert_eq!(best_at_time(&trace, 1.0), Some(7.0));
        assert_eq!(best_at_time(&trace, 10.0), Some(6.0));
    }

    #[test]
    fn the_median_interval_has_the_textbook_ranks() {
        // n = 10: (x₂, x₉), coverage 1 − 2·11/1024 ≈ 97.9%; n = 20: (x₆, x₁₅); n ≤ 5: none
        assert_eq!(median_interval_ranks(10), Some((2, 9)));
        assert_eq!(median_interval_ranks(20), Some((6, 15)));
        assert_eq!(median_interval_ranks(6), Some((1, 6)));
        assert_eq!(median_interval_ranks(5), None);
        assert_eq!(median_interval_ranks(0), None);
    }
}
