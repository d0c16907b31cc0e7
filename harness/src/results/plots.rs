//! The plots of a results folder, per scenario, into `plots/<scenario>/`:
//!
//! - `success-vs-iterations`, `success-vs-time`: the fraction of runs with an exact solution
//!   by then, per configuration, with the 95% Wilson interval as a band;
//! - `cost-vs-iterations`, `cost-vs-time`: the median best cost with the interquartile band
//!   (unsolved runs count as +∞, so the median shows once half the runs are solved); against
//!   planning time, planners whose iterations differ in cost (trajopt's convex subproblems,
//!   RRT's extensions) are compared at equal time;
//! - a box plot of every metric the table ([`crate::metrics::TABLE`]) gives one (`final-cost`,
//!   `time-to-first-solution`, `path-length`, ...; with trackers `rms-error`, `max-error`, the
//!   worst agent's, ...), one box per configuration;
//! - with trackers: `rms-error-cdf` and, for a team of three or more, each agent's RMS error
//!   (`rms-error-per-agent`, one colour per agent).
//!
//! A configuration drawn from a sample of its runs (more than [`super::sample::SAMPLE`]) says so
//! in its legend: "(a sample: 7502 of 30005 runs)".
//!
//! Planners are drawn in one colour family and tracked configurations in another, each with
//! its own dash and marker ([`crate::plot::style`]); iterations and times get a log axis when
//! they span more than a decade ([`FigureOptions::axes`]). docs/figures.md has the options.

use crate::units::Shown;
use std::path::{Path, PathBuf};

use super::manifest::Manifest;
use super::summary::{GroupSummary, groups};
use super::traces::{TracePoint, Traces};
use crate::Error;
use crate::metrics::Metric;
use crate::plot::charts::{BandPoint, BoxChart, CdfChart, LineBandChart, Series};
use crate::plot::export::{AxisScale, FigureOptions};
use crate::plot::style::{self, Family, Look};
use crate::plot::{Figure, save_with};
use crate::run::RunRecord;
use crate::stats::quantile::quantile_sorted;
use crate::stats::wilson;

/// A written plot: its title and the stem of its `.svg`/`.png` pair.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotFile {
    /// Scenario it belongs to.
    pub scenario: String,
    /// Title.
    pub title: String,
    /// Path without extension.
    pub stem: PathBuf,
}

/// A file-name-safe form of a label.
pub fn slug(s: &str) -> String {
    let t: String = s
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "-_.".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    t.trim_end_matches(".toml").to_string()
}

const GRID: usize = 120;

/// `GRID + 1` points from 0 to `max`, or log-spaced from `min` to `max` on a log axis.
fn grid(max: f64, log_from: Option<f64>) -> Vec<f64> {
    let max = if max.is_finite() && max > 0.0 {
        max
    } else {
        1.0
    };
    match log_from.filter(|m| m.is_finite() && *m > 0.0 && *m < max) {
        Some(min) => {
            let (a, b) = (min.ln(), max.ln());
            (0..=GRID)
                .map(|k| (a + (b - a) * k as f64 / GRID as f64).exp())
                .collect()
        }
        None => (0..=GRID).map(|k| max * k as f64 / GRID as f64).collect(),
    }
}

/// The decade at or below the smallest positive value (the start of a log axis).
fn decade_below(values: impl Iterator<Item = f64>) -> Option<f64> {
    let min = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold(f64::INFINITY, f64::min);
    min.is_finite().then(|| 10f64.powf(min.log10().floor()))
}

/// The unit of a cost under the objectives of `runs` (planner parameter `objective`).
pub fn cost_axis(runs: &[&RunRecord], what: &str) -> String {
    let mut objectives: Vec<&str> = runs
        .iter()
        .map(|r| {
            r.planner_params
                .split(',')
                .find_map(|kv| kv.trim().strip_prefix("objective="))
                .map(|v| v.trim_matches('"'))
                .unwrap_or("path-length")
        })
        .collect();
    objectives.sort();
    objectives.dedup();
    let unit = |o: &str| match o {
        "path-length" => "summed agent path length (BL)",
        "duration" => "plan duration (s)",
        "control-effort" => "control effort, ∫ normalised gradient² dt (s)",
        _ => "objective's units",
    };
    match objectives.as_slice() {
        [one] => format!("{what}: {}", unit(one)),
        _ => format!("{what} ({})", objectives.join(" / ")),
    }
}

