//! `report.html`: one self-contained page (inline SVG and CSS, a few lines of inline script
//! that sort the tables, no network) with the experiment, a summary table per configuration,
//! and every plot. It fits a 1,280-px window; cells of columns that do not apply to a row
//! (tracking columns of a planning-only configuration) are empty.

use crate::units::{Shown, Units};
use std::fmt::Write as _;
use std::path::Path;

use super::manifest::Manifest;
use super::plots::PlotFile;
use super::sample::SAMPLE;
use super::summary::GroupSummary;
use crate::Error;
use crate::metrics::{Aggregation, Compute, Metric};
use crate::run::RunRecord;
use crate::stats::Summary;

/// Escapes text for HTML.
pub fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A median with its quartiles, each value shown through `f`.
fn med_in(s: Option<&Summary>, digits: usize, f: impl Fn(f64) -> f64) -> String {
    match s {
        Some(s) => format!(
            "{:.*} <small>[{:.*}, {:.*}]</small>",
            digits,
            f(s.median),
            digits,
            f(s.q1),
            digits,
            f(s.q3)
        ),
        None => "–".into(),
    }
}

/// A metric's cell: its median with the quartiles, or its total over the runs, in the units
/// `shown` gives.
fn cell(g: &GroupSummary, m: Metric, digits: usize, shown: Shown) -> String {
    let d = m.def();
    let digits = shown.digits(d.unit, digits);
    let f = |v: f64| shown.value(d.unit, v);
    match d.aggregation {
        Aggregation::Median => med_in(g.metric(m), digits, f),
        Aggregation::Sum => g.metric(m).map_or("–".into(), |s| {
            format!("{:.*}", digits, f(s.mean * s.n as f64))
        }),
    }
}

/// The table's report columns whose computation `stage` accepts and that some row of `rows`
/// has a value of: a column empty in every row is left out.
fn columns(stage: fn(&Compute) -> bool, rows: &[&GroupSummary]) -> Vec<(Metric, usize)> {
    Metric::ALL
        .iter()
        .filter_map(|m| Some((*m, m.def().report?)))
        .filter(|(m, _)| stage(&m.def().compute))
        .filter(|(m, _)| rows.iter().any(|g| g.metric(*m).is_some()))
        .collect()
}

/// A header cell per column, in the units `shown` gives.
fn headers(o: &mut String, cols: &[(Metric, usize)], shown: Shown) {
    for (m, _) in cols {
        let d = m.def();
        let _ = write!(o, "<th>{}</th>", esc(&shown.axis(d.label, d.unit)));
    }
}

/// A cell per column of row `g`.
fn cells(o: &mut String, g: &GroupSummary, cols: &[(Metric, usize)], shown: Shown) {
    for &(m, digits) in cols {
        let _ = write!(o, "<td>{}</td>", cell(g, m, digits, shown));
    }
}

