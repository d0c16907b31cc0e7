//! The report stage: comparisons as text — a table per configuration, the counts of each
//! verdict, the methods, and the result.

use super::analysis::{Comparison, Design, Tolerances, Value};
use super::metric::Change;
use super::verdict::Verdict;

/// Whether an inconclusive verdict fails the check.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum OnInconclusive {
    /// Fail: a check that cannot tell is not a pass (the safe default for CI).
    Fail,
    /// Pass: only regressions and missing configurations fail.
    Pass,
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

/// A value as the table shows it.
fn value(v: &Value) -> String {
    match *v {
        Value::Rate { successes, runs } if runs > 0 => format!(
            "{:.1}% ({successes}/{runs})",
            100.0 * successes as f64 / runs as f64
        ),
        Value::Rate { .. } => "–".into(),
        Value::Median { value, n } => format!("{} (n={n})", fmt(value)),
        Value::Samples(n) => format!("n={n}"),
        Value::Runs(n) => n.to_string(),
    }
}

/// `[lo, hi]` with `f`, or `[unbounded]` when too few runs bound the change.
fn interval(lo: f64, hi: f64, f: impl Fn(f64) -> String) -> String {
    if lo.is_finite() && hi.is_finite() {
        format!("[{}, {}]", f(lo), f(hi))
    } else {
        "[unbounded]".into()
    }
}

/// A change as the table shows it.
fn change(c: &Change) -> String {
    match *c {
        Change::None => "–".into(),
        Change::Points { diff, lo, hi } => {
            let f = |x: f64| format!("{:+.1}", 100.0 * x);
            format!("{} pts {}", f(diff), interval(lo, hi, f))
        }
        Change::Relative { rel, lo, hi } => {
            let f = |x: f64| format!("{:+.1}%", 100.0 * x);
            format!("{} {}", f(rel), interval(lo, hi, f))
        }
        Change::Absolute { diff, lo, hi } => {
            let f = |x: f64| {
                let s = fmt(x);
                if x >= 0.0 { format!("+{s}") } else { s }
            };
            format!("{} {}", f(diff), interval(lo, hi, f))
        }
    }
}

/// A verdict as the table shows it.
fn verdict(r: &Comparison) -> String {
    let mut s = match r.verdict {
        Verdict::Ok if r.better => "ok (better)".to_string(),
        Verdict::Inconclusive if r.untested() => "inconclusive (too few values)".into(),
        Verdict::Inconclusive => match r.seeds_needed {
            Some(n) if n >= super::verdict::MAX_SEEDS => format!(
                "inconclusive (> {} seeds, more than an experiment runs)",
                crate::experiment::MAX_SEEDS
            ),
            Some(n) => format!("inconclusive (~{n} seeds)"),
            None => "inconclusive".into(),
        },
        v => v.as_str().to_string(),
    };
    if !r.gated && r.verdict != Verdict::New {
        s += " (not gated)";
    }
    s
}

/// The heading of a configuration's table.
fn heading(r: &Comparison) -> String {
    let mut s = match r.design {
        Design::Paired(n) => format!("{} — paired by seed ({n} seeds)", r.config),
        Design::Unpaired(b, c) => format!(
            "{} — unpaired: different seeds ({b} baseline, {c} candidate runs)",
            r.config
        ),
        Design::Missing => format!("{} — missing from the candidate", r.config),
    };
    if let Some((b, c)) = r.sampled_from {
        s += &format!(
            "; a sample of the seeds (the same on both sides) of {b} baseline and {c} \
             candidate runs"
        );
    }
    s
}

/// The column heading of the change, with the interval's level.
fn change_head(alpha: f64) -> String {
    format!("change [{}% CI]", fmt(100.0 * (1.0 - 2.0 * alpha)))
}

