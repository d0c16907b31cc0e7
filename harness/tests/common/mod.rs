//! Helpers shared by the harness's integration tests.
#![allow(dead_code)]

use std::path::Path;

use magbench::run::RunRecord;
use magbench::sweep::{ProgressMode, SweepOptions};

/// `runs.csv` of `dir` without the wall-clock columns, as rows of strings, sorted by run.
pub fn deterministic_runs(dir: &Path) -> Vec<Vec<String>> {
    let mut rd = csv::Reader::from_path(dir.join("runs.csv")).unwrap();
    let header: Vec<String> = rd.headers().unwrap().iter().map(str::to_string).collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| !RunRecord::timing_columns().contains(&header[i].as_str()))
        .collect();
    let mut rows: Vec<Vec<String>> = rd
        .records()
        .map(|r| {
            let r = r.unwrap();
            keep.iter().map(|&i| r[i].to_string()).collect()
        })
        .collect();
    rows.sort_by_key(|r| r[0].parse::<usize>().unwrap());
    rows
}

/// `progress.csv` of `dir` without its time column, sorted.
pub fn deterministic_progress(dir: &Path) -> Vec<Vec<String>> {
    let mut rd = csv::Reader::from_path(dir.join("progress.csv")).unwrap();
    let header: Vec<String> = rd.headers().unwrap().iter().map(str::to_string).collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| header[i] != "time_s")
        .collect();
    let mut rows: Vec<Vec<String>> = rd
        .records()
        .map(|r| {
            let r = r.unwrap();
            keep.iter().map(|&i| r[i].to_string()).collect()
        })
        .collect();
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
