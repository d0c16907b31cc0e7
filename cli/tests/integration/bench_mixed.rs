//! An experiment that compares every planner by planning runs and tracks only some planners'
//! plans (`[tracking]`): its run matrix, validation, and the sweep machinery over the mixed
//! matrix (threads, resume, shards and merge, report and plots), with the fake executor.

use crate::common;

use std::path::Path;

use common::{deterministic_progress, deterministic_runs, opts, write};
use magbench::experiment::{Experiment, Tracking};
use magbench::results::merge::merge;
use magbench::results::store::read_runs;
use magbench::run::fake::FakeExecutor;
use magbench::sweep::{SweepOptions, run_sweep};

const MIXED: &str = r#"
name = "mixed"
scenarios = ["micro-factory", "open-field"]
planners = ["fake", "fake{p=0.4, cost=8}", "fake{cost=12}"]
seeds = 3
[limits]
iterations = 1000
[tracking]
plans = ["fake{cost=8,p=0.4}"]
trackers = ["fake", "fake{gain=0.5}"]
presets = ["ideal", "realistic"]
"#;

/// 2 scenarios × (3 planners' planning runs + 1 tracked planner × 2 trackers × 2 presets) × 3 seeds
const MIXED_RUNS: usize = 2 * (3 + 4) * 3;

fn parse(text: &str) -> Result<Experiment, magbench_env::InputError> {
    Experiment::parse(text, "exp.toml", Path::new("."), "exp", &FakeExecutor)
}

#[test]
fn every_planner_plans_and_only_the_listed_plans_are_tracked() {
    let e = parse(MIXED).unwrap();
    assert_eq!(
        e.tracking,
        Tracking::Plans(vec!["fake{cost=8,p=0.4}".into()])
    );
    let runs = e.runs();
    assert_eq!(runs.len(), MIXED_RUNS);
    assert!(runs.iter().enumerate().all(|(i, r)| r.index == i));
    let ids: std::collections::BTreeSet<String> = runs.iter().map(|r| r.id()).collect();
    assert_eq!(ids.len(), runs.len(), "run ids are unique");
    for p in &e.planners {
        let planning = runs
            .iter()
            .filter(|r| r.planner == *p && r.tracker.is_none())
            .count();
        let tracked = runs
            .iter()
            .filter(|r| r.planner == *p && r.tracker.is_some())
            .count();
        assert_eq!(planning, 2 * 3, "{p}: planning runs");
        let want = if p.label() == "fake{cost=8,p=0.4}" {
            2 * 4 * 3
        } else {
            0
        };
        assert_eq!(tracked, want, "{p}: tracked runs");
    }
    // a planner's planning runs come before its tracked runs
    let ids: Vec<String> = runs[3..7].iter().map(|r| r.id()).collect();
    assert_eq!(
        ids,
        [
            "micro-factory|fake{cost=8,p=0.4}|-|-|0",
            "micro-factory|fake{cost=8,p=0.4}|-|-|1",
            "micro-factory|fake{cost=8,p=0.4}|-|-|2",
            "micro-factory|fake{cost=8,p=0.4}|fake|ideal|0",
        ]
    );
    // without `plans`, every planner's plans are tracked, and each still has planning runs
    let all = parse(&MIXED.replace("plans = [\"fake{cost=8,p=0.4}\"]\n", "")).unwrap();
    assert_eq!(all.runs().len(), 2 * (3 + 3 * 4) * 3);
    // today's form is unchanged: top-level trackers track every run, with no planning runs
    let every = parse(
        r#"
scenarios = ["micro-factory", "open-field"]
planners = ["fake", "fake{p=0.4, cost=8}", "fake{cost=12}"]
trackers = ["fake", "fake{gain=0.5}"]
presets = ["ideal", "realistic"]
seeds = 3
[limits]
iterations = 1000
"#,
    )
    .unwrap();
    assert_eq!(every.tracking, Tracking::Every);
    assert_eq!(every.runs().len(), 2 * 3 * 4 * 3);
    assert!(every.runs().iter().all(|r| r.tracker.is_some()));
}

