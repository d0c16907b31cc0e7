//! Results folders cannot lose or double a run: `magbench bench` processes killed with SIGKILL
//! at seeded bytes and rows of their output, folders whose `runs.csv` or `progress.csv` are
//! cut at seeded bytes or deleted, then resumed, end with exactly the rows and traces of an
//! uninterrupted sweep (all columns but wall-clock times); two processes never write one
//! folder; `results verify` finds what is wrong.
//!
//! Most sweeps use the fake executor (24 planning-only runs, 51 trace points each); one uses
//! real planners with iteration limits (8 runs). Kills are deterministic: the process stops for good at a chosen byte of its appends
//! (`MAGBENCH_STALL_AT_BYTE`, announced on stderr) or after a chosen number of finished runs
//! (`MAGBENCH_FAKE_STALL_AFTER`, seen in the sweep's `--lines` output, a line per run written
//! after its row), and is then killed.

use crate::common;

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

use common::{deterministic_progress, deterministic_runs, write};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// 24 planning-only fake runs of 51 trace points each.
const EXP: &str = r#"
name = "crash-test"
scenarios = ["open-field", "narrow-passage"]
planners = ["fake", "fake{p=0.5}"]
seeds = 6
[limits]
iterations = 100
"#;
const RUNS: usize = 24;

fn magbench(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_magbench"));
    c.args(args);
    c
}

/// Real planners, iteration limits only (deterministic per seed): 8 runs.
const EXP_REAL: &str = r#"
name = "crash-test-real"
scenarios = ["open-field"]
planners = ["goal-zoom-rrt", "sst"]
seeds = 4
[limits]
iterations = 1000
"#;

/// `magbench bench` of `exp` into `out`, quiet, with the fake executor unless `exp` is
/// [`EXP_REAL`].
fn bench(exp: &Path, out: &Path, extra: &[&str]) -> Command {
    bench_reporting(exp, out, "--quiet", extra)
}

