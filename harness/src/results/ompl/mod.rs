//! `ompl.log`: the runs in OMPL's benchmark log format, for `ompl_benchmark_statistics.py`
//! (which loads it into an SQLite database) and Planner Arena.
//!
//! The mapping: an OMPL *experiment* is one problem. `ompl.log` holds every run of the
//! magbench experiment as one OMPL experiment whose planner configurations are named
//! `control_<planner variant>`, qualified by `@<scenario>` when the experiment has several
//! scenarios and by `+<tracker>+<preset>` when it tracks. When there are several scenarios,
//! `ompl/<scenario>.log` additionally holds each scenario as its own OMPL experiment with
//! planners named `control_<planner variant>` (Planner Arena's per-problem view).
//!
//! Run properties follow OMPL's names and types: `time REAL` (planning time), `solved
//! BOOLEAN` (exact or approximate, as in OMPL), `approximate solution BOOLEAN`, `solution
//! difference REAL`, `status ENUM` (`ompl::base::PlannerStatus`), `graph states INTEGER`,
//! `iterations INTEGER`, `best cost REAL`, `solution length REAL`, `solution smoothness
//! REAL`, `solution clearance REAL`, ... (the metric table's OMPL names); progress properties
//! are `best cost REAL`, `iterations INTEGER` and `time REAL` for planners that track a best
//! cost; planners that stop at their first solution have no progress section, as OMPL's
//! non-optimizing planners declare no progress properties (their traces stay in
//! `progress.csv`). The log declares no experiment properties: Planner Arena's "Progress" tab
//! filters progress rows by them and cannot find them (docs/ompl-logs.md); the team size is a
//! planner configuration's common property `agents`. See [`parse`] for the grammar.

pub mod gather;
pub mod parse;

use gather::{Block, Line, Lines};
pub use gather::{Gather, Gathered};

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::manifest::Manifest;
use super::traces::TracePoint;
use crate::Error;
use crate::metrics::Metric;
use crate::run::RunRecord;

/// The values of OMPL's `PlannerStatus` enum, in order (`status ENUM` indexes this list).
pub const STATUS_ENUM: [&str; 9] = [
    "Unknown status",
    "Invalid start",
    "Invalid goal",
    "Unrecognized goal type",
    "Timeout",
    "Approximate solution",
    "Exact solution",
    "Crash",
    "Abort",
];

fn num(v: f64) -> String {
    if v.is_nan() {
        String::new()
    } else {
        format!("{v}")
    }
}

fn opt<T: ToString>(v: Option<T>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

fn optf(v: Option<f64>) -> String {
    v.map(num).unwrap_or_default()
}

fn boolean(b: bool) -> String {
    (b as u8).to_string()
}

/// The run properties of a record (name with type suffix → value), sorted by name like OMPL:
/// how the run ended, then every metric of the table with an OMPL property (tracking metrics
/// for tracked runs only).
fn properties(r: &RunRecord) -> BTreeMap<&'static str, String> {
    let mut p = BTreeMap::new();
    p.insert("approximate solution BOOLEAN", boolean(r.approximate));
    p.insert("seed INTEGER", r.seed.to_string());
    p.insert("solved BOOLEAN", boolean(r.solved || r.approximate));
    p.insert("status ENUM", r.status.ompl_code().to_string());
    let tracked = !r.tracker.is_empty();
    if tracked {
        p.insert(
            "tracking agent contact BOOLEAN",
            opt(r.agent_contact.map(|b| b as u8)),
        );
        p.insert(
            "tracking reached goal BOOLEAN",
            opt(r.reached_goal.map(|b| b as u8)),
        );
    }
    for m in Metric::ALL {
        let d = m.def();
        if let Some(name) = d.ompl.filter(|_| tracked || !d.tracking()) {
            p.insert(name, optf(r.get(*m)));
        }
    }
    p
}

fn single_line(s: &str) -> String {
    s.replace(['\n', '\r'], " ")
}

fn token(s: &str) -> String {
    let t: String = s
        .chars()
        .map(|c| if c.is_whitespace() { '_' } else { c })
        .collect();
    if t.is_empty() { "NO_NAME".into() } else { t }
}

fn multiline(out: &mut String, text: &str) {
    out.push_str("<<<|\n");
    for l in text.lines() {
        // A line starting with the closing mark would end the block early.
        if l.starts_with("|>>>") {
            out.push(' ');
        }
        out.push_str(l);
        out.push('\n');
    }
    out.push_str("|>>>\n");
}

