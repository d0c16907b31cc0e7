//! Helpers shared by the command line's integration tests.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

use magbench::run::RunRecord;
use magbench::sweep::{ProgressMode, SweepOptions};

/// Runs the magbench binary with `args`: (exit code, stdout, stderr).
pub fn magbench(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_magbench"))
        .args(args)
        .output()
        .expect("run magbench");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Longer than any refusal takes (they take milliseconds); a command still running then hangs.
pub const DEADLINE: Duration = Duration::from_secs(30);

/// Runs the magbench binary with `args` and no stdin or stdout under [`DEADLINE`]:
/// (exit code, stderr). A command that outlives the deadline is killed and fails the test as
/// a hang.
pub fn magbench_in_time(args: &[&str]) -> (i32, String) {
    let child = Command::new(env!("CARGO_BIN_EXE_magbench"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run magbench");
    let (status, stderr) = wait_with_deadline(child, DEADLINE)
        .unwrap_or_else(|| panic!("{args:?} hung (still running after {DEADLINE:?})"));
    (status.code().unwrap_or(-1), stderr)
}

/// Asserts that magbench refuses `args` in time: exit 2 with every part in the message, and
/// no panic.
pub fn refused(args: &[&str], parts: &[&str]) {
    let (code, stderr) = magbench_in_time(args);
    assert_eq!(code, 2, "{args:?}: exit {code}, stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    for p in parts {
        assert!(stderr.contains(p), "{args:?}: {p:?} missing from: {stderr}");
    }
}

/// The rows of the CSV file `dir/name` as strings, without the columns `drop` names.
fn rows_without(dir: &Path, name: &str, drop: impl Fn(&str) -> bool) -> Vec<Vec<String>> {
    let mut rd = csv::Reader::from_path(dir.join(name)).unwrap();
    let header: Vec<String> = rd.headers().unwrap().iter().map(str::to_string).collect();
    let keep: Vec<usize> = (0..header.len()).filter(|&i| !drop(&header[i])).collect();
    rd.records()
        .map(|r| {
            let r = r.unwrap();
            keep.iter().map(|&i| r[i].to_string()).collect()
        })
        .collect()
}

/// A valid plan of open-field written by `magbench plan --out` into `dir/p`: its file and its
/// JSON.
pub fn plan_json(dir: &Path) -> (std::path::PathBuf, serde_json::Value) {
    let out = dir.join("p");
    let (code, _, stderr) = magbench(&[
        "plan",
        "open-field",
        "--planner",
        "goal-zoom-rrt",
        "--max-iters",
        "3000",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    let p = out.join("plan.json");
    let v = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
    (p, v)
}

/// `runs.csv` of `dir` without the wall-clock columns, as rows of strings, sorted by run.
pub fn deterministic_runs(dir: &Path) -> Vec<Vec<String>> {
    let mut rows = rows_without(dir, "runs.csv", |c| {
        RunRecord::timing_columns().contains(&c)
    });
    rows.sort_by_key(|r| r[0].parse::<usize>().unwrap());
    rows
}

/// `progress.csv` of `dir` without its time column, sorted.
pub fn deterministic_progress(dir: &Path) -> Vec<Vec<String>> {
    let mut rows = rows_without(dir, "progress.csv", |c| c == "time_s");
    rows.sort_by(|a, b| {
        (a[0].parse::<usize>().unwrap(), a[2].parse::<u64>().unwrap())
            .cmp(&(b[0].parse::<usize>().unwrap(), b[2].parse::<u64>().unwrap()))
    });
    rows
}

/// Writes `text` to `dir/name` and returns the path.
pub fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Options of a quiet, unsharded, fresh sweep into `out` on `threads` threads.
pub fn opts(out: &Path, threads: usize) -> SweepOptions {
    SweepOptions {
        out: out.to_path_buf(),
        threads,
        shard: None,
        resume: false,
        progress: ProgressMode::Quiet,
    }
}

/// Waits at most `deadline` for `child`, whose stderr is piped: its exit status and stderr,
/// or `None` once the deadline has passed (the child is then killed).
pub fn wait_with_deadline(
    mut child: std::process::Child,
    deadline: std::time::Duration,
) -> Option<(std::process::ExitStatus, String)> {
    use std::io::Read;
    let pid = child.id();
    let mut err = child.stderr.take().expect("stderr piped");
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut s = String::new();
        let _ = err.read_to_string(&mut s);
        let _ = tx.send((child.wait(), s));
    });
    match rx.recv_timeout(deadline) {
        Ok((status, stderr)) => Some((status.expect("wait for the child"), stderr)),
        Err(_) => {
            let _ = std::process::Command::new("kill")
                .args(["-9", &pid.to_string()])
                .status();
            None
        }
    }
}

/// Copies the folder `from` into `to`, leaving out entries named in `skip`.
pub fn copy_dir(from: &Path, to: &Path, skip: &[&str]) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let name = entry.file_name();
        if skip.iter().any(|s| name == *s) {
            continue;
        }
        let path = entry.path();
        if path.is_dir() {
            copy_dir(&path, &to.join(&name), skip);
        } else {
            std::fs::copy(&path, to.join(&name)).unwrap();
        }
    }
}