fn success_curve(runs: &[&RunRecord], xs: &[f64], at: Metric) -> Vec<BandPoint> {
    let n = runs.len() as u64;
    xs.iter()
        .map(|&x| {
            let s = runs
                .iter()
                .filter(|r| r.solved && r.get(at).is_some_and(|v| v <= x))
                .count() as u64;
            let (lo, hi) = wilson(s, n, 0.95);
            BandPoint {
                x,
                y: s as f64 / n.max(1) as f64,
                lo,
                hi,
            }
        })
        .collect()
}

/// The share of each planning group's runs solved by each point of `xs` of `at`, as a step
/// chart with 95% Wilson bands; `x_axis` is the x label and whether that axis is logarithmic.
fn success_chart(
    planning: &[&Vec<&RunRecord>],
    at: Metric,
    xs: &[f64],
    x_axis: (&str, bool),
    title: &str,
    looks: &[Look],
    width: u32,
) -> LineBandChart {
    LineBandChart {
        title: title.into(),
        x_label: x_axis.0.into(),
        y_label: "runs solved (fraction)".into(),
        series: planning
            .iter()
            .map(|g| Series {
                label: g[0].planner.clone(),
                data: success_curve(g, xs, at),
            })
            .collect(),
        y_range: Some((0.0, 1.0)),
        steps: true,
        band_label: "95% Wilson interval".into(),
        empty_note: String::new(),
        looks: looks.to_vec(),
        x_log: x_axis.1,
        width,
    }
}

/// The median best cost of `runs` at each of `xs` (ascending; iterations or seconds, as `at`
/// reads a progress row), with the interquartile band; a run unsolved by then counts as +∞.
/// A run's cost at `x` is that of the last point of its trace's longest prefix with `at` at
/// most `x`.
fn cost_curve(
    runs: &[&RunRecord],
    progress: &Traces,
    xs: &[f64],
    at: fn(&TracePoint) -> f64,
) -> Result<Vec<BandPoint>, Error> {
    // costs[k]: each run's best cost by xs[k]
    let mut costs: Vec<Vec<f64>> = vec![Vec::with_capacity(runs.len()); xs.len()];
    for r in runs {
        let trace = progress.get(r.run)?;
        let mut seen = 0;
        for (k, &x) in xs.iter().enumerate() {
            while seen < trace.len() && at(&trace[seen]) <= x {
                seen += 1;
            }
            let cost = seen
                .checked_sub(1)
                .and_then(|i| trace[i].best_cost)
                .unwrap_or(f64::INFINITY);
            costs[k].push(cost);
        }
    }
    Ok(xs
        .iter()
        .zip(costs.iter_mut())
        .map(|(&x, costs)| {
            costs.sort_by(f64::total_cmp);
            if costs.is_empty() {
                return BandPoint {
                    x,
                    y: f64::NAN,
                    lo: f64::NAN,
                    hi: f64::NAN,
                };
            }
            let q = |p: f64| {
                let v = quantile_sorted(costs, p);
                if v.is_nan() { f64::INFINITY } else { v }
            };
            let (q1, med, q3) = (q(0.25), q(0.5), q(0.75));
            // An infinite upper quartile draws the band to the top of the chart.
            BandPoint {
                x,
                y: if med.is_finite() { med } else { f64::NAN },
                lo: if q1.is_finite() { q1 } else { f64::NAN },
                hi: if q3.is_finite() { q3 } else { 1e300 },
            }
        })
        .collect())
}

