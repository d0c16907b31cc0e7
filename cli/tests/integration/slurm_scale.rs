//! `experiments/slurm-array.sh` at scale under real Slurm daemons (munged, slurmctld, slurmd
//! started by `experiments/slurm-local.sh`): an array of 100 shards of a tiny sweep, one task
//! killed part-way and resubmitted, merged into one folder that equals the unsharded sweep,
//! each run exactly once. Without Slurm the test says so loudly and passes, unless
//! `MAGBENCH_REQUIRE_SLURM=1` (set by `.ci/run`).
//!
//! The kill is in lockstep with the task, not timed: the task's binary is a wrapper that sets
//! `MAGBENCH_STALL_AT_BYTE` for the first run of task [`KILLED`], so its `bench` stops for good
//! half-way through writing its shard's second run and says so in the task's output; the test
//! waits for that line, then cancels the task.

use crate::common;
use crate::slurm;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use common::{deterministic_progress, deterministic_runs, write};
use magbench::results::Manifest;
use slurm::{Cluster, Job, experiments, merge_log, run_ids, skip_or_fail, split, unsharded};

/// Real planners at 1000 iterations (reproducible bit for bit, a few milliseconds a run): 200
/// runs, 2 a shard, no replay pages.
const EXPERIMENT: &str = "name = \"slurm-scale\"
scenarios = [\"open-field\", \"narrow-passage\"]
planners = [\"goal-zoom-rrt\", \"sst\"]
seeds = 50
replays = \"none\"
[limits]
iterations = 1000
";
const RUNS: usize = 200;
const SHARDS: usize = 100;
/// The array task that is killed part-way and resubmitted.
const KILLED: usize = 37;
const MERGE_JOB: &str = "magbench-merge-slurm-scale";
/// A hang guard only: the whole test takes about a minute on an idle 2-core machine.
const DEADLINE: Duration = Duration::from_secs(600);
/// What a [`magbench::results::store::RunWriter`] that stalls prints.
const STALLED: &str = "MAGBENCH_STALL_AT_BYTE: stalled";

/// The runs of shard `task` (1-based) of the sweep: every `SHARDS`-th run from `task - 1`.
fn shard_runs(task: usize) -> Vec<usize> {
    (task - 1..RUNS).step_by(SHARDS).collect()
}

/// The lines of the CSV file `dir/name` (header left out) whose first cell, the run index, is
/// `run`, with their line ends.
fn lines_of_run(dir: &Path, name: &str, run: usize) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join(name)).unwrap();
    text.split_inclusive('\n')
        .skip(1)
        .filter(|l| l.split(',').next() == Some(run.to_string().as_str()))
        .map(str::to_string)
        .collect()
}

/// The bytes a `bench` appends for `run`: its progress lines, then its `runs.csv` line.
fn run_bytes(dir: &Path, run: usize) -> usize {
    let rows = lines_of_run(dir, "runs.csv", run);
    assert_eq!(rows.len(), 1, "run {run} in {}", dir.display());
    let progress: usize = lines_of_run(dir, "progress.csv", run)
        .iter()
        .map(String::len)
        .sum();
    progress + rows[0].len()
}

/// A folder to submit from: the experiment, and at the script's default binary path
/// `target/release/magbench` a wrapper of the binary cargo built for this test that makes the
/// first `bench` of task [`KILLED`] stall after `stall_at` bytes of runs.
fn submit_dir(root: &Path, stall_at: usize) -> PathBuf {
    let d = root.join("submit");
    std::fs::create_dir_all(d.join("target/release")).unwrap();
    let wrapper = write(
        &d.join("target/release"),
        "magbench",
        &format!(
            "#!/bin/sh\n\
             # The first bench of task {KILLED} (mkdir is atomic) stalls; others run as they are.\n\
             if [ \"$1\" = bench ] && [ \"${{SLURM_ARRAY_TASK_ID:-}}\" = {KILLED} ] && mkdir stalled-once 2>/dev/null; then\n\
             \x20 export MAGBENCH_STALL_AT_BYTE={stall_at}\n\
             fi\n\
             exec '{}' \"$@\"\n",
            env!("CARGO_BIN_EXE_magbench")
        ),
    );
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&wrapper, std::fs::Permissions::from_mode(0o755)).unwrap();
    write(&d, "exp.toml", EXPERIMENT);
    d
}

/// The complete data lines of `runs.csv` in `dir`.
fn committed(dir: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join("runs.csv")).unwrap_or_default();
    let complete = &text[..text.rfind('\n').map_or(0, |i| i + 1)];
    complete.lines().skip(1).map(str::to_string).collect()
}

fn assert_merged(d: &Path, merge: &Job) {
    assert_eq!(
        (merge.state.as_str(), merge.exit_code.as_str()),
        ("COMPLETED", "0:0"),
        "{}",
        merge_log(d, merge)
    );
}

