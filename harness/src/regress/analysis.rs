//! The analysis stage: per configuration and metric, the baseline and candidate values, the
//! change with its interval and the verdict, as plain numbers.

use super::metric::{self, Change, Sides};
use super::runs::{Config, Runs};
use super::verdict::{Test, Verdict, adjust, seeds_needed, verdict_of};
use crate::metrics::{Direction, Metric, Regress};
use crate::run::RunRecord;
use crate::stats::median;

/// Thresholds of a regression check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Level of the tests: the family-wise error rate of the regression decisions (Holm),
    /// and the level of each end of the intervals (a two-sided `1 − 2·alpha` interval).
    pub alpha: f64,
    /// Largest acceptable drop of the success rate (absolute, e.g. 0.1 = 10 points).
    pub success: f64,
    /// Largest acceptable relative growth for error, cost and iteration metrics (0.1 = 10%).
    pub relative: f64,
    /// Largest acceptable relative growth of wall-clock metrics (machines differ).
    pub time: f64,
    /// Compare wall-clock metrics at all.
    pub wall_clock: bool,
    /// Let wall-clock metrics fail the check. Off by default: times depend on the machine and
    /// its load, so their verdicts are reported without failing the check.
    pub gate_time: bool,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            alpha: 0.05,
            success: 0.10,
            relative: 0.10,
            time: 1.0,
            wall_clock: true,
            gate_time: false,
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
    /// No value.
    Samples(usize),
    /// Runs of the configuration.
    Runs(usize),
}

/// How a configuration's two sides were matched.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Design {
    /// The same seeds on both sides, compared seed by seed.
    Paired(usize),
    /// Different seeds: (baseline runs, candidate runs), compared as independent samples.
    Unpaired(usize, usize),
    /// The configuration is missing from the candidate.
    Missing,
}

/// One metric of one configuration, compared.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// Configuration label.
    pub config: String,
    /// How the sides were matched.
    pub design: Design,
    /// Metric name.
    pub metric: String,
    /// Baseline value.
    pub baseline: Value,
    /// Candidate value.
    pub current: Value,
    /// The change, with its interval.
    pub change: Change,
    /// The p-value of the one-sided test for a regression: Holm-adjusted over the gated
    /// metrics, or over the others for a metric that is not gated.
    pub p: Option<f64>,
    /// Verdict.
    pub verdict: Verdict,
    /// The whole interval lies on the better side of the tolerance.
    pub better: bool,
    /// The verdict can fail the check (wall-clock metrics only with `gate_time`).
    pub gated: bool,
    /// For an inconclusive verdict: seeds per folder that would likely resolve it.
    pub seeds_needed: Option<u64>,
    /// When the configuration has more runs than a side keeps ([`super::runs::SEEDS`]): its
    /// runs in the baseline and in the candidate, of which the compared seeds are a sample.
    pub sampled_from: Option<(usize, usize)>,
    /// The test behind the verdict.
    test: Option<Test>,
}

impl Comparison {
    fn new(config: &str, design: Design, metric: &str, baseline: Value, current: Value) -> Self {
        Comparison {
            config: config.to_string(),
            design,
            metric: metric.to_string(),
            baseline,
            current,
            change: Change::None,
            p: None,
            verdict: Verdict::Inconclusive,
            better: false,
            gated: true,
            seeds_needed: None,
            sampled_from: None,
            test: None,
        }
    }
}

impl Comparison {
    /// True if no test could be made (a side without values, or no seed with a value on
    /// both sides).
    pub fn untested(&self) -> bool {
        self.test.is_none()
    }
}

/// Sets the verdicts of tested rows: Holm over the gated rows' regression tests, and apart
/// over the other rows' ([`adjust`]).
fn decide(rows: &mut [Comparison], alpha: f64) {
    let tested: Vec<usize> = (0..rows.len())
        .filter(|&i| rows[i].test.is_some())
        .collect();
    let p: Vec<f64> = tested.iter().map(|&i| rows[i].test.unwrap().p).collect();
    let gated: Vec<bool> = tested.iter().map(|&i| rows[i].gated).collect();
    let adj = adjust(&p, &gated);
    for (k, &i) in tested.iter().enumerate() {
        let t = rows[i].test.unwrap();
        let (v, better) = verdict_of(&t, adj[k], alpha);
        let r = &mut rows[i];
        (r.p, r.verdict, r.better) = (Some(adj[k]), v, better);
        if v == Verdict::Inconclusive {
            r.seeds_needed = seeds_needed(&t, alpha);
        }
    }
}

/// A metric compared: its name, its column in [`Runs`], which way is better and how `regress`
/// treats it.
struct Compared {
    name: String,
    column: usize,
    direction: Direction,
    regress: Regress,
}

/// The metrics of the table that `regress` compares, in table order.
pub fn table_metrics() -> Vec<Metric> {
    Metric::ALL
        .iter()
        .copied()
        .filter(|m| m.def().regress != Regress::Off)
        .collect()
}