/// The median best cost of each planning configuration against `xs` (iterations or seconds,
/// as the progress rows are read), with the interquartile band; `x_axis` is the x label and
/// whether that axis is logarithmic.
fn cost_chart(
    planning: &[&Vec<&RunRecord>],
    (by_run, at): (&Traces, fn(&TracePoint) -> f64),
    xs: &[f64],
    x_axis: (&str, bool),
    title: &str,
    looks: &[Look],
    width: u32,
) -> Result<LineBandChart, Error> {
    let series: Vec<Series<Vec<BandPoint>>> = planning
        .iter()
        .map(|g| {
            Ok(Series {
                label: g[0].planner.clone(),
                data: cost_curve(g, by_run, xs, at)?,
            })
        })
        .collect::<Result<_, Error>>()?;
    let finite: Vec<f64> = series
        .iter()
        .flat_map(|s| s.data.iter())
        .flat_map(|p| [p.y, p.lo, p.hi])
        .filter(|v| v.is_finite() && *v < 1e299)
        .collect();
    let y_range = match (
        finite.iter().copied().reduce(f64::min),
        finite.iter().copied().reduce(f64::max),
    ) {
        (Some(a), Some(b)) if b > a => Some((a - 0.05 * (b - a), b + 0.05 * (b - a))),
        (Some(a), Some(_)) => Some((a * 0.9 - 1e-9, a * 1.1 + 1e-9)),
        _ => Some((0.0, 1.0)),
    };
    let planning_runs: Vec<&RunRecord> = planning.iter().flat_map(|g| g.iter().copied()).collect();
    Ok(LineBandChart {
        title: title.into(),
        x_label: x_axis.0.into(),
        y_label: cost_axis(&planning_runs, "best cost"),
        series,
        y_range,
        steps: true,
        band_label: "interquartile range (unsolved = +∞)".into(),
        empty_note: "no configuration solved half of its runs: no median cost yet".into(),
        looks: looks.to_vec(),
        x_log: x_axis.1,
        width,
    })
}

struct Writer<'a> {
    dir: &'a Path,
    opts: &'a FigureOptions,
    files: Vec<PlotFile>,
}

impl Writer<'_> {
    fn save<F: Figure>(
        &mut self,
        scenario: &str,
        name: &str,
        fig: &F,
        title: &str,
    ) -> Result<(), Error> {
        let stem = self.dir.join("plots").join(slug(scenario)).join(name);
        save_with(fig, &stem, self.opts)?;
        self.files.push(PlotFile {
            scenario: scenario.to_string(),
            title: title.to_string(),
            stem,
        });
        Ok(())
    }
}

/// Teams this large or larger get a per-agent box plot (a pair's two agents are in the worst
/// agent's and the team's plots already).
const PER_AGENT_PLOT_AGENTS: usize = 3;

/// One box per configuration and agent of the agents' observed RMS errors, in the agents'
/// colours, when a configuration tracks a team of [`PER_AGENT_PLOT_AGENTS`] or more.
fn per_agent_box(
    sc: &str,
    tracked: &[&Vec<&RunRecord>],
    label: &dyn Fn(&[&RunRecord]) -> String,
    (opts, shown): (&FigureOptions, Shown),
) -> Option<BoxChart> {
    let agents = |g: &[&RunRecord]| g.iter().map(|r| r.per_agent.len()).max().unwrap_or(0);
    if !tracked.iter().any(|g| agents(g) >= PER_AGENT_PLOT_AGENTS) {
        return None;
    }
    let mut groups = vec![];
    let mut colors = vec![];
    for g in tracked {
        for i in 0..agents(g) {
            groups.push(Series {
                label: format!("{} · agent {}", label(g), i + 1),
                data: g
                    .iter()
                    .map(|r| {
                        r.per_agent
                            .get(i)
                            .and_then(|a| a.rms_bl)
                            .map_or(f64::NAN, |v| shown.value("BL", v))
                    })
                    .collect(),
            });
            colors.push(crate::plot::palette::agent(i));
        }
    }
    Some(BoxChart {
        title: format!("{sc}: RMS tracking error of each agent (observed positions)"),
        value_label: shown.axis("RMS distance of the agent to its planned path", "BL"),
        groups,
        colors,
        log: opts.axes == AxisScale::Log,
        width: opts.size.layout_width(),
    })
}

