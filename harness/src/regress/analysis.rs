//! The analysis stage: per configuration and metric, the baseline and current values, the
//! change with its interval, the one-sided tests and the verdict, as plain numbers.

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
    /// A metric the baseline does not have (e.g. a column added after it was recorded).
    New,
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
            Verdict::New => "new (not in baseline)",
        }
    }
}

/// One side's value of a metric.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    /// A success rate: runs that succeeded, of how many.
    Rate {
        /// Successful runs.
        successes: u64,
        /// Runs.
        runs: u64,
    },
    /// The median of `n` finite values.
    Median {
        /// The median.
        value: f64,
        /// Values.
        n: usize,
    },
    /// Only the number of values (too few for a median on one side).
    Samples(usize),
    /// Runs of the configuration.
    Runs(usize),
}

/// The change from the baseline to the current value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Change {
    /// Not computed.
    None,
    /// A difference of rates (fractions; 0.05 is 5 points).
    Points(f64),
    /// A relative change of the median with the 95% interval (fractions of the baseline
    /// median).
    Relative {
        /// The change.
        rel: f64,
        /// Lower end of the interval.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
    /// The difference of medians with its interval, when the baseline median is zero.
    Absolute {
        /// The difference.
        diff: f64,
        /// Lower end of the interval.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
}

/// One metric of one configuration, compared.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// Configuration label.
    pub config: String,
    /// Metric name.
    pub metric: String,
    /// Baseline value.
    pub baseline: Value,
    /// Current value.
    pub current: Value,
    /// The change, with its interval.
    pub change: Change,
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
fn decide(rows: &mut [Comparison], alpha: f64, gate_time: bool) {
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

/// Continuous metrics checked (name, value, wall-clock?); then each agent's, see
/// [`agent_metrics`].
pub const METRICS: [Metric; 12] = [
    ("rms_error_bl", |r| r.rms_error_bl, false),
    (
        "rms_error_worst_agent_bl",
        |r| r.rms_error_worst_agent_bl,
        false,
    ),
    ("rms_error_true_bl", |r| r.rms_error_true_bl, false),
    (
        "rms_error_true_worst_agent_bl",
        |r| r.rms_error_true_worst_agent_bl,
        false,
    ),
    ("rms_error_sync_bl", |r| r.rms_error_sync_bl, false),
    ("rms_error_time_bl", |r| r.rms_error_time_bl, false),
    ("max_error_bl", |r| r.max_error_bl, false),
    ("max_error_true_bl", |r| r.max_error_true_bl, false),
    ("cost", |r| r.cost, false),
    (
        "first_solution_iteration",
        |r| r.first_solution_iteration.map(|i| i as f64),
        false,
    ),
    ("first_solution_time_s", |r| r.first_solution_time_s, true),
    ("plan_time_s", |r| Some(r.plan_time_s), true),
];

/// A metric by name: its value in a run (boxed: per-agent metrics are made at run time).
type NamedMetric = (String, Box<dyn Fn(&RunRecord) -> Option<f64>>, bool);

/// Each agent's RMS path error, observed and true (`rms_error_agent{i}_bl`,
/// `rms_error_true_agent{i}_bl`), for the agents of the largest team in `runs`.
pub fn agent_metrics<'a>(runs: impl IntoIterator<Item = &'a RunRecord>) -> Vec<NamedMetric> {
    let n = runs
        .into_iter()
        .map(|r| r.per_agent.len())
        .max()
        .unwrap_or(0);
    let mut out: Vec<NamedMetric> = vec![];
    for i in 0..n {
        let [rms, _, rms_true, _] = crate::run::record::agent_columns(i);
        out.push((
            rms,
            Box::new(move |r: &RunRecord| r.per_agent.get(i).and_then(|a| a.rms_bl)),
            false,
        ));
        out.push((
            rms_true,
            Box::new(move |r: &RunRecord| r.per_agent.get(i).and_then(|a| a.rms_true_bl)),
            false,
        ));
    }
    out
}

fn config_label(r: &RunRecord) -> String {
    let mut s = format!("{} / {}", r.scenario, r.planner);
    if !r.tracker.is_empty() {
        s += &format!(" / {} ({})", r.tracker, r.preset);
    }
    s
}

/// Compares `current` against `baseline`.
pub fn compare(baseline: &[RunRecord], current: &[RunRecord], tol: &Tolerances) -> Vec<Comparison> {
    let cur_groups = groups(current);
    let mut rows = vec![];
    for b in groups(baseline) {
        let config = config_label(b[0]);
        let Some(c) = cur_groups.iter().find(|g| key(g[0]) == key(b[0])) else {
            rows.push(Comparison {
                config,
                metric: "runs".into(),
                baseline: Value::Runs(b.len()),
                current: Value::Runs(0),
                change: Change::None,
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
        rows.push(Comparison {
            config: config.clone(),
            metric: "success_rate".into(),
            baseline: Value::Rate {
                successes: sb,
                runs: nb,
            },
            current: Value::Rate {
                successes: sc,
                runs: nc,
            },
            change: Change::Points(rc - rb),
            p: None,
            verdict: Verdict::Ok,
            tests: Some((p_worse, p_better, rb - rc > tol.success, rc > rb)),
            wall: false,
        });
        let metrics: Vec<NamedMetric> = METRICS
            .iter()
            .map(|&(name, f, wall)| -> NamedMetric { (name.to_string(), Box::new(f), wall) })
            .chain(agent_metrics(b.iter().chain(c.iter()).copied()))
            .collect();
        for (name, f, wall) in metrics {
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
            if xb.is_empty() {
                rows.push(Comparison {
                    config: config.clone(),
                    metric: name,
                    baseline: Value::Samples(0),
                    current: match median(&xc) {
                        Some(value) => Value::Median { value, n: xc.len() },
                        None => Value::Samples(xc.len()),
                    },
                    change: Change::None,
                    p: None,
                    verdict: Verdict::New,
                    tests: None,
                    wall,
                });
                continue;
            }
            let (Some(mb), Some(mc)) = (median(&xb), median(&xc)) else {
                rows.push(Comparison {
                    config: config.clone(),
                    metric: name.clone(),
                    baseline: Value::Samples(xb.len()),
                    current: Value::Samples(xc.len()),
                    change: Change::None,
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
            let metric = name;
            let ci = median_diff_ci(&xb, &xc, 0.95, 2000, seed);
            let change = match ci {
                Some(ci) if mb.abs() > 1e-12 => Change::Relative {
                    rel,
                    lo: ci.lo / mb.abs(),
                    hi: ci.hi / mb.abs(),
                },
                Some(ci) => Change::Absolute {
                    diff: ci.diff,
                    lo: ci.lo,
                    hi: ci.hi,
                },
                None => Change::None,
            };
            let enough = xb.len() >= 3 && xc.len() >= 3;
            rows.push(Comparison {
                config: config.clone(),
                metric,
                baseline: Value::Median {
                    value: mb,
                    n: xb.len(),
                },
                current: Value::Median {
                    value: mc,
                    n: xc.len(),
                },
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