/// The compared metrics of a configuration: the table's, then each agent's RMS path error,
/// observed and true (`rms_error_agent{i}_bl`, `rms_error_true_agent{i}_bl`), for the agents of
/// the larger team of the two sides.
fn compared(metrics: &[Metric], agents: usize) -> Vec<Compared> {
    let table = metrics.iter().enumerate().map(|(column, m)| Compared {
        name: m.def().column.to_string(),
        column,
        direction: m.def().direction,
        regress: m.def().regress,
    });
    let agent = (0..agents).flat_map(|i| {
        let [rms, _, rms_true, _] = crate::run::record::agent_columns(i);
        [(rms, 0), (rms_true, 1)].map(|(name, k)| Compared {
            name,
            column: metrics.len() + 2 * i + k,
            direction: Direction::Lower,
            regress: Regress::Gated,
        })
    });
    table.chain(agent).collect()
}

/// The two sides of a configuration: paired by seed when both hold the same seeds, each once.
pub fn sides(b: &Config, c: &Config) -> Sides {
    let sorted = |g: &Config| {
        let mut s: Vec<(u64, usize)> = g.seeds.iter().copied().zip(0..).collect();
        s.sort_unstable();
        s
    };
    let (sb, sc) = (sorted(b), sorted(c));
    let same = sb.len() == sc.len() && sb.iter().zip(&sc).all(|(x, y)| x.0 == y.0);
    if same && sb.windows(2).all(|w| w[0].0 != w[1].0) {
        Sides::Paired(sb.iter().zip(&sc).map(|(x, y)| (x.1, y.1)).collect())
    } else {
        Sides::Unpaired(b.len(), c.len())
    }
}

/// Finite values of column `k` over `g`'s runs.
fn values(g: &Config, k: usize) -> Vec<f64> {
    (0..g.len())
        .filter_map(|i| g.value(k, i))
        .filter(|v| v.is_finite())
        .collect()
}

fn median_value(v: &[f64]) -> Value {
    match median(v) {
        Some(value) => Value::Median { value, n: v.len() },
        None => Value::Samples(v.len()),
    }
}

/// Compares `current` (the candidate) against `baseline`.
pub fn compare(baseline: &[RunRecord], current: &[RunRecord], tol: &Tolerances) -> Vec<Comparison> {
    compare_runs(&Runs::of(baseline), &Runs::of(current), tol)
}

/// Compares `current` (the candidate) against `baseline`, each read by [`Runs::read`].
pub fn compare_runs(baseline: &Runs, current: &Runs, tol: &Tolerances) -> Vec<Comparison> {
    let mut rows = vec![];
    let m = baseline.metrics.len();
    for b in &baseline.configs {
        let config = b.label();
        let Some(c) = current.get(&b.key) else {
            let mut r = Comparison::new(
                &config,
                Design::Missing,
                "runs",
                Value::Runs(b.all),
                Value::Runs(0),
            );
            r.verdict = Verdict::Missing;
            rows.push(r);
            continue;
        };
        let level = b.level.max(c.level);
        let (b, c) = (b.thinned(level), c.thinned(level));
        let (b, c) = (b.as_ref(), c.as_ref());
        let sampled_from = (b.sampled() || c.sampled()).then_some((b.all, c.all));
        let s = sides(b, c);
        let design = match &s {
            Sides::Paired(p) => Design::Paired(p.len()),
            Sides::Unpaired(..) => Design::Unpaired(b.len(), c.len()),
        };
        let rate = |g: &Config| Value::Rate {
            successes: g.success.iter().filter(|&&x| x).count() as u64,
            runs: g.len() as u64,
        };
        let mut row = Comparison::new(&config, design, "success_rate", rate(b), rate(c));
        let (test, change) = metric::success(&s, &b.success, &c.success, tol.success, tol.alpha);
        (row.test, row.change) = (Some(test), change);
        row.sampled_from = sampled_from;
        rows.push(row);
        for Compared {
            name,
            column: k,
            direction,
            regress,
        } in compared(&baseline.metrics, b.agents(m).max(c.agents(m)))
        {
            let wall = regress == Regress::WallClock;
            if wall && !tol.wall_clock {
                continue;
            }
            let (xb, xc) = (values(b, k), values(c, k));
            if xb.is_empty() && xc.is_empty() {
                continue;
            }
            let mut row =
                Comparison::new(&config, design, &name, median_value(&xb), median_value(&xc));
            row.gated = match regress {
                Regress::Gated => true,
                Regress::WallClock => tol.gate_time,
                Regress::Shown | Regress::Off => false,
            };
            if xb.is_empty() {
                row.verdict = Verdict::New;
            } else {
                let rel = if wall { tol.time } else { tol.relative };
                let mb = median(&xb).unwrap_or(0.0);
                let (fb, fc) = (|i| b.value(k, i), |j| c.value(k, j));
                if let Some((test, change)) =
                    metric::shift(&s, &fb, &fc, direction, rel, mb, tol.alpha)
                {
                    (row.test, row.change) = (Some(test), change);
                }
            }
            row.sampled_from = sampled_from;
            rows.push(row);
        }
    }
    decide(&mut rows, tol.alpha);
    rows
}