/// The summary of one scenario's configurations, as three narrow tables rather than one wide
/// one: planning (with success and the replays), tracking (tracked configurations only) and
/// the plan's path quality.
fn table(o: &mut String, rows: &[&GroupSummary], (dir, runs): (&Path, &[RunRecord]), shown: Shown) {
    let cols = columns(|c| matches!(c, Compute::Plan(_)), rows);
    o.push_str("<h3>Planning</h3>\n<table><thead><tr><th>configuration</th><th>runs</th><th>success (95% CI)</th><th>crashed</th>");
    headers(o, &cols, shown);
    o.push_str("<th>replays (by seed)</th></tr></thead><tbody>\n");
    for g in rows {
        let rate = g.succeeded as f64 / g.n.max(1) as f64;
        let _ = write!(
            o,
            "<tr><td>{}</td><td>{}</td><td data-v=\"{rate}\">{}/{} = {:.0}% <small>[{:.0}, {:.0}]</small></td><td>{}</td>",
            esc(&g.config_label()),
            g.n,
            g.succeeded,
            g.n,
            100.0 * rate,
            100.0 * g.success_ci.0,
            100.0 * g.success_ci.1,
            g.crashed,
        );
        cells(o, g, &cols, shown);
        let _ = writeln!(
            o,
            "<td class=\"replays\">{}</td></tr>",
            crate::replay::files::links_cell(dir, runs, g)
        );
    }
    o.push_str("</tbody></table>\n");
    let tracked: Vec<&GroupSummary> = rows.iter().copied().filter(|g| g.tracked()).collect();
    if !tracked.is_empty() {
        let cols = columns(|c| matches!(c, Compute::Track(_)), &tracked);
        o.push_str("<h3>Tracking</h3>\n<table><thead><tr><th>configuration</th>");
        headers(o, &cols, shown);
        o.push_str("<th>agent contacts</th></tr></thead><tbody>\n");
        for g in &tracked {
            let _ = write!(o, "<tr><td>{}</td>", esc(&g.config_label()));
            cells(o, g, &cols, shown);
            let _ = writeln!(o, "<td>{}</td></tr>", g.agent_contacts);
        }
        o.push_str("</tbody></table>\n");
    }
    let cols = columns(|c| matches!(c, Compute::Path(_)), rows);
    if !cols.is_empty() {
        o.push_str("<h3>Path quality of the plan</h3>\n<table><thead><tr><th>configuration</th>");
        headers(o, &cols, shown);
        o.push_str("</tr></thead><tbody>\n");
        for g in rows {
            let _ = write!(o, "<tr><td>{}</td>", esc(&g.config_label()));
            cells(o, g, &cols, shown);
            o.push_str("</tr>\n");
        }
        o.push_str("</tbody></table>\n");
    }
    o.push_str("<p class=\"note\">Medians with [first quartile, third quartile] over the runs that have the metric; times and costs over solved runs. Success: an exact plan (planning only) or reaching the goal without agent contact (tracking). Tracking errors: the observed positions' distance to each agent's own path (RMS and max), the true positions' (simulation only), the worst agent's (the agent with the largest RMS), the team against the nearest common point of the team path (synchronous) and against the reference at the same elapsed time (time-indexed), and the team against its nearest plan node (node: the seed's tracking error, to which its ≈ 0.2 BL compares); docs/tracking.md, \"Metrics\". Path quality (length, smoothness, cusps, clearance, proximity margin, field flips and field-angle variation) of the plan, the first leg's for tracked runs; docs/results.md, \"The metric table\".</p>\n");
    if rows.iter().any(|g| g.n > SAMPLE) {
        let _ = writeln!(
            o,
            "<p class=\"note\">A configuration of more than {SAMPLE} runs: its quartiles, figures, replay links and place in the across-problems comparison are those of an evenly spread sample of its runs (every 2<sup>j</sup>-th run, at most {SAMPLE}); its counts, success rate, means, totals, smallest and largest values are those of every run.</p>"
        );
    }
}

/// Teams this large get the per-agent table (a pair's worst agent is in the main table).
const PER_AGENT_TABLE_AGENTS: usize = 3;

/// Each agent's errors, one row per configuration and agent, for configurations tracking a
/// team of [`PER_AGENT_TABLE_AGENTS`] or more; nothing otherwise.
fn agent_table(o: &mut String, rows: &[&GroupSummary], shown: Shown) {
    let teams: Vec<&&GroupSummary> = rows
        .iter()
        .filter(|g| g.per_agent.len() >= PER_AGENT_TABLE_AGENTS)
        .collect();
    if teams.is_empty() {
        return;
    }
    let u = shown.unit("BL");
    let digits = shown.digits("BL", 3);
    let length = |s: Option<&Summary>| med_in(s, digits, |v| shown.value("BL", v));
    let _ = writeln!(
        o,
        "<h3>Per agent</h3>\n<table class=\"agents\"><thead><tr><th>configuration</th><th>agent</th><th>RMS error, observed ({u})</th><th>max error, observed ({u})</th><th>RMS error, true ({u})</th><th>worst agent in</th></tr></thead><tbody>"
    );
    for g in teams {
        for (i, a) in g.per_agent.iter().enumerate() {
            let c = crate::plot::palette::agent(i);
            let _ = writeln!(
                o,
                "<tr><td>{}</td><td><span style=\"color:#{:02x}{:02x}{:02x}\">&#9679;</span> agent {}</td><td>{}</td><td>{}</td><td>{}</td><td>{} of {} runs</td></tr>",
                esc(&g.config_label()),
                c.0,
                c.1,
                c.2,
                i + 1,
                length(a.rms_error.as_ref()),
                length(a.max_error.as_ref()),
                length(a.rms_error_true.as_ref()),
                a.worst,
                g.n,
            );
        }
        let _ = writeln!(
            o,
            "<tr><td>{}</td><td>worst agent</td><td>{}</td><td>{}</td><td>{}</td><td></td></tr>",
            esc(&g.config_label()),
            length(g.metric(Metric::RmsErrorWorstAgent)),
            length(g.metric(Metric::MaxError)),
            length(g.metric(Metric::RmsErrorTrueWorstAgent)),
        );
    }
    o.push_str("</tbody></table>\n<p class=\"note\">Agents numbered from 1 as in the plots (column <code>rms_error_agent0_bl</code> of runs.csv is agent 1). Medians with [first quartile, third quartile] over the tracked runs. The worst agent of a run is the one with the largest observed RMS error; its row is the median of that per-run worst, its max the largest error of any agent. docs/tracking.md, \"Metrics\".</p>\n");
}

