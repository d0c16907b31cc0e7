//! The deterministic mutation test of the commands that *use* accepted inputs: mutants of every
//! format (the same as `mutation.rs` draws) that the checker accepts are written to a file and
//! run by `plan`, `track`, `rig emulate` and `bench` (see `xtask::fuzz::Target::commands`),
//! and `stlc` runs with mutated numbers. Each command is a child process under a memory cap
//! (`ulimit -v`, [`MEMORY_CAP_KIB`]) and a deadline ([`DEADLINE`]): a panic, an abort (a
//! failed allocation under the cap), a signal or a command still running at the deadline fails
//! the test, with the input saved to `target/mutation-failures/`. Exit codes 0, 1 (the command
//! ran and failed, e.g. no plan found) and 2 (refused input) are fine.
//!
//! `MAGBENCH_COMMAND_MUTANTS` sets how many accepted mutants per format run (default
//! [`ACCEPTED`]); each test prints how many inputs it tried, ran and how they ended.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use xtask::fuzz::{Target, mutate, stlc_command};

const BIN: &str = env!("CARGO_BIN_EXE_magbench");

/// Accepted mutants run per format by default.
const ACCEPTED: u64 = 8;

/// Mutants tried per format at most while looking for accepted ones.
const TRIED: u64 = 5_000;

/// The deadline of one command (debug build, a shared machine): the commands bound their own
/// work to about a second, so a command still running then does not end.
const DEADLINE: Duration = Duration::from_secs(120);

/// The address-space cap of one command: the 2 GiB memory budget of accepted inputs, plus
/// room for thread stacks and the allocator's reservations.
const MEMORY_CAP_KIB: u64 = 4 << 20;

fn accepted_per_format() -> u64 {
    std::env::var("MAGBENCH_COMMAND_MUTANTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(ACCEPTED)
}

/// How one command ended.
#[derive(Debug)]
enum End {
    /// Exit 0, 1 or 2, and the last line of stderr.
    Fine(i32, String),
    /// Anything else (a panic is exit 101, an abort a signal), with its stderr.
    Bad(String),
}

/// Runs `magbench ARGS` under the memory cap and the deadline.
fn run_capped(args: &[String]) -> End {
    let child = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {MEMORY_CAP_KIB} && exec \"$0\" \"$@\""))
        .arg(BIN)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run sh");
    match common::wait_with_deadline(child, DEADLINE) {
        Some((status, stderr)) => {
            // a usage error is a mistake of the test's command line, not of the input
            assert!(
                !stderr.contains("For more information, try '--help'"),
                "magbench {}: {stderr}",
                args.join(" ")
            );
            match status.code() {
                Some(c @ 0..=2) if !stderr.contains("panicked") => {
                    End::Fine(c, stderr.lines().last().unwrap_or("").to_string())
                }
                _ => End::Bad(format!(
                    "{status}\n{}",
                    &stderr[stderr.len().saturating_sub(3000)..]
                )),
            }
        }
        None => End::Bad(format!("still running after {DEADLINE:?}: a hang")),
    }
}

/// Writes a failing input where a developer can replay it.
fn save(name: &str, data: &[u8]) -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/mutation-failures");
    let _ = std::fs::create_dir_all(&dir);
    let p = dir.join(name);
    let _ = std::fs::write(&p, data);
    p
}

/// Runs the commands of up to `accepted_per_format()` accepted mutants of `target`.
fn supervise(target: Target) {
    let seeds = target.seeds();
    let want = accepted_per_format();
    let (mut tried, mut ran, mut skipped) = (0u64, 0u64, 0u64);
    let mut codes = [0u64; 3];
    let mut refusals = std::collections::BTreeSet::new();
    let ext = if target == Target::Plan {
        "json"
    } else {
        "toml"
    };
    for i in 0..TRIED {
        if ran >= want {
            break;
        }
        tried += 1;
        let seed = &seeds[(i % seeds.len() as u64) as usize];
        let data = mutate(0x5EED_0000 + target as u64, i, seed, &seeds);
        if target.run(&data).is_err() {
            continue;
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(format!("input.{ext}"));
        std::fs::write(&path, &data).unwrap();
        let commands = target.commands(&data, &path, dir.path());
        if commands.is_empty() {
            skipped += 1;
            continue;
        }
        ran += 1;
        for args in commands {
            match run_capped(&args) {
                End::Fine(c, last) => {
                    codes[c as usize] += 1;
                    if c == 2 {
                        // the kind of refusal: the field, without the file and the value
                        refusals.insert(format!(
                            "{} {}",
                            args[0],
                            last.split(": ").nth(2).unwrap_or(&last)
                        ));
                    }
                }
                End::Bad(why) => {
                    let saved = save(&format!("{}-command-{i}.{ext}", target.name()), &data);
                    panic!(
                        "{}: input {i} (saved to {}): magbench {}: {why}",
                        target.name(),
                        saved.display(),
                        args.join(" ")
                    );
                }
            }
        }
    }
    println!(
        "{}: {tried} mutants tried, {ran} accepted ones run ({skipped} accepted but too long to run); commands exited 0: {}, 1: {}, 2: {}",
        target.name(),
        codes[0],
        codes[1],
        codes[2]
    );
    for r in refusals.iter().take(5) {
        println!("  refused: {r}");
    }
    assert!(ran > 0, "{}: no accepted mutant ran", target.name());
}

#[test]
fn commands_run_accepted_scenarios_within_their_caps() {
    supervise(Target::Scenario);
}

#[test]
fn commands_run_accepted_experiments_within_their_caps() {
    supervise(Target::Experiment);
}

#[test]
fn commands_run_accepted_rig_files_within_their_caps() {
    supervise(Target::Rig);
}

#[test]
fn commands_run_accepted_plans_within_their_caps() {
    supervise(Target::Plan);
}

#[test]
fn commands_run_accepted_presets_within_their_caps() {
    supervise(Target::Preset);
}

#[test]
fn stlc_runs_mutated_numbers_within_its_caps() {
    let n = accepted_per_format();
    let mut codes = [0u64; 3];
    for i in 0..n {
        let args = stlc_command(i.wrapping_mul(0x9E37_79B9) % 20_000);
        match run_capped(&args) {
            End::Fine(c, _) => codes[c as usize] += 1,
            End::Bad(why) => panic!("magbench {}: {why}", args.join(" ")),
        }
    }
    println!(
        "stlc: {n} command lines; exited 0: {}, 1: {}, 2: {}",
        codes[0], codes[1], codes[2]
    );
}
