//! A real SIGKILL of a `magbench bench` process mid-sweep keeps every finished run, and
//! `--resume` completes the sweep without duplicating or losing a run.
//!
//! The killed sweep cannot finish before the kill whatever the load: its fake runs stall for
//! good after 25 have finished (`MAGBENCH_FAKE_STALL_AFTER`).

use crate::common;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

use common::{deterministic_runs, write};

const EXP: &str = r#"
name = "kill-test"
scenarios = ["open-field", "narrow-passage"]
planners = ["fake", "fake{p=0.5}"]
seeds = 30
[limits]
iterations = 500
"#;

fn bench(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_magbench"));
    c.arg("bench").args(args).args(["--executor", "fake"]);
    c
}

#[test]
fn sigkill_mid_sweep_then_resume_loses_and_duplicates_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let exp = write(dir.path(), "exp.toml", EXP);
    let out = dir.path().join("killed");
    let mut child = bench(&[
        exp.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--threads",
        "2",
        "--lines",
    ])
    .env("MAGBENCH_FAKE_STALL_AFTER", "25")
    .stdout(Stdio::piped())
    .stderr(Stdio::null())
    .spawn()
    .unwrap();
    // Wait until 25 runs have reported (each line is printed after its row is written); the
    // sweep then stalls.
    let mut reported = 0;
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    while reported < 25 {
        let l = lines
            .next()
            .expect("the sweep ended before it could be killed")
            .unwrap();
        if l.starts_with('[') {
            reported += 1;
        }
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let kept = deterministic_runs(&out);
    assert!(
        kept.len() >= 25,
        "only {} rows kept after {reported} reported runs",
        kept.len()
    );
    assert!(kept.len() < 120, "the sweep finished before the kill");
    assert!(
        !out.join("report.html").exists(),
        "an interrupted sweep must not look finished"
    );

    // Resume: only the missing runs execute.
    let o = bench(&[
        exp.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--threads",
        "2",
        "--resume",
        "--quiet",
    ])
    .output()
    .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains(&format!("{} done before", kept.len())),
        "{stdout}"
    );
    let resumed = deterministic_runs(&out);
    assert_eq!(resumed.len(), 120);
    let mut ids: Vec<&String> = resumed.iter().map(|r| &r[1]).collect();
    ids.dedup();
    assert_eq!(ids.len(), 120, "duplicate run ids");
    // Every kept row survived unchanged.
    for k in &kept {
        assert!(
            resumed.contains(k),
            "a finished run changed or was lost: {k:?}"
        );
    }
    // And the result equals an uninterrupted sweep.
    let clean = dir.path().join("clean");
    let o = bench(&[
        exp.to_str().unwrap(),
        "--out",
        clean.to_str().unwrap(),
        "--threads",
        "2",
        "--quiet",
    ])
    .output()
    .unwrap();
    assert!(o.status.success());
    assert_eq!(deterministic_runs(&clean), resumed);
    // the resumed folder's OMPL log and report cover every run, as the clean sweep's do
    let runs_in_log = |d: &std::path::Path| -> Vec<String> {
        std::fs::read_to_string(d.join("ompl.log"))
            .unwrap()
            .lines()
            .filter(|l| l.ends_with(" runs"))
            .map(str::to_string)
            .collect()
    };
    let logged = runs_in_log(&out);
    assert!(!logged.is_empty(), "ompl.log lists no runs");
    assert_eq!(logged, runs_in_log(&clean));
    let rows = |d: &std::path::Path| {
        std::fs::read_to_string(d.join("report.html"))
            .unwrap()
            .matches("<tr")
            .count()
    };
    assert!(
        rows(&out) > 0 && rows(&out) == rows(&clean),
        "the report's tables differ"
    );
}