fn inline_svg(stem: &Path) -> Result<String, Error> {
    let path = crate::plot::with_ext(stem, "svg");
    let text = std::fs::read_to_string(&path)
        .map_err(|e| Error::Failed(format!("{}: {e}", path.display())))?;
    let start = text.find("<svg").unwrap_or(0);
    Ok(text[start..].to_string())
}

const STYLE: &str = "body{font-family:'DejaVu Sans',Helvetica,Arial,sans-serif;margin:1.5em auto;max-width:1220px;color:#222;padding:0 1em;box-sizing:border-box}\
h1{font-size:1.6em}h2{margin-top:2em;border-bottom:1px solid #ccc}table{border-collapse:collapse;font-size:.78em;margin:1em 0;width:100%;table-layout:fixed}\
th,td{border:1px solid #ccc;padding:.25em .3em;text-align:right;vertical-align:top;overflow-wrap:anywhere}th:first-child{width:11em}th{hyphens:auto;overflow-wrap:break-word}th{background:#f3f3f3;vertical-align:bottom;font-weight:600;cursor:pointer;user-select:none}\
th[data-dir=asc]::after{content:' \\25B2'}th[data-dir=desc]::after{content:' \\25BC'}td:first-child,th:first-child{text-align:left}td.na{background:#fafafa}\
td small{display:block}small{color:#666}.note{color:#555;font-size:.85em}figure{margin:1.5em 0}svg{max-width:100%;height:auto}\
pre{background:#f6f6f6;padding:1em;overflow:auto;white-space:pre-wrap}code{overflow-wrap:anywhere}\
dl{display:grid;grid-template-columns:max-content auto;gap:.2em 1em}dt{font-weight:bold}dd{margin:0;overflow-wrap:anywhere}";

/// Sorts a table by the clicked column (again: the other way): by a cell's `data-v` if it has
/// one, else by the number its text starts with, else by its text; empty cells last.
const SORT_SCRIPT: &str = "document.querySelectorAll('table').forEach(function(t){var h=t.tHead;if(!h)return;\
var hs=Array.prototype.slice.call(h.rows[0].cells);hs.forEach(function(th,i){th.title='sort';th.addEventListener('click',function(){\
var asc=th.dataset.dir!=='asc';hs.forEach(function(c){delete c.dataset.dir});th.dataset.dir=asc?'asc':'desc';var b=t.tBodies[0];\
var key=function(r){var c=r.cells[i];if(!c)return null;var s=c.dataset.v!==undefined?c.dataset.v:c.textContent.trim();if(s===''||s==='\\u2013')return null;\
var n=parseFloat(s);return isNaN(n)?s.toLowerCase():n};var rows=Array.prototype.slice.call(b.rows);rows.sort(function(x,y){var p=key(x),q=key(y);\
if(p===null)return q===null?0:1;if(q===null)return -1;var d=typeof p===typeof q?(p<q?-1:p>q?1:0):(typeof p==='number'?-1:1);return asc?d:-d});\
rows.forEach(function(r){b.appendChild(r)})})})});";

