//! The difficulty measures of each run's scenario as columns of `runs.csv`: written by a sweep
//! with the values `scenario show` prints, carried by `merge` and by a resume, and absent
//! (without error) in a folder written before the columns existed.

use crate::common;

use std::path::Path;
use std::process::Command;

use common::{opts, write};
use magbench::compare::instances::Instances;
use magbench::experiment::Experiment;
use magbench::metrics::difficulty::{Measure, Measures};
use magbench::results::merge::merge;
use magbench::results::store::read_runs;
use magbench::run::fake::FakeExecutor;
use magbench::sweep::run_sweep;
use magbench_env::Scenario;

const EXP: &str = r#"
name = "difficulty-columns"
scenarios = ["narrow-passage", "open-field", "micro-factory"]
planners = ["fake"]
seeds = 2
[limits]
iterations = 200
"#;

const SCENARIOS: [&str; 3] = ["narrow-passage", "open-field", "micro-factory"];

fn load(dir: &Path) -> Experiment {
    Experiment::load(&write(dir, "exp.toml", EXP), &FakeExecutor).unwrap()
}

/// Every row of `dir/runs.csv` carries the measures of its scenario, exactly.
fn assert_measured(dir: &Path) {
    let runs = read_runs(dir).unwrap();
    assert_eq!(runs.len(), 6, "{}", dir.display());
    for r in &runs {
        let want = Measures::of(&Scenario::load(&r.scenario).unwrap());
        assert_eq!(r.difficulty, want, "run {} of {}", r.run, r.scenario);
    }
    let header = std::fs::read_to_string(dir.join("runs.csv")).unwrap();
    let header = header.lines().next().unwrap();
    for m in Measure::ALL {
        assert!(header.contains(m.def().column), "{}", m.def().column);
    }
}

/// The number after `key` on the line of `scenario show`'s text that starts with `line`.
fn shown(text: &str, line: &str, key: &str) -> f64 {
    let l = text.lines().find(|l| l.starts_with(line)).unwrap();
    let rest = &l[l.find(key).unwrap() + key.len()..];
    let num: String = rest
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.' || *c == '-')
        .collect();
    num.parse().unwrap()
}

#[test]
fn a_sweep_writes_the_values_scenario_show_prints() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r");
    run_sweep(&load(dir.path()), &FakeExecutor, &opts(&out, 2)).unwrap();
    assert_measured(&out);
    assert!(!out.join("difficulty.csv").exists(), "one table: runs.csv");
    let runs = read_runs(&out).unwrap();
    for sc in SCENARIOS {
        let o = Command::new(env!("CARGO_BIN_EXE_magbench"))
            .args(["scenario", "show", sc])
            .output()
            .unwrap();
        assert!(o.status.success());
        let text = String::from_utf8(o.stdout).unwrap();
        let r = runs.iter().find(|r| r.scenario == sc).unwrap();
        let d = |m: Measure| r.difficulty.get(m).unwrap();
        let close = |a: f64, b: f64, digits: i32| (a - b).abs() <= 0.51 * 10f64.powi(-digits);
        let free = shown(&text, "free space", "free space");
        assert!(close(100.0 * d(Measure::FreeFraction), free, 1), "{sc}");
        let narrow = shown(&text, "passage", "narrowest");
        assert!(close(d(Measure::NarrowestPassageBl), narrow, 2), "{sc}");
        let ratio = shown(&text, "passage", "=");
        assert!(close(d(Measure::PassageRatio), ratio, 2), "{sc}");
        let centroid = shown(&text, "move", "centroid");
        assert!(close(d(Measure::CentroidMoveBl), centroid, 2), "{sc}");
        let rotation = shown(&text, "move", "rotation");
        assert!(close(d(Measure::RotationDeg), rotation, 1), "{sc}");
        if let Some(len) = r.difficulty.get(Measure::PathLengthBl) {
            let path = shown(&text, "path", ":");
            assert!(close(len, path, 2), "{sc}: {len} vs {path}");
            let turns = shown(&text, "path", "BL,");
            assert_eq!(d(Measure::PathTurns), turns, "{sc}");
        }
    }
    // the plots against difficulty read them back from runs.csv
    let t = Instances::of(&runs);
    assert_eq!(t.problems.len(), 3);
    assert!(t.difficulty.iter().all(|d| !d.is_empty()));
}

#[test]
fn merge_and_resume_carry_the_columns() {
    let dir = tempfile::tempdir().unwrap();
    let e = load(dir.path());
    let mut shards = vec![];
    for i in 1..=2 {
        let d = dir.path().join(format!("s{i}"));
        let mut o = opts(&d, 1);
        o.shard = Some((i, 2));
        run_sweep(&e, &FakeExecutor, &o).unwrap();
        shards.push(d);
    }
    let merged = dir.path().join("merged");
    merge(&shards, &merged).unwrap();
    assert_measured(&merged);

    // a resume after losing rows measures the scenarios of the runs it runs again and keeps the
    // others' columns
    let out = dir.path().join("resumed");
    run_sweep(&e, &FakeExecutor, &opts(&out, 1)).unwrap();
    let text = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let kept: Vec<&str> = text.lines().take(3).collect();
    std::fs::write(out.join("runs.csv"), kept.join("\n") + "\n").unwrap();
    let mut o = opts(&out, 1);
    o.resume = true;
    let s = run_sweep(&e, &FakeExecutor, &o).unwrap();
    assert_eq!((s.skipped, s.executed), (2, 4));
    assert_measured(&out);
}

/// `runs.csv` of `dir` rewritten without its `difficulty_*` columns, as a folder written before
/// the columns existed has it.
fn drop_difficulty_columns(dir: &Path) {
    let path = dir.join("runs.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    let header = reader.headers().unwrap().clone();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| !header[i].starts_with("difficulty_"))
        .collect();
    assert!(
        keep.len() < header.len(),
        "the sweep wrote no difficulty column"
    );
    let mut writer = csv::Writer::from_path(&path).unwrap();
    writer
        .write_record(keep.iter().map(|&i| &header[i]))
        .unwrap();
    for row in reader.records() {
        let row = row.unwrap();
        writer.write_record(keep.iter().map(|&i| &row[i])).unwrap();
    }
    writer.flush().unwrap();
}

#[test]
fn a_folder_without_the_columns_still_loads() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("legacy");
    run_sweep(&load(dir.path()), &FakeExecutor, &opts(&out, 1)).unwrap();
    drop_difficulty_columns(&out);
    let runs = read_runs(&out).unwrap();
    assert_eq!(runs.len(), 6);
    assert!(runs.iter().all(|r| r.difficulty.is_empty()));
    let t = Instances::of(&runs);
    assert!(t.difficulty.iter().all(Measures::is_empty));
}