fn block_name(r: &RunRecord, qualify_scenario: bool) -> String {
    let mut name = format!("control_{}", r.planner);
    if qualify_scenario {
        name += &format!("@{}", r.scenario);
    }
    if !r.tracker.is_empty() {
        name += &format!("+{}+{}", r.tracker, r.preset);
    }
    single_line(&name)
}

fn settings(r: &RunRecord) -> Vec<(String, String)> {
    let mut s = vec![("planner".to_string(), r.planner_name.clone())];
    for kv in r.planner_params.split(',').filter(|s| !s.is_empty()) {
        if let Some((k, v)) = kv.split_once('=') {
            s.push((format!("{}.{k}", r.planner_name), v.to_string()));
        }
    }
    s.push(("scenario".into(), r.scenario.clone()));
    if !r.tracker.is_empty() {
        s.push(("tracker".into(), r.tracker.clone()));
        s.push(("preset".into(), r.preset.clone()));
    }
    if let Some(i) = r.max_iterations {
        s.push(("max_iterations".into(), i.to_string()));
    }
    s.push(("agents".into(), r.agents.to_string()));
    s.sort();
    s
}

/// A run's progress line: `best cost,iterations,time,;` for each point of its trace, the last
/// point of each time kept (OMPL's progress table is keyed by run and time).
fn progress_line(points: &[TracePoint]) -> String {
    // a time as it is written: distinct numbers are distinct texts, and every NaN is ""
    let time = |t: f64| if t.is_nan() { u64::MAX } else { t.to_bits() };
    // the last point of each time, at the place of the time's first point
    let mut at: std::collections::HashMap<u64, usize> =
        std::collections::HashMap::with_capacity(points.len());
    let mut kept: Vec<&TracePoint> = Vec::with_capacity(points.len());
    for p in points {
        match at.entry(time(p.time_s)) {
            std::collections::hash_map::Entry::Occupied(e) => kept[*e.get()] = p,
            std::collections::hash_map::Entry::Vacant(e) => {
                e.insert(kept.len());
                kept.push(p);
            }
        }
    }
    let mut o = String::new();
    for p in kept {
        match p.best_cost {
            Some(c) => write_num(&mut o, c),
            None => o.push_str("inf"),
        }
        let _ = write!(o, ",{},", p.iteration);
        write_num(&mut o, p.time_s);
        o.push_str(",;");
    }
    o
}

/// Appends `v` as [`num`] writes it.
fn write_num(o: &mut String, v: f64) {
    if !v.is_nan() {
        let _ = write!(o, "{v}");
    }
}

/// Writes one OMPL benchmark log holding the configurations `bl` as experiment `name` to `w`,
/// a run's line at a time, read from `lines`; a configuration's name is qualified by its
/// scenario if `qualify_scenario`.
fn write_log(
    w: &mut impl std::io::Write,
    name: &str,
    m: &Manifest,
    (bl, lines): (&[&Block], &mut Lines),
    qualify_scenario: bool,
) -> std::io::Result<()> {
    // the text so far, written out and cleared after the head and after each block's head
    let mut o = String::new();
    let e = &m.experiment;
    let _ = writeln!(o, "magbench version {}", m.magbench_version);
    let _ = writeln!(o, "Experiment {}", token(name));
    let _ = writeln!(o, "Running on {}", token(&m.host.name));
    let _ = writeln!(o, "Starting at {}", m.started.trim_end_matches('Z'));
    let mut setup = format!(
        "magbench experiment {} (sha256 {})\ngit revision {}\n",
        e.name, e.sha256, m.git_revision
    );
    setup += &e.content;
    multiline(&mut o, &setup);
    multiline(
        &mut o,
        &format!("{} ({} CPUs, {})", m.host.cpu_model, m.host.cpus, m.host.os),
    );
    let _ = writeln!(
        o,
        "{} is the random seed",
        e.seeds.first().copied().unwrap_or(0)
    );
    let _ = writeln!(
        o,
        "{} seconds per run",
        e.time_limit_s.map(num).unwrap_or_else(|| "inf".into())
    );
    let _ = writeln!(o, "inf MB per run");
    let per_planner = bl.iter().map(|b| b.runs.len()).max().unwrap_or(0);
    let _ = writeln!(o, "{per_planner} runs per planner");
    let total: f64 = m.sessions.iter().filter_map(|s| s.wall_time_s).sum();
    let _ = writeln!(o, "{} seconds spent to collect the data", num(total));
    let _ = writeln!(o, "1 enum type");
    let _ = writeln!(o, "status|{}", STATUS_ENUM.join("|"));
    let _ = writeln!(o, "{} planners", bl.len());
    w.write_all(o.as_bytes())?;
    o.clear();
    for b in bl {
        let _ = writeln!(o, "{}", b.name[usize::from(qualify_scenario)]);
        let _ = writeln!(o, "{} common properties", b.settings.len());
        for (k, v) in &b.settings {
            let _ = writeln!(o, "{} = {}", single_line(k), single_line(v));
        }
        let _ = writeln!(o, "{} properties for each run", b.names.len());
        for n in &b.names {
            let _ = writeln!(o, "{n}");
        }
        let _ = writeln!(o, "{} runs", b.runs.len());
        w.write_all(o.as_bytes())?;
        o.clear();
        for &at in &b.runs {
            let run = lines.read(at, Line::Run)?;
            writeln!(w, "{run}")?;
        }
        // OMPL writes progress only for planners that declare progress properties, which
        // its non-optimizing planners (RRT, KPIECE, ...) do not.
        if b.tracks_cost {
            let _ = writeln!(o, "3 progress properties for each run");
            let _ = writeln!(o, "best cost REAL\niterations INTEGER\ntime REAL");
            let _ = writeln!(o, "{} runs", b.runs.len());
            w.write_all(o.as_bytes())?;
            o.clear();
            for &at in &b.runs {
                let progress = lines.read(at, Line::Progress)?;
                writeln!(w, "{progress}")?;
            }
        }
        o.push_str(".\n");
    }
    w.write_all(o.as_bytes())?;
    w.flush()
}