/// [`bench`] with the progress option `progress` (`--quiet` or `--lines`).
fn bench_reporting(exp: &Path, out: &Path, progress: &str, extra: &[&str]) -> Command {
    let real = std::fs::read_to_string(exp)
        .unwrap()
        .contains("crash-test-real");
    let mut c = magbench(&[
        "bench",
        exp.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    c.args(["--executor", if real { "real" } else { "fake" }, progress])
        .args(extra);
    c
}

fn text(o: &Output) -> String {
    format!(
        "exit {:?}\nstdout: {}\nstderr: {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn resume_ok(exp: &Path, out: &Path) -> Output {
    let o = bench(exp, out, &["--resume", "--threads", "2"])
        .output()
        .unwrap();
    assert!(o.status.success(), "resume failed: {}", text(&o));
    o
}

fn verify(dir: &Path) -> Output {
    magbench(&["results", "verify", dir.to_str().unwrap()])
        .output()
        .unwrap()
}

/// The rows and traces of `dir` without wall-clock times.
fn content(dir: &Path) -> (Vec<Vec<String>>, Vec<Vec<String>>) {
    (deterministic_runs(dir), deterministic_progress(dir))
}

/// An uninterrupted sweep, and the bytes its runs append (both files, without headers).
fn reference(root: &Path, exp: &Path) -> (PathBuf, u64) {
    let clean = root.join("clean");
    let o = bench(exp, &clean, &["--threads", "2"]).output().unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let body = |f: &str| {
        let t = std::fs::read_to_string(clean.join(f)).unwrap();
        (t.len() - t.find('\n').unwrap() - 1) as u64
    };
    (clean.clone(), body("runs.csv") + body("progress.csv"))
}

/// Waits for `child` to announce its stall on stderr (then kills it: true) or to end (false).
fn kill_at_stall(mut child: Child) -> bool {
    let err = child.stderr.take().unwrap();
    for line in BufReader::new(err).lines() {
        if line.unwrap().starts_with("MAGBENCH_STALL_AT_BYTE: stalled") {
            child.kill().unwrap(); // SIGKILL
            child.wait().unwrap();
            return true;
        }
    }
    let status = child.wait().unwrap();
    assert!(
        status.success(),
        "a sweep that was not stalled failed: {status}"
    );
    false
}

/// Rows of `dir/runs.csv` (complete lines but the header).
fn rows(dir: &Path) -> usize {
    std::fs::read_to_string(dir.join("runs.csv"))
        .map(|t| t.matches('\n').count().saturating_sub(1))
        .unwrap_or(0)
}

/// Reads the `--lines` output of `child` (a sweep stalled after `k` finished runs) until it
/// has reported `k` runs: the sweep prints a run's line after writing its row.
fn wait_for_rows(child: &mut Child, k: usize) {
    let out = BufReader::new(child.stdout.as_mut().expect("stdout piped"));
    let mut reported = 0;
    for line in out.lines() {
        if line.unwrap().starts_with('[') {
            reported += 1;
            if reported == k {
                return;
            }
        }
    }
    panic!("the sweep ended after {reported} runs, before {k}");
}

/// Kills `child` (stalled after `k` finished runs) once it has reported their rows.
fn kill_after_rows(mut child: Child, k: usize) {
    wait_for_rows(&mut child, k);
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
}

fn cut(path: &Path, len: u64) {
    if let Ok(f) = std::fs::OpenOptions::new().write(true).open(path) {
        let size = f.metadata().unwrap().len();
        f.set_len(len.min(size)).unwrap();
    }
}

/// Damages the folder as a full disk, a lost file or a dying node would, chosen by `rng`.
fn damage(rng: &mut ChaCha8Rng, dir: &Path) -> String {
    let size = |f: &str| std::fs::metadata(dir.join(f)).map(|m| m.len()).unwrap_or(0);
    let pick = |rng: &mut ChaCha8Rng, f: &str| rng.random_range(0..=size(f));
    let tail = |rng: &mut ChaCha8Rng, f: &str| size(f).saturating_sub(rng.random_range(0..300));
    match rng.random_range(0..8) {
        0 => "none".into(),
        1 => {
            let n = pick(rng, "runs.csv");
            cut(&dir.join("runs.csv"), n);
            format!("runs.csv cut at byte {n}")
        }
        2 => {
            let n = pick(rng, "progress.csv");
            cut(&dir.join("progress.csv"), n);
            format!("progress.csv cut at byte {n}")
        }
        3 => {
            let (a, b) = (tail(rng, "runs.csv"), tail(rng, "progress.csv"));
            cut(&dir.join("runs.csv"), a);
            cut(&dir.join("progress.csv"), b);
            format!("runs.csv cut at byte {a}, progress.csv at byte {b}")
        }
        4 => {
            let _ = std::fs::remove_file(dir.join("runs.csv"));
            "runs.csv deleted".into()
        }
        5 => {
            let _ = std::fs::remove_file(dir.join("progress.csv"));
            "progress.csv deleted".into()
        }
        6 => {
            let (a, b) = (pick(rng, "runs.csv"), pick(rng, "progress.csv"));
            cut(&dir.join("runs.csv"), a);
            cut(&dir.join("progress.csv"), b);
            format!("runs.csv cut at byte {a}, progress.csv at byte {b}")
        }
        _ => {
            let n = tail(rng, "manifest.json");
            cut(&dir.join("manifest.json"), n);
            format!("manifest.json cut at byte {n}")
        }
    }
}

#[test]
fn kills_at_seeded_bytes_and_rows_and_cut_files_resume_to_the_uninterrupted_sweep() {
    let root = tempfile::tempdir().unwrap();
    let exp = write(root.path(), "exp.toml", EXP);
    let (clean, bytes) = reference(root.path(), &exp);
    let want = content(&clean);
    assert_eq!(want.0.len(), RUNS);
    assert_eq!(want.1.len(), RUNS * 51);
    let mut rng = ChaCha8Rng::seed_from_u64(25);
    let (mut torn_kills, mut damaged) = (0, 0);
    for case in 0..14 {
        let out = root.path().join(format!("case{case}"));
        let mut story = vec![];
        // one to three kills, each a later session (--resume) of the same folder
        for round in 0..rng.random_range(1..=3) {
            let resume: &[&str] = if round == 0 { &[] } else { &["--resume"] };
            let rows_mode = case % 4 == 3 && round == 0;
            let threads = rng.random_range(1..=2).to_string();
            if rows_mode {
                // a fresh sweep killed once k runs have their rows (at most k + 1 finish)
                let k = rng.random_range(1..RUNS - 1);
                let mut cmd = bench_reporting(&exp, &out, "--lines", resume);
                cmd.args(["--threads", &threads])
                    .env("MAGBENCH_FAKE_STALL_AFTER", k.to_string())
                    .stdout(Stdio::piped())
                    .stderr(Stdio::null());
                kill_after_rows(cmd.spawn().unwrap(), k);
                story.push(format!("killed after {k} runs"));
                break;
            }
            let mut cmd = bench(&exp, &out, resume);
            cmd.args(["--threads", &threads]).stdout(Stdio::null());
            let at = rng.random_range(0..bytes);
            cmd.env("MAGBENCH_STALL_AT_BYTE", at.to_string())
                .stderr(Stdio::piped());
            if kill_at_stall(cmd.spawn().unwrap()) {
                torn_kills += 1;
                story.push(format!("killed at byte {at} of its appends"));
            } else {
                story.push(format!("finished before byte {at}"));
                break;
            }
        }
        let d = damage(&mut rng, &out);
        if d != "none" {
            damaged += 1;
        }
        story.push(d);
        eprintln!("case {case}: {}", story.join(", "));
        let o = resume_ok(&exp, &out);
        let got = content(&out);
        assert_eq!(
            got.0,
            want.0,
            "case {case} ({}): runs.csv differs\n{}",
            story.join(", "),
            text(&o)
        );
        assert!(
            got.1 == want.1,
            "case {case} ({}): progress.csv has {} rows, want {}\n{}",
            story.join(", "),
            got.1.len(),
            want.1.len(),
            text(&o)
        );
        let v = verify(&out);
        assert!(v.status.success(), "case {case}: {}", text(&v));
    }
    assert!(torn_kills >= 8, "only {torn_kills} kills at a byte");
    assert!(damaged >= 8, "only {damaged} damaged folders");
}

#[test]
fn real_planners_killed_at_seeded_bytes_resume_to_the_uninterrupted_sweep() {
    let root = tempfile::tempdir().unwrap();
    let exp = write(root.path(), "exp.toml", EXP_REAL);
    let (clean, bytes) = reference(root.path(), &exp);
    let want = content(&clean);
    assert_eq!(want.0.len(), 8);
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for case in 0..3 {
        let out = root.path().join(format!("real{case}"));
        let at = rng.random_range(0..bytes);
        let mut cmd = bench(&exp, &out, &["--threads", "2"]);
        cmd.env("MAGBENCH_STALL_AT_BYTE", at.to_string())
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        assert!(
            kill_at_stall(cmd.spawn().unwrap()),
            "case {case}: not killed"
        );
        let d = damage(&mut rng, &out);
        let o = resume_ok(&exp, &out);
        assert!(
            content(&out) == want,
            "case {case} (killed at byte {at}, {d})\n{}",
            text(&o)
        );
    }
}

#[test]
fn a_finished_folder_cut_at_seeded_bytes_resumes_to_itself() {
    let root = tempfile::tempdir().unwrap();
    let exp = write(root.path(), "exp.toml", EXP);
    let (clean, _) = reference(root.path(), &exp);
    let want = content(&clean);
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for case in 0..6 {
        let out = root.path().join(format!("cut{case}"));
        std::fs::create_dir(&out).unwrap();
        for f in ["manifest.json", "runs.csv", "progress.csv"] {
            std::fs::copy(clean.join(f), out.join(f)).unwrap();
        }
        let file = ["runs.csv", "progress.csv"][case % 2];
        let size = std::fs::metadata(out.join(file)).unwrap().len();
        let at = rng.random_range(0..size);
        cut(&out.join(file), at);
        let v = verify(&out);
        assert_eq!(v.status.code(), Some(1), "{file} cut at {at}: {}", text(&v));
        resume_ok(&exp, &out);
        assert!(content(&out) == want, "{file} cut at {at}");
    }
}

#[test]
fn deleting_runs_csv_but_keeping_progress_csv_does_not_double_traces() {
    let root = tempfile::tempdir().unwrap();
    let exp = write(root.path(), "exp.toml", EXP);
    let (clean, _) = reference(root.path(), &exp);
    let out = root.path().join("out");
    std::fs::create_dir(&out).unwrap();
    for f in ["manifest.json", "progress.csv"] {
        std::fs::copy(clean.join(f), out.join(f)).unwrap();
    }
    let o = resume_ok(&exp, &out);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains(&format!("dropped {} trace points", RUNS * 51)),
        "{stderr}"
    );
    assert!(content(&out) == content(&clean));
}

#[test]
fn a_second_bench_or_merge_on_a_busy_folder_gets_exit_2_naming_pid_and_host() {
    let root = tempfile::tempdir().unwrap();
    let exp = write(root.path(), "exp.toml", EXP);
    let out = root.path().join("busy");
    let mut first = bench_reporting(&exp, &out, "--lines", &["--threads", "1"])
        .env("MAGBENCH_FAKE_STALL_AFTER", "3")
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for_rows(&mut first, 3);
    let pid = format!("pid {}", first.id());
    let host = magbench::results::manifest::host().name;
    let mut second = bench(&exp, &out, &["--resume"]);
    let mut third = bench(&exp, &out, &[]);
    let mut merge = magbench(&["merge", "--out", out.to_str().unwrap()]);
    merge.arg(out.to_str().unwrap());
    let mut check = magbench(&["results", "verify", out.to_str().unwrap()]);
    for c in [&mut second, &mut third, &mut merge, &mut check] {
        let o = c.output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
        assert!(
            err.contains(&pid) && err.contains(&host) && err.contains("busy"),
            "{err}"
        );
    }
    assert_eq!(rows(&out), 3, "a refused process wrote rows");
    first.kill().unwrap();
    first.wait().unwrap();
    // the dead holder's lock is taken over
    let o = resume_ok(&exp, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("taking over the lock") && err.contains(&pid),
        "{err}"
    );
    assert_eq!(rows(&out), RUNS);
}

#[test]
fn merge_holds_the_lock_and_takes_only_whole_runs() {
    let root = tempfile::tempdir().unwrap();
    let exp = write(root.path(), "exp.toml", EXP);
    let (clean, _) = reference(root.path(), &exp);
    let shards: Vec<PathBuf> = (1..=2)
        .map(|i| {
            let d = root.path().join(format!("shard{i}"));
            let o = bench(&exp, &d, &["--shard", &format!("{i}/2")])
                .output()
                .unwrap();
            assert!(o.status.success(), "{}", text(&o));
            d
        })
        .collect();
    let merged = root.path().join("merged");
    let merge = |out: &Path| {
        let mut c = magbench(&["merge", "--out", out.to_str().unwrap()]);
        c.args(&shards).output().unwrap()
    };
    // held by this process: the merge is refused and writes nothing
    std::fs::create_dir(&merged).unwrap();
    let lock = magbench::results::lock::exclusive(&merged, "test", "--out").unwrap();
    let o = merge(&merged);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(&format!("pid {}", std::process::id())),
        "{err}"
    );
    assert!(!merged.join("manifest.json").exists());
    drop(lock);
    let o = merge(&merged);
    assert!(o.status.success(), "{}", text(&o));
    assert!(content(&merged) == content(&clean));
    assert!(verify(&merged).status.success());
    assert_eq!(std::fs::read(merged.join(".magbench.lock")).unwrap(), b"");
    // a shard whose trace was cut: its damaged runs are left out, never merged half
    cut(&shards[1].join("progress.csv"), 3000);
    let partial = root.path().join("partial");
    let o = merge(&partial);
    assert!(o.status.success(), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("runs left out"), "{err}");
    let v = verify(&partial);
    let report = String::from_utf8_lossy(&v.stdout);
    assert_eq!(v.status.code(), Some(1), "{}", text(&v));
    assert!(report.contains("runs missing"), "{report}");
    assert!(!report.contains("trace"), "{report}");
}

#[test]
fn verify_names_what_is_wrong_and_exits_2_on_bad_input() {
    let root = tempfile::tempdir().unwrap();
    let exp = write(root.path(), "exp.toml", EXP);
    let (clean, _) = reference(root.path(), &exp);
    let o = verify(&clean);
    assert!(o.status.success(), "{}", text(&o));
    let ok = String::from_utf8_lossy(&o.stdout);
    assert!(
        ok.contains(&format!("{RUNS} runs, {} trace points", RUNS * 51)),
        "{ok}"
    );
    // a torn runs.parquet is named with its reason, a torn progress.parquet by its hash; a
    // resume writes each whole again
    for (file, named) in [
        ("runs.parquet", "runs.parquet: not a Parquet file"),
        (
            "progress.parquet",
            "files changed since the folder was finalized: progress.parquet",
        ),
    ] {
        let path = clean.join(file);
        let whole = std::fs::read(&path).unwrap();
        std::fs::write(&path, &whole[..whole.len() / 2]).unwrap();
        let o = verify(&clean);
        assert_eq!(o.status.code(), Some(1), "{}", text(&o));
        let report = String::from_utf8_lossy(&o.stdout);
        assert!(report.contains(named), "{named}: {report}");
        resume_ok(&exp, &clean);
        assert_eq!(std::fs::read(&path).unwrap(), whole, "{file}");
        assert!(verify(&clean).status.success());
    }
    // a doubled row, a changed plot
    let runs = std::fs::read_to_string(clean.join("runs.csv")).unwrap();
    let last = runs.lines().last().unwrap();
    std::fs::write(clean.join("runs.csv"), format!("{runs}{last}\n")).unwrap();
    let o = verify(&clean);
    let report = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    for want in [
        "run ids with several rows",
        "files changed since the folder was finalized: runs.csv",
        "runs_done is 24, runs.csv has 25 rows",
    ] {
        assert!(report.contains(want), "{want}: {report}");
    }
    // bad input
    for dir in [root.path().join("none"), root.path().to_path_buf(), exp] {
        let o = verify(&dir);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    }
}
