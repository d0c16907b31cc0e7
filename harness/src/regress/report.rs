//! The report stage: comparisons as text — an aligned table and the one-line verdict.

use super::analysis::{Change, Comparison, Tolerances, Value, Verdict};

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
        Value::Rate { successes, runs } => format!(
            "{:.1}% ({successes}/{runs})",
            100.0 * successes as f64 / runs as f64
        ),
        Value::Median { value, n } => format!("{} (n={n})", fmt(value)),
        Value::Samples(n) => format!("n={n}"),
        Value::Runs(n) => n.to_string(),
    }
}

/// A change as the table shows it.
fn change(c: &Change) -> String {
    match *c {
        Change::None => "–".into(),
        Change::Points(d) => format!("{:+.1} points", 100.0 * d),
        Change::Relative { rel, lo, hi } => format!(
            "{:+.1}% [{:+.1}%, {:+.1}%]",
            100.0 * rel,
            100.0 * lo,
            100.0 * hi
        ),
        Change::Absolute { diff, lo, hi } => {
            format!("{} [{}, {}]", fmt(diff), fmt(lo), fmt(hi))
        }
    }
}

/// The rows as an aligned text table.
pub fn table(rows: &[Comparison]) -> String {
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
                value(&r.baseline),
                value(&r.current),
                change(&r.change),
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

/// Regressions (and missing configurations) among `rows`.
pub fn regressions(rows: &[Comparison]) -> usize {
    rows.iter()
        .filter(|r| matches!(r.verdict, Verdict::Regression | Verdict::Missing))
        .count()
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

/// The closing line: what was compared, under which tolerances, and the verdict; before it,
/// the metrics new since the baseline (reported, not compared).
pub fn footer(rows: &[Comparison], tol: &Tolerances) -> String {
    let bad = regressions(rows);
    let new = new_metrics(rows);
    let new = if new.is_empty() {
        String::new()
    } else {
        format!(
            "new since the baseline (not compared): {}\n",
            new.join(", ")
        )
    };
    new + &format!(
        "{} metrics compared (one-sided tests at α = {}, Holm-adjusted; tolerances: success −{:.0} points, error/cost +{:.0}%, time +{:.0}%): {}\n",
        rows.iter().filter(|r| r.verdict != Verdict::New).count(),
        tol.alpha,
        100.0 * tol.success,
        100.0 * tol.relative,
        100.0 * tol.time,
        if bad == 0 {
            "no regression".to_string()
        } else {
            format!("{bad} REGRESSION(S)")
        }
    )
}