/// Writes the log of [`write_log`] to the file at `path`.
fn write_file(
    path: &Path,
    name: &str,
    m: &Manifest,
    log: (&[&Block], &mut Lines),
    qualify_scenario: bool,
) -> Result<(), Error> {
    let failed = |e: std::io::Error| Error::Failed(format!("{}: {e}", path.display()));
    let mut w = std::io::BufWriter::new(std::fs::File::create(path).map_err(failed)?);
    write_log(&mut w, name, m, log, qualify_scenario).map_err(failed)
}

/// Writes `ompl.log` (and `ompl/<scenario>.log` for several scenarios) into `dir` from the
/// gathered runs, and removes their temporary file.
pub fn write(dir: &Path, m: &Manifest, gathered: Gathered) -> Result<Vec<PathBuf>, Error> {
    let Gathered {
        mut lines,
        blocks,
        scenarios,
    } = gathered;
    let all: Vec<&Block> = blocks.iter().collect();
    let many = scenarios.len() > 1;
    let mut files = vec![];
    let path = dir.join("ompl.log");
    write_file(&path, &m.experiment.name, m, (&all, &mut lines), many)?;
    files.push(path);
    if many {
        let sub = dir.join("ompl");
        std::fs::create_dir_all(&sub)
            .map_err(|e| Error::Failed(format!("{}: {e}", sub.display())))?;
        for s in &scenarios {
            let these: Vec<&Block> = blocks.iter().filter(|b| &b.scenario == s).collect();
            let stem = token(&s.replace(['/', '\\'], "_"));
            let path = sub.join(format!("{}.log", stem.trim_end_matches(".toml")));
            let name = format!("{}-{}", m.experiment.name, stem.trim_end_matches(".toml"));
            write_file(&path, &name, m, (&these, &mut lines), false)?;
            files.push(path);
        }
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(iteration: u64, time_s: f64, best_cost: Option<f64>) -> TracePoint {
        TracePoint {
            iteration,
            time_s,
            best_cost,
        }
    }

    #[test]
    fn a_progress_line_has_the_last_point_of_each_time_where_the_time_first_appears() {
        let points = [
            point(1, 0.5, None),
            point(2, 0.25, Some(9.0)),
            point(3, 0.5, Some(7.5)),
            point(4, -0.0, Some(f64::NAN)),
            point(5, 0.0, Some(6.0)),
            point(6, f64::NAN, None),
            point(7, f64::NAN, Some(5.0)),
        ];
        assert_eq!(
            progress_line(&points),
            "7.5,3,0.5,;9,2,0.25,;,4,-0,;6,5,0,;5,7,,;"
        );
        assert_eq!(progress_line(&[]), "");
    }
}
