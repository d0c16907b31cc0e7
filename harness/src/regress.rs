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

use crate::results::summary::{groups, key};
use crate::run::RunRecord;
use crate::stats::{Alternative, mann_whitney_u, median, median_diff_ci, two_proportion_z};

/// Thresholds of a regression check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Significance level of each test.
    pub alpha: f64,
    /// Largest acceptable drop of the success rate (absolute, e.g. 0.1 = 10 points).
    pub success: f64,
    /// Largest acceptable relative growth of a median for error and cost metrics (0.1 = 10%).
    pub relative: f64,
    /// Largest acceptable relative growth of a median for wall-clock metrics (machines differ).
    pub time: f64,
    /// Compare wall-clock metrics at all.
    pub wall_clock: bool,
    /// Let wall-clock metrics fail the check. Off by default: times depend on the machine and
    /// its load, so a significant slowdown is reported as `slower` without failing.
    pub gate_time: bool,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            alpha: 0.01,
            success: 0.10,
            relative: 0.10,
            time: 1.0,
            wall_clock: true,
            gate_time: false,
        }
    }
}

/// The verdict on one metric.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// No significant change beyond the tolerance.
    Ok,
    /// Significantly better.
    Improved,
    /// Significantly worse, beyond the tolerance.
    Regression,
    /// Too few values to test.
    NoData,
    /// The configuration is missing from the current results.
    Missing,
    /// A wall-clock metric significantly slower beyond its tolerance, reported but not gated.
    Slower,
}

impl Verdict {
    /// Table text.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Ok => "ok",
            Verdict::Improved => "improved",
            Verdict::Regression => "REGRESSION",
            Verdict::NoData => "no data",
            Verdict::Missing => "MISSING",
            Verdict::Slower => "slower (not gated)",
        }
    }
}

/// One line of the comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Configuration label.
    pub config: String,
    /// Metric name.
    pub metric: String,
    /// Baseline value (median, or rate).
    pub baseline: String,
    /// Current value.
    pub current: String,
    /// Change, with its interval.
    pub change: String,
    /// Holm-adjusted p-value of the one-sided test for a regression.
    pub p: Option<f64>,
    /// Verdict.
    pub verdict: Verdict,
    /// Raw one-sided p-values (worse, better) and whether the change exceeds the tolerance.
    tests: Option<(f64, f64, bool, bool)>,
    /// A wall-clock metric.
    wall: bool,
}

/// Holm's step-down adjustment of `p` (family-wise error control).
pub fn holm(p: &[f64]) -> Vec<f64> {
    let m = p.len();
    let mut idx: Vec<usize> = (0..m).collect();
    idx.sort_by(|&a, &b| p[a].total_cmp(&p[b]));
    let mut adj = vec![0.0; m];
    let mut running: f64 = 0.0;
    for (k, &i) in idx.iter().enumerate() {
        running = running.max(((m - k) as f64 * p[i]).min(1.0));
        adj[i] = running;
    }
    adj
}

/// Sets the verdicts of tested rows from Holm-adjusted p-values.
fn decide(rows: &mut [Row], alpha: f64, gate_time: bool) {
    let tested: Vec<usize> = (0..rows.len())
        .filter(|&i| rows[i].tests.is_some())
        .collect();
    let worse = holm(
        &tested
            .iter()
            .map(|&i| rows[i].tests.unwrap().0)
            .collect::<Vec<_>>(),
    );
    let better = holm(
        &tested
            .iter()
            .map(|&i| rows[i].tests.unwrap().1)
            .collect::<Vec<_>>(),
    );
    for (k, &i) in tested.iter().enumerate() {
        let (_, _, beyond, improved) = rows[i].tests.unwrap();
        rows[i].p = Some(worse[k]);
        rows[i].verdict = if worse[k] < alpha && beyond && rows[i].wall && !gate_time {
            Verdict::Slower
        } else if worse[k] < alpha && beyond {
            Verdict::Regression
        } else if better[k] < alpha && improved {
            Verdict::Improved
        } else {
            Verdict::Ok
        };
    }
}

type Metric = (&'static str, fn(&RunRecord) -> Option<f64>, bool);

/// Continuous metrics checked (name, value, wall-clock?).
pub const METRICS: [Metric; 6] = [
    ("rms_error_bl", |r| r.rms_error_bl, false),
    ("max_error_bl", |r| r.max_error_bl, false),
    ("cost", |r| r.cost, false),
    (
        "first_solution_iteration",
        |r| r.first_solution_iteration.map(|i| i as f64),
        false,
    ),
    ("first_solution_time_s", |r| r.first_solution_time_s, true),
    ("plan_time_s", |r| Some(r.plan_time_s), true),
];

fn config_label(r: &RunRecord) -> String {
    let mut s = format!("{} / {}", r.scenario, r.planner);
    if !r.tracker.is_empty() {
        s += &format!(" / {} ({})", r.tracker, r.preset);
    }
    s
}

fn fmt(v: f64) -> String {
    if v != 0.0 && v.abs() < 0.01 {
        format!("{v:.3e}")
    } else if v.abs() >= 1000.0 || v == v.round() {
        format!("{v:.0}")
    } else if v.abs() >= 10.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.4}")
    }
}

