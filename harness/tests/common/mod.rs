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
