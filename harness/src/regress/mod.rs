//! Regression checks between two results folders (a baseline and a current run).
//!
//! Per configuration (scenario, planner, tracker, preset) present in both:
//!
//! - success rate: one-sided pooled two-proportion z test (is the current rate lower?), and a
//!   regression only if the rate also dropped by more than `success_tolerance` (absolute);
//! - continuous metrics, lower is better (tracking RMS and max error, final cost, iterations and
//!   time to the first solution, planning time): one-sided Mann–Whitney U test (are current
//!   values larger?), and a regression only if the median also grew by more than the metric's
//!   relative tolerance. The change is reported with a seeded 95% bootstrap interval of the
//!   median difference.
//!
//! A table has many tests, so the p-values are adjusted with Holm's step-down method: the
//! chance of one or more false alarms over the whole table stays at `alpha`. A configuration
//! of the baseline missing from the current results is a regression too.
//!
//! Two stages over plain data, as criterion separates them: [`analysis`] turns two sets of runs
//! into [`Comparison`]s (numbers, p-values, verdicts), and [`report`] turns those into text.

pub mod analysis;
pub mod report;

pub use analysis::{Change, Comparison, METRICS, Tolerances, Value, Verdict, compare, holm};
pub use report::{footer, new_metrics, table};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::RunRecord;
    use crate::run::Status;

    fn runs(rms: &[f64], solved: usize) -> Vec<RunRecord> {
        rms.iter()
            .enumerate()
            .map(|(i, e)| {
                let mut r = RunRecord::example();
                (r.run, r.scenario, r.planner, r.tracker, r.preset) =
                    (i, "s".into(), "p".into(), "t".into(), "ideal".into());
                r.solved = i < solved;
                r.status = if r.solved {
                    Status::Exact
                } else {
                    Status::Approximate
                };
                r.reached_goal = Some(r.solved);
                r.agent_contact = Some(false);
                r.rms_error_bl = Some(*e);
                r
            })
            .collect()
    }

    fn verdict(rows: &[Comparison], metric: &str) -> Verdict {
        rows.iter().find(|r| r.metric == metric).unwrap().verdict
    }

    #[test]
    fn flags_doubled_error_and_passes_noise() {
        let base: Vec<f64> = (0..20).map(|i| 0.1 + 0.002 * i as f64).collect();
        let same: Vec<f64> = (0..20)
            .map(|i| 0.101 + 0.002 * ((i * 7) % 20) as f64)
            .collect();
        let worse: Vec<f64> = base.iter().map(|v| 2.0 * v).collect();
        let tol = Tolerances::default();
        assert_eq!(
            verdict(
                &compare(&runs(&base, 20), &runs(&same, 20), &tol),
                "rms_error_bl"
            ),
            Verdict::Ok
        );
        assert_eq!(
            verdict(
                &compare(&runs(&base, 20), &runs(&worse, 20), &tol),
                "rms_error_bl"
            ),
            Verdict::Regression
        );
        assert_eq!(
            verdict(
                &compare(&runs(&worse, 20), &runs(&base, 20), &tol),
                "rms_error_bl"
            ),
            Verdict::Improved
        );
        // Significant but within the tolerance: 3% worse everywhere.
        let slightly: Vec<f64> = base.iter().map(|v| 1.03 * v).collect();
        assert_eq!(
            verdict(
                &compare(&runs(&base, 20), &runs(&slightly, 20), &tol),
                "rms_error_bl"
            ),
            Verdict::Ok
        );
    }

    #[test]
    fn slower_times_are_reported_but_not_gated_by_default() {
        let e = vec![0.1; 20];
        let mut slow = runs(&e, 20);
        slow.iter_mut()
            .enumerate()
            .for_each(|(i, r)| r.plan_time_s = 3.0 + 0.01 * i as f64);
        let mut fast = runs(&e, 20);
        fast.iter_mut()
            .enumerate()
            .for_each(|(i, r)| r.plan_time_s = 1.0 + 0.01 * i as f64);
        let tol = Tolerances::default();
        assert_eq!(
            verdict(&compare(&fast, &slow, &tol), "plan_time_s"),
            Verdict::Slower
        );
        let gated = Tolerances {
            gate_time: true,
            ..tol
        };
        assert_eq!(
            verdict(&compare(&fast, &slow, &gated), "plan_time_s"),
            Verdict::Regression
        );
        let off = Tolerances {
            wall_clock: false,
            ..tol
        };
        assert!(
            compare(&fast, &slow, &off)
                .iter()
                .all(|r| r.metric != "plan_time_s")
        );
    }

    #[test]
    fn holm_adjusts_step_down() {
        // p = (0.01, 0.04, 0.03, 0.005) → sorted 0.005, 0.01, 0.03, 0.04 → 0.02, 0.03, 0.06, 0.06.
        let a = holm(&[0.01, 0.04, 0.03, 0.005]);
        let want = [0.03, 0.06, 0.06, 0.02];
        for (x, y) in a.iter().zip(want) {
            assert!((x - y).abs() < 1e-12, "{a:?}");
        }
    }

    #[test]
    fn flags_a_success_drop_and_a_missing_configuration() {
        let e = vec![0.1; 30];
        let tol = Tolerances::default();
        assert_eq!(
            verdict(&compare(&runs(&e, 29), &runs(&e, 15), &tol), "success_rate"),
            Verdict::Regression
        );
        assert_eq!(
            verdict(&compare(&runs(&e, 29), &runs(&e, 27), &tol), "success_rate"),
            Verdict::Ok
        );
        let mut other = runs(&e, 29);
        other.iter_mut().for_each(|r| r.preset = "realistic".into());
        assert_eq!(
            verdict(&compare(&runs(&e, 29), &other, &tol), "runs"),
            Verdict::Missing
        );
        assert!(table(&compare(&runs(&e, 29), &other, &tol)).contains("MISSING"));
    }

    /// Three-agent runs whose agent 2 has RMS error `e2` (agents 0 and 1: 0.1), true errors
    /// 80% of those.
    fn trio(e2: &[f64]) -> Vec<RunRecord> {
        let mut rs = runs(&vec![0.1; e2.len()], e2.len());
        for (r, &e) in rs.iter_mut().zip(e2) {
            r.agents = 3;
            r.per_agent = [0.1, 0.1, e]
                .iter()
                .map(|&x| crate::run::record::AgentErrors {
                    rms_bl: Some(x),
                    max_bl: Some(3.0 * x),
                    rms_true_bl: Some(0.8 * x),
                    max_true_bl: Some(2.4 * x),
                })
                .collect();
            r.rms_error_worst_agent_bl = Some(e.max(0.1));
        }
        rs
    }

    #[test]
    fn per_agent_errors_are_compared_and_a_drifting_agent_is_flagged() {
        let base: Vec<f64> = (0..20).map(|i| 0.2 + 0.003 * i as f64).collect();
        let worse: Vec<f64> = base.iter().map(|v| 2.0 * v).collect();
        let rows = compare(&trio(&base), &trio(&worse), &Tolerances::default());
        assert_eq!(verdict(&rows, "rms_error_agent2_bl"), Verdict::Regression);
        assert_eq!(
            verdict(&rows, "rms_error_true_agent2_bl"),
            Verdict::Regression
        );
        assert_eq!(
            verdict(&rows, "rms_error_worst_agent_bl"),
            Verdict::Regression
        );
        assert_eq!(verdict(&rows, "rms_error_agent0_bl"), Verdict::Ok);
        // the team's RMS did not move: only the per-agent view sees the drift
        assert_eq!(verdict(&rows, "rms_error_bl"), Verdict::Ok);
        assert!(new_metrics(&rows).is_empty());
    }

    #[test]
    fn a_baseline_without_per_agent_columns_compares_cleanly() {
        let e: Vec<f64> = (0..20).map(|i| 0.2 + 0.003 * i as f64).collect();
        // an old baseline: no per-agent, worst-true or true-max values
        let mut old = trio(&e);
        for r in &mut old {
            r.per_agent.clear();
            r.rms_error_true_worst_agent_bl = None;
        }
        let mut cur = trio(&e);
        for r in &mut cur {
            r.rms_error_true_worst_agent_bl = Some(0.16);
        }
        let rows = compare(&old, &cur, &Tolerances::default());
        assert_eq!(report::regressions(&rows), 0);
        assert_eq!(verdict(&rows, "rms_error_agent1_bl"), Verdict::New);
        assert_eq!(verdict(&rows, "rms_error_bl"), Verdict::Ok);
        assert_eq!(
            new_metrics(&rows),
            [
                "rms_error_true_worst_agent_bl",
                "rms_error_agent0_bl",
                "rms_error_true_agent0_bl",
                "rms_error_agent1_bl",
                "rms_error_true_agent1_bl",
                "rms_error_agent2_bl",
                "rms_error_true_agent2_bl",
            ]
        );
        let text = footer(&rows, &Tolerances::default());
        assert!(
            text.starts_with("new since the baseline (not compared): rms_error_true_worst_agent_bl, rms_error_agent0_bl,"),
            "{text}"
        );
        assert!(text.contains("no regression"), "{text}");
        assert!(table(&rows).contains("new (not in baseline)"));
    }
}