/// Compares `current` against `baseline`.
pub fn compare(baseline: &[RunRecord], current: &[RunRecord], tol: &Tolerances) -> Vec<Row> {
    let cur_groups = groups(current);
    let mut rows = vec![];
    for b in groups(baseline) {
        let config = config_label(b[0]);
        let Some(c) = cur_groups.iter().find(|g| key(g[0]) == key(b[0])) else {
            rows.push(Row {
                config,
                metric: "runs".into(),
                baseline: b.len().to_string(),
                current: "0".into(),
                change: "–".into(),
                p: None,
                verdict: Verdict::Missing,
                tests: None,
                wall: false,
            });
            continue;
        };
        // Success rate.
        let (sb, nb) = (
            b.iter().filter(|r| r.success()).count() as u64,
            b.len() as u64,
        );
        let (sc, nc) = (
            c.iter().filter(|r| r.success()).count() as u64,
            c.len() as u64,
        );
        let (rb, rc) = (sb as f64 / nb as f64, sc as f64 / nc as f64);
        let (_, p_worse) = two_proportion_z(sc, nc, sb, nb, Alternative::Less);
        let (_, p_better) = two_proportion_z(sc, nc, sb, nb, Alternative::Greater);
        rows.push(Row {
            config: config.clone(),
            metric: "success_rate".into(),
            baseline: format!("{:.1}% ({sb}/{nb})", 100.0 * rb),
            current: format!("{:.1}% ({sc}/{nc})", 100.0 * rc),
            change: format!("{:+.1} points", 100.0 * (rc - rb)),
            p: None,
            verdict: Verdict::Ok,
            tests: Some((p_worse, p_better, rb - rc > tol.success, rc > rb)),
            wall: false,
        });
        for (name, f, wall) in METRICS {
            if wall && !tol.wall_clock {
                continue;
            }
            let xb: Vec<f64> = b
                .iter()
                .filter_map(|r| f(r))
                .filter(|v| v.is_finite())
                .collect();
            let xc: Vec<f64> = c
                .iter()
                .filter_map(|r| f(r))
                .filter(|v| v.is_finite())
                .collect();
            if xb.is_empty() && xc.is_empty() {
                continue;
            }
            let (Some(mb), Some(mc)) = (median(&xb), median(&xc)) else {
                rows.push(Row {
                    config: config.clone(),
                    metric: name.into(),
                    baseline: format!("n={}", xb.len()),
                    current: format!("n={}", xc.len()),
                    change: "–".into(),
                    p: None,
                    verdict: Verdict::NoData,
                    tests: None,
                    wall: false,
                });
                continue;
            };
            let tolerance = if wall { tol.time } else { tol.relative };
            let worse = mann_whitney_u(&xc, &xb, Alternative::Greater)
                .map(|t| t.p)
                .unwrap_or(1.0);
            let better = mann_whitney_u(&xc, &xb, Alternative::Less)
                .map(|t| t.p)
                .unwrap_or(1.0);
            let rel = if mb.abs() > 1e-12 {
                (mc - mb) / mb.abs()
            } else if mc > mb {
                f64::INFINITY
            } else {
                0.0
            };
            let seed = crate::run::fake::seed_of(&format!("{config}|{name}"));
            let ci = median_diff_ci(&xb, &xc, 0.95, 2000, seed);
            let change = match ci {
                Some(ci) if mb.abs() > 1e-12 => format!(
                    "{:+.1}% [{:+.1}%, {:+.1}%]",
                    100.0 * rel,
                    100.0 * ci.lo / mb.abs(),
                    100.0 * ci.hi / mb.abs()
                ),
                Some(ci) => format!("{:+} [{:+}, {:+}]", fmt(ci.diff), fmt(ci.lo), fmt(ci.hi)),
                None => "–".into(),
            };
            let enough = xb.len() >= 3 && xc.len() >= 3;
            rows.push(Row {
                config: config.clone(),
                metric: name.into(),
                baseline: format!("{} (n={})", fmt(mb), xb.len()),
                current: format!("{} (n={})", fmt(mc), xc.len()),
                change,
                p: None,
                verdict: Verdict::NoData,
                tests: enough.then_some((worse, better, rel > tolerance, rel < 0.0)),
                wall,
            });
        }
    }
    decide(&mut rows, tol.alpha, tol.gate_time);
    rows
}

/// The rows as an aligned text table.
pub fn table(rows: &[Row]) -> String {
    let head = [
        "configuration",
        "metric",
        "baseline",
        "current",
        "change [95% CI]",
        "p (Holm)",
        "verdict",
    ];
    let cells: Vec<[String; 7]> = rows
        .iter()
        .map(|r| {
            [
                r.config.clone(),
                r.metric.clone(),
                r.baseline.clone(),
                r.current.clone(),
                r.change.clone(),
                r.p.map(|p| format!("{p:.2e}"))
                    .unwrap_or_else(|| "–".into()),
                r.verdict.as_str().into(),
            ]
        })
        .collect();
    let mut w = head.map(|h| h.chars().count());
    for c in &cells {
        for (i, s) in c.iter().enumerate() {
            w[i] = w[i].max(s.chars().count());
        }
    }
    let line = |c: &[String]| -> String {
        c.iter()
            .enumerate()
            .map(|(i, s)| format!("{s:<width$}", width = w[i]))
            .collect::<Vec<_>>()
            .join("  ")
            .trim_end()
            .to_string()
            + "\n"
    };
    let mut out = line(&head.map(String::from));
    out += &line(&w.map(|n| "-".repeat(n)));
    for c in &cells {
        out += &line(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
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

    fn verdict(rows: &[Row], metric: &str) -> Verdict {
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
}