#[test]
fn an_array_of_100_shards_with_a_killed_and_resubmitted_task_merges_into_the_unsharded_sweep() {
    let t0 = Instant::now();
    let cluster = match Cluster::start() {
        Ok(c) => c,
        Err(why) => return skip_or_fail(&why),
    };
    let stage = |what: &str| {
        eprintln!(
            "slurm scale test: {what} at {:.1} s",
            t0.elapsed().as_secs_f64()
        )
    };
    stage("cluster up");
    let root = tempfile::tempdir().unwrap();
    let root = root.path();
    let whole = unsharded(root, EXPERIMENT);
    let whole_runs = deterministic_runs(&whole);
    assert_eq!(whole_runs.len(), RUNS);
    stage("unsharded sweep done");

    // Task KILLED runs its shard's runs in order at one thread: stalling half-way through the
    // bytes of its second run leaves the first committed and the second torn.
    let [first, second] = shard_runs(KILLED)[..] else {
        panic!("two runs a shard")
    };
    let stall_at = run_bytes(&whole, first) + run_bytes(&whole, second) / 2;
    let d = submit_dir(root, stall_at);
    let script = experiments().join("slurm-array.sh").display().to_string();
    let array = |tasks: &str| {
        cluster.sbatch(
            &d,
            &[
                &format!("--array={tasks}"),
                "--cpus-per-task=1",
                &script,
                "exp.toml",
                &SHARDS.to_string(),
            ],
        )
    };
    let job = array(&format!("1-{SHARDS}"));
    let out = d.join(format!("magbench-{job}_{KILLED}.out"));
    cluster.wait_until(&format!("task {KILLED} stalling"), DEADLINE, || {
        std::fs::read_to_string(&out).is_ok_and(|t| t.contains(STALLED))
    });
    cluster.run(&d, "scancel", &[&format!("{job}_{KILLED}")]);
    cluster.wait_idle(DEADLINE);
    stage("array of 100 done, one task killed");

    let shard = d.join(format!("results/slurm-scale-shard-{KILLED}-of-{SHARDS}"));
    let before = committed(&shard);
    assert_eq!(before.len(), 1, "task {KILLED} killed after its first run");
    let jobs = cluster.jobs();
    let (tasks, merges) = split(&jobs, &job, MERGE_JOB);
    assert_eq!(tasks.len(), SHARDS, "{tasks:?}");
    for (t, state) in &tasks {
        if *t == KILLED {
            assert!(state.starts_with("CANCELLED"), "task {t}: {state}");
        } else {
            assert_eq!(state, "COMPLETED 0:0", "task {t}");
        }
    }
    assert_eq!(merges.len(), 1, "{merges:?}");
    assert_merged(&d, &merges[0]);
    assert!(
        merge_log(&d, &merges[0]).contains("1 runs are missing"),
        "{}",
        merge_log(&d, &merges[0])
    );
    let merged = d.join("results/slurm-scale");
    assert_eq!(deterministic_runs(&merged).len(), RUNS - 1);

    // Resubmitted alone: it runs only its missing run, and its merge job merges all 100 shards.
    let known: BTreeSet<String> = jobs.into_iter().map(|j| j.id).collect();
    let job = array(&KILLED.to_string());
    cluster.wait_idle(DEADLINE);
    stage("killed task resubmitted and merged");
    let jobs: Vec<Job> = cluster
        .jobs()
        .into_iter()
        .filter(|j| !known.contains(&j.id))
        .collect();
    let (tasks, merges) = split(&jobs, &job, MERGE_JOB);
    assert_eq!(tasks, vec![(KILLED, "COMPLETED 0:0".to_string())]);
    assert_eq!(merges.len(), 1, "{merges:?}");
    assert_merged(&d, &merges[0]);
    let now = committed(&shard);
    assert_eq!(now.len(), 2);
    assert_eq!(
        now[0], before[0],
        "the run finished before the kill was kept"
    );
    let last = Manifest::read(&shard).unwrap().sessions.pop().unwrap();
    assert_eq!(
        (last.kind.as_str(), last.runs_executed),
        ("bench --resume", 1)
    );

    let ids = run_ids(&merged);
    let unique: BTreeSet<&String> = ids.iter().collect();
    assert_eq!((ids.len(), unique.len()), (RUNS, RUNS), "each run once");
    assert_eq!(
        unique,
        run_ids(&whole).iter().collect(),
        "the unsharded run ids"
    );
    assert_eq!(
        deterministic_runs(&merged),
        whole_runs,
        "merged vs unsharded"
    );
    assert_eq!(
        deterministic_progress(&merged),
        deterministic_progress(&whole),
        "merged progress vs unsharded"
    );
    let m = Manifest::read(&merged).unwrap();
    assert_eq!((m.merged_from.len(), m.runs_done), (SHARDS, RUNS));
    drop(cluster);
    stage("cluster stopped");
}