/// Writes `dir/report.html` from the summary of each configuration (`sums`, exact counts with
/// the quartiles of the runs kept for the figures, [`super::sample`]), those runs (`runs`, in
/// run order; the replay links are theirs) and the number of the folder's runs with a replay
/// page.
pub fn write(
    dir: &Path,
    m: &Manifest,
    (sums, runs, replays): (&[GroupSummary], &[RunRecord], usize),
    plots: &[PlotFile],
    units: Units,
) -> Result<(), Error> {
    let e = &m.experiment;
    let mut o = String::new();
    let _ = write!(
        o,
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>magbench: {}</title><style>{STYLE}</style></head><body>\n",
        esc(&e.name)
    );
    let _ = writeln!(
        o,
        "<h1>magbench experiment <code>{}</code></h1>",
        esc(&e.name)
    );
    if !e.description.is_empty() {
        let _ = writeln!(o, "<p>{}</p>", esc(&e.description));
    }
    let failed = if m.runs_failed > 0 {
        format!(
            ", <strong>{} crashed</strong> (see the <code>error</code> column)",
            m.runs_failed
        )
    } else {
        String::new()
    };
    let wall: f64 = m.sessions.iter().filter_map(|s| s.wall_time_s).sum();
    let _ = writeln!(
        o,
        "<dl><dt>runs</dt><dd>{} of {}{failed}</dd><dt>scenarios</dt><dd>{}</dd><dt>planners</dt><dd>{}</dd>{}<dt>seeds</dt><dd>{}</dd><dt>limits</dt><dd>{}</dd>\
<dt>code</dt><dd>magbench {} at git {}</dd><dt>host</dt><dd>{} ({}, {} CPUs), {} threads</dd><dt>time</dt><dd>{} to {} ({:.1} s of sweeping)</dd><dt>experiment sha256</dt><dd><code>{}</code></dd></dl>",
        m.runs_done,
        e.runs_total,
        esc(&e.scenarios.join(", ")),
        esc(&e.planners.join(", ")),
        if e.trackers.is_empty() {
            String::new()
        } else {
            format!(
                "{}<dt>trackers</dt><dd>{}</dd><dt>presets</dt><dd>{}</dd>",
                match &e.tracked_plans {
                    Some(p) => format!(
                        "<dt>tracked plans</dt><dd>{} (every planner also has planning runs)</dd>",
                        esc(&p.join(", "))
                    ),
                    None => String::new(),
                },
                esc(&e.trackers.join(", ")),
                esc(&e.presets.join(", "))
            )
        },
        e.seeds.len(),
        [
            e.max_iterations.map(|i| format!("{i} iterations")),
            e.time_limit_s.map(|t| format!("{t} s"))
        ]
        .into_iter()
        .flatten()
        .collect::<Vec<_>>()
        .join(", "),
        esc(&m.magbench_version),
        esc(&m.git_revision),
        esc(&m.host.name),
        esc(&m.host.cpu_model),
        m.host.cpus,
        m.threads,
        esc(&m.started),
        esc(m.finished.as_deref().unwrap_or("–")),
        wall,
        esc(&e.sha256),
    );
    if !m.one_at_a_time.is_empty() {
        let _ = writeln!(
            o,
            "<p class=\"note\">The runs of {} went one at a time: they hold a global lock (Python plugins hold Python's GIL, and one thread runs Python at a time). Their times are those of a run alone; the other runs went on beside them on {} threads, and the sweep took longer than its thread count suggests.</p>",
            esc(&m.one_at_a_time.join(", ")),
            m.threads
        );
    }
    let policy = m
        .replays
        .as_deref()
        .map(|p| format!(" (replay policy <code>{}</code>)", esc(p)))
        .unwrap_or_default();
    let _ = writeln!(
        o,
        "<p>Replays: {}{policy}; each configuration's are linked in its <em>replays (by seed)</em> column.</p>",
        if replays == 0 {
            "no replay pages".to_string()
        } else {
            format!("{replays} of {} runs have a replay page", m.runs_done)
        }
    );
    o.push_str("<p>Files: <a href=\"runs.csv\">runs.csv</a> · <a href=\"progress.csv\">progress.csv</a> · <a href=\"manifest.json\">manifest.json</a> · <a href=\"ompl.log\">ompl.log</a> (OMPL benchmark log)</p>\n");
    let mut scenarios: Vec<&str> = vec![];
    for g in sums {
        if !scenarios.contains(&g.scenario.as_str()) {
            scenarios.push(&g.scenario);
        }
    }
    for sc in scenarios {
        let _ = writeln!(o, "<h2>{}</h2>", esc(sc));
        let preview = dir.join(crate::replay::files::preview_file(sc));
        if preview.is_file() {
            let _ = writeln!(
                o,
                "<figure class=\"preview\" style=\"max-width:720px\">{}<figcaption>The scenario: each leg's map, start (agents to scale), goals and the pair's proximity range.</figcaption></figure>",
                inline_svg(&preview.with_extension(""))?
            );
        }
        let rows: Vec<&GroupSummary> = sums.iter().filter(|g| g.scenario == sc).collect();
        let shown = Shown::for_scenario(units, sc, dir);
        if let Some(k) = shown.um_per_bl {
            let _ = writeln!(
                o,
                "<p class=\"note\">Lengths in µm and speeds in mm/s: 1 BL = {k} µm, this scenario's agent diameter.</p>"
            );
        }
        table(&mut o, &rows, (dir, runs), shown);
        agent_table(&mut o, &rows, shown);
        for p in plots.iter().filter(|p| p.scenario == sc) {
            let rel = p
                .stem
                .strip_prefix(dir)
                .unwrap_or(&p.stem)
                .display()
                .to_string();
            let _ = writeln!(
                o,
                "<figure>{}<figcaption>{} — <a href=\"{}.svg\">SVG</a> · <a href=\"{}.png\">PNG</a></figcaption></figure>",
                inline_svg(&p.stem)?,
                esc(&p.title),
                esc(&rel),
                esc(&rel)
            );
        }
    }
    o.push_str(&crate::compare::section::html(dir, runs)?);
    let _ = writeln!(
        o,
        "<h2>Experiment file</h2><p><code>{}</code></p><pre>{}</pre>",
        esc(&e.source),
        esc(&e.content)
    );
    let _ = writeln!(o, "<script>{SORT_SCRIPT}</script>");
    o.push_str("</body></html>\n");
    let path = dir.join("report.html");
    std::fs::write(&path, o).map_err(|e| Error::Failed(format!("{}: {e}", path.display())))
}
