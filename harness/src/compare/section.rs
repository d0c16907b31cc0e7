//! The report's "Across problems" section: the paired comparisons as a table, the performance
//! profile, and success and time against each difficulty measure that varies over the
//! problems, as plots in `plots/across-problems/`. Empty for fewer than two problems.

use std::fmt::Write as _;
use std::path::Path;

use super::by_difficulty::{bins, success, time};
use super::instances::Instances;
use super::paired::paired;
use super::profile::{profile, tau_grid};
use crate::Error;
use crate::metrics::difficulty::Measure;
use crate::plot::charts::{BandPoint, LineBandChart, Series, W};
use crate::plot::style::{self, Family};
use crate::plot::{save, with_ext};
use crate::results::report::esc;
use crate::run::RunRecord;

/// The folder of the section's plots inside `plots/`.
pub const FOLDER: &str = "across-problems";

/// Measures with fewer distinct values than this over the problems are not plotted.
const MIN_DISTINCT: usize = 3;

fn figure(dir: &Path, name: &str, fig: &LineBandChart, caption: &str) -> Result<String, Error> {
    let stem = dir.join("plots").join(FOLDER).join(name);
    save(fig, &stem)?;
    let path = with_ext(&stem, "svg");
    let text = std::fs::read_to_string(&path)
        .map_err(|e| Error::Failed(format!("{}: {e}", path.display())))?;
    let svg = &text[text.find("<svg").unwrap_or(0)..];
    let rel = format!("plots/{FOLDER}/{name}");
    Ok(format!(
        "<figure>{svg}<figcaption>{} — <a href=\"{rel}.svg\">SVG</a> · <a href=\"{rel}.png\">PNG</a></figcaption></figure>\n",
        esc(caption)
    ))
}

fn pct(v: f64) -> String {
    if v.is_nan() {
        "–".into()
    } else {
        format!("{:.0}", 100.0 * v)
    }
}

fn paired_table(o: &mut String, t: &Instances) {
    o.push_str("<table><thead><tr><th>A vs B</th><th>problems</th><th>A faster / B faster / ties</th><th>A's win rate (95% CI)</th><th>time A / time B (95% CI)</th><th>both solved</th></tr></thead><tbody>\n");
    for a in 0..t.planners.len() {
        for b in a + 1..t.planners.len() {
            let p = paired(&t.time[a], &t.time[b]);
            let ratio = match p.ratio {
                Some(r) => format!(
                    "{r:.3} <small>[{:.3}, {:.3}]</small>",
                    p.ratio_ci.0, p.ratio_ci.1
                ),
                None => "–".into(),
            };
            let _ = writeln!(
                o,
                "<tr><td>{} vs {}</td><td>{}</td><td>{} / {} / {}</td><td>{}% <small>[{}, {}]</small></td><td>{ratio}</td><td>{}</td></tr>",
                esc(&t.planners[a]),
                esc(&t.planners[b]),
                p.problems,
                p.wins,
                p.losses,
                p.ties,
                pct(p.win_rate),
                pct(p.win_ci.0),
                pct(p.win_ci.1),
                p.both_solved
            );
        }
    }
    o.push_str("</tbody></table>\n<p class=\"note\">Per problem, each planner's median time to a first solution over its seeds (unsolved when half or more of its seeds are). A wins a problem when its time is shorter; an unsolved problem loses to any time, two unsolved ones tie. Win rate: wins / (wins + losses) with the Wilson interval. Time ratio: the Hodges–Lehmann estimate of the median ratio over the problems both solved, with the Wilcoxon signed-rank interval; below 1, A is faster. docs/suites.md, \"Comparisons across problems\".</p>\n");
}

/// Draws the section's plots into `dir/plots/across-problems/` and returns its HTML (empty
/// when the runs span fewer than two problems).
pub fn html(dir: &Path, runs: &[RunRecord]) -> Result<String, Error> {
    let t = Instances::of(runs);
    if t.problems.len() < 2 || t.planners.is_empty() {
        return Ok(String::new());
    }
    let mut o = String::new();
    let _ = writeln!(
        o,
        "<h2>Across problems</h2>\n<p>{} problems, {} planners.</p>",
        t.problems.len(),
        t.planners.len()
    );
    if t.planners.len() >= 2 {
        paired_table(&mut o, &t);
    }
    let taus = tau_grid(&t.time, 200);
    let rho = profile(&t.time, &taus);
    let series = t
        .planners
        .iter()
        .zip(&rho)
        .map(|(label, r)| Series {
            label: label.clone(),
            data: taus
                .iter()
                .zip(r)
                .map(|(tau, y)| BandPoint {
                    x: tau.log2(),
                    y: *y,
                    lo: f64::NAN,
                    hi: f64::NAN,
                })
                .collect(),
        })
        .collect();
    let title = "performance profile: problems solved within τ × the best time".to_string();
    let fig = LineBandChart {
        title: title.clone(),
        x_label: "log₂ τ (τ: time over the best planner's time on the problem)".into(),
        y_label: "problems solved within τ (fraction)".into(),
        series,
        y_range: Some((0.0, 1.0)),
        steps: true,
        band_label: String::new(),
        empty_note: "no planner solved a problem".into(),
        looks: style::looks(Family::Planner, t.planners.len()),
        x_log: false,
        width: W,
    };
    o.push_str(&figure(dir, "performance-profile", &fig, &title)?);

    for m in Measure::ALL.iter().filter(|m| m.def().axis) {
        let (col, axis) = (m.def().name, m.def().axis_label());
        let x: Vec<Option<f64>> = t.difficulty.iter().map(|d| d.get(*m)).collect();
        let mut distinct: Vec<f64> = x.iter().flatten().copied().collect();
        distinct.sort_by(f64::total_cmp);
        distinct.dedup();
        if distinct.len() < MIN_DISTINCT {
            continue;
        }
        let b = bins(&x);
        let per = |f: &dyn Fn(usize) -> Vec<BandPoint>| -> Vec<Series<Vec<BandPoint>>> {
            (0..t.planners.len())
                .map(|p| Series {
                    label: t.planners[p].clone(),
                    data: f(p),
                })
                .collect()
        };
        let title = format!("success rate vs {}", m.def().label);
        let fig = LineBandChart {
            title: title.clone(),
            x_label: format!("{axis}: bin median (runs.csv: {})", m.def().column),
            y_label: "runs solved (fraction)".into(),
            series: per(&|p| success(&t, p, &x, &b)),
            y_range: Some((0.0, 1.0)),
            steps: false,
            band_label: "95% Wilson interval".into(),
            empty_note: String::new(),
            looks: style::looks(Family::Planner, t.planners.len()),
            x_log: false,
            width: W,
        };
        o.push_str(&figure(dir, &format!("success-vs-{col}"), &fig, &title)?);
        let title = format!("time to first solution vs {}", m.def().label);
        let fig = LineBandChart {
            title: title.clone(),
            x_label: format!("{axis}: bin median (runs.csv: {})", m.def().column),
            y_label: "log₁₀ median time to 1st solution (s)".into(),
            series: per(&|p| time(&t, p, &x, &b)),
            y_range: None,
            steps: false,
            band_label: "quartiles of the problems' medians".into(),
            empty_note: "no bin with half of its problems solved".into(),
            looks: style::looks(Family::Planner, t.planners.len()),
            x_log: false,
            width: W,
        };
        o.push_str(&figure(dir, &format!("time-vs-{col}"), &fig, &title)?);
    }
    Ok(o)
}