#[test]
fn bad_tracking_tables_name_the_file_the_field_and_the_reason() {
    for (text, field, why) in [
        (
            MIXED.replace("seeds = 3", "seeds = 3\ntrackers = [\"fake\"]"),
            "trackers",
            "not both",
        ),
        (
            MIXED.replace("seeds = 3", "seeds = 3\npresets = [\"ideal\"]"),
            "presets",
            "not both",
        ),
        (
            MIXED.replace(
                "plans = [\"fake{cost=8,p=0.4}\"]",
                "plans = [\"fake{cost=9}\"]",
            ),
            "tracking.plans[0]",
            "is not one of the planners",
        ),
        (
            MIXED.replace(
                "plans = [\"fake{cost=8,p=0.4}\"]",
                "plans = [\"fake\", \"fake{}\"]",
            ),
            "tracking.plans[1]",
            "listed twice",
        ),
        (
            MIXED.replace("plans = [\"fake{cost=8,p=0.4}\"]", "plans = []"),
            "tracking.plans",
            "at least one planner",
        ),
        (
            MIXED.replace("trackers = [\"fake\", \"fake{gain=0.5}\"]", "trackers = []"),
            "tracking.trackers",
            "at least one tracker",
        ),
        (
            MIXED.replace(
                "trackers = [\"fake\", \"fake{gain=0.5}\"]",
                "trackers = [\"pid\"]",
            ),
            "tracking.trackers[0]",
            "unknown tracker",
        ),
        (
            MIXED.replace(
                "presets = [\"ideal\", \"realistic\"]",
                "presets = [\"rough\"]",
            ),
            "tracking.presets[0]",
            "unknown preset",
        ),
        (
            MIXED.replace("presets = [\"ideal\", \"realistic\"]", "presets = []"),
            "tracking.presets",
            "at least one preset",
        ),
        (
            MIXED.replace("[tracking]\n", "[tracking]\nscenarios = [\"open-field\"]\n"),
            "tracking",
            "scenarios",
        ),
    ] {
        let e = parse(&text).unwrap_err();
        assert_eq!(e.file, "exp.toml", "{e}");
        assert!(e.field.starts_with(field), "{field}: {e}");
        assert!(e.reason.contains(why), "{why}: {e}");
    }
    // the bound on the matrix counts tracked and planning runs alike
    let e = parse(&MIXED.replace("seeds = 3", "seeds = 100000")).unwrap_err();
    assert_eq!(e.field, "seeds", "{e}");
}

#[test]
fn the_mixed_matrix_sweeps_resumes_shards_merges_and_reports() {
    let dir = tempfile::tempdir().unwrap();
    let e = Experiment::load(&write(dir.path(), "exp.toml", MIXED), &FakeExecutor).unwrap();
    let (a, b) = (dir.path().join("t1"), dir.path().join("t2"));
    assert_eq!(
        run_sweep(&e, &FakeExecutor, &opts(&a, 1)).unwrap().executed,
        MIXED_RUNS
    );
    run_sweep(&e, &FakeExecutor, &opts(&b, 2)).unwrap();
    assert_eq!(deterministic_runs(&a), deterministic_runs(&b));
    assert_eq!(deterministic_progress(&a), deterministic_progress(&b));

    // one results folder and one report: planning rows and tracked rows side by side
    let html = std::fs::read_to_string(a.join("report.html")).unwrap();
    assert!(
        html.contains("<dt>tracked plans</dt><dd>fake{cost=8,p=0.4}"),
        "report header"
    );
    for row in [
        "<td>fake</td>",
        "<td>fake{cost=12}</td>",
        "<td>fake{cost=8,p=0.4}</td>",
        "<td>fake{cost=8,p=0.4} + fake{gain=0.5} (realistic)</td>",
    ] {
        assert!(html.contains(row), "{row} missing from the report");
    }
    assert!(
        !html.contains("fake{cost=12} + "),
        "an untracked planner's plans were tracked"
    );
    for sc in ["micro-factory", "open-field"] {
        for p in [
            "success-vs-iterations",
            "final-cost",
            "rms-error",
            "rms-error-cdf",
        ] {
            assert!(
                a.join("plots").join(sc).join(format!("{p}.svg")).is_file(),
                "{sc}/{p}"
            );
        }
    }
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(a.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(m["experiment"]["tracked_plans"][0], "fake{cost=8,p=0.4}");
    assert_eq!(m["experiment"]["runs_total"], MIXED_RUNS);

    // resume: drop the last rows as if killed, and only those run again
    let text = std::fs::read_to_string(a.join("runs.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    std::fs::write(
        a.join("runs.csv"),
        lines[..lines.len() - 9].join("\n") + "\n",
    )
    .unwrap();
    let s = run_sweep(
        &e,
        &FakeExecutor,
        &SweepOptions {
            resume: true,
            ..opts(&a, 2)
        },
    )
    .unwrap();
    assert_eq!((s.skipped, s.executed), (MIXED_RUNS - 9, 9));
    assert_eq!(deterministic_runs(&a), deterministic_runs(&b));

    // shards merge into the unsharded result
    let mut shards = vec![];
    for i in 1..=4 {
        let d = dir.path().join(format!("s{i}"));
        run_sweep(
            &e,
            &FakeExecutor,
            &SweepOptions {
                shard: Some((i, 4)),
                ..opts(&d, 1)
            },
        )
        .unwrap();
        shards.push(d);
    }
    let merged = dir.path().join("merged");
    assert_eq!(merge(&shards, &merged).unwrap().runs_done, MIXED_RUNS);
    assert_eq!(deterministic_runs(&merged), deterministic_runs(&b));
    assert_eq!(deterministic_progress(&merged), deterministic_progress(&b));
    assert_eq!(read_runs(&merged).unwrap().len(), MIXED_RUNS);
}

#[test]
fn a_results_folder_of_todays_form_has_no_tracked_plans_entry() {
    let dir = tempfile::tempdir().unwrap();
    let text = "scenarios = [\"open-field\"]\nplanners = [\"fake\"]\ntrackers = [\"fake\"]\nseeds = 2\n[limits]\niterations = 100\n";
    let e = Experiment::load(&write(dir.path(), "exp.toml", text), &FakeExecutor).unwrap();
    let out = dir.path().join("r");
    run_sweep(&e, &FakeExecutor, &opts(&out, 1)).unwrap();
    let m = std::fs::read_to_string(out.join("manifest.json")).unwrap();
    assert!(!m.contains("tracked_plans"), "{m}");
}