/// The rows as text: per configuration a heading and an aligned table (metric, baseline,
/// candidate, change with its interval, verdict).
pub fn table(rows: &[Comparison], tol: &Tolerances) -> String {
    let head = [
        "metric".to_string(),
        "baseline".into(),
        "candidate".into(),
        change_head(tol.alpha),
        "verdict".into(),
    ];
    let cells: Vec<[String; 5]> = rows
        .iter()
        .map(|r| {
            [
                r.metric.clone(),
                value(&r.baseline),
                value(&r.current),
                change(&r.change),
                verdict(r),
            ]
        })
        .collect();
    let mut w = head.clone().map(|h| h.chars().count());
    for c in &cells {
        for (i, s) in c.iter().enumerate() {
            w[i] = w[i].max(s.chars().count());
        }
    }
    let line = |c: &[String]| -> String {
        let text = c
            .iter()
            .enumerate()
            .map(|(i, s)| format!("{s:<width$}", width = w[i]))
            .collect::<Vec<_>>()
            .join("  ");
        format!("  {}\n", text.trim_end())
    };
    let mut out = String::new();
    for (i, (r, c)) in rows.iter().zip(&cells).enumerate() {
        if i == 0 || rows[i - 1].config != r.config {
            if i > 0 {
                out += "\n";
            }
            out += &heading(r);
            out += "\n";
            out += &line(&head);
            out += &line(&w.map(|n| "-".repeat(n)));
        }
        out += &line(c);
    }
    out
}

/// Gated regressions and missing configurations among `rows`.
pub fn regressions(rows: &[Comparison]) -> usize {
    rows.iter()
        .filter(|r| r.gated && matches!(r.verdict, Verdict::Regression | Verdict::Missing))
        .count()
}

/// Gated inconclusive verdicts among `rows`.
pub fn inconclusive(rows: &[Comparison]) -> usize {
    rows.iter()
        .filter(|r| r.gated && r.verdict == Verdict::Inconclusive)
        .count()
}

/// The verdicts that fail the check under `policy`.
pub fn failures(rows: &[Comparison], policy: OnInconclusive) -> usize {
    regressions(rows)
        + match policy {
            OnInconclusive::Fail => inconclusive(rows),
            OnInconclusive::Pass => 0,
        }
}

/// The metrics of `rows` that the baseline does not have, each once, in table order.
pub fn new_metrics(rows: &[Comparison]) -> Vec<&str> {
    let mut out: Vec<&str> = vec![];
    for r in rows.iter().filter(|r| r.verdict == Verdict::New) {
        if !out.contains(&r.metric.as_str()) {
            out.push(&r.metric);
        }
    }
    out
}

/// The closing lines: the metrics new since the baseline, the counts of each verdict, the
/// methods and tolerances, and the result under `policy`.
pub fn footer(rows: &[Comparison], tol: &Tolerances, policy: OnInconclusive) -> String {
    let mut out = String::new();
    let new = new_metrics(rows);
    if !new.is_empty() {
        out += &format!(
            "new since the baseline (not compared): {}\n",
            new.join(", ")
        );
    }
    let gated = |v: Verdict| rows.iter().filter(|r| r.gated && r.verdict == v).count();
    let ungated = rows
        .iter()
        .filter(|r| !r.gated && r.verdict != Verdict::New)
        .count();
    let family = rows.iter().filter(|r| r.gated && r.p.is_some()).count();
    let shown = rows.iter().filter(|r| !r.gated && r.p.is_some()).count();
    let shown = if shown > 0 {
        format!(", and apart over the {shown} tests not gated")
    } else {
        String::new()
    };
    out += &format!(
        "summary: {} ok, {} inconclusive, {} regression, {} missing{}\n",
        gated(Verdict::Ok),
        gated(Verdict::Inconclusive),
        gated(Verdict::Regression),
        gated(Verdict::Missing),
        if ungated > 0 {
            format!(" ({ungated} wall-clock verdicts not gated)")
        } else {
            String::new()
        }
    );
    out += &format!(
        "method: regression = a one-sided test that the change exceeds the tolerance, Holm-adjusted over {family} gated tests (family-wise α = {}){shown}; ok = the worse end of the {}% interval inside the tolerance; tolerances: success −{} points, error/cost/iterations +{}%, time +{}%\n",
        tol.alpha,
        fmt(100.0 * (1.0 - 2.0 * tol.alpha)),
        fmt(100.0 * tol.success),
        fmt(100.0 * tol.relative),
        fmt(100.0 * tol.time),
    );
    let (reg, inc) = (regressions(rows), inconclusive(rows));
    out += &match (reg, inc, policy) {
        (0, 0, _) => "result: pass (no regression)\n".to_string(),
        (0, n, OnInconclusive::Pass) => {
            format!(
                "result: pass (no regression; {n} inconclusive accepted by --inconclusive pass)\n"
            )
        }
        (0, n, OnInconclusive::Fail) => format!(
            "result: FAIL (no regression shown, but {n} inconclusive: run more seeds, or accept with --inconclusive pass)\n"
        ),
        (r, _, _) => format!("result: FAIL ({r} REGRESSION(S))\n"),
    };
    out
}
