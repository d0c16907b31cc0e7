//! One value per planner and problem: the median time to a first exact solution over the
//! planner's seeds (+∞ when half or more of them found none) and how many seeds solved it;
//! and one set of difficulty measures per problem, read from its runs' difficulty columns.

use crate::metrics::Metric;
use crate::metrics::difficulty::Measures;
use crate::run::RunRecord;

/// Planners × problems of the planning runs (runs without a tracker) of a results folder.
#[derive(Debug, Clone, PartialEq)]
pub struct Instances {
    /// Planner labels, in first-seen order.
    pub planners: Vec<String>,
    /// Problems (scenario labels), in first-seen order.
    pub problems: Vec<String>,
    /// `time[p][i]`: planner `p`'s median time to a first solution on problem `i` (s); +∞
    /// when the median run is unsolved, NaN when the planner has no run of the problem.
    pub time: Vec<Vec<f64>>,
    /// `solved[p][i]`: (runs solved, runs) of planner `p` on problem `i`.
    pub solved: Vec<Vec<(u64, u64)>>,
    /// `difficulty[i]`: the difficulty measures of problem `i` (from its first run that has
    /// them; empty for runs of a `runs.csv` without the columns).
    pub difficulty: Vec<Measures>,
}

/// The median of `v` where +∞ stands for an unsolved run: +∞ when a middle value is; NaN
/// for an empty `v`.
pub fn median_inf(v: &[f64]) -> f64 {
    let mut s: Vec<f64> = v.iter().copied().filter(|x| !x.is_nan()).collect();
    if s.is_empty() {
        return f64::NAN;
    }
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        let (a, b) = (s[n / 2 - 1], s[n / 2]);
        if b.is_infinite() { b } else { 0.5 * (a + b) }
    }
}

impl Instances {
    /// The table of the planning runs in `runs`.
    pub fn of(runs: &[RunRecord]) -> Instances {
        let mut planners: Vec<String> = vec![];
        let mut problems: Vec<String> = vec![];
        let planning: Vec<&RunRecord> = runs.iter().filter(|r| r.tracker.is_empty()).collect();
        for r in &planning {
            if !planners.contains(&r.planner) {
                planners.push(r.planner.clone());
            }
            if !problems.contains(&r.scenario) {
                problems.push(r.scenario.clone());
            }
        }
        let mut times = vec![vec![vec![]; problems.len()]; planners.len()];
        let mut solved = vec![vec![(0, 0); problems.len()]; planners.len()];
        let mut difficulty = vec![Measures::default(); problems.len()];
        for r in &planning {
            let p = planners.iter().position(|x| *x == r.planner).unwrap_or(0);
            let i = problems.iter().position(|x| *x == r.scenario).unwrap_or(0);
            let t = match (r.solved, r.get(Metric::FirstSolutionTime)) {
                (true, Some(t)) => t,
                _ => f64::INFINITY,
            };
            if difficulty[i].is_empty() {
                difficulty[i] = r.difficulty;
            }
            times[p][i].push(t);
            solved[p][i].1 += 1;
            if t.is_finite() {
                solved[p][i].0 += 1;
            }
        }
        let time = times
            .iter()
            .map(|row| row.iter().map(|v| median_inf(v)).collect())
            .collect();
        Instances {
            planners,
            problems,
            time,
            solved,
            difficulty,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::difficulty::Measure;

    #[test]
    fn median_counts_unsolved_as_infinite() {
        assert_eq!(median_inf(&[1.0, 3.0, 2.0]), 2.0);
        assert_eq!(median_inf(&[1.0, 3.0]), 2.0);
        assert_eq!(median_inf(&[1.0, f64::INFINITY]), f64::INFINITY);
        assert_eq!(median_inf(&[1.0, 2.0, f64::INFINITY]), 2.0);
        assert!(median_inf(&[]).is_nan());
    }

    #[test]
    fn table_groups_planning_runs_by_planner_and_problem() {
        let run = |sc: &str, pl: &str, t: Option<f64>, tracker: &str| {
            let mut r = RunRecord::example();
            r.difficulty
                .set(Measure::PathTurns, Some(if sc == "a" { 1.0 } else { 4.0 }));
            r.scenario = sc.into();
            r.planner = pl.into();
            r.solved = t.is_some();
            r.set(Metric::FirstSolutionTime, t);
            r.tracker = tracker.into();
            r
        };
        let runs = vec![
            run("a", "x", Some(1.0), ""),
            run("a", "x", Some(3.0), ""),
            run("a", "y", None, ""),
            run("b", "x", Some(5.0), ""),
            run("b", "y", Some(0.5), ""),
            run("b", "y", Some(9.0), "obc"),
        ];
        let t = Instances::of(&runs);
        assert_eq!(t.planners, ["x", "y"]);
        assert_eq!(t.problems, ["a", "b"]);
        assert_eq!(t.time[0], [2.0, 5.0]);
        assert_eq!(t.time[1], [f64::INFINITY, 0.5]);
        assert_eq!(t.solved[0], [(2, 2), (1, 1)]);
        assert_eq!(t.solved[1], [(0, 1), (1, 1)]);
        let turns: Vec<Option<f64>> = t
            .difficulty
            .iter()
            .map(|d| d.get(Measure::PathTurns))
            .collect();
        assert_eq!(turns, [Some(1.0), Some(4.0)]);
    }
}
