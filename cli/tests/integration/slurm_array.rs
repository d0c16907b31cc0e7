//! `experiments/slurm-array.sh` under real Slurm daemons (munged, slurmctld, slurmd started by
//! `experiments/slurm-local.sh`): a job array of 4 and its merge job give the unsharded sweep;
//! a task cancelled part-way and resubmitted alone resumes without losing or repeating a run.
//! Without Slurm (`apt-get install slurm-wlm munge`) the real-cluster test says so
//! loudly and passes, unless `MAGBENCH_REQUIRE_SLURM=1` (set by `.ci/run`). The script's merge
//! step, which needs no Slurm, is also tested on its own.

use crate::common;
use crate::slurm;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use common::{deterministic_runs, write};
use magbench::results::Manifest;
use slurm::{Cluster, Job, experiments, merge_log, run_ids, skip_or_fail, split, unsharded};

/// Real planners, iteration limits only (reproducible bit for bit): 32 runs, about 0.1 s each
/// for goal-zoom-rrt and 0.6 s for sst, so a shard of 8 runs at one thread lasts about 3 s.
const EXPERIMENT: &str = "name = \"slurm-test\"
scenarios = [\"open-field\", \"narrow-passage\"]
planners = [\"goal-zoom-rrt\", \"sst\"]
seeds = 8
[limits]
iterations = 10000
";
const RUNS: usize = 32;
const SHARDS: usize = 4;
const MERGE_JOB: &str = "magbench-merge-slurm-test";
/// Generous: the whole test takes about half a minute on an idle 2-core machine.
const DEADLINE: Duration = Duration::from_secs(600);

fn script() -> String {
    experiments().join("slurm-array.sh").display().to_string()
}

/// A folder to submit from, as a user's checkout: the experiment, and the binary at the
/// script's default path `target/release/magbench` (a link to the binary cargo built for
/// this test: the dev profile is optimised, and a second, release build would cost CI minutes).
fn submit_dir(root: &Path, name: &str) -> PathBuf {
    let d = root.join(name);
    std::fs::create_dir_all(d.join("target/release")).unwrap();
    std::os::unix::fs::symlink(
        env!("CARGO_BIN_EXE_magbench"),
        d.join("target/release/magbench"),
    )
    .unwrap();
    write(&d, "exp.toml", EXPERIMENT);
    d
}

fn shard_dir(d: &Path, i: usize) -> PathBuf {
    d.join(format!("results/slurm-test-shard-{i}-of-{SHARDS}"))
}

/// The data lines of `runs.csv` in `dir` that are complete, as written.
fn run_lines(dir: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join("runs.csv")).unwrap_or_default();
    let complete = &text[..text.rfind('\n').map_or(0, |i| i + 1)];
    complete.lines().skip(1).map(str::to_string).collect()
}

/// The merged folder has its report and its plots (SVG and PNG).
fn assert_report(dir: &Path) {
    assert!(dir.join("report.html").is_file(), "{}", dir.display());
    let mut kinds = BTreeSet::new();
    let mut stack = vec![dir.join("plots")];
    while let Some(p) = stack.pop() {
        for e in std::fs::read_dir(&p).unwrap() {
            let path = e.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if let Some(x) = path.extension() {
                kinds.insert(x.to_string_lossy().to_string());
            }
        }
    }
    assert!(
        kinds.contains("svg") && kinds.contains("png"),
        "plots: {kinds:?}"
    );
}

fn new_jobs(cluster: &Cluster, before: &BTreeSet<String>) -> Vec<Job> {
    cluster
        .jobs()
        .into_iter()
        .filter(|j| !before.contains(&j.id))
        .collect()
}

fn job_ids(cluster: &Cluster) -> BTreeSet<String> {
    cluster.jobs().into_iter().map(|j| j.id).collect()
}

#[test]
fn a_job_array_under_real_slurm_merges_and_a_cancelled_task_resumes() {
    let t0 = Instant::now();
    let cluster = match Cluster::start() {
        Ok(c) => c,
        Err(why) => return skip_or_fail(&why),
    };
    let stage = |what: &str| eprintln!("slurm test: {what} at {:.1} s", t0.elapsed().as_secs_f64());
    stage("cluster up");
    let root = tempfile::tempdir().unwrap();
    let root = root.path();
    let whole = deterministic_runs(&unsharded(root, EXPERIMENT));
    assert_eq!(whole.len(), RUNS);
    stage("unsharded sweep done");
    let script = script();
    let array = |d: &Path, tasks: &str| {
        cluster.sbatch(
            d,
            &[
                &format!("--array={tasks}"),
                "--cpus-per-task=1",
                &script,
                "exp.toml",
                &SHARDS.to_string(),
            ],
        )
    };

    // An array of 4 and the merge job its first task submits.
    let a = submit_dir(root, "a");
    let job = array(&a, "1-4");
    cluster.wait_idle(DEADLINE);
    let (tasks, merges) = split(&cluster.jobs(), &job, MERGE_JOB);
    let done: Vec<_> = (1..=SHARDS)
        .map(|t| (t, "COMPLETED 0:0".to_string()))
        .collect();
    assert_eq!(tasks, done);
    assert_eq!(merges.len(), 1, "{merges:?}");
    assert_eq!(
        (merges[0].state.as_str(), merges[0].exit_code.as_str()),
        ("COMPLETED", "0:0")
    );
    assert!(a.join(format!("magbench-{job}_1.out")).is_file());
    let merged = a.join("results/slurm-test");
    assert_eq!(deterministic_runs(&merged), whole, "merged vs unsharded");
    assert_report(&merged);
    stage("array of 4 merged, equal to the unsharded sweep");

    // Another array; task 3 is cancelled once it has finished a run (7 runs, about 2.5 s, are
    // then left), and the merge job still merges what there is.
    let b = submit_dir(root, "b");
    let before = job_ids(&cluster);
    let job = array(&b, "1-4");
    let shard3 = shard_dir(&b, 3);
    cluster.wait_until("task 3 finishing a run", DEADLINE, || {
        !run_lines(&shard3).is_empty() || cluster.queue().is_empty()
    });
    cluster.run(&b, "scancel", &[&format!("{job}_3")]);
    cluster.wait_idle(DEADLINE);
    stage("second array done, task 3 cancelled");
    let committed = run_lines(&shard3);
    let per_shard = RUNS / SHARDS;
    assert!(
        !committed.is_empty() && committed.len() < per_shard,
        "task 3 was not cancelled part-way: {} of {per_shard} runs",
        committed.len()
    );
    let jobs = new_jobs(&cluster, &before);
    let (tasks, merges) = split(&jobs, &job, MERGE_JOB);
    assert_eq!(tasks[2].0, 3);
    assert!(tasks[2].1.starts_with("CANCELLED"), "{tasks:?}");
    for t in [0, 1, 3] {
        assert_eq!(tasks[t].1, "COMPLETED 0:0", "{tasks:?}");
    }
    assert_eq!(merges.len(), 1, "{merges:?}");
    assert_eq!(
        merges[0].state,
        "COMPLETED",
        "{:?}\n{}",
        merges[0],
        merge_log(&b, &merges[0])
    );
    let merged = b.join("results/slurm-test");
    let missing = per_shard - committed.len();
    assert_eq!(deterministic_runs(&merged).len(), RUNS - missing);
    assert!(
        merge_log(&b, &merges[0]).contains(&format!("{missing} runs are missing")),
        "{}",
        merge_log(&b, &merges[0])
    );

    // Resubmitted alone, as the script's header says: it resumes and merges again.
    let before = job_ids(&cluster);
    let job = array(&b, "3");
    cluster.wait_idle(DEADLINE);
    stage("task 3 resubmitted and done");
    let (tasks, merges) = split(&new_jobs(&cluster, &before), &job, MERGE_JOB);
    assert_eq!(tasks, vec![(3, "COMPLETED 0:0".to_string())]);
    assert_eq!(merges.len(), 1, "{merges:?}");
    assert_eq!(
        (merges[0].state.as_str(), merges[0].exit_code.as_str()),
        ("COMPLETED", "0:0")
    );
    let now = run_lines(&shard3);
    for line in &committed {
        assert!(
            now.contains(line),
            "a run finished before the cancel was redone or lost: {line}"
        );
    }
    let ids = run_ids(&shard3);
    let expected: BTreeSet<String> = run_ids(&root.join("whole"))
        .into_iter()
        .enumerate()
        .filter(|(i, _)| i % SHARDS == 2)
        .map(|(_, id)| id)
        .collect();
    assert_eq!(ids.len(), per_shard, "no duplicated run");
    assert_eq!(
        ids.into_iter().collect::<BTreeSet<_>>(),
        expected,
        "no lost run"
    );
    let m = Manifest::read(&shard3).unwrap();
    let last = m.sessions.last().unwrap();
    assert_eq!(
        (last.kind.as_str(), last.runs_executed),
        ("bench --resume", missing)
    );
    assert_eq!(
        deterministic_runs(&merged),
        whole,
        "merged after resume vs unsharded"
    );
    assert_report(&merged);
    eprintln!(
        "slurm test: task 3 cancelled after {} of {per_shard} runs, resumed {missing}; merged equals unsharded ({RUNS} runs)",
        committed.len()
    );
    drop(cluster);
    stage("cluster stopped");
}

/// The script run outside Slurm, with the given arguments and array task id.
fn script_in(d: &Path, args: &[&str], task: Option<&str>) -> Output {
    let mut c = Command::new("bash");
    c.arg(script()).args(args).current_dir(d);
    for (k, _) in std::env::vars_os() {
        if k.to_string_lossy().starts_with("SLURM_") {
            c.env_remove(k);
        }
    }
    if let Some(t) = task {
        c.env("SLURM_ARRAY_TASK_ID", t);
    }
    c.env("MAGBENCH", env!("CARGO_BIN_EXE_magbench"))
        .output()
        .unwrap()
}

fn bench(d: &Path, args: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_magbench"))
        .args(["bench", "exp.toml", "--executor", "fake", "--quiet"])
        .args(args)
        .current_dir(d)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn the_merge_step_skips_a_shard_that_never_started_and_merges_again_later() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(
        d,
        "exp.toml",
        "name = \"fake-sweep\"\nscenarios = [\"open-field\"]\nplanners = [\"fake\"]\nseeds = 9\n[limits]\niterations = 300\n",
    );
    let shard = |i: usize| format!("results/fake-sweep-shard-{i}-of-3");
    for i in [1, 3] {
        bench(d, &["--shard", &format!("{i}/3"), "--out", &shard(i)]);
    }
    let o = script_in(d, &["exp.toml", "3", "merge"], None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("shards 2 of 3 have not started"), "{err}");
    assert!(
        err.contains("sbatch --array=2 experiments/slurm-array.sh exp.toml 3"),
        "{err}"
    );
    let merged = d.join("results/fake-sweep");
    assert_eq!(deterministic_runs(&merged).len(), 6);

    bench(d, &["--shard", "2/3", "--out", &shard(2)]);
    let o = script_in(d, &["exp.toml", "3", "merge"], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    bench(d, &["--out", "whole"]);
    assert_eq!(
        deterministic_runs(&merged),
        deterministic_runs(&d.join("whole"))
    );
    let leftovers: Vec<_> = std::fs::read_dir(d.join("results"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .filter(|n| n.starts_with('.') || n.ends_with(".old"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");

    // Results of an unsharded sweep in results/<name> are never replaced by a merge.
    std::fs::remove_dir_all(&merged).unwrap();
    bench(d, &["--out", "results/fake-sweep"]);
    let manifest = std::fs::read(merged.join("manifest.json")).unwrap();
    let o = script_in(d, &["exp.toml", "3", "merge"], None);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr)
            .contains("results/fake-sweep holds results that are not a merge")
    );
    assert_eq!(
        std::fs::read(merged.join("manifest.json")).unwrap(),
        manifest
    );

    // Bad arguments: exit code 2 and the reason.
    for (args, task, reason) in [
        (
            &["exp.toml", "x"][..],
            Some("1"),
            "N: \"x\" is not a number",
        ),
        (
            &["exp.toml", "3"],
            Some("4"),
            "array task 4 is not a shard of 1-3",
        ),
        (&["exp.toml", "3"], None, "SLURM_ARRAY_TASK_ID is not set"),
        (
            &["nope.toml", "3"],
            Some("1"),
            "nope.toml: no such experiment file",
        ),
        (
            &["exp.toml", "3", "marge"],
            None,
            "\"marge\": unknown third argument",
        ),
    ] {
        let o = script_in(d, args, task);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(reason), "{args:?}: {err}");
    }
}

/// A merge job can run while a task writes its shard: the first submission's merge waits only
/// for the first array, not for a task resubmitted meanwhile. Merging must then only read the
/// shard folders: rewriting one (as a repair does) would swap the file under the task, whose
/// later rows would go to the replaced file and be lost.
#[test]
fn merging_leaves_the_shard_folders_as_they_are() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    write(
        d,
        "exp.toml",
        "name = \"live\"\nscenarios = [\"open-field\"]\nplanners = [\"fake\"]\nseeds = 6\n[limits]\niterations = 300\n",
    );
    bench(d, &["--shard", "1/2", "--out", "s1"]);
    bench(d, &["--shard", "2/2", "--out", "s2"]);
    // Shard 2 as a task writing its last run: progress rows written, its runs.csv row half.
    let runs = d.join("s2/runs.csv");
    let text = std::fs::read_to_string(&runs).unwrap();
    let last = text.trim_end().rfind('\n').unwrap() + 1;
    let torn = format!("{}{}", &text[..last], &text[last..last + 20]);
    std::fs::write(&runs, &torn).unwrap();
    let files = [
        "s1/runs.csv",
        "s1/progress.csv",
        "s2/runs.csv",
        "s2/progress.csv",
    ];
    let before: Vec<Vec<u8>> = files
        .iter()
        .map(|f| std::fs::read(d.join(f)).unwrap())
        .collect();
    let o = Command::new(env!("CARGO_BIN_EXE_magbench"))
        .args(["merge", "s1", "s2", "--out", "m"])
        .current_dir(d)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let after: Vec<Vec<u8>> = files
        .iter()
        .map(|f| std::fs::read(d.join(f)).unwrap())
        .collect();
    for ((f, b), a) in files.iter().zip(&before).zip(&after) {
        assert!(b == a, "merge rewrote {f}");
    }
    // The merge holds the finished runs, and no progress of the run in flight.
    let ids = run_ids(&d.join("m"));
    assert_eq!(ids.len(), 5);
    let progress = std::fs::read_to_string(d.join("m/progress.csv")).unwrap();
    assert!(
        !progress.contains("open-field|fake|-|-|5"),
        "progress of the run in flight"
    );
}
