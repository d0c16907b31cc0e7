//! The deterministic mutation test of the input parsers and validators (stable Rust, run by
//! CI): 100 000 mutated inputs per format (scenario, experiment, rig, plan, preset), the same
//! inputs on every run, each parsed and validated by `xtask::fuzz::Target::run`.
//!
//! The inputs run in a child process (this test binary again, the ignored test `child`, under
//! an address-space cap of [`MEMORY_CAP_KIB`]), which reports each input's number before trying
//! it. A panic, an abort (say, an allocation beyond the cap) or an input that takes more than a
//! minute fails the test with that input, also written to `target/mutation-failures/`.
//! `MAGBENCH_MUTATION_INPUTS` changes the count.

use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use xtask::fuzz::{Target, mutate};

/// Inputs per format.
const INPUTS: u64 = 100_000;

/// The child's address-space cap: the 2 GiB memory budget of inputs plus 1 GiB for the test
/// binary, its threads and the allocator. An input whose check allocates beyond it aborts the
/// child and fails the test.
const MEMORY_CAP_KIB: u64 = 3 << 20;

/// Longest time one input may take before it counts as a hang.
const HANG: Duration = Duration::from_secs(60);

fn inputs() -> u64 {
    std::env::var("MAGBENCH_MUTATION_INPUTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(INPUTS)
}

/// Input `i` of `target`: a mutation of one of its seeds.
fn input(target: Target, seeds: &[String], i: u64) -> Vec<u8> {
    let seed = &seeds[(i % seeds.len() as u64) as usize];
    mutate(0x5EED_0000 + target as u64, i, seed, seeds)
}

/// The name of the test [`child`] in this binary: its module's path, less the crate's name.
fn child_test() -> String {
    match module_path!().split_once("::") {
        Some((_, module)) => format!("{module}::child"),
        None => "child".to_string(),
    }
}

/// Runs every input of `target` in a child process and fails on a panic, abort or hang.
fn supervise(target: Target) {
    let n = inputs();
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {MEMORY_CAP_KIB} && exec \"$0\" \"$@\""))
        .arg(std::env::current_exe().unwrap())
        .arg(child_test())
        .args(["--exact", "--ignored", "--nocapture", "--test-threads=1"])
        .env("MAGBENCH_MUTATION_TARGET", target.name())
        .env("MAGBENCH_MUTATION_INPUTS", n.to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let (tx, rx) = mpsc::channel();
    let out = child.stdout.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let mut err = child.stderr.take().unwrap();
    let stderr = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = err.read_to_string(&mut s);
        s
    });
    let mut last: Option<u64> = None;
    let mut summary = None;
    let hung = loop {
        match rx.recv_timeout(HANG) {
            Ok(line) => {
                if let Some(i) = line.strip_prefix("input ") {
                    last = i.parse().ok();
                } else if line.starts_with("summary ") {
                    summary = Some(line);
                }
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => break false,
            Err(mpsc::RecvTimeoutError::Timeout) => {
                let _ = child.kill();
                break true;
            }
        }
    };
    let status = child.wait().unwrap();
    let stderr = stderr.join().unwrap();
    if hung || !status.success() || summary.is_none() {
        let seeds = target.seeds();
        let bad = last.map(|i| input(target, &seeds, i));
        let saved = bad.as_ref().map(|b| save(target, last.unwrap(), b));
        panic!(
            "{}: input {last:?} {} ({status}); saved to {saved:?}\n--- input (first 2000 bytes) ---\n{}\n--- child stderr (tail) ---\n{}",
            target.name(),
            if hung { "hung" } else { "crashed" },
            bad.map(|b| String::from_utf8_lossy(&b[..b.len().min(2000)]).into_owned())
                .unwrap_or_default(),
            &stderr[stderr.len().saturating_sub(4000)..]
        );
    }
    println!("{}: {}", target.name(), summary.unwrap());
}

/// Writes a failing input where a developer can replay it.
fn save(target: Target, i: u64, data: &[u8]) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/mutation-failures");
    let _ = std::fs::create_dir_all(&dir);
    let p = dir.join(format!("{}-{i}", target.name()));
    let _ = std::fs::write(&p, data);
    p
}

/// The child: runs the inputs of `MAGBENCH_MUTATION_TARGET`, announcing each on stdout.
#[test]
#[ignore = "run by the mutation tests in a child process"]
fn child() {
    let Some(target) = std::env::var("MAGBENCH_MUTATION_TARGET")
        .ok()
        .and_then(|t| Target::by_name(&t))
    else {
        return;
    };
    let seeds = target.seeds();
    let mut out = std::io::stdout().lock();
    let (mut accepted, mut refused) = (0u64, 0u64);
    let mut reasons = std::collections::BTreeSet::new();
    for i in 0..inputs() {
        writeln!(out, "input {i}").unwrap();
        out.flush().unwrap();
        match target.run(&input(target, &seeds, i)) {
            Ok(()) => accepted += 1,
            Err(e) => {
                refused += 1;
                // the kind of refusal: the field, without the file and the value
                let field = e.to_string().split(": ").nth(1).unwrap_or("").to_string();
                reasons.insert(field);
            }
        }
    }
    writeln!(
        out,
        "summary {} inputs: {accepted} accepted, {refused} refused with exit-2 errors naming {} distinct fields",
        accepted + refused,
        reasons.len()
    )
    .unwrap();
}

#[test]
fn scenario_files_never_crash_the_checker() {
    supervise(Target::Scenario);
}

#[test]
fn experiment_files_never_crash_the_checker() {
    supervise(Target::Experiment);
}

#[test]
fn rig_files_never_crash_the_checker() {
    supervise(Target::Rig);
}

#[test]
fn plan_files_never_crash_the_checker() {
    supervise(Target::Plan);
}

#[test]
fn preset_files_never_crash_the_checker() {
    supervise(Target::Preset);
}
