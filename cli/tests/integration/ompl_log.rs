//! `ompl.log` loads into OMPL's own parser (`ompl_benchmark_statistics`, Debian package
//! `ompl-demos`, installed by `.ci/run`) and into a strict reimplementation of the format's
//! grammar (`magbench::results::ompl::parse`), with every run, property and progress sample.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{opts, write};
use magbench::experiment::Experiment;
use magbench::metrics::Metric;
use magbench::results::ompl::parse::parse;
use magbench::results::store::{read_progress, read_runs};
use magbench::run::fake::FakeExecutor;
use magbench::sweep::run_sweep;

const EXP: &str = r#"
name = "ompl-test"
scenarios = ["micro-factory", "open-field"]
planners = ["fake", "fake{p=0.5, cost=8}", "fake{panic=true}"]
trackers = ["fake"]
presets = ["ideal", "realistic"]
seeds = 3
[limits]
iterations = 400
"#;

/// The progress samples `ompl.log` holds: those of configurations that track a best cost (a
/// run with a cost at more than one point of its trace); OMPL writes no progress for planners
/// that do not.
fn logged_progress(out: &Path) -> usize {
    use std::collections::BTreeMap;
    let runs = read_runs(out).unwrap();
    let progress = read_progress(out).unwrap();
    let config = |r: &magbench::run::RunRecord| {
        (
            r.scenario.clone(),
            r.planner.clone(),
            r.tracker.clone(),
            r.preset.clone(),
        )
    };
    let mut costs: BTreeMap<usize, usize> = BTreeMap::new();
    let mut rows: BTreeMap<usize, usize> = BTreeMap::new();
    for p in &progress {
        *rows.entry(p.run).or_default() += 1;
        *costs.entry(p.run).or_default() += p.best_cost.is_some() as usize;
    }
    let mut tracks: BTreeMap<_, bool> = BTreeMap::new();
    for r in &runs {
        *tracks.entry(config(r)).or_default() |= costs.get(&r.run).is_some_and(|c| *c > 1);
    }
    let n: usize = runs
        .iter()
        .filter(|r| tracks[&config(r)])
        .map(|r| rows.get(&r.run).copied().unwrap_or(0))
        .sum();
    assert!(
        n > 0 && n < progress.len(),
        "the fake planners include both kinds"
    );
    n
}

fn results(dir: &Path) -> PathBuf {
    let e = Experiment::load(&write(dir, "exp.toml", EXP), &FakeExecutor).unwrap();
    let out = dir.join("r");
    run_sweep(&e, &FakeExecutor, &opts(&out, 2)).unwrap();
    out
}

#[test]
fn the_log_follows_the_grammar_and_holds_every_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = results(dir.path());
    let runs = read_runs(&out).unwrap();
    let progress = read_progress(&out).unwrap();
    let log = parse(&std::fs::read_to_string(out.join("ompl.log")).unwrap()).unwrap();
    assert_eq!(log.experiment, "ompl-test");
    assert_eq!(log.version.as_ref().map(|v| v.0.as_str()), Some("magbench"));
    assert_eq!(log.enums[0].0, "status");
    assert_eq!(log.enums[0].1[6], "Exact solution");
    // 2 scenarios × 3 planners × 1 tracker × 2 presets configurations of 3 runs.
    assert_eq!(log.planners.len(), 12);
    assert!(
        log.planners
            .iter()
            .all(|p| p.name.starts_with("control_") && p.runs.len() == 3)
    );
    assert_eq!(
        log.planners.iter().map(|p| p.runs.len()).sum::<usize>(),
        runs.len()
    );
    let p = &log.planners[0];
    for (name, ty) in [
        ("time", "REAL"),
        ("solved", "BOOLEAN"),
        ("best cost", "REAL"),
        ("status", "ENUM"),
        ("iterations", "INTEGER"),
        ("tracking rms error", "REAL"),
    ] {
        assert!(
            p.properties.contains(&(name.to_string(), ty.to_string())),
            "{name} {ty} missing"
        );
    }
    let prog = ["best cost", "iterations", "time"].map(|n| n.to_string());
    assert_eq!(
        p.progress_properties
            .iter()
            .map(|(n, _)| n.clone())
            .collect::<Vec<_>>(),
        prog
    );
    let samples: usize = log
        .planners
        .iter()
        .flat_map(|p| &p.progress)
        .map(|r| r.len())
        .sum();
    assert_eq!(samples, logged_progress(&out), "progress samples lost");
    assert!(samples <= progress.len());
    // Crashed runs carry status 7 (Crash).
    let status = p
        .properties
        .iter()
        .position(|(n, _)| n == "status")
        .unwrap();
    let crashed = log
        .planners
        .iter()
        .filter(|p| p.name.starts_with("control_fake{panic=true}"))
        .flat_map(|p| &p.runs)
        .filter(|r| r[status].as_deref() == Some("7"))
        .count();
    assert_eq!(crashed, 12);
    // The runs' lines went through a temporary file, which is gone.
    assert!(!out.join("ompl.log.runs.tmp").exists());
    // One log per scenario as well, with plain planner names.
    for s in ["micro-factory", "open-field"] {
        let l = parse(&std::fs::read_to_string(out.join("ompl").join(format!("{s}.log"))).unwrap())
            .unwrap();
        assert_eq!(l.planners.len(), 6);
        assert!(l.planners.iter().all(|p| !p.name.contains('@')));
    }
}

