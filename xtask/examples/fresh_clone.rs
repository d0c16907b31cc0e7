//! A fresh clone to the main job's results: clones the repository's committed `HEAD` into a
//! temporary folder, fetches its crates (not timed), builds the release binary there from an
//! empty target folder (`cargo build --release -p magbench --timings`) and runs the README's
//! main job (`cargo run --release -p magbench -- bench`), then prints each step's wall time
//! and the compile times `--timings` recorded, as one Markdown table.
//!
//! The compile time of a crate is cargo's duration of its unit; their sum is the CPU the build
//! spent compiling (on 2 cores, up to twice the build's wall time).

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

/// A crate of this workspace (its compile time is the project's own share): `magbench` and
/// every `magbench-*`.
fn own(name: &str) -> bool {
    name == "magbench" || name.starts_with("magbench-")
}

/// Dependencies listed by name with their compile time.
const LARGEST: usize = 5;

fn main() {
    if let Err(e) = run() {
        eprintln!("fresh_clone: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let tmp = tempfile::tempdir().map_err(|e| format!("temporary folder: {e}"))?;
    let clone = tmp.path().join("magbench");
    let target = clone.join("target");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());

    let t_clone = timed(
        "git clone",
        Command::new("git")
            .args(["clone", "--quiet", "--no-local"])
            .arg(&root)
            .arg(&clone),
    )?;
    timed(
        "cargo fetch",
        Command::new(&cargo)
            .args(["fetch", "--locked"])
            .current_dir(&clone),
    )?;
    let in_clone = |args: &[&str]| {
        let mut c = Command::new(&cargo);
        c.args(args)
            .current_dir(&clone)
            .env_remove("RUSTFLAGS")
            .env("CARGO_TARGET_DIR", &target);
        c
    };
    let t_build = timed(
        "cargo build",
        &mut in_clone(&["build", "--release", "-p", "magbench", "--timings"]),
    )?;
    let t_job = timed(
        "main job",
        &mut in_clone(&["run", "--release", "-p", "magbench", "--", "bench"]),
    )?;

    let html = target.join("cargo-timings").join("cargo-timing.html");
    let units = units(&std::fs::read_to_string(&html).map_err(|e| format!("{html:?}: {e}"))?)?;
    let all: f64 = units.iter().map(|u| u.1).sum();
    let mut crates: BTreeMap<&str, f64> = BTreeMap::new();
    for (name, secs) in &units {
        *crates.entry(name.as_str()).or_default() += secs;
    }
    let (ours, mut deps): (Vec<_>, Vec<_>) = crates.into_iter().partition(|(n, _)| own(n));
    let own_secs: f64 = ours.iter().map(|c| c.1).sum();
    deps.sort_by(|a, b| b.1.total_cmp(&a.1));

    println!("| step | seconds |");
    println!("| --- | --- |");
    println!("| `git clone` of `HEAD` | {t_clone:.1} |");
    println!(
        "| `cargo build --release -p magbench` from an empty target folder (wall; crates downloaded before) | {t_build:.0} |"
    );
    println!("| the main job, `cargo run --release -p magbench -- bench` (wall) | {t_job:.0} |");
    println!(
        "| **fresh clone → main job's results** (wall) | **{:.0}** |",
        t_clone + t_build + t_job
    );
    println!(
        "| compile time of every crate ({} units, summed) | {all:.0} |",
        units.len()
    );
    println!(
        "| compile time of the project's own {} crates | {own_secs:.0} |",
        ours.len()
    );
    for (name, secs) in deps.iter().take(LARGEST) {
        println!("| compile time of `{name}` (a dependency) | {secs:.0} |");
    }
    Ok(())
}

/// Runs `command` and returns its wall time (s); its output goes to stderr.
fn timed(what: &str, command: &mut Command) -> Result<f64, String> {
    eprintln!("fresh_clone: {what} …");
    let start = Instant::now();
    let status = command
        .stdout(Stdio::null())
        .status()
        .map_err(|e| format!("{what}: {e}"))?;
    if !status.success() {
        return Err(format!("{what}: {status}"));
    }
    Ok(start.elapsed().as_secs_f64())
}

/// Each compilation unit's crate name and duration (s), from the `UNIT_DATA` array of the
/// timing page cargo writes.
fn units(html: &str) -> Result<Vec<(String, f64)>, String> {
    let start = html
        .find("const UNIT_DATA = ")
        .ok_or("cargo-timing.html: no UNIT_DATA")?
        + "const UNIT_DATA = ".len();
    let end = start
        + html[start..]
            .find(";\n")
            .ok_or("cargo-timing.html: UNIT_DATA does not end")?;
    let data: Vec<serde_json::Value> = serde_json::from_str(&html[start..end])
        .map_err(|e| format!("cargo-timing.html: UNIT_DATA: {e}"))?;
    data.iter()
        .map(|u| {
            let name = u["name"].as_str().ok_or("a unit without a name")?;
            let secs = u["duration"].as_f64().ok_or("a unit without a duration")?;
            Ok((name.to_string(), secs))
        })
        .collect()
}
