//! The sweep machinery with the fake executor: determinism across thread counts, resume,
//! shards and merge, crash rows, results files.

use crate::common;

use std::path::Path;

use common::{deterministic_progress, deterministic_runs, opts, write};
use magbench::experiment::Experiment;
use magbench::results::merge::merge;
use magbench::results::store::read_runs;
use magbench::run::fake::FakeExecutor;
use magbench::sweep::{SweepOptions, run_sweep};

const EXP: &str = r#"
name = "fake-test"
scenarios = ["micro-factory", "open-field"]
planners = ["fake", "fake{p=0.4, cost=8, spin=2000}"]
trackers = ["fake", "fake{gain=0.5}"]
presets = ["ideal", "realistic"]
seeds = 4
[limits]
iterations = 1000
"#;

fn load(dir: &Path, text: &str) -> Experiment {
    Experiment::load(&write(dir, "exp.toml", text), &FakeExecutor).unwrap()
}

#[test]
fn results_are_identical_at_one_and_two_threads() {
    let dir = tempfile::tempdir().unwrap();
    let e = load(dir.path(), EXP);
    let (a, b) = (dir.path().join("t1"), dir.path().join("t2"));
    let sa = run_sweep(&e, &FakeExecutor, &opts(&a, 1)).unwrap();
    let sb = run_sweep(&e, &FakeExecutor, &opts(&b, 2)).unwrap();
    assert_eq!(sa.executed, 64);
    assert_eq!(sb.executed, 64);
    assert_eq!(deterministic_runs(&a), deterministic_runs(&b));
    assert_eq!(deterministic_progress(&a), deterministic_progress(&b));
    // Every file of a results folder is there.
    for f in [
        "runs.csv",
        "progress.csv",
        "manifest.json",
        "ompl.log",
        "report.html",
    ] {
        assert!(a.join(f).is_file(), "{f} missing");
    }
    for sc in ["micro-factory", "open-field"] {
        for p in [
            "success-vs-iterations",
            "success-vs-time",
            "cost-vs-iterations",
            "cost-vs-time",
            "time-to-first-solution",
            "final-cost",
            "rms-error",
            "rms-error-true",
            "rms-error-sync",
            "rms-error-time",
            "rms-error-worst-agent",
            "rms-error-true-worst-agent",
            "max-error",
            "rms-error-cdf",
        ] {
            for ext in ["svg", "png"] {
                let f = a.join("plots").join(sc).join(format!("{p}.{ext}"));
                assert!(
                    std::fs::metadata(&f)
                        .map(|m| m.len() > 2000)
                        .unwrap_or(false),
                    "{} missing or empty",
                    f.display()
                );
            }
        }
    }
    // The report is one self-contained page: inline SVG, inline script (table sorting), no
    // remote resources.
    let html = std::fs::read_to_string(a.join("report.html")).unwrap();
    // per scenario its preview and 14 plots (two agents: no per-agent plot)
    assert_eq!(html.matches("<svg").count(), 30);
    let without_ns = html.replace("xmlns=\"http://www.w3.org/2000/svg\"", "");
    assert!(
        !html.contains("<script src")
            && !without_ns.contains("http://")
            && !without_ns.contains("https://")
            && !html.contains(" src=")
    );
    assert!(html.contains("fake{cost=8,p=0.4,spin=2000} + fake{gain=0.5} (realistic)"));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(a.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(m["runs_done"], 64);
    assert_eq!(m["threads"], 1);
    assert!(
        m["experiment"]["content"]
            .as_str()
            .unwrap()
            .contains("fake-test")
    );
    assert_eq!(m["experiment"]["sha256"].as_str().unwrap().len(), 64);
    assert!(
        m["finished"].is_string()
            && m["host"]["name"].is_string()
            && m["crate_versions"]["magbench-env"].is_string()
    );
}

#[test]
fn refuses_to_overwrite_and_resumes_only_what_is_missing() {
    let dir = tempfile::tempdir().unwrap();
    let e = load(dir.path(), EXP);
    let out = dir.path().join("r");
    run_sweep(&e, &FakeExecutor, &opts(&out, 2)).unwrap();
    let err = run_sweep(&e, &FakeExecutor, &opts(&out, 2)).unwrap_err();
    assert_eq!(err.exit_code(), 2, "{err}");
    // Drop the last 10 rows, as if the sweep had been killed, then resume.
    let text = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    std::fs::write(
        out.join("runs.csv"),
        lines[..lines.len() - 10].join("\n") + "\n",
    )
    .unwrap();
    let before = deterministic_runs(&out).len();
    assert_eq!(before, 54);
    let s = run_sweep(
        &e,
        &FakeExecutor,
        &SweepOptions {
            resume: true,
            ..opts(&out, 2)
        },
    )
    .unwrap();
    assert_eq!((s.skipped, s.executed), (54, 10));
    let runs = read_runs(&out).unwrap();
    let mut ids: Vec<&str> = runs.iter().map(|r| r.run_id.as_str()).collect();
    ids.sort();
    ids.dedup();
    assert_eq!(ids.len(), 64, "duplicates or losses after resume");
    // A changed experiment is not resumed into the same folder.
    let e2 = load(dir.path(), &EXP.replace("seeds = 4", "seeds = 5"));
    let err = run_sweep(
        &e2,
        &FakeExecutor,
        &SweepOptions {
            resume: true,
            ..opts(&out, 2)
        },
    )
    .unwrap_err();
    assert_eq!(err.exit_code(), 2);
}

#[test]
fn shards_merge_into_the_unsharded_result() {
    let dir = tempfile::tempdir().unwrap();
    let e = load(dir.path(), EXP);
    let whole = dir.path().join("whole");
    run_sweep(&e, &FakeExecutor, &opts(&whole, 2)).unwrap();
    let mut shards = vec![];
    for i in 1..=3 {
        let d = dir.path().join(format!("s{i}"));
        let s = run_sweep(
            &e,
            &FakeExecutor,
            &SweepOptions {
                shard: Some((i, 3)),
                ..opts(&d, 1)
            },
        )
        .unwrap();
        assert!(s.total == 21 || s.total == 22);
        shards.push(d);
    }
    let merged = dir.path().join("merged");
    let m = merge(&shards, &merged).unwrap();
    assert_eq!(m.runs_done, 64);
    assert_eq!(deterministic_runs(&merged), deterministic_runs(&whole));
    assert_eq!(
        deterministic_progress(&merged),
        deterministic_progress(&whole)
    );
    // Merging a folder twice does not duplicate runs.
    let again = dir.path().join("again");
    let m = merge(
        &[
            shards[0].clone(),
            shards[0].clone(),
            shards[1].clone(),
            shards[2].clone(),
        ],
        &again,
    )
    .unwrap();
    assert_eq!(m.runs_done, 64);
}

#[test]
fn a_panicking_run_becomes_a_crash_row_and_the_sweep_goes_on() {
    let dir = tempfile::tempdir().unwrap();
    let e = load(
        dir.path(),
        "scenarios = [\"open-field\"]\nplanners = [\"fake\", \"fake{panic=true}\"]\nseeds = 3\n[limits]\niterations = 100\n",
    );
    let out = dir.path().join("r");
    let s = run_sweep(&e, &FakeExecutor, &opts(&out, 2)).unwrap();
    assert_eq!((s.executed, s.failed), (6, 3));
    let runs = read_runs(&out).unwrap();
    let crashed: Vec<_> = runs
        .iter()
        .filter(|r| r.status == magbench::run::Status::Crash)
        .collect();
    assert_eq!(crashed.len(), 3);
    assert!(crashed.iter().all(|r| r.error.contains("panic")));
}