#[test]
fn the_grammar_parser_rejects_malformed_logs() {
    let dir = tempfile::tempdir().unwrap();
    let out = results(dir.path());
    let text = std::fs::read_to_string(out.join("ompl.log")).unwrap();
    assert!(parse(&text).is_ok());
    let broken = [
        text.replacen("1 enum type", "2 enum type", 1),
        text.replacen(" properties for each run", " props for each run", 1),
        text.replacen("; \n", ";\n", 1),
        text.replacen("status ENUM", "status TEXT", 1),
        text.replacen(",;", ";", 1),
        text.trim_end_matches('\n')
            .trim_end_matches('.')
            .to_string()
            + "\n",
        text.replacen("12 planners", "13 planners", 1),
    ];
    for (i, b) in broken.iter().enumerate() {
        assert!(parse(b).is_err(), "malformed log {i} accepted");
    }
}

fn ompl_script() -> Option<PathBuf> {
    [
        "/usr/bin/ompl_benchmark_statistics",
        "/usr/share/ompl/scripts/ompl_benchmark_statistics.py",
    ]
    .iter()
    .map(PathBuf::from)
    .find(|p| p.exists())
}

#[test]
fn the_log_loads_into_ompls_own_parser() {
    let Some(script) = ompl_script() else {
        eprintln!(
            "ompl_benchmark_statistics not installed (Debian package ompl-demos): checked with the grammar parser only"
        );
        if std::env::var("MAGBENCH_REQUIRE_OMPL").is_ok() {
            panic!("MAGBENCH_REQUIRE_OMPL is set but ompl_benchmark_statistics is missing");
        }
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = results(dir.path());
    let db = dir.path().join("bench.db");
    let mut logs = vec![out.join("ompl.log")];
    logs.extend(["micro-factory", "open-field"].map(|s| out.join("ompl").join(format!("{s}.log"))));
    let o = Command::new("/usr/bin/python3")
        .arg(&script)
        .args(&logs)
        .arg("-d")
        .arg(&db)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "OMPL's parser failed:\n{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    let query = r#"
import sqlite3, sys
c = sqlite3.connect(sys.argv[1])
q = lambda s: c.execute(s).fetchone()[0]
print(q('select count(*) from experiments'), q('select count(*) from runs'), q('select count(distinct plannerid) from runs'),
      q('select count(*) from progress'), q('select count(*) from enums'), q('select count(*) from runs where status = 7'),
      q("select count(*) from plannerConfigs where name not like 'control_%'"), q('select count(tracking_rms_error) from runs'))
"#;
    let o = Command::new("/usr/bin/python3")
        .arg("-c")
        .arg(query)
        .arg(&db)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let got: Vec<usize> = String::from_utf8_lossy(&o.stdout)
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    let runs = read_runs(&out).unwrap().len();
    let progress = logged_progress(&out);
    let tracked = read_runs(&out)
        .unwrap()
        .iter()
        .filter(|r| r.get(Metric::RmsError).is_some())
        .count();
    // ompl.log + one log per scenario: every run twice; 12 + 6 + 6 planner configurations.
    assert_eq!(
        got,
        vec![3, 2 * runs, 24, 2 * progress, 9, 24, 0, 2 * tracked]
    );
}