/// The look of a configuration: planning runs in the planners' family by the planner's place
/// in the experiment, tracked runs in the trackers' family by tracker and preset.
fn look_of(m: &Manifest, g: &[&RunRecord]) -> Look {
    let r = g[0];
    let e = &m.experiment;
    let place = |list: &[String], name: &str| list.iter().position(|p| p == name);
    if r.tracker.is_empty() {
        let i = place(&e.planners, &r.planner).unwrap_or(e.planners.len());
        style::look(Family::Planner, i)
    } else {
        let t = place(&e.trackers, &r.tracker).unwrap_or(e.trackers.len());
        let p = place(&e.presets, &r.preset).unwrap_or(0);
        style::look(Family::Tracker, t + p * e.trackers.len().max(1))
    }
}

/// What a figure's legend adds to the label of configuration `g` when `g` holds a sample of
/// its runs ([`super::sample`]): how many of how many (`sums` has every configuration's count).
fn sample_note(g: &[&RunRecord], sums: &[GroupSummary]) -> Option<String> {
    let r = g[0];
    let n = sums
        .iter()
        .find(|s| {
            (&s.scenario, &s.planner, &s.tracker, &s.preset)
                == (&r.scenario, &r.planner, &r.tracker, &r.preset)
        })?
        .n;
    (n > g.len()).then(|| format!(" (a sample: {} of {n} runs)", g.len()))
}

/// The figures of results folder `dir` with the figure options `opts` (size preset, DPI, axes,
/// PDF), drawn from `runs` (in run order: every run, or the runs a configuration keeps,
/// [`super::sample`]); `sums` has every configuration's count of runs, for the legends of
/// configurations drawn from a sample.
pub fn write_all_with(
    dir: &Path,
    m: &Manifest,
    (runs, sums): (&[RunRecord], &[GroupSummary]),
    progress: &Traces,
    opts: &FigureOptions,
) -> Result<Vec<PlotFile>, Error> {
    let width = opts.size.layout_width();
    let mut w = Writer {
        dir,
        opts,
        files: vec![],
    };
    let all = groups(runs);
    let mut scenarios: Vec<&str> = vec![];
    for g in &all {
        if !scenarios.contains(&g[0].scenario.as_str()) {
            scenarios.push(&g[0].scenario);
        }
    }
    for sc in scenarios {
        let shown = Shown::for_scenario(opts.units, sc, dir);
        let gs: Vec<&Vec<&RunRecord>> = all.iter().filter(|g| g[0].scenario == sc).collect();
        let label = |g: &[&RunRecord]| {
            let r = g[0];
            let note = sample_note(g, sums).unwrap_or_default();
            if r.tracker.is_empty() {
                format!("{}{note}", r.planner)
            } else {
                format!("{} + {} ({}){note}", r.planner, r.tracker, r.preset)
            }
        };
        // a line chart's series are the planning configurations
        let noted = |mut fig: LineBandChart, planning: &[&Vec<&RunRecord>]| {
            for (s, g) in fig.series.iter_mut().zip(planning) {
                s.label += &sample_note(g, sums).unwrap_or_default();
            }
            fig
        };
        // Planning curves: one series per planner variant (tracking repeats the same plans):
        // its planning runs where it has them (they plan every leg; a tracked run's planner
        // columns describe its first plan), else its first tracked configuration.
        let mut planning: Vec<&Vec<&RunRecord>> = vec![];
        for g in &gs {
            match planning.iter().position(|p| p[0].planner == g[0].planner) {
                None => planning.push(g),
                Some(i) if !planning[i][0].tracker.is_empty() && g[0].tracker.is_empty() => {
                    planning[i] = g
                }
                Some(_) => {}
            }
        }
        let looks: Vec<Look> = planning.iter().map(|g| look_of(m, g)).collect();
        // Iterations count across legs: a run of several legs may use the limit once per leg.
        let sc_runs = gs.iter().flat_map(|g| g.iter());
        let most = sc_runs
            .clone()
            .filter_map(|r| r.get(Metric::Iterations))
            .fold(0.0, f64::max);
        let max_it = m
            .experiment
            .max_iterations
            .map(|i| (i as f64).max(most))
            .unwrap_or(most);
        let multi_leg = m.experiment.max_iterations.is_some_and(|i| most > i as f64);
        let first_its = || {
            sc_runs
                .clone()
                .filter_map(|r| r.get(Metric::FirstSolutionIteration))
        };
        let it_log = opts.axes.is_log(first_its().chain([max_it]));
        let xs = grid(
            max_it,
            it_log.then(|| decade_below(first_its()).unwrap_or(1.0).max(1.0)),
        );
        let it_label = if multi_leg {
            "iterations (all legs)"
        } else {
            "iterations"
        };
        let title = format!("{sc}: success rate vs iterations");
        let fig = success_chart(
            &planning,
            Metric::FirstSolutionIteration,
            &xs,
            (it_label, it_log),
            &title,
            &looks,
            width,
        );
        w.save(sc, "success-vs-iterations", &noted(fig, &planning), &title)?;

        let max_t = gs
            .iter()
            .flat_map(|g| g.iter())
            .filter_map(|r| r.get(Metric::PlanTime))
            .fold(0.0, f64::max);
        let max_t = m
            .experiment
            .time_limit_s
            .map(|t| t.max(max_t))
            .unwrap_or(max_t);
        let first_ts = || {
            sc_runs
                .clone()
                .filter_map(|r| r.get(Metric::FirstSolutionTime))
        };
        let t_log = opts.axes.is_log(first_ts().chain([max_t]));
        let ts = grid(
            max_t,
            t_log.then(|| decade_below(first_ts()).unwrap_or(1e-3)),
        );
        let title = format!("{sc}: success rate vs planning time");
        let fig = success_chart(
            &planning,
            Metric::FirstSolutionTime,
            &ts,
            ("planning time (s)", t_log),
            &title,
            &looks,
            width,
        );
        w.save(sc, "success-vs-time", &noted(fig, &planning), &title)?;

        let title = format!("{sc}: best cost vs iterations");
        let fig = cost_chart(
            &planning,
            (progress, |p: &TracePoint| p.iteration as f64),
            &xs,
            (it_label, it_log),
            &title,
            &looks,
            width,
        )?;
        w.save(sc, "cost-vs-iterations", &noted(fig, &planning), &title)?;
        let title = format!("{sc}: best cost vs planning time");
        let fig = cost_chart(
            &planning,
            (progress, |p: &TracePoint| p.time_s),
            &ts,
            ("planning time (s)", t_log),
            &title,
            &looks,
            width,
        )?;
        w.save(sc, "cost-vs-time", &noted(fig, &planning), &title)?;
        let planning_runs: Vec<&RunRecord> =
            planning.iter().flat_map(|g| g.iter().copied()).collect();

        // one box per configuration of a per-run figure
        // `spans`: a quantity (times) that gets a log axis when it spans more than a decade
        let mut save_box = |name: &str,
                            what: &str,
                            value_label: &str,
                            f: &dyn Fn(&RunRecord) -> Option<f64>,
                            groups: &[&Vec<&RunRecord>],
                            spans: bool|
         -> Result<(), Error> {
            let title = format!("{sc}: {what}");
            let colors = groups.iter().map(|g| look_of(m, g).color).collect();
            let groups: Vec<Series<Vec<f64>>> = groups
                .iter()
                .map(|g| Series {
                    label: label(g),
                    data: g.iter().map(|r| f(r).unwrap_or(f64::NAN)).collect(),
                })
                .collect();
            let log = match opts.axes {
                AxisScale::Auto => {
                    spans
                        && opts
                            .axes
                            .is_log(groups.iter().flat_map(|g| g.data.iter().copied()))
                }
                a => a == AxisScale::Log,
            };
            let fig = BoxChart {
                title: title.clone(),
                value_label: value_label.into(),
                colors,
                groups,
                log,
                width,
            };
            w.save(sc, name, &fig, &title)
        };
        let tracked: Vec<&Vec<&RunRecord>> = gs
            .iter()
            .copied()
            .filter(|g| !g[0].tracker.is_empty())
            .collect();
        // the table's box plots: planning and path metrics over the planning series, then
        // tracking metrics over the tracked configurations; times and iterations may get a log
        // axis, a cost's axis names its objective's unit
        for stage_tracking in [false, true] {
            let groups = if stage_tracking { &tracked } else { &planning };
            if groups.is_empty() {
                continue;
            }
            for m in Metric::ALL {
                let d = m.def();
                let Some(p) = d.plot.filter(|_| d.tracking() == stage_tracking) else {
                    continue;
                };
                let any = groups.iter().any(|g| g.iter().any(|r| r.get(*m).is_some()));
                if p.always || any {
                    let spans = d.unit == "s"
                        || matches!(m, Metric::Iterations | Metric::FirstSolutionIteration);
                    let axis = if *m == Metric::Cost {
                        cost_axis(&planning_runs, "final cost")
                    } else {
                        shown.axis(d.label, d.unit)
                    };
                    let value = |r: &RunRecord| r.get(*m).map(|v| shown.value(d.unit, v));
                    save_box(p.stem, p.title, &axis, &value, groups, spans)?;
                }
            }
        }
        if !tracked.is_empty() {
            if let Some(fig) = per_agent_box(sc, &tracked, &label, (opts, shown)) {
                let title = fig.title.clone();
                w.save(sc, "rms-error-per-agent", &fig, &title)?;
            }
            let title = format!("{sc}: distribution of RMS tracking error");
            let rms = Metric::RmsError.def();
            let fig = CdfChart {
                title: title.clone(),
                x_label: shown.axis(rms.label, rms.unit),
                looks: tracked.iter().map(|g| look_of(m, g)).collect(),
                width,
                series: tracked
                    .iter()
                    .map(|g| Series {
                        label: label(g),
                        data: g
                            .iter()
                            .map(|r| {
                                r.get(Metric::RmsError)
                                    .map_or(f64::NAN, |v| shown.value(rms.unit, v))
                            })
                            .collect(),
                    })
                    .collect(),
            };
            w.save(sc, "rms-error-cdf", &fig, &title)?;
        }
    }
    Ok(w.files)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::ProgressRow;

    fn point(run: usize, iteration: u64, time_s: f64, best_cost: Option<f64>) -> ProgressRow {
        ProgressRow {
            run,
            run_id: format!("r{run}"),
            iteration,
            time_s,
            best_cost,
        }
    }

    #[test]
    fn a_configuration_drawn_from_a_sample_says_so_in_its_legend() {
        let runs: Vec<RunRecord> = (0..3)
            .map(|i| RunRecord {
                run: i,
                ..RunRecord::example()
            })
            .collect();
        let g: Vec<&RunRecord> = runs.iter().collect();
        let mut sums = super::super::summary::summaries(&runs);
        assert_eq!(sample_note(&g, &sums), None);
        sums[0].n = 10;
        assert_eq!(
            sample_note(&g, &sums).as_deref(),
            Some(" (a sample: 3 of 10 runs)")
        );
    }

    #[test]
    fn a_cost_curve_is_read_at_iterations_or_at_seconds() {
        let mut a = RunRecord::example();
        a.run = 0;
        let mut b = RunRecord::example();
        b.run = 1;
        // run 0: 9 at iteration 10 (0.5 s), 5 at iteration 20 (3 s); run 1: 7 at iteration 30
        // (0.2 s): its iterations are slow by the first run's clock, fast by the wall clock
        let rows = [
            point(0, 10, 0.5, Some(9.0)),
            point(0, 20, 3.0, Some(5.0)),
            point(1, 30, 0.2, Some(7.0)),
        ];
        let by_run = Traces::from_rows(&rows);
        let runs = [&a, &b];
        let medians = |xs: &[f64], at: fn(&TracePoint) -> f64| -> Vec<f64> {
            cost_curve(&runs, &by_run, xs, at)
                .unwrap()
                .iter()
                .map(|p| p.y)
                .collect()
        };
        let by_iteration = medians(&[15.0, 25.0, 35.0], |p| p.iteration as f64);
        let by_time = medians(&[0.3, 1.0, 5.0], |p| p.time_s);
        // the median of two runs is their mean: one unsolved makes it +∞ (no line)
        assert!(by_iteration[0].is_nan() && by_iteration[1].is_nan());
        assert_eq!(by_iteration[2], 6.0);
        assert!(by_time[0].is_nan());
        assert_eq!(by_time[1], 8.0);
        assert_eq!(by_time[2], 6.0);
    }
}
